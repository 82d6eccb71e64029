//! The peers' meshes of the benchmark scenes: OpenSCAD's CGAL export, Manifold's mesh booleans
//! and build123d's exact booleans tessellated at a sweep of tolerances; each mesh's Hausdorff
//! distance to the exact surface, and the table that puts it beside qcsg's sampling of equal
//! error.

use std::fmt::Write as _;
use std::path::Path;
use std::time::Duration;

use qcsg_bench::mesh::{Mesh, mesh_distance};
use qcsg_bench::python_peer::{self, Installed, Peer};
use qcsg_bench::shape::benchmark_scene;

use crate::{Row, Scene, ms, sci, secs};

/// One mesh of a peer and its distance to the exact surface.
pub struct PeerRow {
    /// The setting as the peer names it (`$fn = 16`, `n = 64`, `tolerance 1e-3 diag`).
    pub setting: String,
    /// "ok", "invalid", or why there is no mesh.
    pub outcome: String,
    /// The peer's time for this mesh (see the table's heading).
    pub time: Duration,
    pub triangles: usize,
    pub surface_to_mesh: f64,
    pub mesh_to_surface: f64,
}

impl PeerRow {
    /// The mesh's Hausdorff distance to the exact surface (∞ without a mesh).
    pub fn hausdorff(&self) -> f64 {
        self.surface_to_mesh.max(self.mesh_to_surface)
    }

    /// Whether the row has a measured mesh.
    pub fn measured(&self) -> bool {
        self.hausdorff().is_finite()
    }

    /// A row of a mesh, measured against `scene`'s exact surface.
    pub fn of_mesh(
        scene: &Scene,
        setting: String,
        outcome: &str,
        time: Duration,
        mesh: &Mesh,
    ) -> Self {
        let d = mesh_distance(&scene.dnf, mesh, &scene.refs.surface, scene.diag / 400.0);
        PeerRow {
            setting,
            outcome: outcome.into(),
            time,
            triangles: mesh.triangles.len(),
            surface_to_mesh: d.surface_to_mesh,
            mesh_to_surface: d.mesh_to_surface,
        }
    }

    /// A row without a mesh.
    pub fn failed(setting: String, time: Duration, why: &str) -> Self {
        PeerRow {
            setting,
            outcome: why.replace('|', "/"),
            time,
            triangles: 0,
            surface_to_mesh: f64::INFINITY,
            mesh_to_surface: f64::INFINITY,
        }
    }
}

/// What one Python peer gave for one scene.
pub struct PythonScene {
    /// One row per setting (for build123d, per tolerance).
    pub rows: Vec<PeerRow>,
    /// build123d's exact boolean: time and validity.
    pub exact: Option<(Duration, bool)>,
    /// Wall time of the whole process.
    pub process: Duration,
}

/// Manifold's segment counts, or build123d's tolerances relative to the diagonal.
pub fn settings(peer: Peer, quick: bool) -> Vec<f64> {
    match (peer, quick) {
        (Peer::Manifold, true) => vec![16.0, 64.0],
        (Peer::Manifold, false) => vec![8.0, 16.0, 32.0, 64.0, 128.0, 256.0],
        (Peer::Build123d, true) => vec![1e-2, 1e-3],
        (Peer::Build123d, false) => vec![1e-2, 3e-3, 1e-3, 3e-4, 1e-4],
    }
}

