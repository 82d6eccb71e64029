//! Golden images: small scenes rendered and compared with the PNGs committed under the
//! workspace's `tests/golden/`, within a tolerance (mean difference and a count of pixels that
//! differ visibly). `QCSG_BLESS=1 cargo test -p qcsg-render --test golden` rewrites them.

use std::path::PathBuf;

use qcsg_csg::{Aabb, Dag, DnfOptions, Edge, Source};
use qcsg_quadric::{DVec3, Quadric};
use qcsg_render::{Camera, ImageSize, Projection, RenderOptions, Scene, View, render};

/// The largest mean absolute difference per channel, in 8-bit steps.
const MAX_MEAN_DIFFERENCE: f64 = 2.0;
/// A pixel differs visibly when a channel is off by more than this.
const VISIBLE_DIFFERENCE: u8 = 24;
/// The largest share of visibly different pixels.
const MAX_DIFFERENT_SHARE: f64 = 0.01;

fn golden_path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/golden")
        .join(format!("{name}.png"))
}

fn sphere(dag: &mut Dag, centre: DVec3, radius: f64) -> Edge {
    let r = DVec3::splat(radius);
    dag.bounded_leaf(
        Quadric::sphere(centre, radius).unwrap(),
        Source::default(),
        Aabb::new(centre - r, centre + r),
    )
    .into()
}

fn cube(dag: &mut Dag, centre: DVec3, half: f64) -> Edge {
    let slabs: Vec<Edge> = [DVec3::X, DVec3::Y, DVec3::Z]
        .into_iter()
        .map(|n| {
            dag.leaf(Quadric::slab(centre, n, half).unwrap(), Source::default())
                .into()
        })
        .collect();
    let cube = dag.intersection(slabs, Source::default());
    dag.bounded(cube, Aabb::from_centre_half(centre, DVec3::splat(half)))
        .into()
}

/// A cube minus a sphere at its corner, and a blue sphere beside it.
fn cube_minus_sphere() -> Scene {
    let mut dag = Dag::new();
    let block = cube(&mut dag, DVec3::ZERO, 1.0);
    let bite = sphere(&mut dag, DVec3::new(1.0, -1.0, 1.0), 1.0);
    let carved = dag.difference([block, bite], Source::default());
    let ball = sphere(&mut dag, DVec3::new(-2.2, 0.0, 0.0), 0.8);
    let blue = dag
        .color(ball, [0.3, 0.5, 0.9, 1.0], Source::default())
        .unwrap();
    let root = dag.union([carved.into(), blue.into()], Source::default());
    dag.set_root(root.into());
    Scene::from_dag(&mut dag, &DnfOptions::default()).unwrap()
}

/// A hemisphere (sphere ∩ half-space) with a highlighted cylinder subtracted and a background
/// sphere beside it.
fn modifiers() -> Scene {
    let mut dag = Dag::new();
    let ball = sphere(&mut dag, DVec3::ZERO, 1.5);
    let below = dag.leaf(
        Quadric::half_space(DVec3::ZERO, DVec3::Z).unwrap(),
        Source::default(),
    );
    let dome = dag.intersection([ball, below.into()], Source::default());
    let rod = dag.leaf(
        Quadric::cylinder(DVec3::ZERO, DVec3::X, 0.4).unwrap(),
        Source::default(),
    );
    let limit = cube(&mut dag, DVec3::ZERO, 2.0);
    let rod = dag.intersection([rod.into(), limit], Source::default());
    let marked = dag.highlight(rod.into(), Source::default());
    let solid = dag.difference([dome.into(), marked.into()], Source::default());
    dag.set_root(solid.into());
    let ghost = sphere(&mut dag, DVec3::new(0.0, 2.5, 0.0), 0.8);
    dag.add_background(ghost);
    Scene::from_dag(&mut dag, &DnfOptions::default()).unwrap()
}

fn check(name: &str, scene: &Scene, view: View, projection: Projection) {
    let size = ImageSize::new(64, 48).unwrap();
    let camera = Camera::fit(&view, projection, &scene.bounds(), size).unwrap();
    let frame = render(scene, &camera, size, &RenderOptions::default(), &|_| {});
    let path = golden_path(name);
    if std::env::var_os("QCSG_BLESS").is_some_and(|v| v == "1") {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, qcsg_render::png::encode(&frame).unwrap()).unwrap();
        return;
    }
    let golden = image::load_from_memory(
        &std::fs::read(&path)
            .unwrap_or_else(|e| panic!("{}: {e} (QCSG_BLESS=1 writes it)", path.display())),
    )
    .unwrap()
    .to_rgb8();
    assert_eq!(
        (golden.width(), golden.height()),
        (size.width(), size.height()),
        "{name}: size"
    );
    let mut total = 0u64;
    let mut visible = 0usize;
    for (new, old) in frame.rgb.chunks(3).zip(golden.as_raw().chunks(3)) {
        let mut worst = 0u8;
        for (a, b) in new.iter().zip(old) {
            let d = a.abs_diff(*b);
            total += u64::from(d);
            worst = worst.max(d);
        }
        if worst > VISIBLE_DIFFERENCE {
            visible += 1;
        }
    }
    let mean = total as f64 / frame.rgb.len() as f64;
    let share = visible as f64 / size.pixel_count() as f64;
    assert!(
        mean <= MAX_MEAN_DIFFERENCE && share <= MAX_DIFFERENT_SHARE,
        "{name}: mean difference {mean:.2}, {visible} pixels differ visibly; if intended, \
         rerun with QCSG_BLESS=1"
    );
}

#[test]
fn golden_cube_minus_sphere_iso() {
    check(
        "cube_minus_sphere_iso",
        &cube_minus_sphere(),
        View::Iso,
        Projection::Perspective,
    );
}

#[test]
fn golden_cube_minus_sphere_front_ortho() {
    check(
        "cube_minus_sphere_front",
        &cube_minus_sphere(),
        View::Front,
        Projection::Orthographic,
    );
}

#[test]
fn golden_modifiers_iso() {
    check(
        "modifiers_iso",
        &modifiers(),
        View::Iso,
        Projection::Perspective,
    );
}

#[test]
fn golden_modifiers_top() {
    check(
        "modifiers_top",
        &modifiers(),
        View::Top,
        Projection::Orthographic,
    );
}

#[test]
fn a_changed_image_fails_the_comparison() {
    // The tolerance must not hide a real change: a moved sphere differs visibly.
    let size = ImageSize::new(64, 48).unwrap();
    let scene = cube_minus_sphere();
    let camera = Camera::fit(&View::Iso, Projection::Perspective, &scene.bounds(), size).unwrap();
    let a = render(&scene, &camera, size, &RenderOptions::default(), &|_| {});
    let moved = Camera::fit(&View::Front, Projection::Perspective, &scene.bounds(), size).unwrap();
    let b = render(&scene, &moved, size, &RenderOptions::default(), &|_| {});
    let visible = a
        .rgb
        .chunks(3)
        .zip(b.rgb.chunks(3))
        .filter(|(x, y)| {
            x.iter()
                .zip(y.iter())
                .any(|(p, q)| p.abs_diff(*q) > VISIBLE_DIFFERENCE)
        })
        .count();
    assert!(visible as f64 / size.pixel_count() as f64 > MAX_DIFFERENT_SHARE);
}
