//! Exact convex hulls of finite point sets in 3-D and 2-D, for OpenSCAD's `hull()`.
//!
//! Every decision (which points are collinear or coplanar, which side of a plane a point lies
//! on) is made with the exact orientation predicates of [`crate::exact`], so the combinatorial
//! hull is the true one for the given doubles: duplicates, collinear and coplanar inputs fall
//! into the lower-dimensional cases of [`ConvexHull`] instead of producing slivers.
//!
//! The 3-D facets are found by brute force over triples of points (a triple spans a facet's
//! plane when no point lies strictly on both sides of it), with early exit on the first point
//! of each side. That is cubic in the number of points, so the caller bounds it
//! ([`HullError::TooManyPoints`]); the hulls of OpenSCAD models (corners of boxes, centres of
//! balls, vertices of a few polyhedra) stay far below the bound.

use std::collections::HashSet;

use glam::{DVec2, DVec3};

use crate::exact::{normal_signs, orient2d, orient3d};

/// The convex hull of a point set, by its dimension.
#[derive(Clone, Debug, PartialEq)]
pub enum ConvexHull {
    /// No points.
    Empty,
    /// All points equal.
    Point(DVec3),
    /// All points on a line: the two extreme ones.
    Segment(DVec3, DVec3),
    /// All points on a plane: the polygon's vertices in order (strictly convex, no collinear
    /// vertices), counter-clockwise about `normal`.
    Polygon {
        /// The vertices.
        vertices: Vec<DVec3>,
        /// A normal of the plane (not unit), computed in floating point.
        normal: DVec3,
    },
    /// A solid polytope: its faces, each a strictly convex polygon counter-clockwise seen from
    /// outside, with its outward normal (not unit).
    Solid(Vec<HullFace>),
}

/// A face of a solid hull.
#[derive(Clone, Debug, PartialEq)]
pub struct HullFace {
    /// The vertices, counter-clockwise seen from outside.
    pub vertices: Vec<DVec3>,
    /// The outward normal (not unit), computed in floating point from the face's vertices.
    pub normal: DVec3,
}

/// Why no hull was computed.
#[derive(Clone, Debug, PartialEq)]
pub enum HullError {
    /// More distinct points than the limit.
    TooManyPoints(usize),
    /// A coordinate is not finite or beyond [`crate::MAX_MESH_COORDINATE`].
    Coordinate(f64),
}

impl std::fmt::Display for HullError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            HullError::TooManyPoints(limit) => {
                write!(f, "the hull has more than {limit} distinct points")
            }
            HullError::Coordinate(x) => write!(
                f,
                "a point of the hull has the coordinate {x:e}, beyond the supported magnitude {:e}",
                crate::MAX_MESH_COORDINATE
            ),
        }
    }
}

fn lexicographic(a: &DVec3, b: &DVec3) -> std::cmp::Ordering {
    a.x.total_cmp(&b.x)
        .then(a.y.total_cmp(&b.y))
        .then(a.z.total_cmp(&b.z))
}

fn collinear(a: DVec3, b: DVec3, c: DVec3) -> bool {
    normal_signs(a, b, c) == [0, 0, 0]
}

/// The axis to drop when projecting the plane of `a`, `b`, `c` (not collinear) to 2-D: one
/// where the exact normal is non-zero, the largest in floating point; and the sign of the
/// normal's component along it.
fn projection_axis(a: DVec3, b: DVec3, c: DVec3) -> (usize, i32) {
    let signs = normal_signs(a, b, c);
    let n = (b - a).cross(c - a).abs().to_array();
    let mut best = None::<usize>;
    for k in 0..3 {
        if signs[k] != 0 && best.is_none_or(|b| n[k] > n[b]) {
            best = Some(k);
        }
    }
    let k = best.unwrap_or(2);
    (k, signs[k])
}

/// `p` without coordinate `axis`, the other two in cyclic order (so that the projection keeps
/// orientation about `+e_axis`).
fn drop_axis(p: DVec3, axis: usize) -> DVec2 {
    let c = p.to_array();
    DVec2::new(c[(axis + 1) % 3], c[(axis + 2) % 3])
}

