//! Sampling-plane heightfields (paper eq. 7) and their distortion (eq. 13, §3.4).
//!
//! For the sampling plane `P_ij` through the centre, spanned by principal axes `u_i, u_j`, with
//! normal axis `u_k` (`(i, j, k)` cyclic), the canonical form
//! `λ_i x² + λ_j y² + λ_k t² + 2 m·(x, y, t) + κ = 0` gives the surface as a heightfield over the
//! plane:
//! - `λ_k ≠ 0`: `t = ±√(α_x x² + α_y y² + 2β_x x + 2β_y y + α_c)` with `α_x = −λ_i/λ_k`,
//!   `α_y = −λ_j/λ_k`, `α_c = −κ/λ_k` (eq. 7) and `β = −m/λ_k` (non-zero only in planes that
//!   hold a paraboloid's axis);
//! - `λ_k = 0`, `m_k ≠ 0` (paraboloids seen along their axis, planes): a polynomial
//!   `t = γ_x x² + γ_y y² + γ_c`;
//! - `λ_k = 0`, `m_k = 0`: the surface is ruled along `u_k` (cylinders), no heightfield.

use glam::DVec3;

use crate::frame::PrincipalFrame;

/// The heightfield of a quadric over one sampling plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Heightfield {
    /// Index `k` of the principal axis normal to the plane.
    pub normal_axis: usize,
    /// Indices `(i, j)` of the axes spanning the plane (the heightfield's `x` and `y`).
    pub plane_axes: (usize, usize),
    /// The height function.
    pub form: HeightfieldForm,
}

/// The height function `t(x, y)` over a sampling plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum HeightfieldForm {
    /// `t = ±√S`, `S = α_x x² + α_y y² + 2β_x x + 2β_y y + α_c` (eq. 7; `β = 0` for central quadrics).
    Root {
        /// `α_x = −λ_i / λ_k`.
        alpha_x: f64,
        /// `α_y = −λ_j / λ_k`.
        alpha_y: f64,
        /// `α_c = −κ / λ_k = (qᵀb − c) / λ_k`.
        alpha_c: f64,
        /// `β_x = −m_i / λ_k`.
        beta_x: f64,
        /// `β_y = −m_j / λ_k`.
        beta_y: f64,
    },
    /// `t = γ_x x² + γ_y y² + γ_c`, a single sheet.
    Polynomial {
        /// `γ_x = −λ_i / 2m_k`.
        gamma_x: f64,
        /// `γ_y = −λ_j / 2m_k`.
        gamma_y: f64,
        /// `γ_c = −κ / 2m_k`.
        gamma_c: f64,
    },
    /// Lines parallel to the normal axis lie in the surface or miss it: no heightfield.
    Ruled,
}

impl PrincipalFrame {
    /// The heightfield over the sampling plane normal to axis `normal_axis` (taken modulo 3).
    pub fn heightfield(&self, normal_axis: usize) -> Heightfield {
        let k = normal_axis % 3;
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        let (lambda, m) = (self.eigenvalues, self.linear);
        let form = if lambda[k] != 0.0 {
            HeightfieldForm::Root {
                alpha_x: -lambda[i] / lambda[k],
                alpha_y: -lambda[j] / lambda[k],
                alpha_c: -self.constant / lambda[k],
                beta_x: -m[i] / lambda[k],
                beta_y: -m[j] / lambda[k],
            }
        } else if m[k] != 0.0 {
            let d = -2.0 * m[k];
            HeightfieldForm::Polynomial {
                gamma_x: lambda[i] / d,
                gamma_y: lambda[j] / d,
                gamma_c: self.constant / d,
            }
        } else {
            HeightfieldForm::Ruled
        };
        Heightfield {
            normal_axis: k,
            plane_axes: (i, j),
            form,
        }
    }

    /// The three heightfields, indexed by normal axis.
    pub fn heightfields(&self) -> [Heightfield; 3] {
        [0, 1, 2].map(|k| self.heightfield(k))
    }

    /// The world point at plane coordinates `(x, y)` and height `t` over the plane normal to
    /// `heightfield.normal_axis`.
    pub fn heightfield_point(&self, heightfield: &Heightfield, x: f64, y: f64, t: f64) -> DVec3 {
        let (i, j) = heightfield.plane_axes;
        self.centre + x * self.axes[i] + y * self.axes[j] + t * self.axes[heightfield.normal_axis]
    }
}

impl Heightfield {
    /// The radicand `S(x, y)` of a [`HeightfieldForm::Root`] heightfield; `None` otherwise.
    /// Exact to a few `u` of its terms `|α_x| x² + |α_y| y² + 2|β_x x| + 2|β_y y| + |α_c|`.
    pub fn radicand(&self, x: f64, y: f64) -> Option<f64> {
        match self.form {
            HeightfieldForm::Root {
                alpha_x,
                alpha_y,
                alpha_c,
                beta_x,
                beta_y,
            } => {
                Some((alpha_x * x + 2.0 * beta_x) * x + (alpha_y * y + 2.0 * beta_y) * y + alpha_c)
            }
            _ => None,
        }
    }

