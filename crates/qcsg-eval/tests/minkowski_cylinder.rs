//! `minkowski()` of convex polytopes (and unions of them) with circular cylinders, checked against
//! an independent sum: the support function of each convex part of the sum (the sum of the
//! parts' support functions: corners, balls, discs) sampled in many directions, which is the
//! hull of the brute-force sum of the parts' sampled points, with the sampling error bounded so
//! that only points too close to the surface to tell are skipped.

mod common;

use common::{codes, eval};
use glam::{DMat4, DVec3, EulerRot};
use qcsg_csg::{DnfOptions, build_dnf};
use qcsg_testkit::Rng;

/// Directions sampled on the sphere (Fibonacci lattices): a coarse one that settles most points
/// and a fine one for the rest.
const DIRECTIONS: [usize; 2] = [1_000, 20_000];

/// `n` directions and a bound on the distance from any unit vector to the nearest.
fn directions(n: usize) -> (Vec<DVec3>, f64) {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let count = n as f64;
    let dirs = (0..n)
        .map(|k| {
            let z = 1.0 - (2.0 * k as f64 + 1.0) / count;
            let rho = (1.0 - z * z).sqrt();
            let phi = golden * k as f64;
            DVec3::new(rho * phi.cos(), rho * phi.sin(), z)
        })
        .collect();
    // Each lattice point holds an area 4π/n; the cells are nearly hexagonal (covering radius
    // 0.62 √area), and 1.5 √area bounds them with room (checked by `the_lattices_cover_the_sphere`).
    (dirs, 1.5 * (4.0 * std::f64::consts::PI / count).sqrt())
}

/// A convex part: the hull of `points` grown by a ball of `ball` and a disc of `disc` square to
/// z.
#[derive(Clone)]
struct Part {
    points: Vec<DVec3>,
    ball: f64,
    disc: f64,
}

impl Part {
    fn sum(&self, other: &Part) -> Part {
        Part {
            points: self
                .points
                .iter()
                .flat_map(|a| other.points.iter().map(move |b| *a + *b))
                .collect(),
            ball: self.ball + other.ball,
            disc: self.disc + other.disc,
        }
    }

    /// The sampled `max over v of (v · p − h(v))` and its error bound.
    fn signed(&self, p: DVec3, dirs: &[DVec3], delta: f64) -> (f64, f64) {
        let o = self.points.iter().copied().sum::<DVec3>() / self.points.len() as f64;
        let q = p - o;
        let mut best = f64::NEG_INFINITY;
        for v in dirs {
            let h = self
                .points
                .iter()
                .map(|x| (*x - o).dot(*v))
                .fold(f64::NEG_INFINITY, f64::max)
                + self.ball
                + self.disc * v.truncate().length();
            best = best.max(v.dot(q) - h);
        }
        let reach = self
            .points
            .iter()
            .map(|x| (*x - o).length())
            .fold(0.0, f64::max);
        // v ↦ v·q − h(v) is Lipschitz with constant |q| + reach + ball + disc.
        (best, (q.length() + reach + self.ball + self.disc) * delta)
    }
}

/// `Some(inside)` where every part tells, `None` near the surface.
fn oracle(p: DVec3, parts: &[Part], lattices: &[(Vec<DVec3>, f64)], margin: f64) -> Option<bool> {
    let mut all_out = true;
    for part in parts {
        // A sampled value above 0 is a lower bound of a positive distance; one below minus its
        // error bound is an upper bound of a negative one; else the finer lattice decides.
        let mut told = None;
        for (dirs, delta) in lattices {
            let (f, error) = part.signed(p, dirs, *delta);
            if f > margin {
                told = Some(false);
                break;
            }
            if f < -(error + margin) {
                told = Some(true);
                break;
            }
        }
        match told {
            Some(true) => return Some(true),
            Some(false) => {}
            None => all_out = false,
        }
    }
    all_out.then_some(false)
}

/// A box `[0, size]` turned by `angles` (OpenSCAD's `rotate`) and moved by `at`.
struct Box3 {
    at: DVec3,
    angles: DVec3,
    size: DVec3,
}

