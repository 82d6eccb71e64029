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
//! of the library files it may include; `qcsg_testkit::openscad`), so OpenSCAD runs again whenever a scene changes and always on a
//! fresh checkout. Set `OPENSCAD` to the command's path if it is not `openscad` on `PATH`.

use std::collections::hash_map::DefaultHasher;
use std::hash::{Hash, Hasher};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::Duration;

use glam::DVec3;
use qcsg_csg::{DnfOptions, build_dnf};
use qcsg_eval::{EvalOptions, evaluate};
use qcsg_sema::{CheckOptions, FsLoader, check_file};
use qcsg_testkit::openscad::{Export, tessellation_tolerance};
use qcsg_testkit::{Rng, TriangleMesh};

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

/// OpenSCAD's mesh of `scene`, cached under the test target directory by the content of the
/// scene and of the library files it may read.
fn openscad_mesh(scene: &Path) -> Result<TriangleMesh, String> {
    let mut export = Export::new(
        scene,
        Path::new(env!("CARGO_TARGET_TMPDIR")).join("openscad-stl"),
    );
    export.inputs = std::fs::read_dir(scenes_dir().join("lib"))
        .map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    // CGAL's hulls of rounded shapes take many minutes on a loaded machine; the export is
    // cached, so only a changed scene pays for it.
    export.timeout = Duration::from_secs(3600);
    export.mesh().map_err(|e| e.to_string())
}

/// A seed fixed by the scene's text, so that every run tests the same points.
fn seed(text: &str) -> u64 {
    let mut hasher = DefaultHasher::new();
    text.hash(&mut hasher);
    hasher.finish()
}

/// What comparing one scene found.
struct Comparison {
    inside: usize,
    outside: usize,
    disagreements: Vec<String>,
}

fn compare(scene: &Path, mesh: &TriangleMesh) -> Result<Comparison, String> {
    let text = std::fs::read_to_string(scene).map_err(|e| e.to_string())?;
    let fragments =
        fragments(&text).ok_or("the scene states no `$fn = N;` or `// fragments: N`")?;
    let half_diagonal = 0.5 * (mesh.max - mesh.min).length();
    let tolerance = tessellation_tolerance(fragments, half_diagonal);

    let name = scene.to_string_lossy().into_owned();
    let analysis = check_file(&name, text.clone(), &CheckOptions::default(), &FsLoader);
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
    let mut points = Rng::new(seed(&text));
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
                    let outcome = openscad_mesh(scene).and_then(|mesh| compare(scene, &mesh));
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
