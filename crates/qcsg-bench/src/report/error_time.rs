//! Section 1 of the report, error against run time: each benchmark scene sampled over the sweep
//! of radii (one thread), its coverage and on-surface errors against the exact reference points,
//! and the CPU splat model's images beside the ray tracer's, with a plot of each against time.

use std::fmt::Write as _;
use std::path::Path;
use std::time::{Duration, Instant};

use qcsg_bench::image::{Agreement, camera_for, ray_traced, splat};
use qcsg_bench::measure::measure;
use qcsg_bench::plot::{Plot, Series};
use qcsg_render::ImageSize;
use qcsg_sample::SampleError;

use crate::peer_meshes::Peers;
use crate::{Config, ImageRow, Row, Scene, ms, one_thread, sci, secs};

/// The sweep of every scene.
pub struct Sweep {
    /// Per scene, one row per radius reached.
    pub rows: Vec<Vec<Row>>,
    /// Per scene, the radius the sweep stopped before and the samples it would have made.
    pub stops: Vec<Option<(f64, f64)>>,
    /// The most samples a sampling was allowed to be expected to make (`--max-samples`).
    pub max_samples: usize,
    /// The most samples of a sampling whose images were drawn (`--max-image-samples`).
    pub max_image_samples: usize,
}

/// Samples every scene at every radius of `cfg` until a sampling would be expected to make
/// more than `max_samples` samples; draws the images of samplings of at most
/// `max_image_samples` samples.
pub fn measure_all(
    scenes: &[Scene],
    cfg: &Config,
    max_samples: usize,
    max_image_samples: usize,
) -> Result<Sweep, String> {
    let mut rows: Vec<Vec<Row>> = Vec::new();
    // Per scene, the radius the sweep stopped before and the samples it would have made.
    let mut stops: Vec<Option<(f64, f64)>> = Vec::new();
    for scene in scenes {
        let mut frames = Vec::new();
        for &(w, h) in &cfg.sizes {
            let size = ImageSize::new(w, h).map_err(|e| e.to_string())?;
            let camera = camera_for(&scene.dnf, size).ok_or("no camera")?;
            let (frame, time) = ray_traced(&scene.dnf, &camera, size);
            frames.push((size, camera, frame, time));
        }
        let mut scene_rows: Vec<Row> = Vec::new();
        let mut stop = None;
        for &rel in &cfg.radii {
            if let (Some(last), Some(&last_rel)) = (
                scene_rows.last(),
                cfg.radii.get(scene_rows.len().wrapping_sub(1)),
            ) {
                let expected = last.m.sampling.samples.len() as f64 * (last_rel / rel).powi(2);
                if expected > max_samples as f64 {
                    stop = Some((rel, expected));
                    break;
                }
            }
            let m = one_thread(|| measure(&scene.dnf, rel * scene.diag, &scene.refs))?
                .map_err(|e: SampleError| e.to_string())?;
            let mut images = Vec::new();
            let draw = m.sampling.samples.len() <= max_image_samples;
            for (size, camera, frame, rt) in frames.iter().filter(|_| draw) {
                let start = Instant::now();
                let drawn = splat(&scene.dnf, &m.sampling.samples, camera, *size);
                let time = start.elapsed();
                images.push(ImageRow {
                    size: (size.width(), size.height()),
                    ray_trace: *rt,
                    splat: time,
                    agreement: Agreement::compare(frame, &drawn.pixels, 1e-6 * scene.diag),
                });
            }
            eprintln!(
                "{} r = {rel}: {} samples in {:.3} s",
                scene.name,
                m.sampling.samples.len(),
                secs(m.time)
            );
            scene_rows.push(Row { m, images });
        }
        rows.push(scene_rows);
        stops.push(stop);
    }
    Ok(Sweep {
        rows,
        stops,
        max_samples,
        max_image_samples,
    })
}

