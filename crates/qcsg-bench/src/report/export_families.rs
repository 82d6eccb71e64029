//! The report's section 9.1: the scaling families of section 4 (plates with holes, a cube minus
//! balls, unions of balls) meshed by `qcsg export` at a stated tolerance, beside Manifold's
//! booleans on the same primitives at equal two-way Hausdorff error: time and triangles per
//! size, their ratios, and growth exponents. `--export-families` regenerates it alone.

use std::fmt::Write as _;
use std::path::Path;
use std::sync::Mutex;
use std::time::{Duration, Instant};

use qcsg_bench::measure::References;
use qcsg_bench::mesh::Mesh;
use qcsg_bench::pipeline::compile_source;
use qcsg_bench::plot::{Plot, Series};
use qcsg_bench::python_peer::{self, Installed};
use qcsg_bench::reference::diagonal;
use qcsg_bench::shape::Shape;
use qcsg_csg::DnfOptions;
use qcsg_export::{ExportOptions, Progress, export};

use crate::families::Family;
use crate::peers::PeerRow;
use crate::{Scene, fit_text, ms, one_thread, sci, secs};

/// The heading that starts the section; `--export-families` replaces the report's text from it
/// to the next section.
pub const HEADING: &str = "## 9.1 Meshes of the scaling families: `qcsg export` beside Manifold";

/// The tolerance of every export, relative to the scene's diagonal: the export's check samples
/// the surface at `T/2` (a count growing as `T⁻²`), which at 3·10⁻³ took minutes on one size of
/// a few hundred balls.
pub const TOLERANCE: f64 = 1e-2;

/// Random lines for each size's exact reference points (plus the lines through each quadric).
const RAYS: usize = 2000;

/// One size of one family.
pub struct SizeRow {
    pub count: usize,
    pub diag: f64,
    /// The export: time, triangles and measured distances (or why it failed).
    pub qcsg: PeerRow,
    /// The export's time to its first mesh, before the check.
    pub first_mesh: Option<Duration>,
    pub passes: u32,
    /// Manifold's meshes of the sweep, measured the same way.
    pub manifold: Vec<PeerRow>,
}

impl SizeRow {
    /// Manifold's quickest mesh whose Hausdorff distance is at most the export's.
    pub fn manifold_match(&self) -> Option<&PeerRow> {
        if !self.qcsg.measured() {
            return None;
        }
        self.manifold
            .iter()
            .filter(|p| p.measured() && p.outcome == "ok")
            .filter(|p| p.hausdorff() <= self.qcsg.hausdorff())
            .min_by(|a, b| a.time.cmp(&b.time))
    }
}

/// The segment count whose chord stays within `error` of a circle of radius `r`, rounded up to
/// a multiple of 4 (Manifold's spheres need it).
fn segments_for(r: f64, error: f64) -> u32 {
    let half = (1.0 - (error / r).min(1.0)).acos();
    let n = (std::f64::consts::PI / half.max(1e-9)).ceil() as u32;
    n.div_ceil(4).max(1) * 4
}

/// Manifold's segment counts around the one whose chord error on the largest circle equals the
/// export's measured distance: the mesh is then coarse where the circle is, and the sweep finds
/// the cheapest count that still meets the distance.
fn manifold_settings(shape: &Shape, error: f64) -> Vec<f64> {
    let r = shape.largest_radius();
    let n = if r > 0.0 && error.is_finite() {
        segments_for(r, error)
    } else {
        16
    };
    let mut counts: Vec<u32> = [n.saturating_sub(4), n, n + 4, n + 8, n + 16, 2 * n + 8]
        .into_iter()
        .filter(|&c| c >= 4)
        .collect();
    counts.dedup();
    counts.into_iter().map(f64::from).collect()
}

