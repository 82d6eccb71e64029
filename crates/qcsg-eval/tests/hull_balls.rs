//! `hull()` of balls of different radii and of balls with polytopes, checked against an
//! independent membership test: p is in the hull of the balls B(cᵢ, rᵢ) exactly when some convex
//! combination λ has |p − Σλᵢcᵢ| ≤ Σλᵢrᵢ. A Frank–Wolfe search over λ either finds a combination
//! that holds p with a margin (a certificate that p is inside) or a direction u with
//! p·u > maxᵢ(cᵢ·u + rᵢ) plus the margin (a supporting plane that p lies beyond: a certificate
//! that p is outside); points with neither, too close to the surface, are skipped. Nothing of
//! the construction (tangent cones, tangent planes) is used.

mod common;

use common::{codes, eval};
use glam::DVec3;
use qcsg_csg::{DnfOptions, build_dnf};
use qcsg_testkit::Rng;

/// Whether `p` is inside the hull of `balls` with `margin` to spare (`Some(true)`), outside by
/// more than `margin` (`Some(false)`), or too close to tell.
fn oracle(p: DVec3, balls: &[(DVec3, f64)], margin: f64) -> Option<bool> {
    let phi = |x: DVec3, r: f64| (p - x).length() - r;
    let start = balls
        .iter()
        .min_by(|a, b| phi(a.0, a.1).total_cmp(&phi(b.0, b.1)))
        .copied()?;
    let (mut x, mut r) = start;
    for _ in 0..2000 {
        let value = phi(x, r);
        if value < -margin {
            return Some(true);
        }
        // p at the combination's centre with φ = −r not below −margin: too close to tell.
        let v = (p - x).try_normalize()?;
        let (c, s) = balls
            .iter()
            .max_by(|a, b| (a.0.dot(v) + a.1).total_cmp(&(b.0.dot(v) + b.1)))
            .copied()?;
        // The plane with normal v supporting the hull.
        if p.dot(v) - (c.dot(v) + s) > margin {
            return Some(false);
        }
        // Golden-section line search towards (c, s) of the convex φ.
        let along = |t: f64| phi(x + t * (c - x), r + t * (s - r));
        let (mut a, mut b) = (0.0f64, 1.0f64);
        let g = 0.5 * (5f64.sqrt() - 1.0);
        for _ in 0..80 {
            let (t1, t2) = (b - g * (b - a), a + g * (b - a));
            if along(t1) <= along(t2) {
                b = t2;
            } else {
                a = t1;
            }
        }
        let t = 0.5 * (a + b);
        x += t * (c - x);
        r += t * (s - r);
    }
    None
}

fn fmt(v: DVec3) -> String {
    format!("[{:e}, {:e}, {:e}]", v.x, v.y, v.z)
}

/// A scene's children: balls and cubes (centred, of edge `size`), and the oracle's balls (a
/// cube's corners of radius 0).
#[derive(Default)]
struct Scene {
    children: String,
    balls: Vec<(DVec3, f64)>,
}

impl Scene {
    fn ball(&mut self, c: DVec3, r: f64) {
        self.children += &format!("translate({}) sphere({r:e});", fmt(c));
        self.balls.push((c, r));
    }

    fn cube(&mut self, c: DVec3, size: f64) {
        self.children += &format!("translate({}) cube({size:e}, center = true);", fmt(c));
        for k in 0..8 {
            let corner = DVec3::new(
                if k & 1 == 0 { -0.5 } else { 0.5 },
                if k & 2 == 0 { -0.5 } else { 0.5 },
                if k & 4 == 0 { -0.5 } else { 0.5 },
            );
            self.balls.push((c + size * corner, 0.0));
        }
    }

    fn text(&self) -> String {
        format!("hull() {{ {} }}", self.children)
    }

