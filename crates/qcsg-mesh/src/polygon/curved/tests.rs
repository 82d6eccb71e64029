//! The curved decomposition against winding numbers of finely flattened outlines.

use super::*;
use qcsg_testkit::Rng;

fn p(x: f64, y: f64) -> DVec2 {
    DVec2::new(x, y)
}

/// The winding number of the outline at `q`, with every arc flattened into `n` chords.
fn flattened_winding(contours: &[Vec<Segment>], q: DVec2, n: usize) -> i32 {
    let mut w = 0;
    let mut edge = |a: DVec2, b: DVec2| {
        if (a.y <= q.y) != (b.y <= q.y) {
            let t = (q.y - a.y) / (b.y - a.y);
            if a.x + t * (b.x - a.x) > q.x {
                w += if b.y > a.y { 1 } else { -1 };
            }
        }
    };
    for contour in contours {
        for s in contour {
            match *s {
                Segment::Line(a, b) => edge(a, b),
                Segment::Quad(a, c, b) => {
                    let arc = BezierArc {
                        p0: a,
                        p1: c,
                        p2: b,
                    };
                    for k in 0..n {
                        edge(
                            arc.point(k as f64 / n as f64),
                            arc.point((k + 1) as f64 / n as f64),
                        );
                    }
                }
            }
        }
    }
    // The crossing test counts rays to +x; a counter-clockwise loop gives −1 on its left side.
    -w
}

/// The distance from `q` to the outline, flattened.
fn distance(contours: &[Vec<Segment>], q: DVec2, n: usize) -> f64 {
    let seg = |a: DVec2, b: DVec2| {
        let t = ((q - a).dot(b - a) / (b - a).length_squared().max(1e-300)).clamp(0.0, 1.0);
        (a + (b - a) * t).distance(q)
    };
    let mut d = f64::INFINITY;
    for contour in contours {
        for s in contour {
            match *s {
                Segment::Line(a, b) => d = d.min(seg(a, b)),
                Segment::Quad(a, c, b) => {
                    let arc = BezierArc {
                        p0: a,
                        p1: c,
                        p2: b,
                    };
                    for k in 0..n {
                        d = d.min(seg(
                            arc.point(k as f64 / n as f64),
                            arc.point((k + 1) as f64 / n as f64),
                        ));
                    }
                }
            }
        }
    }
    d
}

fn check_against_flattening(contours: &[Vec<Segment>], rule: FillRule, seed: u64) {
    let region = curved_cells(contours, rule).unwrap();
    let mut rng = Rng::new(seed);
    let mut checked = 0;
    for _ in 0..800 {
        let q = p(rng.unit() * 12.0 - 1.0, rng.unit() * 12.0 - 1.0);
        // Flattening with 1024 chords moves the curve by far less than this margin.
        if distance(contours, q, 64) < 2e-3 {
            continue;
        }
        let w = flattened_winding(contours, q, 1024);
        let expected = match rule {
            FillRule::EvenOdd => w % 2 != 0,
            FillRule::NonZero => w != 0,
        };
        assert_eq!(region.contains(q), expected, "at {q} (winding {w})");
        checked += 1;
    }
    assert!(checked > 500);
}

#[test]
fn a_square_with_a_bulging_and_a_hollow_side() {
    // Counter-clockwise; the right side bulges out, the top side dips in.
    let contour = vec![
        Segment::Line(p(0.0, 0.0), p(8.0, 0.0)),
        Segment::Quad(p(8.0, 0.0), p(12.0, 4.0), p(8.0, 8.0)),
        Segment::Quad(p(8.0, 8.0), p(4.0, 3.0), p(0.0, 8.0)),
        Segment::Line(p(0.0, 8.0), p(0.0, 0.0)),
    ];
    for rule in [FillRule::NonZero, FillRule::EvenOdd] {
        let region = curved_cells(std::slice::from_ref(&contour), rule).unwrap();
        assert!(region.contains(p(9.5, 4.0)), "in the bulge");
        assert!(!region.contains(p(10.5, 4.0)), "beyond the bulge");
        assert!(!region.contains(p(4.0, 7.0)), "in the dip");
        assert!(region.contains(p(4.0, 5.0)), "below the dip");
        assert_eq!(region.arcs.len(), 2);
        check_against_flattening(std::slice::from_ref(&contour), rule, 1);
    }
}

