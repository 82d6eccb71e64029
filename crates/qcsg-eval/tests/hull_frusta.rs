//! `hull()` of cylinders and cones with parallel axes at any heights, with polytopes, checked
//! against the hull of their discs and corners by their sampled support function
//! (`support`), and the refusals that remain.

mod common;
mod support;

use common::{codes, eval};
use glam::{DMat4, DVec3};
use qcsg_testkit::Rng;
use support::Convex;

/// A random cylinder or cone about a vertical axis: its text and its two discs.
fn random_frustum(rng: &mut Rng) -> (String, [(DVec3, f64); 2]) {
    let at = DVec3::new(
        rng.range(-4.0, 4.0),
        rng.range(-4.0, 4.0),
        rng.range(-2.0, 2.0),
    );
    let h = rng.range(0.3, 3.0);
    let (r1, r2) = match rng.below(4) {
        0 => {
            let r = rng.range(0.2, 1.5);
            (r, r)
        }
        1 => (rng.range(0.2, 1.5), 0.0),
        _ => (rng.range(0.1, 1.5), rng.range(0.1, 1.5)),
    };
    (
        format!(
            "translate([{:e}, {:e}, {:e}]) cylinder(h = {:e}, r1 = {:e}, r2 = {:e});",
            at.x, at.y, at.z, h, r1, r2
        ),
        [(at, r1), (at + DVec3::Z * h, r2)],
    )
}

#[test]
fn random_parallel_cylinders_and_cones_match_the_sampled_hull() {
    let mut rng = Rng::new(39);
    let (mut inside, mut outside) = (0, 0);
    for case in 0..12 {
        let mut text = String::from("hull() {");
        let mut discs = Vec::new();
        for _ in 0..1 + case % 4 {
            let (t, d) = random_frustum(&mut rng);
            text += " ";
            text += &t;
            discs.extend(d);
        }
        if case % 3 == 2 {
            // A cube beside them: its corners are discs of radius 0.
            let at = DVec3::new(
                rng.range(-4.0, 4.0),
                rng.range(-4.0, 4.0),
                rng.range(-2.0, 2.0),
            );
            text += &format!(" translate([{:e}, {:e}, {:e}]) cube(1);", at.x, at.y, at.z);
            for k in 0..8 {
                let c = DVec3::new(
                    f64::from(k & 1),
                    f64::from((k >> 1) & 1),
                    f64::from((k >> 2) & 1),
                );
                discs.push((at + c, 0.0));
            }
        }
        text += " }";
        let set = Convex {
            discs,
            ..Convex::default()
        };
        let (i, o) = support::compare(&text, &[set], DMat4::IDENTITY, &mut rng);
        inside += i;
        outside += o;
    }
    assert!(
        inside > 200 && outside > 200,
        "{inside} inside, {outside} outside"
    );
}

#[test]
fn turned_far_tiny_and_stiff_hulls_match_the_sampled_hull() {
    let mut rng = Rng::new(12);
    let tapered = "hull() { cylinder(h = 2, r1 = 2, r2 = 1); translate([6, 1, 1]) cylinder(h = 3, r = 0.5); translate([2, 5, -1]) cylinder(h = 1, r1 = 0, r2 = 1); }";
    let discs = vec![
        (DVec3::ZERO, 2.0),
        (DVec3::new(0.0, 0.0, 2.0), 1.0),
        (DVec3::new(6.0, 1.0, 1.0), 0.5),
        (DVec3::new(6.0, 1.0, 4.0), 0.5),
        (DVec3::new(2.0, 5.0, -1.0), 0.0),
        (DVec3::new(2.0, 5.0, 0.0), 1.0),
    ];
    let set = Convex {
        discs: discs.clone(),
        ball: 0.0,
        balls: Vec::new(),
    };
    let placements =
        std::iter::once((String::new(), DMat4::IDENTITY)).chain(support::turned_far_and_tiny());
    for (outer, frame) in placements {
        let text = format!("{outer} {tapered}");
        let (i, o) = support::compare(&text, std::slice::from_ref(&set), frame, &mut rng);
        assert!(i > 10 && o > 10, "{text}: {i} in, {o} out");
    }
    // Stiff: nearly equal radii, a cylinder inside another, equal heights, discs on one plane.
    for (text, discs) in [
        (
            "hull() { cylinder(h = 2, r1 = 1, r2 = 1.000000001); translate([5, 0, 1]) cylinder(h = 2, r = 1); }",
            vec![
                (DVec3::ZERO, 1.0),
                (DVec3::new(0.0, 0.0, 2.0), 1.000000001),
                (DVec3::new(5.0, 0.0, 1.0), 1.0),
                (DVec3::new(5.0, 0.0, 3.0), 1.0),
            ],
        ),
        (
            "hull() { cylinder(h = 4, r = 3); translate([1, 0, 1]) cylinder(h = 1, r1 = 1, r2 = 0.5); translate([8, 0, 0]) cylinder(h = 1, r = 1); }",
            vec![
                (DVec3::ZERO, 3.0),
                (DVec3::new(0.0, 0.0, 4.0), 3.0),
                (DVec3::new(8.0, 0.0, 0.0), 1.0),
                (DVec3::new(8.0, 0.0, 1.0), 1.0),
            ],
        ),
        (
            "hull() { cylinder(h = 2, r = 1); translate([6, 0, 0]) cylinder(h = 2, r1 = 2, r2 = 1); translate([3, 4, 0]) cylinder(h = 2, r = 1); }",
            vec![
                (DVec3::ZERO, 1.0),
                (DVec3::new(0.0, 0.0, 2.0), 1.0),
                (DVec3::new(6.0, 0.0, 0.0), 2.0),
                (DVec3::new(6.0, 0.0, 2.0), 1.0),
                (DVec3::new(3.0, 4.0, 0.0), 1.0),
                (DVec3::new(3.0, 4.0, 2.0), 1.0),
            ],
        ),
    ] {
        let set = Convex {
            discs,
            ..Convex::default()
        };
        let (i, o) = support::compare(text, &[set], DMat4::IDENTITY, &mut rng);
        assert!(i > 10 && o > 10, "{text}: {i} in, {o} out");
    }
}

#[test]
fn refusals_that_remain_name_both_parts() {
    for text in [
        "hull() { cylinder(h = 1, r = 1); rotate([0, 90, 0]) cylinder(h = 2, r1 = 1, r2 = 0.5); }",
        "hull() { cylinder(h = 1, r1 = 1, r2 = 0.5); translate([3, 0, 0]) sphere(1); }",
    ] {
        let e = eval(text);
        assert_eq!(codes(&e), vec!["E0301"], "{text}: {:?}", e.diagnostics);
        assert_eq!(e.diagnostics[0].labels.len(), 2, "{text}");
    }
    // qcsg's `cone` (apex at z = 0) is read as a cone too: its hull is itself.
    let e = eval("hull() { cone(h = 2, r = 1); }");
    assert!(!e.has_errors(), "{:?}", e.diagnostics);
    for (p, inside) in [
        (DVec3::new(0.45, 0.0, 1.0), true),
        (DVec3::new(0.55, 0.0, 1.0), false),
        (DVec3::new(0.0, 0.95, 1.95), true),
        (DVec3::new(0.0, 0.0, 2.05), false),
    ] {
        assert_eq!(e.dag.contains(p), inside, "cone at {p}");
    }
}
