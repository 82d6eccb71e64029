//! The convex hull H of discs square to one axis (the ends of cylinders and cones with parallel
//! axes, at any heights and of any radii; a point being a disc of radius 0), built exactly from
//! planes and oblique circular cones. It serves `hull` of parallel cylinders and cones, and
//! `minkowski` of a polytope with a cone (the hull of the cone's two discs moved to every
//! corner).
//!
//! In a frame where the axis is z, H is the union of the discs D(c, R) across z over the points
//! (c, R) of the lifted polytope L = conv{(cᵢ, rᵢ)} ⊂ ℝ⁴ (a convex combination of points of the
//! discs is a point of the combined disc, and back). For p ∈ H, the (c, R) ∈ L at p's height
//! maximising R − |(p − c)ₕ| lies on a face of L exposed by (u, λ, 1) with u = (p − c)ₕ/|…|
//! (optimality on the slice of L at that height, λ the multiplier of the height), and p lies on
//! the segment from c to c + R u. The faces met that way, away from a set of no volume, are
//!
//! - two discs at different heights with a plane of normal (u, λ), |u| = 1, touching both and
//!   every disc below it: p is in the hull of the two discs, which is the solid oblique cone
//!   through the two circles between their heights (a circular cylinder's shape for equal
//!   radii), a quadric cut by a slab;
//! - several discs touching one such plane: p is in the polytope spanned by their centres and
//!   their points c + r u on the plane (u is the same for all);
//! - and p = c: the hull K of the centres.
//!
//! Every piece lies in H and together they cover it. A pair is kept when the normals u for which
//! the plane through both discs has every disc below form a non-empty set: each other disc
//! bounds u to an arc of the circle, and a non-empty intersection of arcs has an arc's end in
//! every arc, so the test is exact; doubtful pairs are kept, which costs pieces, not
//! correctness.

use glam::{DMat4, DVec3, DVec4};
use qcsg_csg::{Dag, Edge};
use qcsg_mesh::{ConvexHull, convex_hull};
use qcsg_quadric::Quadric;

use crate::codes;
use crate::hull::{HullBuilder, HullRefusal, box_of, hull_error, padded};

/// A disc square to the axis: its centre and radius.
#[derive(Clone, Copy, Debug)]
pub struct AxialDisc {
    /// The centre, in world space.
    pub centre: DVec3,
    /// The radius (0 for a point).
    pub radius: f64,
}

/// The hull of `discs`, all square to the unit `axis`, as DAG nodes built by `builder`.
pub fn build(
    dag: &mut Dag,
    builder: &HullBuilder,
    discs: &[AxialDisc],
    axis: DVec3,
) -> Result<Edge, HullRefusal> {
    let (e1, e2) = frame_of(axis);
    let local: Vec<(DVec3, f64)> = discs
        .iter()
        .map(|d| {
            let c = d.centre;
            (DVec3::new(e1.dot(c), e2.dot(c), axis.dot(c)), d.radius)
        })
        .collect();
    if let Some((bad, _)) = local.iter().find(|(c, r)| !c.is_finite() || !r.is_finite()) {
        return Err(HullRefusal::Unrepresentable(format!(
            "a point of the hull is not finite ({bad})"
        )));
    }
    let Some(edge) = build_local(dag, builder, &local)? else {
        return Ok(dag.empty(builder.source).into());
    };
    if axis == DVec3::Z {
        return Ok(edge);
    }
    let frame = DMat4::from_cols(
        e1.extend(0.0),
        e2.extend(0.0),
        axis.extend(0.0),
        DVec4::new(0.0, 0.0, 0.0, 1.0),
    );
    dag.transformed(edge, &frame)
        .map_err(|_| HullRefusal::Unrepresentable("the axis' frame is not representable".into()))
}

