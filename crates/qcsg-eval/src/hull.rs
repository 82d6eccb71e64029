//! `hull()` of 3-D children, exactly where the hull is bounded by quadrics: the children are read
//! in world space as points (the vertices of convex polytopes: `cube`s, cells of `polyhedron`s
//! and imported meshes) and balls (`sphere`s, scaled evenly), and
//!
//! - points alone give the convex hull K of the points ([`qcsg_mesh::convex_hull`], exact), an
//!   intersection of half-spaces (nothing when the points are coplanar: no volume, as OpenSCAD);
//! - balls of one radius r give K ⊕ B(r) with K the hull of the centres: K ∪ one prism per face
//!   of K (the slab of half-width r about the face's plane cut by the planes through its edges
//!   perpendicular to it) ∪ one cylinder per edge (cut by the planes across its ends) ∪ one ball
//!   per vertex. Every point within r of K is within r of a face, an edge or a vertex it is
//!   nearest to, and every piece lies within r of K, so the union is exact. A flat K (coplanar
//!   centres) is its one face seen from both sides, a segment the capsule, a point the ball.
//!
//! Circular cylinders (cut square across their axes) whose axes are parallel and whose ends lie
//! on the same two planes have the hull of their discs in one plane, extruded between the two
//! ([`crate::hull_2d::build_prism`]); cylinders and cones with parallel axes otherwise, also with
//! points, are the hull of their end discs ([`crate::hull_frusta`]).
//!
//! Balls of different radii (a point being a ball of radius 0) have cones and planes tangent to
//! several balls in their hull, built by [`crate::hull_balls`] when [`common_radius`] finds two
//! radii ([`HullRefusal::UnequalRadii`]). Parts that are none of these (an ellipsoid, a
//! difference) are refused ([`HullRefusal::Part`]), and so are pairs that are not quadric
//! together (a cylinder beside a ball: [`HullRefusal::Pair`]).

use std::collections::{HashMap, HashSet};

use glam::{DMat3, DMat4, DVec3};
use qcsg_csg::{Aabb, Dag, Edge, NodeId, NodeKind, Source};
use qcsg_mesh::{ConvexHull, HullError, convex_hull};
use qcsg_quadric::Quadric;

/// The limits of a hull's or a Minkowski sum's size (see [`crate::EvalOptions`]).
#[derive(Clone, Copy, Debug)]
pub struct HullLimits {
    /// The most distinct points a hull (a convex part of a sum) is computed of.
    pub points: usize,
    /// The most distinct planes of one convex part whose vertices are enumerated.
    pub planes: usize,
    /// The most convex parts of a Minkowski sum.
    pub parts: usize,
}

/// What the hull is made of, in world space.
#[derive(Clone, Copy, Debug)]
pub enum Piece {
    /// A vertex of a convex part.
    Point(DVec3, Source),
    /// A ball.
    Ball(DVec3, f64, Source),
    /// A circular cylinder cut square across its axis: its discs.
    Cylinder(Cylinder),
}

/// A circular cylinder or cone between two planes across its unit axis `axis`: the points `p`
/// with `axis · p` in `[low, high]` and `|p − centre|` off the axis at most the radius there,
/// which goes linearly from `radius` at `low` to `radius_high` at `high`.
#[derive(Clone, Copy, Debug)]
pub struct Cylinder {
    /// A point of the axis.
    pub centre: DVec3,
    /// The unit axis.
    pub axis: DVec3,
    /// The radius at `low`.
    pub radius: f64,
    /// The radius at `high` (`radius` for a cylinder).
    pub radius_high: f64,
    /// The extent along the axis, as `axis · p`.
    pub low: f64,
    /// See `low`.
    pub high: f64,
    /// The part's source.
    pub source: Source,
}

