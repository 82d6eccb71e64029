//! `hull()` of circles of different radii, points and polygons in 2-D, and of parallel cylinders
//! of different radii and one height, checked against an independent hull: the support function
//! of the discs sampled in many directions (the hull of a dense sampling of the circles), with
//! the sampling error bounded so that only points too near the outline to tell are skipped.

mod common;

use common::{codes, eval};
use glam::{DVec2, DVec3};
use qcsg_csg::{DnfOptions, build_dnf};
use qcsg_testkit::Rng;

/// Directions sampled by the oracle.
const DIRECTIONS: usize = 4096;
/// The side of the square standing for a point.
const POINT: f64 = 1e-6;

/// `max over sampled unit u of (u · p − h(u))` with `h` the discs' support function, and the
/// bound on its error: the true signed distance to the hull's outline (positive outside) is
/// within the bound of the first value and at least it.
fn signed(p: DVec2, discs: &[(DVec2, f64)]) -> (f64, f64) {
    let step = std::f64::consts::TAU / DIRECTIONS as f64;
    let mut best = f64::NEG_INFINITY;
    for k in 0..DIRECTIONS {
        let (s, c) = (step * k as f64).sin_cos();
        let u = DVec2::new(c, s);
        let h = discs
            .iter()
            .map(|(centre, r)| centre.dot(u) + r)
            .fold(f64::NEG_INFINITY, f64::max);
        best = best.max(u.dot(p) - h);
    }
    // u ↦ u·p − h(u) is Lipschitz with constant |p| + max |c|; the nearest sample is within
    // half a step of the best direction.
    let lipschitz = p.length() + discs.iter().map(|(c, _)| c.length()).fold(0.0, f64::max);
    (best, lipschitz * 0.5 * step)
}

fn disc_scene(discs: &[(DVec2, f64)], offset: DVec2) -> String {
    let mut s = format!(
        "linear_extrude(1) translate([{:e}, {:e}]) hull() {{",
        offset.x, offset.y
    );
    for (c, r) in discs {
        if *r == 0.0 {
            // A point: a square of side `POINT` about it, within the oracle's margin.
            s += &format!(
                " translate([{:e}, {:e}]) square({POINT:e}, center = true);",
                c.x, c.y
            );
        } else {
            s += &format!(" translate([{:e}, {:e}]) circle({:e});", c.x, c.y, r);
        }
    }
    s + " }"
}

/// Random points about the discs compared with the oracle on the DAG and the DNF at height
/// `z`; returns how many were inside and outside.
fn compare(
    text: &str,
    discs: &[(DVec2, f64)],
    offset: DVec2,
    frame: &dyn Fn(DVec2) -> DVec3,
    rng: &mut Rng,
) -> (usize, usize) {
    let e = eval(text);
    assert!(!e.has_errors(), "{text}: {:?}", e.diagnostics);
    let dnf = build_dnf(&e.dag, &DnfOptions::default()).expect("a solid");
    let lo = discs
        .iter()
        .fold(DVec2::INFINITY, |m, (c, r)| m.min(*c - *r));
    let hi = discs
        .iter()
        .fold(DVec2::NEG_INFINITY, |m, (c, r)| m.max(*c + *r));
    let pad = 0.2 * (hi - lo).max_element();
    let scale = (hi - lo).max_element();
    let (mut inside, mut outside) = (0, 0);
    for _ in 0..300 {
        let p = DVec2::new(
            rng.range(lo.x - pad, hi.x + pad),
            rng.range(lo.y - pad, hi.y + pad),
        );
        let (f, error) = signed(p, discs);
        // The rounding of qcsg's coefficients, of the size of the scene and its distance.
        let margin = error + POINT + 1e-7 * scale + 1e-12 * offset.length();
        if f.abs() <= margin {
            continue;
        }
        let expected = f < 0.0;
        let q = frame(p + offset);
        assert_eq!(e.dag.contains(q), expected, "{text} at {p} (signed {f:e})");
        assert_eq!(
            dnf.contains(q),
            expected,
            "DNF of {text} at {p} (signed {f:e})"
        );
        if expected {
            inside += 1;
        } else {
            outside += 1;
        }
    }
    (inside, outside)
}

fn random_discs(rng: &mut Rng, n: usize, scale: f64) -> Vec<(DVec2, f64)> {
    (0..n)
        .map(|_| {
            let c = DVec2::new(rng.range(-scale, scale), rng.range(-scale, scale));
            // One in four a point.
            let r = if rng.below(4) == 0 {
                0.0
            } else {
                rng.range(0.05, 0.6) * scale
            };
            (c, r)
        })
        .collect()
}

fn flat(z: f64) -> impl Fn(DVec2) -> DVec3 {
    move |p: DVec2| p.extend(z)
}

#[test]
fn the_oracle_knows_two_discs() {
    let discs = [(DVec2::ZERO, 2.0), (DVec2::new(10.0, 0.0), 1.0)];
    // The outer tangent of radii 2 and 1 at distance 10 meets the midline at height ≈ 1.507.
    let kappa: f64 = 0.1;
    let at5 = (2.0 - 5.0 * kappa) / (1.0 - kappa * kappa).sqrt();
    let (f, e) = signed(DVec2::new(5.0, at5 - 0.05), &discs);
    assert!(f < -e, "{f} {e}");
    let (f, e) = signed(DVec2::new(5.0, at5 + 0.05), &discs);
    assert!(f > e, "{f} {e}");
}

