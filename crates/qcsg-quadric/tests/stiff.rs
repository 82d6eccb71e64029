//! The stiff and extreme suite: radii from 1e-6 to 1e6, translations of 1e6, aspect ratios of
//! 1e4, eigenvalues of 1e-12 beside 1, tangent and coincident configurations. Every case is a
//! table row; each row states the tolerance it enforces.

mod common;

use common::{Rng, true_distance};
use qcsg_quadric::{DMat4, DVec3, LineIntersection, Quadric, QuadricKind, Tolerances};

const EPS: f64 = f64::EPSILON;

fn translate(x: f64, y: f64, z: f64) -> DMat4 {
    DMat4::from_translation(DVec3::new(x, y, z))
}

fn scale(s: f64) -> DMat4 {
    DMat4::from_scale(DVec3::splat(s))
}

fn rotate(seed: u64) -> DMat4 {
    Rng::new(seed).rotation()
}

/// Applies the transforms in order, failing the test if one is rejected.
fn apply(q: &Quadric, chain: &[DMat4]) -> (Quadric, DMat4) {
    let mut total = DMat4::IDENTITY;
    let mut q = *q;
    for m in chain {
        q = q.transformed(m).expect("invertible transform");
        total = *m * total;
    }
    (q, total)
}

struct SphereCase {
    name: &'static str,
    centre: DVec3,
    radius: f64,
    chain: Vec<DMat4>,
    /// Relative tolerance on the centre and radius, in units of the final radius.
    tolerance: f64,
}

fn sphere_cases() -> Vec<SphereCase> {
    let c = |name, centre, radius, chain, tolerance| SphereCase {
        name,
        centre,
        radius,
        chain,
        tolerance,
    };
    vec![
        c(
            "unit, translated 1e6 along x",
            DVec3::ZERO,
            1.0,
            vec![translate(1e6, 0.0, 0.0)],
            1e-9,
        ),
        c(
            "unit, translated 1e6 diagonally",
            DVec3::ZERO,
            1.0,
            vec![translate(1e6, -1e6, 1e6)],
            1e-9,
        ),
        c(
            "unit, scaled 1e-3",
            DVec3::ZERO,
            1.0,
            vec![scale(1e-3)],
            1e-9,
        ),
        c(
            "unit at 1e6, scaled 1e-3 about the origin",
            DVec3::new(1e6, 0.0, 0.0),
            1.0,
            vec![scale(1e-3)],
            1e-9,
        ),
        c(
            "unit, translated 1e6, rotated, scaled 1e-3, translated back",
            DVec3::ZERO,
            1.0,
            vec![
                translate(1e6, 2e6, -3e6),
                rotate(1),
                scale(1e-3),
                translate(-1e3, 5e2, 7e2),
            ],
            1e-9,
        ),
        c(
            "radius 1e-6 at the origin, rotated",
            DVec3::ZERO,
            1e-6,
            vec![rotate(2)],
            1e-9,
        ),
        c(
            "radius 1e6, rotated and translated 1e6",
            DVec3::ZERO,
            1e6,
            vec![rotate(3), translate(1e6, 1e6, 0.0)],
            1e-9,
        ),
        c(
            "radius 1e-6, scaled 1e12 to 1e6",
            DVec3::ZERO,
            1e-6,
            vec![scale(1e12)],
            1e-9,
        ),
        // The centre's absolute error is bounded by ε |centre| ≈ 2e-10, i.e. 2e-4 of this radius.
        c(
            "radius 1e-6, translated 1e6",
            DVec3::ZERO,
            1e-6,
            vec![translate(1e6, 0.0, 0.0)],
            1e-3,
        ),
        c(
            "unit, hundred random similarity steps",
            DVec3::ZERO,
            1.0,
            {
                let mut rng = Rng::new(4);
                (0..100).map(|_| rng.similarity(2.0, 1e5)).collect()
            },
            1e-9,
        ),
    ]
}

