//! The conservative signed distance of paper §3.3 (eqs. 10-12).
//!
//! Along any unit direction `v`, `Q(x₀ + t v) = Q(x₀) + 2t (A x₀ − b)ᵀv + t² vᵀAv` is bounded by
//! `Q(x₀) ± 2t ‖A x₀ − b‖ + t² λ_max/min`; the first root of the bound that can reach zero is a
//! radius around `x₀` free of surface.

use glam::{BVec3, DVec3};

use crate::quadric::{EPS, Quadric};

impl Quadric {
    /// Conservative signed distance from the world point `p` to the surface (eq. 12): positive
    /// outside (`Q > 0`), negative inside, and `|d|` never exceeds the true Euclidean distance to
    /// the surface.
    ///
    /// The bound is rigorous in floating point, not just in exact arithmetic: the value's
    /// rounding error (see [`Quadric::value_with_error`]), the gradient's rounding error, the
    /// eigenvalue bounds ([`Quadric::eigenvalue_bounds`]) and the rounding of `p − origin` are all
    /// accounted for, so a point within rounding noise of the surface gets `±0.0`. Infinite when
    /// no surface point exists in the relevant direction (e.g. outside of an empty quadric); NaN
    /// only for non-finite `p`. The tests check `|d| ≤ true distance` on thousands of points around
    /// every kind (also transformed, and on extreme radii and translations), and
    /// `|d| ≥ (1 − 2·10⁻³) · true distance` within `10⁻³` of a sphere's radius from its surface
    /// (the relative error vanishes towards the surface, paper §3.3).
    #[inline]
    pub fn conservative_distance(&self, p: DVec3) -> f64 {
        let x = p - self.origin();
        if let Some(d) = self.aligned_distance(x) {
            return d;
        }
        let ax = self.apply_a(x);
        let l = self.linear();
        let half_gradient = ax + l;
        let value = x.dot(ax + 2.0 * l) + self.constant();

        let value_error = 16.0 * EPS * self.term_bound(x);
        let gradient_error = 8.0 * EPS * self.half_gradient_term_bound(x);

        let magnitude = value.abs() - value_error;
        if magnitude <= 0.0 {
            return 0.0f64.copysign(value);
        }
        let slope = half_gradient.length() + gradient_error;
        let (lower, upper) = self.eigenvalue_bounds();
        // Curvature that pushes the bound towards zero: λ_max inside, −λ_min outside.
        let curvature = if value < 0.0 { upper } else { -lower };
        let t = first_root(magnitude, slope, curvature);
        // Absorb the rounding of t itself and of p − origin.
        let t = (t * (1.0 - 8.0 * EPS) - 2.0 * EPS * x.abs().max_element()).max(0.0);
        t.copysign(value)
    }

    /// [`Self::conservative_distance`] at `x = p − origin` of a quadric with an
    /// [`AlignedForm`]: with `y` the part of `x` along its axes, `±(‖y‖ − R)`, the bound of
    /// eq. 12 there, without the general bound's two square roots and division. Its rounding
    /// (of `x`, `‖y‖` and `R`, each a few `u` of `‖y‖` or `R`) is taken off. `None` for any other
    /// quadric, and where `‖y‖²` could leave the range where that bound holds.
    #[inline]
    fn aligned_distance(&self, x: DVec3) -> Option<f64> {
        let form = self.aligned?;
        let length_squared = DVec3::select(form.axes, x, DVec3::ZERO).length_squared();
        (length_squared < 1e250).then(|| {
            let (length, radius) = (length_squared.sqrt(), form.radius);
            let outward = length - radius;
            let magnitude = outward.abs() - 8.0 * EPS * (length + radius);
            // Positive where `Q > 0`: outside the solid, inside its complement.
            let signed = if form.solid { outward } else { -outward };
            magnitude.max(0.0).copysign(signed)
        })
    }
}

/// A sphere, a circular cylinder or a slab about its origin and along the axes: `A` diagonal
/// with its non-zero entries all `k`, and `l = 0`, exactly, as `sphere`, `cylinder` and `cube`
/// make them (translations and uniform scalings keep the form). Found once per quadric, so that
/// each conservative distance to one takes a square root instead of three, and no division
/// (cached by [`Quadric`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct AlignedForm {
    /// The axes along which `A` is non-zero.
    axes: BVec3,
    /// `R = √(−j / k)`.
    radius: f64,
    /// `k > 0`: the solid is where `‖y‖ ≤ R` (else its complement).
    solid: bool,
}

impl AlignedForm {
    /// The form of the quadric with `coefficients`; `None` for any other quadric, and where
    /// `R²` lies outside `[1e-250, 1e250)`, where the squares of the short way could under- or
    /// overflow.
    pub(crate) fn of(coefficients: &[f64; 10]) -> Option<Self> {
        let [a, b, c, d, e, f, g, h, i, j] = *coefficients;
        if [d, e, f, g, h, i].iter().any(|&k| k != 0.0) {
            return None;
        }
        let k = [a, b, c].into_iter().find(|&v| v != 0.0)?;
        if [a, b, c].iter().any(|&v| v != 0.0 && v != k) {
            return None;
        }
        let radius_squared = -j / k;
        if !(1e-250..1e250).contains(&radius_squared) {
            return None;
        }
        Some(Self {
            axes: BVec3::new(a != 0.0, b != 0.0, c != 0.0),
            radius: radius_squared.sqrt(),
            solid: k > 0.0,
        })
    }

    /// The form of the negated quadric: the same surface, the solid swapped (`−j / −k` is
    /// `j / k` exactly).
    pub(crate) fn negated(self) -> Self {
        Self {
            solid: !self.solid,
            ..self
        }
    }
}

/// Smallest positive root of `magnitude − 2 slope t − curvature t² = 0`, written without
/// cancellation as `magnitude / (slope + sqrt(slope² + magnitude · curvature))`; infinite when
/// there is none.
#[inline]
fn first_root(magnitude: f64, slope: f64, curvature: f64) -> f64 {
    let discriminant = slope * slope + magnitude * curvature;
    // The fast path is exact to a few ulps unless the discriminant over- or underflows.
    let fast_path_safe = discriminant.is_finite() && discriminant.abs() >= f64::MIN_POSITIVE;
    if fast_path_safe {
        if discriminant < 0.0 {
            return f64::INFINITY;
        }
        return magnitude / (slope + discriminant.sqrt());
    }
    // Rare: squares under- or overflow. Scale to keep slope² and the product in range.
    let s = slope.max((magnitude * curvature.abs()).sqrt());
    if s == 0.0 {
        return f64::INFINITY;
    }
    if !s.is_finite() {
        return 0.0;
    }
    let slope_s = slope / s;
    let discriminant = slope_s * slope_s + (magnitude / s) * (curvature / s);
    if discriminant < 0.0 {
        return f64::INFINITY;
    }
    let denominator = slope_s + discriminant.sqrt();
    if denominator <= 0.0 {
        return f64::INFINITY;
    }
    (magnitude / s) / denominator
}
