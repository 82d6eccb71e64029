//! Boxes of terms whose literals' own boxes leave them unbounded, from their planar literals.
//!
//! A term such as the intersection of six tilted half-spaces is bounded although every literal
//! is unbounded on its own and no node declared a box. Its half-spaces (and the two planes of
//! each slab) form a polyhedron: it is bounded exactly when its recession cone `{d : nᵢ·d ≤ 0}`
//! is `{0}`, and then it is the hull of its vertices. Ignoring the curved literals only enlarges
//! the set, so the box stays conservative. Ties are resolved towards "unbounded".

use qcsg_quadric::{DVec3, Quadric};

use crate::bounds::Aabb;

/// Most planes considered (vertex enumeration is cubic in their number).
const MAX_PLANES: usize = 32;

/// Relative widening of the computed box (vertex rounding, eigenvector error of slabs).
const WIDENING: f64 = 1e-6;

/// A half-space `normal · p ≤ offset` with a unit normal.
#[derive(Clone, Copy, Debug)]
pub struct HalfSpace {
    /// Outward unit normal.
    pub normal: DVec3,
    /// Offset along the normal.
    pub offset: f64,
}

/// The half-spaces whose intersection contains the solid of `q`: one for a plane, two for a
/// slab (a rank-one quadric `λ (u·x)² + 2μ (u·x) + j`), none otherwise.
pub fn half_spaces(q: &Quadric) -> Vec<HalfSpace> {
    let k = q.coefficients();
    let l = q.linear();
    let origin = q.origin();
    if k[..6].iter().all(|&v| v == 0.0) {
        let length = l.length();
        if length == 0.0 || !length.is_finite() {
            return Vec::new();
        }
        // 2 l·(p − o) + j ≤ 0  ⟺  l̂·p ≤ l̂·o − j / (2|l|).
        let normal = l / length;
        return vec![HalfSpace {
            normal,
            offset: normal.dot(origin) - q.constant() / (2.0 * length),
        }];
    }
    let eigen = q.eigen();
    let [small, middle, large] = eigen.values;
    if large <= 0.0 || small.abs().max(middle.abs()) > 1e-12 * large {
        return Vec::new();
    }
    let axis = eigen.vectors[2];
    let along = l.dot(axis);
    if (l - along * axis).length() > 1e-12 * l.length().max(large) {
        // Not a slab (e.g. a parabolic cylinder).
        return Vec::new();
    }
    // λ t² + 2 μ t + j ≤ 0 with t = u·(p − o).
    let discriminant = along * along - large * q.constant();
    if discriminant < 0.0 {
        return Vec::new();
    }
    let root = discriminant.sqrt();
    let (t1, t2) = ((-along - root) / large, (-along + root) / large);
    let base = axis.dot(origin);
    vec![
        HalfSpace {
            normal: axis,
            offset: base + t2,
        },
        HalfSpace {
            normal: -axis,
            offset: -(base + t1),
        },
    ]
}

/// A box containing the polyhedron `⋂ {normal · p ≤ offset}`, or `None` if it may be
/// unbounded (or has too many planes to check).
pub fn polyhedron_bounds(planes: &[HalfSpace]) -> Option<Aabb> {
    if planes.len() < 4 || planes.len() > MAX_PLANES {
        return None;
    }
    // A recession direction lies on the intersection line of two independent planes.
    let mut independent = false;
    for (i, a) in planes.iter().enumerate() {
        for b in &planes[i + 1..] {
            let d = a.normal.cross(b.normal);
            let length = d.length();
            if length < 1e-9 {
                continue;
            }
            let d = d / length;
            for direction in [d, -d] {
                if planes.iter().all(|p| p.normal.dot(direction) <= 1e-9) {
                    return None;
                }
            }
            independent = true;
        }
    }
    if !independent {
        return None;
    }
    let scale = planes.iter().fold(0.0f64, |m, p| m.max(p.offset.abs()));
    let mut result = Aabb::EMPTY;
    for (i, a) in planes.iter().enumerate() {
        for (j, b) in planes.iter().enumerate().skip(i + 1) {
            for c in &planes[j + 1..] {
                let Some(vertex) = intersect_three(a, b, c) else {
                    continue;
                };
                let tolerance = 1e-9 * (scale + vertex.abs().max_element());
                if planes
                    .iter()
                    .all(|p| p.normal.dot(vertex) <= p.offset + tolerance)
                {
                    result = result.union(&Aabb::new(vertex, vertex));
                }
            }
        }
    }
    if result.is_empty() || !result.is_bounded() {
        return None;
    }
    let extent = (result.max - result.min).max_element();
    let magnitude = result.min.abs().max(result.max.abs()).max_element();
    let pad = DVec3::splat(WIDENING * (extent + magnitude));
    Some(Aabb::new(result.min - pad, result.max + pad))
}

/// The point on three planes, if their normals are independent enough.
fn intersect_three(a: &HalfSpace, b: &HalfSpace, c: &HalfSpace) -> Option<DVec3> {
    let bc = b.normal.cross(c.normal);
    let det = a.normal.dot(bc);
    if det.abs() < 1e-9 {
        return None;
    }
    let point =
        (a.offset * bc + b.offset * c.normal.cross(a.normal) + c.offset * a.normal.cross(b.normal))
            / det;
    point.is_finite().then_some(point)
}

#[cfg(test)]
mod tests {
    use super::*;
    use qcsg_quadric::DMat4;

    #[test]
    fn tilted_box_of_half_spaces_is_bounded() {
        let rotation = DMat4::from_rotation_z(0.4) * DMat4::from_rotation_x(0.3);
        let mut planes = Vec::new();
        for axis in [DVec3::X, DVec3::Y, DVec3::Z] {
            for sign in [1.0, -1.0] {
                let normal = rotation.transform_vector3(axis * sign);
                let q = Quadric::half_space(normal * 2.0 + DVec3::splat(10.0), normal).unwrap();
                planes.extend(half_spaces(&q));
            }
        }
        let b = polyhedron_bounds(&planes).unwrap();
        assert!(b.contains(DVec3::splat(10.0)));
        assert!((b.max - b.min).max_element() < 8.0);
        // Without one face it is unbounded.
        assert!(polyhedron_bounds(&planes[1..]).is_none());
    }

    #[test]
    fn slab_gives_two_planes() {
        let q = Quadric::slab(DVec3::new(0.0, 0.0, 3.0), DVec3::new(0.0, 1.0, 1.0), 1.0).unwrap();
        let planes = half_spaces(&q);
        assert_eq!(planes.len(), 2);
        for plane in &planes {
            // Each face lies at the half-width from the centre, on its own side.
            let gap = plane.offset - plane.normal.dot(DVec3::new(0.0, 0.0, 3.0));
            assert!((gap - 1.0).abs() < 1e-9, "{planes:?}");
        }
        assert!((planes[0].normal + planes[1].normal).length() < 1e-12);
    }
}
