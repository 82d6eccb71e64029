//! `polygon_cells` against an independent even–odd point-in-polygon oracle, on random, adversarial
//! and degenerate polygons at ordinary, huge, tiny and far-off coordinates, with bounds on the
//! number and size of the cells.

use glam::DVec2;
use proptest::prelude::*;
use qcsg_mesh::{Polygon, PolygonError, PolygonLimits, polygon_cells};
use qcsg_testkit::Rng;

/// The even–odd rule by a horizontal ray, the textbook way (no shared code with the crate).
fn oracle(points: &[DVec2], paths: &[Vec<usize>], p: DVec2) -> bool {
    let mut inside = false;
    for path in paths {
        for k in 0..path.len() {
            let a = points[path[k]];
            let b = points[path[(k + 1) % path.len()]];
            if (a.y > p.y) != (b.y > p.y) {
                let x = a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x);
                if p.x < x {
                    inside = !inside;
                }
            }
        }
    }
    inside
}

/// The distance from `p` to the nearest edge.
fn distance_to_outline(points: &[DVec2], paths: &[Vec<usize>], p: DVec2) -> f64 {
    let mut best = f64::INFINITY;
    for path in paths {
        for k in 0..path.len() {
            let a = points[path[k]];
            let b = points[path[(k + 1) % path.len()]];
            let ab = b - a;
            let t = if ab == DVec2::ZERO {
                0.0
            } else {
                ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
            };
            best = best.min((a + ab * t - p).length());
        }
    }
    best
}

fn decompose(points: &[DVec2], paths: &[Vec<usize>]) -> Polygon {
    polygon_cells(points, Some(paths), &PolygonLimits::default()).expect("a valid polygon")
}

/// Checks membership at `samples` points of the outline's box (and a margin around it) against
/// the oracle, skipping points within `1e-9` of the box size (or a few units in the last place
/// of the coordinates) from an edge, and checks that no point lies in two cells and that every
/// cell's box contains the point.
fn check_membership(points: &[DVec2], paths: &[Vec<usize>], samples: usize, seed: u64) -> Polygon {
    let polygon = decompose(points, paths);
    let (lo, hi) = points.iter().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    let size = (hi - lo).max_element();
    // Within a few units in the last place of the coordinates a point's side of an edge is
    // rounding: a polygon 10⁻³ wide at 10⁶ from the origin has coordinates 1.2·10⁻¹⁰ apart,
    // a thousand times the relative band.
    let magnitude = lo.abs().max(hi.abs()).max_element();
    let band = 1e-9 * size + 64.0 * f64::EPSILON * magnitude;
    let margin = (hi - lo) * 0.1;
    let mut rng = Rng::new(seed);
    for _ in 0..samples {
        let p = lo - margin + (hi - lo + 2.0 * margin) * DVec2::new(rng.unit(), rng.unit());
        if distance_to_outline(points, paths, p) < band {
            continue;
        }
        let expected = oracle(points, paths, p);
        let containing: Vec<_> = polygon.cells.iter().filter(|c| c.contains(p)).collect();
        assert_eq!(
            !containing.is_empty(),
            expected,
            "membership of {p:?} (oracle: {expected}) in a polygon of {} points",
            points.len()
        );
        assert!(
            containing.len() <= 1,
            "{p:?} lies in {} cells",
            containing.len()
        );
        for c in containing {
            assert!(
                c.min.cmple(p).all() && p.cmple(c.max).all(),
                "cell box misses {p:?}"
            );
        }
    }
    polygon
}

fn one_path(n: usize) -> Vec<Vec<usize>> {
    vec![(0..n).collect()]
}

fn max_half_planes(polygon: &Polygon) -> usize {
    polygon
        .cells
        .iter()
        .map(|c| c.half_planes.len())
        .max()
        .unwrap_or(0)
}

fn star(n: usize, inner: f64, outer: f64) -> Vec<DVec2> {
    (0..n)
        .map(|i| {
            let angle = std::f64::consts::TAU * i as f64 / n as f64;
            let r = if i % 2 == 0 { outer } else { inner };
            DVec2::new(angle.cos(), angle.sin()) * r
        })
        .collect()
}

fn circle(n: usize, r: f64) -> Vec<DVec2> {
    star(n, r, r)
}