#[test]
fn spheres_keep_centre_and_radius_through_transforms() {
    for case in sphere_cases() {
        let q = Quadric::sphere(case.centre, case.radius).expect("valid sphere");
        let (q, total) = apply(&q, &case.chain);
        let expected_centre = total.transform_point3(case.centre);
        let expected_radius = case.radius * total.x_axis.truncate().length();
        let frame = q.frame();
        assert_eq!(q.kind(), QuadricKind::Sphere, "{}", case.name);
        let centre_error = (frame.centre - expected_centre).length() / expected_radius;
        let radii = frame.semi_axes();
        let radius_error = radii
            .iter()
            .map(|r| (r - expected_radius).abs() / expected_radius)
            .fold(0.0, f64::max);
        assert!(
            centre_error <= case.tolerance,
            "{}: centre off by {centre_error:e} radii",
            case.name
        );
        assert!(
            radius_error <= case.tolerance,
            "{}: radius off by {radius_error:e}",
            case.name
        );
        // The coefficients stay those of a unit sphere (up to a power of two).
        let k = q.coefficients();
        assert!(k.iter().all(|c| c.is_finite()), "{}", case.name);
        assert!(
            q.scale() >= 1.0 && q.scale() < 2.0,
            "{}: not normalised",
            case.name
        );
    }
}

#[test]
fn pure_translation_is_exact() {
    let q = Quadric::sphere(DVec3::new(0.25, -0.5, 0.125), 1.0).unwrap();
    let moved = q.transformed(&translate(1e6, 1e6, 1e6)).unwrap();
    assert_eq!(moved.coefficients(), q.coefficients());
    assert_eq!(
        moved.origin(),
        DVec3::new(1e6 + 0.25, 1e6 - 0.5, 1e6 + 0.125)
    );
}

struct KindCase {
    name: &'static str,
    quadric: Quadric,
    chain: Vec<DMat4>,
    expected: QuadricKind,
}

fn raw(origin: DVec3, k: [f64; 10]) -> Quadric {
    Quadric::new(origin, k).expect("finite")
}

