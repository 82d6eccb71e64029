//! The point of a feature curve (where two quadrics of the CSG surface meet) nearest to a given
//! point, for the distance from a mesh point to the exact surface near creases.
//!
//! Walking along one quadric from the foot of a normal towards some surface reference point
//! finds *a* point of the crease, but where the walk crosses the crease obliquely that point
//! is far from the nearest one, and the distance it gives is overstated by the obliquity (a
//! mesh vertex inside a concave crease measured twice its distance). Here the crease point is
//! refined to the foot of the perpendicular from the mesh point onto the curve, and accepted
//! only where the solid is seen to change within a small step of it, so that the distance
//! stays an upper bound.

use qcsg_csg::Dnf;
use qcsg_quadric::{DVec3, Quadric};

/// Newton's minimum-norm step onto both quadrics at once (`None` where their gradients are
/// parallel, as at a tangency, where the curve is not a transversal crossing).
fn onto_both(a: &Quadric, b: &Quadric, x: DVec3) -> Option<DVec3> {
    let (ga, gb) = (a.gradient(x), b.gradient(x));
    let (aa, ab, bb) = (ga.dot(ga), ga.dot(gb), gb.dot(gb));
    let det = aa * bb - ab * ab;
    if det.is_nan() || det <= 1e-12 * aa * bb {
        return None;
    }
    let (fa, fb) = (a.value(x), b.value(x));
    // (J Jᵀ) λ = F, step = −Jᵀ λ.
    let la = (bb * fa - ab * fb) / det;
    let lb = (aa * fb - ab * fa) / det;
    let next = x - la * ga - lb * gb;
    next.is_finite().then_some(next)
}

/// The point of the curve where quadrics `a` and `b` meet nearest to `p`, from a point `start`
/// near the curve: alternately onto both quadrics and along the curve's tangent to the foot
/// of the perpendicular from `p`. `None` where it does not settle.
pub fn nearest_on_curve(a: &Quadric, b: &Quadric, start: DVec3, p: DVec3) -> Option<DVec3> {
    let scale = (start - p)
        .length()
        .max(start.abs().max_element())
        .max(1e-300);
    let mut x = start;
    for _ in 0..64 {
        for _ in 0..3 {
            x = onto_both(a, b, x)?;
        }
        let t = a.gradient(x).cross(b.gradient(x)).try_normalize()?;
        let step = (p - x).dot(t);
        // Long tangent steps leave the curve where it bends: at most a quarter of the
        // distance to `p` per step.
        let limit = 0.25 * (p - x).length().max(1e-15 * scale);
        x += step.clamp(-limit, limit) * t;
        if step.abs() <= 1e-13 * scale {
            break;
        }
    }
    for _ in 0..4 {
        x = onto_both(a, b, x)?;
    }
    let t = a.gradient(x).cross(b.gradient(x)).try_normalize()?;
    ((p - x).dot(t).abs() <= 1e-9 * scale).then_some(x)
}

/// The quadric other than `q` whose surface passes nearest `x` (by the first-order distance
/// `|f| / |∇f|`): the other side of a crease found on `q`.
pub fn other_quadric(dnf: &Dnf, q: usize, x: DVec3) -> Option<usize> {
    dnf.quadrics
        .iter()
        .enumerate()
        .filter(|&(i, _)| i != q)
        .filter_map(|(i, e)| {
            let g = e.quadric.gradient(x).length();
            (g > 0.0).then(|| (i, e.quadric.value(x).abs() / g))
        })
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(i, _)| i)
}

/// Whether the solid's membership differs between two points within `delta` of `y` (then the
/// segment between them, inside the ball of radius `delta` about `y`, crosses the surface, so
/// a point of the surface lies within `delta` of `y`). The points are `y` and `y ± delta·u` for
/// the normals of both quadrics and their sum and difference, which straddle every side of a
/// crease.
pub fn surface_within(dnf: &Dnf, a: &Quadric, b: &Quadric, y: DVec3, delta: f64) -> bool {
    let (Some(na), Some(nb)) = (a.normal(y), b.normal(y)) else {
        return false;
    };
    let here = dnf.contains(y);
    let mut dirs = vec![na, nb];
    dirs.extend((na + nb).try_normalize());
    dirs.extend((na - nb).try_normalize());
    dirs.iter()
        .flat_map(|&u| [y + delta * u, y - delta * u])
        .any(|z| dnf.contains(z) != here)
}
