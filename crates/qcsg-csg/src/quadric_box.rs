//! Quadrics against boxes: the box a quadric's solid fits in, and whether a quadric is
//! provably inside, outside or possibly cutting a box.
//!
//! These are what pruning rests on, so they are conservative: an answer other than
//! [`BoxClass::Cuts`] is a proof that accounts for rounding.

use qcsg_quadric::{DVec3, Quadric};

use crate::bounds::{Aabb, interval_product, scale_interval};

/// Unit roundoff of f64.
const EPS: f64 = f64::EPSILON * 0.5;

/// Relative margin added to computed extents of a quadric's solid.
const EXTENT_MARGIN: f64 = 1e-9;

/// How a quadric's solid relates to a box.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BoxClass {
    /// Every point of the box satisfies `q ≤ 0`.
    Inside,
    /// No point of the box satisfies `q ≤ 0`.
    Outside,
    /// Neither could be proved.
    Cuts,
}

/// A box (in world coordinates) containing the solid `q ≤ 0`: exact up to a small outward
/// margin for ellipsoids (positive definite `A`) and for quadrics of a single coordinate (a
/// slab `x² ≤ a²`, a half-space `x ≤ c`); all of space otherwise. Empty when the solid is
/// provably empty.
pub fn solid_bounds(q: &Quadric) -> Aabb {
    let (lower, _) = q.eigenvalue_bounds();
    if lower > 0.0 {
        return ellipsoid_bounds(q);
    }
    let k = q.coefficients();
    let a = q.matrix_a();
    let l = q.linear();
    let mut result = Aabb::EVERYTHING;
    for axis in 0..3 {
        let others_zero = (0..3).all(|r| {
            (0..3).all(|c| (r == axis && c == axis) || a[r][c] == 0.0) && (r == axis || l[r] == 0.0)
        });
        if !others_zero {
            continue;
        }
        let (lo, hi) = match quadratic_solutions(a[axis][axis], l[axis], k[9]) {
            Some(interval) => interval,
            None => return Aabb::EMPTY,
        };
        let origin = q.origin()[axis];
        result.min[axis] = lo + origin;
        result.max[axis] = hi + origin;
    }
    result.widened_by(EXTENT_MARGIN)
}

/// For a quadric of one world coordinate whose solid is the outside of an interval (the
/// complement of a slab `x² ≥ a²`): that axis and the open interval `(low, high)` it excludes,
/// in world coordinates, shrunk slightly so that it never excludes a point of the solid.
pub fn excluded_interval(q: &Quadric) -> Option<(usize, f64, f64)> {
    let a = q.matrix_a();
    let l = q.linear();
    let axis = single_axis(&a, l)?;
    let (square, half_linear, constant) = (a[axis][axis], l[axis], q.constant());
    if square >= 0.0 {
        return None;
    }
    // −q ≥ 0 outside the roots of q: q = square·x² + 2·half_linear·x + constant ≤ 0 with
    // square < 0 holds outside the roots of the upward parabola −q.
    let (r1, r2) = quadratic_solutions(-square, -half_linear, -constant)?;
    if r1 >= r2 {
        return None;
    }
    let origin = q.origin()[axis];
    // The roots come back widened by ~1e-12 relative; shrinking by EXTENT_MARGIN (1e-9
    // relative) more than undoes that, so the excluded interval errs on the small side.
    let shrink = EXTENT_MARGIN * (r1.abs().max(r2.abs()) + origin.abs());
    let (low, high) = (r1 + origin + shrink, r2 + origin - shrink);
    (low < high).then_some((axis, low, high))
}

/// The axis a quadric depends on alone, if there is one.
fn single_axis(a: &[[f64; 3]; 3], l: DVec3) -> Option<usize> {
    (0..3).find(|&axis| {
        (0..3).all(|r| {
            (0..3).all(|c| (r == axis && c == axis) || a[r][c] == 0.0) && (r == axis || l[r] == 0.0)
        })
    })
}