/// Why the hull is not computed here.
#[derive(Clone, Debug, PartialEq)]
pub enum HullRefusal {
    /// A part that is not a ball or a convex polytope: its source and what it is.
    Part(Source, &'static str),
    /// Two parts of different radii (a point has radius 0): their sources and radii.
    UnequalRadii([(Source, f64); 2]),
    /// Two parts that together make the result non-quadric (each may be fine alone): their
    /// sources, what they are together, and the exact alternative.
    Pair([Source; 2], &'static str, &'static str),
    /// A limit crossed: the limit's diagnostic code and what crossed it.
    Limit(&'static str, String),
    /// A point or frame that cannot be represented.
    Unrepresentable(String),
}

/// A plane `normal · p ≤ offset` with a unit normal.
#[derive(Clone, Copy, Debug)]
struct Plane {
    normal: DVec3,
    offset: f64,
}

/// The ball of `q` when it is one: its centre and radius (`None` radius: an empty ball).
fn ball_of(q: &Quadric) -> Option<(DVec3, Option<f64>)> {
    let a = q.matrix_a();
    let lambda = (a[0][0] + a[1][1] + a[2][2]) / 3.0;
    if lambda.is_nan() || lambda <= 0.0 {
        return None;
    }
    let mut off = 0.0f64;
    for (r, row) in a.iter().enumerate() {
        for (c, &x) in row.iter().enumerate() {
            let expected = if r == c { lambda } else { 0.0 };
            off = off.max((x - expected).abs());
        }
    }
    // Rotations round the entries of an evenly scaled sphere by a few ulps.
    if off > 1e-9 * lambda {
        return None;
    }
    let l = q.linear();
    let centre = q.origin() - l / lambda;
    let r2 = l.length_squared() / (lambda * lambda) - q.constant() / lambda;
    Some((centre, (r2 > 0.0 && r2.is_finite()).then(|| r2.sqrt())))
}

/// The axis (unit), a point of the axis and the radius of `q` when it is an infinite circular
/// cylinder (`None` radius: empty).
fn cylinder_of(q: &Quadric) -> Option<(DVec3, DVec3, Option<f64>)> {
    let a = q.matrix_a();
    let lambda = 0.5 * (a[0][0] + a[1][1] + a[2][2]);
    if lambda.is_nan() || lambda <= 0.0 {
        return None;
    }
    // A = λ (I − u uᵀ): the axis is along the rows' cross product of largest norm.
    let rows = a.map(DVec3::from_array);
    let u = [
        rows[0].cross(rows[1]),
        rows[1].cross(rows[2]),
        rows[2].cross(rows[0]),
    ]
    .into_iter()
    .max_by(|x, y| x.length_squared().total_cmp(&y.length_squared()))?
    .try_normalize()?;
    let ua = u.to_array();
    for (r, row) in a.iter().enumerate() {
        for (c, &x) in row.iter().enumerate() {
            let expected = lambda * (f64::from(u8::from(r == c)) - ua[r] * ua[c]);
            if (x - expected).abs() > 1e-9 * lambda {
                return None;
            }
        }
    }
    let l = q.linear();
    if l.dot(u).abs() > 1e-9 * (l.length() + f64::MIN_POSITIVE) + 1e-300 {
        return None;
    }
    let centre = q.origin() - l / lambda;
    let r2 = l.length_squared() / (lambda * lambda) - q.constant() / lambda;
    Some((u, centre, (r2 > 0.0 && r2.is_finite()).then(|| r2.sqrt())))
}

/// The eigenvalues of a symmetric 3 × 3 matrix, ascending (the trigonometric closed form).
fn eigenvalues(a: &[[f64; 3]; 3]) -> [f64; 3] {
    let off = a[0][1].powi(2) + a[0][2].powi(2) + a[1][2].powi(2);
    let q = (a[0][0] + a[1][1] + a[2][2]) / 3.0;
    let p2 = (a[0][0] - q).powi(2) + (a[1][1] - q).powi(2) + (a[2][2] - q).powi(2) + 2.0 * off;
    if p2 == 0.0 {
        return [q; 3];
    }
    let p = (p2 / 6.0).sqrt();
    let b = DMat3::from_cols_array_2d(a) - DMat3::from_diagonal(DVec3::splat(q));
    let r = (b.determinant() / (p * p * p) / 2.0).clamp(-1.0, 1.0);
    let phi = r.acos() / 3.0;
    let high = q + 2.0 * p * phi.cos();
    let low = q + 2.0 * p * (phi + 2.0 * std::f64::consts::FRAC_PI_3).cos();
    [low, 3.0 * q - high - low, high]
}

/// A circular cone `q` as its unit axis u, a point a of the axis and the radius `α + k s` at
/// `s = u · (x − a)` along it (both nappes: the solid is `|x⊥| ≤ |α + k s|`).
fn cone_of(q: &Quadric) -> Option<(DVec3, DVec3, f64, f64)> {
    let a = q.matrix_a();
    let [mut e0, e1, e2] = eigenvalues(&a);
    // The closed form is a few ulps off a simple root, and ~√ε off a double one: polish the
    // simple one by Newton on det(A − t I), and take the double one from the trace.
    let m = DMat3::from_cols_array_2d(&a);
    for _ in 0..3 {
        let b = m - DMat3::from_diagonal(DVec3::splat(e0));
        let minors = b.x_axis.x * b.y_axis.y - b.x_axis.y * b.y_axis.x + b.x_axis.x * b.z_axis.z
            - b.x_axis.z * b.z_axis.x
            + b.y_axis.y * b.z_axis.z
            - b.y_axis.z * b.z_axis.y;
        if minors == 0.0 {
            break;
        }
        // d/dt det(A − t I) = −(the sum of the principal 2 × 2 minors).
        e0 += b.determinant() / minors;
    }
    // A = λ (I − u uᵀ) − λ k² u uᵀ: λ twice, −λ k² along the axis.
    let trace = a[0][0] + a[1][1] + a[2][2];
    let lambda = 0.5 * (trace - e0);
    if !(lambda > 0.0 && e0 <= 0.0 && (e2 - e1) <= 1e-6 * lambda) {
        return None;
    }
    let rows = a.map(DVec3::from_array);
    let u = (0..3)
        .map(|i| rows[i] - lambda * DVec3::AXES[i])
        .max_by(|x, y| x.length_squared().total_cmp(&y.length_squared()))?
        .try_normalize()?;
    // uᵀ A u is −λ k² without the cancellation of the eigenvalue's (exact for an axis-aligned
    // cone, whose radii may be nearly equal: k tiny).
    let e0 = u.dot(DMat3::from_cols_array_2d(&a) * u);
    let lambda = 0.5 * (trace - e0);
    if !(e0 < 0.0 && lambda > 0.0) {
        return None;
    }
    let k2 = -e0 / lambda;
    let ua = u.to_array();
    for (r, row) in a.iter().enumerate() {
        for (c, &x) in row.iter().enumerate() {
            let expected = lambda * (f64::from(u8::from(r == c)) - (1.0 + k2) * ua[r] * ua[c]);
            if (x - expected).abs() > 1e-9 * lambda {
                return None;
            }
        }
    }
    // About a point a of the axis with u · (o − a) = 0, d = o − a:
    // l = λ (d − k α u) and j = λ (|d|² − α²).
    let l = q.linear();
    let k = k2.sqrt();
    let d = (l - l.dot(u) * u) / lambda;
    let alpha = -l.dot(u) / (lambda * k);
    let j = lambda * (d.length_squared() - alpha * alpha);
    let size = lambda * (d.length_squared() + alpha * alpha);
    if (q.constant() - j).abs() > 1e-9 * size + f64::MIN_POSITIVE
        || !(alpha.is_finite() && k.is_finite() && d.is_finite())
    {
        return None;
    }
    Some((u, q.origin() - d, alpha, k))
}

/// Whether `q` is positive definite (an ellipsoid or nothing).
fn is_ellipsoidal(q: &Quadric) -> bool {
    let a = q.matrix_a();
    let m = DMat3::from_cols_array_2d(&a);
    a[0][0] > 0.0 && a[0][0] * a[1][1] - a[0][1] * a[1][0] > 0.0 && m.determinant() > 0.0
}

/// The planes of `q` when it is a half-space or a slab (`Some(empty)` for an empty slab).
fn planes_of(q: &Quadric) -> Option<Vec<Plane>> {
    let a = q.matrix_a();
    let (l, j, o) = (q.linear(), q.constant(), q.origin());
    let amax = a.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
    let plane = |u: DVec3, at: f64| {
        // u · (p − o) ≤ at.
        let length = u.length();
        (length > 0.0 && length.is_finite()).then(|| Plane {
            normal: u / length,
            offset: (u.dot(o) + at) / length,
        })
    };
    if amax == 0.0 {
        // 2 l · x + j ≤ 0.
        return Some(vec![plane(l, -0.5 * j)?]);
    }
    let k = (0..3).max_by(|&x, &y| a[x][x].total_cmp(&a[y][y]))?;
    if a[k][k].is_nan() || a[k][k] <= 0.0 {
        return None;
    }
    let u = DVec3::from_array(a[k]) / a[k][k].sqrt();
    let ua = u.to_array();
    for (r, row) in a.iter().enumerate() {
        for (c, &x) in row.iter().enumerate() {
            if (x - ua[r] * ua[c]).abs() > 1e-12 * a[k][k] {
                return None;
            }
        }
    }
    // (u·x)² + 2 l·x + j with l = μ u: (u·x + μ)² ≤ μ² − j.
    let mu = l.dot(u) / u.length_squared();
    if (l - mu * u).length() > 1e-12 * (l.length() + u.length() * mu.abs()) + f64::MIN_POSITIVE {
        return None;
    }
    let h2 = mu * mu - j;
    if h2.is_nan() || h2 <= 0.0 {
        return Some(Vec::new());
    }
    let h = h2.sqrt();
    Some(vec![plane(u, h - mu)?, plane(-u, h + mu)?])
}

/// The planes of a box.
fn box_planes(b: &Aabb) -> Vec<Plane> {
    let mut out = Vec::with_capacity(6);
    for (k, axis) in [DVec3::X, DVec3::Y, DVec3::Z].into_iter().enumerate() {
        out.push(Plane {
            normal: axis,
            offset: b.max[k],
        });
        out.push(Plane {
            normal: -axis,
            offset: -b.min[k],
        });
    }
    out
}

/// The vertices of the bounded polytope `planes` (inside `bounds`, finite), found by solving
/// every triple of planes about the box's centre and keeping the solutions inside all planes.
fn vertices(planes: &[Plane], bounds: &Aabb) -> Vec<DVec3> {
    let centre = bounds.centre();
    let extent = (bounds.max - bounds.min)
        .max_element()
        .max(f64::MIN_POSITIVE);
    let tol = 1e-9 * extent;
    // About the centre, offsets are of the size of the part, not of its distance from the origin.
    let local: Vec<Plane> = planes
        .iter()
        .map(|p| Plane {
            normal: p.normal,
            offset: p.offset - p.normal.dot(centre),
        })
        .collect();
    let mut found: Vec<DVec3> = Vec::new();
    let n = local.len();
    for i in 0..n {
        for j in i + 1..n {
            for k in j + 1..n {
                let (a, b, c) = (local[i], local[j], local[k]);
                let m = DMat3::from_cols(a.normal, b.normal, c.normal).transpose();
                let det = m.determinant();
                if det.abs() < 1e-12 {
                    continue;
                }
                let x = m.inverse() * DVec3::new(a.offset, b.offset, c.offset);
                if !x.is_finite() || local.iter().any(|p| p.normal.dot(x) > p.offset + tol) {
                    continue;
                }
                if !found.iter().any(|y| (*y - x).length() <= tol) {
                    found.push(x);
                }
            }
        }
    }
    found.into_iter().map(|x| x + centre).collect()
}

/// Collects the pieces of 3-D subtrees in world space.
pub struct Collector<'d> {
    dag: &'d Dag,
    /// The pieces found so far.
    pub pieces: Vec<Piece>,
    /// For each piece, the convex part it belongs to (a ball, a cylinder and each convex
    /// polytope are one part each), numbered from 0.
    pub parts: Vec<usize>,
    next_part: usize,
    seen: HashSet<(NodeId, [u64; 16])>,
    max_planes: usize,
}

impl<'d> Collector<'d> {
    /// A collector over `dag`, refusing convex parts of more than `max_planes` faces.
    pub fn new(dag: &'d Dag, max_planes: usize) -> Self {
        Self {
            dag,
            pieces: Vec::new(),
            parts: Vec::new(),
            next_part: 0,
            seen: HashSet::new(),
            max_planes,
        }
    }

