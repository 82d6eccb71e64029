//! The [`Quadric`] type: ten coefficients relative to a local origin, evaluation, transforms.
//!
//! `q(x, y, z) = a x² + b y² + c z² + 2d xy + 2e xz + 2f yz + 2g x + 2h y + 2i z + j`, evaluated at
//! `p − origin`; the solid is `q ≤ 0`. In the paper's notation (eq. 2-3) `A` is the symmetric
//! matrix of `a…f`, `b_paper = −(g, h, i)` and `c_paper = j`.
//!
//! Keeping an origin near the geometry is what keeps the coefficients meaningful: a unit sphere
//! at 10⁶ stored about the world origin has `j ≈ 10¹²`, where its radius drowns in rounding.
//! Affine transforms map the origin along with the shape, so translations never touch the
//! coefficients at all.

use glam::{DMat3, DMat4, DVec3, DVec4};

use crate::distance::AlignedForm;
use crate::eigen::{Sym3, SymmetricEigen, power_of_two_reciprocal, symmetric_eigen};

/// Unit roundoff of f64.
pub(crate) const EPS: f64 = f64::EPSILON * 0.5;

/// A quadric surface `q(p − origin) = 0` bounding the solid `q(p − origin) ≤ 0`.
///
/// Besides the coefficients, a quadric caches rigorous bounds on the extreme eigenvalues of
/// its matrix `A` (used by the conservative distance, eqs. 10-11), and its aligned form where it
/// has one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quadric {
    origin: DVec3,
    coefficients: [f64; 10],
    /// A lower bound on the smallest eigenvalue of `A`.
    eigen_lower: f64,
    /// An upper bound on the largest eigenvalue of `A`.
    eigen_upper: f64,
    /// `Σ |A_rc|` over all nine entries, for cheap rounding-error bounds.
    abs_sum_a: f64,
    /// `Σ |l_k|`.
    abs_sum_l: f64,
    /// A sphere, circular cylinder or slab along the axes about the origin
    /// ([`AlignedForm`]), for the conservative distance's short way.
    pub(crate) aligned: Option<AlignedForm>,
}

impl Quadric {
    /// A quadric from its local origin and coefficients `[a, b, c, d, e, f, g, h, i, j]`, kept
    /// verbatim. `None` if any input is not finite.
    pub fn new(origin: DVec3, coefficients: [f64; 10]) -> Option<Self> {
        if !origin.is_finite() || coefficients.iter().any(|c| !c.is_finite()) {
            return None;
        }
        Some(Self::from_parts(origin, coefficients))
    }

    /// A quadric `xᵀ A x + 2 lᵀ x + j` about `origin`, from the matrix `A` (its symmetric part),
    /// the half-linear vector `l = (g, h, i)` and the constant `j`. `None` if not finite.
    pub fn from_matrix(origin: DVec3, a: &Sym3, l: DVec3, j: f64) -> Option<Self> {
        let s = |r: usize, c: usize| 0.5 * (a[r][c] + a[c][r]);
        Self::new(
            origin,
            [
                a[0][0],
                a[1][1],
                a[2][2],
                s(0, 1),
                s(0, 2),
                s(1, 2),
                l.x,
                l.y,
                l.z,
                j,
            ],
        )
    }

    /// Builds the quadric and its eigenvalue bounds; inputs must be finite.
    pub(crate) fn from_parts(origin: DVec3, coefficients: [f64; 10]) -> Self {
        let mut q = Self {
            origin,
            coefficients,
            eigen_lower: 0.0,
            eigen_upper: 0.0,
            abs_sum_a: 0.0,
            abs_sum_l: 0.0,
            aligned: None,
        };
        q.update_derived();
        let eigen = q.eigen();
        // Jacobi's absolute eigenvalue error is a few ulps of ‖A‖; widen by a safe margin.
        let margin = 32.0 * EPS * q.matrix_norm();
        q.eigen_lower = eigen.values[0] - margin;
        q.eigen_upper = eigen.values[2] + margin;
        q
    }

    /// The sums and the aligned form, from the coefficients.
    fn update_derived(&mut self) {
        let k = self.coefficients.map(f64::abs);
        self.abs_sum_a = k[0] + k[1] + k[2] + 2.0 * (k[3] + k[4] + k[5]);
        self.abs_sum_l = k[6] + k[7] + k[8];
        self.aligned = AlignedForm::of(&self.coefficients);
    }

    /// A bound on the magnitude of the terms of `Q` at the local vector `x`:
    /// `‖x‖∞² Σ|A_rc| + 2 ‖x‖∞ Σ|l_k| + |j| ≥ |x|ᵀ|A||x| + 2|l|ᵀ|x| + |j|`.
    #[inline]
    pub(crate) fn term_bound(&self, x: DVec3) -> f64 {
        let m = x.abs().max_element();
        (m * self.abs_sum_a + 2.0 * self.abs_sum_l) * m + self.coefficients[9].abs()
    }

