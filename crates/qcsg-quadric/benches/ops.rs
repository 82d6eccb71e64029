//! Micro-benchmarks mirroring paper 000 Table 1: quadric value, normal, heightfield value,
//! distortion, distortion bounds over a rectangle, line intersection, conservative distance.
//!
//! Each benchmark runs one operation over a batch of 1024 precomputed inputs on an ellipsoid in
//! general position (rotated, translated), so per-op time = reported time / 1024 (criterion's
//! throughput line shows the rate directly).

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use qcsg_quadric::{DMat4, DVec3, Heightfield, Quadric};
use qcsg_testkit::Rng;

const BATCH: usize = 1024;

/// A point uniform in the cube of half-side `extent` about `centre`.
fn point(rng: &mut Rng, centre: DVec3, extent: f64) -> DVec3 {
    centre + rng.in_box(DVec3::splat(-extent), DVec3::splat(extent))
}

struct Inputs {
    quadric: Quadric,
    heightfield: Heightfield,
    points: Vec<DVec3>,
    directions: Vec<DVec3>,
    plane: Vec<(f64, f64)>,
}

fn inputs() -> Inputs {
    let ellipsoid = Quadric::ellipsoid(DVec3::ZERO, DVec3::new(1.0, 2.0, 3.0)).expect("valid");
    let m = DMat4::from_translation(DVec3::new(10.0, -5.0, 3.0))
        * DMat4::from_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), 0.7);
    let quadric = ellipsoid.transformed(&m).expect("invertible");
    let heightfield = quadric.frame().heightfield(2);
    let mut rng = Rng::new(42);
    let centre = quadric.origin();
    let points = (0..BATCH).map(|_| point(&mut rng, centre, 4.0)).collect();
    let directions = (0..BATCH)
        .map(|_| point(&mut rng, DVec3::ZERO, 1.0).normalize_or(DVec3::X))
        .collect();
    let plane = (0..BATCH)
        .map(|_| (rng.range(-0.5, 0.5), rng.range(-1.0, 1.0)))
        .collect();
    Inputs {
        quadric,
        heightfield,
        points,
        directions,
        plane,
    }
}

fn table_1(c: &mut Criterion) {
    let inputs = inputs();
    let q = &inputs.quadric;
    let hf = &inputs.heightfield;
    let mut group = c.benchmark_group("table1");
    group.throughput(Throughput::Elements(BATCH as u64));

    group.bench_function("value Q(x)", |b| {
        b.iter(|| {
            let mut sum = 0.0;
            for p in &inputs.points {
                sum += q.value(black_box(*p));
            }
            sum
        })
    });
    group.bench_function("normal N(x)", |b| {
        b.iter(|| {
            let mut sum = DVec3::ZERO;
            for p in &inputs.points {
                sum += q.normal(black_box(*p)).unwrap_or(DVec3::ZERO);
            }
            sum
        })
    });
    group.bench_function("heightfield h(x,y)", |b| {
        b.iter(|| {
            let mut sum = 0.0;
            for &(x, y) in &inputs.plane {
                sum += hf.height(black_box(x), black_box(y)).unwrap_or(0.0);
            }
            sum
        })
    });
    group.bench_function("distortion delta(x,y)", |b| {
        b.iter(|| {
            let mut sum = 0.0;
            for &(x, y) in &inputs.plane {
                sum += hf.distortion(black_box(x), black_box(y)).unwrap_or(0.0);
            }
            sum
        })
    });
    group.bench_function("distortion bounds over a rectangle", |b| {
        b.iter(|| {
            let mut sum = 0.0;
            for &(x, y) in &inputs.plane {
                let x0 = black_box(x);
                let y0 = black_box(y);
                if let Some((lo, _)) = hf.distortion_bounds((x0, x0 + 0.01), (y0, y0 + 0.01)) {
                    sum += lo;
                }
            }
            sum
        })
    });
    group.bench_function("line intersection", |b| {
        b.iter(|| {
            let mut sum = 0.0;
            for (p, v) in inputs.points.iter().zip(&inputs.directions) {
                if let Some(t) = q
                    .intersect_line(black_box(*p), black_box(*v))
                    .first_at_or_after(0.0)
                {
                    sum += t;
                }
            }
            sum
        })
    });
    group.bench_function("conservative distance d(x)", |b| {
        b.iter(|| {
            let mut sum = 0.0;
            for p in &inputs.points {
                sum += q.conservative_distance(black_box(*p));
            }
            sum
        })
    });
    group.finish();
}

criterion_group!(benches, table_1);
criterion_main!(benches);
