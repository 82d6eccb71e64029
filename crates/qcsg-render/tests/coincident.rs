//! Flush faces: a scene whose parts share a surface (a cutter flush with a face, a ball minus
//! a turned copy of itself) must render as the same solid written without shared surfaces.
//!
//! Each case is a pair of sources, flush and clean (`qcsg_testkit::FLUSH_PAIRS`, shared with
//! the splats' and the sampler's tests), rendered by the ray tracer with one
//! explicit camera. Outside a 1-pixel band around the clean image's edges (silhouettes and
//! creases, where a sub-pixel shift of an edge changes a pixel), at least 99.9 % of the pixels
//! must agree: both miss, or both hit at the same depth with the same colour. Every case is
//! also checked moved by 10⁵ and scaled by 10⁻³, where rounding in the transforms differs, and
//! the flush scene is rendered twice: as compiled, and with the pruning of terms emptied by a
//! coincident pair turned off, so that the ray tracer's own classification is tested too.
//! (What these cases measured before the ray tracer read literals through their surfaces is in
//! `docs/compiler.md`, "Coincident surfaces".)

use qcsg_csg::dnf::Pruning;
use qcsg_driver::{Options, Stage, compile};
use qcsg_quadric::DVec3;
use qcsg_render::{Camera, Frame, ImageSize, Projection, RenderOptions, Scene, render};
use qcsg_sema::FsLoader;
use qcsg_testkit::{FLUSH_PAIRS, FlushPair};

/// The least share of pixels outside the edge band that must agree.
const MIN_AGREEMENT: f64 = 0.999;

const WIDTH: u32 = 200;
const HEIGHT: u32 = 150;

/// How a case is placed: as written, moved far from the origin, or scaled down.
#[derive(Clone, Copy, Debug)]
enum Placement {
    AsWritten,
    Moved,
    Scaled,
}

impl Placement {
    const ALL: [Placement; 3] = [Self::AsWritten, Self::Moved, Self::Scaled];
    const OFFSET: f64 = 1e5;
    const SCALE: f64 = 1e-3;

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
            Self::Moved => p + DVec3::splat(Self::OFFSET),
            Self::Scaled => p * Self::SCALE,
        }
    }
}

fn scene(source: &str, pruning: Pruning) -> Scene {
    let mut options = Options::default();
    options.dnf.pruning = pruning;
    let compilation = compile(
        "coincident.qcsg",
        source.to_string(),
        &options,
        &FsLoader,
        Stage::Dnf,
    );
    assert!(
        !compilation.has_errors(),
        "{source}: {:?}",
        compilation.analysis.diagnostics
    );
    let layers = compilation.layers.expect("layers");
    Scene::from_layers(layers)
}

/// A camera looking at `centre` from the direction `towards_eye`, `distance` away.
fn camera(centre: DVec3, towards_eye: DVec3, distance: f64, placement: Placement) -> Camera {
    let size = ImageSize::new(WIDTH, HEIGHT).unwrap();
    let eye = centre + distance * towards_eye.normalize();
    Camera::look_at(
        placement.point(eye),
        placement.point(centre),
        Projection::Perspective,
        (15f64).to_radians().tan(),
        size,
    )
    .unwrap()
}

fn frame(scene: &Scene, camera: &Camera) -> Frame {
    let size = ImageSize::new(WIDTH, HEIGHT).unwrap();
    render(scene, camera, size, &RenderOptions::default(), &|_| {})
}

/// Whether two pixels show the same thing: both nothing, or the same depth and colour.
fn agree(a: &Frame, b: &Frame, i: usize) -> bool {
    let (da, db) = (a.depth[i], b.depth[i]);
    if da.is_infinite() || db.is_infinite() {
        return da.is_infinite() && db.is_infinite();
    }
    let depth_ok = (da - db).abs() <= 1e-6 * da.abs().max(db.abs());
    let colour_ok = (0..3).all(|c| a.rgb[3 * i + c].abs_diff(b.rgb[3 * i + c]) <= 2);
    depth_ok && colour_ok
}

/// The pixels within one pixel of an edge of `frame`: where a neighbour shows another quadric,
/// or a miss beside a hit.
fn edge_band(frame: &Frame) -> Vec<bool> {
    let (w, h) = (WIDTH as i64, HEIGHT as i64);
    let id = |x: i64, y: i64| frame.ids[(y * w + x) as usize].quadric;
    let hit = |x: i64, y: i64| frame.depth[(y * w + x) as usize].is_finite();
    let mut edge = vec![false; frame.ids.len()];
    for y in 0..h {
        for x in 0..w {
            let differs = [(1, 0), (0, 1)].iter().any(|&(dx, dy)| {
                let (nx, ny) = (x + dx, y + dy);
                nx < w && ny < h && (id(x, y) != id(nx, ny) || hit(x, y) != hit(nx, ny))
            });
            if differs {
                edge[(y * w + x) as usize] = true;
                edge[(y * w + (x + 1).min(w - 1)) as usize] = true;
                edge[((y + 1).min(h - 1) * w + x) as usize] = true;
            }
        }
    }
    let mut band = edge.clone();
    for y in 0..h {
        for x in 0..w {
            if !edge[(y * w + x) as usize] {
                continue;
            }
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let (nx, ny) = (x + dx, y + dy);
                    if (0..w).contains(&nx) && (0..h).contains(&ny) {
                        band[(ny * w + nx) as usize] = true;
                    }
                }
            }
        }
    }
    band
}

/// The share of pixels outside the clean image's edge band where the two frames disagree.
fn mismatch(flush: &Frame, clean: &Frame) -> (f64, usize, usize) {
    let band = edge_band(clean);
    let mut counted = 0;
    let mut different = 0;
    for (i, &in_band) in band.iter().enumerate() {
        if in_band {
            continue;
        }
        counted += 1;
        if !agree(flush, clean, i) {
            different += 1;
        }
    }
    (different as f64 / counted.max(1) as f64, different, counted)
}

/// Renders one pair at every placement, flush both pruned and unpruned; the failures.
fn check(case: &FlushPair) -> Vec<String> {
    let unpruned = Pruning::without("final_coincident_pairs").unwrap();
    let mut failures = Vec::new();
    for placement in Placement::ALL {
        let camera = camera(case.centre, case.towards_eye, case.distance, placement);
        let clean = frame(&scene(&placement.wrap(case.clean), Pruning::all()), &camera);
        for (pruning, label) in [(Pruning::all(), "pruned"), (unpruned, "unpruned")] {
            let flush = frame(&scene(&placement.wrap(case.flush), pruning), &camera);
            let (share, different, counted) = mismatch(&flush, &clean);
            eprintln!(
                "{} {placement:?} {label}: {different} of {counted} pixels differ ({:.3} %), \
                 clean shows {} hits",
                case.name,
                100.0 * share,
                clean.hit_count()
            );
            if 1.0 - share < MIN_AGREEMENT {
                failures.push(format!(
                    "{} {placement:?} {label}: {:.3} % differ",
                    case.name,
                    100.0 * share
                ));
            }
        }
    }
    failures
}

#[test]
fn flush_scenes_render_as_their_clean_twins() {
    let failures: Vec<String> = FLUSH_PAIRS.iter().flat_map(check).collect();
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
