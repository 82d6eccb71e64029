//! Every example and stability scene exported at a coarse tolerance: the mesh must bound a
//! solid (watertight, every edge used twice in opposite directions, no degenerate triangle,
//! positive volume) and lie within the tolerance of the exact surface both ways, as measured
//! by the benchmarks' independent oracle (`qcsg_bench::mesh::mesh_distance`: exact ray-cast
//! reference points on the surface to the mesh, and points spread over the triangles projected
//! onto the quadrics).

use std::path::{Path, PathBuf};

use qcsg_bench::mesh::{Mesh, mesh_distance};
use qcsg_bench::reference::reference_points;
use qcsg_export::{ExportOptions, export, topology};

/// The tolerance, as a fraction of each scene's diagonal: coarse, so the debug build checks
/// every scene in seconds.
const TOLERANCE: f64 = 0.03;

/// Scenes with more surfaces meshed as level sets than this are left out (they export, slowly).
const MAX_LEVEL_SETS: usize = 8;

/// Scenes left out, each with the reason: they fail or are too slow (`docs/export.md`, "Known limits").
const KNOWN: &[(&str, &str)] = &[(
    "rounded_enclosure.scad",
    "too slow for the suite: it exports within the tolerance (19,176 triangles, 0.22 / 0.63 of T by the oracle), but took 810 s in the debug build on a loaded machine",
)];

fn scenes() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut files = Vec::new();
    for dir in ["examples", "tests/stability"] {
        for entry in std::fs::read_dir(root.join(dir)).expect("scene folder") {
            let path = entry.expect("entry").path();
            if matches!(
                path.extension().and_then(|e| e.to_str()),
                Some("qcsg" | "scad")
            ) {
                files.push(path);
            }
        }
    }
    files.sort();
    files
}

fn check(path: &Path) -> Result<String, String> {
    let text = std::fs::read_to_string(path).map_err(|e| e.to_string())?;
    let name = path.to_string_lossy();
    let compiled = qcsg_driver::compile(
        &name,
        text,
        &qcsg_driver::Options::default(),
        &qcsg_sema::FsLoader,
        qcsg_driver::Stage::Dnf,
    );
    let Some(dnf) = compiled.solid().filter(|_| !compiled.has_errors()) else {
        return Ok("no solid (errors or unbounded)".into());
    };
    if dnf.terms.is_empty() {
        return Ok("empty".into());
    }
    if dnf.terms.iter().any(|t| !t.bounds.is_bounded()) {
        return Ok("unbounded".into());
    }
    // Text is made of parabolic cylinders, each a level set: too slow for a debug-build test.
    let level_sets = qcsg_export::level_set_surfaces(dnf);
    if level_sets > MAX_LEVEL_SETS {
        return Ok(format!("skipped: {level_sets} level-set surfaces"));
    }
    let diagonal = (dnf.bounds.max - dnf.bounds.min).length();
    let tolerance = TOLERANCE * diagonal;
    let exported =
        export(dnf, &ExportOptions::new(tolerance), &|_| {}).map_err(|e| e.to_string())?;
    let mesh = &exported.mesh;
    let topo = topology(mesh);
    if !topo.is_closed_solid() {
        return Err(format!("not a closed solid: {topo:?}"));
    }
    let soup = Mesh {
        triangles: mesh.triangle_soup(),
    };
    // The oracle's mesh-to-surface distance is an upper bound that is loose near feature
    // curves when its reference points are sparse (a mesh point whose projection onto a quadric
    // lands off the solid's surface walks towards the nearest reference point of that quadric,
    // which may lie the wrong way): where it exceeds the tolerance with 600 rays it is measured
    // again with ten times as many, which a mesh truly too far still fails.
    let mut measured = mesh_distance(dnf, &soup, &reference_points(dnf, 600, 7), tolerance / 2.0);
    if measured.mesh_to_surface > tolerance * 1.25 {
        measured = mesh_distance(dnf, &soup, &reference_points(dnf, 6000, 7), tolerance / 2.0);
    }
    // The oracle's mesh-to-surface points are within spacing/2 of every mesh point.
    if measured.surface_to_mesh > tolerance || measured.mesh_to_surface > tolerance * 1.25 {
        return Err(format!(
            "deviation {:.3} / {:.3} of the tolerance (surface to mesh / mesh to surface)",
            measured.surface_to_mesh / tolerance,
            measured.mesh_to_surface / tolerance
        ));
    }
    Ok(format!(
        "{} triangles, deviation {:.2} / {:.2} of T",
        mesh.triangles.len(),
        measured.surface_to_mesh / tolerance,
        measured.mesh_to_surface / tolerance
    ))
}