fn comb(teeth: usize) -> Vec<DVec2> {
    // A base bar with `teeth` tall thin teeth.
    let mut points = vec![DVec2::new(0.0, 0.0), DVec2::new(2.0 * teeth as f64, 0.0)];
    for t in (0..teeth).rev() {
        let x = 2.0 * t as f64;
        points.push(DVec2::new(x + 1.0, 1.0));
        points.push(DVec2::new(x + 1.0, 50.0));
        points.push(DVec2::new(x, 50.0));
        points.push(DVec2::new(x, 1.0));
    }
    points.pop();
    points[1].y = 0.0;
    points.push(DVec2::new(0.0, 1.0));
    points
}

#[test]
fn pentagram_loses_its_centre_and_bow_tie_keeps_two_triangles() {
    let pentagram: Vec<DVec2> = (0..5)
        .map(|i| {
            let a = (90.0 + 144.0 * i as f64).to_radians();
            DVec2::new(a.cos(), a.sin()) * 10.0
        })
        .collect();
    let polygon = check_membership(&pentagram, &one_path(5), 4000, 1);
    assert!(!polygon.contains(DVec2::ZERO));
    assert!(polygon.contains(DVec2::new(0.0, 8.0)));
    assert!(
        polygon
            .warnings
            .iter()
            .any(|w| w.contains("crosses itself")),
        "{:?}",
        polygon.warnings
    );

    let bow_tie = [
        DVec2::new(0.0, 0.0),
        DVec2::new(10.0, 10.0),
        DVec2::new(10.0, 0.0),
        DVec2::new(0.0, 10.0),
    ];
    let polygon = check_membership(&bow_tie, &one_path(4), 4000, 2);
    assert!(polygon.contains(DVec2::new(1.0, 5.0)));
    assert!(polygon.contains(DVec2::new(9.0, 5.0)));
    assert!(!polygon.contains(DVec2::new(5.0, 1.0)));
}

#[test]
fn paths_combine_by_even_odd_whatever_their_orientation() {
    let square = |x: f64, y: f64, s: f64| {
        [
            DVec2::new(x, y),
            DVec2::new(x + s, y),
            DVec2::new(x + s, y + s),
            DVec2::new(x, y + s),
        ]
    };
    // A hole with the same orientation as its outline.
    let points: Vec<DVec2> = square(0.0, 0.0, 10.0)
        .into_iter()
        .chain(square(2.0, 2.0, 6.0))
        .collect();
    let paths = vec![vec![0, 1, 2, 3], vec![4, 5, 6, 7]];
    let polygon = check_membership(&points, &paths, 4000, 3);
    assert!(!polygon.contains(DVec2::splat(5.0)) && polygon.contains(DVec2::splat(1.0)));
    // Overlapping squares keep what one covers.
    let points: Vec<DVec2> = square(0.0, 0.0, 10.0)
        .into_iter()
        .chain(square(5.0, 0.0, 10.0))
        .collect();
    let polygon = check_membership(&points, &paths, 4000, 4);
    assert!(!polygon.contains(DVec2::new(7.0, 5.0)) && polygon.contains(DVec2::new(12.0, 5.0)));
    // The same square twice is empty, even given with the opposite orientation.
    let points: Vec<DVec2> = square(0.0, 0.0, 10.0)
        .into_iter()
        .chain(square(0.0, 0.0, 10.0))
        .collect();
    assert!(decompose(&points, &paths).cells.is_empty());
    assert!(
        decompose(&points, &[vec![0, 1, 2, 3], vec![7, 6, 5, 4]])
            .cells
            .is_empty()
    );
    // Without paths the points are one outline.
    let polygon = polygon_cells(&square(0.0, 0.0, 1.0), None, &PolygonLimits::default()).unwrap();
    assert!(polygon.contains(DVec2::splat(0.5)));
    assert_eq!((polygon.min, polygon.max), (DVec2::ZERO, DVec2::ONE));
}

#[test]
fn boundary_lies_on_input_lines() {
    // Every half-plane of every cell is a box wall (axis-parallel) or the line through two input
    // points, bit for bit.
    let points = star(40, 3.0, 7.0);
    let polygon = decompose(&points, &one_path(40));
    let lines: Vec<qcsg_mesh::HalfPlane> = (0..40)
        .map(|i| qcsg_mesh::HalfPlane::left_of(points[i], points[(i + 1) % 40]))
        .collect();
    for cell in &polygon.cells {
        for h in &cell.half_planes {
            let axis_parallel = h.normal.x == 0.0 || h.normal.y == 0.0;
            assert!(
                axis_parallel || lines.iter().any(|l| *l == *h || l.flipped() == *h),
                "{h:?}"
            );
        }
    }
}

