//! `qcsg-bench`: regenerates `docs/report.md` and its plots in `docs/report/` — error against
//! run time for the benchmark scenes (`crates/qcsg-bench/scenes/`), the OpenSCAD comparison,
//! throughput beside paper 000's Tables 1 and 2, scaling with fitted exponents, what pruning
//! left out, and the stability suite's measured errors.
//!
//! Run it with `cargo run --release -p qcsg-bench` (add `--quick` for smaller sweeps). The
//! Python peers (Manifold, build123d) are measured when `crates/qcsg-bench/peers/setup.sh` has
//! made their environment; OpenSCAD when it is installed, its preview when Xvfb is.

mod error_time;
mod export_families;
mod exports;
mod families;
mod mesh_scale;
mod peer_meshes;
mod peers;
mod pruning;
mod scaling;
mod stability_table;
mod summary;
mod throughput;
mod to_image;

use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use clap::Parser;
use peak_alloc::PeakAlloc;
use qcsg_bench::image::Agreement;
use qcsg_bench::measure::{Measured, References};
use qcsg_bench::openscad::{Display, find};
use qcsg_bench::pipeline::compile_file;
use qcsg_bench::plot::power_law;
use qcsg_bench::python_peer::{self, Peer};
use qcsg_bench::reference::diagonal;
use qcsg_csg::{Dnf, DnfOptions};
use qcsg_sample::{Sampling, sample};

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
    /// Run only the imported-mesh scaling benchmark, which writes `docs/report/mesh_scale.md`
    /// (and leaves `docs/report.md` as it is).
    #[arg(long)]
    mesh_scale: bool,
    /// Seconds each peer process (OpenSCAD, Python) may run.
    #[arg(long, default_value_t = 60)]
    peer_limit: u64,
    /// Regenerate only section 9 (`qcsg export` beside the peers' meshes, the peers measured
    /// again) in the existing report, leaving the other sections as they are.
    #[arg(long)]
    meshes_only: bool,
    /// Regenerate only section 9.1 (the scaling families through `qcsg export` beside
    /// Manifold at equal error) in the existing report; with `--quick`, only the two smallest
    /// sizes of each family.
    #[arg(long)]
    export_families: bool,
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

/// What the peers' meshes of the benchmark scenes gave (section 2).
struct PeerResults {
    /// OpenSCAD's path and version, where it is installed and wanted.
    openscad: Option<(PathBuf, String)>,
    /// Per scene, OpenSCAD's exports over `$fn`.
    openscad_rows: Vec<Vec<peers::PeerRow>>,
    manifold: Result<python_peer::Installed, String>,
    manifold_runs: Option<Vec<peers::PythonScene>>,
    build123d: Result<python_peer::Installed, String>,
    build123d_runs: Option<Vec<peers::PythonScene>>,
}

impl PeerResults {
    /// Runs every installed peer over the scenes, each process within `limit`.
    fn measure(
        args: &Args,
        cfg: &Config,
        root: &std::path::Path,
        scenes: &[Scene],
        work: &std::path::Path,
        limit: Duration,
    ) -> Result<Self, String> {
        let openscad = if args.no_openscad { None } else { find() };
        let openscad_rows = match &openscad {
            Some((program, _)) => peer_meshes::openscad(program, scenes, &cfg.fns, work, limit),
            None => Vec::new(),
        };
        let python = |peer: Peer| {
            if args.no_python_peers {
                Err("left out (`--no-python-peers`)".to_owned())
            } else {
                python_peer::find(root, peer)
            }
        };
        let manifold = python(Peer::Manifold);
        let build123d = python(Peer::Build123d);
        let manifold_runs = match &manifold {
            Ok(m) => Some(peers::run_python(m, scenes, args.quick, work, limit)?),
            Err(_) => None,
        };
        let build123d_runs = match &build123d {
            Ok(b) => Some(peers::run_python(b, scenes, args.quick, work, limit)?),
            Err(_) => None,
        };
        Ok(Self {
            openscad,
            openscad_rows,
            manifold,
            manifold_runs,
            build123d,
            build123d_runs,
        })
    }

    fn peers(&self) -> peer_meshes::Peers<'_> {
        peer_meshes::Peers {
            openscad: self.openscad.as_ref().map(|(_, version)| version.as_str()),
            openscad_rows: &self.openscad_rows,
            manifold: &self.manifold,
            manifold_runs: self.manifold_runs.as_deref(),
            build123d: &self.build123d,
            build123d_runs: self.build123d_runs.as_deref(),
        }
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
    if args.mesh_scale {
        return mesh_scale::run(&root, args.no_python_peers);
    }
    let out_dir = root.join("docs/report");
    std::fs::create_dir_all(&out_dir)
        .map_err(|e| format!("cannot create {}: {e}", out_dir.display()))?;
    if args.export_families {
        return export_families_only(args, &root, started);
    }
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

    if args.meshes_only {
        return meshes_only(args, &cfg, &root, &scenes, started, &machine, &load_start);
    }

    // (a) error against run time.
    let sweep = error_time::measure_all(&scenes, &cfg, args.max_samples, args.max_image_samples)?;

    // (b) The peers.
    let limit = Duration::from_secs(args.peer_limit);
    let work = std::env::temp_dir().join(format!("qcsg-bench-{}", std::process::id()));
    std::fs::create_dir_all(&work).map_err(|e| e.to_string())?;
    let measured = PeerResults::measure(args, &cfg, &root, &scenes, &work, limit)?;
    let PeerResults {
        openscad: peer,
        openscad_rows: peer_rows,
        manifold,
        manifold_runs,
        build123d,
        build123d_runs,
    } = &measured;

