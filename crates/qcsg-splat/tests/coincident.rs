//! Flush faces in splats: pairs of one solid written with surfaces shared by its parts (a
//! cutter flush with a face, a cylinder cut flush at half height, a ball minus a turned copy of
//! itself, a tube bored flush, a union with a flush top, boxes sharing their sides;
//! `qcsg_testkit::FLUSH_PAIRS`) and without, each also moved by 10⁵ and scaled by 10⁻³. With one explicit camera, the splats of
//! the flush scene must show what the ray tracer shows of the clean one: outside a one-pixel
//! band around the clean frame's silhouettes, creases and depth steps, at least 99.9 % of the
//! pixels agree in coverage and depth (within [`DEPTH_TOLERANCE`] of the depth range). The ray
//! tracer's own frame of the flush scene is held to the same measure
//! (`crates/qcsg-render/tests/coincident.rs` compares it pixel by pixel).
//!
//! It needs a GPU adapter, a software one being enough; the backend follows `WGPU_BACKEND`
//! (CI runs it on Vulkan through lavapipe and on OpenGL through llvmpipe). Without any adapter
//! the test fails: it never skips.

use qcsg_csg::DnfOptions;
use qcsg_eval::{EvalOptions, evaluate};
use qcsg_quadric::DVec3;
use qcsg_render::{Camera, Frame, ImageSize, Projection, RenderOptions, Scene};
use qcsg_sema::{CheckOptions, FsLoader};
use qcsg_splat::compare::DEPTH_TOLERANCE;
use qcsg_splat::{AdapterRequirement, PreparedScene, SplatRenderer};
use qcsg_testkit::{FLUSH_PAIRS, FlushPair};

/// The least share of pixels outside the band that must agree.
const REQUIRED_AGREEMENT: f64 = 0.999;

/// Neighbouring depths further apart than this share of the depth range mark a depth step.
const DEPTH_STEP: f64 = 5e-3;

/// The splat radius as a share of the scene's diagonal.
const RADIUS_OF_DIAGONAL: f64 = 0.1;

const WIDTH: u32 = 160;
const HEIGHT: u32 = 120;

/// How a pair is placed: as written, moved far from the origin, or scaled down.
#[derive(Clone, Copy, Debug)]
enum Placement {
    AsWritten,
    Moved,
    Scaled,
}

impl Placement {
    const ALL: [Placement; 3] = [Self::AsWritten, Self::Moved, Self::Scaled];

    fn wrap(self, source: &str) -> String {
        match self {
            Self::AsWritten => source.to_string(),
            Self::Moved => format!("translate([1e5, 1e5, 1e5]) {{ {source} }}"),
            Self::Scaled => format!("scale(1e-3) {{ {source} }}"),
        }
    }

    fn point(self, p: DVec3) -> DVec3 {
        match self {
            Self::AsWritten => p,
            Self::Moved => p + DVec3::splat(1e5),
            Self::Scaled => p * 1e-3,
        }
    }
}

fn scene(name: &str, source: String) -> Scene {
    let analysis = qcsg_sema::check_file(name, source, &CheckOptions::default(), &FsLoader);
    assert!(!analysis.has_errors(), "{name} has errors");
    let evaluation = evaluate(&analysis, &EvalOptions::default());
    assert!(!evaluation.has_errors(), "{name} fails to evaluate");
    let mut dag = evaluation.dag;
    Scene::from_dag(&mut dag, &DnfOptions::default()).unwrap_or_else(|_| panic!("{name}: no DNF"))
}

fn camera(case: &FlushPair, placement: Placement) -> Camera {
    let size = ImageSize::new(WIDTH, HEIGHT).unwrap();
    let eye = case.centre + case.distance * case.towards_eye.normalize();
    Camera::look_at(
        placement.point(eye),
        placement.point(case.centre),
        Projection::Perspective,
        (15f64).to_radians().tan(),
        size,
    )
    .unwrap()
}

