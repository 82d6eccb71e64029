//! `qcsg-bench --mesh-scale`: how the time from an imported STL to an 800×600 image grows with
//! the mesh's triangle count, written to `docs/report/mesh_scale.md`.
//!
//! The meshes are [`qcsg_bench::bumpy`]'s closed non-convex surfaces of 2,000 to 20,000
//! triangles, written to a scratch folder at run time. Each is imported alone and with 100
//! cylinders subtracted from it, and timed stage by stage as `qcsg render` runs them (check and
//! evaluation, which reads the file and cuts the mesh into convex cells; the normal form; the
//! ray tracer's index; the ray tracer at 800×600 on every thread; the PNG). Beside each, when
//! the Python peers' environment has it, Manifold subtracts the same 100 cylinders from the
//! same file (`peer.py`, the mesh read from the STL inside the timed part). All figures come
//! from one run, so the growth ratios between sizes compare like with like.

use std::fmt::Write as _;
use std::path::Path;
use std::time::{Duration, Instant};

use qcsg_bench::bumpy;
use qcsg_bench::pipeline::compile_source;
use qcsg_bench::plot::power_law;
use qcsg_bench::python_peer::{self, Installed, Peer};
use qcsg_bench::shape::Shape;
use qcsg_csg::DnfOptions;
use qcsg_render::{Camera, ImageSize, Projection, RenderOptions, Scene, View};
use qcsg_testkit::cpu::own_cpu_time;

use crate::{load_average, machine, secs};

/// Triangle counts of the sweep.
const SIZES: [usize; 4] = [2_000, 5_000, 10_000, 20_000];

/// The term limit of the sweep: ten times `qcsg`'s default, so that a mesh whose cells outgrow
/// the default is still timed; the report says whether any did.
const TERM_LIMIT: usize = 1_000_000;

/// The image size the target is stated for.
const IMAGE: (u32, u32) = (800, 600);

/// One scene's timings, stage by stage.
struct Timing {
    triangles: usize,
    terms: usize,
    literals: usize,
    front_end: Duration,
    normal_form: Duration,
    index: Duration,
    render: Duration,
    png: Duration,
    hits: usize,
    /// The process's CPU time over all the stages (every thread), where `/proc` tells it.
    cpu: Option<Duration>,
}

impl Timing {
    fn total(&self) -> Duration {
        self.front_end + self.normal_form + self.index + self.render + self.png
    }
}

/// 100 upright cylinders of radius 0.5 on a 10×10 grid 1.6 apart, through the whole mesh.
fn cylinders() -> Vec<Shape> {
    let mut out = Vec::with_capacity(100);
    for i in 0..10 {
        for j in 0..10 {
            let at = |k: i32| 1.6 * (f64::from(k) - 4.5);
            out.push(
                Shape::Cylinder {
                    h: 4.0 * bumpy::RADIUS,
                    r: 0.5,
                    center: true,
                }
                .at([at(i), at(j), 0.0]),
            );
        }
    }
    out
}

/// Runs `shape` from text to PNG the way `qcsg render` does, timed per stage.
fn time_qcsg(shape: &Shape, dir: &Path, triangles: usize) -> Result<Timing, String> {
    let cpu_start = own_cpu_time();
    let main = dir.join("scene.scad");
    let options = DnfOptions {
        term_limit: TERM_LIMIT,
        ..DnfOptions::default()
    };
    let compiled = compile_source(&main.to_string_lossy(), shape.to_scad(), &options);
    let codes = compiled.error_codes();
    let dnf = compiled
        .dnf
        .ok_or_else(|| format!("the scene did not compile: {codes:?}"))?;
    let (terms, literals) = (dnf.terms.len(), dnf.literal_count());
    let start = Instant::now();
    let scene = Scene::new(dnf);
    let index = start.elapsed();
    let size = ImageSize::new(IMAGE.0, IMAGE.1).map_err(|e| e.to_string())?;
    let camera = Camera::fit(&View::Iso, Projection::Perspective, &scene.bounds(), size)
        .map_err(|e| e.to_string())?;
    let start = Instant::now();
    let frame = qcsg_render::render(&scene, &camera, size, &RenderOptions::default(), &|_| {});
    let render = start.elapsed();
    let start = Instant::now();
    let png = qcsg_render::png::encode(&frame).map_err(|e| e.to_string())?;
    let png_time = start.elapsed();
    let cpu = own_cpu_time()
        .zip(cpu_start)
        .map(|(end, start)| end - start);
    std::fs::write(dir.join("scene.png"), png).map_err(|e| e.to_string())?;
    Ok(Timing {
        triangles,
        terms,
        literals,
        front_end: compiled.front_end,
        normal_form: compiled.normal_form,
        index,
        render,
        png: png_time,
        hits: frame.hit_count(),
        cpu,
    })
}

