//! `hull()` of 2-D children: the figure read as points (the corners of convex polygons:
//! `square`s, cells of `polygon`s) and discs (`circle`s), and, as in 3-D ([`crate::hull`]):
//!
//! - points alone give their convex polygon K ([`qcsg_mesh::convex_hull_2d`], exact), an
//!   intersection of half-planes (nothing when the points are collinear: no area);
//! - discs of one radius r give K ⊕ disc(r): K ∪ a band per edge of K (the rectangle between the
//!   edge and its copy moved out by r) ∪ a disc per vertex; a segment K is the stadium, a point
//!   the disc.
//!
//! The hull of circular cylinders with parallel axes, cut by the same two planes across them,
//! is the 2-D hull of their sections extruded between the planes ([`build_prism`]): the rounded
//! box of four vertical cylinders.
//!
//! Discs of different radii (a point is a disc of radius 0) have lines tangent to two circles
//! in their hull, built by [`crate::hull_discs`]; ellipses, differences and complements are
//! refused.

use glam::{DMat4, DVec2, DVec3, DVec4};
use qcsg_csg::{Dag, Edge, Source};
use qcsg_mesh::convex_hull_2d;
use qcsg_quadric::Quadric;

use crate::codes;
use crate::hull::{Cylinder, HullLimits, HullRefusal};
use crate::offset::{circle_of, convex_vertices, lines_of};
use crate::planar::{PlanarExpr, PlanarId, PlanarKind};
use crate::primitives_2d::column;

/// What a 2-D hull is made of.
#[derive(Clone, Copy, Debug)]
pub enum Piece2 {
    /// A corner of a convex polygon.
    Point(DVec2, Source),
    /// A disc: centre, radius.
    Disc(DVec2, f64, Source),
}

/// Collects the pieces of a plane figure.
pub struct Collector2<'e> {
    expr: &'e PlanarExpr,
    /// The pieces found so far.
    pub pieces: Vec<Piece2>,
    /// For each piece, the convex part it belongs to (a disc and each convex polygon are one
    /// part each), numbered from 0.
    pub parts: Vec<usize>,
}

impl<'e> Collector2<'e> {
    /// A collector over `expr`.
    pub fn new(expr: &'e PlanarExpr) -> Self {
        Self {
            expr,
            pieces: Vec::new(),
            parts: Vec::new(),
        }
    }

    /// Adds the pieces of the node `id`.
    pub fn add(&mut self, id: PlanarId) -> Result<(), HullRefusal> {
        stacker::maybe_grow(128 * 1024, 4 * 1024 * 1024, || self.node(id))
    }

    fn node(&mut self, id: PlanarId) -> Result<(), HullRefusal> {
        let node = self.expr.node(id);
        match &node.kind {
            PlanarKind::Union(children) => {
                for &c in children {
                    self.add(c)?;
                }
                Ok(())
            }
            PlanarKind::Difference(_) => Err(HullRefusal::Part(node.source, "a difference")),
            PlanarKind::Complement(_) => Err(HullRefusal::Part(node.source, "a complement")),
            PlanarKind::Leaf(_) | PlanarKind::Intersection(_) => self.convex(id),
        }
    }

