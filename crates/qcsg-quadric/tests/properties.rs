//! Randomised properties (proptest with a fixed seed and case count, so runs are deterministic).

mod common;

use common::{Rng, catalogue, raw_value};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};
use qcsg_quadric::{
    DMat4, DVec3, HeightfieldForm, LineIntersection, Quadric, QuadricKind, symmetric_eigen,
};

fn config(cases: u32) -> Config {
    Config {
        cases,
        rng_seed: RngSeed::Fixed(0x9c5a_0001),
        failure_persistence: None,
        ..Config::default()
    }
}

fn rotation(seed: u64) -> DMat4 {
    Rng::new(seed).rotation()
}

/// Orthonormality defect and residual of a decomposition.
fn eigen_errors(a: [[f64; 3]; 3]) -> (f64, f64, f64) {
    let e = symmetric_eigen(&a);
    let mut ortho = 0.0f64;
    for i in 0..3 {
        for j in 0..3 {
            let expected = if i == j { 1.0 } else { 0.0 };
            ortho = ortho.max((e.vectors[i].dot(e.vectors[j]) - expected).abs());
        }
    }
    let norm = a.iter().flatten().map(|v| v * v).sum::<f64>().sqrt();
    let mut residual = 0.0f64;
    for k in 0..3 {
        let v = e.vectors[k];
        let av = DVec3::new(
            a[0][0] * v.x + a[0][1] * v.y + a[0][2] * v.z,
            a[1][0] * v.x + a[1][1] * v.y + a[1][2] * v.z,
            a[2][0] * v.x + a[2][1] * v.y + a[2][2] * v.z,
        );
        residual = residual.max((av - e.values[k] * v).length() / norm.max(f64::MIN_POSITIVE));
    }
    assert!(e.values[0] <= e.values[1] && e.values[1] <= e.values[2]);
    let det = e.vectors[0].cross(e.vectors[1]).dot(e.vectors[2]);
    (ortho, residual, (det - 1.0).abs())
}

/// `R diag(λ) Rᵀ` with the given eigenvalues.
fn with_spectrum(values: [f64; 3], seed: u64) -> [[f64; 3]; 3] {
    let r = rotation(seed);
    let cols = [
        r.x_axis.truncate(),
        r.y_axis.truncate(),
        r.z_axis.truncate(),
    ];
    let mut a = [[0.0; 3]; 3];
    for (k, &lambda) in values.iter().enumerate() {
        let u = cols[k].to_array();
        for i in 0..3 {
            for j in 0..3 {
                a[i][j] += lambda * u[i] * u[j];
            }
        }
    }
    a
}

proptest! {
    #![proptest_config(config(400))]

    #[test]
    fn eigen_is_orthonormal_and_accurate(
        entries in prop::array::uniform6(-1e3f64..1e3),
        exponent in -200i32..200,
    ) {
        let s = 2f64.powi(exponent);
        let [a, b, c, d, e, f] = entries.map(|v| v * s);
        let (ortho, residual, det) = eigen_errors([[a, d, e], [d, b, f], [e, f, c]]);
        prop_assert!(ortho <= 1e-14, "orthonormality {ortho}");
        prop_assert!(residual <= 1e-14, "residual {residual}");
        prop_assert!(det <= 1e-14);
    }

    #[test]
    fn eigen_handles_repeated_eigenvalues(
        base in -10.0f64..10.0,
        other in -10.0f64..10.0,
        pattern in 0usize..4,
        seed in any::<u64>(),
    ) {
        let values = match pattern {
            0 => [base, base, base],
            1 => [base, base, other],
            2 => [base, other, other],
            _ => [base, base * (1.0 + 1e-12), other],
        };
        let (ortho, residual, det) = eigen_errors(with_spectrum(values, seed));
        prop_assert!(ortho <= 1e-14, "orthonormality {ortho}");
        prop_assert!(residual <= 1e-14, "residual {residual}");
        prop_assert!(det <= 1e-14);
    }
}

