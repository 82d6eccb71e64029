//! DNF construction for scenes of many primitive instances built through the builder API:
//!
//! - `union_1000`: a union of 1,000 translated (and partly rotated) spheres and cylinders;
//! - `intersection_of_unions_500`: two offset grids of 500 spheres, intersected (only
//!   neighbouring pairs of the 250,000 overlap);
//! - `block_minus_row_50`: a block minus a row of 50 cubes that pass through it;
//! - `block_minus_pockets_50`: a block minus a row of 50 cubes inside it (cavities);
//! - `block_minus_jittered_grid_1000_region`: a block minus a jittered 10×10×10 grid of cubes
//!   (3^1000 terms globally), restricted to a region around one hole.
//!
//! Before timing, each scene's per-pass term / literal / quadric counts are printed.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use qcsg_csg::{Aabb, Dag, DnfOptions, NodeId, Source, build_dnf};
use qcsg_quadric::{DMat4, DVec3, Quadric};

fn cube(dag: &mut Dag, size: DVec3) -> NodeId {
    let centre = 0.5 * size;
    let slabs: Vec<_> = (0..3)
        .map(|axis| {
            let mut normal = DVec3::ZERO;
            normal[axis] = 1.0;
            let q = Quadric::slab(centre, normal, 0.5 * size[axis]).unwrap();
            dag.leaf(q, Source::default()).into()
        })
        .collect();
    let node = dag.intersection(slabs, Source::default());
    dag.bounded(node, Aabb::new(DVec3::ZERO, size))
}

fn sphere(dag: &mut Dag, radius: f64) -> NodeId {
    let q = Quadric::sphere(DVec3::ZERO, radius).unwrap();
    dag.bounded_leaf(
        q,
        Source::default(),
        Aabb::from_centre_half(DVec3::ZERO, DVec3::splat(radius)),
    )
}

fn cylinder(dag: &mut Dag, radius: f64, height: f64) -> NodeId {
    let side = Quadric::cylinder(DVec3::ZERO, DVec3::Z, radius).unwrap();
    let caps = Quadric::slab(DVec3::new(0.0, 0.0, 0.5 * height), DVec3::Z, 0.5 * height).unwrap();
    let side = dag.leaf(side, Source::default());
    let caps = dag.leaf(caps, Source::default());
    let node = dag.intersection([side.into(), caps.into()], Source::default());
    dag.bounded(
        node,
        Aabb::new(
            DVec3::new(-radius, -radius, 0.0),
            DVec3::new(radius, radius, height),
        ),
    )
}

fn union_1000() -> Dag {
    let mut dag = Dag::new();
    let mut parts = Vec::new();
    for i in 0..1000 {
        let at = DVec3::new((i % 10) as f64, ((i / 10) % 10) as f64, (i / 100) as f64) * 3.0;
        let edge = if i % 2 == 0 {
            let s = sphere(&mut dag, 1.0 + 0.01 * (i % 5) as f64);
            dag.translated(s.into(), at).unwrap()
        } else {
            let c = cylinder(&mut dag, 0.8, 2.0);
            let m = DMat4::from_translation(at) * DMat4::from_rotation_x(0.1 * (i % 7) as f64);
            dag.edge(c, &m).unwrap()
        };
        parts.push(edge);
    }
    let u = dag.union(parts, Source::default());
    dag.set_root(u.into());
    dag
}

/// Two offset grids of 500 spheres each, intersected: the product has 250,000 pairs, of
/// which only neighbours overlap.
fn intersection_of_unions_500() -> Dag {
    let mut dag = Dag::new();
    let mut unions = Vec::new();
    for shift in [0.0, 0.9] {
        let mut parts = Vec::new();
        for i in 0..500 {
            let at = DVec3::new((i % 10) as f64, ((i / 10) % 10) as f64, (i / 100) as f64) * 3.0;
            let s = sphere(&mut dag, 1.0);
            parts.push(dag.translated(s.into(), at + shift).unwrap());
        }
        unions.push(dag.union(parts, Source::default()).into());
    }
    let i = dag.intersection(unions, Source::default());
    dag.set_root(i.into());
    dag
}

fn block_minus_row(through: bool) -> Dag {
    let mut dag = Dag::new();
    let block = cube(&mut dag, DVec3::new(101.0, 4.0, 4.0));
    let mut children = vec![block.into()];
    for i in 0..50 {
        let (size, at) = if through {
            (
                DVec3::new(1.0, 6.0, 2.0),
                DVec3::new(1.0 + 2.0 * i as f64, -1.0, 1.0),
            )
        } else {
            (
                DVec3::new(1.0, 2.0, 2.0),
                DVec3::new(1.0 + 2.0 * i as f64, 1.0, 1.0),
            )
        };
        let c = cube(&mut dag, size);
        children.push(dag.translated(c.into(), at).unwrap());
    }
    let d = dag.difference(children, Source::default());
    dag.set_root(d.into());
    dag
}

fn block_minus_jittered_grid() -> Dag {
    let mut dag = Dag::new();
    let block = cube(&mut dag, DVec3::splat(20.0));
    let mut children = vec![block.into()];
    for i in 0..1000 {
        let c = cube(&mut dag, DVec3::splat(0.5));
        let cell = DVec3::new((i % 10) as f64, ((i / 10) % 10) as f64, (i / 100) as f64);
        let wobble = DVec3::new((i % 7) as f64, (i % 11) as f64, (i % 13) as f64) * 0.01;
        children.push(
            dag.translated(c.into(), cell * 2.0 + 0.75 + wobble)
                .unwrap(),
        );
    }
    let d = dag.difference(children, Source::default());
    dag.set_root(d.into());
    dag
}

fn report(name: &str, dag: &Dag, options: &DnfOptions) {
    match build_dnf(dag, options) {
        Ok(dnf) => eprintln!("== {name} ({} DAG nodes)\n{}\n", dag.len(), dnf.stats),
        Err(errors) => eprintln!("== {name}: {}", errors[0].message),
    }
}

fn benches(c: &mut Criterion) {
    let region = Aabb::new(DVec3::splat(0.25), DVec3::splat(1.75));
    let scenes: Vec<(&str, Dag, DnfOptions)> = vec![
        ("union_1000", union_1000(), DnfOptions::default()),
        (
            "intersection_of_unions_500",
            intersection_of_unions_500(),
            DnfOptions::default(),
        ),
        (
            "block_minus_row_50",
            block_minus_row(true),
            DnfOptions::default(),
        ),
        (
            "block_minus_pockets_50",
            block_minus_row(false),
            DnfOptions::default(),
        ),
        (
            "block_minus_jittered_grid_1000_region",
            block_minus_jittered_grid(),
            DnfOptions {
                region: Some(region),
                ..DnfOptions::default()
            },
        ),
    ];
    for (name, dag, options) in &scenes {
        report(name, dag, options);
    }
    let mut group = c.benchmark_group("dnf");
    group.sample_size(20);
    for (name, dag, options) in &scenes {
        group.bench_function(*name, |b| {
            b.iter(|| build_dnf(black_box(dag), black_box(options)))
        });
    }
    group.finish();
}

criterion_group!(dnf, benches);
criterion_main!(dnf);
