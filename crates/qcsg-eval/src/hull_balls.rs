//! The convex hull H of balls of different radii (a point being a ball of radius 0), built
//! exactly from quadrics.
//!
//! H is the union of the balls B(c, R) over the points (c, R) of the lifted polytope
//! L = conv{(cᵢ, rᵢ)}, and its boundary is made of pieces of the balls, of cones tangent to two
//! balls and of planes tangent to three or more. For p ∈ H, the (c, R) ∈ L maximising
//! R − |p − c| lies on the face of L in the direction (u, 1) with u = (p − c)/|p − c| (first-order
//! optimality of a concave function on a convex set), so p lies on a segment from c to c + R u
//! for (c, R) on that face, or p = c is in the hull K of the centres. The faces of L met that way
//! are single balls, pairs of balls whose tangent cone is on the boundary, and sets of balls
//! touching one tangent plane, so H is the union of
//!
//! - K, the hull of the centres (exact, [`qcsg_mesh::convex_hull`]);
//! - every ball;
//! - for every pair of balls on the boundary, the truncated cone between the two circles where
//!   their common tangent cone touches them (the hull of the two balls is the two balls and
//!   that frustum);
//! - for every tangent plane touching several balls with all others below it, the polytope
//!   spanned by their centres and their points of tangency.
//!
//! Every piece lies in H (each is the hull of points of H), and together they cover it, so the
//! union is exact; the outer surface is made of the balls, the frustums' cones and the tangent
//! planes. A frustum is written as the quadric `|x⊥|² − ρ(s)² ≤ 0` with ρ linear in the axial
//! coordinate s, so nearly equal radii give a nearly circular cylinder instead of a cone with an
//! apex far away.

use glam::{DVec2, DVec3};
use qcsg_csg::{Dag, Edge};
use qcsg_mesh::{ConvexHull, convex_hull, convex_hull_2d};
use qcsg_quadric::Quadric;

use crate::hull::{HullBuilder, HullRefusal, Piece, box_of, hull_error, padded};

/// A ball in coordinates about the configuration's centre.
#[derive(Clone, Copy, Debug)]
struct Ball {
    centre: DVec3,
    radius: f64,
}

/// A plane tangent to several balls with all balls on its inner side: its unit normal and the
/// balls touching it.
struct Facet {
    normal: DVec3,
    touching: Vec<usize>,
}

/// The hull of `pieces` (points and balls; no cylinders) with at most `builder.max_points`
/// distinct centres, as DAG nodes built by `builder`.
pub fn build(dag: &mut Dag, builder: &HullBuilder, pieces: &[Piece]) -> Result<Edge, HullRefusal> {
    let world: Vec<(DVec3, f64)> = pieces
        .iter()
        .filter_map(|p| match *p {
            Piece::Point(c, _) => Some((c, 0.0)),
            Piece::Ball(c, r, _) => Some((c, r)),
            Piece::Cylinder(_) => None,
        })
        .collect();
    if world.is_empty() {
        return Ok(dag.empty(builder.source).into());
    }
    // Work about the centre of the configuration: offsets of the size of the hull, not of its
    // distance from the origin.
    let lo = world.iter().fold(DVec3::INFINITY, |m, (c, _)| m.min(*c));
    let hi = world
        .iter()
        .fold(DVec3::NEG_INFINITY, |m, (c, _)| m.max(*c));
    let origin = 0.5 * (lo + hi);
    let mut balls: Vec<Ball> = world
        .iter()
        .map(|&(c, r)| Ball {
            centre: c - origin,
            radius: r,
        })
        .collect();
    let scale = balls
        .iter()
        .map(|b| b.centre.length() + b.radius)
        .fold(0.0f64, f64::max);
    if scale == 0.0 || !scale.is_finite() {
        return Ok(dag.empty(builder.source).into());
    }
    let tol = 1e-9 * scale;
    balls = prune(balls, tol, builder.max_points)?;
    let facets = facets(&balls, tol);
    let edges = edges(&balls, &facets, tol);

    let mut parts: Vec<Edge> = Vec::new();
    let centres: Vec<DVec3> = balls.iter().map(|b| b.centre).collect();
    if let Some(k) = polytope(dag, builder, &centres, origin)? {
        parts.push(k);
    }
    for f in &facets {
        if f.touching.iter().all(|&m| balls[m].radius == 0.0) {
            // A face of K.
            continue;
        }
        let points: Vec<DVec3> = f
            .touching
            .iter()
            .flat_map(|&m| {
                let b = balls[m];
                [b.centre, b.centre + b.radius * f.normal]
            })
            .collect();
        if let Some(piece) = polytope(dag, builder, &points, origin)? {
            parts.push(piece);
        }
    }
    for &(i, j) in &edges {
        if let Some(piece) = frustum(dag, builder, balls[i], balls[j], origin) {
            parts.push(piece);
        }
    }
    for b in &balls {
        if b.radius > 0.0 {
            parts.push(builder.ball(dag, b.centre + origin, b.radius));
        }
    }
    if parts.is_empty() {
        return Ok(dag.empty(builder.source).into());
    }
    let union = dag.union(parts, builder.source);
    let lo = world
        .iter()
        .fold(DVec3::INFINITY, |m, (c, r)| m.min(*c - *r));
    let hi = world
        .iter()
        .fold(DVec3::NEG_INFINITY, |m, (c, r)| m.max(*c + *r));
    Ok(dag.bounded(union, padded(lo, hi)).into())
}

