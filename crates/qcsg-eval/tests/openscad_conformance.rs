//! Conformance with OpenSCAD 2021.01: every `tests/openscad/NAME.scad` of the repository is
//! exported to STL by the `openscad` command and evaluated by qcsg, and for many points away
//! from the surface qcsg's solid (both the DAG and its DNF) must agree with the mesh on which
//! points are inside.
//!
//! - Inside the mesh means a generalised winding number above one half (robust for the closed
//!   meshes OpenSCAD writes).
//! - OpenSCAD approximates curved surfaces by polygons, qcsg does not: points closer to the mesh
//!   than the tessellation error are skipped. The error of a circle of radius `r` cut into `n`
//!   fragments is `r (1 − cos(π/n))`; a scene states its smallest fragment count with a
//!   top-level `$fn = N;` or a `// fragments: N` comment, and the tolerance takes `r` as the
//!   half-diagonal of the mesh's box (generous, so that no curved part is missed).
//! - Each scene must leave enough points on each side for the comparison to mean something.
//!
//! The STL files are cached under the test target directory by a hash of the scene's text (and
//! of the files it includes), so OpenSCAD runs again whenever a scene changes and always on a
//! fresh checkout. Set `OPENSCAD` to the command's path if it is not `openscad` on `PATH`.

use std::collections::hash_map::DefaultHasher;
use std::hash::{Hash, Hasher};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Mutex;

use glam::DVec3;
use qcsg_csg::{DnfOptions, build_dnf};
use qcsg_eval::{EvalOptions, evaluate};
use qcsg_sema::{CheckOptions, FsLoader, check_file};

/// Random points tried per scene.
const POINTS_PER_SCENE: usize = 600;
/// The fewest points required on each side of the surface.
const MIN_POINTS_PER_SIDE: usize = 25;

fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/openscad")
}

fn scenes() -> Vec<PathBuf> {
    let mut scenes: Vec<PathBuf> = std::fs::read_dir(scenes_dir())
        .expect("tests/openscad exists")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "scad"))
        .collect();
    scenes.sort();
    scenes
}

/// A triangle mesh as OpenSCAD exports it.
struct Mesh {
    triangles: Vec<[DVec3; 3]>,
    min: DVec3,
    max: DVec3,
}

impl Mesh {
    /// Reads an ASCII STL file (what OpenSCAD 2021.01 writes).
    fn parse_ascii_stl(text: &str) -> Result<Mesh, String> {
        let mut vertices = Vec::new();
        for line in text.lines() {
            let Some(rest) = line.trim().strip_prefix("vertex") else {
                continue;
            };
            let coords: Vec<f64> = rest
                .split_whitespace()
                .map(|c| c.parse::<f64>().map_err(|e| format!("{c:?}: {e}")))
                .collect::<Result<_, _>>()?;
            let [x, y, z] = coords[..] else {
                return Err(format!("vertex line with {} coordinates", coords.len()));
            };
            vertices.push(DVec3::new(x, y, z));
        }
        if vertices.is_empty() || vertices.len() % 3 != 0 {
            return Err(format!("{} vertices: not a triangle mesh", vertices.len()));
        }
        let triangles: Vec<[DVec3; 3]> = vertices.chunks(3).map(|t| [t[0], t[1], t[2]]).collect();
        let min = vertices.iter().fold(DVec3::INFINITY, |m, v| m.min(*v));
        let max = vertices.iter().fold(DVec3::NEG_INFINITY, |m, v| m.max(*v));
        Ok(Mesh {
            triangles,
            min,
            max,
        })
    }

    /// The generalised winding number of the mesh around `p` (1 inside a closed mesh, 0
    /// outside): the sum of the triangles' signed solid angles over 4π (Van Oosterom and
    /// Strackee's formula).
    fn winding_number(&self, p: DVec3) -> f64 {
        let mut total = 0.0;
        for [a, b, c] in &self.triangles {
            let (a, b, c) = (*a - p, *b - p, *c - p);
            let (la, lb, lc) = (a.length(), b.length(), c.length());
            let numerator = a.dot(b.cross(c));
            let denominator = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
            total += 2.0 * numerator.atan2(denominator);
        }
        total / (4.0 * std::f64::consts::PI)
    }

    /// Whether some triangle comes closer to `p` than `distance`.
    fn is_within(&self, p: DVec3, distance: f64) -> bool {
        let squared = distance * distance;
        self.triangles
            .iter()
            .any(|t| closest_point_on_triangle(p, t).distance_squared(p) < squared)
    }
}

/// The point of triangle `[a, b, c]` closest to `p` (Ericson, Real-Time Collision Detection,
/// 5.1.5).
fn closest_point_on_triangle(p: DVec3, &[a, b, c]: &[DVec3; 3]) -> DVec3 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denominator = 1.0 / (va + vb + vc);
    a + ab * (vb * denominator) + ac * (vc * denominator)
}