/// A right-handed frame (e1, e2, axis), the coordinate axes themselves where the axis is one.
pub(crate) fn frame_of(u: DVec3) -> (DVec3, DVec3) {
    if u == DVec3::Z {
        (DVec3::X, DVec3::Y)
    } else if u == DVec3::X {
        (DVec3::Y, DVec3::Z)
    } else if u == DVec3::Y {
        (DVec3::Z, DVec3::X)
    } else {
        let helper = if u.x.abs() < 0.9 { DVec3::X } else { DVec3::Y };
        let e1 = u.cross(helper).normalize();
        (e1, u.cross(e1))
    }
}

/// The hull in the frame where the axis is z, or `None` when it has no volume.
fn build_local(
    dag: &mut Dag,
    builder: &HullBuilder,
    world: &[(DVec3, f64)],
) -> Result<Option<Edge>, HullRefusal> {
    if world.is_empty() {
        return Ok(None);
    }
    // Work about the centre of the configuration: offsets of the hull's size.
    let lo = world.iter().fold(DVec3::INFINITY, |m, (c, _)| m.min(*c));
    let hi = world
        .iter()
        .fold(DVec3::NEG_INFINITY, |m, (c, _)| m.max(*c));
    let origin = 0.5 * (lo + hi);
    let scale = world
        .iter()
        .map(|(c, r)| (*c - origin).length() + r)
        .fold(0.0f64, f64::max);
    if scale == 0.0 {
        return Ok(None);
    }
    let tol = 1e-9 * scale;
    let discs = prune(world.iter().map(|&(c, r)| (c - origin, r)).collect(), tol);
    if discs.len() > builder.max_points {
        return Err(HullRefusal::Limit(
            codes::HULL_POINT_LIMIT,
            format!(
                "the hull has more than {} distinct discs and corners",
                builder.max_points
            ),
        ));
    }
    let mut parts: Vec<Edge> = Vec::new();
    let centres: Vec<DVec3> = discs.iter().map(|(c, _)| *c).collect();
    parts.extend(polytope(dag, builder, &centres, origin)?);
    for (normal, touching) in facets(&discs, tol) {
        if touching.iter().all(|&m| discs[m].1 == 0.0) {
            // A face of K.
            continue;
        }
        let points: Vec<DVec3> = touching
            .iter()
            .flat_map(|&m| [discs[m].0, discs[m].0 + discs[m].1 * normal])
            .collect();
        parts.extend(polytope(dag, builder, &points, origin)?);
    }
    let n = discs.len();
    for i in 0..n {
        for j in i + 1..n {
            if exposed(&discs, i, j, tol) {
                parts.extend(frustum(dag, builder, discs[i], discs[j], origin));
            }
        }
    }
    if parts.is_empty() {
        return Ok(None);
    }
    let union = dag.union(parts, builder.source);
    let lo = world.iter().fold(DVec3::INFINITY, |m, (c, r)| {
        m.min(*c - DVec3::new(*r, *r, 0.0))
    });
    let hi = world.iter().fold(DVec3::NEG_INFINITY, |m, (c, r)| {
        m.max(*c + DVec3::new(*r, *r, 0.0))
    });
    Ok(Some(dag.bounded(union, padded(lo, hi)).into()))
}

/// Drops discs inside another disc at the same height (and repeated points).
fn prune(mut discs: Vec<(DVec3, f64)>, tol: f64) -> Vec<(DVec3, f64)> {
    discs.sort_by(|a, b| b.1.total_cmp(&a.1));
    let mut kept: Vec<(DVec3, f64)> = Vec::with_capacity(discs.len());
    for (c, r) in discs {
        let inside = kept
            .iter()
            .any(|(k, s)| (c.z - k.z).abs() <= tol && (c - *k).truncate().length() + r <= s + tol);
        if !inside {
            kept.push((c, r));
        }
    }
    kept
}

