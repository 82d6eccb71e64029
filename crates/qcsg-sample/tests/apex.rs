//! The apex ring ([`qcsg_sample::apex`]): on random elliptic cones, turned and moved, every
//! point of either nappe near the apex lies within reach of a ring sample that faces the same
//! side, and the ring's points lie on the cone.

mod common;

use common::Rng;
use qcsg_quadric::{DMat4, DVec3, Quadric};
use qcsg_sample::apex::ring;

#[test]
fn a_ring_covers_every_point_near_the_apex() {
    let mut rng = Rng::new(11);
    let mut checked = 0;
    for _ in 0..200 {
        // x²/p² + y²/q² − z² ≤ 0: half-angles from very narrow to very wide, ellipticity to 1:50.
        let (p, q) = (rng.range(0.02, 5.0), rng.range(0.02, 5.0));
        let cone = Quadric::new(
            DVec3::ZERO,
            [
                1.0 / (p * p),
                1.0 / (q * q),
                -1.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
            ],
        )
        .expect("finite");
        let turn = DMat4::from_axis_angle(rng.direction(), rng.range(0.0, 3.0));
        let moved = DMat4::from_translation(rng.direction() * rng.range(0.0, 100.0)) * turn;
        let cone = cone.transformed(&moved).expect("invertible");
        let apex = moved.transform_point3(DVec3::ZERO);
        let along = rng.range(0.01, 1.0);
        let reach = 1e-3 * along;
        let Some(samples) = ring(&cone, along) else {
            panic!("no ring for the cone with semi-axes {p} and {q}");
        };
        for (s, n) in &samples {
            let g = cone.gradient(*s);
            let off = cone.value(*s).abs() / g.length();
            assert!(off <= 1e-12 * along, "ring point {off} off the cone");
            assert!((n.length() - 1.0).abs() < 1e-12);
        }
        for _ in 0..50 {
            // A point of the cone within `reach` of the apex, on a random ruling.
            let phi = rng.range(0.0, std::f64::consts::TAU);
            let nappe = if rng.unit() < 0.5 { 1.0 } else { -1.0 };
            let local = DVec3::new(p * phi.cos(), q * phi.sin(), nappe);
            let point = moved.transform_point3(local.normalize() * rng.range(1e-6, 1.0) * reach);
            let Some(normal) = cone.normal(point) else {
                continue;
            };
            let covered = samples
                .iter()
                .any(|(s, n)| (*s - point).length() <= along + reach && n.dot(normal) > 0.0);
            assert!(
                covered,
                "semi-axes {p}, {q}: the point at {} from the apex, nappe {nappe}, φ = {phi}, \
                 faces no ring sample",
                (point - apex).length()
            );
            checked += 1;
        }
    }
    assert!(checked > 9_000);
}