/// The indices of the strictly convex hull of `points` (distinct), counter-clockwise; one or two
/// indices when the points are all equal or collinear.
fn hull_2d_indices(points: &[DVec2]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_by(|&i, &j| {
        points[i]
            .x
            .total_cmp(&points[j].x)
            .then(points[i].y.total_cmp(&points[j].y))
    });
    order.dedup_by(|a, b| points[*a] == points[*b]);
    if order.len() <= 2 {
        return order;
    }
    // Andrew's monotone chain; collinear points are dropped (orientation ≤ 0 pops).
    let mut hull: Vec<usize> = Vec::with_capacity(order.len() + 1);
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &usize>> = if pass == 0 {
            Box::new(order.iter())
        } else {
            Box::new(order.iter().rev())
        };
        for &i in iter {
            while hull.len() >= start + 2
                && orient2d(
                    points[hull[hull.len() - 2]],
                    points[hull[hull.len() - 1]],
                    points[i],
                ) <= 0
            {
                hull.pop();
            }
            hull.push(i);
        }
        hull.pop();
    }
    if hull.len() < 3 {
        // Collinear: the two extreme points.
        return vec![order[0], order[order.len() - 1]];
    }
    hull
}

/// The strictly convex hull of `points` in the plane, counter-clockwise: empty, one point, the
/// two ends of a segment, or a polygon of at least three vertices with no collinear ones.
pub fn convex_hull_2d(points: &[DVec2]) -> Vec<DVec2> {
    hull_2d_indices(points)
        .into_iter()
        .map(|i| points[i])
        .collect()
}

/// Newell's normal of a planar polygon: robust for any vertex count.
fn newell(vertices: &[DVec3]) -> DVec3 {
    let centre = vertices.iter().copied().sum::<DVec3>() / vertices.len() as f64;
    let mut n = DVec3::ZERO;
    for (i, &a) in vertices.iter().enumerate() {
        let b = vertices[(i + 1) % vertices.len()];
        n += (a - centre).cross(b - centre);
    }
    n
}