/// Writes section 1 and its plots into `out_dir`; returns the plots' file names.
pub fn write(
    md: &mut String,
    out_dir: &Path,
    cfg: &Config,
    scenes: &[Scene],
    sweep: &Sweep,
    peers: &Peers,
) -> Result<Vec<String>, String> {
    let (max_samples, max_image_samples) = (sweep.max_samples, sweep.max_image_samples);
    let mut plots = Vec::new();
    let _ = writeln!(md, "\n## 1. Error against run time\n");
    let _ = writeln!(
        md,
        "For each scene, over a sweep of sample radii `r` (relative to the scene's diagonal): \
         the sampling time and\n\n\
         - **coverage error**: the largest distance from a reference point (surface or feature \
         curve) to its nearest sample *on the same quadric* (or on another quadric through the \
         point: coincident faces are sampled once); the guarantee is coverage ≤ r;\n\
         - **on-surface error**: the largest first-order distance `|Q(p)| / ‖∇Q(p)‖` of a sample \
         to its quadric, relative to the diagonal;\n\
         - **image disagreement**: pixels where an image drawn from the samples differs from the \
         exact ray tracer's (a hole, a pixel drawn outside the solid, or a different quadric in \
         front), over the pixels that see the solid.\n\n\
         The image from samples is the CPU model of splat rendering in \
         `crates/qcsg-bench/src/image.rs` (each sample a disc of its radius, the pixel's ray \
         intersected exactly with the sample's quadric, kept within the radius and where the solid \
         changes across it). It measures what the samples alone show, independently of the GPU. \
         The wgpu splat renderer (`crates/qcsg-splat`) is measured where it lives: its agreement \
         with the ray tracer on every example and stiff scene is a test \
         (`cargo test -p qcsg-splat --test agreement`), and its 1920×1080 times against the ray \
         tracer on this machine's software adapter are in [render.md](render.md). The splat \
         model's time is a CPU time, not comparable to the paper's GPU times. Samplings of more \
         than {} samples are not drawn (\"not drawn\"; `--max-image-samples`): the CPU model's \
         cost grows with the samples and the report must stay within its time.\n",
        max_image_samples
    );
    for (scene, scene_rows) in scenes.iter().zip(&sweep.rows) {
        let _ = writeln!(md, "### {}\n", scene.name);
        let mut head = String::from(
            "| r / diag | samples | sampling ms | coverage / r | coverage / diag | on-surface / diag | unresolved |",
        );
        let mut rule = String::from("|---:|---:|---:|---:|---:|---:|---:|");
        for &(w, h) in &cfg.sizes {
            let _ = write!(head, " {w}×{h} splat ms | {w}×{h} disagreement |");
            rule.push_str("---:|---:|");
        }
        let _ = writeln!(md, "{head}\n{rule}");
        for (rel, row) in cfg.radii.iter().zip(scene_rows) {
            let m = &row.m;
            let cov = m.coverage.max_distance.max(m.edge_coverage.max_distance);
            let _ = write!(
                md,
                "| {rel} | {} | {} | {:.3} | {} | {} | {} |",
                m.sampling.samples.len(),
                ms(m.time),
                cov / m.radius,
                sci(cov / scene.diag),
                sci(m.on_surface),
                m.sampling.stats.unresolved()
            );
            for img in &row.images {
                let _ = write!(
                    md,
                    " {} | {:.4} |",
                    ms(img.splat),
                    img.agreement.disagreement()
                );
            }
            for _ in row.images.len()..cfg.sizes.len() {
                md.push_str(" not drawn | – |");
            }
            let _ = writeln!(md);
        }
        let rt: Vec<String> = scene_rows
            .first()
            .map(|r| {
                r.images
                    .iter()
                    .map(|i| format!("{}×{} in {} ms", i.size.0, i.size.1, ms(i.ray_trace)))
                    .collect()
            })
            .unwrap_or_default();
        let _ = writeln!(md, "\nReference ray tracer: {}.\n", rt.join(", "));
        if let Some(Some((rel, expected))) = sweep.stops.get(
            scenes
                .iter()
                .position(|s| s.name == scene.name)
                .unwrap_or(0),
        ) {
            let _ = writeln!(
                md,
                "The sweep stops here: r = {rel} diag would make about {:.1} M samples (extrapolated \
                 as r⁻² from the last row), over the limit of {:.1} M (`--max-samples`; the \
                 sampling, its k-d tree and the measurements must fit this shared machine's memory \
                 and the report's time).\n",
                expected / 1e6,
                max_samples as f64 / 1e6
            );
        }

        let mut error_plot = Plot {
            title: format!("{}: error against time", scene.name),
            x_label: "time (s)".into(),
            y_label: "error / diagonal".into(),
            series: vec![
                Series {
                    name: "qcsg coverage error (sampling time)".into(),
                    points: scene_rows
                        .iter()
                        .map(|r| {
                            let cov =
                                r.m.coverage
                                    .max_distance
                                    .max(r.m.edge_coverage.max_distance);
                            (secs(r.m.time), cov / scene.diag)
                        })
                        .collect(),
                },
                Series {
                    name: "qcsg radius r (the guaranteed bound)".into(),
                    points: scene_rows
                        .iter()
                        .map(|r| (secs(r.m.time), r.m.radius / scene.diag))
                        .collect(),
                },
            ],
        };
        if let Some(list) = peers.openscad_rows.get(
            scenes
                .iter()
                .position(|s| s.name == scene.name)
                .unwrap_or(0),
        ) {
            error_plot.series.push(Series {
                name: "OpenSCAD Hausdorff distance (export time)".into(),
                points: list
                    .iter()
                    .filter(|p| p.measured())
                    .map(|p| (secs(p.time), p.hausdorff() / scene.diag))
                    .collect(),
            });
        }
        let k = scenes
            .iter()
            .position(|s| s.name == scene.name)
            .unwrap_or(0);
        for (name, runs) in [
            ("Manifold", peers.manifold_runs),
            ("build123d (boolean + tessellation)", peers.build123d_runs),
        ] {
            if let Some(run) = runs.and_then(|r| r.get(k)) {
                let exact = run.exact.map_or(Duration::ZERO, |e| e.0);
                error_plot.series.push(Series {
                    name: format!("{name} Hausdorff distance"),
                    points: run
                        .rows
                        .iter()
                        .filter(|p| p.measured())
                        .map(|p| (secs(exact + p.time), p.hausdorff() / scene.diag))
                        .collect(),
                });
            }
        }
        let file = format!("error_{}.svg", scene.name);
        if error_plot.write_svg(&out_dir.join(&file))? {
            let _ = writeln!(md, "![{}](report/{file})\n", error_plot.title);
            plots.push(file);
        }
        let mut image_plot = Plot {
            title: format!("{}: image disagreement against time", scene.name),
            x_label: "sampling + splat time (s)".into(),
            y_label: "disagreeing pixels / solid pixels".into(),
            series: Vec::new(),
        };
        for (k, &(w, h)) in cfg.sizes.iter().enumerate() {
            image_plot.series.push(Series {
                name: format!("{w}×{h}"),
                points: scene_rows
                    .iter()
                    .filter_map(|r| {
                        let i = r.images.get(k)?;
                        Some((secs(r.m.time + i.splat), i.agreement.disagreement()))
                    })
                    .collect(),
            });
        }
        let file = format!("image_{}.svg", scene.name);
        let drawn = image_plot.write_svg(&out_dir.join(&file))?;
        if !drawn {
            let _ = writeln!(
                md,
                "The image from samples matched the ray tracer's in every pixel at every radius \
                 and resolution drawn (no disagreement plot: a zero has no place on a log axis).\n"
            );
        }
        if drawn {
            let _ = writeln!(
                md,
                "![{}](report/{file})\n\n(Zero disagreement cannot be drawn on a log axis; the \
                 table has every value.)\n",
                image_plot.title
            );
            plots.push(file);
        }
    }
    Ok(plots)
}
