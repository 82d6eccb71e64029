//! `minkowski()` of 3-D children, exactly where every child is a union of convex polytopes and
//! balls. Each convex part is a point set grown by a radius: a polytope its corners grown by 0,
//! a ball its centre grown by r. The Minkowski sum distributes over union and of two such parts
//!
//!   (hull P ⊕ B(r)) ⊕ (hull Q ⊕ B(s)) = hull(P + Q) ⊕ B(r + s),
//!
//! with P + Q the pairwise sums, so the sum of the children is the union, over one part of each
//! child, of the hull of balls of one radius that [`crate::hull::HullBuilder`] builds exactly (a
//! box with a ball: the rounded box; a box with a box: a box). Cylinders, ellipsoids, differences
//! and other curved parts are refused like in `hull`.

use glam::DVec3;
use qcsg_csg::{Dag, Edge, Source};
use qcsg_mesh::{ConvexHull, convex_hull};

use crate::codes;
use crate::hull::{HullBuilder, HullLimits, HullRefusal, Piece, hull_error};

/// A convex part: the hull of `points` grown by `radius`.
#[derive(Clone, Debug)]
pub struct Part {
    /// The points (reduced to the corners of their hull once summed).
    pub points: Vec<DVec3>,
    /// The radius.
    pub radius: f64,
    /// The source of the part, for errors.
    pub source: Source,
}

/// The convex parts of one child from its collected pieces and their part numbers.
pub fn parts_of(
    pieces: &[Piece],
    numbers: &[usize],
    limits: &HullLimits,
) -> Result<Vec<Part>, HullRefusal> {
    let mut parts: Vec<Part> = Vec::new();
    let mut last = None;
    for (piece, &n) in pieces.iter().zip(numbers) {
        let (point, radius, source) = match *piece {
            Piece::Point(p, s) => (p, 0.0, s),
            Piece::Ball(c, r, s) => (c, r, s),
            Piece::Cylinder(c) => {
                return Err(HullRefusal::Part(
                    c.source,
                    "a cylinder (its sum with a ball has toroidal edges)",
                ));
            }
        };
        if last != Some(n) {
            parts.push(Part {
                points: Vec::new(),
                radius,
                source,
            });
            last = Some(n);
        }
        if let Some(part) = parts.last_mut() {
            part.points.push(point);
        }
    }
    parts
        .iter_mut()
        .try_for_each(|p| reduce(p, limits.points))?;
    Ok(parts)
}

/// Keeps only the corners of the part's hull.
fn reduce(part: &mut Part, max_points: usize) -> Result<(), HullRefusal> {
    let hull = convex_hull(&part.points, max_points).map_err(hull_error)?;
    part.points = match hull {
        ConvexHull::Empty => Vec::new(),
        ConvexHull::Point(p) => vec![p],
        ConvexHull::Segment(a, b) => vec![a, b],
        ConvexHull::Polygon { vertices, .. } => vertices,
        ConvexHull::Solid(faces) => {
            let mut v: Vec<DVec3> = faces.into_iter().flat_map(|f| f.vertices).collect();
            v.sort_by(|a, b| {
                a.x.total_cmp(&b.x)
                    .then(a.y.total_cmp(&b.y))
                    .then(a.z.total_cmp(&b.z))
            });
            v.dedup();
            v
        }
    };
    Ok(())
}

/// The Minkowski sum of two unions of parts.
pub fn sum(a: &[Part], b: &[Part], limits: &HullLimits) -> Result<Vec<Part>, HullRefusal> {
    if a.len().saturating_mul(b.len()) > limits.parts {
        return Err(HullRefusal::Limit(
            codes::MINKOWSKI_PART_LIMIT,
            format!(
                "the Minkowski sum is a union of more than {} convex parts",
                limits.parts
            ),
        ));
    }
    let mut out = Vec::with_capacity(a.len() * b.len());
    for p in a {
        for q in b {
            // The pairwise sums are reduced to their hull's corners, at most `limits.points`.
            if p.points.len().saturating_mul(q.points.len())
                > limits.points.saturating_mul(limits.points)
            {
                return Err(HullRefusal::Limit(
                    codes::HULL_POINT_LIMIT,
                    format!(
                        "a convex part of the Minkowski sum has more than {} points before its \
                         hull is taken",
                        limits.points.saturating_mul(limits.points)
                    ),
                ));
            }
            let mut part = Part {
                points: p
                    .points
                    .iter()
                    .flat_map(|x| q.points.iter().map(move |y| *x + *y))
                    .collect(),
                radius: p.radius + q.radius,
                source: p.source,
            };
            reduce(&mut part, limits.points)?;
            out.push(part);
        }
    }
    Ok(out)
}

/// The union of the parts as DAG nodes.
pub fn build(
    dag: &mut Dag,
    parts: &[Part],
    source: Source,
    max_points: usize,
) -> Result<Edge, HullRefusal> {
    let builder = HullBuilder { source, max_points };
    let mut edges = Vec::with_capacity(parts.len());
    for part in parts {
        let pieces: Vec<Piece> = part
            .points
            .iter()
            .map(|&p| {
                if part.radius > 0.0 {
                    Piece::Ball(p, part.radius, part.source)
                } else {
                    Piece::Point(p, part.source)
                }
            })
            .collect();
        edges.push(builder.build(dag, &pieces, part.radius)?);
    }
    Ok(match edges.len() {
        1 => edges[0],
        _ => dag.union(edges, source).into(),
    })
}