    /// A bound on the magnitude of the terms of `A x + l`: `‖x‖∞ Σ|A_rc| + Σ|l_k|`, which bounds
    /// the 1-norm (hence the 2-norm) of `|A||x| + |l|`.
    #[inline]
    pub(crate) fn half_gradient_term_bound(&self, x: DVec3) -> f64 {
        x.abs().max_element() * self.abs_sum_a + self.abs_sum_l
    }

    /// The local origin in world coordinates.
    pub fn origin(&self) -> DVec3 {
        self.origin
    }

    /// The coefficients `[a, b, c, d, e, f, g, h, i, j]` relative to [`Self::origin`].
    pub fn coefficients(&self) -> [f64; 10] {
        self.coefficients
    }

    /// The symmetric matrix `A` (rows).
    pub fn matrix_a(&self) -> Sym3 {
        let [a, b, c, d, e, f, ..] = self.coefficients;
        [[a, d, e], [d, b, f], [e, f, c]]
    }

    /// The half-linear vector `l = (g, h, i)`; the paper's `b` is `−l`.
    pub fn linear(&self) -> DVec3 {
        let k = &self.coefficients;
        DVec3::new(k[6], k[7], k[8])
    }

    /// The constant `j` (the value at the origin).
    pub fn constant(&self) -> f64 {
        self.coefficients[9]
    }

    /// Frobenius norm of `A`.
    pub fn matrix_norm(&self) -> f64 {
        let [a, b, c, d, e, f, ..] = self.coefficients;
        (a * a + b * b + c * c + 2.0 * (d * d + e * e + f * f)).sqrt()
    }

    /// The largest coefficient magnitude.
    pub fn scale(&self) -> f64 {
        self.coefficients.iter().fold(0.0, |m, c| m.max(c.abs()))
    }

    /// Rigorous bounds `(lower, upper)` on the extreme eigenvalues of `A`: every unit `v` has
    /// `lower ≤ vᵀ A v ≤ upper`.
    pub fn eigenvalue_bounds(&self) -> (f64, f64) {
        (self.eigen_lower, self.eigen_upper)
    }

    /// Eigen-decomposition of `A` (see [`symmetric_eigen`]).
    pub fn eigen(&self) -> SymmetricEigen {
        symmetric_eigen(&self.matrix_a())
    }

    /// `A x` for a local vector `x`.
    #[inline]
    pub(crate) fn apply_a(&self, x: DVec3) -> DVec3 {
        let [a, b, c, d, e, f, ..] = self.coefficients;
        DVec3::new(
            a * x.x + d * x.y + e * x.z,
            d * x.x + b * x.y + f * x.z,
            e * x.x + f * x.y + c * x.z,
        )
    }

    /// The value `q(x)` at a local vector `x = p − origin`.
    #[inline]
    pub fn value_local(&self, x: DVec3) -> f64 {
        let ax = self.apply_a(x);
        x.dot(ax + 2.0 * self.linear()) + self.coefficients[9]
    }

    /// The value `Q(p)` at a world point (eq. 3). Negative inside, positive outside.
    ///
    /// Error bound: see [`Self::value_with_error`] (tested through the sign agreement of values
    /// across transforms and the canonical form, which agree to `1e-9` of the terms).
    #[inline]
    pub fn value(&self, p: DVec3) -> f64 {
        self.value_local(p - self.origin)
    }

    /// The value at a world point together with a rigorous bound on its rounding error,
    /// `16 u (‖x‖∞² Σ|A_rc| + 2 ‖x‖∞ Σ|l_k| + |j|)` with `x = p − origin` and `u = 2⁻⁵³`, which
    /// dominates `16 u (|x|ᵀ|A||x| + 2|l|ᵀ|x| + |j|)` (this includes the rounding of `p − origin`).
    #[inline]
    pub fn value_with_error(&self, p: DVec3) -> (f64, f64) {
        let x = p - self.origin;
        (self.value_local(x), 16.0 * EPS * self.term_bound(x))
    }

    /// The gradient `∇Q(p) = 2 (A x + l)` (eq. 4, with `b = −l`), `x = p − origin`.
    ///
    /// Each component is exact to `8 u (‖x‖∞ Σ|A_rc| + Σ|l_k|)` (`u = 2⁻⁵³`); the tests compare it
    /// with central differences of [`Self::value`] to `1e-6` relative.
    #[inline]
    pub fn gradient(&self, p: DVec3) -> DVec3 {
        let x = p - self.origin;
        2.0 * (self.apply_a(x) + self.linear())
    }

