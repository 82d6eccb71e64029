//! `minkowski()` of convex polytopes (and unions of them) with circular cylinders and cones,
//! checked against
//! an independent sum: the support function of each convex part of the sum (the sum of the
//! parts' support functions: corners, balls, discs) sampled in many directions, which is the
//! hull of the brute-force sum of the parts' sampled points, with the sampling error bounded so
//! that only points too close to the surface to tell are skipped.

mod common;
mod support;

use common::assert_refused_at_both_parts;
use glam::{DMat4, DVec3, EulerRot};
use qcsg_testkit::Rng;
use support::{Convex, DIRECTIONS, directions};

/// A box `[0, size]` turned by `angles` (OpenSCAD's `rotate`) and moved by `at`.
struct Box3 {
    at: DVec3,
    angles: DVec3,
    size: DVec3,
}

impl Box3 {
    fn random(rng: &mut Rng, turn_all: bool) -> Box3 {
        let angles = if turn_all {
            rng.in_box(DVec3::splat(0.0), DVec3::splat(360.0))
        } else {
            DVec3::new(0.0, 0.0, rng.range(0.0, 360.0))
        };
        Box3 {
            at: rng.in_box(DVec3::splat(-2.0), DVec3::splat(2.0)),
            angles,
            size: DVec3::new(
                rng.range(0.5, 4.0),
                rng.range(0.5, 4.0),
                rng.range(0.5, 3.0),
            ),
        }
    }

    fn scad(&self) -> String {
        let (a, s, r) = (self.at, self.size, self.angles);
        format!(
            "translate([{:e}, {:e}, {:e}]) rotate([{:e}, {:e}, {:e}]) cube([{:e}, {:e}, {:e}]);",
            a.x, a.y, a.z, r.x, r.y, r.z, s.x, s.y, s.z
        )
    }

    fn part(&self) -> Convex {
        let r = self.angles * std::f64::consts::PI / 180.0;
        let m = DMat4::from_translation(self.at) * DMat4::from_euler(EulerRot::ZYX, r.z, r.y, r.x);
        let points: Vec<DVec3> = (0..8)
            .map(|k| {
                let c = DVec3::new(
                    f64::from(k & 1),
                    f64::from((k >> 1) & 1),
                    f64::from((k >> 2) & 1),
                );
                m.transform_point3(c * self.size)
            })
            .collect();
        Convex::points(&points)
    }
}

/// A cylinder of radius `r` from height `z0` to `z0 + h` about the vertical line through `at`.
fn cylinder(at: DVec3, r: f64, h: f64) -> (String, Convex) {
    (
        format!(
            "translate([{:e}, {:e}, {:e}]) cylinder(h = {:e}, r = {:e});",
            at.x, at.y, at.z, h, r
        ),
        Convex {
            discs: vec![(at, r), (at + DVec3::Z * h, r)],
            ball: 0.0,
            balls: Vec::new(),
        },
    )
}

/// Compares the sum of `children` (each a union of convex parts) with the oracle at random
/// points, seen through `frame`; returns how many were inside and outside.
fn compare(text: &str, children: &[Vec<Convex>], frame: DMat4, rng: &mut Rng) -> (usize, usize) {
    let mut parts = children[0].clone();
    for child in &children[1..] {
        parts = parts
            .iter()
            .flat_map(|a| child.iter().map(move |b| a.sum(b)))
            .collect();
    }
    support::compare(text, &parts, frame, rng)
}

#[test]
fn the_lattices_cover_the_sphere() {
    let mut rng = Rng::new(1);
    for n in DIRECTIONS {
        let (dirs, delta) = directions(n);
        for _ in 0..300 {
            let u = rng.direction();
            let nearest = dirs
                .iter()
                .map(|v| (*v - u).length())
                .fold(f64::INFINITY, f64::min);
            assert!(nearest <= delta, "{n}, {u}: {nearest} > {delta}");
        }
    }
}

#[test]
fn random_boxes_with_a_cylinder_match_the_sampled_sum() {
    let mut rng = Rng::new(39);
    let (mut inside, mut outside) = (0, 0);
    for case in 0..10 {
        let b = Box3::random(&mut rng, case % 2 == 1);
        let at = rng.in_box(DVec3::splat(-1.0), DVec3::splat(1.0));
        let (cyl, part) = cylinder(at, rng.range(0.3, 1.5), rng.range(0.1, 2.0));
        let text = format!("minkowski() {{ {} {cyl} }}", b.scad());
        let (i, o) = compare(
            &text,
            &[vec![b.part()], vec![part]],
            DMat4::IDENTITY,
            &mut rng,
        );
        inside += i;
        outside += o;
    }
    assert!(
        inside > 150 && outside > 150,
        "{inside} inside, {outside} outside"
    );
}