/// `bounds` shrunk to the hull of its points outside the open interval `(low, high)` on `axis`.
pub fn clip_outside_interval(bounds: &Aabb, axis: usize, low: f64, high: f64) -> Aabb {
    let (lo, hi) = (bounds.min[axis], bounds.max[axis]);
    let left = lo <= low;
    let right = high <= hi;
    let mut result = *bounds;
    match (left, right) {
        (false, false) => return Aabb::EMPTY,
        (true, false) => result.max[axis] = hi.min(low),
        (false, true) => result.min[axis] = lo.max(high),
        (true, true) => {}
    }
    result
}

/// The hull of `{x : a x² + 2 g x + j ≤ 0}` as an interval (possibly infinite); `None` when
/// empty.
fn quadratic_solutions(a: f64, g: f64, j: f64) -> Option<(f64, f64)> {
    if a == 0.0 {
        if g == 0.0 {
            return (j <= 0.0).then_some((f64::NEG_INFINITY, f64::INFINITY));
        }
        let root = -j / (2.0 * g);
        return Some(if g > 0.0 {
            (f64::NEG_INFINITY, root)
        } else {
            (root, f64::INFINITY)
        });
    }
    let discriminant = g * g - a * j;
    if a < 0.0 {
        // The complement of an interval (or everything): its hull is the whole line.
        return Some((f64::NEG_INFINITY, f64::INFINITY));
    }
    if discriminant < 0.0 {
        // Within rounding the solid might be a single point; only call it empty when clear.
        let scale = (g * g).max((a * j).abs());
        if -discriminant > 8.0 * EPS * scale {
            return None;
        }
        let centre = -g / a;
        return Some((centre, centre));
    }
    // Roots without cancellation: t = −(g + sign(g) √D), roots t / a and j / t.
    let root = discriminant.sqrt();
    let t = -(g + root.copysign(g));
    let (r1, r2) = if t == 0.0 { (0.0, 0.0) } else { (t / a, j / t) };
    let spread = 16.0 * EPS * (r1.abs().max(r2.abs())) + root.abs() / a * 1e-12;
    Some((r1.min(r2) - spread, r1.max(r2) + spread))
}

/// The box of an ellipsoid `xᵀAx + 2lᵀx + j ≤ 0` with positive definite `A`: centre
/// `c = −A⁻¹l`, extent `sqrt(r² (A⁻¹)_ii)` with `r² = −q(c)`.
fn ellipsoid_bounds(q: &Quadric) -> Aabb {
    let a = q.matrix_a();
    let a = qcsg_quadric::DMat4::from_cols_array(&[
        a[0][0], a[1][0], a[2][0], 0.0, a[0][1], a[1][1], a[2][1], 0.0, a[0][2], a[1][2], a[2][2],
        0.0, 0.0, 0.0, 0.0, 1.0,
    ]);
    let inverse = a.inverse();
    if !inverse.is_finite() {
        return Aabb::EVERYTHING;
    }
    let centre = -(inverse.transform_vector3(q.linear()));
    let r2 = -q.value_local(centre);
    if !r2.is_finite() {
        return Aabb::EVERYTHING;
    }
    if r2 < 0.0 {
        let (_, error) = q.value_with_error(q.origin() + centre);
        if -r2 > error {
            return Aabb::EMPTY;
        }
    }
    let r2 = r2.max(0.0);
    let half = DVec3::new(
        (r2 * inverse.x_axis.x.abs()).sqrt(),
        (r2 * inverse.y_axis.y.abs()).sqrt(),
        (r2 * inverse.z_axis.z.abs()).sqrt(),
    );
    let world_centre = q.origin() + centre;
    Aabb::from_centre_half(world_centre, half).widened_by(EXTENT_MARGIN)
}

