//! The summary at the top of the report, computed from this run's measurements only: the
//! guarantees, where qcsg wins and loses against each peer and by how much, and where its time
//! goes where it is behind.

use std::fmt::Write as _;
use std::time::Duration;

use crate::families::{Family, SizeRow};
use crate::peers::{PeerRow, PythonScene, ratios};
use crate::to_image::SceneImage;
use crate::{Row, Scene, ms, sci, secs};

/// Everything the summary reads.
pub struct Inputs<'a> {
    pub scenes: &'a [Scene],
    pub rows: &'a [Vec<Row>],
    pub radii: &'a [f64],
    pub stops: &'a [Option<(f64, f64)>],
    pub max_samples: usize,
    pub openscad: &'a [Vec<PeerRow>],
    pub manifold: Option<&'a [PythonScene]>,
    pub build123d: Option<&'a [PythonScene]>,
    pub images: &'a [SceneImage],
    pub families: &'a [Family],
    pub family_results: &'a [Vec<SizeRow>],
    pub stable: (usize, usize, usize),
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    if v.is_empty() {
        f64::NAN
    } else {
        v[v.len() / 2]
    }
}

fn times(x: f64) -> String {
    if x >= 10.0 {
        format!("{x:.0}×")
    } else {
        format!("{x:.2}×")
    }
}

/// A peer's meshes against qcsg's samplings of equal error: one sentence.
fn against(name: &str, inputs: &Inputs, lists: &[&[PeerRow]]) -> String {
    let mut all = Vec::new();
    let mut finer = 0;
    let mut meshes = 0;
    for (k, list) in lists.iter().enumerate() {
        let r = ratios(&inputs.rows[k], inputs.radii, list);
        meshes += list.iter().filter(|p| p.measured()).count();
        finer += list.iter().filter(|p| p.measured()).count() - r.len();
        all.extend(r);
    }
    if all.is_empty() {
        return format!("- {name}: no mesh has a qcsg sampling of equal error in this run.");
    }
    let lo = all.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = all.iter().copied().fold(0.0, f64::max);
    let slower = all.iter().filter(|&&r| r > 1.0).count();
    let n = all.len();
    format!(
        "- {name} against qcsg's one-thread sampling of equal or smaller error: the peer took \
         {}–{} qcsg's time (median {}); qcsg was quicker for {slower} of {n} meshes, slower for \
         {}. {finer} of the {meshes} meshes were finer than qcsg's finest sampling (no row to \
         compare).",
        times(lo),
        times(hi),
        times(median(&mut all)),
        n - slower
    )
}

