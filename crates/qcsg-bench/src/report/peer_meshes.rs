//! Section 2 of the report, the peers' meshes: OpenSCAD's CGAL export swept over `$fn`, and
//! the tables that put OpenSCAD's, Manifold's and build123d's meshes beside qcsg's sweep.

use std::fmt::Write as _;
use std::path::Path;
use std::time::Duration;

use qcsg_bench::mesh::parse_stl;
use qcsg_bench::openscad::{Export, export_stl};
use qcsg_bench::python_peer::Installed;

use crate::peers::{self, PeerRow, PythonScene};
use crate::{Config, Row, Scene, ms, secs};

/// How to install the Python peers, for the report.
const SETUP: &str = "Install them with `sh crates/qcsg-bench/peers/setup.sh` (a virtual \
    environment under `target/qcsg-bench-peers/`, versions pinned in \
    `crates/qcsg-bench/peers/requirements.txt`) and run the report again.";

/// What the peers measured, for sections 1 and 2.
pub struct Peers<'a> {
    /// OpenSCAD's version, where it ran.
    pub openscad: Option<&'a str>,
    /// Per scene, OpenSCAD's exports over `$fn` (empty where it did not run).
    pub openscad_rows: &'a [Vec<PeerRow>],
    pub manifold: &'a Result<Installed, String>,
    pub manifold_runs: Option<&'a [PythonScene]>,
    pub build123d: &'a Result<Installed, String>,
    pub build123d_runs: Option<&'a [PythonScene]>,
}

/// Exports every scene from OpenSCAD at each `$fn` of `fns`, each within `limit`, and measures
/// each mesh; a scene's sweep ends at its first timeout.
pub fn openscad(
    program: &Path,
    scenes: &[Scene],
    fns: &[u32],
    work: &Path,
    limit: Duration,
) -> Vec<Vec<PeerRow>> {
    let mut peer_rows: Vec<Vec<PeerRow>> = Vec::new();
    for scene in scenes {
        let mut list = Vec::new();
        for &f in fns {
            let export = export_stl(program, &scene.path, f, work, limit);
            let row = match export {
                Export::Done(bytes, time) => match parse_stl(&bytes) {
                    Ok(mesh) => PeerRow::of_mesh(scene, f.to_string(), "ok", time, &mesh),
                    Err(e) => PeerRow::failed(f.to_string(), time, &e),
                },
                Export::TimedOut(time) => PeerRow::failed(f.to_string(), time, "timed out"),
                Export::Failed(e) => PeerRow::failed(f.to_string(), Duration::ZERO, &e),
            };
            eprintln!(
                "openscad {} $fn={f}: {} in {:.2} s",
                scene.name,
                row.outcome,
                secs(row.time)
            );
            let stop = row.outcome == "timed out";
            list.push(row);
            if stop {
                break;
            }
        }
        peer_rows.push(list);
    }
    peer_rows
}

/// Why a peer has no table.
fn why_missing(err: Option<&String>) -> String {
    err.map_or_else(
        || "the peer did not run".to_owned(),
        |e| e.replace('|', "/"),
    )
}