    /// Adds the pieces of the subtree behind `edge`, seen in the frame `world`.
    pub fn add(&mut self, edge: Edge, world: &DMat4) -> Result<(), HullRefusal> {
        let m = *world * self.dag.matrix(edge.transform);
        stacker::maybe_grow(128 * 1024, 4 * 1024 * 1024, || self.node(edge.child, &m))
    }

    fn node(&mut self, id: NodeId, world: &DMat4) -> Result<(), HullRefusal> {
        if !self
            .seen
            .insert((id, world.to_cols_array().map(f64::to_bits)))
        {
            // The same part in the same place adds nothing to a hull.
            return Ok(());
        }
        let Some(node) = self.dag.node(id) else {
            return Ok(());
        };
        let source = node.source;
        match &node.kind {
            NodeKind::Union(children) => {
                for c in children.clone() {
                    self.add(c, world)?;
                }
                Ok(())
            }
            NodeKind::Color(_, e) | NodeKind::Highlight(e) => self.add(*e, world),
            NodeKind::Difference(_) => Err(HullRefusal::Part(source, "a difference")),
            NodeKind::Complement(_) => Err(HullRefusal::Part(source, "a complement")),
            NodeKind::Leaf(q) => {
                let q = q.transformed(world).ok_or(HullRefusal::Part(
                    source,
                    "a part with a singular transform",
                ))?;
                if let Some((centre, radius)) = ball_of(&q) {
                    if let Some(r) = radius {
                        self.push(Piece::Ball(centre, r, source));
                        self.next_part += 1;
                    }
                    return Ok(());
                }
                if is_ellipsoidal(&q) {
                    return Err(HullRefusal::Part(
                        source,
                        "an ellipsoid (a sphere scaled unevenly)",
                    ));
                }
                self.convex(id, world)
            }
            NodeKind::Intersection(_) => self.convex(id, world),
        }
    }

