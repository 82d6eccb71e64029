//! `offset(r | delta, chamfer)` on the plane figures of a [`PlanarExpr`], where the result is a
//! union or intersection of half-planes, strips and discs, exactly:
//!
//! - **Growing** (`r > 0` or `delta > 0`) distributes over union, so a union is offset part by
//!   part, down to convex polygons (a `square`, a cell of a `polygon`) and discs. A convex polygon
//!   grown by `r` (rounded) is itself ∪ one band per edge ∪ one disc per vertex; by `delta`
//!   (mitred, OpenSCAD's default miter limit being out of reach) the intersection of its shifted
//!   half-planes; with `chamfer` also cut at distance `delta` from each vertex across the corner.
//!   A disc of radius R grows to radius R + r (or R + delta: OpenSCAD's circle is a polygon, whose
//!   mitred offset tends to that disc).
//! - **Shrinking** (`r < 0` or `delta < 0`) distributes over intersection, so an intersection of
//!   half-planes, strips and discs is shrunk piece by piece: each half-plane shifted inwards, each
//!   disc of radius R to R − |r| (empty when that is not positive).
//!
//! Anything else (growing a difference or a complement, or a shape with an ellipse; shrinking a
//! union of several parts, a difference or a complement) has no such exact construction here and
//! is refused with the source of the part ([`OffsetRefusal`]).

use glam::{DVec2, DVec3};
use qcsg_csg::{Dag, Edge, Source};
use qcsg_quadric::Quadric;

use crate::planar::{Conic, PlanarExpr, PlanarId, PlanarKind};
use crate::primitives_2d::column;

/// How the corners of a grown outline are joined.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Join {
    /// `r`: rounded, the Minkowski sum with a disc.
    Round,
    /// `delta`: the edges' lines extended until they meet.
    Miter,
    /// `delta` with `chamfer = true`: the mitred corner cut at distance `delta` from the vertex.
    Chamfer,
}

/// A part that this construction cannot offset exactly: its source and what it is.
#[derive(Clone, Debug, PartialEq)]
pub struct OffsetRefusal {
    /// The code of the part.
    pub source: Source,
    /// What it is, for the message ("a difference", "an ellipse", …).
    pub what: &'static str,
}

/// A half-plane `normal · p ≤ offset` with a unit normal, in world coordinates of the plane.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Line {
    pub(crate) normal: DVec2,
    pub(crate) offset: f64,
}

impl Line {
    fn shifted(self, by: f64) -> Line {
        Line {
            offset: self.offset + by,
            ..self
        }
    }

    fn quadric(self) -> Option<Quadric> {
        Quadric::half_space(
            (self.normal * self.offset).extend(0.0),
            self.normal.extend(0.0),
        )
    }
}

/// The half-planes of a linear conic or of a strip (its two halves); `None` for a curve.
pub(crate) fn lines_of(conic: &Conic) -> Option<Vec<Line>> {
    let halves = if conic.is_linear() {
        vec![*conic]
    } else {
        conic.split_strip()?.to_vec()
    };
    halves
        .iter()
        .map(|c| {
            let [_, _, _, g, h, j] = c.coefficients();
            // 2g X + 2h Y + j ≤ 0 about the origin o: n · p ≤ n · o − j with n = 2 (g, h).
            let n = 2.0 * DVec2::new(g, h);
            let length = n.length();
            (length > 0.0 && length.is_finite()).then(|| Line {
                normal: n / length,
                offset: (n.dot(c.origin) - j) / length,
            })
        })
        .collect()
}

/// The centre and radius of a circle conic; `None` for anything else.
pub(crate) fn circle_of(conic: &Conic) -> Option<(DVec2, f64)> {
    let [a, b, d, g, h, j] = conic.coefficients();
    if a.is_nan() || a <= 0.0 || (a - b).abs() > 1e-12 * a || d.abs() > 1e-12 * a {
        return None;
    }
    let centre = DVec2::new(-g / a, -h / a);
    let r2 = centre.length_squared() - j / a;
    (r2 > 0.0).then(|| (conic.origin + centre, r2.sqrt()))
}

/// The vertices, counter-clockwise, of the bounded convex polygon `lines`, found by clipping a
/// box `[min, max]` that contains it.
pub(crate) fn convex_vertices(lines: &[Line], min: DVec2, max: DVec2) -> Vec<DVec2> {
    let mut poly = vec![min, DVec2::new(max.x, min.y), max, DVec2::new(min.x, max.y)];
    for line in lines {
        let mut out = Vec::with_capacity(poly.len() + 1);
        for (i, &a) in poly.iter().enumerate() {
            let b = poly[(i + 1) % poly.len()];
            let (va, vb) = (
                line.normal.dot(a) - line.offset,
                line.normal.dot(b) - line.offset,
            );
            if va <= 0.0 {
                out.push(a);
            }
            if (va < 0.0 && vb > 0.0) || (va > 0.0 && vb < 0.0) {
                out.push(a + (b - a) * (va / (va - vb)));
            }
        }
        poly = out;
    }
    poly.dedup_by(|a, b| (*a - *b).length() <= 1e-12 * (a.length() + 1.0));
    poly
}

