//! Render-time benchmark: every example (or the files given) at 1920×1080 with the splat
//! renderer and the CPU reference ray tracer, in the same run, printed as a markdown table.
//!
//! `cargo run --release -p qcsg-splat --example bench -- [--size W,H] [--runs N] [--radius F]
//! [FILE...]` (`WGPU_BACKEND=vulkan|gl` picks the backend). Sampling is timed once per scene and
//! reported apart from the splat render; `--radius F` samples at F times the scene's diagonal
//! instead of the radius `qcsg render` would pick. The table goes to docs/render.md.

use std::path::{Path, PathBuf};
use std::time::Instant;

use qcsg_csg::DnfOptions;
use qcsg_eval::{EvalOptions, evaluate};
use qcsg_render::{Camera, ImageSize, Projection, RenderOptions, Scene, View};
use qcsg_sema::{CheckOptions, FsLoader};
use qcsg_splat::compare::compare;
use qcsg_splat::{AdapterRequirement, PreparedScene, SplatRenderer, splat_radius};

fn scene_of(path: &Path) -> Result<Scene, String> {
    let text = std::fs::read_to_string(path).map_err(|e| e.to_string())?;
    let name = path.display().to_string();
    let analysis = qcsg_sema::check_file(&name, text, &CheckOptions::default(), &FsLoader);
    if analysis.has_errors() {
        return Err(format!("{name} has errors"));
    }
    let evaluation = evaluate(&analysis, &EvalOptions::default());
    if evaluation.has_errors() {
        return Err(format!("{name} fails to evaluate"));
    }
    let mut dag = evaluation.dag;
    Scene::from_dag(&mut dag, &DnfOptions::default()).map_err(|_| format!("{name}: no DNF"))
}

/// The median of `runs` timings of `f`, in milliseconds.
fn median_ms<T>(runs: usize, mut f: impl FnMut() -> T) -> (f64, T) {
    let mut times = Vec::new();
    let mut last = None;
    for _ in 0..runs.max(1) {
        let started = Instant::now();
        last = Some(f());
        times.push(started.elapsed().as_secs_f64() * 1e3);
    }
    times.sort_by(f64::total_cmp);
    let value = last.unwrap_or_else(|| unreachable!("at least one run"));
    (times[times.len() / 2], value)
}

fn main() {
    let mut size = ImageSize::new(1920, 1080).unwrap_or_default();
    let mut runs = 3;
    let mut radius_of_diagonal: Option<f64> = None;
    let mut files: Vec<PathBuf> = Vec::new();
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--size" => match args.next().map(|s| ImageSize::parse(&s)) {
                Some(Ok(parsed)) => size = parsed,
                _ => return eprintln!("--size wants W,H"),
            },
            "--radius" => match args.next().and_then(|s| s.parse().ok()) {
                Some(f) => radius_of_diagonal = Some(f),
                None => return eprintln!("--radius wants a fraction of the scene's diagonal"),
            },
            "--runs" => match args.next().and_then(|s| s.parse().ok()) {
                Some(n) => runs = n,
                None => return eprintln!("--runs wants a count"),
            },
            _ => files.push(arg.into()),
        }
    }
    if files.is_empty() {
        let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
        if let Ok(entries) = std::fs::read_dir(&examples) {
            files = entries
                .flatten()
                .map(|e| e.path())
                .filter(|p| {
                    matches!(
                        p.extension().and_then(|e| e.to_str()),
                        Some("qcsg" | "scad")
                    )
                })
                .collect();
        }
        files.sort();
    }
    let renderer = match SplatRenderer::new(AdapterRequirement::Any) {
        Ok(renderer) => renderer,
        Err(error) => return eprintln!("error: {error}"),
    };
    let threads = rayon::current_num_threads();
    println!(
        "Adapter: {}; image {}x{}; median of {runs} runs; {threads} CPU threads.\n",
        renderer.adapter(),
        size.width(),
        size.height()
    );
    println!(
        "| scene | quadrics | samples | clip indices | sampling ms | splat render ms | ray tracer ms | ray tracer / splat | agreement |"
    );
    println!("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |");
    for file in &files {
        let name = file.file_name().unwrap_or_default().to_string_lossy();
        let scene = match scene_of(file) {
            Ok(scene) => scene,
            Err(error) => {
                eprintln!("skipping {name}: {error}");
                continue;
            }
        };
        let Ok(camera) = Camera::fit(&View::Iso, Projection::Perspective, &scene.bounds(), size)
        else {
            continue;
        };
        let options = RenderOptions::default();
        let Some(radius) = radius_of_diagonal
            .map(|f| f * 2.0 * scene.bounds().half_diagonal())
            .or_else(|| splat_radius(&scene, &camera, size))
        else {
            continue;
        };
        let (sampling_ms, prepared) = median_ms(1, || PreparedScene::new(&scene, radius));
        let prepared = match prepared {
            Ok(prepared) => prepared,
            Err(error) => {
                eprintln!("{name}: {error}");
                continue;
            }
        };
        let (splat_ms, splats) = median_ms(runs, || {
            renderer.render_prepared(&scene, &prepared, &camera, size, &options)
        });
        let splats = match splats {
            Ok(frame) => frame,
            Err(error) => {
                eprintln!("{name}: {error}");
                continue;
            }
        };
        let (trace_ms, reference) = median_ms(runs, || {
            qcsg_render::render(&scene, &camera, size, &options, &|_| {})
        });
        let agreement = compare(&reference, &splats);
        println!(
            "| {name} | {} | {} | {} | {sampling_ms:.0} | {splat_ms:.0} | {trace_ms:.0} | {:.2}× | {:.4} |",
            scene.quadric_count(),
            prepared.sample_count(),
            prepared.clip_index_count(),
            trace_ms / splat_ms,
            agreement.fraction(),
        );
    }
}