    /// A convex part: an intersection of half-spaces and slabs, within its boxes.
    fn convex(&mut self, id: NodeId, world: &DMat4) -> Result<(), HullRefusal> {
        let mut planes = Vec::new();
        let mut cylinder = None;
        let mut bounds = Aabb::EVERYTHING;
        let mut stack = vec![(id, *world)];
        let source = self.dag.node(id).map(|n| n.source).unwrap_or_default();
        while let Some((id, m)) = stack.pop() {
            let Some(node) = self.dag.node(id) else {
                return Ok(());
            };
            if let Some(b) = node.bounds {
                bounds = bounds.intersection(&b.transformed(&m));
            }
            match &node.kind {
                NodeKind::Leaf(q) => {
                    let q = q.transformed(&m).ok_or(HullRefusal::Part(
                        source,
                        "a part with a singular transform",
                    ))?;
                    match (planes_of(&q), cylinder_of(&q)) {
                        (Some(found), _) if found.is_empty() => return Ok(()),
                        (Some(found), _) => planes.extend(found),
                        (None, Some((_, _, None))) => return Ok(()),
                        (None, Some((axis, centre, Some(radius)))) if cylinder.is_none() => {
                            cylinder = Some((axis, centre, radius, 0.0, node.source));
                        }
                        (None, None) if cylinder.is_none() && cone_of(&q).is_some() => {
                            cylinder = cone_of(&q)
                                .map(|(axis, at, alpha, k)| (axis, at, alpha, k, node.source));
                        }
                        _ => {
                            return Err(HullRefusal::Part(
                                node.source,
                                "a curved surface cut by others",
                            ));
                        }
                    }
                }
                NodeKind::Intersection(children) => {
                    for c in children {
                        stack.push((c.child, m * self.dag.matrix(c.transform)));
                    }
                }
                NodeKind::Color(_, e) | NodeKind::Highlight(e) => {
                    stack.push((e.child, m * self.dag.matrix(e.transform)));
                }
                NodeKind::Union(_) | NodeKind::Difference(_) | NodeKind::Complement(_) => {
                    return Err(HullRefusal::Part(
                        node.source,
                        "an intersection with a union, difference or complement",
                    ));
                }
            }
        }
        if bounds.is_empty() {
            return Ok(());
        }
        if let Some((axis, centre, alpha, k, at)) = cylinder {
            return self.cylinder(axis, centre, (alpha, k), &planes, source, at);
        }
        if !bounds.is_bounded() {
            return Err(HullRefusal::Part(source, "an unbounded part"));
        }
        planes.extend(box_planes(&bounds));
        // Equal planes (a box plane on a face of a cube) once.
        let mut unique: Vec<Plane> = Vec::with_capacity(planes.len());
        let extent = (bounds.max - bounds.min).max_element();
        for p in planes {
            if !unique.iter().any(|u| {
                (u.normal - p.normal).length() <= 1e-12
                    && (u.offset - p.offset).abs() <= 1e-12 * (extent + u.offset.abs())
            }) {
                unique.push(p);
            }
        }
        if unique.len() > self.max_planes {
            return Err(HullRefusal::Limit(
                crate::codes::PART_PLANE_LIMIT,
                format!(
                    "a convex part has more than {} distinct faces",
                    self.max_planes
                ),
            ));
        }
        for v in vertices(&unique, &bounds) {
            self.push(Piece::Point(v, source));
        }
        self.next_part += 1;
        Ok(())
    }
}

impl Collector<'_> {
    fn push(&mut self, piece: Piece) {
        self.pieces.push(piece);
        self.parts.push(self.next_part);
    }