/// Drops the balls inside another ball and the points inside the hull of the other centres,
/// which add nothing to the hull.
fn prune(mut balls: Vec<Ball>, tol: f64, max_points: usize) -> Result<Vec<Ball>, HullRefusal> {
    balls.sort_by(|a, b| b.radius.total_cmp(&a.radius));
    let mut kept: Vec<Ball> = Vec::with_capacity(balls.len());
    for b in balls {
        let inside = kept
            .iter()
            .any(|k| (b.centre - k.centre).length() + b.radius <= k.radius + tol);
        if !inside {
            kept.push(b);
        }
    }
    let centres: Vec<DVec3> = kept.iter().map(|b| b.centre).collect();
    let corners: Vec<DVec3> = match convex_hull(&centres, max_points).map_err(hull_error)? {
        ConvexHull::Empty => Vec::new(),
        ConvexHull::Point(p) => vec![p],
        ConvexHull::Segment(a, b) => vec![a, b],
        ConvexHull::Polygon { vertices, .. } => vertices,
        ConvexHull::Solid(faces) => faces.into_iter().flat_map(|f| f.vertices).collect(),
    };
    // The hull's vertices are input points, so they compare equal.
    kept.retain(|b| b.radius > 0.0 || corners.contains(&(b.centre + DVec3::ZERO)));
    Ok(kept)
}

/// How far ball `m` reaches beyond the plane with normal `u` through the far point of ball `i`.
fn above(balls: &[Ball], i: usize, m: usize, u: DVec3) -> f64 {
    (balls[m].centre - balls[i].centre).dot(u) + balls[m].radius - balls[i].radius
}

/// The planes tangent to three or more balls with every ball on their inner side.
fn facets(balls: &[Ball], tol: f64) -> Vec<Facet> {
    let n = balls.len();
    let mut found: Vec<Facet> = Vec::new();
    for i in 0..n {
        for j in i + 1..n {
            for k in j + 1..n {
                for u in tangent_normals(balls[i], balls[j], balls[k]) {
                    if found.iter().any(|f| (f.normal - u).length() <= 1e-9) {
                        continue;
                    }
                    if (0..n).any(|m| above(balls, i, m, u) > tol) {
                        continue;
                    }
                    let touching: Vec<usize> =
                        (0..n).filter(|&m| above(balls, i, m, u) >= -tol).collect();
                    found.push(Facet {
                        normal: u,
                        touching,
                    });
                }
            }
        }
    }
    found
}

/// The unit normals u of the planes tangent to the three balls on the same side:
/// `u · (cⱼ − cᵢ) = rᵢ − rⱼ`, `u · (cₖ − cᵢ) = rᵢ − rₖ`, `|u| = 1` (none, one or two).
fn tangent_normals(a: Ball, b: Ball, c: Ball) -> Vec<DVec3> {
    let (x, y) = (b.centre - a.centre, c.centre - a.centre);
    let (alpha, beta) = (a.radius - b.radius, a.radius - c.radius);
    let n = x.cross(y);
    let n2 = n.length_squared();
    if n2 <= (1e-12 * x.length() * y.length()).powi(2) || n2 == 0.0 {
        // Collinear centres: the tangent planes form a family or there are none.
        return Vec::new();
    }
    let u0 = (alpha * y.cross(n) + beta * n.cross(x)) / n2;
    let rest = 1.0 - u0.length_squared();
    if rest < -1e-12 {
        return Vec::new();
    }
    let t = rest.max(0.0).sqrt() / n2.sqrt();
    let mut out = Vec::with_capacity(2);
    for u in [u0 + t * n, u0 - t * n] {
        if let Some(u) = u.try_normalize()
            && !out.iter().any(|v: &DVec3| (*v - u).length() <= 1e-12)
        {
            out.push(u);
        }
    }
    out
}

