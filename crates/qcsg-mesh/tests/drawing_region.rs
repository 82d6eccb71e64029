//! A drawing's exact region against an independent even–odd count over its exact edges, arcs,
//! elliptic arcs, circles and ellipses, on drawings written here, the conformance scenes'
//! drawings, and OpenSCAD's example drawings.

use std::f64::consts::TAU;

use glam::DVec2;
use qcsg_mesh::{
    Drawing, DrawingLimits, DrawingOptions, EllipticArc, PolygonLimits, RegionError,
    drawing_region, read_dxf,
};
use qcsg_testkit::dxf::{self, Entity, arc, circle, ellipse, line};

/// The coordinates of `p` in an ellipse's frame (on the unit circle for its points), and the
/// ellipse's semi-minor axis.
fn ellipse_local(center: DVec2, axes: [DVec2; 2], p: DVec2) -> (DVec2, f64) {
    let [a, b] = axes;
    let det = a.perp_dot(b);
    let d = p - center;
    let sum = a.length_squared() + b.length_squared();
    let major = (0.5 * (sum + (sum * sum - 4.0 * det * det).max(0.0).sqrt())).sqrt();
    (
        DVec2::new(d.perp_dot(b) / det, a.perp_dot(d) / det),
        det.abs() / major,
    )
}

/// Crossings of the ray from `p` along +x with an elliptic arc edge, and a lower bound of the
/// distance from `p` to its ellipse.
fn elliptic_crossings(from: DVec2, to: DVec2, el: &EllipticArc, p: DVec2) -> (bool, f64) {
    let [a, b] = el.axes;
    let (local, minor) = ellipse_local(el.center, el.axes, p);
    let near = (local.length() - 1.0).abs() * minor;
    let (first, second) = if el.forward { (from, to) } else { (to, from) };
    let start = el.param(first);
    let sweep = (el.param(second) - start).rem_euclid(TAU);
    // y(t) = c.y + a.y cos t + b.y sin t = R cos(t − φ) + c.y.
    let (r, phi) = (a.y.hypot(b.y), b.y.atan2(a.y));
    let k = (p.y - el.center.y) / r;
    let mut flip = false;
    if k.abs() < 1.0 {
        for t in [phi + k.acos(), phi - k.acos()] {
            let x = el.center.x + a.x * t.cos() + b.x * t.sin();
            if x > p.x && (t - start).rem_euclid(TAU) <= sweep {
                flip = !flip;
            }
        }
    }
    (flip, near)
}

/// Whether `angle` lies on the arc of `edge` (counter-clockwise from its first end to its second).
fn on_arc(from: DVec2, to: DVec2, center: DVec2, ccw: bool, p: DVec2) -> bool {
    let (a, b) = if ccw { (from, to) } else { (to, from) };
    let start = (a - center).to_angle();
    let sweep = ((b - center).to_angle() - start).rem_euclid(TAU);
    ((p - center).to_angle() - start).rem_euclid(TAU) <= sweep
}