impl Box3 {
    fn random(rng: &mut Rng, turn_all: bool) -> Box3 {
        let angles = if turn_all {
            DVec3::new(
                rng.range(0.0, 360.0),
                rng.range(0.0, 360.0),
                rng.range(0.0, 360.0),
            )
        } else {
            DVec3::new(0.0, 0.0, rng.range(0.0, 360.0))
        };
        Box3 {
            at: DVec3::new(
                rng.range(-2.0, 2.0),
                rng.range(-2.0, 2.0),
                rng.range(-2.0, 2.0),
            ),
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

    fn part(&self) -> Part {
        let r = self.angles * std::f64::consts::PI / 180.0;
        let m = DMat4::from_translation(self.at) * DMat4::from_euler(EulerRot::ZYX, r.z, r.y, r.x);
        let points = (0..8)
            .map(|k| {
                let c = DVec3::new(
                    f64::from(k & 1),
                    f64::from((k >> 1) & 1),
                    f64::from((k >> 2) & 1),
                );
                m.transform_point3(c * self.size)
            })
            .collect();
        Part {
            points,
            ball: 0.0,
            disc: 0.0,
        }
    }
}

/// A cylinder of radius `r` from height `z0` to `z0 + h` about the vertical line through `at`.
fn cylinder(at: DVec3, r: f64, h: f64) -> (String, Part) {
    (
        format!(
            "translate([{:e}, {:e}, {:e}]) cylinder(h = {:e}, r = {:e});",
            at.x, at.y, at.z, h, r
        ),
        Part {
            points: vec![at, at + DVec3::Z * h],
            ball: 0.0,
            disc: r,
        },
    )
}

/// Compares the sum of `children` (each a union of parts) with the oracle at random points,
/// seen through `frame`; returns how many were inside and outside.
fn compare(text: &str, children: &[Vec<Part>], frame: DMat4, rng: &mut Rng) -> (usize, usize) {
    let e = eval(text);
    assert!(!e.has_errors(), "{text}: {:?}", e.diagnostics);
    let dnf = build_dnf(&e.dag, &DnfOptions::default()).expect("a solid");
    let mut parts = children[0].clone();
    for child in &children[1..] {
        parts = parts
            .iter()
            .flat_map(|a| child.iter().map(move |b| a.sum(b)))
            .collect();
    }
    let lattices: Vec<(Vec<DVec3>, f64)> = DIRECTIONS.iter().map(|&n| directions(n)).collect();
    let grow = parts.iter().map(|p| p.ball + p.disc).fold(0.0, f64::max);
    let lo = parts
        .iter()
        .flat_map(|p| p.points.iter())
        .fold(DVec3::INFINITY, |m, x| m.min(*x))
        - (grow + 0.5);
    let hi = parts
        .iter()
        .flat_map(|p| p.points.iter())
        .fold(DVec3::NEG_INFINITY, |m, x| m.max(*x))
        + (grow + 0.5);
    let (mut inside, mut outside) = (0, 0);
    // The rounding of qcsg's coefficients, of the size of the scene and of its distance.
    let margin = 1e-9 * (hi - lo).max_element() + 1e-8;
    for _ in 0..150 {
        let p = rng.in_box(lo, hi);
        let Some(expected) = oracle(p, &parts, &lattices, margin) else {
            continue;
        };
        let q = frame.transform_point3(p);
        assert_eq!(e.dag.contains(q), expected, "{text} at {p}");
        assert_eq!(dnf.contains(q), expected, "DNF of {text} at {p}");
        if expected {
            inside += 1;
        } else {
            outside += 1;
        }
    }
    (inside, outside)
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
        let at = DVec3::new(
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
        );
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
    for (outer, frame) in [
        (
            "rotate([30, 60, 10])".to_string(),
            DMat4::from_euler(
                EulerRot::ZYX,
                10f64.to_radians(),
                60f64.to_radians(),
                30f64.to_radians(),
            ),
        ),
        (
            "translate([1e6, -2e6, 5e5]) rotate([90, 0, 0])".to_string(),
            DMat4::from_translation(DVec3::new(1e6, -2e6, 5e5))
                * DMat4::from_rotation_x(90f64.to_radians()),
        ),
        (
            "scale(1e-3)".to_string(),
            DMat4::from_scale(DVec3::splat(1e-3)),
        ),
    ] {
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
        let e = eval(text);
        assert_eq!(codes(&e), vec!["E0301"], "{text}: {:?}", e.diagnostics);
        let d = &e.diagnostics[0];
        let labels: Vec<&str> = d
            .labels
            .iter()
            .map(|l| &text[l.span.start as usize..l.span.end as usize])
            .collect();
        assert_eq!(labels.len(), 2, "{text}: {labels:?}");
        assert!(labels[0].starts_with(first), "{text}: {labels:?}");
        assert!(labels[1].starts_with(second), "{text}: {labels:?}");
        assert!(d.help.is_some(), "{text}");
    }
}