    /// Random points about the scene compared with the oracle on the DAG and the DNF; returns
    /// how many were inside and outside.
    fn compare(&self, rng: &mut Rng, points: usize) -> (usize, usize) {
        let text = self.text();
        let e = eval(&text);
        assert!(!e.has_errors(), "{text}: {:?}", e.diagnostics);
        let dnf = build_dnf(&e.dag, &DnfOptions::default()).expect("a solid");
        let min = self
            .balls
            .iter()
            .fold(DVec3::INFINITY, |m, (c, r)| m.min(*c - *r));
        let max = self
            .balls
            .iter()
            .fold(DVec3::NEG_INFINITY, |m, (c, r)| m.max(*c + *r));
        let scale = (max - min).max_element();
        let (min, max) = (min - 0.2 * scale, max + 0.2 * scale);
        let margin = 1e-6 * scale;
        let (mut inside, mut outside) = (0, 0);
        for k in 0..points {
            // Half in the box, half about one ball, where the surface is.
            let p = if k % 2 == 0 {
                rng.in_box(min, max)
            } else {
                let (c, r) = self.balls[rng.below(self.balls.len())];
                let reach = DVec3::splat(1.3 * r + 0.1 * scale);
                rng.in_box(c - reach, c + reach)
            };
            let Some(expected) = oracle(p, &self.balls, margin) else {
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
}

#[test]
fn the_oracle_knows_a_tapered_capsule() {
    let balls = [(DVec3::ZERO, 3.0), (DVec3::new(10.0, 0.0, 0.0), 1.0)];
    // The tangent cone's half-angle: sin α = 2/10; its surface at x = 5 lies at radius
    // (3 + (5 − 3 sin α)·…) — checked against points well inside and outside it.
    assert_eq!(oracle(DVec3::new(5.0, 1.9, 0.0), &balls, 1e-9), Some(true));
    assert_eq!(oracle(DVec3::new(5.0, 2.3, 0.0), &balls, 1e-9), Some(false));
    assert_eq!(
        oracle(DVec3::new(-3.1, 0.0, 0.0), &balls, 1e-9),
        Some(false)
    );
    assert_eq!(oracle(DVec3::new(10.9, 0.0, 0.0), &balls, 1e-9), Some(true));
}

#[test]
fn random_balls_of_different_radii_match_the_oracle() {
    let mut rng = Rng::new(3939);
    let (mut inside, mut outside) = (0, 0);
    for case in 0..30 {
        let (offset, scale) = match case % 3 {
            0 => (DVec3::ZERO, 1.0),
            1 => (DVec3::new(1e6, -1e6, 1e6), 1.0),
            _ => (DVec3::new(0.002, 0.0, -0.001), 1e-3),
        };
        let mut scene = Scene::default();
        for _ in 0..2 + case % 5 {
            let c = offset + scale * rng.in_box(DVec3::splat(-1.0), DVec3::ONE);
            scene.ball(c, scale * rng.range(0.05, 0.8));
        }
        if case % 4 == 3 {
            let c = offset + scale * rng.in_box(DVec3::splat(-1.0), DVec3::ONE);
            scene.cube(c, scale * rng.range(0.1, 0.6));
        }
        let (i, o) = scene.compare(&mut rng, 200);
        inside += i;
        outside += o;
    }
    assert!(
        inside > 1000 && outside > 1000,
        "{inside} in, {outside} out"
    );
}

#[test]
fn stiff_placements_match_the_oracle() {
    let mut rng = Rng::new(17);
    let x = DVec3::X;
    let scenes: Vec<Vec<(DVec3, f64)>> = vec![
        // Nearly equal radii: a cone with its apex ~10⁹ away.
        vec![(DVec3::ZERO, 1.0), (5.0 * x, 1.0 + 1e-9)],
        vec![
            (DVec3::ZERO, 1.0),
            (5.0 * x, 1.0 + 1e-6),
            (DVec3::new(2.0, 3.0, 0.5), 1.0),
        ],
        // Nearly collinear centres.
        vec![
            (DVec3::ZERO, 1.0),
            (DVec3::new(4.0, 1e-7, 0.0), 1.5),
            (8.0 * x, 2.0),
        ],
        vec![
            (DVec3::ZERO, 1.0),
            (DVec3::new(4.0, 1e-4, 0.0), 1.2),
            (8.0 * x, 0.5),
        ],
        // Exactly collinear, radii varying linearly: the middle ball touches the cone.
        vec![(DVec3::ZERO, 1.0), (4.0 * x, 1.5), (8.0 * x, 2.0)],
        // A ball inside another, one touching it from inside, coincident centres.
        vec![
            (DVec3::ZERO, 3.0),
            (DVec3::new(1.0, 0.5, 0.0), 1.0),
            (7.0 * x, 1.0),
        ],
        vec![(DVec3::ZERO, 3.0), (2.0 * x, 1.0), (7.0 * x, 0.5)],
        vec![
            (DVec3::ZERO, 3.0),
            (DVec3::ZERO, 1.0),
            (DVec3::new(0.0, 6.0, 0.0), 1.0),
        ],
        // Coplanar centres, four balls touching one plane.
        vec![
            (DVec3::ZERO, 1.0),
            (DVec3::new(4.0, 0.0, 0.0), 2.0),
            (DVec3::new(4.0, 4.0, 0.0), 1.0),
            (DVec3::new(0.0, 4.0, 0.0), 2.0),
        ],
        vec![
            (DVec3::new(0.0, 0.0, 0.0), 1.0),
            (DVec3::new(5.0, 0.0, 0.0), 1.0),
            (DVec3::new(0.0, 5.0, 0.0), 1.0),
            (DVec3::new(0.0, 0.0, -3.0), 4.0),
        ],
    ];
    for balls in scenes {
        let mut scene = Scene::default();
        for (c, r) in balls {
            scene.ball(c, r);
        }
        let (i, o) = scene.compare(&mut rng, 400);
        assert!(i > 20 && o > 20, "{}: {i} in, {o} out", scene.text());
    }
}

#[test]
fn a_cube_and_a_ball_is_the_ball_on_a_pyramid_of_cones_and_planes() {
    let mut rng = Rng::new(5);
    let mut scene = Scene::default();
    scene.cube(DVec3::ZERO, 4.0);
    scene.ball(DVec3::new(0.0, 0.0, 7.0), 1.5);
    let (i, o) = scene.compare(&mut rng, 600);
    assert!(i > 50 && o > 50, "{i} in, {o} out");
    // A ball that holds the cube's corners is the ball.
    let e = eval("hull() { cube(1, center = true); sphere(2); }");
    assert!(!e.has_errors(), "{:?}", e.diagnostics);
    assert!(e.dag.contains(DVec3::new(0.0, 0.0, 1.99)));
    assert!(!e.dag.contains(DVec3::new(1.2, 1.2, 1.2)));
}

#[test]
fn unequal_radii_are_no_longer_refused() {
    let e = eval("hull() { sphere(1); translate([3, 0, 0]) sphere(2); }");
    assert!(codes(&e).is_empty(), "{:?}", e.diagnostics);
}
