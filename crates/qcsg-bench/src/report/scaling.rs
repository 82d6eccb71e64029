//! Section 6 of the report, scaling of sampling: time and peak heap memory against the number
//! of primitives (a grid of balls) and against the radius, with fitted exponents and plots.

use std::fmt::Write as _;
use std::path::Path;

use qcsg_bench::pipeline::compile_source;
use qcsg_bench::plot::{Plot, Series};
use qcsg_csg::DnfOptions;

use crate::{Config, Scene, fit_text, ms, sample_with_memory, secs};

/// `N` balls of radius 1 in a cubic grid 1.5 apart, united (neighbours overlap).
fn ball_grid(n: usize) -> String {
    let side = (n as f64).cbrt().ceil() as usize;
    let mut text = String::new();
    for i in 0..n {
        let (x, y, z) = (i % side, (i / side) % side, i / (side * side));
        let _ = writeln!(
            text,
            "translate([{}, {}, {}]) sphere(1);",
            1.5 * x as f64,
            1.5 * y as f64,
            1.5 * z as f64
        );
    }
    text
}

pub fn scaling(
    md: &mut String,
    plots: &mut Vec<String>,
    out_dir: &Path,
    cfg: &Config,
    scenes: &[Scene],
) -> Result<(), String> {
    let _ = writeln!(md, "## 6. Scaling of sampling\n");
    let _ = writeln!(
        md,
        "Time (one thread) and peak heap memory of sampling (measured by a counting global \
         allocator, above what was in use before), against the number of primitives (`N` unit \
         balls in a grid 1.5 apart, united, sample radius 0.1 in world units) and against the \
         radius (three_spheres). Exponents are least-squares fits of `y = c·x^k` on log-log \
         axes.\n"
    );
    let mut by_count = Vec::new();
    for &n in &cfg.counts {
        let compiled = compile_source("grid.scad", ball_grid(n), &DnfOptions::default());
        let dnf = compiled.dnf.ok_or("the ball grid did not compile")?;
        let (s, t, mem) = sample_with_memory(&dnf, 0.1)?;
        eprintln!(
            "scaling N = {n}: {} samples in {:.3} s",
            s.samples.len(),
            secs(t)
        );
        by_count.push((
            n,
            dnf.terms.len(),
            dnf.literal_count(),
            s.samples.len(),
            s.stats.subdivision.distance_queries,
            t,
            mem,
        ));
    }
    let _ = writeln!(
        md,
        "| balls N | terms | literals | samples | distance queries | sampling ms | peak memory MiB |"
    );
    let _ = writeln!(md, "|---:|---:|---:|---:|---:|---:|---:|");
    for r in &by_count {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} | {:.2} |",
            r.0,
            r.1,
            r.2,
            r.3,
            r.4,
            ms(r.5),
            r.6 as f64 / (1 << 20) as f64
        );
    }
    let t_n: Vec<(f64, f64)> = by_count.iter().map(|r| (r.0 as f64, secs(r.5))).collect();
    let m_n: Vec<(f64, f64)> = by_count.iter().map(|r| (r.0 as f64, r.6 as f64)).collect();
    let q_n: Vec<(f64, f64)> = by_count.iter().map(|r| (r.0 as f64, r.4 as f64)).collect();
    let s_n: Vec<(f64, f64)> = by_count.iter().map(|r| (r.0 as f64, r.3 as f64)).collect();
    let _ = writeln!(
        md,
        "\nFitted exponents against N: time {}, memory {}, distance queries {}, samples {}.\n",
        fit_text(&t_n),
        fit_text(&m_n),
        fit_text(&q_n),
        fit_text(&s_n)
    );
    let plot = Plot {
        title: "sampling against primitive count".into(),
        x_label: "balls N".into(),
        y_label: "value / value at N = 1".into(),
        series: [
            ("time", &t_n),
            ("peak memory", &m_n),
            ("distance queries", &q_n),
            ("samples", &s_n),
        ]
        .iter()
        .map(|(name, pts)| normalised(name, pts))
        .collect(),
    };
    if plot.write_svg(&out_dir.join("scaling_count.svg"))? {
        let _ = writeln!(
            md,
            "![scaling against primitive count](report/scaling_count.svg)\n"
        );
        plots.push("scaling_count.svg".into());
    }

    let scene = scenes.first().ok_or("no scenes")?;
    let mut by_radius = Vec::new();
    for &rel in &cfg.scaling_radii {
        let (s, t, mem) = sample_with_memory(&scene.dnf, rel * scene.diag)?;
        by_radius.push((
            rel,
            s.samples.len(),
            s.stats.subdivision.distance_queries,
            t,
            mem,
        ));
    }
    let _ = writeln!(
        md,
        "| r / diag ({}) | samples | distance queries | sampling ms | peak memory MiB |",
        scene.name
    );
    let _ = writeln!(md, "|---:|---:|---:|---:|---:|");
    for r in &by_radius {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {:.2} |",
            r.0,
            r.1,
            r.2,
            ms(r.3),
            r.4 as f64 / (1 << 20) as f64
        );
    }
    let t_r: Vec<(f64, f64)> = by_radius.iter().map(|r| (r.0, secs(r.3))).collect();
    let m_r: Vec<(f64, f64)> = by_radius.iter().map(|r| (r.0, r.4 as f64)).collect();
    let q_r: Vec<(f64, f64)> = by_radius.iter().map(|r| (r.0, r.2 as f64)).collect();
    let s_r: Vec<(f64, f64)> = by_radius.iter().map(|r| (r.0, r.1 as f64)).collect();
    let _ = writeln!(
        md,
        "\nFitted exponents against r: time {}, memory {}, distance queries {}, samples {} \
         (over the whole sweep: once r is small against the features, samples of a surface tend to \
         r⁻² and distance queries, which follow the feature curves, to r⁻¹).\n",
        fit_text(&t_r),
        fit_text(&m_r),
        fit_text(&q_r),
        fit_text(&s_r)
    );
    let plot = Plot {
        title: format!("{}: sampling against radius", scene.name),
        x_label: "r / diagonal".into(),
        y_label: "value / value at the largest r".into(),
        series: [
            ("time", &t_r),
            ("peak memory", &m_r),
            ("distance queries", &q_r),
            ("samples", &s_r),
        ]
        .iter()
        .map(|(name, pts)| normalised(name, pts))
        .collect(),
    };
    if plot.write_svg(&out_dir.join("scaling_radius.svg"))? {
        let _ = writeln!(md, "![scaling against radius](report/scaling_radius.svg)\n");
        plots.push("scaling_radius.svg".into());
    }
    Ok(())
}

/// A series divided by its first value.
fn normalised(name: &str, points: &[(f64, f64)]) -> Series {
    let first = points.first().map_or(1.0, |p| p.1);
    Series {
        name: format!("{name} (k = {})", fit_text(points)),
        points: points.iter().map(|&(x, y)| (x, y / first)).collect(),
    }
}
