//! Throughput beside paper 000's Tables 1 and 2: samples per second of one-thread sampling on a
//! single quadric and on the benchmark scenes, and the paper's rows beside this run's.

use std::fmt::Write as _;
use std::time::Duration;

use qcsg_bench::pipeline::compile_source;
use qcsg_bench::reference::diagonal;
use qcsg_csg::DnfOptions;

use crate::{Config, Row, Scene, ms, one_thread, secs, timed_sample};

/// Paper 000, Table 2: quadrics, splat size, samples, distance queries, clip indices, sampling
/// ms (one 4.8 GHz core), render ms (RTX 2080 Ti, 1920×1080).
const PAPER_TABLE_2: [(u32, &str, u64, u64, u64, f64, f64); 18] = [
    (3, "large", 5454, 22372, 2, 1.51, 0.34),
    (3, "medium", 23452, 47336, 2, 3.39, 0.23),
    (3, "small", 249014, 100398, 2, 8.51, 0.27),
    (5, "large", 8112, 103296, 52, 7.63, 0.27),
    (5, "medium", 35904, 215040, 23, 16.45, 0.18),
    (5, "small", 329856, 576048, 17, 66.87, 0.26),
    (5, "large", 9465, 52578, 52, 4.38, 0.31),
    (5, "medium", 27882, 103908, 31, 8.71, 0.28),
    (5, "small", 205075, 254592, 25, 23.47, 0.26),
    (21, "large", 7134, 30802, 78, 6.26, 0.45),
    (21, "medium", 31940, 85744, 37, 18.01, 0.39),
    (21, "small", 104972, 171958, 31, 37.91, 0.33),
    (31, "large", 28432, 196298, 51, 36.63, 0.96),
    (31, "medium", 91895, 325705, 34, 62.23, 0.87),
    (31, "small", 184533, 415847, 29, 83.36, 0.69),
    (80, "large", 10176, 194024, 299, 94.47, 0.32),
    (80, "medium", 141200, 558582, 244, 292.35, 0.34),
    (80, "small", 655727, 1182464, 236, 623.92, 0.47),
];

pub fn throughput(
    md: &mut String,
    scenes: &[Scene],
    rows: &[Vec<Row>],
    cfg: &Config,
) -> Result<(), String> {
    let _ = writeln!(md, "## 5. Throughput beside paper 000\n");
    // Table 1: a single quadric, and the scenes.
    let ball = compile_source("ball.scad", "sphere(1);".into(), &DnfOptions::default());
    let ball = ball.dnf.ok_or("the single ball did not compile")?;
    let diag = diagonal(&ball);
    let mut single = Vec::new();
    // The ball alone needs more samples than a scene at the same relative radius; its sweep
    // ends where the sampler's own sample limit would stop it.
    let mut ball_radii = Vec::new();
    for &rel in &cfg.radii {
        let Ok((s, t)) = one_thread(|| timed_sample(&ball, rel * diag))? else {
            break;
        };
        ball_radii.push(rel);
        single.push((
            rel,
            s.samples.len(),
            s.stats.subdivision.distance_queries,
            t,
        ));
    }
    let _ = writeln!(
        md,
        "Paper 000 Table 1 (one 4.8 GHz core) beside this run (one thread of this machine). \
         Throughput is samples per second of sampling time.\n"
    );
    let _ = writeln!(md, "| case | paper 000 | qcsg (this run) |");
    let _ = writeln!(md, "|---|---:|---|");
    let rate = |n: usize, t: Duration| n as f64 / secs(t).max(1e-9);
    let span = |v: &[f64]| {
        let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = v.iter().copied().fold(0.0, f64::max);
        format!("{:.2}–{:.2} M/s", lo / 1e6, hi / 1e6)
    };
    let single_rates: Vec<f64> = single.iter().map(|&(_, n, _, t)| rate(n, t)).collect();
    let _ = writeln!(
        md,
        "| single quadric, with subdivision (a ball) | 40–70 M/s (14–25 ns/sample) | {} over r/diag {:?} |",
        span(&single_rates),
        ball_radii
    );
    let simple: Vec<f64> = rows
        .first()
        .map(|r| {
            r.iter()
                .map(|r| rate(r.m.sampling.samples.len(), r.m.time))
                .collect()
        })
        .unwrap_or_default();
    let _ = writeln!(
        md,
        "| simple CSG surface (paper Fig. 9; here three_spheres) | 10–50 M/s (20–100 ns/sample) | {} |",
        span(&simple)
    );
    let complex: Vec<f64> = rows
        .iter()
        .skip(1)
        .flat_map(|r| r.iter().map(|r| rate(r.m.sampling.samples.len(), r.m.time)))
        .collect();
    let _ = writeln!(
        md,
        "| complex CSG surface (paper Fig. 1; here the other scenes) | 0.5–2 M/s (500–2000 ns/sample) | {} |\n",
        span(&complex)
    );

    let _ = writeln!(
        md,
        "Paper 000 Table 2 (sampling on one 4.8 GHz core; rendering on an RTX 2080 Ti at \
         1920×1080) beside this run's scenes at the largest, a middle and the smallest radius of \
         the sweep. The paper does not give its splat sizes numerically, so rows are matched by \
         size class only; our \"render\" column is the CPU splat model at the largest resolution \
         of the sweep, not a GPU time.\n"
    );
    let _ = writeln!(
        md,
        "| source | quadrics | splat size | samples | dist. queries | clip indices | sampling ms | ns/sample | render ms |"
    );
    let _ = writeln!(md, "|---|---:|---|---:|---:|---:|---:|---:|---:|");
    for p in PAPER_TABLE_2 {
        let _ = writeln!(
            md,
            "| paper 000 | {} | {} | {} | {} | {} | {:.2} | {:.1} | {:.2} (GPU) |",
            p.0,
            p.1,
            p.2,
            p.3,
            p.4,
            p.5,
            p.5 * 1e6 / p.2 as f64,
            p.6
        );
    }
    for (scene, scene_rows) in scenes.iter().zip(rows) {
        let last = scene_rows.len().saturating_sub(1);
        let picks = [0, last / 2, last];
        for (k, &i) in picks.iter().enumerate() {
            let Some(row) = scene_rows.get(i) else {
                continue;
            };
            let st = &row.m.sampling.stats;
            let n = row.m.sampling.samples.len();
            let _ = writeln!(
                md,
                "| {} | {} | {} (r = {} diag) | {} | {} | {} | {} | {:.1} | {} (CPU) |",
                scene.name,
                scene.dnf.quadrics.len(),
                ["large", "medium", "small"][k],
                cfg.radii[i],
                n,
                st.subdivision.distance_queries,
                st.clip_indices,
                ms(row.m.time),
                secs(row.m.time) * 1e9 / n.max(1) as f64,
                row.images
                    .last()
                    .map_or_else(String::new, |img| ms(img.splat)),
            );
        }
    }
    let _ = writeln!(md);
    Ok(())
}