#[test]
fn a_ring_of_arcs_with_a_hole() {
    // An "O": an outer loop of four arcs clockwise (as TrueType draws it), a hole counter-clockwise.
    let ring = |r: f64, clockwise: bool| {
        let c = p(5.0, 5.0);
        let pts: Vec<DVec2> = (0..8)
            .map(|k| {
                let a = std::f64::consts::FRAC_PI_4 * k as f64;
                let rr = if k % 2 == 0 {
                    r
                } else {
                    r * std::f64::consts::SQRT_2
                };
                c + DVec2::new(a.cos(), a.sin()) * rr
            })
            .collect();
        let mut arcs: Vec<Segment> = (0..4)
            .map(|k| Segment::Quad(pts[2 * k], pts[2 * k + 1], pts[(2 * k + 2) % 8]))
            .collect();
        if clockwise {
            arcs = arcs
                .into_iter()
                .rev()
                .map(|s| match s {
                    Segment::Quad(a, c, b) => Segment::Quad(b, c, a),
                    other => other,
                })
                .collect();
        }
        arcs
    };
    let contours = vec![ring(5.0, true), ring(3.0, false)];
    for rule in [FillRule::NonZero, FillRule::EvenOdd] {
        let region = curved_cells(&contours, rule).unwrap();
        assert!(!region.contains(p(5.0, 5.0)));
        assert!(region.contains(p(9.0, 5.0)));
        check_against_flattening(&contours, rule, 2);
    }
}

/// A smooth closed contour of `n` quadratic arcs around a circle (each turning `2π / n`).
fn smooth_loop(n: usize, r: f64) -> Vec<Segment> {
    let c = p(5.0, 5.0);
    let step = std::f64::consts::TAU / n as f64;
    let at = |k: f64, rr: f64| c + DVec2::new((k * step).cos(), (k * step).sin()) * rr;
    (0..n)
        .map(|k| {
            let k = k as f64;
            Segment::Quad(
                at(k, r),
                at(k + 0.5, r / (0.5 * step).cos()),
                at(k + 1.0, r),
            )
        })
        .collect()
}

/// Consecutive arcs are tangent where they join: a cell keeping both parabolas would have them
/// close over a stretch; the line normal to the join parts them.
#[test]
fn cells_of_a_smooth_loop_keep_one_arc_each() {
    for n in [5, 8, 13] {
        let contour = smooth_loop(n, 4.0);
        for rule in [FillRule::NonZero, FillRule::EvenOdd] {
            let region = curved_cells(std::slice::from_ref(&contour), rule).unwrap();
            assert_eq!(region.arcs.len(), n);
            for cell in &region.cells {
                assert!(cell.sides.len() <= 1, "{n} arcs: {cell:?}");
            }
            check_against_flattening(std::slice::from_ref(&contour), rule, 10 + n as u64);
        }
        check_complement(
            std::slice::from_ref(&contour),
            FillRule::NonZero,
            20 + n as u64,
        );
        let complement = curved_complement_cells(&[contour], FillRule::NonZero)
            .unwrap()
            .unwrap();
        assert!(complement.region.cells.iter().all(|c| c.sides.len() <= 1));
    }
}

/// In a convex outline each arc's lune is one cell: neither the lines of the straight edges
/// that join it smoothly (its tangents at the ends) nor its neighbours' end lines cut it.
#[test]
fn each_arc_of_a_rounded_rectangle_is_one_cell() {
    let (w, h, r) = (10.0, 6.0, 2.0);
    let corner = |c: DVec2, from: f64| {
        let step = std::f64::consts::FRAC_PI_4;
        let at = move |a: f64, rr: f64| c + DVec2::new(a.cos(), a.sin()) * rr;
        (0..2).map(move |k| {
            let a = from + step * k as f64;
            Segment::Quad(
                at(a, r),
                at(a + 0.5 * step, r / (0.5 * step).cos()),
                at(a + step, r),
            )
        })
    };
    let half_pi = std::f64::consts::FRAC_PI_2;
    let mut contour = vec![Segment::Line(p(r, 0.0), p(w - r, 0.0))];
    contour.extend(corner(p(w - r, r), -half_pi));
    contour.push(Segment::Line(p(w, r), p(w, h - r)));
    contour.extend(corner(p(w - r, h - r), 0.0));
    contour.push(Segment::Line(p(w - r, h), p(r, h)));
    contour.extend(corner(p(r, h - r), half_pi));
    contour.push(Segment::Line(p(0.0, h - r), p(0.0, r)));
    contour.extend(corner(p(r, r), 2.0 * half_pi));
    let region = curved_cells(std::slice::from_ref(&contour), FillRule::NonZero).unwrap();
    assert_eq!(region.arcs.len(), 8);
    for arc in 0..region.arcs.len() {
        let cells = region
            .cells
            .iter()
            .filter(|c| c.sides.iter().any(|s| s.arc == arc));
        assert_eq!(cells.count(), 1, "arc {arc}");
    }
    check_against_flattening(std::slice::from_ref(&contour), FillRule::NonZero, 40);
    check_complement(std::slice::from_ref(&contour), FillRule::NonZero, 41);
}