/// Measures every size of every family: the export on one thread, then Manifold.
pub fn measure(
    families: &[Family],
    manifold: Option<&Installed>,
    work: &Path,
    limit: Duration,
) -> Result<Vec<Vec<SizeRow>>, String> {
    std::fs::create_dir_all(work).map_err(|e| e.to_string())?;
    let mut out = Vec::new();
    for family in families {
        let mut rows = Vec::new();
        for &count in &family.sizes {
            let shape = (family.make)(count);
            let compiled = compile_source("family.scad", shape.to_scad(), &DnfOptions::default());
            let codes = compiled.error_codes();
            let dnf = compiled
                .dnf
                .ok_or_else(|| format!("{} {count}: errors {codes:?}", family.name))?;
            let diag = diagonal(&dnf);
            let refs = References::find(&dnf, RAYS, 0);
            let scene = Scene {
                name: format!("{} {count}", family.name),
                about: String::new(),
                path: Default::default(),
                dnf,
                diag,
                refs,
            };
            let options = ExportOptions::new(TOLERANCE * diag);
            let checking: Mutex<Option<Instant>> = Mutex::new(None);
            let (result, time, started) = one_thread(|| {
                let started = Instant::now();
                let result = export(&scene.dnf, &options, &|p| {
                    if p == Progress::Checking {
                        let mut first = checking.lock().unwrap_or_else(|e| e.into_inner());
                        first.get_or_insert_with(Instant::now);
                    }
                });
                (result, started.elapsed(), started)
            })?;
            let first_mesh = checking
                .into_inner()
                .unwrap_or_else(|e| e.into_inner())
                .map(|t| t - started);
            let setting = format!("{} diag", sci(TOLERANCE));
            let (qcsg, passes) = match result {
                Ok(exported) => {
                    let soup = Mesh {
                        triangles: exported.mesh.triangle_soup(),
                    };
                    (
                        PeerRow::of_mesh(&scene, setting, "ok", time, &soup),
                        exported.passes,
                    )
                }
                Err(e) => (PeerRow::failed(setting, time, &e.to_string()), 0),
            };
            let manifold_rows = match manifold {
                Some(m) if qcsg.measured() => {
                    let settings = manifold_settings(&shape, qcsg.hausdorff());
                    let run = python_peer::run(m, &shape, &settings, &work.join("manifold"), limit);
                    let mut list: Vec<PeerRow> = run
                        .results
                        .iter()
                        .filter_map(|r| {
                            let label = format!("n = {}", r.setting?);
                            let outcome = if r.valid { "ok" } else { "invalid" };
                            Some(match &r.mesh {
                                Some(mesh) => {
                                    PeerRow::of_mesh(&scene, label, outcome, r.time, mesh)
                                }
                                None => PeerRow::failed(label, r.time, "no mesh"),
                            })
                        })
                        .collect();
                    if let Some(why) = run.failure {
                        list.push(PeerRow::failed("–".into(), run.process, &why));
                    }
                    list
                }
                _ => Vec::new(),
            };
            let row = SizeRow {
                count,
                diag,
                qcsg,
                first_mesh,
                passes,
                manifold: manifold_rows,
            };
            eprintln!(
                "{} {count}: qcsg export {} in {:.2} s ({} triangles, Hausdorff {} diag); Manifold at equal error {}",
                family.name,
                row.qcsg.outcome,
                secs(row.qcsg.time),
                row.qcsg.triangles,
                sci(row.qcsg.hausdorff() / diag),
                row.manifold_match().map_or_else(
                    || "none".to_owned(),
                    |m| format!(
                        "{} in {:.2} s ({} triangles)",
                        m.setting,
                        secs(m.time),
                        m.triangles
                    )
                ),
            );
            rows.push(row);
        }
        out.push(rows);
    }
    Ok(out)
}