/// How far disc `m` reaches beyond the plane of normal `n = (u, λ)` (|u| = 1) through the
/// point of disc `i` furthest along u, in units of the plane's distance.
fn beyond(discs: &[(DVec3, f64)], i: usize, m: usize, n: DVec3) -> f64 {
    ((discs[m].0 - discs[i].0).dot(n) + discs[m].1 - discs[i].1) / n.length()
}

/// The planes touching three or more discs with every disc on their inner side, whose normal
/// is not along the axis: the unit horizontal part u of the normal and the discs touching.
fn facets(discs: &[(DVec3, f64)], tol: f64) -> Vec<(DVec3, Vec<usize>)> {
    let n = discs.len();
    let mut found: Vec<(DVec3, Vec<usize>)> = Vec::new();
    let mut normals: Vec<DVec3> = Vec::new();
    for i in 0..n {
        for j in i + 1..n {
            for k in j + 1..n {
                for normal in tangent_normals(discs[i], discs[j], discs[k]) {
                    let unit = normal.normalize();
                    if normals.iter().any(|v| (*v - unit).length() <= 1e-9) {
                        continue;
                    }
                    if (0..n).any(|m| beyond(discs, i, m, normal) > tol) {
                        continue;
                    }
                    normals.push(unit);
                    let touching: Vec<usize> = (0..n)
                        .filter(|&m| beyond(discs, i, m, normal) >= -tol)
                        .collect();
                    found.push((DVec3::new(normal.x, normal.y, 0.0), touching));
                }
            }
        }
    }
    found
}

/// The normals n = (u, λ) with |u| = 1 of the planes touching the three discs on the same side:
/// `n · (cⱼ − cᵢ) = rᵢ − rⱼ`, `n · (cₖ − cᵢ) = rᵢ − rₖ` (none, one or two).
fn tangent_normals(a: (DVec3, f64), b: (DVec3, f64), c: (DVec3, f64)) -> Vec<DVec3> {
    let (x, y) = (b.0 - a.0, c.0 - a.0);
    let (alpha, beta) = (a.1 - b.1, a.1 - c.1);
    let m = x.cross(y);
    let m2 = m.length_squared();
    if m2 <= (1e-12 * x.length() * y.length()).powi(2) || m2 == 0.0 {
        // Collinear centres: the touching planes form a family, or there are none.
        return Vec::new();
    }
    // n = n0 + t m solves both equations; |(n0 + t m)ₕ| = 1 picks t.
    let n0 = (alpha * y.cross(m) + beta * m.cross(x)) / m2;
    let (n0h, mh) = (n0.truncate(), m.truncate());
    let qa = mh.length_squared();
    if qa <= 1e-24 * m2 {
        // The centres at one height: the planes touching all three, if any, form a family.
        return Vec::new();
    }
    let qb = 2.0 * n0h.dot(mh);
    let qc = n0h.length_squared() - 1.0;
    let disc = qb * qb - 4.0 * qa * qc;
    if disc < -1e-12 * qb.abs().max(qa) {
        return Vec::new();
    }
    let root = disc.max(0.0).sqrt();
    let mut out: Vec<DVec3> = Vec::with_capacity(2);
    for t in [(-qb + root) / (2.0 * qa), (-qb - root) / (2.0 * qa)] {
        let n = n0 + t * m;
        let h = n.truncate().length();
        if h > 0.0 && n.is_finite() {
            // Exactly unit across the axis.
            let n = DVec3::new(n.x / h, n.y / h, n.z / h);
            if !out
                .iter()
                .any(|v| (*v - n).length() <= 1e-12 * (1.0 + n.z.abs()))
            {
                out.push(n);
            }
        }
    }
    out
}