/// The pairs of balls (at least one of radius > 0) whose tangent cone is on the boundary: the
/// sides of the polygons of tangency of the facets, and the pairs with a normal on their circle
/// of tangent normals where no ball reaches further (a cone that goes all the way round).
fn edges(balls: &[Ball], facets: &[Facet], tol: f64) -> Vec<(usize, usize)> {
    let mut out: Vec<(usize, usize)> = Vec::new();
    let add = |i: usize, j: usize, out: &mut Vec<(usize, usize)>| {
        let key = (i.min(j), i.max(j));
        if balls[i].radius + balls[j].radius > 0.0 && !out.contains(&key) {
            out.push(key);
        }
    };
    for f in facets {
        let (e1, e2) = f.normal.any_orthonormal_pair();
        let flat: Vec<DVec2> = f
            .touching
            .iter()
            .map(|&m| {
                let t = balls[m].centre + balls[m].radius * f.normal;
                DVec2::new(t.dot(e1), t.dot(e2))
            })
            .collect();
        let ring = convex_hull_2d(&flat);
        let index = |p: DVec2| flat.iter().position(|q| *q == p).map(|h| f.touching[h]);
        let ids: Vec<usize> = ring.iter().filter_map(|p| index(*p)).collect();
        match ids.len() {
            0 | 1 => {}
            2 => add(ids[0], ids[1], &mut out),
            len => {
                for h in 0..len {
                    add(ids[h], ids[(h + 1) % len], &mut out);
                }
            }
        }
    }
    let n = balls.len();
    for i in 0..n {
        for j in i + 1..n {
            if balls[i].radius + balls[j].radius == 0.0 || out.contains(&(i, j)) {
                continue;
            }
            let axis = balls[j].centre - balls[i].centre;
            let length = axis.length();
            let kappa = (balls[i].radius - balls[j].radius) / length;
            if kappa.is_nan() || kappa.abs() >= 1.0 {
                continue;
            }
            let d = axis / length;
            let (e1, e2) = d.any_orthonormal_pair();
            let side = (1.0 - kappa * kappa).sqrt();
            let samples = 16;
            let free = (0..samples).any(|s| {
                let phi = std::f64::consts::TAU * f64::from(s) / f64::from(samples);
                let u = kappa * d + side * (phi.cos() * e1 + phi.sin() * e2);
                (0..n).all(|m| above(balls, i, m, u) <= tol)
            });
            if free {
                out.push((i, j));
            }
        }
    }
    out
}

/// The convex polytope spanned by `points` (about `origin`) as an intersection of half-spaces,
/// or `None` when it has no volume.
fn polytope(
    dag: &mut Dag,
    builder: &HullBuilder,
    points: &[DVec3],
    origin: DVec3,
) -> Result<Option<Edge>, HullRefusal> {
    let ConvexHull::Solid(faces) = convex_hull(points, usize::MAX).map_err(hull_error)? else {
        return Ok(None);
    };
    let cells: Vec<Edge> = faces
        .iter()
        .map(|f| {
            let q = Quadric::half_space(f.vertices[0] + origin, f.normal);
            builder.leaf(dag, q)
        })
        .collect();
    let world: Vec<DVec3> = points.iter().map(|p| *p + origin).collect();
    Ok(Some(builder.intersection_in(
        dag,
        cells,
        box_of(&world, 0.0),
    )))
}

/// The truncated cone between the circles where the common tangent cone of `a` and `b` touches
/// them, or `None` when one ball holds the other.
fn frustum(dag: &mut Dag, builder: &HullBuilder, a: Ball, b: Ball, origin: DVec3) -> Option<Edge> {
    let axis = b.centre - a.centre;
    let length = axis.length();
    let kappa = (a.radius - b.radius) / length;
    if length == 0.0 || kappa.is_nan() || kappa.abs() >= 1.0 {
        return None;
    }
    let d = axis / length;
    let side = (1.0 - kappa * kappa).sqrt();
    // The circles of tangency lie at s0 = rₐ κ and s1 = L + r_b κ along d from a's centre, with
    // radii rₐ √(1 − κ²) and r_b √(1 − κ²); ρ(s) = α + β s in between.
    let (s0, s1) = (a.radius * kappa, length + b.radius * kappa);
    let (rho0, rho1) = (a.radius * side, b.radius * side);
    let beta = (rho1 - rho0) / (s1 - s0);
    let alpha = rho0 - beta * s0;
    // |x|² − s² − (α + β s)², scaled by the larger radius so that values are in its units.
    let w = 1.0 / (a.radius.max(b.radius)).powi(2);
    let mut m = [[0.0f64; 3]; 3];
    let da = d.to_array();
    for (r, row) in m.iter_mut().enumerate() {
        for (c, e) in row.iter_mut().enumerate() {
            let identity = if r == c { 1.0 } else { 0.0 };
            *e = w * (identity - (1.0 + beta * beta) * da[r] * da[c]);
        }
    }
    let centre = a.centre + origin;
    let lateral = Quadric::from_matrix(centre, &m, -w * alpha * beta * d, -w * alpha * alpha);
    let slab = Quadric::slab(centre + 0.5 * (s0 + s1) * d, d, 0.5 * (s1 - s0));
    let parts = vec![builder.leaf(dag, lateral), builder.leaf(dag, slab)];
    let ends = [a.centre + origin, b.centre + origin];
    let lo = ends[0].min(ends[1]) - a.radius.max(b.radius);
    let hi = ends[0].max(ends[1]) + a.radius.max(b.radius);
    Some(builder.intersection_in(dag, parts, padded(lo, hi)))
}
