//! The 2-D hull H of discs of different radii (a point being a disc of radius 0), built exactly
//! from circles and lines, as a z-invariant solid.
//!
//! As for balls ([`crate::hull_balls`]), H is the union of the discs D(c, R) over the points
//! (c, R) of the lifted polygon L = conv{(cᵢ, rᵢ)}: for p ∈ H the (c, R) ∈ L maximising
//! R − |p − c| lies on the face of L in the direction (u, 1), u = (p − c)/|p − c|. Such a face is
//! one disc (p is in it), an edge of L joining two discs whose common outer tangent line has
//! every disc on its inner side (p is in the quadrilateral of the two centres and the two points
//! of tangency), or, when p = c, a point of the hull K of the centres. So H is the union of
//!
//! - K (exact, [`qcsg_mesh::convex_hull_2d`]), when it has area;
//! - every disc;
//! - for every outer tangent of two discs with all discs on its inner side, the convex
//!   quadrilateral spanned by the two centres and the two points of tangency.
//!
//! Each piece lies in H and together they cover it; the outline is made of arcs of the circles
//! and of the tangent lines. Several discs touching one tangent line give overlapping
//! quadrilaterals, which the union takes as they are.

use glam::DVec2;
use qcsg_csg::{Dag, Edge, Source};
use qcsg_mesh::convex_hull_2d;
use qcsg_quadric::Quadric;

use crate::codes;
use crate::hull::HullRefusal;
use crate::hull_2d::{Piece2, boxed, disc, leaf};

/// The hull of `pieces` (points and discs of any radii) as a z-invariant solid, with at most
/// `max_points` discs left once those inside another are dropped.
pub fn build(
    dag: &mut Dag,
    pieces: &[Piece2],
    source: Source,
    max_points: usize,
) -> Result<Edge, HullRefusal> {
    let world: Vec<(DVec2, f64)> = pieces
        .iter()
        .map(|p| match *p {
            Piece2::Point(c, _) => (c, 0.0),
            Piece2::Disc(c, r, _) => (c, r),
        })
        .collect();
    if let Some((bad, _)) = world.iter().find(|(c, r)| !c.is_finite() || !r.is_finite()) {
        return Err(HullRefusal::Unrepresentable(format!(
            "a point of the hull is not finite ({bad})"
        )));
    }
    if world.is_empty() {
        return Ok(dag.empty(source).into());
    }
    // Work about the centre of the configuration, so that offsets are of the hull's size.
    let lo = world.iter().fold(DVec2::INFINITY, |m, (c, _)| m.min(*c));
    let hi = world
        .iter()
        .fold(DVec2::NEG_INFINITY, |m, (c, _)| m.max(*c));
    let origin = 0.5 * (lo + hi);
    let discs: Vec<(DVec2, f64)> = world.iter().map(|&(c, r)| (c - origin, r)).collect();
    let scale = discs
        .iter()
        .map(|(c, r)| c.length() + r)
        .fold(0.0f64, f64::max);
    if scale == 0.0 {
        return Ok(dag.empty(source).into());
    }
    let tol = 1e-9 * scale;
    let discs = prune(discs, tol);
    if discs.len() > max_points {
        return Err(HullRefusal::Limit(
            codes::HULL_POINT_LIMIT,
            format!("the 2-D hull has more than {max_points} distinct circles and corners"),
        ));
    }
    let mut parts: Vec<Edge> = Vec::new();
    let at = |p: DVec2| p + origin;
    let centres: Vec<DVec2> = discs.iter().map(|(c, _)| *c).collect();
    if let Some(k) = polygon(dag, &centres, origin, source) {
        parts.push(k);
    }
    for (i, j, u) in tangents(&discs, tol) {
        let ((ci, ri), (cj, rj)) = (discs[i], discs[j]);
        let quad = [ci, cj, cj + rj * u, ci + ri * u];
        if let Some(piece) = polygon(dag, &quad, origin, source) {
            parts.push(piece);
        }
    }
    for &(c, r) in &discs {
        if r > 0.0 {
            parts.push(disc(dag, at(c), r, source));
        }
    }
    if parts.is_empty() {
        return Ok(dag.empty(source).into());
    }
    let union = dag.union(parts, source);
    let lo = world
        .iter()
        .fold(DVec2::INFINITY, |m, (c, r)| m.min(*c - *r));
    let hi = world
        .iter()
        .fold(DVec2::NEG_INFINITY, |m, (c, r)| m.max(*c + *r));
    Ok(boxed(dag, union.into(), &[lo, hi], 0.0))
}

/// Drops the discs inside another disc and duplicate points, which add nothing to the hull.
fn prune(mut discs: Vec<(DVec2, f64)>, tol: f64) -> Vec<(DVec2, f64)> {
    discs.sort_by(|a, b| b.1.total_cmp(&a.1));
    let mut kept: Vec<(DVec2, f64)> = Vec::with_capacity(discs.len());
    for (c, r) in discs {
        if !kept.iter().any(|(k, s)| (c - *k).length() + r <= s + tol) {
            kept.push((c, r));
        }
    }
    let centres: Vec<DVec2> = kept.iter().map(|(c, _)| *c).collect();
    let corners = convex_hull_2d(&centres);
    // A point strictly inside the centres' hull is inside K; the hull's corners are input points.
    kept.retain(|(c, r)| *r > 0.0 || corners.contains(c));
    kept
}

/// The outer tangents with every disc on their inner side: the two discs (the outline runs
/// from the first to the second counter-clockwise) and the tangent's outward unit normal.
fn tangents(discs: &[(DVec2, f64)], tol: f64) -> Vec<(usize, usize, DVec2)> {
    let n = discs.len();
    let mut out = Vec::new();
    for i in 0..n {
        for j in 0..n {
            if i == j || discs[i].1 + discs[j].1 == 0.0 {
                continue;
            }
            let ((ci, ri), (cj, rj)) = (discs[i], discs[j]);
            let d = cj - ci;
            let length = d.length();
            let kappa = (ri - rj) / length;
            if length == 0.0 || kappa.is_nan() || kappa.abs() >= 1.0 {
                continue;
            }
            let d = d / length;
            // u · d = κ (the tangent touches both), u to the right of i → j (outward when the
            // outline turns counter-clockwise).
            let u = kappa * d + (1.0 - kappa * kappa).sqrt() * DVec2::new(d.y, -d.x);
            let beyond = |m: usize| (discs[m].0 - ci).dot(u) + discs[m].1 - ri;
            if (0..n).all(|m| beyond(m) <= tol) {
                out.push((i, j, u));
            }
        }
    }
    out
}

/// The convex polygon spanned by `points` (about `origin`) as an intersection of half-planes,
/// or `None` when it has no area.
fn polygon(dag: &mut Dag, points: &[DVec2], origin: DVec2, source: Source) -> Option<Edge> {
    let k = convex_hull_2d(points);
    if k.len() < 3 {
        return None;
    }
    let world: Vec<DVec2> = k.iter().map(|p| *p + origin).collect();
    let mut cell = Vec::with_capacity(k.len());
    for (i, &a) in world.iter().enumerate() {
        let t = k[(i + 1) % k.len()] - k[i];
        // Counter-clockwise: the outward normal is the edge turned clockwise.
        let normal = glam::DVec3::new(t.y, -t.x, 0.0);
        cell.push(leaf(
            dag,
            Quadric::half_space(a.extend(0.0), normal),
            source,
        ));
    }
    let cut = dag.intersection(cell, source);
    Some(boxed(dag, cut.into(), &world, 0.0))
}
