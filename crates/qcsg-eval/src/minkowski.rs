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
//! A circular cylinder or cone cut square across its axis is the hull of its two end discs;
//! sums of discs square to one axis are discs (centres and radii add), so a part is then the
//! hull of discs: of one radius, the hull of their centres grown by that disc, built by
//! [`crate::minkowski_disc`] (a box with a cylinder: the plate with rounded vertical edges); of
//! several radii, built by [`crate::hull_frusta`] (a box with a cone). A disc with a ball
//! (toroidal edges) or with a disc about another axis is refused at both parts, and ellipsoids,
//! differences and other curved parts are refused like in `hull`.

use glam::DVec3;
use qcsg_csg::{Dag, Edge, Source};
use qcsg_mesh::{ConvexHull, convex_hull};

use crate::codes;
use crate::hull::{HullBuilder, HullLimits, HullRefusal, Piece, hull_error};
use crate::hull_frusta::AxialDisc;

/// A convex part: the hull of `points` grown by a ball of `radius` and by `disc`.
#[derive(Clone, Debug)]
pub struct Part {
    /// The points (reduced to the corners of their hull once summed).
    pub points: Vec<DVec3>,
    /// The radius.
    pub radius: f64,
    /// The axis of the discs the part is the hull of, if any: then point i is the centre of a
    /// disc square to it of radius `widths[i]`.
    pub disc: Option<Disc>,
    /// The discs' radii, one per point (empty without `disc`).
    pub widths: Vec<f64>,
    /// The source of the part, for errors.
    pub source: Source,
}

/// The axis of discs, from the cylinder or cone at `source`.
#[derive(Clone, Copy, Debug)]
pub struct Disc {
    /// The unit axis.
    pub axis: DVec3,
    /// The cylinder or cone it comes from.
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
        let (ends, widths, radius, disc, source) = match *piece {
            Piece::Point(p, s) => ([Some(p), None], [0.0; 2], 0.0, None, s),
            Piece::Ball(c, r, s) => ([Some(c), None], [0.0; 2], r, None, s),
            Piece::Cylinder(c) => {
                // The end discs: the centre moved along the axis to each end plane.
                let at = |h: f64| c.centre + (h - c.axis.dot(c.centre)) * c.axis;
                let disc = Disc {
                    axis: c.axis,
                    source: c.source,
                };
                (
                    [Some(at(c.low)), Some(at(c.high))],
                    [c.radius, c.radius_high],
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
                widths: Vec::new(),
                source,
            });
            last = Some(n);
        }
        if let Some(part) = parts.last_mut() {
            for (end, width) in ends.into_iter().zip(widths) {
                if let Some(end) = end {
                    part.points.push(end);
                    if part.disc.is_some() {
                        part.widths.push(width);
                    }
                }
            }
        }
    }
    parts
        .iter_mut()
        .try_for_each(|p| reduce(p, limits.points))?;
    Ok(parts)
}

/// Keeps only the corners of the part's hull (of its discs' centres where the discs are of one
/// radius; discs of different radii are kept for [`crate::hull_frusta`], which prunes them).
fn reduce(part: &mut Part, max_points: usize) -> Result<(), HullRefusal> {
    let width = part.widths.first().copied().unwrap_or(0.0);
    if part.widths.iter().any(|w| *w != width) {
        if part.points.len() > max_points {
            return Err(HullRefusal::Limit(
                codes::HULL_POINT_LIMIT,
                format!("a convex part of the Minkowski sum has more than {max_points} discs"),
            ));
        }
        return Ok(());
    }
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
    if part.disc.is_some() {
        part.widths = vec![width; part.points.len()];
    }
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
                widths: Vec::new(),
                source: p.source,
            };
            if part.disc.is_some() {
                let width = |part: &Part, i: usize| part.widths.get(i).copied().unwrap_or(0.0);
                part.widths = (0..p.points.len())
                    .flat_map(|i| (0..q.points.len()).map(move |j| (i, j)))
                    .map(|(i, j)| width(p, i) + width(q, j))
                    .collect();
            }
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
            Some(a)
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
            let width = part.widths.first().copied().unwrap_or(0.0);
            edges.push(if part.widths.iter().all(|w| *w == width) {
                crate::minkowski_disc::build(dag, &builder, &part.points, disc.axis, width)?
            } else {
                let discs: Vec<AxialDisc> = part
                    .points
                    .iter()
                    .zip(&part.widths)
                    .map(|(&centre, &radius)| AxialDisc { centre, radius })
                    .collect();
                crate::hull_frusta::build(dag, &builder, &discs, disc.axis)?
            });
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