    /// A cylinder or cone about `axis` through `centre`, of radius `α + k s` at
    /// `s = axis · (x − centre)`, cut by `planes`, which must all be square to the axis.
    fn cylinder(
        &mut self,
        axis: DVec3,
        centre: DVec3,
        (alpha, k): (f64, f64),
        planes: &[Plane],
        source: Source,
        at: Source,
    ) -> Result<(), HullRefusal> {
        // One sign for the axis whatever the transform: its largest component positive.
        let (axis, k) = if axis.abs().max_element() == axis.max_element() {
            (axis, k)
        } else {
            (-axis, -k)
        };
        let (mut low, mut high) = (f64::NEG_INFINITY, f64::INFINITY);
        for p in planes {
            let along = p.normal.dot(axis);
            if p.normal.cross(axis).length() > 1e-9 {
                return Err(HullRefusal::Part(at, "a cylinder cut across at a slant"));
            }
            // p.normal = ±axis: ±(axis · x) ≤ offset.
            if along > 0.0 {
                high = high.min(p.offset);
            } else {
                low = low.max(-p.offset);
            }
        }
        if !(low.is_finite() && high.is_finite()) {
            return Err(HullRefusal::Part(source, "an unbounded part"));
        }
        let radius_at = |h: f64| alpha + k * (h - axis.dot(centre));
        let (mut radius, mut radius_high) = (radius_at(low), radius_at(high));
        if radius < 0.0 && radius_high < 0.0 || radius + radius_high < 0.0 {
            (radius, radius_high) = (-radius, -radius_high);
        }
        // An apex within the cut (beyond the rounding of the radii) holds both nappes.
        let tiny = 1e-9 * radius.abs().max(radius_high.abs());
        if radius < -tiny || radius_high < -tiny {
            return Err(HullRefusal::Part(
                at,
                "a double cone (its apex between the cuts)",
            ));
        }
        let (radius, radius_high) = (radius.max(0.0), radius_high.max(0.0));
        if low < high {
            self.push(Piece::Cylinder(Cylinder {
                centre,
                axis,
                radius,
                radius_high,
                low,
                high,
                source,
            }));
            self.next_part += 1;
        }
        Ok(())
    }
}