fn kind_cases() -> Vec<KindCase> {
    use QuadricKind as K;
    let o = DVec3::ZERO;
    let far = vec![rotate(11), translate(1e6, -1e6, 1e6)];
    let shrink = vec![rotate(12), scale(1e-3), translate(3e5, 0.0, 0.0)];
    let c = |name, quadric: Option<Quadric>, chain, expected| KindCase {
        name,
        quadric: quadric.expect("valid"),
        chain,
        expected,
    };
    vec![
        c(
            "sphere r=1e-6 far",
            Quadric::sphere(o, 1e-6),
            far.clone(),
            K::Sphere,
        ),
        c(
            "sphere r=1e6 far",
            Quadric::sphere(o, 1e6),
            far.clone(),
            K::Sphere,
        ),
        c(
            "ellipsoid aspect 1e4",
            Quadric::ellipsoid(o, DVec3::new(1.0, 1e2, 1e4)),
            far.clone(),
            K::Ellipsoid,
        ),
        c(
            "spheroid aspect 1e4",
            Quadric::ellipsoid(o, DVec3::new(1e-2, 1e2, 1e-2)),
            shrink.clone(),
            K::Spheroid,
        ),
        c(
            "near-cylinder: eigenvalue 1e-12 beside 1",
            Some(raw(
                o,
                [1.0, 1.0, 1e-12, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0],
            )),
            far.clone(),
            K::EllipticCylinder,
        ),
        c(
            "near-slab: two eigenvalues 1e-12 beside 1",
            Some(raw(
                o,
                [1e-12, 1.0, 1e-12, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0],
            )),
            far.clone(),
            K::ParallelPlanes,
        ),
        c(
            "near-cone: hyperboloid waist 1e-12 relative, apex far",
            Some(raw(o, [1.0, 1.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0])),
            far.clone(),
            K::Cone,
        ),
        c(
            "hyperboloid with waist 1e-6",
            Quadric::hyperboloid_one_sheet(o, DVec3::Z, 1e-6, 1e-6),
            far.clone(),
            K::HyperboloidOneSheet,
        ),
        c(
            "two-sheet hyperboloid, vertices 1e4 apart (aspect 5e3)",
            Quadric::hyperboloid_two_sheets(o, DVec3::Y, 1.0, 5e3),
            shrink.clone(),
            K::HyperboloidTwoSheets,
        ),
        c(
            "cylinder r=1e-6 along a skew axis",
            Quadric::cylinder(o, DVec3::new(1.0, 1e-3, 1e3), 1e-6),
            far.clone(),
            K::EllipticCylinder,
        ),
        c(
            "cylinder r=1e6",
            Quadric::cylinder(o, DVec3::new(1.0, 2.0, 3.0), 1e6),
            far.clone(),
            K::EllipticCylinder,
        ),
        c(
            "paraboloid with focal length 1e-6",
            Quadric::paraboloid(o, DVec3::new(1.0, 1.0, 0.0), 1e-6),
            far.clone(),
            K::EllipticParaboloid,
        ),
        c(
            "paraboloid with focal length 1e6",
            Quadric::paraboloid(o, DVec3::X, 1e6),
            shrink.clone(),
            K::EllipticParaboloid,
        ),
        c(
            "slab of half-width 1e-6",
            Quadric::slab(o, DVec3::new(3.0, 4.0, 0.0), 1e-6),
            far.clone(),
            K::ParallelPlanes,
        ),
        c(
            "half-space far away",
            Quadric::half_space(o, DVec3::new(1.0, 1e-8, 0.0)),
            far.clone(),
            K::Plane,
        ),
        c(
            "cone with slope 1e-4",
            Quadric::cone(o, DVec3::Z, 1e-4),
            far.clone(),
            K::Cone,
        ),
        c(
            "cone with slope 1e4",
            Quadric::cone(o, DVec3::Z, 1e4),
            far.clone(),
            K::Cone,
        ),
        c(
            "coincident planes",
            Some(raw(o, [0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0])),
            far.clone(),
            K::CoincidentPlanes,
        ),
        c(
            "intersecting planes at 1e-3 rad",
            Some(raw(o, [1e-6, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0])),
            far.clone(),
            K::IntersectingPlanes,
        ),
        c(
            "line",
            Some(raw(o, [1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0])),
            far.clone(),
            K::Line,
        ),
        c(
            "point",
            Some(raw(o, [1.0, 1e4, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0])),
            far.clone(),
            K::Point,
        ),
        c(
            "empty: imaginary sphere",
            Some(raw(o, [1.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1e-12])),
            far.clone(),
            K::Empty,
        ),
        c(
            "all space: complement of an imaginary cylinder",
            Some(raw(
                o,
                [-1.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0],
            )),
            far,
            K::AllSpace,
        ),
    ]
}

#[test]
fn stiff_kinds_survive_transforms() {
    for case in kind_cases() {
        assert_eq!(
            case.quadric.kind(),
            case.expected,
            "{} (as built)",
            case.name
        );
        let (q, _) = apply(&case.quadric, &case.chain);
        assert_eq!(q.kind(), case.expected, "{} (transformed)", case.name);
        let frame = q.frame();
        for i in 0..3 {
            for j in 0..3 {
                let expected = if i == j { 1.0 } else { 0.0 };
                let defect = (frame.axes[i].dot(frame.axes[j]) - expected).abs();
                assert!(defect <= 1e-14, "{}: axes defect {defect:e}", case.name);
            }
        }
        assert!(frame.centre.is_finite(), "{}", case.name);
        assert!(frame.constant.is_finite(), "{}", case.name);
    }
}