#[test]
fn degenerate_outlines() {
    let limits = PolygonLimits::default();
    // Repeated points, zero-length edges and collinear runs.
    let points = vec![
        DVec2::new(0.0, 0.0),
        DVec2::new(0.0, 0.0),
        DVec2::new(5.0, 0.0),
        DVec2::new(10.0, 0.0),
        DVec2::new(10.0, 10.0),
        DVec2::new(10.0, 10.0),
        DVec2::new(0.0, 10.0),
    ];
    check_membership(&points, &one_path(7), 3000, 5);
    // Zero area: a segment there and back, all points collinear.
    let line = [
        DVec2::new(0.0, 0.0),
        DVec2::new(1.0, 1.0),
        DVec2::new(3.0, 3.0),
    ];
    assert!(
        polygon_cells(&line, None, &limits)
            .unwrap()
            .cells
            .is_empty()
    );
    let flat = [
        DVec2::new(0.0, 0.0),
        DVec2::new(1.0, 0.0),
        DVec2::new(3.0, 0.0),
    ];
    assert!(
        polygon_cells(&flat, None, &limits)
            .unwrap()
            .cells
            .is_empty()
    );
    // Fewer than three points: empty, with a warning.
    let two = polygon_cells(&[DVec2::ZERO, DVec2::ONE], None, &limits).unwrap();
    assert!(two.cells.is_empty() && two.warnings[0].contains("fewer than three"));
    assert!(polygon_cells(&[], None, &limits).unwrap().cells.is_empty());
    // A spike: an edge out and back inside a square.
    let spike = [
        DVec2::new(0.0, 0.0),
        DVec2::new(10.0, 0.0),
        DVec2::new(10.0, 5.0),
        DVec2::new(3.0, 5.0),
        DVec2::new(10.0, 5.0),
        DVec2::new(10.0, 10.0),
        DVec2::new(0.0, 10.0),
    ];
    check_membership(&spike, &one_path(7), 3000, 6);
}

#[test]
fn bad_input_is_an_error_naming_the_culprit() {
    let limits = PolygonLimits::default();
    let mut points = vec![DVec2::ZERO, DVec2::X, DVec2::Y];
    let paths = vec![vec![0, 1, 2], vec![0, 1, 7]];
    let error = polygon_cells(&points, Some(&paths), &limits).unwrap_err();
    assert_eq!(
        error,
        PolygonError::IndexOutOfRange {
            path: 1,
            position: 2,
            index: 7,
            points: 3
        }
    );
    assert!(
        error
            .to_string()
            .contains("entry 2 of path 1 refers to point 7"),
        "{error}"
    );
    points[1].y = f64::NAN;
    let error = polygon_cells(&points, None, &limits).unwrap_err();
    assert_eq!(error, PolygonError::NonFinitePoint { index: 1 });
    assert!(error.to_string().contains("point 1"));
    points[1].y = f64::INFINITY;
    assert_eq!(
        polygon_cells(&points, None, &limits).unwrap_err(),
        PolygonError::NonFinitePoint { index: 1 }
    );
    points[1].y = 1e200;
    assert!(matches!(
        polygon_cells(&points, None, &limits).unwrap_err(),
        PolygonError::HugeCoordinate { index: 1, .. }
    ));
    let small = PolygonLimits { max_points: 2 };
    assert!(matches!(
        polygon_cells(&[DVec2::ZERO, DVec2::X, DVec2::Y], None, &small).unwrap_err(),
        PolygonError::TooManyPoints { count: 3, limit: 2 }
    ));
    let many_entries = vec![vec![0, 1, 0, 1]];
    assert!(matches!(
        polygon_cells(&[DVec2::ZERO, DVec2::X], Some(&many_entries), &small).unwrap_err(),
        PolygonError::TooManyPoints { count: 4, limit: 2 }
    ));
}