/// The convex hull of `points` (at most `max_points` distinct ones).
pub fn convex_hull(points: &[DVec3], max_points: usize) -> Result<ConvexHull, HullError> {
    for p in points {
        for x in p.to_array() {
            if !x.is_finite() || x.abs() > crate::MAX_MESH_COORDINATE {
                return Err(HullError::Coordinate(x));
            }
        }
    }
    let mut p: Vec<DVec3> = points.to_vec();
    // −0 and +0 are the same point.
    for q in &mut p {
        *q += DVec3::ZERO;
    }
    p.sort_by(lexicographic);
    p.dedup();
    if p.len() > max_points {
        return Err(HullError::TooManyPoints(max_points));
    }
    match p.len() {
        0 => return Ok(ConvexHull::Empty),
        1 => return Ok(ConvexHull::Point(p[0])),
        _ => {}
    }
    let Some(k) = (2..p.len()).find(|&k| !collinear(p[0], p[1], p[k])) else {
        // Sorted lexicographically, collinear points have their extremes first and last.
        return Ok(ConvexHull::Segment(p[0], p[p.len() - 1]));
    };
    let (a, b, c) = (p[0], p[1], p[k]);
    if (0..p.len()).all(|m| orient3d(a, b, c, p[m]) == 0) {
        let (axis, sign) = projection_axis(a, b, c);
        let flat: Vec<DVec2> = p.iter().map(|q| drop_axis(*q, axis)).collect();
        let mut vertices: Vec<DVec3> = hull_2d_indices(&flat).into_iter().map(|i| p[i]).collect();
        // Counter-clockwise about +e_axis; about the normal (b − a) × (c − a) when it points
        // the same way.
        if sign < 0 {
            vertices.reverse();
        }
        let normal = newell(&vertices);
        return Ok(ConvexHull::Polygon { vertices, normal });
    }
    let n = p.len();
    let mut seen: HashSet<Vec<usize>> = HashSet::new();
    let mut faces = Vec::new();
    let mut on_plane = Vec::with_capacity(n);
    for i in 0..n {
        for j in i + 1..n {
            for k in j + 1..n {
                if collinear(p[i], p[j], p[k]) {
                    continue;
                }
                let (mut positive, mut negative) = (false, false);
                on_plane.clear();
                for m in 0..n {
                    match orient3d(p[i], p[j], p[k], p[m]) {
                        0 => on_plane.push(m),
                        s if s > 0 => positive = true,
                        _ => negative = true,
                    }
                    if positive && negative {
                        break;
                    }
                }
                if (positive && negative) || on_plane.first() != Some(&i) {
                    // Not a supporting plane, or one already met from its first point.
                    continue;
                }
                if !seen.insert(on_plane.clone()) {
                    continue;
                }
                let (axis, sign) = projection_axis(p[i], p[j], p[k]);
                let flat: Vec<DVec2> = on_plane.iter().map(|&m| drop_axis(p[m], axis)).collect();
                let mut vertices: Vec<DVec3> = hull_2d_indices(&flat)
                    .into_iter()
                    .map(|h| p[on_plane[h]])
                    .collect();
                // orient3d > 0 for the other points: they lie opposite (pj − pi) × (pk − pi),
                // which is then outward. The projected polygon is counter-clockwise about
                // sign · e_axis, i.e. about that normal.
                let outward_is_normal = positive;
                if outward_is_normal != (sign > 0) {
                    vertices.reverse();
                }
                let normal = newell(&vertices);
                faces.push(HullFace { vertices, normal });
            }
        }
    }
    Ok(ConvexHull::Solid(faces))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube_corners(offset: DVec3, size: f64) -> Vec<DVec3> {
        let mut v = Vec::new();
        for i in 0..8 {
            v.push(
                offset
                    + size
                        * DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64),
            );
        }
        v
    }

    #[test]
    fn cube_has_six_square_faces_facing_out() {
        let mut pts = cube_corners(DVec3::splat(1e6), 1e-3);
        // Interior, face-centre and edge-midpoint points change nothing.
        pts.push(DVec3::splat(1e6 + 5e-4));
        pts.push(DVec3::new(1e6 + 5e-4, 1e6 + 5e-4, 1e6));
        pts.push(DVec3::new(1e6 + 5e-4, 1e6, 1e6));
        pts.extend(cube_corners(DVec3::splat(1e6), 1e-3));
        let ConvexHull::Solid(faces) = convex_hull(&pts, 100).unwrap() else {
            panic!("solid")
        };
        assert_eq!(faces.len(), 6);
        let centre = DVec3::splat(1e6 + 5e-4);
        for f in &faces {
            assert_eq!(f.vertices.len(), 4);
            assert!(f.normal.dot(f.vertices[0] - centre) > 0.0);
        }
    }

    #[test]
    fn degenerate_sets() {
        assert_eq!(convex_hull(&[], 10).unwrap(), ConvexHull::Empty);
        let a = DVec3::new(1.0, 2.0, 3.0);
        assert_eq!(convex_hull(&[a, a], 10).unwrap(), ConvexHull::Point(a));
        let line: Vec<DVec3> = (0..5).map(|i| a + DVec3::ONE * i as f64 * 0.25).collect();
        assert_eq!(
            convex_hull(&line, 10).unwrap(),
            ConvexHull::Segment(line[0], line[4])
        );
        let square = [
            DVec3::ZERO,
            DVec3::X,
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::Y,
            DVec3::new(0.5, 0.0, 0.0),
        ];
        let ConvexHull::Polygon { vertices, normal } = convex_hull(&square, 10).unwrap() else {
            panic!("polygon")
        };
        assert_eq!(vertices.len(), 4);
        assert!(normal.z.abs() > 0.0);
        assert!(matches!(
            convex_hull(&square, 3),
            Err(HullError::TooManyPoints(3))
        ));
        assert!(convex_hull(&[DVec3::splat(f64::NAN)], 3).is_err());
    }

    #[test]
    fn hull_2d_drops_collinear_points() {
        let pts = [
            DVec2::ZERO,
            DVec2::new(2.0, 0.0),
            DVec2::new(1.0, 0.0),
            DVec2::new(2.0, 2.0),
            DVec2::new(0.0, 2.0),
            DVec2::new(1.0, 1.0),
        ];
        let h = convex_hull_2d(&pts);
        assert_eq!(h.len(), 4);
        assert_eq!(convex_hull_2d(&pts[..3]).len(), 2);
    }
}
