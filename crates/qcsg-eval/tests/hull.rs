//! `hull()`: convex polytopes and balls (or circles) of one radius, checked against an
//! independent distance to the convex hull of the centres (Frank–Wolfe with its duality gap,
//! which brackets the distance, so only points too close to the surface to tell are skipped),
//! stiff placements, 2-D hulls, and the errors for hulls not bounded by quadrics.

mod common;

use common::{assert_refused_at_both_parts, codes, eval};
use glam::DVec3;
use qcsg_csg::{DnfOptions, build_dnf};
use qcsg_testkit::Rng;

/// Bounds `[lo, hi]` on the squared distance from `p` to the convex hull of `points`.
fn distance2_bounds(p: DVec3, points: &[DVec3]) -> (f64, f64) {
    // Start at the nearest point; Frank–Wolfe steps towards the vertex minimising the gradient.
    let mut x = *points
        .iter()
        .min_by(|a, b| {
            (**a - p)
                .length_squared()
                .total_cmp(&(**b - p).length_squared())
        })
        .expect("points");
    let mut lower = 0.0f64;
    for _ in 0..3000 {
        let grad = 2.0 * (x - p);
        let s = *points
            .iter()
            .min_by(|a, b| grad.dot(**a).total_cmp(&grad.dot(**b)))
            .expect("points");
        let gap = grad.dot(x - s);
        let f = (x - p).length_squared();
        lower = lower.max(f - gap);
        let d = s - x;
        let dd = d.length_squared();
        if dd == 0.0 || gap <= 1e-15 * f.max(1e-300) {
            break;
        }
        // Exact line search on the quadratic.
        let t = ((p - x).dot(d) / dd).clamp(0.0, 1.0);
        x += t * d;
    }
    (lower.max(0.0), (x - p).length_squared())
}

fn fmt(v: DVec3) -> String {
    format!("[{:e}, {:e}, {:e}]", v.x, v.y, v.z)
}

/// Random points around `centres` compared with "distance to their hull ≤ r" on the DAG and the
/// DNF; returns how many were inside and outside.
fn compare(text: &str, centres: &[DVec3], r: f64, scale: f64, rng: &mut Rng) -> (usize, usize) {
    let e = eval(text);
    assert!(!e.has_errors(), "{text}: {:?}", e.diagnostics);
    let dnf = build_dnf(&e.dag, &DnfOptions::default()).expect("a solid");
    let min = centres.iter().fold(DVec3::INFINITY, |m, c| m.min(*c)) - (r + 0.3 * scale);
    let max = centres.iter().fold(DVec3::NEG_INFINITY, |m, c| m.max(*c)) + (r + 0.3 * scale);
    let margin = 1e-6 * scale;
    let (mut inside, mut outside) = (0, 0);
    for _ in 0..300 {
        let p = rng.in_box(min, max);
        let (lo, hi) = distance2_bounds(p, centres);
        let expected = if r > 0.0 {
            if hi.sqrt() < r - margin {
                true
            } else if lo.sqrt() > r + margin {
                false
            } else {
                continue;
            }
        } else if hi < (1e-9 * scale).powi(2) {
            true
        } else if lo.sqrt() > margin {
            false
        } else {
            continue;
        };
        assert_eq!(e.dag.contains(p), expected, "{text}: DAG at {}", fmt(p));
        assert_eq!(dnf.contains(p), expected, "{text}: DNF at {}", fmt(p));
        if expected {
            inside += 1;
        } else {
            outside += 1;
        }
    }
    (inside, outside)
}

fn balls_scene(centres: &[DVec3], r: f64) -> String {
    let children: String = centres
        .iter()
        .map(|c| format!("translate({}) sphere({r:e});", fmt(*c)))
        .collect();
    format!("hull() {{ {children} }}")
}

fn random_centres(rng: &mut Rng, n: usize, offset: DVec3, scale: f64) -> Vec<DVec3> {
    (0..n)
        .map(|_| offset + scale * rng.in_box(DVec3::splat(-1.0), DVec3::ONE))
        .collect()
}

