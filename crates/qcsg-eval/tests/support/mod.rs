//! An independent membership test for convex sets given by their support function: the hull of
//! discs square to z (centres and radii; points have radius 0) and of balls, grown by a ball. The support
//! function is sampled on Fibonacci lattices of directions (the hull of a dense sampling of the
//! discs and the ball), with the sampling error bounded by the function's Lipschitz constant, so
//! that a point is told inside or outside only when the sampling cannot be wrong.

// Each test file uses the helpers it needs.
#![allow(dead_code)]

use glam::{DMat4, DVec3, EulerRot};
use qcsg_csg::{DnfOptions, build_dnf};
use qcsg_testkit::Rng;

use crate::common::eval;

/// Directions sampled on the sphere: a coarse lattice that settles most points and a fine one
/// for the rest.
pub const DIRECTIONS: [usize; 2] = [1_000, 20_000];

/// `n` directions and a bound on the distance from any unit vector to the nearest.
pub fn directions(n: usize) -> (Vec<DVec3>, f64) {
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
    // 0.62 √area), and 1.5 √area bounds them with room (checked by the tests that use it).
    (dirs, 1.5 * (4.0 * std::f64::consts::PI / count).sqrt())
}

/// The lattices of [`DIRECTIONS`].
pub fn lattices() -> Vec<(Vec<DVec3>, f64)> {
    DIRECTIONS.iter().map(|&n| directions(n)).collect()
}

/// The placements a result must survive, as OpenSCAD text and the matrix it means: turned about
/// every axis, far from the origin, and tiny.
pub fn turned_far_and_tiny() -> [(String, DMat4); 3] {
    [
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
    ]
}

/// A convex set: the hull of discs square to z (centre, radius) and of balls, grown by a ball.
#[derive(Clone, Debug, Default)]
pub struct Convex {
    /// The discs.
    pub discs: Vec<(DVec3, f64)>,
    /// The balls (centre, radius).
    pub balls: Vec<(DVec3, f64)>,
    /// The ball's radius.
    pub ball: f64,
}

impl Convex {
    /// The hull of points.
    pub fn points(points: &[DVec3]) -> Convex {
        Convex {
            discs: points.iter().map(|p| (*p, 0.0)).collect(),
            ..Convex::default()
        }
    }

    /// The Minkowski sum of sets without `balls`: discs about one axis add centres and radii.
    pub fn sum(&self, other: &Convex) -> Convex {
        Convex {
            discs: self
                .discs
                .iter()
                .flat_map(|a| other.discs.iter().map(move |b| (a.0 + b.0, a.1 + b.1)))
                .collect(),
            balls: Vec::new(),
            ball: self.ball + other.ball,
        }
    }

    /// The centres and how far each reaches from its centre at most.
    fn centres(&self) -> impl Iterator<Item = (DVec3, f64)> + '_ {
        self.discs.iter().chain(&self.balls).copied()
    }

    /// The sampled `max over v of (v · p − h(v))` and its error bound.
    fn signed(&self, p: DVec3, dirs: &[DVec3], delta: f64) -> (f64, f64) {
        let count = self.discs.len() + self.balls.len();
        let o = self.centres().map(|d| d.0).sum::<DVec3>() / count as f64;
        let q = p - o;
        let mut best = f64::NEG_INFINITY;
        for v in dirs {
            let across = v.truncate().length();
            let h = self
                .discs
                .iter()
                .map(|(c, r)| (*c - o).dot(*v) + r * across)
                .chain(self.balls.iter().map(|(c, r)| (*c - o).dot(*v) + r))
                .fold(f64::NEG_INFINITY, f64::max)
                + self.ball;
            best = best.max(v.dot(q) - h);
        }
        let reach = self
            .centres()
            .map(|(c, r)| (c - o).length() + r)
            .fold(0.0, f64::max);
        // v ↦ v·q − h(v) is Lipschitz with constant |q| + reach + ball.
        (best, (q.length() + reach + self.ball) * delta)
    }

    /// The box around the set.
    pub fn bounds(&self) -> (DVec3, DVec3) {
        let grow = |r: f64| DVec3::new(r, r, 0.0) + self.ball;
        let lo = self
            .discs
            .iter()
            .fold(DVec3::INFINITY, |m, (c, r)| m.min(*c - grow(*r)));
        let hi = self
            .discs
            .iter()
            .fold(DVec3::NEG_INFINITY, |m, (c, r)| m.max(*c + grow(*r)));
        let lo = self
            .balls
            .iter()
            .fold(lo, |m, (c, r)| m.min(*c - (*r + self.ball)));
        let hi = self
            .balls
            .iter()
            .fold(hi, |m, (c, r)| m.max(*c + (*r + self.ball)));
        (lo, hi)
    }
}

/// Whether `p` is in the union of `sets`: `Some` where the sampling tells, `None` within the
/// sampling error (and `margin`) of a surface.
pub fn oracle(
    p: DVec3,
    sets: &[Convex],
    lattices: &[(Vec<DVec3>, f64)],
    margin: f64,
) -> Option<bool> {
    let mut all_out = true;
    for set in sets {
        // A sampled value above 0 is a lower bound of a positive distance; one below minus its
        // error bound is an upper bound of a negative one; else the finer lattice decides.
        let mut told = None;
        for (dirs, delta) in lattices {
            let (f, error) = set.signed(p, dirs, *delta);
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

/// Evaluates `text` and compares it with the union of `sets` (seen through `frame`) at random
/// points about them, on the DAG and the DNF; returns how many were inside and outside.
pub fn compare(text: &str, sets: &[Convex], frame: DMat4, rng: &mut Rng) -> (usize, usize) {
    let e = eval(text);
    assert!(!e.has_errors(), "{text}: {:?}", e.diagnostics);
    let dnf = build_dnf(&e.dag, &DnfOptions::default()).expect("a solid");
    let lattices = lattices();
    let (lo, hi) = sets.iter().map(Convex::bounds).fold(
        (DVec3::INFINITY, DVec3::NEG_INFINITY),
        |(lo, hi), (a, b)| (lo.min(a), hi.max(b)),
    );
    let pad = 0.15 * (hi - lo).max_element();
    let (lo, hi) = (lo - pad, hi + pad);
    // The rounding of qcsg's coefficients, of the size of the scene and of its distance.
    let margin = 1e-9 * (hi - lo).max_element() + 1e-8;
    let (mut inside, mut outside) = (0, 0);
    for k in 0..300 {
        // Half uniform in the box, half convex combinations of points of the discs (inside, and
        // mostly deep enough to be told so).
        let p = if k % 2 == 0 {
            rng.in_box(lo, hi)
        } else {
            let set = &sets[rng.below(sets.len())];
            let mut sum = DVec3::ZERO;
            let mut total = 0.0;
            for _ in 0..4 {
                let w = rng.unit();
                let point = if set.discs.is_empty() || (!set.balls.is_empty() && rng.below(2) == 0)
                {
                    let (c, r) = set.balls[rng.below(set.balls.len())];
                    c + r * rng.unit() * rng.direction()
                } else {
                    let (c, r) = set.discs[rng.below(set.discs.len())];
                    let angle = rng.range(0.0, std::f64::consts::TAU);
                    c + r * rng.unit() * DVec3::new(angle.cos(), angle.sin(), 0.0)
                };
                sum += w * point;
                total += w;
            }
            sum / total.max(1e-300)
        };
        let Some(expected) = oracle(p, sets, &lattices, margin) else {
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