/// The pixels of `reference` within one pixel of a silhouette, crease or depth step, and its
/// depth range.
fn band(reference: &Frame) -> (Vec<bool>, f64) {
    let (w, h) = (WIDTH as i64, HEIGHT as i64);
    let finite = reference.depth.iter().copied().filter(|d| d.is_finite());
    let (lo, hi) = finite.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), d| {
        (lo.min(d), hi.max(d))
    });
    let range = if hi > lo { hi - lo } else { 1.0 };
    let at = |x: i64, y: i64| (y * w + x) as usize;
    let differs = |a: usize, b: usize| {
        let (da, db) = (reference.depth[a], reference.depth[b]);
        da.is_finite() != db.is_finite()
            || (da.is_finite()
                && (reference.ids[a].quadric != reference.ids[b].quadric
                    || (da - db).abs() > DEPTH_STEP * range))
    };
    let mut banded = vec![false; reference.depth.len()];
    for y in 0..h {
        for x in 0..w {
            banded[at(x, y)] = (-1..=1).any(|dy| {
                (-1..=1).any(|dx| {
                    let (nx, ny) = (x + dx, y + dy);
                    (0..w).contains(&nx) && (0..h).contains(&ny) && differs(at(x, y), at(nx, ny))
                })
            });
        }
    }
    (banded, range)
}

/// The share of pixels outside the clean frame's band where `frame` agrees with it in coverage
/// and depth, and how many were compared.
fn agreement(clean: &Frame, frame: &Frame) -> (f64, usize) {
    let (banded, range) = band(clean);
    let (mut compared, mut agree) = (0usize, 0usize);
    for (i, &in_band) in banded.iter().enumerate() {
        if in_band {
            continue;
        }
        compared += 1;
        let (a, b) = (clean.depth[i], frame.depth[i]);
        let same = if a.is_finite() && b.is_finite() {
            (a - b).abs() <= DEPTH_TOLERANCE * range
        } else {
            a.is_finite() == b.is_finite()
        };
        agree += usize::from(same);
    }
    (agree as f64 / compared.max(1) as f64, compared)
}

#[test]
fn splats_of_flush_scenes_show_their_clean_twins() {
    let renderer = SplatRenderer::new(AdapterRequirement::Any).unwrap_or_else(|error| {
        panic!(
            "{error}\nThe test needs a GPU adapter; a software one is enough (Debian: apt-get \
             install mesa-vulkan-drivers libvulkan1, or libegl1 libgl1-mesa-dri for OpenGL)."
        )
    });
    let adapter = renderer.adapter();
    eprintln!("adapter: {adapter}");
    // Run for one backend, it must be on that backend (CI runs it once per backend).
    if let Ok(wanted) = std::env::var("WGPU_BACKEND")
        && !wanted.contains(',')
    {
        let wanted = if wanted.eq_ignore_ascii_case("opengl") {
            "gl"
        } else {
            &wanted
        };
        assert!(
            adapter.backend.eq_ignore_ascii_case(wanted),
            "WGPU_BACKEND={wanted} but the adapter is {adapter}"
        );
    }
    let size = ImageSize::new(WIDTH, HEIGHT).unwrap();
    let options = RenderOptions::default();
    let mut failures = Vec::new();
    for case in FLUSH_PAIRS {
        for placement in Placement::ALL {
            let flush = scene(case.name, placement.wrap(case.flush));
            let clean = scene(case.name, placement.wrap(case.clean));
            let camera = camera(case, placement);
            let reference = qcsg_render::render(&clean, &camera, size, &options, &|_| {});
            let traced = qcsg_render::render(&flush, &camera, size, &options, &|_| {});
            let radius = RADIUS_OF_DIAGONAL * 2.0 * flush.bounds().half_diagonal();
            let radius = if radius.is_finite() && radius > 0.0 {
                radius
            } else {
                1.0
            };
            let prepared = PreparedScene::new(&flush, radius)
                .unwrap_or_else(|e| panic!("{} {placement:?}: {e}", case.name));
            let splats = renderer
                .render_prepared(&flush, &prepared, &camera, size, &options)
                .unwrap_or_else(|e| panic!("{} {placement:?}: {e}", case.name));
            for (what, frame) in [("splats", &splats), ("ray tracer", &traced)] {
                let (share, compared) = agreement(&reference, frame);
                let line = format!(
                    "{} {placement:?}, {what}: {share:.5} of {compared} pixels agree with the \
                     clean scene ({} shown)",
                    case.name,
                    reference.hit_count()
                );
                eprintln!("{line}");
                if share < REQUIRED_AGREEMENT {
                    failures.push(line);
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
