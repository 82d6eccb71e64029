//! `minkowski()` of 3-D children, exactly where every child is a union of convex polytopes and
//! balls. Each convex part is a point set grown by a radius: a polytope its corners grown by 0,
//! a ball its centre grown by r. The Minkowski sum distributes over union and of two such parts
//!
//!   (hull P ⊕ B(r)) ⊕ (hull Q ⊕ B(s)) = hull(P + Q) ⊕ B(r + s),
//!
//! with P + Q the pairwise sums, so the sum of the children is the union, over one part of each
//! child, of the hull of balls of one radius that [`crate::hull::HullBuilder`] builds exactly (a
//! box with a ball: the rounded box; a box with a box: a box).
//!
//! A circular cylinder cut square across its axis is its axis segment grown by a disc square to
//! the axis; discs about parallel axes add their radii, and a part with a disc but no ball is
//! built by [`crate::minkowski_disc`] (a box with a cylinder: the plate with rounded vertical
//! edges). A disc with a ball (toroidal edges) or with a disc about another axis is refused at
//! both parts, and ellipsoids, differences and other curved parts are refused like in `hull`.

use glam::DVec3;
use qcsg_csg::{Dag, Edge, Source};
use qcsg_mesh::{ConvexHull, convex_hull};

use crate::codes;
use crate::hull::{HullBuilder, HullLimits, HullRefusal, Piece, hull_error};

/// A convex part: the hull of `points` grown by a ball of `radius` and by `disc`.
#[derive(Clone, Debug)]
pub struct Part {
    /// The points (reduced to the corners of their hull once summed).
    pub points: Vec<DVec3>,
    /// The radius.
    pub radius: f64,
    /// The disc square to an axis that the part is grown by, if any.
    pub disc: Option<Disc>,
    /// The source of the part, for errors.
    pub source: Source,
}

/// A disc of `radius` square to the unit `axis`, from the cylinder at `source`.
#[derive(Clone, Copy, Debug)]
pub struct Disc {
    /// The unit axis.
    pub axis: DVec3,
    /// The radius.
    pub radius: f64,
    /// The cylinder it comes from.
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
        let (ends, radius, disc, source) = match *piece {
            Piece::Point(p, s) => ([Some(p), None], 0.0, None, s),
            Piece::Ball(c, r, s) => ([Some(c), None], r, None, s),
            Piece::Cylinder(c) => {
                // The axis segment: the centre moved along the axis to each end plane.
                let at = |h: f64| c.centre + (h - c.axis.dot(c.centre)) * c.axis;
                let disc = Disc {
                    axis: c.axis,
                    radius: c.radius,
                    source: c.source,
                };
                (
                    [Some(at(c.low)), Some(at(c.high))],
                    0.0,
                    Some(disc),
                    c.source,
                )
            }
        };
        if last != Some(n) {
            parts.push(Part {
                points: Vec::new(),
                radius,
                disc,
                source,
            });
            last = Some(n);
        }
        if let Some(part) = parts.last_mut() {
            part.points.extend(ends.into_iter().flatten());
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
                disc: sum_discs(p, q)?,
                source: p.source,
            };
            reduce(&mut part, limits.points)?;
            out.push(part);
        }
    }
    Ok(out)
}

/// The disc of the sum of two parts: discs about one axis add their radii; discs about
/// different axes, or a disc with a ball, give surfaces that are not quadric.
fn sum_discs(p: &Part, q: &Part) -> Result<Option<Disc>, HullRefusal> {
    let disc = match (p.disc, q.disc) {
        (None, d) | (d, None) => d,
        (Some(a), Some(b)) => {
            if a.axis.cross(b.axis).length() > 1e-9 {
                return Err(HullRefusal::Pair(
                    [a.source, b.source],
                    "two cylinders whose axes are not parallel (the sum has surfaces that are \
                     not quadric)",
                    "turn the cylinders parallel, or sum each with the other parts separately \
                     where that is the same solid",
                ));
            }
            Some(Disc {
                radius: a.radius + b.radius,
                ..a
            })
        }
    };
    if let Some(d) = disc
        && p.radius + q.radius > 0.0
    {
        let ball = if p.radius > 0.0 { p.source } else { q.source };
        return Err(HullRefusal::Pair(
            [ball, d.source],
            "a ball together with a cylinder (the sum has toroidal edges)",
            "sum the box with the ball and unite the cylinder's part, or use a cylinder with \
             balls at its ends (a capsule) where that is the same solid",
        ));
    }
    Ok(disc)
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
        if let Some(disc) = part.disc {
            edges.push(crate::minkowski_disc::build(
                dag,
                &builder,
                &part.points,
                disc.axis,
                disc.radius,
            )?);
            continue;
        }
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