#[test]
fn random_discs_of_different_radii_match_the_oracle() {
    let mut rng = Rng::new(39);
    let (mut inside, mut outside) = (0, 0);
    for case in 0..24 {
        let n = 1 + case % 7;
        let discs = random_discs(&mut rng, n, 4.0);
        let text = disc_scene(&discs, DVec2::ZERO);
        let (i, o) = compare(&text, &discs, DVec2::ZERO, &flat(0.5), &mut rng);
        inside += i;
        outside += o;
    }
    assert!(
        inside > 1000 && outside > 1000,
        "{inside} inside, {outside} outside"
    );
}

#[test]
fn circles_with_polygons_match_the_oracle() {
    // A polygon's corners are discs of radius 0 for the oracle.
    let mut rng = Rng::new(7);
    for _ in 0..8 {
        let mut discs = random_discs(&mut rng, 3, 3.0);
        discs.retain(|(_, r)| *r > 0.0);
        let corner = DVec2::new(rng.range(-4.0, 4.0), rng.range(-4.0, 4.0));
        let size = DVec2::new(rng.range(0.5, 3.0), rng.range(0.5, 3.0));
        let mut text = format!(
            "linear_extrude(1) hull() {{ translate([{:e}, {:e}]) square([{:e}, {:e}]);",
            corner.x, corner.y, size.x, size.y
        );
        for (c, r) in &discs {
            text += &format!(" translate([{:e}, {:e}]) circle({:e});", c.x, c.y, r);
        }
        text += " }";
        let mut all = discs.clone();
        for k in [DVec2::ZERO, DVec2::X, DVec2::Y, DVec2::ONE] {
            all.push((corner + k * size, 0.0));
        }
        compare(&text, &all, DVec2::ZERO, &flat(0.5), &mut rng);
    }
}

#[test]
fn stiff_placements_match_the_oracle() {
    let mut rng = Rng::new(11);
    let cases: Vec<(Vec<(DVec2, f64)>, DVec2)> = vec![
        // Nearly equal radii: a nearly parallel tangent.
        (
            vec![(DVec2::ZERO, 1.0), (DVec2::new(8.0, 0.0), 1.0 + 1e-9)],
            DVec2::ZERO,
        ),
        // Nearly collinear centres.
        (
            vec![
                (DVec2::ZERO, 1.0),
                (DVec2::new(5.0, 1e-9), 0.5),
                (DVec2::new(10.0, 0.0), 1.5),
            ],
            DVec2::ZERO,
        ),
        // A disc inside another, and one touching it from inside.
        (
            vec![
                (DVec2::ZERO, 3.0),
                (DVec2::new(1.0, 0.0), 1.0),
                (DVec2::new(2.0, 0.0), 1.0),
                (DVec2::new(7.0, 2.0), 0.5),
            ],
            DVec2::ZERO,
        ),
        // A point on the tangent of two discs.
        (
            vec![
                (DVec2::ZERO, 1.0),
                (DVec2::new(10.0, 0.0), 1.0),
                (DVec2::new(5.0, -1.0), 0.0),
            ],
            DVec2::ZERO,
        ),
        // Far from the origin, and tiny.
        (
            vec![
                (DVec2::ZERO, 2.0),
                (DVec2::new(9.0, 3.0), 0.5),
                (DVec2::new(2.0, 7.0), 1.0),
            ],
            DVec2::new(1e6, -2e6),
        ),
        (
            vec![
                (DVec2::ZERO, 2e-4),
                (DVec2::new(9e-4, 3e-4), 5e-5),
                (DVec2::new(2e-4, 7e-4), 1e-4),
            ],
            DVec2::ZERO,
        ),
    ];
    for (discs, offset) in cases {
        let text = disc_scene(&discs, offset);
        let (inside, outside) = compare(&text, &discs, offset, &flat(0.5), &mut rng);
        assert!(
            inside > 20 && outside > 20,
            "{text}: {inside} in, {outside} out"
        );
    }
}

#[test]
fn parallel_cylinders_of_different_radii_are_their_discs_hull_extruded() {
    let mut rng = Rng::new(3);
    for case in 0..6 {
        let discs: Vec<(DVec2, f64)> = random_discs(&mut rng, 2 + case % 4, 4.0)
            .into_iter()
            .map(|(c, r)| (c, r.max(0.3)))
            .collect();
        let mut body = String::new();
        for (c, r) in &discs {
            body += &format!(
                " translate([{:e}, {:e}, 0]) cylinder(h = 3, r = {:e});",
                c.x, c.y, r
            );
        }
        // Upright, and lying along x (the axis turned to x by rotate([0, 90, 0])).
        let text = format!("hull() {{{body} }}");
        compare(&text, &discs, DVec2::ZERO, &flat(1.5), &mut rng);
        let e = eval(&text);
        for (c, _) in &discs {
            assert!(!e.dag.contains(c.extend(3.01)), "{text} above {c}");
            assert!(
                e.dag.contains(c.extend(2.99)),
                "{text} below the top at {c}"
            );
        }
        let turned = format!("rotate([0, 90, 0]) {text}");
        // rotate([0, 90, 0]) takes (x, y, z) to (z, y, −x).
        let frame = |p: DVec2| DVec3::new(1.5, p.y, -p.x);
        compare(&turned, &discs, DVec2::ZERO, &frame, &mut rng);
    }
}

#[test]
fn refusals_that_remain() {
    for text in [
        "linear_extrude(1) hull() { scale([1, 2]) circle(1); translate([3, 0]) circle(2); }",
        "hull() { cylinder(h = 1, r = 1); translate([3, 0, 0]) rotate([0, 90, 0]) cylinder(h = 1, r = 2); }",
    ] {
        let e = eval(text);
        assert_eq!(codes(&e), vec!["E0301"], "{text}: {:?}", e.diagnostics);
    }
}