#[test]
fn arcs_turning_a_right_angle_or_more_are_halved() {
    // Arcs turning 90° and 135° (a right angle at one end of each triangle) and a gentle one.
    let contour = vec![
        Segment::Quad(p(0.0, 0.0), p(10.0, 0.0), p(10.0, 10.0)),
        Segment::Quad(p(10.0, 10.0), p(10.0, 14.0), p(6.0, 10.0)),
        Segment::Line(p(6.0, 10.0), p(0.0, 4.0)),
        Segment::Quad(p(0.0, 4.0), p(-1.0, 1.0), p(0.0, 0.0)),
    ];
    for rule in [FillRule::NonZero, FillRule::EvenOdd] {
        let region = curved_cells(std::slice::from_ref(&contour), rule).unwrap();
        assert!(region.arcs.len() > 3);
        // The halves are pieces of the same parabolas: their points are on the arcs drawn.
        for arc in &region.arcs {
            let on_some = contour.iter().any(|s| match *s {
                Segment::Quad(a, c, b) => {
                    let whole = BezierArc {
                        p0: a,
                        p1: c,
                        p2: b,
                    };
                    [0.0, 0.3, 0.7, 1.0]
                        .iter()
                        .all(|&t| whole.value(arc.point(t)).abs() < 1e-9)
                }
                Segment::Line(..) => false,
            });
            assert!(on_some, "{arc:?}");
        }
        check_against_flattening(std::slice::from_ref(&contour), rule, 30);
    }
    check_complement(std::slice::from_ref(&contour), FillRule::NonZero, 31);
}

#[test]
fn overlapping_contours_follow_the_fill_rule() {
    let square = |x: f64, y: f64, s: f64| {
        vec![
            Segment::Line(p(x, y), p(x + s, y)),
            Segment::Quad(p(x + s, y), p(x + s + 2.0, y + s / 2.0), p(x + s, y + s)),
            Segment::Line(p(x + s, y + s), p(x, y + s)),
            Segment::Line(p(x, y + s), p(x, y)),
        ]
    };
    let contours = vec![square(0.0, 0.0, 6.0), square(3.0, 2.0, 6.0)];
    let nonzero = curved_cells(&contours, FillRule::NonZero).unwrap();
    let evenodd = curved_cells(&contours, FillRule::EvenOdd).unwrap();
    // In both squares and in the first one's bulge, which lies in the second square.
    assert!(nonzero.contains(p(6.5, 3.0)));
    assert!(!evenodd.contains(p(6.5, 3.0)));
    assert!(nonzero.contains(p(4.0, 4.0)) && !evenodd.contains(p(4.0, 4.0)));
    check_against_flattening(&contours, FillRule::NonZero, 3);
    check_against_flattening(&contours, FillRule::EvenOdd, 4);
}

#[test]
fn random_curved_outlines_match_their_winding_numbers() {
    let mut rng = Rng::new(99);
    for round in 0..12 {
        let mut contours = Vec::new();
        for _ in 0..2 {
            let n = 3 + (rng.unit() * 6.0) as usize;
            let pts: Vec<DVec2> = (0..n)
                .map(|_| p(rng.unit() * 10.0, rng.unit() * 10.0))
                .collect();
            let contour = (0..n)
                .map(|k| {
                    let (a, b) = (pts[k], pts[(k + 1) % n]);
                    if rng.unit() < 0.6 {
                        let mid = (a + b) * 0.5 + p(rng.unit() - 0.5, rng.unit() - 0.5) * 6.0;
                        Segment::Quad(a, mid, b)
                    } else {
                        Segment::Line(a, b)
                    }
                })
                .collect();
            contours.push(contour);
        }
        match curved_cells(&contours, FillRule::NonZero) {
            Ok(_) => {
                check_against_flattening(&contours, FillRule::NonZero, round);
                check_against_flattening(&contours, FillRule::EvenOdd, round + 100);
            }
            // Random self-crossing outlines may pile up lunes; that must be reported, not wrong.
            Err(e) => assert_eq!(e, CurvedError::TooManyOverlappingArcs),
        }
    }
}