/// Writes the section and its figures; returns the figures' file names.
pub fn write(
    md: &mut String,
    out_dir: &Path,
    families: &[Family],
    results: &[Vec<SizeRow>],
    manifold: Result<&Installed, &str>,
    provenance: &str,
) -> Result<Vec<String>, String> {
    let mut plots = Vec::new();
    let _ = writeln!(md, "{HEADING}\n");
    let manifold_note = match manifold {
        Ok(m) => format!("Manifold is {}", m.version),
        Err(why) => format!("Manifold was not measured ({why})"),
    };
    let _ = writeln!(
        md,
        "{provenance}Section 4's families meshed by `qcsg export` at T = {} of each solid's \
         diagonal, timed on **one thread** from the DNF to the checked mesh (the export's own \
         check of the two-way deviation included; \"first mesh\" is the time before that \
         check). Each mesh is measured against the exact surface both ways by section 2's \
         oracle, and so are Manifold's meshes of the same primitives (its booleans in Python, \
         timed in the script) at segment counts around the one whose chord error on the largest \
         circle equals qcsg's measured distance; beside qcsg stands the quickest Manifold mesh \
         whose Hausdorff distance is at most qcsg's. {manifold_note}. The target of `qcsg \
         export` is to be at least as fast as Manifold from about 100 primitives up with at \
         most 1.5× its triangles at equal error. Exponents are least-squares fits of `y = \
         c·N^k`.\n",
        sci(TOLERANCE)
    );
    for (family, rows) in families.iter().zip(results) {
        let _ = writeln!(md, "### {} (export)\n", family.name);
        let _ = writeln!(
            md,
            "| {} | outcome | export ms | first mesh ms | passes | triangles | Hausdorff / diag | Manifold at ≤ that error | Manifold ms | Manifold triangles | Manifold Hausdorff / diag | time ratio (Manifold / qcsg) | triangle ratio (qcsg / Manifold) |",
            family.unit
        );
        let _ = writeln!(
            md,
            "|---:|---|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|"
        );
        for r in rows {
            let q = &r.qcsg;
            let h = if q.measured() {
                sci(q.hausdorff() / r.diag)
            } else {
                "–".into()
            };
            let m = match r.manifold_match() {
                Some(m) => format!(
                    "{} | {} | {} | {} | {:.2} | {:.2}",
                    m.setting,
                    ms(m.time),
                    m.triangles,
                    sci(m.hausdorff() / r.diag),
                    secs(m.time) / secs(q.time).max(1e-9),
                    q.triangles as f64 / (m.triangles as f64).max(1.0)
                ),
                None if r.manifold.is_empty() => "not measured | – | – | – | – | –".into(),
                None => {
                    let tried: Vec<&str> = r.manifold.iter().map(|p| p.setting.as_str()).collect();
                    format!("none of {} | – | – | – | – | –", tried.join(", "))
                }
            };
            let _ = writeln!(
                md,
                "| {} | {} | {} | {} | {} | {} | {h} | {m} |",
                r.count,
                q.outcome.replace('|', "/"),
                ms(q.time),
                r.first_mesh.map_or_else(|| "–".into(), ms),
                r.passes,
                q.triangles,
            );
        }
        let points = |f: &dyn Fn(&SizeRow) -> Option<f64>| -> Vec<(f64, f64)> {
            rows.iter()
                .filter_map(|r| f(r).map(|y| (r.count as f64, y)))
                .collect()
        };
        let qcsg_time = points(&|r| r.qcsg.measured().then(|| secs(r.qcsg.time)));
        let qcsg_first = points(&|r| r.first_mesh.map(secs));
        let manifold_time = points(&|r| r.manifold_match().map(|m| secs(m.time)));
        let qcsg_tris = points(&|r| r.qcsg.measured().then_some(r.qcsg.triangles as f64));
        let manifold_tris = points(&|r| r.manifold_match().map(|m| m.triangles as f64));
        let from_100 = |f: &dyn Fn(&SizeRow, &PeerRow) -> bool| {
            rows.iter()
                .filter(|r| r.count >= 100)
                .filter_map(|r| r.manifold_match().map(|m| f(r, m)))
                .collect::<Vec<bool>>()
        };
        let faster = from_100(&|r, m| r.qcsg.time <= m.time);
        let fewer = from_100(&|r, m| r.qcsg.triangles as f64 <= 1.5 * m.triangles as f64);
        let met = |v: &[bool]| {
            if v.is_empty() {
                "not measured".to_owned()
            } else {
                format!("{} of {}", v.iter().filter(|&&b| b).count(), v.len())
            }
        };
        let _ = writeln!(
            md,
            "\nGrowth exponents: qcsg export time {}, qcsg first mesh {}, Manifold time {}; \
             triangles qcsg {}, Manifold {}. From 100 {} up, qcsg is at least as fast in {} \
             sizes and within 1.5× Manifold's triangles in {}.\n",
            fit_text(&qcsg_time),
            fit_text(&qcsg_first),
            fit_text(&manifold_time),
            fit_text(&qcsg_tris),
            fit_text(&manifold_tris),
            family.unit,
            met(&faster),
            met(&fewer),
        );
        let plot = Plot {
            title: format!("{}: mesh time against size at equal error", family.name),
            x_label: family.unit.into(),
            y_label: "time (s)".into(),
            series: [
                ("qcsg export", &qcsg_time),
                ("qcsg first mesh", &qcsg_first),
                ("Manifold", &manifold_time),
            ]
            .into_iter()
            .map(|(n, p)| Series {
                name: format!("{n} (k = {})", fit_text(p)),
                points: p.clone(),
            })
            .collect(),
        };
        let file = format!("export_family_{}.svg", family.name.replace(' ', "_"));
        if plot.write_svg(&out_dir.join(&file))? {
            let _ = writeln!(md, "![{}](report/{file})\n", plot.title);
            plots.push(file);
        }
    }
    Ok(plots)
}
