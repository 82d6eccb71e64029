//! Scenes the report gives to every peer: a small CSG tree (balls, cylinders, boxes, moves,
//! turns and the three booleans) written both as OpenSCAD text, which qcsg and OpenSCAD read,
//! and as JSON, which the Python peers (`crates/qcsg-bench/peers/peer.py`) build with Manifold
//! and build123d. One tree gives every peer the same solid; the benchmark scenes' trees are
//! checked against their `.scad` files by a test (same points inside).
//!
//! Also the scaling families: plates with a grid of holes, a cube minus balls, unions of balls.

use std::fmt::Write as _;

/// A CSG tree in OpenSCAD's terms (`cylinder` and `cube` with OpenSCAD's `center`).
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// `sphere(r)`.
    Sphere(f64),
    /// `cylinder(h, r, center)`.
    Cylinder {
        /// Height.
        h: f64,
        /// Radius.
        r: f64,
        /// Centred on the origin in z, else standing on it.
        center: bool,
    },
    /// `cube(size, center)`.
    Cube {
        /// Edge lengths.
        size: [f64; 3],
        /// Centred on the origin, else in the positive octant.
        center: bool,
    },
    /// `translate(v)`.
    Translate([f64; 3], Box<Shape>),
    /// `rotate(v)`, degrees about the fixed x, then y, then z axes.
    Rotate([f64; 3], Box<Shape>),
    /// `union()`.
    Union(Vec<Shape>),
    /// `difference()`: the first child minus the others.
    Difference(Vec<Shape>),
    /// `intersection()`.
    Intersection(Vec<Shape>),
    /// `import(path)` of a binary STL mesh (Manifold reads the same file).
    Import(String),
}

fn num(x: f64) -> String {
    // Shortest text that reads back as the same f64, in both languages.
    let t = format!("{x:?}");
    t.strip_suffix(".0").map_or(t.clone(), str::to_owned)
}

fn vec3(v: [f64; 3]) -> String {
    format!("[{}, {}, {}]", num(v[0]), num(v[1]), num(v[2]))
}

impl Shape {
    /// Moved by `v`.
    pub fn at(self, v: [f64; 3]) -> Shape {
        Shape::Translate(v, Box::new(self))
    }

    /// Turned by `v` (degrees).
    pub fn turned(self, v: [f64; 3]) -> Shape {
        Shape::Rotate(v, Box::new(self))
    }

    /// OpenSCAD text (no `$fn`: the caller sets the segment count).
    pub fn to_scad(&self) -> String {
        let mut out = String::new();
        self.write_scad(&mut out, 0);
        out
    }

    fn write_scad(&self, out: &mut String, depth: usize) {
        let pad = "  ".repeat(depth);
        let _ = match self {
            Shape::Sphere(r) => writeln!(out, "{pad}sphere({});", num(*r)),
            Shape::Cylinder { h, r, center } => writeln!(
                out,
                "{pad}cylinder(h = {}, r = {}, center = {center});",
                num(*h),
                num(*r)
            ),
            Shape::Cube { size, center } => {
                writeln!(out, "{pad}cube({}, center = {center});", vec3(*size))
            }
            Shape::Translate(v, child) | Shape::Rotate(v, child) => {
                let name = if matches!(self, Shape::Translate(..)) {
                    "translate"
                } else {
                    "rotate"
                };
                let _ = writeln!(out, "{pad}{name}({})", vec3(*v));
                child.write_scad(out, depth + 1);
                Ok(())
            }
            Shape::Union(children)
            | Shape::Difference(children)
            | Shape::Intersection(children) => {
                let _ = writeln!(out, "{pad}{}() {{", self.kind());
                for c in children {
                    c.write_scad(out, depth + 1);
                }
                writeln!(out, "{pad}}}")
            }
            Shape::Import(path) => writeln!(out, "{pad}import({path:?});"),
        };
    }

