//! Planar literals as half-spaces ([`HalfSpace`]): a half-space's one, a slab's two, and a
//! slab's outside as the complement of its pair.

use qcsg_quadric::{DVec3, Quadric, QuadricKind};

/// A half-space `{x : normal · x ≤ offset}`, `normal` a unit vector.
#[derive(Clone, Copy, Debug)]
pub(super) struct HalfSpace {
    pub(super) normal: DVec3,
    pub(super) offset: f64,
    pub(super) point: DVec3,
}

/// The half-spaces whose intersection is the solid of `q`: one for a half-space, two for a slab;
/// `None` for anything else (the outside of a slab is a union, not an intersection).
pub(super) fn half_spaces(q: &Quadric) -> Option<Vec<HalfSpace>> {
    half_spaces_of_kind(q, q.kind())
}

/// [`half_spaces`] of `q`, whose kind is `kind`.
fn half_spaces_of_kind(q: &Quadric, kind: QuadricKind) -> Option<Vec<HalfSpace>> {
    let make = |normal: DVec3, point: DVec3| HalfSpace {
        normal,
        offset: normal.dot(point),
        point,
    };
    match kind {
        QuadricKind::Plane => {
            let (low, high) = q.eigenvalue_bounds();
            let normal = q.linear().try_normalize()?;
            if low != 0.0 || high != 0.0 {
                return None;
            }
            // Q = 2 l·(x − o) + j: the plane is at o − j / (2|l|) along the normal.
            let point = q.origin() - normal * (q.constant() / (2.0 * q.linear().length()));
            Some(vec![make(normal, point)])
        }
        QuadricKind::ParallelPlanes => {
            let frame = q.frame();
            let k = (0..3).find(|&k| frame.eigenvalues[k] != 0.0)?;
            let lambda = frame.eigenvalues[k];
            let others_zero = (0..3).all(|j| j == k || frame.eigenvalues[j] == 0.0);
            if !(others_zero && lambda > 0.0 && frame.constant < 0.0) || frame.linear != [0.0; 3] {
                return None;
            }
            let (u, half_width) = (frame.axes[k], (-frame.constant / lambda).sqrt());
            Some(vec![
                make(u, frame.centre + half_width * u),
                make(-u, frame.centre - half_width * u),
            ])
        }
        _ => None,
    }
}

/// The half-spaces of a planar quadric, and whether the quadric is the complement of their
/// intersection (the outside of a slab) rather than the intersection ([`planar_parts`]).
pub(super) type PlanarParts = (Vec<HalfSpace>, bool);

/// The half-spaces of a planar literal ([`half_spaces`]), or those of the slab whose outside
/// it is, flagged `true`.
pub(super) fn planar_parts(q: &Quadric) -> Option<PlanarParts> {
    // Its kind once: an eigen decomposition.
    let kind = q.kind();
    if !matches!(kind, QuadricKind::Plane | QuadricKind::ParallelPlanes) {
        return None;
    }
    half_spaces_of_kind(q, kind)
        .map(|spaces| (spaces, false))
        .or_else(|| half_spaces(&q.negated()).map(|spaces| (spaces, true)))
}

/// The closed complement of a half-space: a slab is `n·x ≤ c` for each of its half-spaces, its
/// outside `n·x ≥ c` for either.
pub(super) fn beyond(h: &HalfSpace) -> HalfSpace {
    HalfSpace {
        normal: -h.normal,
        offset: -h.offset,
        point: h.point,
    }
}
