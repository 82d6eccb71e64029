//! The Minkowski sum of a convex polytope Q with a disc D of radius ρ square to an axis u, built
//! exactly from planes and cylinders: the sum of a polytope with a circular cylinder along u is
//! Q' ⊕ D with Q' the polytope summed with the cylinder's axis segment ([`crate::minkowski`]).
//!
//! In a frame where u is z, every section of Q ⊕ D at a height is the section Q_z of Q grown by
//! ρ in its plane. A point of Q_z ⊕ D outside Q_z has its nearest point of Q_z on a side of
//! Q_z, which lies in a face F of Q whose normal's horizontal part n̂ is the side's outward
//! normal, or at a corner of Q_z, which lies on an edge E of Q. So
//!
//!   Q ⊕ D = Q ∪ ⋃_F hull(F ∪ (F + ρ n̂)) ∪ ⋃_E (E ⊕ D),
//!
//! over the faces that are not horizontal and the edges that are not horizontal (horizontal
//! ones meet one height only: no volume). E ⊕ D is the oblique cylinder of horizontal circles
//! of radius ρ about E, a quadric, cut by the slab of E's heights. A flat Q (a polygon) is its
//! one face seen from both sides, a segment its oblique cylinder.

use glam::{DMat4, DVec3, DVec4};
use qcsg_csg::{Dag, Edge};
use qcsg_mesh::{ConvexHull, convex_hull};
use qcsg_quadric::Quadric;

use crate::hull::{HullBuilder, HullRefusal, box_of, hull_error};
use crate::hull_frusta::frame_of;

