//! Axis-aligned boxes that may be infinite per axis, and their conservative transforms.
//!
//! Boxes are only ever used as supersets of a solid (or of a term of its DNF), so every
//! operation here rounds outwards: a transformed box contains the image of the box, never less.
//! Nothing here produces NaN: `0 · ∞` is taken as `0` (a transform that does not mix an
//! infinite axis into another keeps that axis out of it).

use qcsg_quadric::{DMat4, DVec3};
use serde::Serialize;

/// An axis-aligned box `[min, max]`, possibly infinite per axis; empty when `min > max` on any
/// axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// The lower corner (may hold `-∞`).
    pub min: DVec3,
    /// The upper corner (may hold `+∞`).
    pub max: DVec3,
}

/// Relative outward margin that absorbs the rounding of box arithmetic.
const ROUNDING_MARGIN: f64 = 4.0 * f64::EPSILON;

impl Aabb {
    /// All of space.
    pub const EVERYTHING: Aabb = Aabb {
        min: DVec3::NEG_INFINITY,
        max: DVec3::INFINITY,
    };

    /// The empty box.
    pub const EMPTY: Aabb = Aabb {
        min: DVec3::INFINITY,
        max: DVec3::NEG_INFINITY,
    };

    /// The box `[min, max]`. A NaN coordinate is read as unbounded on that side, so the result
    /// is always a valid superset.
    pub fn new(min: DVec3, max: DVec3) -> Self {
        let fix = |v: DVec3, fallback: f64| {
            DVec3::from_array(v.to_array().map(|c| if c.is_nan() { fallback } else { c }))
        };
        Self {
            min: fix(min, f64::NEG_INFINITY),
            max: fix(max, f64::INFINITY),
        }
    }

    /// The box with centre `centre` and half extents `half`.
    pub fn from_centre_half(centre: DVec3, half: DVec3) -> Self {
        Self::new(centre - half, centre + half)
    }