fn box_of(points: &[DVec2]) -> Option<(DVec2, DVec2)> {
    let min = points.iter().fold(DVec2::INFINITY, |m, p| m.min(*p));
    let max = points.iter().fold(DVec2::NEG_INFINITY, |m, p| m.max(*p));
    (min.x <= max.x && min.y <= max.y).then_some((min, max))
}

/// Builds the offset of a plane figure as DAG nodes.
pub struct Offsetter<'e> {
    /// The figure.
    pub expr: &'e PlanarExpr,
    /// The signed distance (`r` or `delta`).
    pub amount: f64,
    /// How corners are joined when growing.
    pub join: Join,
    /// The source given to the new nodes.
    pub source: Source,
}

impl Offsetter<'_> {
    /// The offset figure, as a z-invariant solid.
    pub fn build(&self, dag: &mut Dag) -> Result<Edge, OffsetRefusal> {
        self.node(dag, self.expr.root)
    }

    fn refuse(&self, id: PlanarId, what: &'static str) -> OffsetRefusal {
        OffsetRefusal {
            source: self.expr.node(id).source,
            what,
        }
    }

    fn half_plane(&self, dag: &mut Dag, line: Line) -> Edge {
        match line.quadric() {
            Some(q) => dag.leaf(q, self.source).into(),
            None => dag.empty(self.source).into(),
        }
    }

    fn disc(&self, dag: &mut Dag, centre: DVec2, radius: f64) -> Edge {
        if radius.is_nan() || radius <= 0.0 {
            return dag.empty(self.source).into();
        }
        let bounds = column(centre - radius, centre + radius);
        match Quadric::cylinder(centre.extend(0.0), DVec3::Z, radius) {
            Some(q) => dag.bounded_leaf(q, self.source, bounds).into(),
            None => dag.empty(self.source).into(),
        }
    }

    fn boxed(&self, dag: &mut Dag, edge: Edge, bounds: Option<(DVec2, DVec2)>) -> Edge {
        match bounds {
            Some((min, max)) => dag.bounded(edge.child, column(min, max)).into(),
            None => edge,
        }
    }

    fn node(&self, dag: &mut Dag, id: PlanarId) -> Result<Edge, OffsetRefusal> {
        let node = self.expr.node(id);
        let grow = self.amount > 0.0;
        match &node.kind {
            PlanarKind::Union(children) if grow || children.len() <= 1 => {
                let parts = children
                    .iter()
                    .map(|c| self.node(dag, *c))
                    .collect::<Result<Vec<_>, _>>()?;
                // The parts carry their boxes (a mitred corner may reach beyond `delta`).
                Ok(dag.union(parts, self.source).into())
            }
            PlanarKind::Union(_) => Err(self.refuse(id, "a union of several parts shrunk")),
            PlanarKind::Difference(_) => Err(self.refuse(id, "a difference")),
            PlanarKind::Complement(_) => Err(self.refuse(id, "a complement")),
            PlanarKind::Leaf(_) | PlanarKind::Intersection(_) => self.convex(dag, id),
        }
    }

    /// An intersection of leaves (or one leaf): half-planes, strips and circles.
    fn convex(&self, dag: &mut Dag, id: PlanarId) -> Result<Edge, OffsetRefusal> {
        let node = self.expr.node(id);
        let children: Vec<PlanarId> = match &node.kind {
            PlanarKind::Intersection(children) => children.clone(),
            _ => vec![id],
        };
        let shrink = self.amount < 0.0;
        let mut lines = Vec::new();
        let mut parts = Vec::new();
        let mut circles = Vec::new();
        for &child in &children {
            let PlanarKind::Leaf(conic) = &self.expr.node(child).kind else {
                if shrink || children.len() == 1 {
                    // Shrinking distributes over intersection; growing a lone child is the
                    // child's offset.
                    parts.push(self.node(dag, child)?);
                    continue;
                }
                return Err(self.refuse(id, "an intersection of parts that are not all edges"));
            };
            if let Some(found) = lines_of(conic) {
                lines.extend(found);
            } else if let Some(circle) = circle_of(conic) {
                circles.push(circle);
            } else {
                return Err(self.refuse(child, "an ellipse"));
            }
        }
        if shrink {
            for line in &lines {
                parts.push(self.half_plane(dag, line.shifted(self.amount)));
            }
            for &(centre, radius) in &circles {
                parts.push(self.disc(dag, centre, radius + self.amount));
            }
            let cut = dag.intersection(parts, self.source);
            return Ok(self.boxed(dag, cut.into(), node.bounds));
        }
        match (lines.is_empty(), circles.as_slice(), parts.len()) {
            (true, [], 1) => Ok(parts[0]),
            (true, [(centre, radius)], 0) => Ok(self.disc(dag, *centre, radius + self.amount)),
            (false, [], 0) => self.grow_polygon(dag, id, &lines),
            _ => Err(self.refuse(id, "an intersection with a curved part")),
        }
    }

    /// A convex polygon grown by `amount` with the join.
    fn grow_polygon(
        &self,
        dag: &mut Dag,
        id: PlanarId,
        lines: &[Line],
    ) -> Result<Edge, OffsetRefusal> {
        let Some((min, max)) = self.expr.node(id).bounds else {
            return Err(self.refuse(id, "an unbounded shape"));
        };
        let vertices = convex_vertices(lines, min, max);
        if vertices.len() < 3 {
            return Ok(dag.empty(self.source).into());
        }
        let d = self.amount;
        // The edges of the polygon in order, each with its outward unit normal.
        let edges: Vec<(DVec2, DVec2, DVec2)> = (0..vertices.len())
            .map(|i| {
                let (a, b) = (vertices[i], vertices[(i + 1) % vertices.len()]);
                let t = (b - a).normalize_or_zero();
                (a, b, DVec2::new(t.y, -t.x))
            })
            .filter(|(a, b, _)| a != b)
            .collect();
        match self.join {
            Join::Round => {
                let mut parts = Vec::with_capacity(1 + 2 * edges.len());
                let cell: Vec<Edge> = lines.iter().map(|l| self.half_plane(dag, *l)).collect();
                let cell = dag.intersection(cell, self.source);
                parts.push(dag.bounded(cell, column(min, max)).into());
                for &(a, b, n) in &edges {
                    parts.push(self.band(dag, a, b, n, d));
                    parts.push(self.disc(dag, a, d));
                }
                let union = dag.union(parts, self.source);
                Ok(dag
                    .bounded(union, column(min - DVec2::splat(d), max + DVec2::splat(d)))
                    .into())
            }
            Join::Miter | Join::Chamfer => {
                let mut shifted: Vec<Line> = edges
                    .iter()
                    .map(|&(a, _, n)| Line {
                        normal: n,
                        offset: n.dot(a) + d,
                    })
                    .collect();
                let reach = d * 1e6;
                let mut corners = convex_vertices(
                    &shifted,
                    min - DVec2::splat(reach),
                    max + DVec2::splat(reach),
                );
                if self.join == Join::Chamfer {
                    for (i, &(a, _, n)) in edges.iter().enumerate() {
                        let previous = edges[(i + edges.len() - 1) % edges.len()].2;
                        let bisector = (n + previous).normalize_or_zero();
                        if bisector != DVec2::ZERO {
                            shifted.push(Line {
                                normal: bisector,
                                offset: bisector.dot(a) + d,
                            });
                        }
                    }
                    corners = convex_vertices(
                        &shifted,
                        min - DVec2::splat(reach),
                        max + DVec2::splat(reach),
                    );
                }
                let parts: Vec<Edge> = shifted.iter().map(|l| self.half_plane(dag, *l)).collect();
                let cell = dag.intersection(parts, self.source);
                let bounds = box_of(&corners).map(|(lo, hi)| {
                    let pad = 1e-9 * (hi - lo).max_element().max(1.0);
                    (lo - pad, hi + pad)
                });
                Ok(self.boxed(dag, cell.into(), bounds))
            }
        }
    }

    /// The rectangle over the edge `a → b` (outward normal `n`), `d` wide on either side.
    fn band(&self, dag: &mut Dag, a: DVec2, b: DVec2, n: DVec2, d: f64) -> Edge {
        let centre = (0.5 * (a + b)).extend(0.0);
        let along = (b - a).extend(0.0);
        let half_length = 0.5 * along.length();
        let slabs = [
            Quadric::slab(centre, along, half_length),
            Quadric::slab(centre, n.extend(0.0), d),
        ];
        let mut parts = Vec::with_capacity(2);
        for q in slabs {
            match q {
                Some(q) => parts.push(dag.leaf(q, self.source).into()),
                None => return dag.empty(self.source).into(),
            }
        }
        let corners = [a + n * d, a - n * d, b + n * d, b - n * d];
        let band = dag.intersection(parts, self.source);
        match box_of(&corners) {
            Some((min, max)) => {
                let pad = 1e-9 * (max - min).max_element().max(1.0);
                dag.bounded(band, column(min - pad, max + pad)).into()
            }
            None => band.into(),
        }
    }
}