/// The even–odd parity of `p` over every edge, arc and circle, by a ray along +x, and the
/// distance from `p` to the nearest curve (to skip points on a boundary).
fn reference(d: &Drawing, p: DVec2) -> (bool, f64) {
    let mut inside = false;
    let mut near = f64::INFINITY;
    for c in &d.circles {
        let r = (p - c.center).length();
        inside ^= r < c.radius;
        near = near.min((r - c.radius).abs());
    }
    for e in &d.ellipses {
        let (local, minor) = ellipse_local(e.center, e.axes, p);
        inside ^= local.length() < 1.0;
        near = near.min((local.length() - 1.0).abs() * minor);
    }
    for path in &d.paths {
        for e in &path.edges {
            if let Some(el) = e.ellipse {
                let (flip, distance) = elliptic_crossings(e.from, e.to, &el, p);
                inside ^= flip;
                near = near.min(distance);
                continue;
            }
            match e.arc {
                None => {
                    let (a, b) = (e.from, e.to);
                    if (a.y > p.y) != (b.y > p.y) {
                        let x = a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x);
                        inside ^= x > p.x;
                    }
                    let t = ((p - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
                    near = near.min((a + (b - a) * t - p).length());
                }
                Some(arc) => {
                    let dy = p.y - arc.center.y;
                    let r = arc.radius;
                    near = near.min(((p - arc.center).length() - r).abs());
                    if dy.abs() < r {
                        let dx = (r * r - dy * dy).sqrt();
                        for x in [arc.center.x - dx, arc.center.x + dx] {
                            let q = DVec2::new(x, p.y);
                            if x > p.x && on_arc(e.from, e.to, arc.center, arc.ccw, q) {
                                inside = !inside;
                            }
                        }
                    }
                }
            }
        }
    }
    (inside, near)
}

/// Compares the region with the reference on a grid of points over the drawing's box.
fn compare(d: &Drawing, lo: DVec2, hi: DVec2) {
    let region = drawing_region(d, &PolygonLimits::default()).unwrap();
    let n = 120;
    let margin = 1e-6 * (hi - lo).max_element();
    let mut checked = 0;
    for i in 0..n {
        for j in 0..n {
            // Irrational offsets keep the samples off the drawing's round numbers.
            let t = DVec2::new(
                (i as f64 + 0.291_7) / n as f64,
                (j as f64 + 0.707_13) / n as f64,
            );
            let p = lo + (hi - lo) * t;
            let (expected, near) = reference(d, p);
            if near < margin {
                continue;
            }
            checked += 1;
            assert_eq!(region.contains(p), expected, "at {p}");
        }
    }
    assert!(checked > n * n / 2);
}

fn example(layer: &str, origin: DVec2) -> Drawing {
    let bytes = std::fs::read("/usr/share/openscad/examples/Old/example009.dxf").unwrap();
    let options = DrawingOptions {
        layer: Some(layer.into()),
        origin,
        scale: 1.0,
    };
    read_dxf(&bytes, &options, &DrawingLimits::default()).unwrap()
}

#[test]
fn example009_layers_with_arcs_and_circles() {
    if !std::path::Path::new("/usr/share/openscad/examples/Old").exists() {
        eprintln!("OpenSCAD's examples are not installed; skipped");
        return;
    }
    for layer in ["body", "plate", "fan_top", "fan_side"] {
        let d = example(layer, DVec2::ZERO);
        let (lo, hi) = (DVec2::new(-25.0, -55.0), DVec2::new(25.0, 25.0));
        match drawing_region(&d, &PolygonLimits::default()) {
            Ok(_) => compare(&d, lo, hi),
            Err(e) => panic!("{layer}: {e}"),
        }
    }
}

/// A DXF drawing of `entities`, as the reader gives it.
fn dxf(entities: &[Entity]) -> Drawing {
    read_dxf(
        dxf::dxf(entities).as_bytes(),
        &DrawingOptions::default(),
        &DrawingLimits::default(),
    )
    .unwrap()
}

/// A rectangle `[0, w] × [0, h]` with corners rounded by `r` (tangent arcs), moved by `at` and
/// scaled by `s`, with a hole of radius `hole` at its centre and an island inside that hole.
fn rounded(at: [f64; 2], s: f64, concave: bool) -> Vec<Entity> {
    let p = |x: f64, y: f64| [at[0] + s * x, at[1] + s * y];
    let (w, h, r) = (10.0, 6.0, 1.0);
    let mut e = vec![
        line(p(r, 0.0), p(w - r, 0.0)),
        line(p(w, r), p(w, h - r)),
        line(p(w - r, h), p(r, h)),
        line(p(0.0, h - r), p(0.0, r)),
    ];
    if concave {
        // Corners bitten out by quarter circles about the rectangle's corners.
        e.push(arc(p(w, 0.0), s * r, 90.0, 180.0));
        e.push(arc(p(w, h), s * r, 180.0, 270.0));
        e.push(arc(p(0.0, h), s * r, 270.0, 360.0));
        e.push(arc(p(0.0, 0.0), s * r, 0.0, 90.0));
    } else {
        e.push(arc(p(w - r, r), s * r, 270.0, 360.0));
        e.push(arc(p(w - r, h - r), s * r, 0.0, 90.0));
        e.push(arc(p(r, h - r), s * r, 90.0, 180.0));
        e.push(arc(p(r, r), s * r, 180.0, 270.0));
    }
    e.push(circle(p(5.0, 3.0), s * 2.0));
    e.push(circle(p(5.0, 3.0), s * 1.0));
    e.push(circle(p(2.0, 3.0), s * 0.5));
    e
}

#[test]
fn rounded_and_bitten_rectangles_with_holes_and_islands() {
    for concave in [false, true] {
        let d = dxf(&rounded([0.0, 0.0], 1.0, concave));
        assert_eq!(d.paths.len(), 1);
        assert!(d.paths[0].closed_in_file);
        let region = drawing_region(&d, &PolygonLimits::default()).unwrap();
        assert_eq!(region.steps.len(), 7);
        assert!(region.contains(DVec2::new(5.0, 3.0)), "the island");
        assert!(!region.contains(DVec2::new(6.5, 3.0)), "the hole");
        assert!(!region.contains(DVec2::new(2.0, 3.0)), "the small hole");
        assert!(!region.contains(DVec2::new(0.1, 0.1)), "a cut corner");
        compare(&d, DVec2::new(-1.0, -1.0), DVec2::new(11.0, 7.0));
    }
}

#[test]
fn far_and_tiny_drawings() {
    for (at, s) in [([1e6, -1e6], 1.0), ([0.0, 0.0], 1e-6), ([3e5, 2e5], 1e3)] {
        for concave in [false, true] {
            let d = dxf(&rounded(at, s, concave));
            let lo = DVec2::from_array(at) - s;
            let hi = DVec2::from_array(at) + DVec2::new(11.0, 7.0) * s;
            compare(&d, lo, hi);
        }
    }
}

#[test]
fn crossing_pieces_are_refused_with_their_lines() {
    let square = [
        line([0.0, 0.0], [4.0, 0.0]),
        line([4.0, 0.0], [4.0, 4.0]),
        line([4.0, 4.0], [0.0, 4.0]),
        line([0.0, 4.0], [0.0, 0.0]),
    ];
    // A circle across an edge.
    let mut e = square.to_vec();
    e.push(circle([4.0, 2.0], 1.0));
    let error = drawing_region(&dxf(&e), &PolygonLimits::default()).unwrap_err();
    assert!(
        matches!(
            error,
            RegionError::Crossing {
                piece: "the circle",
                line: 53,
                other: "a line",
                other_line: 17
            }
        ),
        "{error:?}"
    );
    assert!(error.to_string().contains("DXF line 53"), "{error}");
    // Two circles that cross.
    let e = [circle([0.0, 0.0], 1.0), circle([1.5, 0.0], 1.0)];
    let error = drawing_region(&dxf(&e), &PolygonLimits::default()).unwrap_err();
    assert!(matches!(error, RegionError::Crossing { .. }), "{error}");
    // A circle touching an edge from inside, and circles touching each other, do not cross.
    let mut e = square.to_vec();
    e.push(circle([2.0, 2.0], 2.0));
    e.push(circle([1.0, 2.0], 1.0));
    let d = dxf(&e);
    compare(&d, DVec2::splat(-1.0), DVec2::splat(5.0));
    // An arc bulging out of a square across a circle outside it.
    let mut e = square[..3].to_vec();
    e.push(arc([0.0, 2.0], 2.0, 90.0, 270.0));
    e.push(circle([-2.0, 2.0], 0.5));
    let error = drawing_region(&dxf(&e), &PolygonLimits::default()).unwrap_err();
    assert!(matches!(error, RegionError::Crossing { .. }), "{error}");
}

#[test]
fn an_open_arc_is_its_segment_and_two_half_arcs_a_disc() {
    let d = dxf(&[arc([0.0, 0.0], 2.0, 0.0, 120.0)]);
    compare(&d, DVec2::splat(-3.0), DVec2::splat(3.0));
    let d = dxf(&[
        arc([0.0, 0.0], 2.0, 0.0, 180.0),
        arc([0.0, 0.0], 2.0, 180.0, 360.0),
    ]);
    let region = drawing_region(&d, &PolygonLimits::default()).unwrap();
    assert!(region.contains(DVec2::new(0.0, 1.9)));
    assert!(region.contains(DVec2::new(0.3, -1.9)));
    compare(&d, DVec2::splat(-3.0), DVec2::splat(3.0));
}

/// A drawing of the conformance scenes (`tests/openscad/dxf`).
fn scene_drawing(name: &str) -> Drawing {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/openscad/dxf")
        .join(name);
    let bytes = std::fs::read(path).unwrap();
    read_dxf(
        &bytes,
        &DrawingOptions::default(),
        &DrawingLimits::default(),
    )
    .unwrap()
}

#[test]
fn ellipses_and_bulges_of_the_conformance_drawings() {
    let d = scene_drawing("ellipses.dxf");
    assert_eq!(d.ellipses.len(), 2);
    compare(&d, DVec2::new(-12.0, -12.0), DVec2::new(82.0, 37.0));
    let d = scene_drawing("bulges.dxf");
    compare(&d, DVec2::new(-2.0, -16.0), DVec2::new(52.0, 22.0));
}

#[test]
fn nested_and_touching_ellipses_and_circles() {
    // An ellipse holding a circle holding a rotated ellipse; an elliptic hole in a square; an
    // ellipse touching a line from outside.
    let d = dxf(&[
        ellipse([0.0, 0.0], [10.0, 0.0], 0.6, 0.0, TAU),
        circle([1.0, 0.0], 4.0),
        ellipse([1.0, 0.0], [2.0, 2.0], 0.3, 0.0, TAU),
        line([20.0, -5.0], [30.0, -5.0]),
        line([30.0, -5.0], [30.0, 5.0]),
        line([30.0, 5.0], [20.0, 5.0]),
        line([20.0, 5.0], [20.0, -5.0]),
        ellipse([25.0, 0.0], [0.0, 4.0], 0.5, 0.0, TAU),
        ellipse([25.0, 8.0], [4.0, 0.0], 0.75, 0.0, TAU),
    ]);
    let region = drawing_region(&d, &PolygonLimits::default()).unwrap();
    assert!(region.contains(DVec2::new(8.0, 0.0)));
    assert!(!region.contains(DVec2::new(-2.0, 0.0)), "the circle's hole");
    assert!(region.contains(DVec2::new(1.5, 0.5)), "the island");
    assert!(!region.contains(DVec2::new(25.0, 0.0)), "the square's hole");
    assert!(region.contains(DVec2::new(21.0, 4.0)));
    compare(&d, DVec2::new(-11.0, -7.0), DVec2::new(31.0, 12.0));
}

#[test]
fn crossing_ellipses_are_an_error_naming_both() {
    let d = dxf(&[
        ellipse([0.0, 0.0], [10.0, 0.0], 0.3, 0.0, TAU),
        ellipse([0.0, 0.0], [0.0, 10.0], 0.3, 0.0, TAU),
    ]);
    match drawing_region(&d, &PolygonLimits::default()) {
        Err(RegionError::Crossing { piece, other, .. }) => {
            assert_eq!((piece, other), ("the ellipse", "the ellipse"));
        }
        other => panic!("{other:?}"),
    }
    // An elliptic arc whose bulge crosses a line.
    let d = dxf(&[
        ellipse([0.0, 0.0], [10.0, 0.0], 0.5, 0.0, std::f64::consts::PI),
        line([-2.0, 1.0], [2.0, 8.0]),
        line([2.0, 8.0], [3.0, 1.0]),
        line([3.0, 1.0], [-2.0, 1.0]),
    ]);
    assert!(matches!(
        drawing_region(&d, &PolygonLimits::default()),
        Err(RegionError::Crossing { .. })
    ));
}
