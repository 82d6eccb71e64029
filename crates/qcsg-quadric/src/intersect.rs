//! Line and ray intersection (paper eqs. 5-6) with a cancellation-free quadratic formula.
//!
//! Along `p + t v`, `Q = α t² + 2β t + γ` with `α = vᵀAv`, `β = vᵀ(A x + l)`, `γ = Q(x)`,
//! `x = p − origin`. The roots are computed as `r = −(β + sign(β) √D)`, `t = r/α` and `t = γ/r`,
//! which never subtracts nearly equal numbers; as `α → 0` the second root tends continuously to
//! the linear root `−γ / 2β` (eq. 6) and the first leaves to infinity, where it is dropped.

use glam::DVec3;

use crate::quadric::{EPS, Quadric};

/// The intersection of a line with a quadric surface, parameters ascending.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LineIntersection {
    /// The line misses the surface.
    None,
    /// One transversal crossing (the quadratic is linear along this line, or its other root is
    /// beyond the range of f64).
    One(f64),
    /// The line touches the surface at a double root without crossing it.
    Tangent(f64),
    /// Two crossings, `t0 < t1`.
    Two(f64, f64),
    /// The whole line lies in the surface.
    Contained,
}

impl LineIntersection {
    /// The finite roots, ascending (a tangent root once).
    pub fn roots(&self) -> Vec<f64> {
        match *self {
            Self::None | Self::Contained => Vec::new(),
            Self::One(t) | Self::Tangent(t) => vec![t],
            Self::Two(t0, t1) => vec![t0, t1],
        }
    }

    /// The smallest root `≥ t_min`, e.g. the first hit of a ray (`t_min = 0`).
    pub fn first_at_or_after(&self, t_min: f64) -> Option<f64> {
        match *self {
            Self::None | Self::Contained => None,
            Self::One(t) | Self::Tangent(t) => (t >= t_min).then_some(t),
            Self::Two(t0, t1) => {
                if t0 >= t_min {
                    Some(t0)
                } else if t1 >= t_min {
                    Some(t1)
                } else {
                    None
                }
            }
        }
    }
}

impl Quadric {
    /// Intersects the line `p + t v` (`v ≠ 0`, not necessarily unit; `t` is in units of `‖v‖`).
    ///
    /// The discriminant `β² − αγ` is computed with a compensated product where it cancels
    /// (Kahan's trick), and is treated as zero — a [`LineIntersection::Tangent`] double root —
    /// when it lies within its rounding bound `16 ε (β² + |α| Γ)`, `Γ` being the magnitude of
    /// the terms of `γ`. Each returned root `t` satisfies
    /// `|Q(p + t v)| ≤ 1e-12 · M(t) + 4 ε |p + t v|_∞ |∇Q|` with `M` the magnitude of the terms of
    /// the polynomial at `t` (the second term is the rounding of forming the world point); tangent
    /// roots satisfy it with `1e-6` and are accurate to about `√ε` of the local feature size, as
    /// the problem is ill-posed there. The stiff suite checks roots to `1e-9` relative on spheres
    /// of radius `1e-6` to `1e6` at `1e6`, slabs of width `2e-6`, and lines within `1e-9` rad of
    /// a cylinder's axis (far root `±1e9`).
    pub fn intersect_line(&self, p: DVec3, v: DVec3) -> LineIntersection {
        self.intersect_line_with_value(p, v, self.value_with_error(p))
    }

    /// [`Self::intersect_line`] given `value`, which must be `self.value_with_error(p)`: a ray
    /// tracer whose rays all start at one eye computes it once per quadric for all of them.
    /// The result is the same, bit for bit, as that of `intersect_line(p, v)`.
    pub fn intersect_line_with_value(
        &self,
        p: DVec3,
        v: DVec3,
        value: (f64, f64),
    ) -> LineIntersection {
        let x = p - self.origin();
        let av = self.apply_a(v);
        let alpha = v.dot(av);
        let beta = av.dot(x) + self.linear().dot(v);
        let (gamma, gamma_error) = value;
        let gamma_terms = gamma_error / (16.0 * EPS);
        if !(alpha.is_finite() && beta.is_finite() && gamma.is_finite()) {
            return LineIntersection::None;
        }

        if alpha == 0.0 {
            if beta == 0.0 {
                return if gamma == 0.0 {
                    LineIntersection::Contained
                } else {
                    LineIntersection::None
                };
            }
            let t = -gamma / (2.0 * beta);
            return if t.is_finite() {
                LineIntersection::One(t)
            } else {
                LineIntersection::None
            };
        }

        let discriminant = discriminant(alpha, beta, gamma);
        let noise = 16.0 * EPS * (beta * beta + alpha.abs() * gamma_terms);
        if discriminant.abs() <= noise {
            let t = -beta / alpha;
            if gamma == 0.0 && beta == 0.0 {
                return LineIntersection::Tangent(0.0);
            }
            return if t.is_finite() {
                LineIntersection::Tangent(t)
            } else {
                LineIntersection::None
            };
        }
        if discriminant < 0.0 {
            return LineIntersection::None;
        }
        let root = discriminant.sqrt();
        let r = -(beta + root.copysign(beta));
        let t_far = r / alpha;
        let t_near = gamma / r;
        match (t_far.is_finite(), t_near.is_finite()) {
            (true, true) => LineIntersection::Two(t_far.min(t_near), t_far.max(t_near)),
            (true, false) => LineIntersection::One(t_far),
            (false, true) => LineIntersection::One(t_near),
            (false, false) => LineIntersection::None,
        }
    }
}

/// `β² − αγ` with a compensated evaluation when the two products nearly cancel.
fn discriminant(alpha: f64, beta: f64, gamma: f64) -> f64 {
    let bb = beta * beta;
    let ag = alpha * gamma;
    let d = bb - ag;
    if 3.0 * d.abs() >= bb + ag.abs() || !d.is_finite() {
        return d;
    }
    let bb_error = beta.mul_add(beta, -bb);
    let ag_error = alpha.mul_add(gamma, -ag);
    d + (bb_error - ag_error)
}
