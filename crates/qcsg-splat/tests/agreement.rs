//! The splat renderer against the reference ray tracer: on every example in `examples/`, every
//! stiff scene in `tests/scenes/` and every scene of the stability suite (`tests/stability/`)
//! that the pipeline is expected to handle (but those whose header says why splats cannot show
//! them, `// splats: …`), from two views, the two frames must agree in coverage
//! and primitive (quadric) on at least 99.9 % of the pixels outside a one-pixel band around the
//! reference's silhouettes and creases, with depths within 1e-4 of the view's depth range
//! ([`qcsg_splat::compare`]).
//!
//! It needs a GPU adapter; a software one (Mesa's lavapipe or llvmpipe) is enough, and CI
//! installs lavapipe. Without any adapter the test fails: it never skips.

use std::path::{Path, PathBuf};

use qcsg_csg::DnfOptions;
use qcsg_eval::{EvalOptions, evaluate};
use qcsg_render::{Camera, ImageSize, Projection, RenderOptions, Scene, View};
use qcsg_sema::{CheckOptions, FsLoader};
use qcsg_splat::compare::{DEPTH_TOLERANCE, compare};
use qcsg_splat::{AdapterRequirement, PreparedScene, SplatRenderer};

/// The share of compared pixels that must agree.
const REQUIRED_AGREEMENT: f64 = 0.999;

/// The splat radius, as a fraction of the scene's bounding-box diagonal. The sampler's guarantee
/// holds for every radius, so every radius must render the same image; a coarse one keeps the
/// sampling of a debug build to seconds. Both views share the samples.
const RADIUS_OF_DIAGONAL: f64 = 0.1;

fn scene_of(path: &Path) -> Scene {
    let text = std::fs::read_to_string(path).unwrap();
    let name = path.display().to_string();
    let analysis = qcsg_sema::check_file(&name, text, &CheckOptions::default(), &FsLoader);
    assert!(!analysis.has_errors(), "{name} has errors");
    let evaluation = evaluate(&analysis, &EvalOptions::default());
    assert!(!evaluation.has_errors(), "{name} fails to evaluate");
    let mut dag = evaluation.dag;
    Scene::from_dag(&mut dag, &DnfOptions::default()).unwrap_or_else(|_| panic!("{name}: no DNF"))
}

fn scene_files() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    let stability = root.join("../../tests/stability");
    for dir in [
        root.join("../../examples"),
        root.join("tests/scenes"),
        stability.clone(),
    ] {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if !matches!(
                path.extension().and_then(|e| e.to_str()),
                Some("qcsg" | "scad")
            ) {
                continue;
            }
            // The stability suite's scenes that the pipeline handles (`// expect: ok`); the
            // others are errors, empty, or known sampler failures.
            if dir == stability {
                let text = std::fs::read_to_string(&path).unwrap();
                let header = |line: &str| text.lines().any(|l| l.trim().starts_with(line));
                if !header("// expect: ok") || header("// splats:") {
                    continue;
                }
            }
            files.push(path);
        }
    }
    files.sort();
    files
}

/// The renderer on the best adapter there is; without one the test fails (it never skips).
fn renderer() -> SplatRenderer {
    SplatRenderer::new(AdapterRequirement::Any).unwrap_or_else(|error| {
        panic!(
            "{error}\nThe splat agreement test needs a GPU adapter; a software one is enough \
             (Debian: apt-get install mesa-vulkan-drivers libvulkan1)."
        )
    })
}

#[test]
fn splats_agree_with_the_ray_tracer_on_every_scene() {
    let renderer = renderer();
    eprintln!("adapter: {}", renderer.adapter());
    let size = ImageSize::new(160, 120).unwrap();
    let views = [
        (View::Iso, Projection::Perspective),
        (View::Front, Projection::Orthographic),
    ];
    let files = scene_files();
    assert!(files.len() >= 10, "examples or stiff scenes are missing");
    let mut failures = Vec::new();
    for file in &files {
        let scene = scene_of(file);
        let started = std::time::Instant::now();
        let radius = RADIUS_OF_DIAGONAL * 2.0 * scene.bounds().half_diagonal();
        let prepared = PreparedScene::new(&scene, radius)
            .unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        eprintln!(
            "{}: {} samples in {:.2} s",
            file.display(),
            prepared.sample_count(),
            started.elapsed().as_secs_f64()
        );
        // A scene seen edge-on (a plate from the front, a thin rod across) may show nothing in
        // one view, but every scene must show something in some view.
        let mut shown = false;
        for (view, projection) in views {
            let camera = Camera::fit(&view, projection, &scene.bounds(), size).unwrap();
            let options = RenderOptions::default();
            let started = std::time::Instant::now();
            let reference = qcsg_render::render(&scene, &camera, size, &options, &|_| {});
            let traced = started.elapsed();
            let splats = renderer
                .render_prepared(&scene, &prepared, &camera, size, &options)
                .unwrap_or_else(|e| panic!("{}: {e}", file.display()));
            let splatted = started.elapsed() - traced;
            let agreement = compare(&reference, &splats);
            let line = format!(
                "{} {view:?} {projection:?}: {:.5} of {} pixels agree ({} banded; coverage {}, \
                 quadric {}, depth {} mismatches; max depth error {:.1e}; {} term differences; \
                 {:.2} s traced, {:.2} s splatted)",
                file.file_name().unwrap().to_string_lossy(),
                agreement.fraction(),
                agreement.compared,
                agreement.banded,
                agreement.coverage_mismatches,
                agreement.quadric_mismatches,
                agreement.depth_mismatches,
                agreement.max_depth_error,
                agreement.term_differences,
                traced.as_secs_f64(),
                splatted.as_secs_f64(),
            );
            eprintln!("{line}");
            shown |= reference.hit_count() > 0;
            if agreement.fraction() < REQUIRED_AGREEMENT {
                failures.push(line);
            }
        }
        if !shown {
            failures.push(format!("{}: no view shows the solid", file.display()));
        }
    }
    assert!(
        failures.is_empty(),
        "the splat renderer drifted from the reference (required: {REQUIRED_AGREEMENT} of the \
         pixels, depth within {DEPTH_TOLERANCE} of the range):\n{}",
        failures.join("\n")
    );
}
