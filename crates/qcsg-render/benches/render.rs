//! Render time of the CPU ray tracer: scenes of about 3 and 30 quadrics, of 4,096 balls and of
//! a plate drilled with 1,024 holes at 800×600 and 1920×1080, on 1 and 2 threads. A plain
//! timing binary (best of a few runs), because one render takes long enough to time on its own:
//! `cargo bench -p qcsg-render --bench render`.

#[path = "../tests/common/mod.rs"]
mod common;

use std::time::Instant;

use qcsg_csg::{Aabb, Dag, DnfOptions, Edge, Source};
use qcsg_quadric::{DVec3, Quadric};
use qcsg_render::{Camera, ImageSize, Projection, RenderOptions, Scene, View, render};

fn sphere(dag: &mut Dag, centre: DVec3, radius: f64) -> Edge {
    let r = DVec3::splat(radius);
    dag.bounded_leaf(
        Quadric::sphere(centre, radius).expect("sphere"),
        Source::default(),
        Aabb::new(centre - r, centre + r),
    )
    .into()
}

/// A ball minus a smaller ball, cut by a half-space: 3 quadrics.
fn small_scene() -> Scene {
    let mut dag = Dag::new();
    let ball = sphere(&mut dag, DVec3::ZERO, 2.0);
    let bite = sphere(&mut dag, DVec3::new(1.0, -1.0, 1.0), 1.2);
    let plane = dag.leaf(
        Quadric::half_space(DVec3::new(0.0, 0.0, 1.2), DVec3::Z).expect("plane"),
        Source::default(),
    );
    let carved = dag.difference([ball, bite], Source::default());
    let solid = dag.intersection([carved.into(), plane.into()], Source::default());
    dag.set_root(solid.into());
    Scene::from_dag(&mut dag, &DnfOptions::default()).expect("scene")
}

/// A drilled block (3 slabs minus 3 cylinders) with a 6×4 grid of balls on top: 30 quadrics.
fn thirty_quadric_scene() -> Scene {
    let mut dag = Dag::new();
    let slabs: Vec<Edge> = [DVec3::X, DVec3::Y, DVec3::Z]
        .into_iter()
        .zip([3.0, 2.0, 1.0])
        .map(|(n, half)| {
            dag.leaf(
                Quadric::slab(DVec3::ZERO, n, half).expect("slab"),
                Source::default(),
            )
            .into()
        })
        .collect();
    let block = dag.intersection(slabs, Source::default());
    let block = dag.bounded(
        block,
        Aabb::new(DVec3::new(-3.0, -2.0, -1.0), DVec3::new(3.0, 2.0, 1.0)),
    );
    let holes: Vec<Edge> = [DVec3::X, DVec3::Y, DVec3::Z]
        .into_iter()
        .map(|axis| {
            dag.leaf(
                Quadric::cylinder(DVec3::ZERO, axis, 0.6).expect("cylinder"),
                Source::default(),
            )
            .into()
        })
        .collect();
    let mut parts = vec![block.into()];
    parts.extend(holes);
    let drilled = dag.difference(parts, Source::default());
    let mut pieces = vec![drilled.into()];
    for i in 0..6 {
        for j in 0..4 {
            let centre = DVec3::new(-2.5 + f64::from(i), -1.5 + f64::from(j), 1.2);
            pieces.push(sphere(&mut dag, centre, 0.45));
        }
    }
    let root = dag.union(pieces, Source::default());
    dag.set_root(root.into());
    Scene::from_dag(&mut dag, &DnfOptions::default()).expect("scene")
}

/// A 64×64 grid of separate balls: 4,096 quadrics and terms. Each ray meets a handful of their
/// boxes; the term-box index finds those without testing all of them.
fn many_balls_scene() -> Scene {
    let mut dag = Dag::new();
    let mut balls = Vec::new();
    for i in 0..64 {
        for j in 0..64 {
            let centre = DVec3::new(f64::from(i), f64::from(j), 0.0);
            balls.push(sphere(&mut dag, centre, 0.4));
        }
    }
    let root = dag.union(balls, Source::default());
    dag.set_root(root.into());
    Scene::from_dag(&mut dag, &DnfOptions::default()).expect("scene")
}

/// A plate drilled with a 32×32 grid of holes: one term of 1,027 literals. Each ray meets a
/// handful of holes; the literal index of the term finds those without intersecting all.
fn drilled_plate_scene() -> Scene {
    let mut dag = Dag::new();
    let plate = common::drilled_plate(&mut dag, 32);
    dag.set_root(plate);
    Scene::from_dag(&mut dag, &DnfOptions::default()).expect("scene")
}

fn main() {
    // `cargo test --benches` runs bench binaries with `--bench` absent: keep that quick.
    if !std::env::args().any(|a| a == "--bench") {
        return;
    }
    let scenes = [
        ("3 quadrics", small_scene()),
        ("30 quadrics", thirty_quadric_scene()),
        ("4,096 balls", many_balls_scene()),
        ("1,024 holes", drilled_plate_scene()),
    ];
    println!("| scene | quadrics | terms | size | threads | seconds (best of 3) |");
    println!("| --- | --- | --- | --- | --- | --- |");
    for (name, scene) in &scenes {
        let terms = scene.solid.as_ref().map_or(0, |s| s.dnf().terms.len());
        for (w, h) in [(800, 600), (1920, 1080)] {
            let size = ImageSize::new(w, h).expect("size");
            let camera = Camera::fit(&View::Iso, Projection::Perspective, &scene.bounds(), size)
                .expect("camera");
            for threads in [1, 2] {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .expect("pool");
                let best = (0..3)
                    .map(|_| {
                        let start = Instant::now();
                        let frame = pool.install(|| {
                            render(scene, &camera, size, &RenderOptions::default(), &|_| {})
                        });
                        std::hint::black_box(frame);
                        start.elapsed().as_secs_f64()
                    })
                    .fold(f64::INFINITY, f64::min);
                println!(
                    "| {name} | {} | {terms} | {w}×{h} | {threads} | {best:.3} |",
                    scene.quadric_count()
                );
            }
        }
    }
}
