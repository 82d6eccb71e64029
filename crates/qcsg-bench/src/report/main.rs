//! `qcsg-bench`: regenerates `docs/report.md` and its plots in `docs/report/` — error against
//! run time for the benchmark scenes (`crates/qcsg-bench/scenes/`), the OpenSCAD comparison,
//! throughput beside paper 000's Tables 1 and 2, scaling with fitted exponents, what pruning
//! left out, and the stability suite's measured errors.
//!
//! Run it with `cargo run --release -p qcsg-bench` (add `--quick` for smaller sweeps). The
//! Python peers (Manifold, build123d) are measured when `crates/qcsg-bench/peers/setup.sh` has
//! made their environment; OpenSCAD when it is installed, its preview when Xvfb is.

mod families;
mod peers;
mod pruning;
mod stability_table;
mod summary;
mod throughput;
mod to_image;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use clap::Parser;
use peak_alloc::PeakAlloc;
use qcsg_bench::image::{Agreement, camera_for, ray_traced, splat};
use qcsg_bench::measure::{Measured, References, measure};
use qcsg_bench::mesh::parse_stl;
use qcsg_bench::openscad::{Display, Export, export_stl, find};
use qcsg_bench::pipeline::{compile_file, compile_source};
use qcsg_bench::plot::{Plot, Series, power_law};
use qcsg_bench::python_peer::{self, Peer};
use qcsg_bench::reference::diagonal;
use qcsg_csg::{Dnf, DnfOptions};
use qcsg_render::ImageSize;
use qcsg_sample::{SampleError, Sampling, sample};

use peers::PeerRow;

#[global_allocator]
static PEAK: PeakAlloc = PeakAlloc;

/// Regenerates docs/report.md and docs/report/*.svg.
#[derive(Parser, Debug)]
#[command(name = "qcsg-bench", version)]
struct Args {
    /// Smaller sweeps and fewer reference points (about a minute; for checking the report
    /// still builds, not for publishing).
    #[arg(long)]
    quick: bool,
    /// The repository root (default: the checkout this crate was built from).
    #[arg(long)]
    root: Option<PathBuf>,
    /// Leave out the OpenSCAD comparison even when `openscad` is installed.
    #[arg(long)]
    no_openscad: bool,
    /// Leave out the Python peers (Manifold, build123d) even when installed.
    #[arg(long)]
    no_python_peers: bool,
    /// The most samples one sampling of the sweep may be expected to make: the sweep stops at
    /// the first radius whose count, extrapolated from the one before (r⁻²), is larger.
    #[arg(long, default_value_t = 12_000_000)]
    max_samples: usize,
    /// The most samples a sampling of the sweep may have for its images to be drawn by the
    /// CPU splat model (its cost grows with the samples).
    #[arg(long, default_value_t = 2_000_000)]
    max_image_samples: usize,
    /// Seconds each peer process (OpenSCAD, Python) may run.
    #[arg(long, default_value_t = 60)]
    peer_limit: u64,
}

/// The sweeps of one run.
struct Config {
    /// Sample radii relative to the scene's diagonal, largest first.
    radii: Vec<f64>,
    /// Render resolutions.
    sizes: Vec<(u32, u32)>,
    /// Random lines for surface reference points, and for feature-curve points.
    rays: (usize, usize),
    /// `$fn` values for OpenSCAD.
    fns: Vec<u32>,
    /// Primitive counts for the scaling sweep.
    counts: Vec<usize>,
    /// Radii (relative) for the scaling sweep against radius.
    scaling_radii: Vec<f64>,
}