/// Manifold's wall and CPU time to read the STL and subtract the cylinders, or why there is none.
fn time_manifold(
    manifold: &Result<Installed, String>,
    shape: &Shape,
    work: &Path,
) -> Result<(Duration, Option<Duration>), String> {
    let installed = manifold.as_ref().map_err(Clone::clone)?;
    let run = python_peer::run(installed, shape, &[32.0], work, Duration::from_secs(120));
    if let Some(failure) = run.failure {
        return Err(failure);
    }
    let result = run.results.first().ok_or("no result")?;
    if !result.valid {
        return Err("Manifold reports an invalid result".into());
    }
    Ok((result.time, result.cpu))
}

fn ms(d: Duration) -> String {
    format!("{:.0}", d.as_secs_f64() * 1e3)
}

/// The growth exponent of `times` against the triangle counts (least squares on log-log axes).
fn exponent(rows: &[Result<Timing, String>], time: impl Fn(&Timing) -> Duration) -> String {
    let points: Vec<(f64, f64)> = rows
        .iter()
        .flatten()
        .map(|r| (r.triangles as f64, secs(time(r)).max(1e-6)))
        .collect();
    power_law(&points).map_or_else(|| "–".into(), |(k, _)| format!("{k:.2}"))
}

fn table(md: &mut String, sizes: &[usize], rows: &[Result<Timing, String>]) {
    let _ = writeln!(
        md,
        "| triangles | terms | literals | check + evaluate ms | normal form ms | index ms | ray trace ms | PNG ms | total ms | total / previous | hit pixels |"
    );
    let _ = writeln!(
        md,
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    );
    for (k, (n, r)) in sizes.iter().zip(rows).enumerate() {
        let r = match r {
            Ok(r) => r,
            Err(why) => {
                let _ = writeln!(md, "| {n} | failed: {why} | | | | | | | | | |");
                continue;
            }
        };
        let previous = k.checked_sub(1).and_then(|p| rows[p].as_ref().ok());
        let growth = previous.map_or_else(
            || "–".to_owned(),
            |before| {
                format!(
                    "{:.2} (for {:.2}× the triangles)",
                    secs(r.total()) / secs(before.total()),
                    r.triangles as f64 / before.triangles as f64
                )
            },
        );
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} | {} | {} | **{}** | {} | {} |",
            r.triangles,
            r.terms,
            r.literals,
            ms(r.front_end),
            ms(r.normal_form),
            ms(r.index),
            ms(r.render),
            ms(r.png),
            ms(r.total()),
            growth,
            r.hits
        );
    }
    let _ = writeln!(
        md,
        "\nGrowth exponents (time ∝ triangles^k): check + evaluate {}, normal form {}, index {}, \
         ray trace {}, total {}.\n",
        exponent(rows, |r| r.front_end),
        exponent(rows, |r| r.normal_form),
        exponent(rows, |r| r.index),
        exponent(rows, |r| r.render),
        exponent(rows, Timing::total),
    );
}

/// Whether the sweep needed the raised term limit: the most terms of any scene against the
/// default.
fn term_limit_note(plain: &[Result<Timing, String>], drilled: &[Result<Timing, String>]) -> String {
    let most = plain
        .iter()
        .chain(drilled)
        .filter_map(|r| r.as_ref().ok())
        .map(|t| t.terms)
        .max()
        .unwrap_or(0);
    let default = qcsg_csg::DEFAULT_TERM_LIMIT;
    if most > default {
        format!(
            "because the default of {default} is too few for the cells of the largest meshes \
             (up to {most} terms)"
        )
    } else {
        format!(
            "only as headroom: the largest scene has {most} terms, within the default of {default}"
        )
    }
}