    /// The outward unit normal `N(p)` (eq. 4); `None` where the gradient vanishes (the centre of
    /// a central quadric, a cone's apex, every point of a degenerate quadric). Unit length to
    /// `1e-15` (tested), direction as accurate as [`Self::gradient`], without overflow or
    /// underflow for any finite gradient.
    #[inline]
    pub fn normal(&self, p: DVec3) -> Option<DVec3> {
        Self::normal_from_gradient(self.gradient(p))
    }

    /// The unit vector along a gradient `g` (as [`Self::normal`] makes it, for a caller that
    /// has the gradient already); `None` where it vanishes or is not finite.
    #[inline]
    pub fn normal_from_gradient(g: DVec3) -> Option<DVec3> {
        Self::normal_from_gradient_squared(g, g.length_squared())
    }

    /// [`Self::normal_from_gradient`] for a caller that has `g.length_squared()` already.
    #[inline]
    pub fn normal_from_gradient_squared(g: DVec3, length_squared: f64) -> Option<DVec3> {
        if (f64::MIN_POSITIVE..=f64::MAX).contains(&length_squared) {
            // One division and three products: the sampler computes millions of normals in
            // batches, where the divider's throughput bounds it (a lone ball 5 % faster than
            // with three divisions); the result differs from `g / |g|` by at most an ulp.
            return Some(g * (1.0 / length_squared.sqrt()));
        }
        // Rare: the squared length under- or overflowed. Scaling first keeps it in range.
        let m = g.abs().max_element();
        if m == 0.0 || !m.is_finite() {
            return None;
        }
        (g / m).try_normalize()
    }

    /// The complement: the same surface with inside and outside swapped. Exact.
    pub fn negated(&self) -> Self {
        Self {
            origin: self.origin,
            coefficients: self.coefficients.map(|c| -c),
            eigen_lower: -self.eigen_upper,
            eigen_upper: -self.eigen_lower,
            aligned: self.aligned.map(AlignedForm::negated),
            ..*self
        }
    }

    /// The same quadric with its coefficients multiplied by a power of two (exact) so that the
    /// largest magnitude lies in `[1, 2)`. The all-zero quadric is returned unchanged.
    pub fn normalized(&self) -> Self {
        let scale = self.scale();
        if scale == 0.0 {
            return *self;
        }
        let factor = power_of_two_reciprocal(scale);
        Self::from_parts(self.origin, self.coefficients.map(|c| c * factor))
    }

    /// The same quadric moved rigidly by `offset`. Exact: only the origin changes.
    pub fn translated(&self, offset: DVec3) -> Self {
        Self {
            origin: self.origin + offset,
            ..*self
        }
    }

    /// The same point set expressed about another origin.
    ///
    /// Re-expansion `q'(x) = q(x + s)` with `s = new_origin − origin` costs an absolute error of
    /// about `ε (|s|ᵀ|A||s| + 2|l|ᵀ|s| + |j|)` in the constant: use it to move an origin *towards*
    /// the geometry, not away from it.
    pub fn with_origin(&self, new_origin: DVec3) -> Self {
        let shift = new_origin - self.origin;
        if shift == DVec3::ZERO {
            return *self;
        }
        let l = self.apply_a(shift) + self.linear();
        let j = self.value_local(shift);
        let mut coefficients = self.coefficients;
        coefficients[6] = l.x;
        coefficients[7] = l.y;
        coefficients[8] = l.z;
        coefficients[9] = j;
        let mut moved = Self {
            origin: new_origin,
            coefficients,
            ..*self
        };
        moved.update_derived();
        moved
    }

    /// The image of the quadric under the invertible transform `m` (points map as `p' = M p`):
    /// `Q' = M⁻ᵀ Q M⁻¹` (eq. 17), normalised with [`Self::normalized`].
    ///
    /// The new origin is the image of the old one, so for an affine `m = [L t; 0 1]` the new
    /// coefficients are `A' = L⁻ᵀ A L⁻¹`, `l' = L⁻ᵀ l`, `j' = j`: the translation never enters them
    /// and a translation alone is exact. Relative error of the coefficients: about
    /// `κ(L)² ε` (the conditioning of `L`). Projective transforms use the full 4×4 form about
    /// the mapped origin.
    ///
    /// `None` if `m` is singular (to working precision) or not finite, or the result overflows.
    pub fn transformed(&self, m: &DMat4) -> Option<Self> {
        if !m.is_finite() {
            return None;
        }
        let affine = m.row(3) == DVec4::W;
        let result = if affine {
            let linear = DMat3::from_mat4(*m);
            let det = linear.determinant();
            if det == 0.0 || !det.is_finite() {
                return None;
            }
            let inverse = linear.inverse();
            let origin = linear * self.origin + m.w_axis.truncate();
            let a = congruence(&self.matrix_a(), &inverse);
            let l = inverse.transpose() * self.linear();
            Self::from_matrix(origin, &a, l, self.constant())?
        } else {
            self.transformed_projective(m)?
        };
        Some(result.normalized())
    }

