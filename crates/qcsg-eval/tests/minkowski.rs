//! `minkowski()`: unions of convex polytopes and balls, checked against the exact distance to
//! the boxes (a point is in box ⊕ ball(r) exactly when its distance to the box is at most r),
//! far and tiny placements, and the refusals.

mod common;

use common::{codes, eval};
use glam::{DMat4, DVec3};
use qcsg_csg::{DnfOptions, build_dnf};
use qcsg_testkit::Rng;

/// A box `[0, size]` turned about z by `angle` degrees, then moved by `at`.
struct Box3 {
    at: DVec3,
    angle: f64,
    size: DVec3,
}

impl Box3 {
    fn scad(&self) -> String {
        format!(
            "translate([{:e}, {:e}, {:e}]) rotate({:e}) cube([{:e}, {:e}, {:e}]);",
            self.at.x, self.at.y, self.at.z, self.angle, self.size.x, self.size.y, self.size.z
        )
    }

    fn frame(&self) -> DMat4 {
        DMat4::from_translation(self.at) * DMat4::from_rotation_z(self.angle.to_radians())
    }

    fn distance(&self, p: DVec3) -> f64 {
        let local = self.frame().inverse().transform_point3(p);
        (local - local.clamp(DVec3::ZERO, self.size)).length()
    }
}

#[test]
fn random_boxes_grown_by_a_ball_match_the_distance_to_the_boxes() {
    let mut rng = Rng::new(6);
    let (mut inside, mut outside) = (0, 0);
    for case in 0..18 {
        let (offset, scale) = match case % 3 {
            0 => (DVec3::ZERO, 1.0),
            1 => (DVec3::new(-1e6, 1e6, 1e6), 1.0),
            _ => (DVec3::new(0.001, 0.002, 0.0), 1e-3),
        };
        // One box, or a non-convex union of two.
        let boxes: Vec<Box3> = (0..1 + case % 2)
            .map(|_| Box3 {
                at: offset + scale * rng.in_box(DVec3::splat(-1.0), DVec3::ONE),
                angle: rng.range(-90.0, 90.0),
                size: scale * rng.in_box(DVec3::splat(0.2), DVec3::splat(1.5)),
            })
            .collect();
        let r = scale * rng.range(0.05, 0.5);
        let children: String = boxes.iter().map(Box3::scad).collect();
        let text = format!("minkowski() {{ union() {{ {children} }} sphere({r:e}); }}");
        let e = eval(&text);
        assert!(!e.has_errors(), "{text}: {:?}", e.diagnostics);
        let dnf = build_dnf(&e.dag, &DnfOptions::default()).expect("a solid");
        for _ in 0..200 {
            // Near a box: a point of its frame around it, mapped to the world.
            let b = &boxes[rng.below(boxes.len())];
            let pad = DVec3::splat(r + 0.2 * scale);
            let local = rng.in_box(-pad, b.size + pad);
            let p = b.frame().transform_point3(local);
            let d = boxes
                .iter()
                .map(|b| b.distance(p))
                .fold(f64::INFINITY, f64::min);
            if (d - r).abs() < 1e-6 * scale {
                continue;
            }
            let expected = d < r;
            assert_eq!(e.dag.contains(p), expected, "{text}: DAG at {p}");
            assert_eq!(dnf.contains(p), expected, "{text}: DNF at {p}");
            if expected {
                inside += 1;
            } else {
                outside += 1;
            }
        }
    }
    assert!(inside > 300 && outside > 300, "{inside} in, {outside} out");
}

#[test]
fn sums_of_boxes_and_balls() {
    for (text, cases) in [
        (
            // Two boxes: a box.
            "minkowski() { cube([2, 1, 1]); translate([1, 1, 1]) cube(1); }",
            vec![
                (DVec3::new(3.9, 2.9, 2.9), true),
                (DVec3::new(4.1, 2.0, 2.0), false),
                (DVec3::new(0.9, 2.0, 2.0), false),
                (DVec3::new(2.0, 2.0, 0.9), false),
            ],
        ),
        (
            // Two balls: a ball of the summed radius about the summed centres.
            "minkowski() { translate([1, 0, 0]) sphere(1); translate([0, 2, 0]) sphere(0.5); }",
            vec![
                (DVec3::new(1.0, 2.0, 1.49), true),
                (DVec3::new(1.0, 2.0, 1.51), false),
            ],
        ),
        (
            // One child: itself.
            "minkowski() { cube(1); }",
            vec![(DVec3::splat(0.5), true), (DVec3::splat(1.1), false)],
        ),
    ] {
        let e = eval(text);
        assert!(!e.has_errors(), "{text}: {:?}", e.diagnostics);
        for (p, inside) in cases {
            assert_eq!(e.dag.contains(p), inside, "{text} at {p}");
        }
    }
}

#[test]
fn sums_not_bounded_by_quadrics_are_refused_at_their_parts() {
    for (text, part) in [
        (
            "minkowski() { cube(1); sphere(1); cylinder(h = 1, r = 1); }",
            "cylinder",
        ),
        (
            "minkowski() { cube(1); scale([1, 2, 1]) sphere(1); }",
            "sphere",
        ),
        (
            "minkowski() { difference() { cube(2); cube(1); } sphere(1); }",
            "difference",
        ),
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
        assert!(d.help.is_some());
    }
    let text = "linear_extrude(1) minkowski() { square(1); scale([2, 1]) circle(1); }";
    let e = eval(text);
    assert_eq!(codes(&e), vec!["E0301"], "{:?}", e.diagnostics);
}

#[test]
fn two_d_sums_are_rounded_polygons() {
    let p = |x: f64, y: f64| DVec3::new(x, y, 0.5);
    for (text, cases) in [
        (
            "linear_extrude(1) minkowski() { square(2); circle(1); }",
            vec![
                (p(1.0, -0.99), true),
                (p(1.0, -1.01), false),
                (p(-0.65, -0.65), true),
                (p(-0.75, -0.75), false),
                (p(2.5, 2.5), true),
            ],
        ),
        (
            // A non-convex L grown by 0.5: its reflex corner stays sharp.
            "linear_extrude(1) minkowski() { polygon([[0, 0], [4, 0], [4, 1], [1, 1], [1, 4], [0, 4]]); circle(0.5); }",
            vec![
                (p(1.45, 1.45), true),
                (p(1.55, 1.55), false),
                (p(4.45, 0.5), true),
                (p(4.55, 0.5), false),
            ],
        ),
        (
            "linear_extrude(1) minkowski() { square(2); translate([1, 1]) square(1); }",
            vec![
                (p(3.9, 3.9), true),
                (p(0.9, 2.0), false),
                (p(4.1, 2.0), false),
            ],
        ),
    ] {
        let e = eval(text);
        assert!(!e.has_errors(), "{text}: {:?}", e.diagnostics);
        let dnf = build_dnf(&e.dag, &DnfOptions::default()).expect("a solid");
        for (q, inside) in cases {
            assert_eq!(e.dag.contains(q), inside, "{text} at {q}");
            assert_eq!(dnf.contains(q), inside, "{text}: DNF at {q}");
        }
    }
}