impl Config {
    fn new(quick: bool) -> Self {
        if quick {
            Self {
                radii: vec![0.1, 0.04, 0.016, 0.004],
                sizes: vec![(160, 120)],
                rays: (600, 150),
                fns: vec![8, 16],
                counts: vec![1, 4, 16],
                scaling_radii: vec![0.1, 0.05, 0.025],
            }
        } else {
            Self {
                radii: vec![
                    0.1, 0.05, 0.025, 0.0125, 0.00625, 0.0025, 0.001, 5e-4, 2.5e-4, 1e-4,
                ],
                sizes: vec![(160, 120), (320, 240), (640, 480)],
                rays: (3000, 600),
                fns: vec![8, 16, 32, 64],
                counts: vec![1, 2, 4, 8, 16, 32, 64],
                scaling_radii: vec![0.2, 0.1, 0.05, 0.025, 0.0125, 0.00625, 0.003125],
            }
        }
    }
}

/// The benchmark scenes: file name and what it shows.
const SCENES: [(&str, &str); 4] = [
    (
        "three_spheres.scad",
        "(A ∩ B) ∪ C of three balls (3 quadrics)",
    ),
    (
        "steinmetz.scad",
        "a ball ∩ three cylinders, minus a ball (5 quadrics)",
    ),
    (
        "drilled_block.scad",
        "a block with holes, a counterbore and a chamfer",
    ),
    (
        "wheel.scad",
        "a wheel with bolt holes from a loop and spokes",
    ),
];

fn main() {
    let args = Args::parse();
    if let Err(err) = run(&args) {
        eprintln!("qcsg-bench: {err}");
        std::process::exit(1);
    }
}

/// Runs `f` on a one-thread rayon pool (paper 000 measures on one core).
fn one_thread<T: Send>(f: impl FnOnce() -> T + Send) -> Result<T, String> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .map_err(|e| e.to_string())?;
    Ok(pool.install(f))
}

/// A compiled benchmark scene.
struct Scene {
    name: String,
    about: String,
    path: PathBuf,
    dnf: Dnf,
    diag: f64,
    refs: References,
}

/// One radius of one scene: the sampling, its errors, and the images at every resolution.
struct Row {
    m: Measured,
    images: Vec<ImageRow>,
}

struct ImageRow {
    size: (u32, u32),
    ray_trace: Duration,
    splat: Duration,
    agreement: Agreement,
}

/// The processor, its logical cores and the memory, from `/proc` (Linux).
fn machine() -> String {
    let cpu = std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
    let model = cpu
        .lines()
        .find(|l| l.starts_with("model name"))
        .and_then(|l| l.split(':').nth(1))
        .map_or_else(
            || "an unknown processor".to_owned(),
            |m| m.trim().to_owned(),
        );
    let cores = std::thread::available_parallelism().map_or(0, usize::from);
    let mem = std::fs::read_to_string("/proc/meminfo").unwrap_or_default();
    let gib = mem
        .lines()
        .find(|l| l.starts_with("MemTotal"))
        .and_then(|l| l.split_whitespace().nth(1))
        .and_then(|k| k.parse::<f64>().ok())
        .map_or_else(String::new, |k| {
            format!(", {:.0} GiB", k / (1 << 20) as f64)
        });
    format!("{model} ({cores} logical cores available{gib})")
}

/// The 1-, 5- and 15-minute load averages (`/proc/loadavg`).
fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg").map_or_else(
        |_| "unknown".to_owned(),
        |l| l.split_whitespace().take(3).collect::<Vec<_>>().join(" / "),
    )
}

/// How to install the Python peers, for the report.
const SETUP: &str = "Install them with `sh crates/qcsg-bench/peers/setup.sh` (a virtual \
    environment under `target/qcsg-bench-peers/`, versions pinned in \
    `crates/qcsg-bench/peers/requirements.txt`) and run the report again.";

fn why_missing(err: &Option<&String>) -> String {
    err.map_or_else(
        || "the peer did not run".to_owned(),
        |e| e.replace('|', "/"),
    )
}

fn secs(d: Duration) -> f64 {
    d.as_secs_f64()
}

fn ms(d: Duration) -> String {
    format!("{:.2}", d.as_secs_f64() * 1e3)
}