    fn kind(&self) -> &'static str {
        match self {
            Shape::Sphere(_) => "sphere",
            Shape::Cylinder { .. } => "cylinder",
            Shape::Cube { .. } => "cube",
            Shape::Translate(..) => "translate",
            Shape::Rotate(..) => "rotate",
            Shape::Union(_) => "union",
            Shape::Difference(_) => "difference",
            Shape::Intersection(_) => "intersection",
            Shape::Import(_) => "stl",
        }
    }

    /// The JSON tree `peer.py` reads.
    pub fn to_json(&self) -> String {
        let kind = self.kind();
        match self {
            Shape::Sphere(r) => format!(r#"{{"kind":"{kind}","r":{}}}"#, num(*r)),
            Shape::Cylinder { h, r, center } => format!(
                r#"{{"kind":"{kind}","h":{},"r":{},"center":{center}}}"#,
                num(*h),
                num(*r)
            ),
            Shape::Cube { size, center } => {
                format!(
                    r#"{{"kind":"{kind}","size":{},"center":{center}}}"#,
                    vec3(*size)
                )
            }
            Shape::Translate(v, child) | Shape::Rotate(v, child) => format!(
                r#"{{"kind":"{kind}","v":{},"child":{}}}"#,
                vec3(*v),
                child.to_json()
            ),
            Shape::Union(c) | Shape::Difference(c) | Shape::Intersection(c) => {
                let inner: Vec<String> = c.iter().map(Shape::to_json).collect();
                format!(r#"{{"kind":"{kind}","children":[{}]}}"#, inner.join(","))
            }
            Shape::Import(path) => format!(
                r#"{{"kind":"{kind}","path":{}}}"#,
                serde_json::Value::from(path.as_str())
            ),
        }
    }

    /// The largest radius of a ball or cylinder in the tree (what sets the segment count a mesh
    /// needs for a given chordal error).
    pub fn largest_radius(&self) -> f64 {
        match self {
            Shape::Sphere(r) | Shape::Cylinder { r, .. } => *r,
            Shape::Cube { .. } | Shape::Import(_) => 0.0,
            Shape::Translate(_, c) | Shape::Rotate(_, c) => c.largest_radius(),
            Shape::Union(c) | Shape::Difference(c) | Shape::Intersection(c) => {
                c.iter().map(Shape::largest_radius).fold(0.0, f64::max)
            }
        }
    }
}

fn cyl(h: f64, r: f64, center: bool) -> Shape {
    Shape::Cylinder { h, r, center }
}

fn cube(size: [f64; 3], center: bool) -> Shape {
    Shape::Cube { size, center }
}

/// The tree of a benchmark scene of `crates/qcsg-bench/scenes/` (by file stem), written out as
/// the file's loops unroll.
pub fn benchmark_scene(name: &str) -> Option<Shape> {
    Some(match name {
        "three_spheres" => Shape::Union(vec![
            Shape::Intersection(vec![
                Shape::Sphere(1.0).at([-0.4, 0.0, 0.0]),
                Shape::Sphere(1.0).at([0.4, 0.0, 0.0]),
            ]),
            Shape::Sphere(0.6).at([0.0, 0.9, 0.3]),
        ]),
        "steinmetz" => Shape::Difference(vec![
            Shape::Intersection(vec![
                Shape::Sphere(1.3),
                Shape::Union(vec![
                    cyl(3.0, 0.7, true),
                    cyl(3.0, 0.7, true).turned([90.0, 0.0, 0.0]),
                    cyl(3.0, 0.7, true).turned([0.0, 90.0, 0.0]),
                ]),
            ]),
            Shape::Sphere(0.9),
        ]),
        "drilled_block" => {
            let mut parts = vec![cube([4.0, 3.0, 1.0], true)];
            for x in [-1.4, 1.4] {
                for y in [-0.9, 0.9] {
                    parts.push(cyl(2.0, 0.25, true).at([x, y, 0.0]));
                }
            }
            parts.push(cyl(2.0, 0.5, true));
            parts.push(cyl(1.0, 0.8, false).at([0.0, 0.0, 0.35]));
            parts.push(
                cube([0.5, 4.0, 0.5], true)
                    .turned([0.0, 45.0, 0.0])
                    .at([2.0, 0.0, 0.5]),
            );
            Shape::Difference(parts)
        }
        "wheel" => {
            let mut hub = vec![Shape::Intersection(vec![
                cyl(0.6, 2.45, true),
                Shape::Sphere(2.6),
            ])];
            for i in 0..6 {
                hub.push(cyl(2.0, 0.3, true).at([1.5, 0.0, 0.0]).turned([
                    0.0,
                    0.0,
                    60.0 * f64::from(i),
                ]));
            }
            hub.push(cyl(2.0, 0.6, true));
            let mut parts = vec![
                Shape::Difference(vec![cyl(0.6, 3.0, true), cyl(2.0, 2.4, true)]),
                Shape::Difference(hub),
            ];
            for i in 0..3 {
                parts.push(cube([5.0, 0.3, 0.4], true).turned([
                    0.0,
                    0.0,
                    60.0 * f64::from(i) + 30.0,
                ]));
            }
            Shape::Union(parts)
        }
        _ => return None,
    })
}

/// A square plate with `n` holes (the next square number at least `n`; the family uses
/// squares), one unit apart, radius 0.3, through a plate 0.4 thick.
pub fn plate_with_holes(n: usize) -> Shape {
    let side = (n as f64).sqrt().ceil() as usize;
    let mut parts = vec![cube([side as f64, side as f64, 0.4], false)];
    for i in 0..side * side {
        let (x, y) = ((i % side) as f64 + 0.5, (i / side) as f64 + 0.5);
        parts.push(cyl(1.0, 0.3, true).at([x, y, 0.2]));
    }
    Shape::Difference(parts)
}

/// A cube of side 10 minus `n` balls, centred at the points of a Halton sequence (bases 2, 3,
/// 5) in the cube, of radius `0.5 · (960 / n)^(1/3)` so that the family keeps a similar volume
/// of bubbles; many cut the faces.
pub fn cube_minus_balls(n: usize) -> Shape {
    let r = 0.5 * (960.0 / n.max(1) as f64).cbrt();
    let mut parts = vec![cube([10.0, 10.0, 10.0], false)];
    for i in 1..=n {
        let p = [
            10.0 * halton(i, 2),
            10.0 * halton(i, 3),
            10.0 * halton(i, 5),
        ];
        parts.push(Shape::Sphere(r).at(p));
    }
    Shape::Difference(parts)
}

fn halton(mut i: usize, base: usize) -> f64 {
    let (mut f, mut x) = (1.0, 0.0);
    while i > 0 {
        f /= base as f64;
        x += f * (i % base) as f64;
        i /= base;
    }
    // Rounded to 1e-6 so that the OpenSCAD text is short and every peer reads the same value.
    (x * 1e6).round() / 1e6
}

/// `n` unit balls in a cubic grid 1.5 apart (the next cube number at least `n`; the family
/// uses cubes), united: neighbours overlap.
pub fn ball_union(n: usize) -> Shape {
    let side = (n as f64).cbrt().round() as usize;
    let side = if side * side * side < n {
        side + 1
    } else {
        side
    };
    let mut balls = Vec::new();
    for i in 0..n {
        let (x, y, z) = (i % side, (i / side) % side, i / (side * side));
        balls.push(Shape::Sphere(1.0).at([1.5 * x as f64, 1.5 * y as f64, 1.5 * z as f64]));
    }
    Shape::Union(balls)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pipeline::{compile_file, compile_source};
    use qcsg_csg::DnfOptions;
    use qcsg_testkit::Rng;

    #[test]
    fn benchmark_trees_are_the_scene_files() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
        for name in ["three_spheres", "steinmetz", "drilled_block", "wheel"] {
            let file = compile_file(&dir.join(format!("{name}.scad")), &DnfOptions::default())
                .expect("readable");
            let file = file.dnf.expect("the scene compiles");
            let tree = benchmark_scene(name).expect("a tree");
            let text = compile_source("tree.scad", tree.to_scad(), &DnfOptions::default());
            let tree = text.dnf.expect("the tree compiles");
            let b = file.bounds;
            assert!((b.min - tree.bounds.min).length() < 1e-9, "{name}");
            assert!((b.max - tree.bounds.max).length() < 1e-9, "{name}");
            let mut rng = Rng::new(7);
            let mut inside = 0;
            for _ in 0..20_000 {
                let p = rng.in_box(b.min, b.max);
                assert_eq!(file.contains(p), tree.contains(p), "{name} at {p:?}");
                inside += usize::from(file.contains(p));
            }
            assert!(inside > 1000, "{name}: the test must see the solid");
        }
    }

    #[test]
    fn json_and_scad_of_a_tree() {
        let s = Shape::Difference(vec![
            cube([1.0, 2.0, 3.5], true),
            cyl(2.0, 0.25, false)
                .turned([0.0, 90.0, 0.0])
                .at([0.5, 0.0, -1e-3]),
        ]);
        assert_eq!(
            s.to_json(),
            r#"{"kind":"difference","children":[{"kind":"cube","size":[1, 2, 3.5],"center":true},{"kind":"translate","v":[0.5, 0, -0.001],"child":{"kind":"rotate","v":[0, 90, 0],"child":{"kind":"cylinder","h":2,"r":0.25,"center":false}}}]}"#
        );
        let scad = s.to_scad();
        assert!(scad.contains("translate([0.5, 0, -0.001])"), "{scad}");
        assert!(
            scad.contains("cylinder(h = 2, r = 0.25, center = false);"),
            "{scad}"
        );
    }

    #[test]
    fn families_have_their_counts() {
        let count = |s: &Shape| match s {
            Shape::Union(c) => c.len(),
            Shape::Difference(c) => c.len() - 1,
            _ => 0,
        };
        for (n, expect) in [(16, 16), (1024, 1024)] {
            assert_eq!(count(&plate_with_holes(n)), expect);
        }
        for n in [15, 960] {
            assert_eq!(count(&cube_minus_balls(n)), n);
        }
        for n in [27, 1000] {
            assert_eq!(count(&ball_union(n)), n);
        }
        // Every family compiles in qcsg.
        for s in [plate_with_holes(16), cube_minus_balls(15), ball_union(27)] {
            let c = compile_source("family.scad", s.to_scad(), &DnfOptions::default());
            assert!(c.dnf.is_some(), "{:?}", c.error_codes());
        }
    }
}
