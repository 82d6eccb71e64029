//! The peers' mesh-to-surface distance on meshes whose distance is known exactly: the eight
//! corners of a cube (distance 0 both ways), and a tube whose hole is a regular n-gon prism
//! inscribed in the hole's cylinder (distance the n-gon's sagitta both ways, reached at the
//! middles of the hole's edges, including on the rims where the flat faces meet the hole).

use std::f64::consts::PI;

use qcsg_bench::measure::References;
use qcsg_bench::mesh::{Mesh, mesh_distance};
use qcsg_bench::pipeline::compile_source;
use qcsg_csg::{Dnf, DnfOptions};
use qcsg_quadric::DVec3;

fn dnf(source: &str) -> Dnf {
    let compiled = compile_source("test.scad", source.to_owned(), &DnfOptions::default());
    let codes = compiled.error_codes();
    compiled
        .dnf
        .unwrap_or_else(|| panic!("{source}: errors {codes:?}"))
}

fn measure(dnf: &Dnf, mesh: &Mesh) -> (f64, f64) {
    let refs = References::find(dnf, 600, 0);
    let diag = (dnf.bounds.max - dnf.bounds.min).length();
    let d = mesh_distance(dnf, mesh, &refs.surface, diag / 400.0);
    (d.surface_to_mesh, d.mesh_to_surface)
}

fn quad(out: &mut Vec<[DVec3; 3]>, a: DVec3, b: DVec3, c: DVec3, d: DVec3) {
    out.push([a, b, c]);
    out.push([a, c, d]);
}

#[test]
fn exact_cube_measures_zero() {
    let dnf = dnf("cube(10);");
    let v = |x: f64, y: f64, z: f64| DVec3::new(10.0 * x, 10.0 * y, 10.0 * z);
    let mut t = Vec::new();
    quad(
        &mut t,
        v(0., 0., 0.),
        v(1., 0., 0.),
        v(1., 1., 0.),
        v(0., 1., 0.),
    );
    quad(
        &mut t,
        v(0., 0., 1.),
        v(1., 0., 1.),
        v(1., 1., 1.),
        v(0., 1., 1.),
    );
    quad(
        &mut t,
        v(0., 0., 0.),
        v(1., 0., 0.),
        v(1., 0., 1.),
        v(0., 0., 1.),
    );
    quad(
        &mut t,
        v(0., 1., 0.),
        v(1., 1., 0.),
        v(1., 1., 1.),
        v(0., 1., 1.),
    );
    quad(
        &mut t,
        v(0., 0., 0.),
        v(0., 1., 0.),
        v(0., 1., 1.),
        v(0., 0., 1.),
    );
    quad(
        &mut t,
        v(1., 0., 0.),
        v(1., 1., 0.),
        v(1., 1., 1.),
        v(1., 0., 1.),
    );
    let (s2m, m2s) = measure(&dnf, &Mesh { triangles: t });
    assert!(s2m < 1e-9, "surface to mesh {s2m}");
    assert!(m2s < 1e-9, "mesh to surface {m2s}");
}

/// A tube of outer radius `big` (an `outer`-gon, fine enough that its sagitta is negligible)
/// and hole radius `small` (an `inner`-gon), height `h`, as a closed triangle mesh.
fn tube(big: f64, small: f64, h: f64, outer: usize, inner: usize) -> Mesh {
    assert_eq!(outer % inner, 0);
    let per = outer / inner;
    let at = |r: f64, k: usize, n: usize, z: f64| {
        let a = 2.0 * PI * (k % n) as f64 / n as f64;
        DVec3::new(r * a.cos(), r * a.sin(), z)
    };
    let mut t = Vec::new();
    for k in 0..outer {
        quad(
            &mut t,
            at(big, k, outer, 0.0),
            at(big, k + 1, outer, 0.0),
            at(big, k + 1, outer, h),
            at(big, k, outer, h),
        );
    }
    for i in 0..inner {
        quad(
            &mut t,
            at(small, i, inner, 0.0),
            at(small, i + 1, inner, 0.0),
            at(small, i + 1, inner, h),
            at(small, i, inner, h),
        );
        for z in [0.0, h] {
            for j in i * per..(i + 1) * per {
                t.push([
                    at(small, i, inner, z),
                    at(big, j, outer, z),
                    at(big, j + 1, outer, z),
                ]);
            }
            t.push([
                at(small, i, inner, z),
                at(big, (i + 1) * per, outer, z),
                at(small, i + 1, inner, z),
            ]);
        }
    }
    Mesh { triangles: t }
}

#[test]
fn tube_with_polygonal_hole_measures_its_sagitta() {
    let (big, small, h, inner) = (10.0, 4.0, 6.0, 8);
    let dnf = dnf(&format!(
        "difference() {{ cylinder(r = {big}, h = {h}); \
         translate([0, 0, -1]) cylinder(r = {small}, h = {}); }}",
        h + 2.0
    ));
    let mesh = tube(big, small, h, 512, inner);
    let sagitta = small * (1.0 - (PI / inner as f64).cos());
    let (s2m, m2s) = measure(&dnf, &mesh);
    // The reference points and the mesh points are finite sets: both directions may fall short
    // of the sagitta by their spacing's effect, never exceed it by more than rounding.
    for (name, d) in [("surface to mesh", s2m), ("mesh to surface", m2s)] {
        assert!(
            (d - sagitta).abs() < 0.02 * sagitta,
            "{name} {d}, sagitta {sagitta}"
        );
    }
}

/// The largest distance from the points of `triangle` to the exact surface of `source`.
fn triangle_to_surface(source: &str, triangle: [DVec3; 3]) -> f64 {
    let dnf = dnf(source);
    measure(
        &dnf,
        &Mesh {
            triangles: vec![triangle],
        },
    )
    .1
}

#[test]
fn point_inside_a_concave_crease_of_planes_measures_to_the_crease() {
    // An L of two blocks: the crease x = z = 10 is concave; from (10 - b, y, 10 - b) the feet
    // on both planes of the crease lie inside the other block, and the nearest point of the
    // surface is the crease, b·√2 away.
    // The bound adds the step within which the solid is seen to change (1e-8 of the diagonal).
    let b = 0.1;
    let d = triangle_to_surface(
        "union() { cube([20, 10, 10]); cube([10, 10, 20]); }",
        [
            DVec3::new(10.0 - b, 4.0, 10.0 - b),
            DVec3::new(10.0 - b, 6.0, 10.0 - b),
            DVec3::new(10.0, 5.0, 10.0),
        ],
    );
    let expected = b * 2f64.sqrt();
    assert!(
        (d - expected).abs() < 1e-5 * expected,
        "{d}, expected {expected}"
    );
}

#[test]
fn point_inside_the_crease_of_two_balls_measures_to_the_crease() {
    // Two unit balls at x = ±0.6 meet on the circle x = 0, radius 0.8, a concave crease of
    // their union; from (0, ρ, 0) inside both, the feet on both spheres lie inside the other
    // ball and the nearest point of the surface is the circle, 0.8 − ρ away.
    let rho = 0.7;
    let d = triangle_to_surface(
        "union() { translate([-0.6, 0, 0]) sphere(1); translate([0.6, 0, 0]) sphere(1); }",
        [
            DVec3::new(0.0, rho, 0.0),
            DVec3::new(0.0, rho + 0.02, 0.01),
            DVec3::new(0.0, rho + 0.02, -0.01),
        ],
    );
    let expected = 0.8 - rho;
    assert!(
        (d - expected).abs() < 1e-5 * expected,
        "{d}, expected {expected}"
    );
}