#[test]
fn tolerances_decide_near_degenerate_kinds() {
    let near_cylinder = raw(
        DVec3::ZERO,
        [1.0, 1.0, 1e-12, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0],
    );
    let strict = Tolerances {
        eigenvalue: 1e-14,
        ..Tolerances::default()
    };
    assert_eq!(near_cylinder.kind(), QuadricKind::EllipticCylinder);
    assert_eq!(near_cylinder.kind_with(&strict), QuadricKind::Spheroid);
    // The strict frame sees the true semi-axis 1e6 to 1e-9.
    let frame = qcsg_quadric::PrincipalFrame::new(&near_cylinder, &strict);
    let long = frame.semi_axes().iter().cloned().fold(0.0, f64::max);
    assert!((long - 1e6).abs() <= 1e-9 * 1e6, "{long}");
}

#[test]
fn elongated_ellipsoid_radii() {
    // Aspect 1e4 under a generic rotation: the smallest eigenvalue carries an absolute error of
    // about ε λ_max, i.e. a relative error of about 1e-8 · ε/ε on the largest radius.
    let radii = DVec3::new(1.0, 1e2, 1e4);
    let q = Quadric::ellipsoid(DVec3::ZERO, radii).unwrap();
    let (q, _) = apply(&q, &[rotate(21), translate(1e6, 0.0, 0.0)]);
    let mut got = q.frame().semi_axes();
    got.sort_by(f64::total_cmp);
    for (g, e) in got.iter().zip(radii.to_array()) {
        assert!((g - e).abs() <= 1e-7 * e, "{g} vs {e}");
    }
}

struct LineCase {
    name: &'static str,
    quadric: Quadric,
    origin: DVec3,
    direction: DVec3,
    expected: Expected,
}

enum Expected {
    None,
    Tangent(f64),
    Two(f64, f64),
    One(f64),
    Contained,
}

