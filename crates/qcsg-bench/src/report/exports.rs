//! The report's section on `qcsg export`: each benchmark scene meshed at a sweep of tolerances,
//! the export's time, triangles and measured two-way distance to the exact surface, beside the
//! quickest mesh of each peer (OpenSCAD, Manifold, build123d) whose distance is no larger, as a
//! table and a figure per scene.

use std::fmt::Write as _;
use std::path::Path;
use std::time::{Duration, Instant};

use qcsg_bench::mesh::Mesh;
use qcsg_bench::plot::{Plot, Series};
use qcsg_export::{ExportOptions, export};

use crate::peer_meshes::Peers;
use crate::peers::PeerRow;
use crate::{Scene, ms, one_thread, sci, secs};

/// The heading that starts the section; `--meshes-only` replaces the report's text from it to
/// the next section.
pub const HEADING: &str = "## 9. Meshes: `qcsg export` beside the peers";

/// One export of one scene.
pub struct ExportRow {
    /// The tolerance asked for, relative to the diagonal.
    pub tolerance: f64,
    /// The mesh measured as the peers' are (setting, time, triangles, distances).
    pub mesh: PeerRow,
    /// How many times the literals were meshed (1 when the first mesh passed the check).
    pub passes: u32,
}

/// The tolerances of the sweep, relative to each scene's diagonal. The export checks its mesh
/// by sampling at `T/2`, whose count grows as `T⁻²`: below 1e-3 of the diagonal the check alone
/// would pass the sample limit that stops the sampling sweep of section 1.
pub fn tolerances(quick: bool) -> Vec<f64> {
    if quick {
        vec![3e-2, 1e-2, 3e-3]
    } else {
        vec![3e-2, 1e-2, 3e-3, 1e-3]
    }
}

/// Exports every scene at every tolerance of `relative`, on one thread, each mesh measured
/// against the exact surface by the peers' oracle.
pub fn measure(scenes: &[Scene], relative: &[f64]) -> Result<Vec<Vec<ExportRow>>, String> {
    let mut all = Vec::new();
    for scene in scenes {
        let mut rows = Vec::new();
        for &t in relative {
            let options = ExportOptions::new(t * scene.diag);
            let (result, time) = one_thread(|| {
                let started = Instant::now();
                let result = export(&scene.dnf, &options, &|_| {});
                (result, started.elapsed())
            })?;
            let setting = format!("{} diag", sci(t));
            let row = match result {
                Ok(exported) => {
                    let soup = Mesh {
                        triangles: exported.mesh.triangle_soup(),
                    };
                    ExportRow {
                        tolerance: t,
                        mesh: PeerRow::of_mesh(scene, setting, "ok", time, &soup),
                        passes: exported.passes,
                    }
                }
                Err(e) => ExportRow {
                    tolerance: t,
                    mesh: PeerRow::failed(setting, time, &e.to_string()),
                    passes: 0,
                },
            };
            eprintln!(
                "qcsg export {} T = {}: {} in {:.2} s, {} triangles",
                scene.name,
                row.mesh.setting,
                row.mesh.outcome,
                secs(time),
                row.mesh.triangles
            );
            rows.push(row);
        }
        all.push(rows);
    }
    Ok(all)
}