/// The common radius of the pieces (0 for points), or the two that differ.
pub fn common_radius(pieces: &[Piece]) -> Result<f64, HullRefusal> {
    let radius = |p: &Piece| match *p {
        Piece::Point(_, s) => (s, 0.0),
        Piece::Ball(_, r, s) => (s, r),
        Piece::Cylinder(c) => (c.source, c.radius),
    };
    let Some(first) = pieces.first().map(radius) else {
        return Ok(0.0);
    };
    for p in &pieces[1..] {
        let (s, r) = radius(p);
        // Transforms round radii by a few ulps; equal up to that is equal.
        if (r - first.1).abs() > 1e-9 * r.max(first.1) {
            return Err(HullRefusal::UnequalRadii([first, (s, r)]));
        }
    }
    Ok(first.1)
}

fn centre_of(p: &Piece) -> DVec3 {
    match *p {
        Piece::Point(c, _) | Piece::Ball(c, _, _) => c,
        Piece::Cylinder(c) => c.centre,
    }
}

/// Builds the hull of `pieces` (all of radius `r`) in world space as DAG nodes.
pub struct HullBuilder {
    /// The source of the new nodes.
    pub source: Source,
    /// The most distinct points of the hull.
    pub max_points: usize,
}

/// The refusal of a point set over the hull point limit, or not representable.
pub(crate) fn hull_error(e: HullError) -> HullRefusal {
    match e {
        HullError::TooManyPoints(limit) => HullRefusal::Limit(
            crate::codes::HULL_POINT_LIMIT,
            format!("the hull has more than {limit} distinct points"),
        ),
        HullError::Coordinate(_) => HullRefusal::Unrepresentable(e.to_string()),
    }
}