#[test]
fn non_convex_children_and_parallel_cylinders_match_the_sampled_sum() {
    let mut rng = Rng::new(5);
    for case in 0..6 {
        let (a, b) = (
            Box3::random(&mut rng, case % 2 == 0),
            Box3::random(&mut rng, false),
        );
        let (c1, p1) = cylinder(DVec3::ZERO, rng.range(0.2, 1.0), rng.range(0.2, 1.0));
        let (c2, p2) = cylinder(
            DVec3::new(0.3, 0.0, -0.5),
            rng.range(0.2, 1.0),
            rng.range(0.2, 1.0),
        );
        // A union of two boxes (non-convex) summed with two parallel cylinders of different
        // radii one after the other, and with their union.
        let text = format!(
            "minkowski() {{ union() {{ {} {} }} {c1} {c2} }}",
            a.scad(),
            b.scad()
        );
        compare(
            &text,
            &[vec![a.part(), b.part()], vec![p1.clone()], vec![p2.clone()]],
            DMat4::IDENTITY,
            &mut rng,
        );
        let text = format!("minkowski() {{ {} union() {{ {c1} {c2} }} }}", a.scad());
        compare(
            &text,
            &[vec![a.part()], vec![p1, p2]],
            DMat4::IDENTITY,
            &mut rng,
        );
    }
}

/// A cone from radius `r1` at height `at.z` to `r2` at `at.z + h` about the vertical line
/// through `at`.
fn cone(at: DVec3, r1: f64, r2: f64, h: f64) -> (String, Convex) {
    (
        format!(
            "translate([{:e}, {:e}, {:e}]) cylinder(h = {:e}, r1 = {:e}, r2 = {:e});",
            at.x, at.y, at.z, h, r1, r2
        ),
        Convex {
            discs: vec![(at, r1), (at + DVec3::Z * h, r2)],
            ball: 0.0,
            balls: Vec::new(),
        },
    )
}

#[test]
fn boxes_with_a_cone_match_the_sampled_sum() {
    let mut rng = Rng::new(41);
    let (mut inside, mut outside) = (0, 0);
    for case in 0..8 {
        let b = Box3::random(&mut rng, case % 2 == 1);
        let at = rng.in_box(DVec3::splat(-1.0), DVec3::splat(1.0));
        // A frustum either way up, and a cone to a point.
        let (r1, r2) = match case % 3 {
            0 => (rng.range(0.3, 1.5), rng.range(0.1, 0.3)),
            1 => (rng.range(0.1, 0.5), rng.range(0.6, 1.5)),
            _ => (rng.range(0.3, 1.5), 0.0),
        };
        let (c, part) = cone(at, r1, r2, rng.range(0.3, 2.0));
        let text = format!("minkowski() {{ {} {c} }}", b.scad());
        let (i, o) = compare(
            &text,
            &[vec![b.part()], vec![part]],
            DMat4::IDENTITY,
            &mut rng,
        );
        inside += i;
        outside += o;
    }
    // A non-convex child with a cone and a cylinder one after the other.
    let (a, b) = (Box3::random(&mut rng, false), Box3::random(&mut rng, true));
    let (c1, p1) = cone(DVec3::ZERO, 1.0, 0.25, 1.0);
    let (c2, p2) = cylinder(DVec3::new(0.0, 0.5, 0.0), 0.5, 0.5);
    let text = format!(
        "minkowski() {{ union() {{ {} {} }} {c1} {c2} }}",
        a.scad(),
        b.scad()
    );
    compare(
        &text,
        &[vec![a.part(), b.part()], vec![p1], vec![p2]],
        DMat4::IDENTITY,
        &mut rng,
    );
    assert!(
        inside > 100 && outside > 100,
        "{inside} inside, {outside} outside"
    );
}

#[test]
fn turned_far_and_tiny_sums_match_the_sampled_sum() {
    let mut rng = Rng::new(8);
    let b = Box3 {
        at: DVec3::ZERO,
        angles: DVec3::new(0.0, 0.0, 25.0),
        size: DVec3::new(4.0, 3.0, 1.0),
    };
    let (cyl, part) = cylinder(DVec3::ZERO, 1.0, 0.5);
    let sum = format!("minkowski() {{ {} {cyl} }}", b.scad());
    for (outer, frame) in support::turned_far_and_tiny() {
        let text = format!("{outer} {sum}");
        let (i, o) = compare(
            &text,
            &[vec![b.part()], vec![part.clone()]],
            frame,
            &mut rng,
        );
        assert!(i > 10 && o > 10, "{text}: {i} in, {o} out");
    }
}

#[test]
fn a_cylinder_with_a_ball_or_a_crossed_cylinder_is_named_at_both_parts() {
    for (text, first, second) in [
        (
            "minkowski() { sphere(1); cylinder(h = 1, r = 1); }",
            "sphere(1)",
            "cylinder(h = 1, r = 1)",
        ),
        (
            "minkowski() { cylinder(h = 1, r = 1); rotate([90, 0, 0]) cylinder(h = 2, r = 1); }",
            "cylinder(h = 1, r = 1)",
            "cylinder(h = 2, r = 1)",
        ),
    ] {
        assert_refused_at_both_parts(text, [first, second]);
    }
}