    /// The height `h(x, y)` (the non-negative branch for [`HeightfieldForm::Root`]); `None` where
    /// the line through `(x, y)` misses the surface or the surface is ruled. The tests check that
    /// `centre + x u_i + y u_j ± h u_k` lies on the surface to `1e-9` of `|∇Q|` times its distance
    /// from the origin, and to `1e-9` of the radius on a far, small sphere; near the rim (`S → 0`)
    /// the height inherits the absolute error of `S` through the square root.
    pub fn height(&self, x: f64, y: f64) -> Option<f64> {
        match self.form {
            HeightfieldForm::Root { .. } => {
                let s = self.radicand(x, y)?;
                (s >= 0.0).then(|| s.sqrt())
            }
            HeightfieldForm::Polynomial {
                gamma_x,
                gamma_y,
                gamma_c,
            } => Some(gamma_x * x * x + gamma_y * y * y + gamma_c),
            HeightfieldForm::Ruled => None,
        }
    }

    /// The squared slope `|∇h|²` numerator and denominator: `δ² = 1 + num / den`.
    fn slope_parts(&self, x: f64, y: f64) -> Option<(f64, f64)> {
        match self.form {
            HeightfieldForm::Root {
                alpha_x,
                alpha_y,
                beta_x,
                beta_y,
                ..
            } => {
                let s = self.radicand(x, y)?;
                if s < 0.0 {
                    return None;
                }
                let gx = alpha_x * x + beta_x;
                let gy = alpha_y * y + beta_y;
                Some((gx * gx + gy * gy, s))
            }
            HeightfieldForm::Polynomial {
                gamma_x, gamma_y, ..
            } => {
                let gx = 2.0 * gamma_x * x;
                let gy = 2.0 * gamma_y * y;
                Some((gx * gx + gy * gy, 1.0))
            }
            HeightfieldForm::Ruled => None,
        }
    }

    /// The distortion `δ(x, y) = |n| / |n_k| ≥ 1` of eq. 13: how much a small patch of the plane
    /// grows when projected onto the surface. `None` where the heightfield is undefined;
    /// `+∞` on the rim (`S = 0` with non-zero slope). Relative error a few ulps.
    pub fn distortion(&self, x: f64, y: f64) -> Option<f64> {
        let (num, den) = self.slope_parts(x, y)?;
        if num == 0.0 {
            return Some(1.0);
        }
        if den == 0.0 {
            return Some(f64::INFINITY);
        }
        Some((1.0 + num / den).sqrt())
    }

    /// Bounds `(min, max)` of the distortion over the rectangle `[x0, x1] × [y0, y1]` (§3.4).
    ///
    /// Within a quadrant the extrema lie at the corners (paper §3.4; for the `β ≠ 0` and
    /// polynomial forms `δ` is monotone in `x` and in `y²` separately); a rectangle crossing an
    /// axis is split there, so the candidates are the corners plus the points where the edges
    /// cross the axes (valid for the forms that [`PrincipalFrame::heightfield`] produces, where
    /// `β` is non-zero only beside a zero `α`). `None` if the heightfield is undefined anywhere in
    /// the rectangle (its
    /// radicand is linear in `(x², y²)` or `(x, y²)`, so the corner candidates decide this too).
    /// Exact up to the rounding of [`Self::distortion`]; the tests check it against dense
    /// sampling.
    pub fn distortion_bounds(&self, x: (f64, f64), y: (f64, f64)) -> Option<(f64, f64)> {
        let (xs, nx) = candidates(x);
        let (ys, ny) = candidates(y);
        // Track the extremes of |∇h|² and take the two square roots at the end.
        let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
        for &cx in &xs[..nx] {
            for &cy in &ys[..ny] {
                let slope = self.slope_squared(cx, cy)?;
                lo = lo.min(slope);
                hi = hi.max(slope);
            }
        }
        Some(((1.0 + lo).sqrt(), (1.0 + hi).sqrt()))
    }

    /// `|∇h|² = δ² − 1` at `(x, y)`, rounded exactly as [`Self::distortion_bounds`] rounds it at
    /// its candidates: over a rectangle inside one quadrant the bound is `√(1 + max)` of the
    /// corners' values, so a subdivision that keeps its corners' values needs no more. `None`
    /// where the heightfield is undefined (or ruled).
    #[inline]
    pub fn slope_squared(&self, x: f64, y: f64) -> Option<f64> {
        let (num, den) = match self.form {
            HeightfieldForm::Root {
                alpha_x,
                alpha_y,
                alpha_c,
                beta_x,
                beta_y,
            } => {
                let s =
                    (alpha_x * x + 2.0 * beta_x) * x + alpha_c + (alpha_y * y + 2.0 * beta_y) * y;
                if s < 0.0 {
                    return None;
                }
                let (gx, gy) = (alpha_x * x + beta_x, alpha_y * y + beta_y);
                (gx * gx + gy * gy, s)
            }
            HeightfieldForm::Polynomial {
                gamma_x, gamma_y, ..
            } => (
                (2.0 * gamma_x * x).powi(2) + (2.0 * gamma_y * y).powi(2),
                1.0,
            ),
            HeightfieldForm::Ruled => return None,
        };
        Some(if num == 0.0 { 0.0 } else { num / den })
    }
}

/// The ends of an interval plus zero if it lies strictly inside, and how many there are.
#[inline]
fn candidates((a, b): (f64, f64)) -> ([f64; 3], usize) {
    let (lo, hi) = (a.min(b), a.max(b));
    if lo < 0.0 && hi > 0.0 {
        ([lo, hi, 0.0], 3)
    } else {
        ([lo, hi, 0.0], 2)
    }
}
