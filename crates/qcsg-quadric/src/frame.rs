//! The principal frame of a quadric (paper §3.2): centre, principal axes and the canonical form
//! of the quadric in that frame, with scale-relative decisions about which eigenvalues and
//! linear terms are zero.
//!
//! In frame coordinates `y` (world point `centre + Σ y_k u_k`) every quadric reads
//! `Σ λ_k y_k² + 2 Σ m_k y_k + κ`, where `m_k ≠ 0` only on a null axis (`λ_k = 0`) and on at most
//! one axis. The centre is the min-norm solution of `A q = b` (via the eigen-decomposition with a
//! relative eigenvalue cut-off, so singular `A` is fine), moved along the linear axis to the
//! vertex for paraboloids, parabolic cylinders and planes (there `κ = 0`).

use glam::DVec3;

use crate::eigen::SymmetricEigen;
use crate::quadric::{EPS, Quadric};

/// Relative tolerances for the decisions made on a quadric's canonical form.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tolerances {
    /// An eigenvalue is zero when `|λ| ≤ eigenvalue · max|λ|` (default `1e-10`: an ellipsoid with
    /// an aspect ratio below 10⁵ stays an ellipsoid; an eigenvalue of 10⁻¹² beside 1 makes a
    /// cylinder). Snapping an eigenvalue to zero is a local approximation: the linear term left
    /// on that axis is then judged by [`Self::linear`], so a long ellipsoid written about a point
    /// off its centre may come out as a paraboloid rather than a cylinder.
    pub eigenvalue: f64,
    /// A linear term on the null space is zero when `|m| ≤ linear · (‖A‖‖q‖ + ‖l‖)`, i.e. within
    /// the noise of the terms it is computed from (default `1e-10`).
    pub linear: f64,
    /// The constant `κ` is zero when `|κ| ≤ constant · (|qᵀAq| + 2|lᵀq| + |j|)`, its rounding
    /// noise (default `128 u ≈ 1.4e-14`, `u = 2⁻⁵³`).
    pub constant: f64,
    /// Two eigenvalues are equal (sphere, spheroid) when they differ by at most
    /// `equal · max|λ|` (default `1e-9`).
    pub equal: f64,
}

impl Default for Tolerances {
    fn default() -> Self {
        Self {
            eigenvalue: 1e-10,
            linear: 1e-10,
            constant: 128.0 * EPS,
            equal: 1e-9,
        }
    }
}

/// Centre, principal axes and canonical form of a quadric.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrincipalFrame {
    /// The centre `q` in world coordinates (vertex for paraboloids and planes).
    pub centre: DVec3,
    /// Principal axes `u_k`: a right-handed orthonormal basis (eigenvectors of `A`).
    pub axes: [DVec3; 3],
    /// Eigenvalues `λ_k` of `A`, in the order of `axes`; exactly `0.0` where judged zero.
    pub eigenvalues: [f64; 3],
    /// Linear coefficients `m_k` of the canonical form; non-zero on at most one null axis.
    pub linear: [f64; 3],
    /// The constant `κ` of the canonical form, `Q(centre)`; exactly `0.0` where judged zero.
    pub constant: f64,
}

impl PrincipalFrame {
    /// The frame of `quadric` under the given tolerances.
    ///
    /// Error bounds (enforced by the tests): axes orthonormal to `1e-14`, including repeated
    /// and zero eigenvalues; for a sphere built about its centre and sent through transform
    /// chains (translations of 10⁶, scales of 10⁻³ to 10¹², a hundred random similarities), the
    /// centre and the semi-axes are exact to `1e-9` of the radius (the centre's absolute error is
    /// also bounded by a few `ε |centre|`, which dominates for radii below `1e-6 |centre|`); for
    /// an ellipsoid of aspect ratio `10⁴` in general position the semi-axes are exact to `1e-7`
    /// relative (the smallest eigenvalue carries an absolute error of about `ε λ_max`).
    pub fn new(quadric: &Quadric, tolerances: &Tolerances) -> Self {
        let SymmetricEigen { values, vectors } = quadric.eigen();
        let largest = values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let is_null = values.map(|v| v.abs() <= tolerances.eigenvalue * largest);
        let l = quadric.linear();

        // Min-norm centre (local): y = −Σ_{λ_k ≠ 0} (u_kᵀ l / λ_k) u_k.
        let mut centre = DVec3::ZERO;
        for k in 0..3 {
            if !is_null[k] {
                centre -= (vectors[k].dot(l) / values[k]) * vectors[k];
            }
        }
        let mut eigenvalues = values;
        let mut axes = vectors;
        for k in 0..3 {
            if is_null[k] {
                eigenvalues[k] = 0.0;
            }
        }

        // Linear part left on the null space, and whether it is noise.
        let residual = quadric.apply_a(centre) + l;
        let mut null_linear = DVec3::ZERO;
        for k in 0..3 {
            if is_null[k] {
                null_linear += axes[k].dot(residual) * axes[k];
            }
        }
        let noise = tolerances.linear * (quadric.matrix_norm() * centre.length() + l.length());
        let has_linear = null_linear.length() > noise;

        let mut linear = [0.0; 3];
        if has_linear {
            let direction = null_linear.normalize();
            let mut nulls = [0usize; 3];
            let mut count = 0;
            for k in (0..3).filter(|&k| is_null[k]) {
                nulls[count] = k;
                count += 1;
            }
            // The axis that carries the linear term, and one that may be flipped for handedness.
            let (carry, free) = match &nulls[..count] {
                [k] => (*k, None),
                [a, b] => {
                    // Rotate the null plane so that its first axis carries the linear term.
                    let other = 3 - a - b;
                    axes[*a] = direction;
                    axes[*b] = axes[other].cross(direction).normalize();
                    (*a, Some(*b))
                }
                _ => {
                    let (u, v) = direction.any_orthonormal_pair();
                    axes = [u, v, direction];
                    (2, Some(0))
                }
            };
            if let Some(free) = free
                && axes[0].cross(axes[1]).dot(axes[2]) < 0.0
            {
                axes[free] = -axes[free];
            }
            linear[carry] = axes[carry].dot(null_linear);
        }

        let mut constant = quadric.value_local(centre);
        if let Some(k) = (0..3).find(|&k| linear[k] != 0.0) {
            // Move to the vertex: κ + 2 m s = 0.
            let shift = -constant / (2.0 * linear[k]);
            centre += shift * axes[k];
            constant = 0.0;
        } else {
            let terms = centre.dot(quadric.apply_a(centre)).abs()
                + 2.0 * l.dot(centre).abs()
                + quadric.constant().abs();
            if constant.abs() <= tolerances.constant * terms {
                constant = 0.0;
            }
        }

        Self {
            centre: quadric.origin() + centre,
            axes,
            eigenvalues,
            linear,
            constant,
        }
    }