    fn transformed_projective(&self, m: &DMat4) -> Option<Self> {
        let image = *m * self.origin.extend(1.0);
        let mapped = image.truncate() / image.w;
        // An origin sent to (or near) infinity cannot be the new origin: fall back to zero.
        let origin_is_mapped = image.w != 0.0 && mapped.is_finite();
        let origin = if origin_is_mapped {
            mapped
        } else {
            DVec3::ZERO
        };
        // K maps old local coordinates to new local ones: K = T(−o') M T(o).
        let mut k = DMat4::from_translation(-origin) * *m * DMat4::from_translation(self.origin);
        if origin_is_mapped {
            // The old origin lands on the new origin: clear the rounding noise there.
            k.w_axis = DVec4::new(0.0, 0.0, 0.0, image.w);
        }
        let det = k.determinant();
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        let n = k.inverse();
        let [a, b, c, d, e, f, g, h, i, j] = self.coefficients;
        let q = DMat4::from_cols_array(&[a, d, e, g, d, b, f, h, e, f, c, i, g, h, i, j]);
        let r = n.transpose() * q * n;
        let s = |row: usize, col: usize| 0.5 * (r.col(col)[row] + r.col(row)[col]);
        Self::new(
            origin,
            [
                s(0, 0),
                s(1, 1),
                s(2, 2),
                s(0, 1),
                s(0, 2),
                s(1, 2),
                s(0, 3),
                s(1, 3),
                s(2, 3),
                s(3, 3),
            ],
        )
    }

    /// Whether `other` describes the same solid up to a positive factor.
    ///
    /// Both are expressed about `self`'s origin and in `self`'s own length unit `s` (which
    /// balances the quadratic, linear and constant parts: `s = √(|j| / max|A|)` when both are
    /// non-zero, else `|l| / max|A|` or `|j| / |l|`, else 1), scaled to unit largest coefficient,
    /// and compared entrywise with absolute tolerance `tolerance`. So `1e-12` means "the same to
    /// about 12 digits of the feature size", for a sphere of radius `1e-3` at `10⁶` as for a unit
    /// one. A complement (negative factor) never compares equal.
    pub fn approx_eq_up_to_scale(&self, other: &Self, tolerance: f64) -> bool {
        let other = other.with_origin(self.origin);
        let unit = self.length_unit();
        let balance = |k: &[f64; 10]| {
            let mut b = *k;
            b[..6].iter_mut().for_each(|c| *c *= unit * unit);
            b[6..9].iter_mut().for_each(|c| *c *= unit);
            b
        };
        let (a, b) = (balance(&self.coefficients), balance(&other.coefficients));
        let scale = |k: &[f64; 10]| k.iter().fold(0.0f64, |m, c| m.max(c.abs()));
        let (sa, sb) = (scale(&a), scale(&b));
        if sa == 0.0 || sb == 0.0 || !sa.is_finite() || !sb.is_finite() {
            return sa == sb && self.coefficients == other.coefficients;
        }
        a.iter()
            .zip(b.iter())
            .all(|(x, y)| (x / sa - y / sb).abs() <= tolerance)
    }

    /// The length that balances the quadratic, linear and constant coefficients:
    /// `√(|j| / max|A|)` when both are non-zero, else `max|l| / max|A|` or `|j| / max|l|`, else 1
    /// (see [`Self::approx_eq_up_to_scale`]).
    pub fn length_unit(&self) -> f64 {
        let k = &self.coefficients;
        let a = k[..6].iter().fold(0.0f64, |m, c| m.max(c.abs()));
        let l = k[6..9].iter().fold(0.0f64, |m, c| m.max(c.abs()));
        let j = k[9].abs();
        let unit = if a > 0.0 && j > 0.0 {
            (j / a).sqrt()
        } else if a > 0.0 && l > 0.0 {
            l / a
        } else if l > 0.0 && j > 0.0 {
            j / l
        } else {
            1.0
        };
        if unit > 0.0 && unit.is_finite() {
            unit
        } else {
            1.0
        }
    }
}

/// `Nᵀ A N` for symmetric `A`, symmetrised.
fn congruence(a: &Sym3, n: &DMat3) -> Sym3 {
    let a_mat = DMat3::from_cols_array_2d(a);
    let r = n.transpose() * a_mat * *n;
    let mut out = [[0.0; 3]; 3];
    for (row, entries) in out.iter_mut().enumerate() {
        for (col, entry) in entries.iter_mut().enumerate() {
            *entry = 0.5 * (r.col(col)[row] + r.col(row)[col]);
        }
    }
    out
}