/// Classifies the solid `q ≤ 0` against a closed box by two independent proofs: the
/// conservative distance from the box centre against the distance to its farthest corner
/// (tight for curved and rotated quadrics), then interval evaluation of `q` over the box (exact
/// per axis for the square and linear terms, so axis-aligned slabs and planes are decided
/// exactly). Both are rigorous, so the order does not change the answer; the distance, a few
/// dozen instructions against the interval's few hundred, decides most boxes away from the
/// surface.
pub fn classify(q: &Quadric, bounds: &Aabb) -> BoxClass {
    if bounds.is_empty() {
        return BoxClass::Inside;
    }
    if bounds.is_bounded() {
        let centre = bounds.centre();
        let distance = q.conservative_distance(centre);
        // The computed centre is off the true one by the rounding of its coordinates.
        let radius = bounds.half_diagonal() + 2.0 * f64::EPSILON * centre.abs().max_element();
        if distance > radius {
            return BoxClass::Outside;
        }
        if -distance > radius {
            return BoxClass::Inside;
        }
    }
    if let Some((lo, hi)) = value_range(q, bounds) {
        if lo > 0.0 {
            return BoxClass::Outside;
        }
        if hi < 0.0 {
            return BoxClass::Inside;
        }
    }
    BoxClass::Cuts
}

/// A rigorous enclosure `[lo, hi]` of `q` over the box (rounding included); `None` if it cannot
/// be formed (an infinite box along an axis the quadric depends on yields infinite ends, which
/// is still returned; `None` only for degenerate input).
pub fn value_range(q: &Quadric, bounds: &Aabb) -> Option<(f64, f64)> {
    coefficient_range(q.origin(), &q.coefficients(), bounds)
}

/// [`value_range`] of the quadric with `coefficients` about `origin` (as
/// [`Quadric::coefficients`] orders them), for a caller that has no [`Quadric`] and needs none:
/// building one finds the eigenvalues of its square part, which the range does not use.
pub fn coefficient_range(
    origin: DVec3,
    coefficients: &[f64; 10],
    bounds: &Aabb,
) -> Option<(f64, f64)> {
    let mut x = [(0.0, 0.0); 3];
    for (axis, interval) in x.iter_mut().enumerate() {
        let (lo, hi) = (bounds.min[axis], bounds.max[axis]);
        if lo.is_nan() || hi.is_nan() || lo == f64::INFINITY || hi == f64::NEG_INFINITY {
            return None;
        }
        // The subtraction rounds; widen by an ulp-scale margin.
        let (a, b) = (lo - origin[axis], hi - origin[axis]);
        let pad = |v: f64, w: f64| 2.0 * EPS * v.abs().max(w.abs());
        *interval = (a - pad(a, lo), b + pad(b, hi));
    }
    let [a00, a11, a22, a01, a02, a12, l0, l1, l2, j] = *coefficients;
    let a = [[a00, a01, a02], [a01, a11, a12], [a02, a12, a22]];
    let l = [l0, l1, l2];
    let mut lo = j;
    let mut hi = j;
    let mut magnitude = j.abs();
    for axis in 0..3 {
        let (flo, fhi) = quadratic_range(a[axis][axis], l[axis], x[axis]);
        lo += flo;
        hi += fhi;
        let m = x[axis].0.abs().max(x[axis].1.abs());
        magnitude +=
            bound_product(a[axis][axis].abs(), m * m) + bound_product(2.0 * l[axis].abs(), m);
    }
    for (r, c) in [(0, 1), (0, 2), (1, 2)] {
        let coefficient = 2.0 * a[r][c];
        if coefficient == 0.0 {
            continue;
        }
        let (plo, phi) = interval_product(x[r], x[c]);
        let (plo, phi) = scale_interval(coefficient, plo, phi);
        lo += plo;
        hi += phi;
        let mr = x[r].0.abs().max(x[r].1.abs());
        let mc = x[c].0.abs().max(x[c].1.abs());
        magnitude += bound_product(coefficient.abs(), bound_product(mr, mc));
    }
    if lo.is_nan() || hi.is_nan() {
        return None;
    }
    let error = 32.0 * EPS * magnitude;
    Some((lo - error, hi + error))
}