/// The summary's text.
pub fn write(inputs: &Inputs) -> String {
    let mut text = String::from("## Summary\n\n");
    let all = || inputs.rows.iter().flatten();
    let worst_cover = all()
        .map(|r| r.m.coverage_over_radius())
        .fold(0.0, f64::max);
    let worst_on = all().map(|r| r.m.on_surface).fold(0.0, f64::max);
    let beyond: usize = all()
        .map(|r| r.m.coverage.beyond_reach + r.m.edge_coverage.beyond_reach)
        .sum();
    let wrong: usize = all()
        .flat_map(|r| r.images.iter())
        .map(|i| i.agreement.holes + i.agreement.spill + i.agreement.wrong_quadric)
        .sum();
    let images = all().map(|r| r.images.len()).sum::<usize>();
    let unresolved = all()
        .filter(|r| r.m.sampling.stats.unresolved() > 0)
        .count();
    let measurements = all().count();
    let _ = writeln!(
        text,
        "- Guarantees: over {measurements} samplings of {} scenes, the farthest reference point \
         from a sample of its quadric was {worst_cover:.3} r ({beyond} points beyond r); the \
         largest on-surface error {} of the diagonal; {unresolved} samplings left a rectangle \
         unresolved; images from the samples (CPU splat model) against the ray tracer: {wrong} \
         differing pixels over {images} images.",
        inputs.scenes.len(),
        sci(worst_on)
    );
    // How far the sweep went.
    let reach: Vec<String> = inputs
        .scenes
        .iter()
        .zip(inputs.rows)
        .zip(inputs.stops)
        .map(|((s, rows), stop)| {
            let finest = rows
                .len()
                .checked_sub(1)
                .map_or(f64::NAN, |i| inputs.radii[i]);
            match stop {
                Some((rel, expected)) => format!(
                    "{} to r = {finest} diag ({:.1} M samples; r = {rel} would need about {:.0} M, \
                     over the limit of {:.0} M, `--max-samples`)",
                    s.name,
                    rows.last().map_or(0, |r| r.m.sampling.samples.len()) as f64 / 1e6,
                    expected / 1e6,
                    inputs.max_samples as f64 / 1e6
                ),
                None => format!("{} to r = {finest} diag", s.name),
            }
        })
        .collect();
    let _ = writeln!(text, "- qcsg's sweep went {}.", reach.join("; "));
    let openscad: Vec<&[PeerRow]> = inputs.openscad.iter().map(Vec::as_slice).collect();
    if !openscad.is_empty() {
        let _ = writeln!(
            text,
            "{}",
            against("OpenSCAD's CGAL export", inputs, &openscad)
        );
    }
    if let Some(runs) = inputs.manifold {
        let lists: Vec<&[PeerRow]> = runs.iter().map(|r| r.rows.as_slice()).collect();
        let _ = writeln!(text, "{}", against("Manifold", inputs, &lists));
    } else {
        let _ = writeln!(text, "- Manifold: not measured (not installed).");
    }
    if let Some(runs) = inputs.build123d {
        let with: Vec<Vec<PeerRow>> = runs
            .iter()
            .map(|r| {
                let exact = r.exact.map_or(Duration::ZERO, |e| e.0);
                r.rows
                    .iter()
                    .map(|p| PeerRow {
                        setting: p.setting.clone(),
                        outcome: p.outcome.clone(),
                        time: p.time + exact,
                        triangles: p.triangles,
                        surface_to_mesh: p.surface_to_mesh,
                        mesh_to_surface: p.mesh_to_surface,
                    })
                    .collect()
            })
            .collect();
        let lists: Vec<&[PeerRow]> = with.iter().map(Vec::as_slice).collect();
        let invalid = runs
            .iter()
            .filter(|r| r.exact.is_some_and(|e| !e.1))
            .count();
        let _ = writeln!(
            text,
            "{} Its exact boolean was invalid in {invalid} of {} scenes.",
            against("build123d (boolean + tessellation)", inputs, &lists),
            runs.len()
        );
    } else {
        let _ = writeln!(text, "- build123d: not measured (not installed).");
    }
    // Time to an image.
    let mut ways: Vec<(String, Vec<f64>)> = Vec::new();
    for s in inputs.images {
        let Some(base) = s.ways.first().and_then(|w| w.time) else {
            continue;
        };
        for w in s.ways.iter().skip(1) {
            let Some(t) = w.time else { continue };
            let ratio = secs(t) / secs(base).max(1e-9);
            match ways.iter_mut().find(|(n, _)| *n == w.peer) {
                Some((_, v)) => v.push(ratio),
                None => ways.push((w.peer.clone(), vec![ratio])),
            }
        }
    }
    if !ways.is_empty() {
        let parts: Vec<String> = ways
            .iter()
            .map(|(n, v)| {
                let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
                let hi = v.iter().copied().fold(0.0, f64::max);
                format!("{n} {}–{}", times(lo), times(hi))
            })
            .collect();
        let _ = writeln!(
            text,
            "- Time to a 1920×1080 image accurate to a pixel, over qcsg's ray tracer (check + DNF + \
             trace) on the {} scenes (above 1× the other way is slower): {}.",
            inputs.images.len(),
            parts.join("; ")
        );
    }
    // Families at their largest size.
    for (family, rows) in inputs.families.iter().zip(inputs.family_results) {
        let Some(last) = rows.last() else { continue };
        let Some(q) = last.qcsg_image() else {
            let _ = writeln!(
                text,
                "- {} {}: qcsg failed ({}).",
                family.name,
                last.count,
                last.qcsg.as_ref().err().map_or("", String::as_str)
            );
            continue;
        };
        let mut parts = Vec::new();
        let mut behind = false;
        for (name, o) in [
            ("Manifold", &last.manifold),
            ("build123d", &last.build123d),
            ("OpenSCAD", &last.openscad),
        ] {
            match o.time() {
                Some(t) => {
                    let r = secs(t) / secs(q).max(1e-9);
                    behind |= r < 1.0;
                    parts.push(format!("{name} {} ms ({} qcsg's)", ms(t), times(r)));
                }
                None => parts.push(format!("{name} {}", o.cell())),
            }
        }
        let mut line = format!(
            "- {} with {} {}: qcsg to the image {} ms; {}.",
            family.name,
            last.count,
            family.unit,
            ms(q),
            parts.join(", ")
        );
        if behind && let Ok(t) = &last.qcsg {
            let total = secs(t[0] + t[1] + t[3]).max(1e-9);
            let _ = write!(
                line,
                " Where qcsg's time goes: check and evaluation {:.0}%, DNF {:.0}%, ray tracer \
                 {:.0}% (sampling for splats, not in this total: {} ms).",
                100.0 * secs(t[0]) / total,
                100.0 * secs(t[1]) / total,
                100.0 * secs(t[3]) / total,
                ms(t[2])
            );
        }
        let _ = writeln!(text, "{line}");
    }
    let _ = writeln!(
        text,
        "- Stability: {} cases, {} as their headers expect, {} keeping every guarantee \
         (the rest are recorded known failures, an expected error or an empty result).\n",
        inputs.stable.0, inputs.stable.1, inputs.stable.2
    );
    text
}