fn sci(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else if v.is_finite() {
        format!("{v:.2e}")
    } else {
        "∞".into()
    }
}

fn run(args: &Args) -> Result<(), String> {
    let started = Instant::now();
    let cfg = Config::new(args.quick);
    let root = args
        .root
        .clone()
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../.."));
    let root = root.canonicalize().unwrap_or(root);
    let out_dir = root.join("docs/report");
    std::fs::create_dir_all(&out_dir)
        .map_err(|e| format!("cannot create {}: {e}", out_dir.display()))?;
    let scene_dir = root.join("crates/qcsg-bench/scenes");
    let threads = rayon::current_num_threads();
    let machine = machine();
    let load_start = load_average();
    let mut md = String::new();
    let mut plots: Vec<String> = Vec::new();

    // Scenes.
    let mut scenes = Vec::new();
    for (file, about) in SCENES {
        let path = scene_dir.join(file);
        let compiled = compile_file(&path, &DnfOptions::default())?;
        let codes = compiled.error_codes();
        let Some(dnf) = compiled.dnf else {
            return Err(format!("{}: errors {codes:?}", path.display()));
        };
        let diag = diagonal(&dnf);
        let refs = References::find(&dnf, cfg.rays.0, cfg.rays.1);
        eprintln!(
            "{file}: {} quadrics, {} terms, {} reference points",
            dnf.quadrics.len(),
            dnf.terms.len(),
            refs.surface.len() + refs.edges.len()
        );
        scenes.push(Scene {
            name: file.trim_end_matches(".scad").to_owned(),
            about: about.to_owned(),
            path,
            dnf,
            diag,
            refs,
        });
    }

    // (a) error against run time.
    let mut rows: Vec<Vec<Row>> = Vec::new();
    // Per scene, the radius the sweep stopped before and the samples it would have made.
    let mut stops: Vec<Option<(f64, f64)>> = Vec::new();
    for scene in &scenes {
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
                if expected > args.max_samples as f64 {
                    stop = Some((rel, expected));
                    break;
                }
            }
            let m = one_thread(|| measure(&scene.dnf, rel * scene.diag, &scene.refs))?
                .map_err(|e: SampleError| e.to_string())?;
            let mut images = Vec::new();
            let draw = m.sampling.samples.len() <= args.max_image_samples;
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

    // (b) OpenSCAD.
    let limit = Duration::from_secs(args.peer_limit);
    let work = std::env::temp_dir().join(format!("qcsg-bench-{}", std::process::id()));
    std::fs::create_dir_all(&work).map_err(|e| e.to_string())?;
    let peer = if args.no_openscad { None } else { find() };
    let mut peer_rows: Vec<Vec<PeerRow>> = Vec::new();
    if let Some((program, _)) = &peer {
        for scene in &scenes {
            let mut list = Vec::new();
            for &f in &cfg.fns {
                let export = export_stl(program, &scene.path, f, &work, limit);
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
    }

    // (b) The Python peers.
    let python = |peer: Peer| {
        if args.no_python_peers {
            Err("left out (`--no-python-peers`)".to_owned())
        } else {
            python_peer::find(&root, peer)
        }
    };
    let manifold = python(Peer::Manifold);
    let build123d = python(Peer::Build123d);
    let manifold_runs = match &manifold {
        Ok(m) => Some(peers::run_python(m, &scenes, args.quick, &work, limit)?),
        Err(_) => None,
    };
    let build123d_runs = match &build123d {
        Ok(b) => Some(peers::run_python(b, &scenes, args.quick, &work, limit)?),
        Err(_) => None,
    };

    // (c) Time to an image.
    let display = peer.as_ref().map(|_| Display::start());
    let images = to_image::measure(
        &scenes,
        peer.as_ref()
            .map(|(p, _)| (p.as_path(), peer_rows.as_slice())),
        display.as_ref().and_then(|d| d.as_ref().ok()),
        manifold_runs.as_deref(),
        build123d_runs.as_deref(),
        &work,
        limit,
    )?;
    drop(display);

    // (d) Scaling beside the peers.
    let family_list = families::families(args.quick);
    let family_results = families::measure(
        &family_list,
        &families::Tools {
            manifold: manifold.as_ref().ok(),
            build123d: build123d.as_ref().ok(),
            openscad: peer.as_ref().map(|(p, _)| p.as_path()),
        },
        &work.join("families"),
        limit,
    )?;
    let _ = std::fs::remove_dir_all(&work);

    // Header.
    let _ = writeln!(md, "# qcsg: error against run time\n");
    let _ = writeln!(
        md,
        "Generated by `cargo run --release -p qcsg-bench{}` in {{TOTAL}} on {machine}, with \
         {threads} rayon threads; load average {load_start} at the start and {{LOAD_END}} at the \
         end (the machine is shared with other work, so absolute times are noisy; every figure \
         comes from this one run, and ratios within a table from the same minutes). Sampling is timed on **one thread**, as paper 000 does; the \
         ray tracer and the CPU splat model use all threads. Errors are measured against the \
         exact surface, independently of the sampler (`crates/qcsg-bench/src/reference.rs`): \
         reference points are exact intersections of random lines with the DNF's quadrics where \
         the solid changes across them, plus points on the feature curves found by bisection.\n",
        if args.quick { " -- --quick" } else { "" }
    );
    let _ = writeln!(md, "{{SUMMARY}}");
    let _ = writeln!(md, "Benchmark scenes (`crates/qcsg-bench/scenes/`):\n");
    let _ = writeln!(
        md,
        "| scene | quadrics | terms | literals | diagonal | reference points (surface + edges) | what |"
    );
    let _ = writeln!(md, "|---|---:|---:|---:|---:|---:|---|");
    for s in &scenes {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {:.3} | {} + {} | {} |",
            s.name,
            s.dnf.quadrics.len(),
            s.dnf.terms.len(),
            s.dnf.literal_count(),
            s.diag,
            s.refs.surface.len(),
            s.refs.edges.len(),
            s.about
        );
    }

    // (a) section.
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
        args.max_image_samples
    );
    for (scene, scene_rows) in scenes.iter().zip(&rows) {
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
        if let Some(Some((rel, expected))) = stops.get(
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
                args.max_samples as f64 / 1e6
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
        if let Some(list) = peer_rows.get(
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
            ("Manifold", &manifold_runs),
            ("build123d (boolean + tessellation)", &build123d_runs),
        ] {
            if let Some(run) = runs.as_ref().and_then(|r| r.get(k)) {
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

    // (b) section.
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
    match &peer {
        None => {
            let _ = writeln!(
                md,
                "Not measured: OpenSCAD is not installed (or `--no-openscad` was given).\n"
            );
        }
        Some((_, version)) => {
            let _ = writeln!(
                md,
                "{version}, `openscad -o scene.stl -D '$fn=N' scene.scad`, timed from start to exit \
                 (one process per export, {} s limit).\n",
                args.peer_limit
            );
            for ((scene, list), scene_rows) in scenes.iter().zip(&peer_rows).zip(&rows) {
                let _ = writeln!(md, "**{}**\n", scene.name);
                peers::table(
                    &mut md, scene, scene_rows, &cfg.radii, list, "$fn", "export",
                );
            }
        }
    }
    let _ = writeln!(md, "### 2.2 Manifold\n");
    match (&manifold, &manifold_runs) {
        (Ok(m), Some(runs)) => {
            let _ = writeln!(
                md,
                "{} (Python bindings of the C++ library), `Manifold.sphere/cylinder/cube` with \
                 `circular_segments = n`, booleans by `batch_boolean`, timed from the first \
                 primitive to the mesh out (`to_mesh`). Spheres are refined octahedra (n rounded up \
                 to a multiple of 4).\n",
                m.version
            );
            for ((scene, run), scene_rows) in scenes.iter().zip(runs).zip(&rows) {
                let _ = writeln!(md, "**{}** (process {} ms)\n", scene.name, ms(run.process));
                peers::table(
                    &mut md, scene, scene_rows, &cfg.radii, &run.rows, "segments", "build",
                );
            }
        }
        _ => {
            let why = why_missing(&manifold.as_ref().err());
            let _ = writeln!(md, "Not measured: {why}. {SETUP}\n");
        }
    }
    let _ = writeln!(md, "### 2.3 build123d (OpenCascade)\n");
    match (&build123d, &build123d_runs) {
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
            for ((scene, run), scene_rows) in scenes.iter().zip(runs).zip(&rows) {
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
                    &mut md,
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
            let why = why_missing(&build123d.as_ref().err());
            let _ = writeln!(md, "Not measured: {why}. {SETUP}\n");
        }
    }

    // (c), (d) sections.
    to_image::write(&mut md, &images);
    plots.extend(families::write(
        &mut md,
        &family_list,
        &family_results,
        &out_dir,
        limit,
    )?);

    // (c) throughput.
    throughput::throughput(&mut md, &scenes, &rows, &cfg)?;

    // (d) scaling.
    scaling(&mut md, &mut plots, &out_dir, &cfg, &scenes)?;

    // (e) pruning.
    pruning::pruning(&mut md, &scenes, &cfg, &scene_dir)?;

    // Stability.
    let stable = stability_table::stability_section(&mut md, &root)?;
    let summary = summary::write(&summary::Inputs {
        scenes: &scenes,
        rows: &rows,
        radii: &cfg.radii,
        stops: &stops,
        max_samples: args.max_samples,
        openscad: &peer_rows,
        manifold: manifold_runs.as_deref(),
        build123d: build123d_runs.as_deref(),
        images: &images,
        families: &family_list,
        family_results: &family_results,
        stable,
    });
    let load_end = load_average();

    let total = started.elapsed();
    let md = md
        .replace("{TOTAL}", &format!("{:.0} s", secs(total)))
        .replace("{SUMMARY}\n", &summary)
        .replace("{LOAD_END}", &load_end);
    let path = root.join("docs/report.md");
    std::fs::write(&path, md).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    // Plots of earlier runs that this run did not draw would be stale: remove them.
    if let Ok(entries) = std::fs::read_dir(&out_dir) {
        for entry in entries.flatten() {
            let name = entry.file_name().to_string_lossy().into_owned();
            if name.ends_with(".svg") && !plots.contains(&name) {
                let _ = std::fs::remove_file(entry.path());
            }
        }
    }
    eprintln!(
        "wrote {} and {} plots in {:.0} s",
        path.display(),
        plots.len(),
        secs(total)
    );
    Ok(())
}

/// Samples on the current pool, timed.
fn timed_sample(dnf: &Dnf, radius: f64) -> Result<(Sampling, Duration), String> {
    let start = Instant::now();
    let s = sample(dnf, radius).map_err(|e| e.to_string())?;
    Ok((s, start.elapsed()))
}

/// Samples on one thread, with its time and the peak of heap memory above what was in use
/// before.
fn sample_with_memory(dnf: &Dnf, radius: f64) -> Result<(Sampling, Duration, usize), String> {
    let base = PEAK.current_usage();
    PEAK.reset_peak_usage();
    let (s, t) = one_thread(|| timed_sample(dnf, radius))??;
    let peak = PEAK.peak_usage().saturating_sub(base);
    Ok((s, t, peak))
}

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

/// A count that may be astronomically large.
fn count(x: f64) -> String {
    if x < 1e9 {
        format!("{x:.0}")
    } else {
        format!("{x:.2e}")
    }
}

fn fit_text(points: &[(f64, f64)]) -> String {
    match power_law(points) {
        Some((k, _)) => format!("{k:.2}"),
        None => "–".into(),
    }
}

fn scaling(
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