fn line_cases() -> Vec<LineCase> {
    let c = |name, quadric: Option<Quadric>, origin, direction, expected| LineCase {
        name,
        quadric: quadric.expect("valid"),
        origin,
        direction,
        expected,
    };
    let far = DVec3::new(1e6, -1e6, 1e6);
    vec![
        c(
            "through a unit sphere at 1e6",
            Quadric::sphere(far, 1.0),
            far - DVec3::X * 5.0,
            DVec3::X,
            Expected::Two(4.0, 6.0),
        ),
        c(
            "tangent to a unit sphere at 1e6",
            Quadric::sphere(far, 1.0),
            far + DVec3::new(-5.0, 1.0, 0.0),
            DVec3::X,
            Expected::Tangent(5.0),
        ),
        c(
            "missing a sphere by 1e-3",
            Quadric::sphere(far, 1.0),
            far + DVec3::new(-5.0, 1.001, 0.0),
            DVec3::X,
            Expected::None,
        ),
        c(
            "through a sphere of radius 1e-6",
            Quadric::sphere(DVec3::ZERO, 1e-6),
            DVec3::new(-1.0, 0.0, 0.0),
            DVec3::X,
            Expected::Two(1.0 - 1e-6, 1.0 + 1e-6),
        ),
        c(
            "through a sphere of radius 1e6",
            Quadric::sphere(DVec3::ZERO, 1e6),
            DVec3::new(-2e6, 0.0, 0.0),
            DVec3::X,
            Expected::Two(1e6, 3e6),
        ),
        c(
            "along a cylinder's axis",
            Quadric::cylinder(far, DVec3::Z, 1.0),
            far,
            DVec3::Z,
            Expected::None,
        ),
        c(
            "on a cylinder's surface line",
            Quadric::cylinder(DVec3::ZERO, DVec3::Z, 1.0),
            DVec3::X,
            DVec3::Z,
            Expected::Contained,
        ),
        c(
            "tangent to a cylinder",
            Quadric::cylinder(far, DVec3::Z, 1.0),
            far + DVec3::new(-3.0, 1.0, 7.0),
            DVec3::X,
            Expected::Tangent(3.0),
        ),
        c(
            "almost along a cylinder (1e-9 rad)",
            Quadric::cylinder(DVec3::ZERO, DVec3::Z, 1.0),
            DVec3::ZERO,
            DVec3::new(1e-9, 0.0, 1.0),
            Expected::Two(-1e9, 1e9),
        ),
        c(
            "into a plane",
            Quadric::half_space(far, DVec3::Y),
            far - DVec3::Y * 2.0,
            DVec3::Y,
            Expected::One(2.0),
        ),
        c(
            "inside a plane",
            Quadric::half_space(far, DVec3::Y),
            far + DVec3::X,
            DVec3::Z,
            Expected::Contained,
        ),
        c(
            "parallel to a plane",
            Quadric::half_space(far, DVec3::Y),
            far + DVec3::Y,
            DVec3::Z,
            Expected::None,
        ),
        c(
            "into a paraboloid along its axis",
            Quadric::paraboloid(DVec3::ZERO, DVec3::Z, 0.25),
            DVec3::new(0.0, 0.0, -3.0),
            DVec3::Z,
            Expected::One(3.0),
        ),
        c(
            "across a slab of half-width 1e-6",
            Quadric::slab(far, DVec3::X, 1e-6),
            far - DVec3::X,
            DVec3::X,
            Expected::Two(1.0 - 1e-6, 1.0 + 1e-6),
        ),
        c(
            "through a cone's apex",
            Quadric::cone(far, DVec3::Z, 1.0),
            far - DVec3::X,
            DVec3::X,
            Expected::Tangent(1.0),
        ),
        c(
            "in coincident planes",
            Some(raw(
                DVec3::ZERO,
                [0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            )),
            DVec3::X,
            DVec3::Y,
            Expected::Contained,
        ),
        c(
            "across coincident planes",
            Some(raw(
                DVec3::ZERO,
                [0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            )),
            DVec3::new(0.0, 0.0, -2.0),
            DVec3::Z,
            Expected::Tangent(2.0),
        ),
    ]
}

#[test]
fn stiff_line_intersections() {
    for case in line_cases() {
        let hit = case.quadric.intersect_line(case.origin, case.direction);
        // Roots within 1e-9 relative (of the larger of the root and the distance scale 1).
        let close = |got: f64, want: f64| (got - want).abs() <= 1e-9 * want.abs().max(1.0);
        let ok = match (&case.expected, hit) {
            (Expected::None, LineIntersection::None) => true,
            (Expected::Contained, LineIntersection::Contained) => true,
            (Expected::One(t), LineIntersection::One(g)) => close(g, *t),
            (Expected::Tangent(t), LineIntersection::Tangent(g)) => {
                (g - t).abs() <= 1e-6 * t.abs().max(1.0)
            }
            (Expected::Two(a, b), LineIntersection::Two(x, y)) => close(x, *a) && close(y, *b),
            _ => false,
        };
        assert!(ok, "{}: got {hit:?}", case.name);
    }
}

#[test]
fn near_linear_roots_are_continuous() {
    // As the direction tilts towards the cylinder's axis, the near root stays put and the far
    // root goes to infinity; nothing becomes NaN.
    let q = Quadric::cylinder(DVec3::ZERO, DVec3::Z, 1.0).unwrap();
    for e in 1..=20 {
        let tilt = 10f64.powi(-e);
        let origin = DVec3::new(0.0, 0.0, 0.0);
        let hit = q.intersect_line(origin, DVec3::new(tilt, 0.0, 1.0));
        match hit {
            LineIntersection::Two(a, b) => {
                assert!((a + 1.0 / tilt).abs() <= 1e-9 / tilt, "{tilt}: {a}");
                assert!((b - 1.0 / tilt).abs() <= 1e-9 / tilt, "{tilt}: {b}");
            }
            other => panic!("{tilt}: {other:?}"),
        }
    }
    // A paraboloid crossed nearly along its axis: one root near the vertex, one far away.
    // Along (tilt, 0, 1) from (0, 0, −1): tilt² t² − t + 1 = 0.
    let p = Quadric::paraboloid(DVec3::ZERO, DVec3::Z, 0.25).unwrap();
    for e in 1..=15 {
        let tilt = 10f64.powi(-e);
        let near = 2.0 / (1.0 + (1.0 - 4.0 * tilt * tilt).sqrt());
        let far = 1.0 / (tilt * tilt * near);
        let hit = p.intersect_line(DVec3::new(0.0, 0.0, -1.0), DVec3::new(tilt, 0.0, 1.0));
        match hit {
            LineIntersection::Two(a, b) => {
                assert!((a - near).abs() <= 1e-12 * near, "{tilt}: {hit:?}");
                assert!((b - far).abs() <= 1e-9 * far, "{tilt}: {hit:?}");
            }
            other => panic!("{tilt}: {other:?}"),
        }
    }
}

struct DistanceCase {
    name: &'static str,
    quadric: Quadric,
    size: f64,
}

fn distance_cases() -> Vec<DistanceCase> {
    let far = DVec3::new(1e6, 1e6, -1e6);
    let c = |name, quadric: Option<Quadric>, size| DistanceCase {
        name,
        quadric: quadric.expect("valid"),
        size,
    };
    vec![
        c("sphere r=1e-6 at 1e6", Quadric::sphere(far, 1e-6), 1e-6),
        c("sphere r=1e6 at 1e6", Quadric::sphere(far, 1e6), 1e6),
        c(
            "ellipsoid aspect 1e4",
            Quadric::ellipsoid(far, DVec3::new(1e-2, 1.0, 1e2)),
            1e-2,
        ),
        c(
            "near-cylinder",
            Some(raw(
                far,
                [1.0, 1.0, 1e-12, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0],
            )),
            1.0,
        ),
        c(
            "cylinder r=1e-6",
            Quadric::cylinder(far, DVec3::new(1.0, 2.0, 2.0), 1e-6),
            1e-6,
        ),
        c("cone slope 1e4", Quadric::cone(far, DVec3::Z, 1e4), 1.0),
        c("cone slope 1e-4", Quadric::cone(far, DVec3::Z, 1e-4), 1.0),
        c(
            "paraboloid f=1e-6",
            Quadric::paraboloid(far, DVec3::X, 1e-6),
            1e-3,
        ),
        c(
            "slab half-width 1e-6",
            Quadric::slab(far, DVec3::Y, 1e-6),
            1e-6,
        ),
        c(
            "hyperboloid waist 1e-6",
            Quadric::hyperboloid_one_sheet(far, DVec3::Z, 1e-6, 1e-6),
            1e-6,
        ),
    ]
}

#[test]
fn stiff_conservative_distance_is_a_lower_bound() {
    let mut rng = Rng::new(0xd15);
    for case in distance_cases() {
        for p in common::points_around(&mut rng, &case.quadric, case.size, 60) {
            let d = case.quadric.conservative_distance(p);
            assert!(!d.is_nan(), "{}: NaN", case.name);
            let truth = true_distance(&case.quadric, p);
            // The oracle's slack: 1e-9 relative plus the rounding of coordinates near 1e6.
            let slack = 1e-9 * truth + 1e-12 * case.size + 8.0 * EPS * 1e6 * 2.0;
            assert!(
                d.abs() <= truth + slack,
                "{}: |d| = {} > {truth} at {p}",
                case.name,
                d.abs()
            );
        }
    }
}

#[test]
fn no_nan_anywhere() {
    let mut quadrics: Vec<Quadric> = kind_cases()
        .into_iter()
        .map(|c| apply(&c.quadric, &c.chain).0)
        .collect();
    quadrics.extend(distance_cases().into_iter().map(|c| c.quadric));
    let mut rng = Rng::new(99);
    for q in &quadrics {
        let frame = q.frame();
        let mut points = vec![
            q.origin(),
            frame.centre,
            DVec3::ZERO,
            DVec3::splat(1e12),
            q.origin() + DVec3::splat(1e-300),
        ];
        for _ in 0..50 {
            points.push(q.origin() + rng.direction() * 10f64.powf(rng.range(-8.0, 8.0)));
        }
        for &p in &points {
            assert!(!q.value(p).is_nan());
            assert!(q.gradient(p).is_finite());
            assert!(q.normal(p).is_none_or(|n| n.is_finite()));
            assert!(!q.conservative_distance(p).is_nan());
            for v in [DVec3::X, rng.direction(), DVec3::new(1e-300, 0.0, 1.0)] {
                for t in q.intersect_line(p, v).roots() {
                    assert!(t.is_finite());
                }
            }
        }
        for hf in frame.heightfields() {
            for (x, y) in [(0.0, 0.0), (1.0, -1.0), (1e6, 1e-6), (-1e-9, 1e9)] {
                assert!(hf.height(x, y).is_none_or(|h| !h.is_nan()));
                assert!(hf.distortion(x, y).is_none_or(|d| !d.is_nan() && d >= 1.0));
            }
        }
    }
}

#[test]
fn heightfields_of_a_far_small_sphere() {
    // Unit sphere at 1e6 scaled by 1e-3: heights must reproduce surface points to 1e-9 radii.
    let q = Quadric::sphere(DVec3::new(1e6, 0.0, 0.0), 1.0).unwrap();
    let (q, _) = apply(&q, &[rotate(5), scale(1e-3)]);
    let frame = q.frame();
    let radius = 1e-3;
    for hf in frame.heightfields() {
        let alpha = match hf.form {
            qcsg_quadric::HeightfieldForm::Root {
                alpha_x,
                alpha_y,
                alpha_c,
                ..
            } => (alpha_x, alpha_y, alpha_c),
            other => panic!("{other:?}"),
        };
        assert!((alpha.0 + 1.0).abs() <= 1e-12 && (alpha.1 + 1.0).abs() <= 1e-12);
        assert!((alpha.2 - radius * radius).abs() <= 1e-12 * radius * radius);
        for (x, y) in [(0.0, 0.0), (3e-4, 4e-4), (-5e-4, 1e-4)] {
            let h = hf.height(x, y).expect("inside the disc");
            let p = frame.heightfield_point(&hf, x, y, h);
            let r = (p - frame.centre).length();
            assert!((r - radius).abs() <= 1e-9 * radius, "{r}");
            let bounds = hf
                .distortion_bounds((x, x + 1e-5), (y, y + 1e-5))
                .expect("defined");
            assert!(bounds.0 >= 1.0 && bounds.1 < 10.0);
        }
    }
}

#[test]
fn centres_follow_transforms() {
    // Apex, vertex and axis points map with the transform: to 1e-9 of the feature size plus the
    // rounding of world coordinates (a few ε |centre|).
    let chain = [rotate(31), scale(1e-3), translate(1e6, -2e6, 5e5)];
    let apex = DVec3::new(1.0, 2.0, 3.0);
    let cases = [
        (
            "cone apex",
            Quadric::cone(apex, DVec3::new(1.0, 1.0, 0.0), 0.3),
        ),
        (
            "ellipsoid centre",
            Quadric::ellipsoid(apex, DVec3::new(1.0, 1e2, 1e-2)),
        ),
        (
            "hyperboloid centre",
            Quadric::hyperboloid_one_sheet(apex, DVec3::Z, 2.0, 1.0),
        ),
        (
            "paraboloid vertex",
            Quadric::paraboloid(apex, DVec3::Y, 0.5),
        ),
    ];
    for (name, q) in cases {
        let (q, total) = apply(&q.expect("valid"), &chain);
        let expected = total.transform_point3(apex);
        let error = (q.frame().centre - expected).length();
        let bound = 1e-9 * 1e-3 + 8.0 * EPS * expected.length();
        assert!(error <= bound, "{name}: off by {error:e} (bound {bound:e})");
    }
}

#[test]
fn recentring_recovers_well_conditioned_coefficients() {
    // A sphere of radius 1 at (1e3, 0, 0) written about the world origin: j = 1e6 − 1.
    let q = raw(
        DVec3::ZERO,
        [1.0, 1.0, 1.0, 0.0, 0.0, 0.0, -1e3, 0.0, 0.0, 1e6 - 1.0],
    );
    let r = q.recentred();
    assert!((r.origin() - DVec3::new(1e3, 0.0, 0.0)).length() <= 1e-12 * 1e3);
    let k = r.coefficients();
    assert!(k[6..9].iter().all(|c| c.abs() <= 1e-9), "{k:?}");
    assert!((k[9] + 1.0).abs() <= 1e-9, "{k:?}");
    assert_eq!(r.kind(), QuadricKind::Sphere);
    // The min-norm centre of a cylinder written about an off-axis origin is the nearest axis point.
    let cylinder = Quadric::cylinder(DVec3::new(5.0, 7.0, 0.0), DVec3::Z, 1.0)
        .unwrap()
        .with_origin(DVec3::new(0.0, 0.0, 3.0));
    let c = cylinder.min_norm_centre(&Tolerances::default());
    assert!((c - DVec3::new(5.0, 7.0, 3.0)).length() <= 1e-12, "{c}");
}

#[test]
fn projective_transforms_keep_inside_and_outside() {
    // A perspective map (w = 1 + z/10): points keep their side of the sphere where w > 0.
    let q = Quadric::sphere(DVec3::new(0.5, -0.25, 1.0), 1.0).unwrap();
    let mut m = DMat4::IDENTITY;
    m.z_axis.w = 0.1;
    let t = q.transformed(&m).expect("invertible");
    let mut rng = Rng::new(77);
    for _ in 0..500 {
        let p = DVec3::new(0.5, -0.25, 1.0) + rng.direction() * rng.range(0.0, 2.0);
        let w = 1.0 + 0.1 * p.z;
        let image = DVec3::new(p.x, p.y, p.z) / w;
        let (v, err) = q.value_with_error(p);
        if v.abs() > 1e-9 {
            assert_eq!(v.signum(), t.value(image).signum(), "{p} (err {err:e})");
        }
    }
    // The sphere's centre is mapped to the new origin.
    assert!((t.origin() - DVec3::new(0.5, -0.25, 1.0) / 1.1).length() <= 1e-15);
}

#[test]
fn coincident_quadrics_compare_equal_far_away() {
    // The same sphere reached two ways, at 1e6: equal to 1e-12 of the largest coefficient.
    let direct = Quadric::sphere(DVec3::new(1e6, 2e6, -3e6), 1e-3).unwrap();
    let (built, _) = apply(
        &Quadric::sphere(DVec3::ZERO, 1.0).unwrap(),
        &[scale(1e-3), rotate(41), translate(1e6, 2e6, -3e6)],
    );
    assert!(direct.approx_eq_up_to_scale(&built, 1e-12));
    assert!(built.approx_eq_up_to_scale(&direct, 1e-12));
    assert!(!direct.approx_eq_up_to_scale(&built.negated(), 1e-3));
    // A radius off by one part in 1e6 is a different sphere at this tolerance.
    let bigger = Quadric::sphere(DVec3::new(1e6, 2e6, -3e6), 1e-3 * (1.0 + 1e-6)).unwrap();
    assert!(!direct.approx_eq_up_to_scale(&bigger, 1e-9));
    // Two halves of a slab are distinct half-spaces; the same plane with opposite normals too.
    let up = Quadric::half_space(DVec3::new(0.0, 0.0, 1e6), DVec3::Z).unwrap();
    let down = Quadric::half_space(DVec3::new(0.0, 0.0, 1e6), -DVec3::Z).unwrap();
    assert!(!up.approx_eq_up_to_scale(&down, 1e-3));
    assert!(up.approx_eq_up_to_scale(&down.negated(), 0.0));
    // The same plane through a different point of it.
    let shifted = Quadric::half_space(DVec3::new(5e5, -5e5, 1e6), DVec3::Z * 3.0).unwrap();
    assert!(up.approx_eq_up_to_scale(&shifted, 1e-15));
}