    // (9) qcsg export beside the peers' meshes.
    let export_rows = exports::measure(&scenes, &exports::tolerances(args.quick))?;

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
    // (9.1) The families through `qcsg export` beside Manifold.
    let export_family_list = families::families(args.quick);
    let export_family_rows = export_families::measure(
        &export_family_list,
        manifold.as_ref().ok(),
        &work.join("export-families"),
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
    let peers = measured.peers();
    plots.extend(error_time::write(
        &mut md, &out_dir, &cfg, &scenes, &sweep, &peers,
    )?);
    let error_time::Sweep { rows, stops, .. } = sweep;

    // (b) section.
    peer_meshes::write(&mut md, &cfg, &scenes, &rows, &peers, args.peer_limit);

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
    scaling::scaling(&mut md, &mut plots, &out_dir, &cfg, &scenes)?;

    // (e) pruning.
    pruning::pruning(&mut md, &scenes, &cfg, &scene_dir)?;

    // Stability.
    let stable = stability_table::stability_section(&mut md, &root)?;

    // Meshes.
    plots.extend(exports::write(
        &mut md,
        &out_dir,
        &scenes,
        &export_rows,
        &peers,
        "",
    )?);
    plots.extend(export_families::write(
        &mut md,
        &out_dir,
        &export_family_list,
        &export_family_rows,
        manifold.as_ref().map_err(String::as_str),
        "",
    )?);
    let summary = summary::write(&summary::Inputs {
        scenes: &scenes,
        rows: &rows,
        radii: &cfg.radii,
        stops: &stops,
        max_samples: args.max_samples,
        openscad: peer_rows,
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

/// `--meshes-only`: measures the peers' meshes and `qcsg export` again and replaces section 9
/// of the existing report, with its own provenance.
fn meshes_only(
    args: &Args,
    cfg: &Config,
    root: &std::path::Path,
    scenes: &[Scene],
    started: Instant,
    machine: &str,
    load_start: &str,
) -> Result<(), String> {
    let limit = Duration::from_secs(args.peer_limit);
    let work = std::env::temp_dir().join(format!("qcsg-bench-{}", std::process::id()));
    std::fs::create_dir_all(&work).map_err(|e| e.to_string())?;
    let measured = PeerResults::measure(args, cfg, root, scenes, &work, limit)?;
    let _ = std::fs::remove_dir_all(&work);
    let export_rows = exports::measure(scenes, &exports::tolerances(args.quick))?;
    let provenance = format!(
        "This section was generated on its own by `cargo run --release -p qcsg-bench -- \
         --meshes-only{}` in {:.0} s on {machine}, load average {load_start} at the start and {} \
         at the end; it measured the peers' meshes again for its comparisons (section 2's tables \
         come from the run that wrote the rest of the report, so their times differ by the \
         machine's load).\n\n",
        if args.quick { " --quick" } else { "" },
        secs(started.elapsed()),
        load_average()
    );
    let mut section = String::new();
    let out_dir = root.join("docs/report");
    exports::write(
        &mut section,
        &out_dir,
        scenes,
        &export_rows,
        &measured.peers(),
        &provenance,
    )?;
    let path = root.join("docs/report.md");
    let report = std::fs::read_to_string(&path).unwrap_or_default();
    std::fs::write(&path, exports::splice(&report, &section))
        .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    eprintln!(
        "replaced section 9 of {} in {:.0} s",
        path.display(),
        secs(started.elapsed())
    );
    Ok(())
}

/// `--export-families`: measures the families through `qcsg export` and Manifold and replaces
/// section 9.1 of the existing report, with its own provenance.
fn export_families_only(
    args: &Args,
    root: &std::path::Path,
    started: Instant,
) -> Result<(), String> {
    let machine = machine();
    let load_start = load_average();
    let limit = Duration::from_secs(args.peer_limit);
    let manifold = if args.no_python_peers {
        Err("left out (`--no-python-peers`)".to_owned())
    } else {
        python_peer::find(root, Peer::Manifold)
    };
    let work = std::env::temp_dir().join(format!("qcsg-bench-{}", std::process::id()));
    let families = families::families(args.quick);
    let rows = export_families::measure(&families, manifold.as_ref().ok(), &work, limit)?;
    let _ = std::fs::remove_dir_all(&work);
    let provenance = format!(
        "This section was generated on its own by `cargo run --release -p qcsg-bench -- \
         --export-families{}` in {:.0} s on {machine}, load average {load_start} at the start \
         and {} at the end.\n\n",
        if args.quick { " --quick" } else { "" },
        secs(started.elapsed()),
        load_average()
    );
    let mut section = String::new();
    export_families::write(
        &mut section,
        &root.join("docs/report"),
        &families,
        &rows,
        manifold.as_ref().map_err(String::as_str),
        &provenance,
    )?;
    let path = root.join("docs/report.md");
    let report = std::fs::read_to_string(&path).unwrap_or_default();
    std::fs::write(
        &path,
        exports::splice_section(&report, export_families::HEADING, &section),
    )
    .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    eprintln!(
        "replaced section 9.1 of {} in {:.0} s",
        path.display(),
        secs(started.elapsed())
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