#[test]
fn random_balls_of_one_radius_match_the_distance_to_the_centres_hull() {
    let mut rng = Rng::new(39);
    let (mut inside, mut outside) = (0, 0);
    for case in 0..24 {
        let (offset, scale) = match case % 3 {
            0 => (DVec3::ZERO, 1.0),
            1 => (DVec3::new(1e6, -1e6, 1e6), 1.0),
            _ => (DVec3::new(0.002, 0.0, -0.001), 1e-3),
        };
        let n = 1 + case % 8;
        let centres = random_centres(&mut rng, n, offset, scale);
        let r = scale * rng.range(0.05, 0.6);
        let (i, o) = compare(&balls_scene(&centres, r), &centres, r, scale, &mut rng);
        inside += i;
        outside += o;
    }
    assert!(inside > 500 && outside > 500, "{inside} in, {outside} out");
}

#[test]
fn random_cubes_match_the_hull_of_their_corners() {
    let mut rng = Rng::new(7);
    let (mut inside, mut outside) = (0, 0);
    for case in 0..12 {
        let (offset, scale) = if case % 2 == 0 {
            (DVec3::ZERO, 1.0)
        } else {
            (DVec3::splat(1e6), 1e-3)
        };
        let n = 1 + case % 5;
        let mut corners = Vec::new();
        let mut children = String::new();
        for c in random_centres(&mut rng, n, offset, scale) {
            let size = scale * rng.range(0.05, 0.5);
            children += &format!("translate({}) cube({size:e});", fmt(c));
            for k in 0..8 {
                let bit = |b: usize| if k >> b & 1 == 1 { size } else { 0.0 };
                corners.push(c + DVec3::new(bit(0), bit(1), bit(2)));
            }
        }
        let text = format!("hull() {{ {children} }}");
        let (i, o) = compare(&text, &corners, 0.0, scale, &mut rng);
        inside += i;
        outside += o;
    }
    assert!(inside > 100 && outside > 500, "{inside} in, {outside} out");
}