    /// Number of non-zero eigenvalues.
    pub fn rank(&self) -> usize {
        self.eigenvalues.iter().filter(|v| **v != 0.0).count()
    }

    /// Frame coordinates `y` of a world point.
    pub fn to_frame(&self, p: DVec3) -> DVec3 {
        let d = p - self.centre;
        DVec3::new(
            self.axes[0].dot(d),
            self.axes[1].dot(d),
            self.axes[2].dot(d),
        )
    }

    /// The world point with frame coordinates `y`.
    pub fn to_world(&self, y: DVec3) -> DVec3 {
        self.centre + y.x * self.axes[0] + y.y * self.axes[1] + y.z * self.axes[2]
    }

    /// The canonical form evaluated at frame coordinates `y`. Agrees with [`Quadric::value`] at
    /// the same point to `1e-9` of the terms (tested), the difference being the snapped
    /// eigenvalues and linear terms and rounding.
    pub fn canonical_value(&self, y: DVec3) -> f64 {
        let y = y.to_array();
        (0..3)
            .map(|k| (self.eigenvalues[k] * y[k] + 2.0 * self.linear[k]) * y[k])
            .sum::<f64>()
            + self.constant
    }

    /// Semi-axis lengths `sqrt(|κ / λ_k|)` along each axis (the radii of an ellipsoid, the
    /// radius of a cylinder, the waist of a hyperboloid); infinite on null axes, zero when `κ = 0`.
    /// See [`Self::new`] for the tested accuracy.
    pub fn semi_axes(&self) -> [f64; 3] {
        self.eigenvalues.map(|v| {
            if v == 0.0 {
                f64::INFINITY
            } else {
                (self.constant / v).abs().sqrt()
            }
        })
    }
}

impl Quadric {
    /// The paper's centre (§3.2): the min-norm solution `q` of `A q = b` relative to the local
    /// origin (eigenvalues below `tolerances.eigenvalue · max|λ|` are treated as zero), in world
    /// coordinates. Unlike [`PrincipalFrame::centre`] it is not moved to the vertex of
    /// paraboloids and planes. Exact to a few `ε κ(A)` relative for non-singular `A`.
    pub fn min_norm_centre(&self, tolerances: &Tolerances) -> DVec3 {
        let SymmetricEigen { values, vectors } = self.eigen();
        let largest = values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let l = self.linear();
        let mut centre = DVec3::ZERO;
        for k in 0..3 {
            if values[k].abs() > tolerances.eigenvalue * largest {
                centre -= (vectors[k].dot(l) / values[k]) * vectors[k];
            }
        }
        self.origin() + centre
    }

    /// The same quadric about its frame centre (see [`Self::with_origin`]): useful for
    /// coefficients that arrive about a distant origin. Returns `self` unchanged when the centre
    /// is not finite.
    pub fn recentred(&self) -> Self {
        let centre = self.frame().centre;
        if centre.is_finite() {
            self.with_origin(centre)
        } else {
            *self
        }
    }

    /// The principal frame with default [`Tolerances`].
    pub fn frame(&self) -> PrincipalFrame {
        PrincipalFrame::new(self, &Tolerances::default())
    }

    /// The centre (min-norm solution of `A q = b`, vertex for paraboloids and planes).
    pub fn centre(&self) -> DVec3 {
        self.frame().centre
    }
}