#[test]
fn many_edges_through_one_point() {
    // A fan of 200 thin triangles sharing the origin, as separate paths, and a star whose every
    // spike goes through the centre.
    let n = 200;
    let mut points = vec![DVec2::ZERO];
    let mut paths = Vec::new();
    for i in 0..n {
        let a = std::f64::consts::TAU * i as f64 / n as f64;
        points.push(DVec2::new(a.cos(), a.sin()) * 10.0);
        points.push(DVec2::new((a + 0.01).cos(), (a + 0.01).sin()) * 10.0);
        paths.push(vec![0, 2 * i + 1, 2 * i + 2]);
    }
    let polygon = check_membership(&points, &paths, 4000, 7);
    assert!(
        max_half_planes(&polygon) <= 8,
        "{}",
        max_half_planes(&polygon)
    );
}

#[test]
fn large_outlines_give_linearly_many_small_cells() {
    let cases: Vec<(&str, Vec<DVec2>)> = vec![
        ("star", star(5000, 50.0, 100.0)),
        ("circle", circle(5000, 100.0)),
        ("comb", comb(1000)),
    ];
    for (name, points) in cases {
        let n = points.len();
        let polygon = check_membership(&points, &one_path(n), 3000, 8);
        let cells = polygon.cells.len();
        let widest = max_half_planes(&polygon);
        assert!(cells <= 8 * n, "{name}: {cells} cells for {n} points");
        assert!(widest <= 8, "{name}: a cell with {widest} half-planes");
    }
    // A square with 100 square holes.
    let mut points = vec![
        DVec2::new(0.0, 0.0),
        DVec2::new(30.0, 0.0),
        DVec2::new(30.0, 30.0),
        DVec2::new(0.0, 30.0),
    ];
    let mut paths = vec![vec![0, 1, 2, 3]];
    for i in 0..10 {
        for j in 0..10 {
            let base = points.len();
            let (x, y) = (1.0 + 3.0 * i as f64, 1.0 + 3.0 * j as f64);
            points.extend([
                DVec2::new(x, y),
                DVec2::new(x + 1.5, y),
                DVec2::new(x + 1.5, y + 1.5),
                DVec2::new(x, y + 1.5),
            ]);
            paths.push((base..base + 4).collect());
        }
    }
    let polygon = check_membership(&points, &paths, 4000, 9);
    assert!(polygon.cells.len() <= 8 * points.len());
    assert!(max_half_planes(&polygon) <= 8);
}

/// A polygon of `n` random points in the unit square, as one outline or split into paths.
fn random_polygon() -> impl Strategy<Value = (Vec<DVec2>, Vec<Vec<usize>>)> {
    (3usize..40, 1usize..4).prop_flat_map(|(n, path_count)| {
        (
            proptest::collection::vec((0.0f64..1.0, 0.0f64..1.0), n * path_count),
            Just((n, path_count)),
        )
            .prop_map(|(coordinates, (n, path_count))| {
                let points: Vec<DVec2> = coordinates
                    .into_iter()
                    .map(|(x, y)| DVec2::new(x, y))
                    .collect();
                let paths = (0..path_count)
                    .map(|p| (p * n..(p + 1) * n).collect())
                    .collect();
                (points, paths)
            })
    })
}

/// A polygon on a small integer grid: collinear edges, shared vertices and axis-parallel edges on
/// the tree's split lines.
fn grid_polygon() -> impl Strategy<Value = (Vec<DVec2>, Vec<Vec<usize>>)> {
    proptest::collection::vec((0i32..6, 0i32..6), 3..24).prop_map(|coordinates| {
        let points: Vec<DVec2> = coordinates
            .into_iter()
            .map(|(x, y)| DVec2::new(x as f64, y as f64))
            .collect();
        let n = points.len();
        (points, vec![(0..n).collect()])
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    #[test]
    fn random_polygons_match_the_oracle((points, paths) in random_polygon(), seed in 0u64..1000) {
        check_membership(&points, &paths, 400, seed);
    }

    #[test]
    fn grid_polygons_match_the_oracle((points, paths) in grid_polygon(), seed in 0u64..1000) {
        check_membership(&points, &paths, 400, seed);
    }

    #[test]
    fn scaled_and_moved_polygons_match_the_oracle(
        (points, paths) in random_polygon(),
        seed in 0u64..1000,
        placement in 0usize..4,
    ) {
        let (scale, offset) = [(1e6, 0.0), (1e-6, 0.0), (1.0, 1e6), (1e-3, -1e6)][placement];
        let points: Vec<DVec2> = points.iter().map(|&p| p * scale + DVec2::splat(offset)).collect();
        check_membership(&points, &paths, 400, seed);
    }
}
