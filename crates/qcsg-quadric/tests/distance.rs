//! The conservative distance (eqs. 10-12) against an independent true distance.

mod common;

use common::{Rng, catalogue, points_around, true_distance};
use qcsg_quadric::{DVec3, Quadric};

/// Slack for the oracle's own rounding: relative `1e-9` plus `1e-12` of the feature size.
fn allowed(truth: f64, size: f64) -> f64 {
    truth * (1.0 + 1e-9) + 1e-12 * size
}

fn check_lower_bound(
    name: &str,
    quadric: &Quadric,
    size: f64,
    rng: &mut Rng,
    count: usize,
) -> usize {
    let mut checked = 0;
    for p in points_around(rng, quadric, size, count) {
        let d = quadric.conservative_distance(p);
        assert!(!d.is_nan(), "{name}: NaN at {p}");
        let value = quadric.value(p);
        assert!(
            d == 0.0 || d.signum() == value.signum(),
            "{name}: sign of d = {d} disagrees with Q = {value} at {p}"
        );
        let truth = true_distance(quadric, p);
        assert!(
            d.abs() <= allowed(truth, size),
            "{name}: |d| = {} exceeds the true distance {truth} at {p}",
            d.abs()
        );
        checked += 1;
    }
    checked
}

#[test]
fn lower_bound_on_every_kind() {
    let mut rng = Rng::new(0x5eed_0001);
    let mut total = 0;
    for case in catalogue() {
        total += check_lower_bound(case.name, &case.quadric, case.size, &mut rng, 120);
    }
    assert!(total >= 2000, "{total}");
}

/// The complement and a re-expansion about another origin keep their own cached forms (the
/// short way for axis-aligned shapes among them) consistent with their coefficients.
#[test]
fn lower_bound_on_complements_and_moved_origins() {
    let mut rng = Rng::new(0x5eed_0003);
    let mut total = 0;
    for case in catalogue() {
        let complement = case.quadric.negated();
        total += check_lower_bound(case.name, &complement, case.size, &mut rng, 40);
        let shift = rng.direction() * case.size * 0.25;
        let moved = case.quadric.with_origin(case.quadric.origin() + shift);
        total += check_lower_bound(case.name, &moved, case.size, &mut rng, 40);
    }
    assert!(total >= 1500, "{total}");
}

#[test]
fn lower_bound_on_transformed_kinds() {
    let mut rng = Rng::new(0x5eed_0002);
    let mut total = 0;
    for case in catalogue() {
        for _ in 0..2 {
            let m = rng.similarity(10.0, 100.0);
            let Some(q) = case.quadric.transformed(&m) else {
                panic!("{}: transform failed", case.name)
            };
            let scale = m.x_axis.truncate().length();
            total += check_lower_bound(case.name, &q, case.size * scale, &mut rng, 60);
        }
    }
    assert!(total >= 2000, "{total}");
}

#[test]
fn tight_near_a_sphere() {
    // Paper §3.3: the relative error vanishes towards the surface.
    let q = Quadric::sphere(DVec3::new(3.0, -2.0, 1.0), 2.0).unwrap();
    let mut rng = Rng::new(7);
    for _ in 0..500 {
        let dir = rng.direction();
        let gap = 2.0 * 10f64.powf(rng.range(-9.0, -3.0));
        for sign in [-1.0, 1.0] {
            let p = DVec3::new(3.0, -2.0, 1.0) + dir * (2.0 + sign * gap);
            let d = q.conservative_distance(p);
            assert!(d * sign > 0.0);
            assert!(d.abs() <= gap * (1.0 + 1e-6), "{d} vs {gap}");
            assert!(d.abs() >= gap * (1.0 - 2e-3), "{d} vs {gap}");
        }
    }
}

#[test]
fn exact_for_planes() {
    let q = Quadric::half_space(DVec3::new(1e6, 0.0, 0.0), DVec3::new(1.0, 2.0, 2.0)).unwrap();
    let n = DVec3::new(1.0, 2.0, 2.0) / 3.0;
    for s in [-1e3, -1.0, -1e-6, 1e-6, 1.0, 1e3] {
        let p = DVec3::new(1e6, 0.0, 0.0) - n.cross(DVec3::Z) * 3.0 + n * s;
        let d = q.conservative_distance(p);
        // Absolute accuracy is limited by the world coordinates: 1e6 ε ≈ 2e-10.
        assert!((d - s).abs() <= 1e-9 * s.abs() + 1e-9, "{d} vs {s}");
        // p itself carries rounding of about 1e6 ε ≈ 1e-10.
        assert!(d.abs() <= s.abs() + 1e-9);
    }
}

#[test]
fn tight_near_smooth_surfaces() {
    // Paper §3.3: the relative error tends to zero towards the surface. At an offset of 1e-6 of
    // the feature size along the normal, |d| is within 1e-3 of the offset on every kind whose
    // gradient does not vanish on the surface.
    use qcsg_quadric::QuadricKind as K;
    let mut rng = Rng::new(0x7167);
    for case in catalogue() {
        if matches!(
            case.kind,
            K::Point | K::Line | K::CoincidentPlanes | K::Empty | K::AllSpace
        ) {
            continue;
        }
        let q = &case.quadric;
        let mut checked = 0;
        while checked < 50 {
            let start = q.origin() + rng.direction() * case.size * rng.range(0.0, 0.5);
            let dir = rng.direction();
            // Near the origin: a line almost along a slab meets it thousands of sizes away,
            // where the rounding of `Q` exceeds its value at the offset below.
            let Some(t) = (q.intersect_line(start, dir).first_at_or_after(0.0))
                .filter(|&t| t <= 10.0 * case.size)
            else {
                continue;
            };
            let surface = start + t * dir;
            let Some(normal) = q.normal(surface) else {
                continue;
            };
            // Stay away from the singular lines of cones and intersecting planes.
            if q.gradient(surface).length() < 1e-3 * q.matrix_norm().max(1.0) * case.size {
                continue;
            }
            let offset = 1e-6 * case.size;
            for sign in [-1.0, 1.0] {
                let p = surface + sign * offset * normal;
                let d = q.conservative_distance(p);
                assert!(d * sign > 0.0, "{}: sign", case.name);
                assert!(
                    d.abs() >= offset * (1.0 - 1e-3) && d.abs() <= offset * (1.0 + 1e-6),
                    "{}: |d| = {} for an offset of {offset}",
                    case.name,
                    d.abs()
                );
            }
            checked += 1;
        }
    }
}

#[test]
fn the_oracle_is_exact_on_spheres_and_cylinders() {
    // The independent true distance agrees with closed forms, so the lower-bound checks above
    // compare against the real distance.
    let mut rng = Rng::new(0x0);
    let centre = DVec3::new(1.0, -2.0, 0.5);
    let sphere = Quadric::sphere(centre, 1.5).unwrap();
    let cylinder = Quadric::cylinder(centre, DVec3::Z, 0.5).unwrap();
    for _ in 0..100 {
        let p = centre + rng.direction() * rng.range(0.0, 4.0);
        let exact = ((p - centre).length() - 1.5).abs();
        let oracle = true_distance(&sphere, p);
        assert!(
            (oracle - exact).abs() <= 1e-9 * (1.0 + exact),
            "{oracle} vs {exact}"
        );
        let radial = (p - centre).truncate().length();
        let exact = (radial - 0.5).abs();
        let oracle = true_distance(&cylinder, p);
        assert!(
            (oracle - exact).abs() <= 1e-9 * (1.0 + exact),
            "{oracle} vs {exact}"
        );
    }
}