proptest! {
    #![proptest_config(config(200))]

    #[test]
    fn similarity_keeps_the_kind(index in 0usize..20, seed in any::<u64>()) {
        let cases = catalogue();
        let case = &cases[index % cases.len()];
        let m = Rng::new(seed).similarity(1e3, 1e4);
        let q = case.quadric.transformed(&m).expect("invertible");
        prop_assert_eq!(q.kind(), case.kind, "{}", case.name);
        // The complement has the same surface kind (empty and all-space swap).
        let expected = match case.kind {
            QuadricKind::Empty => QuadricKind::AllSpace,
            QuadricKind::AllSpace => QuadricKind::Empty,
            k => k,
        };
        prop_assert_eq!(q.negated().kind(), expected, "{} negated", case.name);
    }

    #[test]
    fn affine_keeps_the_kind_family(index in 0usize..20, seed in any::<u64>(), stretch in prop::array::uniform3(0.2f64..5.0)) {
        let cases = catalogue();
        let case = &cases[index % cases.len()];
        let mut rng = Rng::new(seed);
        let m = rng.rotation() * DMat4::from_scale(DVec3::from_array(stretch)) * rng.similarity(10.0, 10.0);
        let q = case.quadric.transformed(&m).expect("invertible");
        let kind = q.kind();
        if case.kind.is_ellipsoidal() {
            prop_assert!(kind.is_ellipsoidal(), "{} became {kind}", case.name);
        } else {
            prop_assert_eq!(kind, case.kind, "{}", case.name);
        }
    }

    #[test]
    fn transform_round_trip(index in 0usize..20, seed in any::<u64>()) {
        let cases = catalogue();
        let case = &cases[index % cases.len()];
        let mut rng = Rng::new(seed);
        let m = rng.rotation() * DMat4::from_scale(DVec3::new(rng.range(0.1, 10.0), rng.range(0.1, 10.0), rng.range(0.1, 10.0)))
            * DMat4::from_translation(rng.direction() * 1e3);
        let there = case.quadric.transformed(&m).expect("invertible");
        let back = there.transformed(&m.inverse()).expect("invertible");
        prop_assert!(back.approx_eq_up_to_scale(&case.quadric, 1e-10), "{}: {:?} vs {:?}", case.name, back, case.quadric);
        prop_assert!(!back.approx_eq_up_to_scale(&case.quadric.negated(), 1e-10) || case.quadric.scale() == 0.0);
        // Values agree in sign at mapped points away from the surface.
        for _ in 0..20 {
            let p = rng.direction() * rng.range(0.0, 3.0);
            let (v, err) = case.quadric.value_with_error(p);
            let w = there.value(m.transform_point3(p));
            if v.abs() > 1e3 * err.max(1e-12) {
                prop_assert_eq!(v.signum(), w.signum(), "{} at {}", case.name, p);
            }
        }
    }

    #[test]
    fn projective_transform_matches_the_affine_path(index in 0usize..20, seed in any::<u64>()) {
        let cases = catalogue();
        let case = &cases[index % cases.len()];
        let m = Rng::new(seed).similarity(10.0, 100.0);
        let affine = case.quadric.transformed(&m).expect("invertible");
        // The same map written with a homogeneous factor 2 takes the projective path.
        let projective = case.quadric.transformed(&(m * 2.0)).expect("invertible");
        prop_assert!(affine.approx_eq_up_to_scale(&projective, 1e-10), "{}", case.name);
    }

    #[test]
    fn line_roots_are_roots(index in 0usize..20, seed in any::<u64>()) {
        let cases = catalogue();
        let case = &cases[index % cases.len()];
        let mut rng = Rng::new(seed);
        let q = case.quadric.transformed(&rng.similarity(10.0, 1e3)).expect("invertible");
        for _ in 0..20 {
            let p = q.origin() + rng.direction() * rng.range(0.0, 20.0);
            let v = rng.direction() * rng.range(0.1, 10.0);
            let hit = q.intersect_line(p, v);
            let roots = hit.roots();
            prop_assert!(roots.windows(2).all(|w| w[0] < w[1]));
            for t in roots {
                let x = p + t * v;
                let k = q.coefficients();
                let terms = raw_value(&k.map(f64::abs), (x - q.origin()).abs());
                let tolerance = if matches!(hit, LineIntersection::Tangent(_)) { 1e-6 } else { 1e-12 };
                // Forming the world point p + t v rounds by about ε |p + t v|.
                let placement = 4.0 * f64::EPSILON * x.abs().max_element() * q.gradient(x).length();
                prop_assert!(q.value(x).abs() <= tolerance * terms + placement, "{}: Q = {} at t = {t}", case.name, q.value(x));
            }
        }
    }

    #[test]
    fn canonical_form_reproduces_the_quadric(index in 0usize..20, seed in any::<u64>()) {
        // Q(p) and the frame's Σ λ y² + 2 m·y + κ agree (the snapped terms are within tolerance).
        let cases = catalogue();
        let case = &cases[index % cases.len()];
        let mut rng = Rng::new(seed);
        let q = case.quadric.transformed(&rng.similarity(10.0, 1e3)).expect("invertible");
        let frame = q.frame();
        for _ in 0..20 {
            let p = frame.centre + rng.direction() * rng.range(0.0, 10.0) * case.size;
            let y = frame.to_frame(p);
            prop_assert!((frame.to_world(y) - p).length() <= 1e-12 * (p.length() + 1.0));
            let (value, _) = q.value_with_error(p);
            let canonical = frame.canonical_value(y);
            let terms = raw_value(&q.coefficients().map(f64::abs), (p - q.origin()).abs());
            let gradient = q.gradient(p).length();
            let tolerance = 1e-9 * terms + 1e-12 * gradient * (p - q.origin()).length() + 1e-300;
            prop_assert!((value - canonical).abs() <= tolerance,
                "{}: Q = {value}, canonical = {canonical}", case.name);
        }
    }

    #[test]
    fn heightfields_lie_on_the_surface(index in 0usize..20, seed in any::<u64>()) {
        let cases = catalogue();
        let case = &cases[index % cases.len()];
        let mut rng = Rng::new(seed);
        let q = case.quadric.transformed(&rng.similarity(10.0, 1e3)).expect("invertible");
        let frame = q.frame();
        for hf in frame.heightfields() {
            for _ in 0..10 {
                let (x, y) = (rng.range(-3.0, 3.0), rng.range(-3.0, 3.0));
                let Some(t) = hf.height(x, y) else { continue };
                for sign in [1.0, -1.0] {
                    if sign < 0.0 && matches!(hf.form, HeightfieldForm::Polynomial { .. }) {
                        continue;
                    }
                    let p = frame.heightfield_point(&hf, x, y, sign * t);
                    let (value, _) = q.value_with_error(p);
                    let scale = q.gradient(p).length() * (1.0 + p.distance(q.origin()));
                    prop_assert!(value.abs() <= 1e-9 * scale.max(1e-300) || value.abs() <= 1e-12 * q.scale(),
                        "{}: axis {} Q = {value}", case.name, hf.normal_axis);
                    // Distortion equals |N| / |N · u_k| from the quadric's own normal.
                    // Skip kinds whose gradient vanishes on the surface (the normal is noise there).
                    let singular = matches!(case.kind, QuadricKind::CoincidentPlanes | QuadricKind::Line | QuadricKind::Point);
                    if singular {
                        continue;
                    }
                    if let (Some(d), Some(n)) = (hf.distortion(x, y), q.normal(p)) {
                        let expected = 1.0 / n.dot(frame.axes[hf.normal_axis]).abs();
                        if d.is_finite() && expected < 1e6 {
                            prop_assert!((d - expected).abs() <= 1e-6 * expected, "{}: {d} vs {expected}", case.name);
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn distortion_bounds_contain_samples(index in 0usize..20, seed in any::<u64>()) {
        let cases = catalogue();
        let case = &cases[index % cases.len()];
        let mut rng = Rng::new(seed);
        let frame = case.quadric.frame();
        for hf in frame.heightfields() {
            let x0 = rng.range(-2.0, 2.0);
            let y0 = rng.range(-2.0, 2.0);
            let (x1, y1) = (x0 + rng.range(0.0, 1.0), y0 + rng.range(0.0, 1.0));
            let Some((lo, hi)) = hf.distortion_bounds((x0, x1), (y0, y1)) else { continue };
            prop_assert!(lo >= 1.0 && lo <= hi);
            for i in 0..=16 {
                for j in 0..=16 {
                    let x = x0 + (x1 - x0) * i as f64 / 16.0;
                    let y = y0 + (y1 - y0) * j as f64 / 16.0;
                    let d = hf.distortion(x, y);
                    prop_assert!(d.is_some(), "{}: undefined inside a bounded rectangle", case.name);
                    let d = d.unwrap_or(f64::NAN);
                    prop_assert!(d >= lo * (1.0 - 1e-12) && d <= hi * (1.0 + 1e-12), "{}: {d} outside [{lo}, {hi}]", case.name);
                }
            }
        }
    }
}

#[test]
fn comparison_up_to_scale() {
    let a = Quadric::sphere(DVec3::new(1.0, 2.0, 3.0), 2.0).unwrap();
    let moved = a.with_origin(DVec3::new(1.5, 2.0, 2.5));
    assert!(a.approx_eq_up_to_scale(&moved, 1e-14));
    assert!(moved.approx_eq_up_to_scale(&a, 1e-14));
    let scaled = Quadric::new(a.origin(), a.coefficients().map(|c| c * 3.7)).unwrap();
    assert!(a.approx_eq_up_to_scale(&scaled, 1e-14));
    assert!(!a.approx_eq_up_to_scale(&a.negated(), 1e-3));
    let bigger = Quadric::sphere(DVec3::new(1.0, 2.0, 3.0), 2.0 + 1e-6).unwrap();
    assert!(!a.approx_eq_up_to_scale(&bigger, 1e-9));
    assert!(a.approx_eq_up_to_scale(&bigger, 1e-5));
}

#[test]
fn kind_names_are_stable_and_distinct() {
    let names: Vec<_> = QuadricKind::ALL.iter().map(|k| k.name()).collect();
    let mut sorted = names.clone();
    sorted.sort();
    sorted.dedup();
    assert_eq!(sorted.len(), names.len());
    for kind in QuadricKind::ALL {
        assert_eq!(QuadricKind::from_name(kind.name()), Some(kind));
    }
    assert_eq!(QuadricKind::ParallelPlanes.name(), "slab");
    assert_eq!(QuadricKind::EllipticCylinder.name(), "elliptic_cylinder");
}

#[test]
fn catalogue_kinds() {
    for case in catalogue() {
        assert_eq!(case.quadric.kind(), case.kind, "{}", case.name);
    }
}

/// A coefficient: zero a third of the time, else a signed magnitude in `10^[-100, 100]`.
fn coefficient() -> impl Strategy<Value = f64> {
    prop_oneof![
        1 => Just(0.0),
        2 => (-100.0f64..100.0, any::<bool>()).prop_map(|(e, s)| if s { 10f64.powf(e) } else { -(10f64.powf(e)) }),
    ]
}

proptest! {
    #![proptest_config(config(300))]

    #[test]
    fn arbitrary_finite_quadrics_never_panic_or_give_nan(
        k in prop::array::uniform10(coefficient()),
        origin in prop::array::uniform3(-1e6f64..1e6),
        point in prop::array::uniform3(-1e3f64..1e3),
        direction in prop::array::uniform3(-1.0f64..1.0),
        m in prop::array::uniform16(-3.0f64..3.0),
    ) {
        let q = Quadric::new(DVec3::from_array(origin), k).expect("finite");
        let p = q.origin() + DVec3::from_array(point);
        let v = DVec3::from_array(direction);
        let kind = q.kind();
        prop_assert!(!kind.name().is_empty());
        let frame = q.frame();
        prop_assert!(frame.axes.iter().all(|a| a.is_finite()));
        prop_assert!(!q.value(p).is_nan());
        prop_assert!(!q.conservative_distance(p).is_nan());
        prop_assert!(q.normal(p).is_none_or(|n| n.is_finite()));
        for t in q.intersect_line(p, v).roots() {
            prop_assert!(t.is_finite());
        }
        for hf in frame.heightfields() {
            prop_assert!(hf.height(0.5, -0.25).is_none_or(|h| !h.is_nan()));
            prop_assert!(hf.distortion(0.5, -0.25).is_none_or(|d| !d.is_nan()));
            prop_assert!(hf.distortion_bounds((-1.0, 1.0), (0.5, 2.0)).is_none_or(|(a, b)| !a.is_nan() && !b.is_nan()));
        }
        let _ = q.negated().kind();
        let _ = q.recentred().kind();
        let _ = q.approx_eq_up_to_scale(&q.negated(), 1e-9);
        if let Some(t) = q.transformed(&DMat4::from_cols_array(&m)) {
            prop_assert!(t.coefficients().iter().all(|c| c.is_finite()));
            let _ = t.kind();
        }
    }

    #[test]
    fn no_crossing_is_missed(index in 0usize..20, seed in any::<u64>()) {
        // Every sign change of Q along a dense sampling of the line brackets a returned root.
        let cases = catalogue();
        let case = &cases[index % cases.len()];
        let mut rng = Rng::new(seed);
        let q = case.quadric.transformed(&rng.similarity(10.0, 1e3)).expect("invertible");
        let p = q.origin() + rng.direction() * rng.range(0.0, 5.0) * case.size;
        let v = rng.direction();
        let roots = q.intersect_line(p, v).roots();
        let span = 20.0 * case.size;
        let steps = 400;
        let mut previous = q.value(p - span * v);
        for i in 1..=steps {
            let t = -span + 2.0 * span * i as f64 / steps as f64;
            let t_prev = t - 2.0 * span / steps as f64;
            let value = q.value(p + t * v);
            if previous != 0.0 && value != 0.0 && previous.signum() != value.signum() {
                let slack = 1e-9 * span;
                prop_assert!(
                    roots.iter().any(|r| *r >= t_prev - slack && *r <= t + slack),
                    "{}: crossing in [{t_prev}, {t}] missed; roots {roots:?}", case.name
                );
            }
            previous = value;
        }
    }
}

proptest! {
    #![proptest_config(config(200))]

    #[test]
    fn gradient_matches_finite_differences(index in 0usize..20, seed in any::<u64>()) {
        let cases = catalogue();
        let case = &cases[index % cases.len()];
        let mut rng = Rng::new(seed);
        let q = case.quadric.transformed(&rng.similarity(10.0, 10.0)).expect("invertible");
        let p = q.origin() + rng.direction() * rng.range(0.1, 3.0) * case.size;
        let g = q.gradient(p);
        // Central differences are exact for quadratics up to rounding.
        let h = 1e-3 * case.size;
        let fd = DVec3::new(
            q.value(p + DVec3::X * h) - q.value(p - DVec3::X * h),
            q.value(p + DVec3::Y * h) - q.value(p - DVec3::Y * h),
            q.value(p + DVec3::Z * h) - q.value(p - DVec3::Z * h),
        ) / (2.0 * h);
        let terms = raw_value(&q.coefficients().map(f64::abs), (p - q.origin()).abs() + h);
        prop_assert!((g - fd).length() <= 1e-6 * (g.length() + terms / h), "{}: {g} vs {fd}", case.name);
        if let Some(n) = q.normal(p) {
            prop_assert!((n.length() - 1.0).abs() <= 1e-15);
            prop_assert!(n.dot(g) > 0.0);
        }
    }
}