    /// Whether the box holds no point.
    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x || self.min.y > self.max.y || self.min.z > self.max.z
    }

    /// Whether the box is finite on every axis (the empty box counts as bounded).
    pub fn is_bounded(&self) -> bool {
        self.is_empty() || (self.min.is_finite() && self.max.is_finite())
    }

    /// Whether axis `axis` (0, 1, 2) is bounded on both sides.
    pub fn is_axis_bounded(&self, axis: usize) -> bool {
        self.min[axis].is_finite() && self.max[axis].is_finite()
    }

    /// The common part of two boxes.
    pub fn intersection(&self, other: &Aabb) -> Aabb {
        Aabb {
            min: self.min.max(other.min),
            max: self.max.min(other.max),
        }
    }

    /// The smallest box holding both.
    pub fn union(&self, other: &Aabb) -> Aabb {
        if self.is_empty() {
            return *other;
        }
        if other.is_empty() {
            return *self;
        }
        Aabb {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }

    /// The box grown by `margin` on every side; an empty box stays empty.
    pub fn expanded(&self, margin: f64) -> Aabb {
        if self.is_empty() {
            return *self;
        }
        Aabb::new(self.min - margin, self.max + margin)
    }

    /// The Euclidean gap between the boxes: 0 where they touch or overlap, `+∞` if either is
    /// empty.
    pub fn gap(&self, other: &Aabb) -> f64 {
        if self.is_empty() || other.is_empty() {
            return f64::INFINITY;
        }
        let gap = (self.min - other.max)
            .max(other.min - self.max)
            .max(DVec3::ZERO);
        let gap = gap.length();
        if gap.is_nan() { 0.0 } else { gap }
    }

    /// Whether the boxes share a point (closed boxes).
    pub fn intersects(&self, other: &Aabb) -> bool {
        !self.intersection(other).is_empty()
    }

    /// Whether `p` lies in the closed box.
    pub fn contains(&self, p: DVec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }

    /// Whether `other` lies inside `self`.
    pub fn contains_box(&self, other: &Aabb) -> bool {
        other.is_empty() || (other.min.cmpge(self.min).all() && other.max.cmple(self.max).all())
    }

    /// The centre of a finite, non-empty box.
    pub fn centre(&self) -> DVec3 {
        0.5 * self.min + 0.5 * self.max
    }

    /// Half the length of the diagonal of a finite box (rounded up slightly).
    pub fn half_diagonal(&self) -> f64 {
        let half = 0.5 * (self.max - self.min);
        half.length() * (1.0 + ROUNDING_MARGIN)
    }

    /// The box grown outwards by a few ulps of its magnitude on every side.
    pub fn widened(&self) -> Aabb {
        self.widened_by(ROUNDING_MARGIN)
    }

    /// The box grown outwards on every side by `relative` times its own scale (its largest
    /// finite extent), plus a few ulps of each coordinate for the rounding of the bounds
    /// themselves. The margin depends on the box's size, not on its distance from the origin:
    /// a unit box far away grows by as little as the same box at the origin, up to rounding.
    pub fn widened_by(&self, relative: f64) -> Aabb {
        if self.is_empty() {
            return *self;
        }
        let scale = (0..3)
            .filter(|&axis| self.is_axis_bounded(axis))
            .map(|axis| self.max[axis] - self.min[axis])
            .fold(0.0, f64::max);
        let size_margin = relative * scale;
        let grow = |v: f64| {
            if v.is_finite() {
                size_margin + ROUNDING_MARGIN * v.abs()
            } else {
                0.0
            }
        };
        Aabb {
            min: DVec3::from_array(self.min.to_array().map(|v| v - grow(v))),
            max: DVec3::from_array(self.max.to_array().map(|v| v + grow(v))),
        }
    }

    /// A box holding the image of this box under `m` (points map as `p' = M p`).
    ///
    /// Affine maps use interval arithmetic per output axis (exact for boxes up to rounding,
    /// equivalent to transforming the eight corners); an input axis that is infinite and mixed
    /// into an output axis makes that output axis infinite. A projective map whose `w` keeps
    /// one sign over a finite box maps it into the hull of its corners' images; otherwise the
    /// result is all of space.
    pub fn transformed(&self, m: &DMat4) -> Aabb {
        if self.is_empty() {
            return *self;
        }
        if *m == DMat4::IDENTITY {
            return *self;
        }
        if !m.is_finite() {
            return Aabb::EVERYTHING;
        }
        let row3 = m.row(3);
        let affine = row3.x == 0.0 && row3.y == 0.0 && row3.z == 0.0 && row3.w != 0.0;
        if affine {
            let w = row3.w;
            let mut min = [0.0; 3];
            let mut max = [0.0; 3];
            for axis in 0..3 {
                let row = m.row(axis);
                let mut lo = row.w;
                let mut hi = row.w;
                for k in 0..3 {
                    let (a, b) = scale_interval(row[k], self.min[k], self.max[k]);
                    lo += a;
                    hi += b;
                }
                let (lo, hi) = scale_interval(1.0 / w, lo, hi);
                min[axis] = lo;
                max[axis] = hi;
            }
            return Aabb::new(DVec3::from_array(min), DVec3::from_array(max)).widened();
        }
        if !self.is_bounded() {
            return Aabb::EVERYTHING;
        }
        let mut result = Aabb::EMPTY;
        let mut sign = 0.0f64;
        for corner in self.corners() {
            let image = *m * corner.extend(1.0);
            if image.w == 0.0 || (sign != 0.0 && image.w.signum() != sign) {
                return Aabb::EVERYTHING;
            }
            sign = image.w.signum();
            let point = image.truncate() / image.w;
            if !point.is_finite() {
                return Aabb::EVERYTHING;
            }
            result = result.union(&Aabb::new(point, point));
        }
        result.widened()
    }

    /// The eight corners of a finite box.
    pub fn corners(&self) -> [DVec3; 8] {
        std::array::from_fn(|i| {
            DVec3::new(
                if i & 1 == 0 { self.min.x } else { self.max.x },
                if i & 2 == 0 { self.min.y } else { self.max.y },
                if i & 4 == 0 { self.min.z } else { self.max.z },
            )
        })
    }

    /// The coordinates as plain arrays, for output (negative zeros written as zeros).
    pub fn to_arrays(&self) -> BoundsJson {
        BoundsJson {
            min: self.min.to_array().map(|v| v + 0.0),
            max: self.max.to_array().map(|v| v + 0.0),
        }
    }

    /// Bit patterns of the six coordinates, for exact hashing.
    pub(crate) fn bits(&self) -> [u64; 6] {
        let [a, b, c] = self.min.to_array();
        let [d, e, f] = self.max.to_array();
        [a, b, c, d, e, f].map(f64::to_bits)
    }
}

/// A box as it appears in JSON: `{"min": [x, y, z], "max": [x, y, z]}`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct BoundsJson {
    /// The lower corner.
    pub min: [f64; 3],
    /// The upper corner.
    pub max: [f64; 3],
}

/// `s · [lo, hi]` as an interval, with `0 · ∞ = 0`.
pub(crate) fn scale_interval(s: f64, lo: f64, hi: f64) -> (f64, f64) {
    if s == 0.0 {
        return (0.0, 0.0);
    }
    let (a, b) = (s * lo, s * hi);
    if a <= b { (a, b) } else { (b, a) }
}