#[test]
fn the_conic_is_the_arc_value_scaled() {
    let arc = BezierArc {
        p0: p(1.0, 2.0),
        p1: p(4.0, 7.0),
        p2: p(8.0, 1.0),
    };
    let origin = p(3.0, 3.0);
    let k = arc.conic(origin);
    let conic = |q: DVec2| {
        let x = q - origin;
        k[0] * x.x * x.x + k[1] * x.y * x.y + k[2] * x.x * x.y + k[3] * x.x + k[4] * x.y + k[5]
    };
    for t in [0.0, 0.1, 0.5, 0.93, 1.0] {
        assert!(conic(arc.point(t)).abs() < 1e-12, "on the arc at {t}");
    }
    let inside = p(4.5, 2.5);
    let ratio = conic(inside) / arc.value(inside);
    assert!(ratio > 0.0);
    for q in [p(0.0, 0.0), p(5.0, 9.0), p(-3.0, 4.0)] {
        assert!((conic(q) / arc.value(q) - ratio).abs() < 1e-9 * ratio);
    }
}

#[test]
fn a_flat_arc_is_its_chord() {
    // The control point at the chord's midpoint up to rounding: the arc is a straight edge.
    let (a, b) = (
        p(7.414277394612631, -0.32503339979383683),
        p(7.561439938015409, -0.752279493543837),
    );
    let c = p(7.48785866631402, -0.5386564466688368);
    let contour = vec![
        Segment::Line(p(0.0, 0.0), a),
        Segment::Quad(a, c, b),
        Segment::Line(b, p(9.0, -3.0)),
        Segment::Line(p(9.0, -3.0), p(9.0, 3.0)),
        Segment::Line(p(9.0, 3.0), p(0.0, 0.0)),
    ];
    let region = curved_cells(std::slice::from_ref(&contour), FillRule::NonZero).unwrap();
    assert!(region.arcs.is_empty());
    check_against_flattening(&[contour], FillRule::NonZero, 5);
}

/// The complement's cells hold exactly the points of its box the flattened outline leaves
/// unfilled, and points outside the box are never filled.
fn check_complement(contours: &[Vec<Segment>], rule: FillRule, seed: u64) {
    let complement = curved_complement_cells(contours, rule)
        .unwrap()
        .expect("an outline with area");
    let region = curved_cells(contours, rule).unwrap();
    let mut rng = Rng::new(seed);
    let mut checked = 0;
    for _ in 0..800 {
        let q = p(rng.unit() * 14.0 - 2.0, rng.unit() * 14.0 - 2.0);
        if distance(contours, q, 64) < 2e-3 {
            continue;
        }
        let w = flattened_winding(contours, q, 1024);
        let filled = match rule {
            FillRule::EvenOdd => w % 2 != 0,
            FillRule::NonZero => w != 0,
        };
        let in_box = q.cmpge(complement.min).all() && q.cmple(complement.max).all();
        let unfilled = !in_box || complement.region.contains(q);
        assert_eq!(unfilled, !filled, "at {q} (winding {w})");
        // The cells on both sides come from one partition: never both.
        assert!(
            !(region.contains(q) && complement.region.contains(q)),
            "at {q}"
        );
        checked += 1;
    }
    assert!(checked > 500);
}

#[test]
fn the_complement_holds_the_unfilled_points() {
    let bulging = vec![
        Segment::Line(p(0.0, 0.0), p(8.0, 0.0)),
        Segment::Quad(p(8.0, 0.0), p(12.0, 4.0), p(8.0, 8.0)),
        Segment::Quad(p(8.0, 8.0), p(4.0, 3.0), p(0.0, 8.0)),
        Segment::Line(p(0.0, 8.0), p(0.0, 0.0)),
    ];
    for rule in [FillRule::NonZero, FillRule::EvenOdd] {
        check_complement(std::slice::from_ref(&bulging), rule, 5);
    }
    let mut rng = Rng::new(7);
    let mut checked = 0;
    for round in 0..12 {
        let n = 3 + (rng.unit() * 6.0) as usize;
        let pts: Vec<DVec2> = (0..n)
            .map(|_| p(rng.unit() * 10.0, rng.unit() * 10.0))
            .collect();
        let contour: Vec<Segment> = (0..n)
            .map(|k| {
                let (a, b) = (pts[k], pts[(k + 1) % n]);
                let mid = (a + b) * 0.5 + p(rng.unit() - 0.5, rng.unit() - 0.5) * 6.0;
                Segment::Quad(a, mid, b)
            })
            .collect();
        if curved_cells(std::slice::from_ref(&contour), FillRule::NonZero).is_ok() {
            check_complement(std::slice::from_ref(&contour), FillRule::NonZero, round);
            checked += 1;
        }
    }
    assert!(checked > 6);
    assert_eq!(curved_complement_cells(&[], FillRule::NonZero), Ok(None));
}