/// The smallest fragment count of the scene's curved primitives: `// fragments: N`, else the
/// top-level `$fn = N;`.
fn fragments(text: &str) -> Option<f64> {
    let stated = text
        .lines()
        .find_map(|l| l.trim().strip_prefix("// fragments:"))
        .or_else(|| {
            text.lines()
                .find_map(|l| l.trim().strip_prefix("$fn ="))
                .map(|rest| rest.trim_end_matches(';'))
        })?;
    stated.trim().parse().ok().filter(|n: &f64| *n >= 3.0)
}

/// A small deterministic generator (xorshift64*), so that every run tests the same points.
struct Points(u64);

impl Points {
    fn unit(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }

    fn in_box(&mut self, min: DVec3, max: DVec3) -> DVec3 {
        DVec3::new(
            min.x + (max.x - min.x) * self.unit(),
            min.y + (max.y - min.y) * self.unit(),
            min.z + (max.z - min.z) * self.unit(),
        )
    }
}

/// A hash of the scene's text and of the library files it may read.
fn content_hash(scene: &Path) -> u64 {
    let mut hasher = DefaultHasher::new();
    std::fs::read(scene).unwrap_or_default().hash(&mut hasher);
    let lib = scenes_dir().join("lib");
    let mut lib_files: Vec<PathBuf> = std::fs::read_dir(&lib)
        .map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    lib_files.sort();
    for file in lib_files {
        std::fs::read(&file).unwrap_or_default().hash(&mut hasher);
    }
    hasher.finish()
}

/// The STL OpenSCAD exports for `scene`, from the cache or by running `openscad`.
fn openscad_stl(scene: &Path) -> Result<String, String> {
    let cache = Path::new(env!("CARGO_TARGET_TMPDIR")).join("openscad-stl");
    std::fs::create_dir_all(&cache).map_err(|e| e.to_string())?;
    let stem = scene.file_stem().unwrap_or_default().to_string_lossy();
    let cached = cache.join(format!("{stem}-{:016x}.stl", content_hash(scene)));
    if let Ok(text) = std::fs::read_to_string(&cached) {
        return Ok(text);
    }
    let partial = cached.with_extension("partial.stl");
    let openscad = std::env::var("OPENSCAD").unwrap_or_else(|_| "openscad".to_owned());
    let output = Command::new(&openscad)
        .arg("-q")
        .arg("-o")
        .arg(&partial)
        .arg(scene)
        .env_remove("DISPLAY")
        // Export needs no display; without this Qt may still look for one.
        .env(
            "QT_QPA_PLATFORM",
            std::env::var("QT_QPA_PLATFORM").unwrap_or_else(|_| "offscreen".to_owned()),
        )
        .output()
        .map_err(|e| format!("cannot run `{openscad}` (install OpenSCAD 2021.01): {e}"))?;
    if !output.status.success() {
        return Err(format!(
            "openscad failed: {}",
            String::from_utf8_lossy(&output.stderr)
        ));
    }
    std::fs::rename(&partial, &cached).map_err(|e| e.to_string())?;
    std::fs::read_to_string(&cached).map_err(|e| e.to_string())
}

/// What comparing one scene found.
struct Comparison {
    inside: usize,
    outside: usize,
    disagreements: Vec<String>,
}

fn compare(scene: &Path, stl: &str) -> Result<Comparison, String> {
    let text = std::fs::read_to_string(scene).map_err(|e| e.to_string())?;
    let fragments =
        fragments(&text).ok_or("the scene states no `$fn = N;` or `// fragments: N`")?;
    let mesh = Mesh::parse_ascii_stl(stl)?;
    let half_diagonal = 0.5 * (mesh.max - mesh.min).length();
    let tolerance = 2.5 * half_diagonal * (1.0 - (std::f64::consts::PI / fragments).cos()) + 1e-3;

    let name = scene.to_string_lossy().into_owned();
    let analysis = check_file(&name, text, &CheckOptions::default(), &FsLoader);
    let evaluation = evaluate(&analysis, &EvalOptions::default());
    let errors: Vec<String> = analysis
        .diagnostics
        .iter()
        .chain(&evaluation.diagnostics)
        .filter(|d| d.is_error())
        .map(|d| format!("{} {}", d.code, d.message))
        .collect();
    if !errors.is_empty() {
        return Err(format!("qcsg errors: {errors:?}"));
    }
    let dag = &evaluation.dag;
    let dnf = build_dnf(dag, &DnfOptions::default()).map_err(|e| format!("DNF: {e:?}"))?;

    let margin = 0.15 * (mesh.max - mesh.min) + DVec3::splat(0.5);
    let (low, high) = (mesh.min - margin, mesh.max + margin);
    let mut points = Points(content_hash(scene) | 1);
    let mut comparison = Comparison {
        inside: 0,
        outside: 0,
        disagreements: Vec::new(),
    };
    for i in 0..POINTS_PER_SCENE {
        // Half the points anywhere in the box, half near the surface (on either side of a
        // random triangle), so that thin and sparse scenes get points inside too.
        let p = if i % 2 == 0 {
            points.in_box(low, high)
        } else {
            let [a, b, c] = mesh.triangles
                [(points.unit() * mesh.triangles.len() as f64) as usize % mesh.triangles.len()];
            let (u, v) = (points.unit(), points.unit());
            let (u, v) = if u + v > 1.0 {
                (1.0 - u, 1.0 - v)
            } else {
                (u, v)
            };
            let on_surface = a + (b - a) * u + (c - a) * v;
            let normal = (b - a).cross(c - a).normalize_or_zero();
            let offset = (2.0 * points.unit() - 1.0) * 0.1 * half_diagonal;
            on_surface + normal * offset
        };
        if mesh.is_within(p, tolerance) {
            continue;
        }
        let in_mesh = mesh.winding_number(p) > 0.5;
        if in_mesh {
            comparison.inside += 1;
        } else {
            comparison.outside += 1;
        }
        let (in_dag, in_dnf) = (dag.contains(p), dnf.contains(p));
        if in_dag != in_mesh || in_dnf != in_mesh {
            comparison.disagreements.push(format!(
                "({:.4}, {:.4}, {:.4}): OpenSCAD {}, qcsg DAG {}, DNF {}",
                p.x,
                p.y,
                p.z,
                side(in_mesh),
                side(in_dag),
                side(in_dnf)
            ));
        }
    }
    Ok(comparison)
}