/// `x · y` for interval bounds, with `0 · ∞ = 0` (the limit inside a closed interval).
pub(crate) fn bound_product(x: f64, y: f64) -> f64 {
    if x == 0.0 || y == 0.0 { 0.0 } else { x * y }
}

/// The product of two intervals.
pub(crate) fn interval_product(a: (f64, f64), b: (f64, f64)) -> (f64, f64) {
    let candidates = [
        bound_product(a.0, b.0),
        bound_product(a.0, b.1),
        bound_product(a.1, b.0),
        bound_product(a.1, b.1),
    ];
    let lo = candidates.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = candidates.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    (lo, hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotation_by_90_degrees_keeps_boxes_exact() {
        let b = Aabb::new(DVec3::new(0.0, 1.0, 2.0), DVec3::new(1.0, 3.0, 4.0));
        let rot = DMat4::from_cols_array(&[
            0.0, 1.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
        ]);
        let t = b.transformed(&rot);
        assert!(t.contains_box(&Aabb::new(
            DVec3::new(-3.0, 0.0, 2.0),
            DVec3::new(-1.0, 1.0, 4.0)
        )));
        assert!((t.min - DVec3::new(-3.0, 0.0, 2.0)).abs().max_element() < 1e-14);
    }

    #[test]
    fn infinite_axes_do_not_leak_into_unmixed_axes() {
        let slab = Aabb::new(
            DVec3::new(-1.0, f64::NEG_INFINITY, f64::NEG_INFINITY),
            DVec3::new(1.0, f64::INFINITY, f64::INFINITY),
        );
        let t = slab.transformed(&DMat4::from_translation(DVec3::new(5.0, 0.0, 0.0)));
        assert!(t.is_axis_bounded(0) && !t.is_axis_bounded(1));
        assert!(!t.min.is_nan() && !t.max.is_nan());
        let rotated = slab.transformed(&DMat4::from_rotation_z(0.3));
        assert!(!rotated.is_axis_bounded(0) && !rotated.min.is_nan());
    }

    #[test]
    fn widening_follows_the_box_size_not_its_distance_from_the_origin() {
        let unit = Aabb::new(DVec3::ZERO, DVec3::ONE);
        for offset in [0.0, 1e3, 1e6, -1e9] {
            let shift = DVec3::splat(offset);
            let far = Aabb::new(unit.min + shift, unit.max + shift);
            let wide = far.widened_by(1e-6);
            assert!(wide.contains_box(&far));
            for axis in 0..3 {
                let grown_low = far.min[axis] - wide.min[axis];
                let grown_high = wide.max[axis] - far.max[axis];
                // 1e-6 of the unit size, plus rounding of coordinates of magnitude |offset|.
                let bound = 1e-6 + 16.0 * f64::EPSILON * (offset.abs() + 1.0);
                assert!(
                    grown_low >= 1e-6 * 0.999 && grown_low <= bound,
                    "{offset}: {grown_low}"
                );
                assert!(
                    grown_high >= 1e-6 * 0.999 && grown_high <= bound,
                    "{offset}: {grown_high}"
                );
            }
        }
        // A big box grows with its largest extent on every axis.
        let slab = Aabb::new(DVec3::new(0.0, 0.0, 5.0), DVec3::new(100.0, 1.0, 5.0));
        let wide = slab.widened_by(1e-3);
        assert!((slab.min.z - wide.min.z - 0.1).abs() < 1e-9);
        // Infinite sides stay infinite and nothing becomes NaN.
        let half_space = Aabb::new(
            DVec3::new(1e8, f64::NEG_INFINITY, 0.0),
            DVec3::new(1e8 + 2.0, 0.0, f64::INFINITY),
        );
        let wide = half_space.widened_by(1e-3);
        assert_eq!(wide.min.y, f64::NEG_INFINITY);
        assert_eq!(wide.max.z, f64::INFINITY);
        assert!((half_space.min.x - wide.min.x - 2e-3).abs() < 1e-6);
        assert!(!wide.min.is_nan() && !wide.max.is_nan());
    }

    #[test]
    fn empty_and_everything() {
        assert!(Aabb::EMPTY.is_empty() && Aabb::EMPTY.is_bounded());
        assert!(!Aabb::EVERYTHING.is_bounded());
        assert!(
            Aabb::EMPTY
                .transformed(&DMat4::from_rotation_x(1.0))
                .is_empty()
        );
    }
}