/// Runs a Python peer over every benchmark scene.
pub fn run_python(
    installed: &Installed,
    scenes: &[Scene],
    quick: bool,
    work: &Path,
    limit: Duration,
) -> Result<Vec<PythonScene>, String> {
    let mut out = Vec::new();
    for scene in scenes {
        let shape =
            benchmark_scene(&scene.name).ok_or_else(|| format!("no tree of {}", scene.name))?;
        let relative = settings(installed.peer, quick);
        let absolute: Vec<f64> = match installed.peer {
            Peer::Manifold => relative.clone(),
            Peer::Build123d => relative.iter().map(|t| t * scene.diag).collect(),
        };
        let run = python_peer::run(
            installed,
            &shape,
            &absolute,
            &work.join(format!("{}-{}", installed.peer.name(), scene.name)),
            limit,
        );
        let mut rows = Vec::new();
        let mut exact = None;
        for r in &run.results {
            let Some(setting) = r.setting else {
                exact = Some((r.time, r.valid));
                continue;
            };
            let label = match installed.peer {
                Peer::Manifold => format!("n = {setting}"),
                Peer::Build123d => format!("{} diag", sci(setting / scene.diag)),
            };
            let outcome = if r.valid { "ok" } else { "invalid" };
            rows.push(match &r.mesh {
                Some(mesh) => PeerRow::of_mesh(scene, label, outcome, r.time, mesh),
                None => PeerRow::failed(label, r.time, "no mesh"),
            });
        }
        // The setting in progress when the process stopped.
        if let Some(why) = &run.failure {
            let done = rows.len();
            let next = relative.get(done).map_or_else(
                || "–".to_owned(),
                |s| match installed.peer {
                    Peer::Manifold => format!("n = {s}"),
                    Peer::Build123d => format!("{} diag", sci(*s)),
                },
            );
            rows.push(PeerRow::failed(next, run.process, why));
        }
        eprintln!(
            "{} {}: {} meshes, process {:.2} s{}",
            installed.peer.name(),
            scene.name,
            rows.iter().filter(|r| r.measured()).count(),
            secs(run.process),
            run.failure
                .as_deref()
                .map_or_else(String::new, |f| format!(" ({f})"))
        );
        out.push(PythonScene {
            rows,
            exact,
            process: run.process,
        });
    }
    Ok(out)
}

/// The quickest qcsg sampling of the sweep whose coverage error is at most `error`: its
/// relative radius and time.
pub fn matching_sampling<'a>(rows: &'a [Row], radii: &[f64], error: f64) -> Option<(f64, &'a Row)> {
    rows.iter()
        .zip(radii)
        .filter(|(r, _)| {
            r.m.coverage
                .max_distance
                .max(r.m.edge_coverage.max_distance)
                <= error
        })
        .min_by(|a, b| a.0.m.time.cmp(&b.0.m.time))
        .map(|(r, &rel)| (rel, r))
}

/// One scene's table of a peer's meshes beside qcsg's samplings.
pub fn table(
    md: &mut String,
    scene: &Scene,
    scene_rows: &[Row],
    radii: &[f64],
    list: &[PeerRow],
    setting: &str,
    time: &str,
) {
    let _ = writeln!(
        md,
        "| {setting} | outcome | {time} ms | triangles | surface → mesh / diag | mesh → surface / diag | Hausdorff / diag | qcsg r / diag | qcsg sampling ms | time ratio |"
    );
    let _ = writeln!(md, "|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|");
    for p in list {
        let hausdorff = p.hausdorff();
        let (qr, qt, ratio) = match matching_sampling(scene_rows, radii, hausdorff) {
            Some((rel, r)) if p.measured() => (
                rel.to_string(),
                ms(r.m.time),
                format!("{:.2}", secs(p.time) / secs(r.m.time).max(1e-9)),
            ),
            _ if p.measured() => ("none of the sweep".into(), "–".into(), "–".into()),
            _ => ("–".into(), "–".into(), "–".into()),
        };
        let (s2m, m2s, h) = if p.measured() {
            (
                sci(p.surface_to_mesh / scene.diag),
                sci(p.mesh_to_surface / scene.diag),
                sci(hausdorff / scene.diag),
            )
        } else {
            ("–".into(), "–".into(), "–".into())
        };
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {s2m} | {m2s} | {h} | {qr} | {qt} | {ratio} |",
            p.setting,
            p.outcome,
            ms(p.time),
            p.triangles,
        );
    }
    let _ = writeln!(md);
}

/// Time ratios (peer over qcsg) of the rows that have a qcsg sampling of equal error.
pub fn ratios(scene_rows: &[Row], radii: &[f64], list: &[PeerRow]) -> Vec<f64> {
    list.iter()
        .filter(|p| p.measured())
        .filter_map(|p| {
            let (_, r) = matching_sampling(scene_rows, radii, p.hausdorff())?;
            Some(secs(p.time) / secs(r.m.time).max(1e-9))
        })
        .collect()
}