fn side(inside: bool) -> &'static str {
    if inside { "inside" } else { "outside" }
}

#[test]
fn membership_agrees_with_openscad_meshes() {
    let scenes = scenes();
    assert!(scenes.len() >= 30, "only {} scenes", scenes.len());
    // OpenSCAD runs (the slow part) in parallel; each worker then compares its scene.
    let next = Mutex::new(scenes.iter());
    let results = Mutex::new(Vec::new());
    let workers = std::thread::available_parallelism().map_or(2, |n| n.get().min(8));
    std::thread::scope(|s| {
        for _ in 0..workers {
            s.spawn(|| {
                loop {
                    let Some(scene) = next.lock().unwrap().next() else {
                        break;
                    };
                    let outcome = openscad_stl(scene).and_then(|stl| compare(scene, &stl));
                    results.lock().unwrap().push((scene.clone(), outcome));
                }
            });
        }
    });
    let mut results = results.into_inner().unwrap();
    results.sort_by(|a, b| a.0.cmp(&b.0));
    let mut failures = Vec::new();
    for (scene, outcome) in results {
        let name = scene.file_name().unwrap_or_default().to_string_lossy();
        match outcome {
            Err(e) => failures.push(format!("{name}: {e}")),
            Ok(c) if c.inside < MIN_POINTS_PER_SIDE || c.outside < MIN_POINTS_PER_SIDE => {
                failures.push(format!(
                    "{name}: too few points to compare ({} inside, {} outside)",
                    c.inside, c.outside
                ));
            }
            Ok(c) if !c.disagreements.is_empty() => failures.push(format!(
                "{name}: {} of {} points disagree, e.g.\n    {}",
                c.disagreements.len(),
                c.inside + c.outside,
                c.disagreements[..c.disagreements.len().min(5)].join("\n    ")
            )),
            Ok(_) => {}
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn winding_number_separates_inside_from_outside_of_a_cube() {
    let stl = "solid t\n".to_owned()
        + &cube_facets()
            .iter()
            .map(|[a, b, c]| {
                format!(
                    "facet normal 0 0 0\nouter loop\nvertex {} {} {}\nvertex {} {} {}\n\
                     vertex {} {} {}\nendloop\nendfacet\n",
                    a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z
                )
            })
            .collect::<String>()
        + "endsolid t\n";
    let mesh = Mesh::parse_ascii_stl(&stl).expect("valid STL");
    assert_eq!(mesh.triangles.len(), 12);
    assert!((mesh.winding_number(DVec3::splat(0.5)) - 1.0).abs() < 1e-9);
    assert!(mesh.winding_number(DVec3::new(1.5, 0.5, 0.5)).abs() < 1e-9);
    assert!(mesh.is_within(DVec3::new(0.5, 0.5, 1.05), 0.1));
    assert!(!mesh.is_within(DVec3::new(0.5, 0.5, 1.2), 0.1));
    assert!(!mesh.is_within(DVec3::splat(0.5), 0.4));
}

/// The unit cube's twelve triangles, outward-facing.
fn cube_facets() -> Vec<[DVec3; 3]> {
    let v = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
    let quads = [
        [v(0., 0., 0.), v(0., 1., 0.), v(1., 1., 0.), v(1., 0., 0.)],
        [v(0., 0., 1.), v(1., 0., 1.), v(1., 1., 1.), v(0., 1., 1.)],
        [v(0., 0., 0.), v(1., 0., 0.), v(1., 0., 1.), v(0., 0., 1.)],
        [v(0., 1., 0.), v(0., 1., 1.), v(1., 1., 1.), v(1., 1., 0.)],
        [v(0., 0., 0.), v(0., 0., 1.), v(0., 1., 1.), v(0., 1., 0.)],
        [v(1., 0., 0.), v(1., 1., 0.), v(1., 1., 1.), v(1., 0., 1.)],
    ];
    quads
        .iter()
        .flat_map(|[a, b, c, d]| [[*a, *b, *c], [*a, *c, *d]])
        .collect()
}