/// Runs the sweep and writes `docs/report/mesh_scale.md` under `root`.
pub fn run(root: &Path, no_python_peers: bool) -> Result<(), String> {
    let started = Instant::now();
    let load_start = load_average();
    let work = std::env::temp_dir().join(format!("qcsg-mesh-scale-{}", std::process::id()));
    std::fs::create_dir_all(&work).map_err(|e| e.to_string())?;
    let manifold = if no_python_peers {
        Err("left out (`--no-python-peers`)".to_owned())
    } else {
        python_peer::find(root, Peer::Manifold)
    };
    let mut sizes = Vec::new();
    let mut plain = Vec::new();
    let mut drilled = Vec::new();
    let mut peer = Vec::new();
    for &n in &SIZES {
        let faces = bumpy::triangles(n);
        sizes.push(faces.len());
        let stl = work.join(format!("bumpy_{n}.stl"));
        std::fs::write(&stl, bumpy::binary_stl(&faces)).map_err(|e| e.to_string())?;
        let mesh = Shape::Import(stl.to_string_lossy().into_owned());
        let timing = time_qcsg(&mesh, &work, faces.len());
        eprintln!(
            "mesh {}: {:?}",
            faces.len(),
            timing.as_ref().map(Timing::total)
        );
        plain.push(timing);
        let mut parts = vec![mesh];
        parts.extend(cylinders());
        let minus = Shape::Difference(parts);
        let timing = time_qcsg(&minus, &work, faces.len());
        eprintln!(
            "mesh {} minus 100 cylinders: {:?}",
            faces.len(),
            timing.as_ref().map(Timing::total)
        );
        drilled.push(timing);
        peer.push(time_manifold(&manifold, &minus, &work.join("manifold")));
    }
    let _ = std::fs::remove_dir_all(&work);

    let mut md = String::new();
    let _ = writeln!(
        md,
        "# Imported meshes: time to an image against triangle count\n"
    );
    let _ = writeln!(
        md,
        "Generated by `cargo run --release -p qcsg-bench -- --mesh-scale` in {:.0} s on {}, with \
         {} rayon threads; load average {load_start} at the start and {} at the end (the \
         machine is shared, so absolute times are noisy; every figure is from this one run).\n",
        secs(started.elapsed()),
        machine(),
        rayon::current_num_threads(),
        load_average()
    );
    let _ = writeln!(
        md,
        "Each mesh is a closed, non-convex bumpy sphere of radius 8 to 12 \
         (`crates/qcsg-bench/src/bumpy.rs`) written as binary STL, imported by \
         `import(\"bumpy_N.stl\");` and run as `qcsg render` runs it: check and evaluation (which \
         read the file and cut the mesh into convex cells), the normal form, the ray tracer's \
         index, the ray tracer at {}×{} (perspective, iso view) on every thread, and the PNG. \
         The target is under 2 s for 20,000 triangles, from parse to PNG. The term limit is \
         raised to {TERM_LIMIT} (`--max-terms {TERM_LIMIT}`) {}.\n",
        IMAGE.0,
        IMAGE.1,
        term_limit_note(&plain, &drilled)
    );
    let _ = writeln!(md, "## The mesh alone\n");
    table(&mut md, &sizes, &plain);
    let _ = writeln!(
        md,
        "## The mesh minus 100 cylinders\n\n100 upright cylinders of radius 0.5 on a 10×10 grid \
         1.6 apart, through the whole mesh, subtracted in one `difference()`.\n"
    );
    table(&mut md, &sizes, &drilled);
    let _ = writeln!(md, "## Beside Manifold\n");
    match &manifold {
        Ok(m) => {
            let _ = writeln!(
                md,
                "{}, 32 segments per cylinder: reading the same STL into a manifold and \
                 subtracting the same 100 cylinders (one batch boolean), with the mesh out, timed \
                 inside `peer.py` (without interpreter start-up).\n",
                m.version
            );
        }
        Err(why) => {
            let _ = writeln!(md, "Manifold not measured: {why}.\n");
        }
    }
    let _ = writeln!(
        md,
        "Wall time on a shared machine measures its load as much as the work, so the CPU time of \
         the same runs (user and system, every thread: qcsg's from `/proc`, Manifold's from \
         Python's `time.process_time`) stands beside it. qcsg's ray tracer runs on every core, \
         which wall time rewards and CPU time does not.\n"
    );
    let _ = writeln!(
        md,
        "| triangles | qcsg: mesh to PNG ms | qcsg: mesh minus cylinders to PNG ms | Manifold: mesh minus cylinders ms | qcsg / Manifold, wall | qcsg (minus cylinders) CPU ms | Manifold CPU ms | qcsg / Manifold, CPU |"
    );
    let _ = writeln!(md, "|---:|---:|---:|---:|---:|---:|---:|---:|");
    let total = |r: &Result<Timing, String>| {
        r.as_ref()
            .map_or_else(|_| "failed".into(), |t| ms(t.total()))
    };
    let ratio = |a: Option<Duration>, b: Option<Duration>| match (a, b) {
        (Some(a), Some(b)) if !b.is_zero() => format!("{:.2}", secs(a) / secs(b)),
        _ => "–".to_owned(),
    };
    let or_dash = |d: Option<Duration>| d.map_or_else(|| "–".to_owned(), ms);
    for (((n, p), d), m) in sizes.iter().zip(&plain).zip(&drilled).zip(&peer) {
        let drilled = d.as_ref().ok();
        let (manifold_wall, manifold_cpu) = match m {
            Ok((wall, cpu)) => (Some(*wall), *cpu),
            Err(_) => (None, None),
        };
        let _ = writeln!(
            md,
            "| {n} | {} | {} | {} | {} | {} | {} | {} |",
            total(p),
            total(d),
            manifold_wall.map_or_else(|| "not measured".to_owned(), ms),
            ratio(drilled.map(Timing::total), manifold_wall),
            or_dash(drilled.and_then(|t| t.cpu)),
            or_dash(manifold_cpu),
            ratio(drilled.and_then(|t| t.cpu), manifold_cpu),
        );
    }
    let path = root.join("docs/report/mesh_scale.md");
    std::fs::write(&path, md).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    eprintln!("wrote {}", path.display());
    Ok(())
}