#[test]
fn degenerate_centres_give_capsules_discs_and_balls() {
    let mut rng = Rng::new(3);
    // Collinear, nearly collinear, coplanar, coincident and single centres.
    let cases: Vec<Vec<DVec3>> = vec![
        vec![
            DVec3::ZERO,
            DVec3::new(4.0, 0.0, 0.0),
            DVec3::new(2.0, 0.0, 0.0),
        ],
        vec![
            DVec3::ZERO,
            DVec3::new(4.0, 1e-9, 0.0),
            DVec3::new(2.0, 0.0, 1e-9),
        ],
        vec![
            DVec3::ZERO,
            DVec3::new(3.0, 0.0, 0.0),
            DVec3::new(3.0, 2.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
        ],
        vec![DVec3::ONE, DVec3::ONE],
        vec![DVec3::new(1e6, 1e6, 1e6)],
    ];
    for centres in cases {
        let (i, o) = compare(&balls_scene(&centres, 0.5), &centres, 0.5, 1.0, &mut rng);
        assert!(i > 5 && o > 5, "{centres:?}: {i} in, {o} out");
    }
}

#[test]
fn the_rounded_box_and_the_capsule_of_openscads_examples() {
    let rounded = "r = 1; s = 10; hull() for (x = [r, s - r], y = [r, s - r], z = [r, s - r]) translate([x, y, z]) sphere(r);";
    let e = eval(rounded);
    assert!(!e.has_errors(), "{:?}", e.diagnostics);
    let corner = DVec3::splat(1.0) - DVec3::splat(1.0 / 3f64.sqrt()) * 1.0;
    for (p, inside) in [
        (DVec3::splat(5.0), true),
        (DVec3::new(5.0, 5.0, 0.01), true),
        (DVec3::new(5.0, 5.0, -0.01), false),
        (DVec3::new(0.5, 0.5, 5.0), true),
        (DVec3::new(0.2, 0.2, 5.0), false),
        (corner + DVec3::splat(0.01), true),
        (corner - DVec3::splat(0.01), false),
    ] {
        assert_eq!(e.dag.contains(p), inside, "rounded box at {p}");
    }
    let capsule = "hull() { sphere(2); translate([10, 0, 0]) sphere(2); }";
    let e = eval(capsule);
    assert!(!e.has_errors(), "{:?}", e.diagnostics);
    for (p, inside) in [
        (DVec3::new(5.0, 1.99, 0.0), true),
        (DVec3::new(5.0, 0.0, 2.01), false),
        (DVec3::new(11.99, 0.0, 0.0), true),
        (DVec3::new(12.01, 0.0, 0.0), false),
    ] {
        assert_eq!(e.dag.contains(p), inside, "capsule at {p}");
    }
}

#[test]
fn flat_or_empty_hulls_have_no_volume() {
    for text in [
        "hull() { }",
        "hull() { cube([1, 1, 0]); }",
        "hull() { sphere(0); }",
    ] {
        let e = eval(text);
        assert!(!e.has_errors(), "{text}: {:?}", e.diagnostics);
        assert!(!e.dag.contains(DVec3::splat(0.5)), "{text}");
    }
}

#[test]
fn two_d_hulls_of_squares_polygons_and_circles() {
    let e = eval(
        "linear_extrude(1) hull() { square(2); translate([6, 0]) square(2); polygon([[3, 5], [4, 6], [2, 6]]); }",
    );
    assert!(!e.has_errors(), "{:?}", e.diagnostics);
    for (x, y, inside) in [
        (4.0, 1.0, true),
        (3.0, 5.9, true),
        (1.0, 3.0, true),
        (0.5, 4.0, false),
        (7.9, 1.9, true),
        (7.5, 3.5, false),
    ] {
        assert_eq!(
            e.dag.contains(DVec3::new(x, y, 0.5)),
            inside,
            "polygons at ({x}, {y})"
        );
    }
    let e = eval(
        "linear_extrude(1) hull() { circle(1); translate([5, 0]) circle(1); translate([0, 4]) circle(1); }",
    );
    assert!(!e.has_errors(), "{:?}", e.diagnostics);
    for (x, y, inside) in [
        (2.5, -0.99, true),
        (2.5, -1.01, false),
        (-0.99, 2.0, true),
        (-1.01, 2.0, false),
        (5.99, 0.0, true),
        (6.01, 0.0, false),
        (2.0, 2.0, true),
    ] {
        assert_eq!(
            e.dag.contains(DVec3::new(x, y, 0.5)),
            inside,
            "circles at ({x}, {y})"
        );
    }
}

#[test]
fn hulls_not_bounded_by_quadrics_are_refused_at_their_parts() {
    for (text, part) in [
        ("hull() { scale([1, 2, 1]) sphere(1); }", "sphere(1)"),
        (
            "hull() { cylinder(h = 1, r = 1); rotate([0, 90, 0]) cylinder(h = 1, r = 1); }",
            "cylinder(h = 1, r = 1)",
        ),
        ("hull() { cylinder(h = 1, r = 1); sphere(1); }", "sphere(1)"),
        (
            "hull() { difference() { cube(2); cube(1); } }",
            "difference()",
        ),
        ("hull() { halfspace([0, 0, 1]); }", "halfspace([0, 0, 1])"),
    ] {
        let e = eval(text);
        assert_eq!(codes(&e), vec!["E0301"], "{text}: {:?}", e.diagnostics);
        let d = &e.diagnostics[0];
        assert!(
            d.labels
                .iter()
                .any(|l| text[l.span.start as usize..l.span.end as usize].starts_with(part)),
            "{text}: {:?}",
            d.labels
        );
    }
}

#[test]
fn parallel_cylinders_of_one_height_are_their_discs_hull_extruded() {
    // The rounded plate of four vertical cylinders, and the same turned and moved far away.
    let plate = "hull() for (x = [1, 9], y = [1, 5]) translate([x, y, 0]) cylinder(h = 2, r = 1);";
    let cases = [
        (DVec3::new(5.0, 3.0, 1.0), true),
        (DVec3::new(5.0, 0.01, 1.0), true),
        (DVec3::new(5.0, -0.01, 1.0), false),
        (DVec3::new(5.0, 3.0, 2.01), false),
        (DVec3::new(5.0, 3.0, 1.99), true),
        (DVec3::new(0.25, 0.25, 1.0), false),
        (DVec3::new(0.32, 0.32, 1.0), true),
    ];
    let e = eval(plate);
    assert!(!e.has_errors(), "{:?}", e.diagnostics);
    let dnf = build_dnf(&e.dag, &DnfOptions::default()).expect("a solid");
    for (p, inside) in cases {
        assert_eq!(e.dag.contains(p), inside, "plate at {p}");
        assert_eq!(dnf.contains(p), inside, "plate DNF at {p}");
    }
    let far = format!("translate([1e6, -1e6, 5e5]) rotate([30, 60, 10]) {plate}");
    let e = eval(&far);
    assert!(!e.has_errors(), "{:?}", e.diagnostics);
    let m = glam::DMat4::from_translation(DVec3::new(1e6, -1e6, 5e5))
        * glam::DMat4::from_euler(
            glam::EulerRot::ZYX,
            10f64.to_radians(),
            60f64.to_radians(),
            30f64.to_radians(),
        );
    for (p, inside) in cases {
        let q = m.transform_point3(p);
        assert_eq!(e.dag.contains(q), inside, "far plate at {p}");
    }
}

#[test]
fn hull_and_minkowski_sizes_are_limits_with_their_flags() {
    use common::eval_with;
    use qcsg_eval::EvalOptions;
    let cases = [
        (
            "hull() for (i = [0:9]) translate([i, i * i, i * i * i]) cube(0.1);",
            EvalOptions {
                max_hull_points: 20,
                ..EvalOptions::default()
            },
            "E0570",
            "--max-hull-points",
        ),
        (
            "hull() { sphere(1); translate([3, 1, 0]) sphere(2); cube(1); }",
            EvalOptions {
                max_hull_points: 3,
                ..EvalOptions::default()
            },
            "E0570",
            "--max-hull-points",
        ),
        (
            "hull() cube(1);",
            EvalOptions {
                max_part_planes: 4,
                ..EvalOptions::default()
            },
            "E0571",
            "--max-part-planes",
        ),
        (
            "minkowski() { union() { cube(1); translate([3, 0, 0]) cube(1); } \
             union() { sphere(1); translate([0, 5, 0]) sphere(1); } }",
            EvalOptions {
                max_minkowski_parts: 3,
                ..EvalOptions::default()
            },
            "E0572",
            "--max-minkowski-parts",
        ),
    ];
    for (text, options, code, flag) in cases {
        let e = eval_with(text, &options);
        assert_eq!(codes(&e), vec![code], "{text}: {:?}", e.diagnostics);
        let d = &e.diagnostics[0];
        assert!(
            d.help.as_deref().is_some_and(|h| h.contains(flag)),
            "{text}: {:?}",
            d.help
        );
        // Within the default limits the same program evaluates.
        let e = eval(text);
        assert!(!e.has_errors(), "{text}: {:?}", e.diagnostics);
    }
}

#[test]
fn a_pair_that_is_not_quadric_together_is_named_at_both_parts() {
    for (text, first, second) in [
        (
            "hull() { cylinder(h = 1, r = 1); rotate([0, 90, 0]) cylinder(h = 2, r = 1); }",
            "cylinder(h = 1, r = 1)",
            "cylinder(h = 2, r = 1)",
        ),
        (
            "hull() { cylinder(h = 1, r = 1); translate([3, 0, 0]) sphere(1); }",
            "sphere(1)",
            "cylinder(h = 1, r = 1)",
        ),
    ] {
        assert_refused_at_both_parts(text, [first, second]);
    }
}