/// The exact range of `a x² + 2 g x` over `[lo, hi]` (ends may be infinite).
fn quadratic_range(a: f64, g: f64, (lo, hi): (f64, f64)) -> (f64, f64) {
    let f = |x: f64| -> f64 {
        if x.is_infinite() {
            if a != 0.0 {
                return f64::INFINITY.copysign(a);
            }
            if g != 0.0 {
                return f64::INFINITY.copysign(g * x.signum());
            }
            return 0.0;
        }
        (a * x + 2.0 * g) * x
    };
    // Each end once. No value is NaN (finite coefficients; infinite ends are taken above), so
    // plain comparisons stand for `f64::min` and `max`, which test for NaN.
    let (at_lo, at_hi) = (f(lo), f(hi));
    let (mut min, mut max) = if at_lo <= at_hi {
        (at_lo, at_hi)
    } else {
        (at_hi, at_lo)
    };
    if a != 0.0 {
        let vertex = -g / a;
        if vertex > lo && vertex < hi {
            let v = f(vertex);
            if v < min {
                min = v;
            }
            if v > max {
                max = v;
            }
        }
    }
    (min, max)
}

fn bound_product(x: f64, y: f64) -> f64 {
    crate::bounds::bound_product(x, y)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sphere_and_slab_bounds() {
        let s = Quadric::sphere(DVec3::new(10.0, 0.0, 0.0), 2.0).unwrap();
        let b = solid_bounds(&s);
        assert!((b.min - DVec3::new(8.0, -2.0, -2.0)).abs().max_element() < 1e-6);
        assert!(b.contains_box(&Aabb::new(
            DVec3::new(8.0, -2.0, -2.0),
            DVec3::new(12.0, 2.0, 2.0)
        )));
        let slab = Quadric::slab(DVec3::new(0.0, 3.0, 0.0), DVec3::Y, 1.0).unwrap();
        let b = solid_bounds(&slab);
        assert!(b.is_axis_bounded(1) && !b.is_axis_bounded(0) && !b.is_axis_bounded(2));
        assert!(b.min.y <= 2.0 && b.max.y >= 4.0 && b.min.y > 1.99);
        assert!(!solid_bounds(&slab.negated()).is_axis_bounded(1));
    }

    #[test]
    fn complement_of_a_slab_clips_boxes() {
        let slab = Quadric::slab(DVec3::new(0.0, 3.0, 0.0), DVec3::Y, 1.0).unwrap();
        let (axis, low, high) = excluded_interval(&slab.negated()).unwrap();
        assert_eq!(axis, 1);
        assert!(low > 2.0 && low < 2.0 + 1e-6 && high < 4.0 && high > 4.0 - 1e-6);
        assert!(excluded_interval(&slab).is_none());
        let b = Aabb::new(DVec3::ZERO, DVec3::new(1.0, 3.0, 1.0));
        let clipped = clip_outside_interval(&b, axis, low, high);
        assert!(clipped.max.y <= 2.0 + 1e-6 && clipped.max.y >= 2.0);
        let inside = Aabb::new(DVec3::new(0.0, 2.5, 0.0), DVec3::new(1.0, 3.5, 1.0));
        assert!(clip_outside_interval(&inside, axis, low, high).is_empty());
    }

    #[test]
    fn classification() {
        let unit = Aabb::new(DVec3::ZERO, DVec3::ONE);
        let slab = Quadric::slab(DVec3::ZERO, DVec3::X, 5.0).unwrap();
        assert_eq!(classify(&slab, &unit), BoxClass::Inside);
        assert_eq!(classify(&slab.negated(), &unit), BoxClass::Outside);
        let far = Quadric::sphere(DVec3::splat(10.0), 1.0).unwrap();
        assert_eq!(classify(&far, &unit), BoxClass::Outside);
        let cutting = Quadric::sphere(DVec3::ZERO, 1.0).unwrap();
        assert_eq!(classify(&cutting, &unit), BoxClass::Cuts);
        let half_infinite = Aabb::new(
            DVec3::new(-1.0, f64::NEG_INFINITY, 0.0),
            DVec3::new(1.0, 0.0, f64::INFINITY),
        );
        assert_eq!(classify(&slab, &half_infinite), BoxClass::Inside);
    }
}