    fn convex(&mut self, id: PlanarId) -> Result<(), HullRefusal> {
        let node = self.expr.node(id);
        let children = match &node.kind {
            PlanarKind::Intersection(children) => children.clone(),
            _ => vec![id],
        };
        let mut lines = Vec::new();
        let mut circles = Vec::new();
        for &c in &children {
            let child = self.expr.node(c);
            match &child.kind {
                PlanarKind::Leaf(conic) => {
                    if let Some(found) = lines_of(conic) {
                        lines.extend(found);
                    } else if let Some(circle) = circle_of(conic) {
                        circles.push((circle, child.source));
                    } else {
                        return Err(HullRefusal::Part(child.source, "an ellipse"));
                    }
                }
                PlanarKind::Intersection(_) if children.len() == 1 => return self.convex(c),
                _ => {
                    return Err(HullRefusal::Part(
                        child.source,
                        "an intersection with a union, difference or complement",
                    ));
                }
            }
        }
        match (lines.is_empty(), circles.as_slice()) {
            (true, [((centre, radius), source)]) => {
                self.pieces.push(Piece2::Disc(*centre, *radius, *source));
                self.parts.push(self.parts.last().map_or(0, |n| n + 1));
                Ok(())
            }
            (false, []) => {
                let Some((min, max)) = node.bounds else {
                    return Err(HullRefusal::Part(node.source, "an unbounded part"));
                };
                let part = self.parts.last().map_or(0, |n| n + 1);
                for v in convex_vertices(&lines, min, max) {
                    self.pieces.push(Piece2::Point(v, node.source));
                    self.parts.push(part);
                }
                Ok(())
            }
            (true, []) => Ok(()),
            _ => Err(HullRefusal::Part(
                node.source,
                "a circle cut by other parts",
            )),
        }
    }
}

/// The common radius of the pieces (0 for points), or the two that differ.
pub fn common_radius(pieces: &[Piece2]) -> Result<f64, HullRefusal> {
    let radius = |p: &Piece2| match *p {
        Piece2::Point(_, s) => (s, 0.0),
        Piece2::Disc(_, r, s) => (s, r),
    };
    let Some(first) = pieces.first().map(radius) else {
        return Ok(0.0);
    };
    for p in &pieces[1..] {
        let (s, r) = radius(p);
        if (r - first.1).abs() > 1e-9 * r.max(first.1) {
            return Err(HullRefusal::UnequalRadii([first, (s, r)]));
        }
    }
    Ok(first.1)
}

pub(crate) fn boxed(dag: &mut Dag, edge: Edge, points: &[DVec2], r: f64) -> Edge {
    let min = points.iter().fold(DVec2::INFINITY, |m, p| m.min(*p)) - r;
    let max = points.iter().fold(DVec2::NEG_INFINITY, |m, p| m.max(*p)) + r;
    let pad = 1e-9 * (max - min).max_element() + 1e-15 * max.abs().max(min.abs()).max_element();
    dag.bounded(edge.child, column(min - pad, max + pad)).into()
}

pub(crate) fn leaf(dag: &mut Dag, q: Option<Quadric>, source: Source) -> Edge {
    match q {
        Some(q) => dag.leaf(q, source).into(),
        None => dag.empty(source).into(),
    }
}

pub(crate) fn disc(dag: &mut Dag, c: DVec2, r: f64, source: Source) -> Edge {
    let q = Quadric::cylinder(c.extend(0.0), DVec3::Z, r);
    let e = leaf(dag, q, source);
    boxed(dag, e, &[c], r)
}

/// The rectangle over the segment `a`–`b`, `r` wide on either side.
fn band(dag: &mut Dag, a: DVec2, b: DVec2, r: f64, source: Source) -> Edge {
    let mid = (0.5 * (a + b)).extend(0.0);
    let along = (b - a).extend(0.0);
    let across = DVec3::new(-along.y, along.x, 0.0);
    let parts = vec![
        leaf(dag, Quadric::slab(mid, along, 0.5 * along.length()), source),
        leaf(dag, Quadric::slab(mid, across, r), source),
    ];
    let cut = dag.intersection(parts, source);
    boxed(dag, cut.into(), &[a, b], r)
}