/// The sum of the polytope spanned by `points` with the disc of `radius` square to the unit
/// `axis`, as DAG nodes.
pub fn build(
    dag: &mut Dag,
    builder: &HullBuilder,
    points: &[DVec3],
    axis: DVec3,
    radius: f64,
) -> Result<Edge, HullRefusal> {
    let (e1, e2) = frame_of(axis);
    let local: Vec<DVec3> = points
        .iter()
        .map(|p| DVec3::new(e1.dot(*p), e2.dot(*p), axis.dot(*p)))
        .collect();
    let Some(edge) = build_local(dag, builder, &local, radius)? else {
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
    dag.transformed(edge, &frame).map_err(|_| {
        HullRefusal::Unrepresentable("the cylinder's frame is not representable".into())
    })
}

/// The sum in the frame where the axis is z, or `None` when it has no volume.
fn build_local(
    dag: &mut Dag,
    builder: &HullBuilder,
    points: &[DVec3],
    rho: f64,
) -> Result<Option<Edge>, HullRefusal> {
    let hull = convex_hull(points, builder.max_points).map_err(hull_error)?;
    let mut parts: Vec<Edge> = Vec::new();
    let mut edges: Vec<(DVec3, DVec3)> = Vec::new();
    match hull {
        ConvexHull::Empty | ConvexHull::Point(_) => {}
        ConvexHull::Segment(a, b) => edges.push((a, b)),
        ConvexHull::Polygon { vertices, normal } => {
            if let Some(out) = horizontal_unit(normal) {
                let sides: Vec<DVec3> = vertices
                    .iter()
                    .flat_map(|v| [*v + rho * out, *v - rho * out])
                    .collect();
                parts.extend(polytope(dag, builder, &sides)?);
            }
            for (i, &a) in vertices.iter().enumerate() {
                edges.push((a, vertices[(i + 1) % vertices.len()]));
            }
        }
        ConvexHull::Solid(faces) => {
            let key = |p: DVec3| p.to_array().map(f64::to_bits);
            let mut seen = std::collections::HashSet::new();
            let mut cells = Vec::with_capacity(faces.len());
            for face in &faces {
                cells.push(builder.leaf(dag, Quadric::half_space(face.vertices[0], face.normal)));
                if let Some(out) = horizontal_unit(face.normal) {
                    let grown: Vec<DVec3> = face
                        .vertices
                        .iter()
                        .flat_map(|v| [*v, *v + rho * out])
                        .collect();
                    parts.extend(polytope(dag, builder, &grown)?);
                }
                for (i, &a) in face.vertices.iter().enumerate() {
                    let b = face.vertices[(i + 1) % face.vertices.len()];
                    let (ka, kb) = (key(a), key(b));
                    if seen.insert(if ka < kb { (ka, kb) } else { (kb, ka) }) {
                        edges.push((a, b));
                    }
                }
            }
            parts.push(builder.intersection_in(dag, cells, box_of(points, 0.0)));
        }
    }
    for (a, b) in edges {
        parts.extend(oblique_cylinder(dag, builder, a, b, rho));
    }
    if parts.is_empty() {
        return Ok(None);
    }
    let union = dag.union(parts, builder.source);
    let mut bounds = box_of(points, rho);
    // The sum reaches ρ out across the axis only.
    let lo = points.iter().fold(f64::INFINITY, |m, p| m.min(p.z));
    let hi = points.iter().fold(f64::NEG_INFINITY, |m, p| m.max(p.z));
    let padded = box_of(&[DVec3::new(0.0, 0.0, lo), DVec3::new(0.0, 0.0, hi)], 0.0);
    bounds.min.z = padded.min.z;
    bounds.max.z = padded.max.z;
    Ok(Some(dag.bounded(union, bounds).into()))
}

/// The unit horizontal part of a face's normal, or `None` for a face that is (nearly)
/// horizontal, whose sum with the disc adds no volume beyond its edges'.
fn horizontal_unit(normal: DVec3) -> Option<DVec3> {
    let h = DVec3::new(normal.x, normal.y, 0.0);
    (h.length() > 1e-12 * normal.length()).then(|| h.normalize())
}

/// The convex polytope spanned by `points` as an intersection of half-spaces, or `None` when
/// it has no volume.
fn polytope(
    dag: &mut Dag,
    builder: &HullBuilder,
    points: &[DVec3],
) -> Result<Option<Edge>, HullRefusal> {
    let ConvexHull::Solid(faces) = convex_hull(points, usize::MAX).map_err(hull_error)? else {
        return Ok(None);
    };
    let cells: Vec<Edge> = faces
        .iter()
        .map(|f| builder.leaf(dag, Quadric::half_space(f.vertices[0], f.normal)))
        .collect();
    Ok(Some(builder.intersection_in(
        dag,
        cells,
        box_of(points, 0.0),
    )))
}

/// The points within ρ across z of the segment `a`–`b`: horizontal circles about it, between
/// the heights of its ends (`None` for a horizontal segment, which has no volume).
fn oblique_cylinder(
    dag: &mut Dag,
    builder: &HullBuilder,
    a: DVec3,
    b: DVec3,
    rho: f64,
) -> Option<Edge> {
    let w = b - a;
    if w.z.abs() <= 1e-12 * w.length() || rho <= 0.0 {
        return None;
    }
    // y = (x − a)ₕ − s (x − a)_z with s = wₕ / w_z is the offset across z from the segment's
    // point at the height of x: |y|²/ρ² − 1 ≤ 0, A = MᵀM/ρ² for M = [[1, 0, −sx], [0, 1, −sy]].
    let (sx, sy) = (w.x / w.z, w.y / w.z);
    let k = 1.0 / (rho * rho);
    let m = [
        [k, 0.0, -k * sx],
        [0.0, k, -k * sy],
        [-k * sx, -k * sy, k * (sx * sx + sy * sy)],
    ];
    let lateral = Quadric::from_matrix(a, &m, DVec3::ZERO, -1.0);
    let mid = 0.5 * (a + b);
    let slab = Quadric::slab(mid, DVec3::Z, 0.5 * w.z.abs());
    let parts = vec![builder.leaf(dag, lateral), builder.leaf(dag, slab)];
    let across = DVec3::new(rho, rho, 0.0);
    let lo = a.min(b) - across;
    let hi = a.max(b) + across;
    Some(builder.intersection_in(dag, parts, box_of(&[lo, hi], 0.0)))
}