/// Whether some plane touching discs `i` and `j` (at different heights, not both points) has
/// every disc on its inner side: the arcs of unit u allowed by each disc meet.
fn exposed(discs: &[(DVec3, f64)], i: usize, j: usize, tol: f64) -> bool {
    let ((ci, ri), (cj, rj)) = (discs[i], discs[j]);
    let w = cj - ci;
    if ri + rj == 0.0 || w.z.abs() <= tol {
        // Two points (an edge of K), or discs at one height (their hull has no volume).
        return false;
    }
    // The plane of normal (u, λ) touches both when λ = (rᵢ − rⱼ − wₕ·u)/w_z; disc m is then
    // below it when A·u + B ≤ 0.
    let mut arcs: Vec<(f64, f64)> = Vec::new();
    for (m, &(cm, rm)) in discs.iter().enumerate() {
        if m == i || m == j {
            continue;
        }
        let d = cm - ci;
        let f = d.z / w.z;
        let a = d.truncate() - f * w.truncate();
        let b = rm - ri + f * (ri - rj);
        // Generous: a disc within the tolerance of the plane does not rule it out.
        let slack = tol * (1.0 + f.abs());
        let length = a.length();
        if length <= slack {
            if b > slack {
                return false;
            }
            continue;
        }
        // −â · u ≥ (b − slack)/|a|: the arc about −â of half-width acos of that.
        let kappa = (b - slack) / length;
        if kappa > 1.0 {
            return false;
        }
        if kappa > -1.0 {
            arcs.push(((-a.y).atan2(-a.x), kappa.acos()));
        }
    }
    if arcs.is_empty() {
        return true;
    }
    let within = |phi: f64| {
        arcs.iter().all(|&(centre, half)| {
            let off = (phi - centre).rem_euclid(std::f64::consts::TAU);
            off.min(std::f64::consts::TAU - off) <= half + 1e-9
        })
    };
    arcs.iter()
        .any(|&(centre, half)| within(centre - half) || within(centre + half))
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
        .map(|f| builder.leaf(dag, Quadric::half_space(f.vertices[0] + origin, f.normal)))
        .collect();
    let world: Vec<DVec3> = points.iter().map(|p| *p + origin).collect();
    Ok(Some(builder.intersection_in(
        dag,
        cells,
        box_of(&world, 0.0),
    )))
}

/// The hull of two discs at different heights: the oblique cone (or cylinder) through their
/// circles, between their heights.
fn frustum(
    dag: &mut Dag,
    builder: &HullBuilder,
    a: (DVec3, f64),
    b: (DVec3, f64),
    origin: DVec3,
) -> Option<Edge> {
    let ((ca, ra), (cb, rb)) = (a, b);
    let w = cb - ca;
    // With X = x − cₐ and s = X_z / w_z, the section at s is the disc about cₐ + s w of radius
    // rₐ + s (r_b − rₐ): |Xₕ − s wₕ|² − (rₐ + δ X_z)² ≤ 0, δ = (r_b − rₐ)/w_z, scaled by the
    // larger radius so that values are of the size of lengths over it.
    let (sx, sy) = (w.x / w.z, w.y / w.z);
    let delta = (rb - ra) / w.z;
    let k = 1.0 / ra.max(rb).powi(2);
    let m = [
        [k, 0.0, -k * sx],
        [0.0, k, -k * sy],
        [-k * sx, -k * sy, k * (sx * sx + sy * sy - delta * delta)],
    ];
    let lateral = Quadric::from_matrix(
        ca + origin,
        &m,
        DVec3::new(0.0, 0.0, -k * ra * delta),
        -k * ra * ra,
    );
    let slab = Quadric::slab(ca + origin + 0.5 * w, DVec3::Z, 0.5 * w.z.abs());
    let parts = vec![builder.leaf(dag, lateral), builder.leaf(dag, slab)];
    let reach = |c: DVec3, r: f64| [c - DVec3::new(r, r, 0.0), c + DVec3::new(r, r, 0.0)];
    let corners: Vec<DVec3> = reach(ca + origin, ra)
        .into_iter()
        .chain(reach(cb + origin, rb))
        .collect();
    Some(builder.intersection_in(dag, parts, box_of(&corners, 0.0)))
}