/// The hull of `pieces`, all of radius `r`, as a z-invariant solid.
pub fn build(
    dag: &mut Dag,
    pieces: &[Piece2],
    r: f64,
    source: Source,
    max_points: usize,
) -> Result<Edge, HullRefusal> {
    let centres: Vec<DVec2> = pieces
        .iter()
        .map(|p| match *p {
            Piece2::Point(c, _) | Piece2::Disc(c, _, _) => c,
        })
        .collect();
    if let Some(bad) = centres.iter().find(|c| !c.is_finite()) {
        return Err(HullRefusal::Unrepresentable(format!(
            "a point of the hull is not finite ({bad})"
        )));
    }
    let mut distinct = centres.clone();
    distinct.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    distinct.dedup();
    if distinct.len() > max_points.saturating_mul(64) {
        return Err(HullRefusal::Limit(
            codes::HULL_POINT_LIMIT,
            format!(
                "the 2-D hull has more than {} distinct points (64 times the limit)",
                max_points.saturating_mul(64)
            ),
        ));
    }
    let k = convex_hull_2d(&distinct);
    let round = r > 0.0;
    let mut parts = Vec::new();
    if k.len() >= 3 {
        let mut cell = Vec::with_capacity(k.len());
        for (i, &a) in k.iter().enumerate() {
            let b = k[(i + 1) % k.len()];
            let t = b - a;
            // Counter-clockwise: the outward normal is the edge turned clockwise.
            let n = DVec3::new(t.y, -t.x, 0.0);
            cell.push(leaf(dag, Quadric::half_space(a.extend(0.0), n), source));
        }
        let cut = dag.intersection(cell, source);
        parts.push(boxed(dag, cut.into(), &k, 0.0));
    }
    if round {
        let edges = match k.len() {
            0 | 1 => 0,
            2 => 1,
            n => n,
        };
        for i in 0..edges {
            parts.push(band(dag, k[i], k[(i + 1) % k.len()], r, source));
        }
        for &c in &k {
            parts.push(disc(dag, c, r, source));
        }
    }
    if parts.is_empty() {
        return Ok(dag.empty(source).into());
    }
    let union = dag.union(parts, source);
    Ok(boxed(dag, union.into(), &k, r))
}

/// The hull of `cylinders`: parallel axes and the same two end planes (else refused), any radii.
pub fn build_prism(
    dag: &mut Dag,
    cylinders: &[Cylinder],
    source: Source,
    max_points: usize,
) -> Result<Edge, HullRefusal> {
    let Some(first) = cylinders.first() else {
        return Ok(dag.empty(source).into());
    };
    let u = first.axis;
    let scale = cylinders
        .iter()
        .map(|c| c.high - c.low + c.radius)
        .fold(0.0f64, f64::max);
    for c in &cylinders[1..] {
        if c.axis.cross(u).length() > 1e-9 {
            return Err(HullRefusal::Pair(
                [first.source, c.source],
                "two cylinders whose axes are not parallel (the hull has ruled surfaces that \
                 are not quadric)",
                "turn the cylinders parallel, or unite the hulls of parallel groups where that is \
                 the same solid",
            ));
        }
        let tol = 1e-9 * scale + 1e-15 * c.low.abs().max(c.high.abs());
        if (c.low - first.low).abs() > tol || (c.high - first.high).abs() > tol {
            return Err(HullRefusal::Pair(
                [first.source, c.source],
                "two parallel cylinders whose ends do not lie on the same two planes",
                "give the cylinders the same height and base, or unite the hull with the taller \
                 cylinder where that is the same solid",
            ));
        }
    }
    // A frame (e1, e2, u), the axes themselves when u is one.
    let (e1, e2) = if u == DVec3::Z {
        (DVec3::X, DVec3::Y)
    } else if u == DVec3::X {
        (DVec3::Y, DVec3::Z)
    } else if u == DVec3::Y {
        (DVec3::Z, DVec3::X)
    } else {
        let helper = if u.x.abs() < 0.9 { DVec3::X } else { DVec3::Y };
        let e1 = u.cross(helper).normalize();
        (e1, u.cross(e1))
    };
    let pieces: Vec<Piece2> = cylinders
        .iter()
        .map(|c| {
            Piece2::Disc(
                DVec2::new(e1.dot(c.centre), e2.dot(c.centre)),
                c.radius,
                c.source,
            )
        })
        .collect();
    let section = match common_radius(&pieces) {
        Ok(r) => build(dag, &pieces, r, source, max_points)?,
        Err(HullRefusal::UnequalRadii(_)) => {
            crate::hull_discs::build(dag, &pieces, source, max_points)?
        }
        Err(refusal) => return Err(refusal),
    };
    let (low, high) = (first.low, first.high);
    let mid = 0.5 * (low + high);
    let slab = match Quadric::slab(DVec3::new(0.0, 0.0, mid), DVec3::Z, 0.5 * (high - low)) {
        Some(q) => dag.leaf(q, source).into(),
        None => return Ok(dag.empty(source).into()),
    };
    let section_box = dag.edge_bounds(section);
    let cut = dag.intersection(vec![section, slab], source);
    let mut local = section_box;
    local.min.z = low;
    local.max.z = high;
    let cut = dag.bounded(cut, local);
    let frame = DMat4::from_cols(
        e1.extend(0.0),
        e2.extend(0.0),
        u.extend(0.0),
        DVec4::new(0.0, 0.0, 0.0, 1.0),
    );
    dag.edge(cut, &frame).map_err(|_| {
        HullRefusal::Unrepresentable("the cylinders' frame is not representable".into())
    })
}