pub(crate) fn padded(min: DVec3, max: DVec3) -> Aabb {
    // Room for the rounding of the pieces' own coefficients, near and far from the origin.
    let pad = 1e-9 * (max - min).max_element() + 1e-15 * max.abs().max(min.abs()).max_element();
    Aabb::new(min - pad, max + pad)
}

pub(crate) fn box_of(points: &[DVec3], r: f64) -> Aabb {
    let min = points.iter().fold(DVec3::INFINITY, |m, p| m.min(*p)) - r;
    let max = points.iter().fold(DVec3::NEG_INFINITY, |m, p| m.max(*p)) + r;
    padded(min, max)
}

impl HullBuilder {
    pub(crate) fn leaf(&self, dag: &mut Dag, q: Option<Quadric>) -> Edge {
        match q {
            Some(q) => dag.leaf(q, self.source).into(),
            None => dag.empty(self.source).into(),
        }
    }

    pub(crate) fn intersection_in(&self, dag: &mut Dag, parts: Vec<Edge>, bounds: Aabb) -> Edge {
        let cut = dag.intersection(parts, self.source);
        dag.bounded(cut, bounds).into()
    }

    pub(crate) fn ball(&self, dag: &mut Dag, c: DVec3, r: f64) -> Edge {
        match Quadric::sphere(c, r) {
            Some(q) => dag
                .bounded_leaf(q, self.source, Aabb::from_centre_half(c, DVec3::splat(r)))
                .into(),
            None => dag.empty(self.source).into(),
        }
    }