#[test]
fn every_scene_exports_a_closed_mesh_within_the_tolerance() {
    // `QCSG_EXPORT_ONLY=NAME[,NAME]` checks just those scenes, known failures included.
    let only = std::env::var("QCSG_EXPORT_ONLY").ok();
    let mut failures = Vec::new();
    for path in scenes() {
        let name = path
            .file_name()
            .and_then(|n| n.to_str())
            .unwrap_or_default()
            .to_owned();
        match &only {
            Some(only) if !only.split(',').any(|o| name.starts_with(o)) => continue,
            None if KNOWN.iter().any(|(k, _)| *k == name) => continue,
            _ => {}
        }
        let started = std::time::Instant::now();
        let outcome = check(&path);
        eprintln!(
            "{name}: {outcome:?} in {:.2} s",
            started.elapsed().as_secs_f64()
        );
        if let Err(e) = outcome {
            failures.push(format!("{name}: {e}"));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// A cube's DNF, from source.
fn cube_dnf() -> qcsg_csg::Dnf {
    let compiled = qcsg_driver::compile(
        "cube.scad",
        "cube(2, center = true);".into(),
        &qcsg_driver::Options::default(),
        &qcsg_sema::FsLoader,
        qcsg_driver::Stage::Dnf,
    );
    compiled.solid().expect("a cube").clone()
}

#[test]
fn the_solid_bounds_the_mesh_where_the_surface_points_are_too_sparse() {
    use qcsg_export::{TriangleMesh, measure_deviation, measure_deviation_of_solid};
    use qcsg_quadric::DVec3;
    let dnf = cube_dnf();
    // The cube's 12 faces, and one surface point only: at a corner.
    let vertices: Vec<DVec3> = (0..8)
        .map(|i| {
            DVec3::new(
                if i & 1 == 0 { -1.0 } else { 1.0 },
                if i & 2 == 0 { -1.0 } else { 1.0 },
                if i & 4 == 0 { -1.0 } else { 1.0 },
            )
        })
        .collect();
    let faces = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let triangles = faces
        .iter()
        .flat_map(|[a, b, c, d]| [[*a, *b, *c], [*a, *c, *d]])
        .collect();
    let surface = TriangleMesh {
        vertices,
        triangles,
    };
    let points = [DVec3::ONE];
    let tolerance = 0.01;
    let from_points = measure_deviation(&surface, &points, 0.0, tolerance, tolerance / 8.0);
    assert!(from_points.mesh_to_surface > 1.0, "{from_points:?}");
    let from_solid =
        measure_deviation_of_solid(&dnf, &surface, &points, 0.0, tolerance, tolerance / 8.0);
    assert!(from_solid.mesh_to_surface <= tolerance, "{from_solid:?}");

    // A wall through the middle of the cube is a whole unit from its surface.
    let wall = TriangleMesh {
        vertices: vec![
            DVec3::new(-0.9, -0.9, 0.0),
            DVec3::new(0.9, -0.9, 0.0),
            DVec3::new(0.0, 0.9, 0.0),
        ],
        triangles: vec![[0, 1, 2]],
    };
    let inside = measure_deviation_of_solid(&dnf, &wall, &points, 0.0, tolerance, tolerance / 8.0);
    assert!(inside.mesh_to_surface >= 0.9, "{inside:?}");
}

/// Exports `source` (OpenSCAD) at `fraction` of its diagonal, failing the test on any error.
fn export_source(source: &str, fraction: f64) -> (qcsg_csg::Dnf, qcsg_export::TriangleMesh) {
    let compiled = qcsg_driver::compile(
        "scene.scad",
        source.into(),
        &qcsg_driver::Options::default(),
        &qcsg_sema::FsLoader,
        qcsg_driver::Stage::Dnf,
    );
    let dnf = compiled.solid().expect("a solid").clone();
    let tolerance = fraction * (dnf.bounds.max - dnf.bounds.min).length();
    let exported = export(&dnf, &ExportOptions::new(tolerance), &|_| {}).expect("exports");
    (dnf, exported.mesh)
}

#[test]
fn touching_cells_of_a_polygon_become_one_shell() {
    // A square with a square and a triangular hole: the normal form cuts it into convex cells
    // that share faces, each meshed on its own. Without growing the shared faces, the union
    // kept a wall between every two touching cells (several shells, 8 triangles inside).
    let (dnf, mesh) = export_source(
        "linear_extrude(height = 4, center = true) polygon(\
             points = [[0, 0], [20, 0], [20, 14], [0, 14], [3, 3], [8, 3], [8, 9], [3, 9], \
                       [12, 3], [17, 3], [14.5, 11]], \
             paths = [[0, 1, 2, 3], [4, 5, 6, 7], [10, 9, 8]]);",
        0.01,
    );
    assert!(dnf.terms.len() > 1, "cells: {}", dnf.terms.len());
    let topo = topology(&mesh);
    assert!(topo.is_closed_solid(), "{topo:?}");
    // One shell with two tunnels: a torus of genus 2.
    assert_eq!(
        (topo.shells, topo.euler_characteristic),
        (1, -2),
        "{topo:?}"
    );
    // The prism's faces are planes, meshed exactly: the volume is the outline's area (280
    // minus holes of 30 and 20) times the height, up to the growth's steps.
    assert!((topo.volume - 920.0).abs() < 1e-6, "{topo:?}");
    // No step left by the growth: every edge is longer than a millionth of the diagonal.
    let diagonal = (dnf.bounds.max - dnf.bounds.min).length();
    for t in &mesh.triangles {
        let [a, b, c] = mesh.corners(t);
        for (p, q) in [(a, b), (b, c), (c, a)] {
            assert!((p - q).length() > 1e-6 * diagonal, "edge {p} {q}");
        }
    }
}

#[test]
fn a_flush_pocket_keeps_no_lid_where_faces_are_grown() {
    // The pocket's top is the cube's top face: the term between the two is flat and must
    // stay flat (dropped), not be grown from both sides into a lid over the pocket.
    let (dnf, mesh) = export_source(
        "difference() { cube(10); translate([3, 3, 5]) cube([4, 4, 5]); }",
        0.01,
    );
    let topo = topology(&mesh);
    assert!(topo.is_closed_solid(), "{topo:?}");
    assert_eq!(topo.shells, 1, "{topo:?}");
    assert!((topo.volume - 920.0).abs() < 1e-6, "{topo:?}");
    // Above the pocket's floor, inside it, is outside the solid and outside the mesh.
    let soup = mesh.triangle_soup();
    let top = soup
        .iter()
        .filter(|[a, b, c]| {
            let centre = (*a + *b + *c) / 3.0;
            (centre.z - 10.0).abs() < 1e-6
                && (3.0..7.0).contains(&centre.x)
                && (3.0..7.0).contains(&centre.y)
        })
        .count();
    assert_eq!(top, 0, "triangles over the pocket at the top: {top}");
    assert!(!dnf.contains(qcsg_quadric::DVec3::new(5.0, 5.0, 9.0)));
}