/// A convex part of a 2-D Minkowski sum: the hull of `points` grown by `radius`.
#[derive(Clone, Debug)]
pub struct Part2 {
    /// The corners of the hull.
    pub points: Vec<DVec2>,
    /// The radius.
    pub radius: f64,
}

/// The convex parts of one 2-D child from its pieces and their part numbers.
pub fn parts_of(pieces: &[Piece2], numbers: &[usize]) -> Vec<Part2> {
    let mut parts: Vec<Part2> = Vec::new();
    let mut last = None;
    for (piece, &n) in pieces.iter().zip(numbers) {
        let (point, radius) = match *piece {
            Piece2::Point(p, _) => (p, 0.0),
            Piece2::Disc(c, r, _) => (c, r),
        };
        if last != Some(n) {
            parts.push(Part2 {
                points: Vec::new(),
                radius,
            });
            last = Some(n);
        }
        if let Some(part) = parts.last_mut() {
            part.points.push(point);
        }
    }
    for part in &mut parts {
        part.points = convex_hull_2d(&part.points);
    }
    parts
}

/// The Minkowski sum of two unions of 2-D parts (see [`crate::minkowski`]).
pub fn sum(a: &[Part2], b: &[Part2], limits: &HullLimits) -> Result<Vec<Part2>, HullRefusal> {
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
            if p.points.len().saturating_mul(q.points.len()) > limits.points.saturating_mul(64) {
                return Err(HullRefusal::Limit(
                    codes::HULL_POINT_LIMIT,
                    format!(
                        "a convex part of the 2-D Minkowski sum has more than {} points (64 times \
                         the limit)",
                        limits.points.saturating_mul(64)
                    ),
                ));
            }
            let points: Vec<DVec2> = p
                .points
                .iter()
                .flat_map(|x| q.points.iter().map(move |y| *x + *y))
                .collect();
            out.push(Part2 {
                points: convex_hull_2d(&points),
                radius: p.radius + q.radius,
            });
        }
    }
    Ok(out)
}

/// The union of 2-D parts as a z-invariant solid.
pub fn build_parts(
    dag: &mut Dag,
    parts: &[Part2],
    source: Source,
    max_points: usize,
) -> Result<Edge, HullRefusal> {
    let mut edges = Vec::with_capacity(parts.len());
    for part in parts {
        let pieces: Vec<Piece2> = part
            .points
            .iter()
            .map(|&p| Piece2::Disc(p, part.radius, source))
            .collect();
        edges.push(build(dag, &pieces, part.radius, source, max_points)?);
    }
    Ok(match edges.len() {
        1 => edges[0],
        _ => dag.union(edges, source).into(),
    })
}