    /// The cylinder of radius `r` about the segment `a`–`b`, cut across its ends.
    fn rod(&self, dag: &mut Dag, a: DVec3, b: DVec3, r: f64) -> Edge {
        let mid = 0.5 * (a + b);
        let along = b - a;
        let parts = vec![
            self.leaf(dag, Quadric::cylinder(mid, along, r)),
            self.leaf(dag, Quadric::slab(mid, along, 0.5 * along.length())),
        ];
        self.intersection_in(dag, parts, box_of(&[a, b], r))
    }

    /// The prism of half-width `r` about the convex polygon `face` (counter-clockwise about
    /// `normal`).
    fn prism(&self, dag: &mut Dag, face: &[DVec3], normal: DVec3, r: f64) -> Edge {
        let centre = face.iter().copied().sum::<DVec3>() / face.len() as f64;
        let mut parts = vec![self.leaf(dag, Quadric::slab(centre, normal, r))];
        for (i, &a) in face.iter().enumerate() {
            let b = face[(i + 1) % face.len()];
            parts.push(self.leaf(dag, Quadric::half_space(a, (b - a).cross(normal))));
        }
        self.intersection_in(dag, parts, box_of(face, r))
    }

    /// The hull of `pieces`, all of radius `r`.
    pub fn build(&self, dag: &mut Dag, pieces: &[Piece], r: f64) -> Result<Edge, HullRefusal> {
        let centres: Vec<DVec3> = pieces.iter().map(centre_of).collect();
        let hull = convex_hull(&centres, self.max_points).map_err(hull_error)?;
        let round = r > 0.0;
        let mut parts: Vec<Edge> = Vec::new();
        let mut corners: Vec<DVec3> = Vec::new();
        let mut edges: Vec<(DVec3, DVec3)> = Vec::new();
        match hull {
            ConvexHull::Empty => {}
            ConvexHull::Point(c) => corners.push(c),
            ConvexHull::Segment(a, b) => {
                corners.extend([a, b]);
                edges.push((a, b));
            }
            ConvexHull::Polygon { vertices, normal } => {
                if round {
                    parts.push(self.prism(dag, &vertices, normal, r));
                }
                for (i, &a) in vertices.iter().enumerate() {
                    edges.push((a, vertices[(i + 1) % vertices.len()]));
                }
                corners = vertices;
            }
            ConvexHull::Solid(faces) => {
                let mut all: Vec<DVec3> = Vec::new();
                let mut cells = Vec::with_capacity(faces.len());
                let key = |p: DVec3| p.to_array().map(f64::to_bits);
                let mut seen_edges = HashSet::new();
                let mut seen_corners = HashMap::new();
                for face in &faces {
                    cells.push(self.leaf(dag, Quadric::half_space(face.vertices[0], face.normal)));
                    if round {
                        parts.push(self.prism(dag, &face.vertices, face.normal, r));
                    }
                    for (i, &a) in face.vertices.iter().enumerate() {
                        let b = face.vertices[(i + 1) % face.vertices.len()];
                        let (ka, kb) = (key(a), key(b));
                        if seen_edges.insert(if ka < kb { (ka, kb) } else { (kb, ka) }) {
                            edges.push((a, b));
                        }
                        seen_corners.entry(ka).or_insert(a);
                        all.push(a);
                    }
                }
                let mut unique: Vec<_> = seen_corners.into_iter().collect();
                unique.sort_by_key(|(k, _)| *k);
                corners = unique.into_iter().map(|(_, p)| p).collect();
                let bounds = box_of(&all, 0.0);
                parts.push(self.intersection_in(dag, cells, bounds));
            }
        }
        if round {
            for &(a, b) in &edges {
                parts.push(self.rod(dag, a, b, r));
            }
            for &c in &corners {
                parts.push(self.ball(dag, c, r));
            }
        }
        if parts.is_empty() {
            return Ok(dag.empty(self.source).into());
        }
        let all_centres: Vec<DVec3> = corners.clone();
        let union = dag.union(parts, self.source);
        Ok(if all_centres.is_empty() {
            union.into()
        } else {
            dag.bounded(union, box_of(&all_centres, r)).into()
        })
    }
}