/// Writes section 2: each peer's meshes beside qcsg's sweep `rows`.
pub fn write(
    md: &mut String,
    cfg: &Config,
    scenes: &[Scene],
    rows: &[Vec<Row>],
    peers: &Peers,
    peer_limit: u64,
) {
    let _ = writeln!(
        md,
        "## 2. The peers' meshes: OpenSCAD, Manifold, build123d (OpenCascade)\n"
    );
    let _ = writeln!(
        md,
        "Every peer gets the same solids: OpenSCAD reads the scene files; Manifold and build123d \
         build the same CSG trees (`crates/qcsg-bench/src/shape.rs`, checked against the files by \
         a test) in Python subprocesses (`crates/qcsg-bench/peers/peer.py`), whose times are \
         measured inside the script around the peer's own work; process times (interpreter, \
         imports, writing the STL files) are given separately. Each mesh's Hausdorff distance to \
         the exact surface is measured both ways: from every surface reference point to the \
         mesh (exact point-triangle distances), and from points spread over every triangle at \
         most diag/400 apart to the exact surface (projection onto the quadrics, kept where the \
         solid changes across the projection; else the nearest reference point). The plots in \
         section 1 draw it on the same axes as qcsg's coverage error; note they are different \
         measures: the mesh's distance to the surface against the samples' coverage of it.\n\n\
         The last columns put each mesh beside the quickest qcsg sampling of the sweep whose \
         coverage error is at most the mesh's Hausdorff distance, and give the ratio of the two \
         times (the peer's over qcsg's one-thread sampling, same run). \"none of the sweep\" \
         marks a mesh finer than qcsg's finest sampling (see section 1 for where and why the \
         sweep stops).\n"
    );
    let _ = writeln!(md, "### 2.1 OpenSCAD's CGAL export\n");
    match peers.openscad {
        None => {
            let _ = writeln!(
                md,
                "Not measured: OpenSCAD is not installed (or `--no-openscad` was given).\n"
            );
        }
        Some(version) => {
            let _ = writeln!(
                md,
                "{version}, `openscad -o scene.stl -D '$fn=N' scene.scad`, timed from start to exit \
                 (one process per export, {} s limit).\n",
                peer_limit
            );
            for ((scene, list), scene_rows) in scenes.iter().zip(peers.openscad_rows).zip(rows) {
                let _ = writeln!(md, "**{}**\n", scene.name);
                peers::table(md, scene, scene_rows, &cfg.radii, list, "$fn", "export");
            }
        }
    }
    let _ = writeln!(md, "### 2.2 Manifold\n");
    match (peers.manifold, peers.manifold_runs) {
        (Ok(m), Some(runs)) => {
            let _ = writeln!(
                md,
                "{} (Python bindings of the C++ library), `Manifold.sphere/cylinder/cube` with \
                 `circular_segments = n`, booleans by `batch_boolean`, timed from the first \
                 primitive to the mesh out (`to_mesh`). Spheres are refined octahedra (n rounded up \
                 to a multiple of 4).\n",
                m.version
            );
            for ((scene, run), scene_rows) in scenes.iter().zip(runs).zip(rows) {
                let _ = writeln!(md, "**{}** (process {} ms)\n", scene.name, ms(run.process));
                peers::table(
                    md, scene, scene_rows, &cfg.radii, &run.rows, "segments", "build",
                );
            }
        }
        _ => {
            let why = why_missing(peers.manifold.as_ref().err());
            let _ = writeln!(md, "Not measured: {why}. {SETUP}\n");
        }
    }
    let _ = writeln!(md, "### 2.3 build123d (OpenCascade)\n");
    match (peers.build123d, peers.build123d_runs) {
        (Ok(b), Some(runs)) => {
            let _ = writeln!(
                md,
                "{} on OpenCascade: `Sphere`, `Cylinder`, `Box` placed as OpenSCAD places them, \
                 `fuse`/`cut`/`intersect` with all tools at once; the exact boolean is timed, then \
                 checked (`is_valid`), then tessellated and written by `export_stl` at each linear \
                 tolerance (relative to the diagonal; angular tolerance 0.5 rad so that the linear \
                 one decides). The time column is the tessellation alone; the boolean's time is \
                 above each table, and the ratio uses boolean + tessellation.\n",
                b.version
            );
            for ((scene, run), scene_rows) in scenes.iter().zip(runs).zip(rows) {
                let (exact, valid) = run.exact.map_or_else(
                    || ("–".to_owned(), "not reached".to_owned()),
                    |(t, v)| {
                        (
                            ms(t),
                            if v {
                                "valid".into()
                            } else {
                                "**invalid**".into()
                            },
                        )
                    },
                );
                let _ = writeln!(
                    md,
                    "**{}**: exact boolean {exact} ms, {valid} (process {} ms)\n",
                    scene.name,
                    ms(run.process)
                );
                let with_boolean: Vec<PeerRow> = run
                    .rows
                    .iter()
                    .map(|r| PeerRow {
                        setting: r.setting.clone(),
                        outcome: r.outcome.clone(),
                        time: r.time + run.exact.map_or(Duration::ZERO, |e| e.0),
                        triangles: r.triangles,
                        surface_to_mesh: r.surface_to_mesh,
                        mesh_to_surface: r.mesh_to_surface,
                    })
                    .collect();
                peers::table(
                    md,
                    scene,
                    scene_rows,
                    &cfg.radii,
                    &with_boolean,
                    "tolerance",
                    "boolean + tessellation",
                );
            }
        }
        _ => {
            let why = why_missing(peers.build123d.as_ref().err());
            let _ = writeln!(md, "Not measured: {why}. {SETUP}\n");
        }
    }
}