/// One peer's meshes of one scene, with the time the table compares (for build123d the exact
/// boolean and the tessellation together); `None` where the peer did not run.
fn peer_meshes(peers: &Peers, k: usize) -> [(&'static str, Option<Vec<PeerRow>>); 3] {
    let copy = |p: &PeerRow, extra: Duration| PeerRow {
        setting: p.setting.clone(),
        outcome: p.outcome.clone(),
        time: p.time + extra,
        triangles: p.triangles,
        surface_to_mesh: p.surface_to_mesh,
        mesh_to_surface: p.mesh_to_surface,
    };
    let openscad = peers
        .openscad
        .and_then(|_| peers.openscad_rows.get(k))
        .map(|list| list.iter().map(|p| copy(p, Duration::ZERO)).collect());
    let python = |runs: Option<&[crate::peers::PythonScene]>| {
        runs.and_then(|r| r.get(k)).map(|run| {
            let exact = run.exact.map_or(Duration::ZERO, |e| e.0);
            run.rows.iter().map(|p| copy(p, exact)).collect()
        })
    };
    [
        ("OpenSCAD", openscad),
        ("Manifold", python(peers.manifold_runs)),
        ("build123d", python(peers.build123d_runs)),
    ]
}

/// The quickest mesh of `list` whose Hausdorff distance is at most `error`.
fn quickest_within(list: &[PeerRow], error: f64) -> Option<&PeerRow> {
    list.iter()
        .filter(|p| p.measured() && p.hausdorff() <= error)
        .min_by(|a, b| a.time.cmp(&b.time))
}

/// Writes the section, its table and figures; returns the figures' file names.
pub fn write(
    md: &mut String,
    out_dir: &Path,
    scenes: &[Scene],
    exports: &[Vec<ExportRow>],
    peers: &Peers,
    provenance: &str,
) -> Result<Vec<String>, String> {
    let mut plots = Vec::new();
    let _ = writeln!(md, "{HEADING}\n");
    let _ = writeln!(
        md,
        "{provenance}`qcsg export` (`crates/qcsg-export`, method in [export.md](export.md)) meshes \
         each scene at a sweep of tolerances T (relative to the diagonal), timed on **one \
         thread** from the DNF to the checked mesh: every literal meshed, Manifold's booleans, \
         and the export's own check of the two-way deviation (with more passes at half the \
         tolerance where it fails). Each mesh is then measured like the peers' meshes of \
         section 2, by the same independent oracle, both ways. Beside each qcsg mesh stands the \
         quickest mesh of each peer whose Hausdorff distance is at most qcsg's (from section \
         2's sweeps, same run): its time, its triangles, and its time over qcsg's. \"none of its \
         sweep\" marks a peer none of whose meshes was that accurate; \"not measured\" a peer \
         that did not run. Manifold's time is its booleans on the primitives' meshes in Python; \
         build123d's is its exact boolean plus tessellation; OpenSCAD's the whole process.\n"
    );
    let peer_names = ["OpenSCAD", "Manifold", "build123d"];
    for (k, (scene, rows)) in scenes.iter().zip(exports).enumerate() {
        let meshes = peer_meshes(peers, k);
        let _ = writeln!(md, "### {}\n", scene.name);
        let _ = writeln!(
            md,
            "| T / diag | outcome | export ms | passes | triangles | surface → mesh / diag | mesh → surface / diag | Hausdorff / diag | {} |",
            peer_names
                .iter()
                .map(|p| format!("{p} at ≤ that error: ms (triangles, time ratio)"))
                .collect::<Vec<_>>()
                .join(" | ")
        );
        let _ = writeln!(
            md,
            "|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
        );
        for row in rows {
            let p = &row.mesh;
            let (s2m, m2s, h) = if p.measured() {
                (
                    sci(p.surface_to_mesh / scene.diag),
                    sci(p.mesh_to_surface / scene.diag),
                    sci(p.hausdorff() / scene.diag),
                )
            } else {
                ("–".into(), "–".into(), "–".into())
            };
            let cells: Vec<String> = meshes
                .iter()
                .map(|(_, list)| match list {
                    None => "not measured".to_owned(),
                    Some(_) if !p.measured() => "–".to_owned(),
                    Some(list) => match quickest_within(list, p.hausdorff()) {
                        None => "none of its sweep".to_owned(),
                        Some(q) => format!(
                            "{} ({}, {:.2}×)",
                            ms(q.time),
                            q.triangles,
                            secs(q.time) / secs(p.time).max(1e-9)
                        ),
                    },
                })
                .collect();
            let _ = writeln!(
                md,
                "| {} | {} | {} | {} | {} | {s2m} | {m2s} | {h} | {} |",
                sci(row.tolerance),
                p.outcome,
                ms(p.time),
                row.passes,
                p.triangles,
                cells.join(" | ")
            );
        }
        let _ = writeln!(md);
        let series = |value: &dyn Fn(&PeerRow) -> f64| {
            let mut series = vec![Series {
                name: "qcsg export".into(),
                points: rows
                    .iter()
                    .map(|r| &r.mesh)
                    .filter(|p| p.measured())
                    .map(|p| (value(p), p.hausdorff() / scene.diag))
                    .collect(),
            }];
            for (name, list) in &meshes {
                if let Some(list) = list {
                    series.push(Series {
                        name: (*name).to_owned(),
                        points: list
                            .iter()
                            .filter(|p| p.measured())
                            .map(|p| (value(p), p.hausdorff() / scene.diag))
                            .collect(),
                    });
                }
            }
            series
        };
        for (what, x_label, value) in [
            (
                "time",
                "time (s)",
                &(|p: &PeerRow| secs(p.time)) as &dyn Fn(&PeerRow) -> f64,
            ),
            ("triangles", "triangles", &|p: &PeerRow| p.triangles as f64),
        ] {
            let plot = Plot {
                title: format!("{}: mesh error against {what}", scene.name),
                x_label: x_label.into(),
                y_label: "Hausdorff distance / diagonal".into(),
                series: series(value),
            };
            let file = format!("mesh_{what}_{}.svg", scene.name);
            if plot.write_svg(&out_dir.join(&file))? {
                let _ = writeln!(md, "![{}](report/{file})\n", plot.title);
                plots.push(file);
            }
        }
    }
    Ok(plots)
}

/// Replaces the section in `report` (from [`HEADING`] to the next `## ` heading, or the end) by
/// `section`, or appends it where the report has none.
pub fn splice(report: &str, section: &str) -> String {
    splice_section(report, HEADING, section)
}

/// Replaces the section that starts at `heading` (up to the next `## ` heading, or the end) by
/// `section`, or appends it where the report has none.
pub fn splice_section(report: &str, heading: &str, section: &str) -> String {
    let Some(start) = report.find(heading) else {
        return format!("{}\n\n{section}", report.trim_end());
    };
    let rest = &report[start + heading.len()..];
    let end = rest
        .find("\n## ")
        .map_or(report.len(), |i| start + heading.len() + i + 1);
    format!("{}{section}{}", &report[..start], &report[end..])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splice_replaces_only_its_section() {
        let report =
            format!("# R\n\n## 8. Before\n\nold 8\n\n{HEADING}\n\nold 9\n\n## 10. After\n");
        let spliced = splice(&report, &format!("{HEADING}\n\nnew 9\n\n"));
        assert_eq!(
            spliced,
            format!("# R\n\n## 8. Before\n\nold 8\n\n{HEADING}\n\nnew 9\n\n## 10. After\n")
        );
        let at_end = splice("# R\n\n## 8. Before\n", &format!("{HEADING}\n\nnew\n"));
        assert_eq!(at_end, format!("# R\n\n## 8. Before\n\n{HEADING}\n\nnew\n"));
        let last = splice(&at_end, &format!("{HEADING}\n\nnewer\n"));
        assert_eq!(last, format!("# R\n\n## 8. Before\n\n{HEADING}\n\nnewer\n"));
    }
}
