//! Symmetric 3×3 eigen-decomposition by the cyclic Jacobi method.
//!
//! Jacobi rotations are exactly orthogonal up to rounding, so the accumulated eigenvector basis
//! stays orthonormal to a few ulps even when eigenvalues repeat (where methods based on the
//! characteristic polynomial lose the eigenvectors entirely). Eigenvalues come out with an
//! absolute error of a few ulps of the matrix's largest entry.

use glam::DVec3;

/// A symmetric 3×3 matrix as rows; only the symmetric part is read.
pub type Sym3 = [[f64; 3]; 3];

/// Eigenvalues and eigenvectors of a symmetric 3×3 matrix.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SymmetricEigen {
    /// Eigenvalues in ascending order.
    pub values: [f64; 3],
    /// Unit eigenvectors, `vectors[k]` belonging to `values[k]`: a right-handed orthonormal basis.
    ///
    /// Each vector's component of largest magnitude is made positive (the first two; the third
    /// follows from handedness), so the result is deterministic.
    pub vectors: [DVec3; 3],
}

/// Upper limit on Jacobi sweeps; 3×3 matrices converge (quadratically) in about five.
const MAX_SWEEPS: usize = 50;

/// Eigen-decomposition of the symmetric part of `m`.
///
/// Error bounds (enforced by the tests): `‖Vᵀ V − I‖_max ≤ 1e-14` for any input, repeated
/// eigenvalues included; `‖A v_k − λ_k v_k‖ ≤ 1e-14 ‖A‖_F`. Non-finite input gives non-finite
/// output but never panics.
pub fn symmetric_eigen(m: &Sym3) -> SymmetricEigen {
    // Scale by a power of two (exact) so that the largest entry is in [1, 2): no intermediate
    // can overflow or underflow, whatever the magnitude of the input.
    let largest = m.iter().flatten().fold(0.0f64, |acc, v| acc.max(v.abs()));
    let factor = if largest > 0.0 && largest.is_finite() {
        power_of_two_reciprocal(largest)
    } else {
        1.0
    };
    let mut a = [[0.0; 3]; 3];
    for (r, row) in a.iter_mut().enumerate() {
        for (c, entry) in row.iter_mut().enumerate() {
            *entry = if r == c {
                m[r][c] * factor
            } else {
                0.5 * (m[r][c] * factor + m[c][r] * factor)
            };
        }
    }
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

    for sweep in 0..MAX_SWEEPS {
        let off = a[0][1].abs() + a[0][2].abs() + a[1][2].abs();
        if off == 0.0 || !off.is_finite() {
            break;
        }
        for (p, q) in [(0usize, 1usize), (0, 2), (1, 2)] {
            let apq = a[p][q];
            if apq == 0.0 {
                continue;
            }
            let app = a[p][p];
            let aqq = a[q][q];
            // Once converging, an off-diagonal entry below the diagonal's ulp is rounding noise.
            if sweep > 3 && app.abs() + 100.0 * apq.abs() == app.abs() && {
                aqq.abs() + 100.0 * apq.abs() == aqq.abs()
            } {
                a[p][q] = 0.0;
                a[q][p] = 0.0;
                continue;
            }
            // Rutishauser's stable rotation: t = tan of the smaller rotation angle.
            let theta = (aqq - app) / (2.0 * apq);
            let t = if theta.abs() > 1e150 {
                0.5 / theta
            } else {
                let sign = if theta < 0.0 { -1.0 } else { 1.0 };
                sign / (theta.abs() + (theta * theta + 1.0).sqrt())
            };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            let tau = s / (1.0 + c);
            a[p][p] = app - t * apq;
            a[q][q] = aqq + t * apq;
            a[p][q] = 0.0;
            a[q][p] = 0.0;
            let r = 3 - p - q;
            let arp = a[r][p];
            let arq = a[r][q];
            a[r][p] = arp - s * (arq + tau * arp);
            a[p][r] = a[r][p];
            a[r][q] = arq + s * (arp - tau * arq);
            a[q][r] = a[r][q];
            for row in &mut v {
                let vp = row[p];
                let vq = row[q];
                row[p] = vp - s * (vq + tau * vp);
                row[q] = vq + s * (vp - tau * vq);
            }
        }
    }

    let mut order = [0usize, 1, 2];
    order.sort_by(|&x, &y| a[x][x].total_cmp(&a[y][y]));
    let column = |k: usize| DVec3::new(v[0][k], v[1][k], v[2][k]);
    let mut vectors = order.map(|k| canonical_sign(column(k)));
    if vectors[0].cross(vectors[1]).dot(vectors[2]) < 0.0 {
        vectors[2] = -vectors[2];
    }
    SymmetricEigen {
        values: order.map(|k| a[k][k] / factor),
        vectors,
    }
}

/// `2^−e` with `2^e ≤ scale < 2^(e+1)`, so that `scale · 2^−e ∈ [1, 2)`.
pub(crate) fn power_of_two_reciprocal(scale: f64) -> f64 {
    let mut exponent = scale.log2().floor() as i32;
    // log2 may round across a power of two; correct by one step.
    if 2f64.powi(exponent) > scale {
        exponent -= 1;
    } else if 2f64.powi(exponent + 1) <= scale {
        exponent += 1;
    }
    // Split the factor so that neither half overflows for extreme exponents.
    let half = -exponent / 2;
    2f64.powi(half) * 2f64.powi(-exponent - half)
}

/// Flips `v` so that its component of largest magnitude (first on ties) is positive.
fn canonical_sign(v: DVec3) -> DVec3 {
    let abs = v.abs();
    let largest = if abs.x >= abs.y && abs.x >= abs.z {
        v.x
    } else if abs.y >= abs.z {
        v.y
    } else {
        v.z
    };
    if largest < 0.0 { -v } else { v }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn diagonal_matrix_is_sorted() {
        let e = symmetric_eigen(&[[3.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 2.0]]);
        assert_eq!(e.values, [-1.0, 2.0, 3.0]);
        assert_eq!(e.vectors[0], DVec3::Y);
    }

    #[test]
    fn normalisation_is_a_power_of_two() {
        for s in [
            1.0,
            1.5,
            2.0,
            3.0,
            1e-300,
            1e300,
            0.75,
            f64::MIN_POSITIVE,
            f64::MAX,
        ] {
            let f = power_of_two_reciprocal(s);
            let scaled = s * f;
            assert!((1.0..2.0).contains(&scaled), "{s} -> {scaled}");
            assert_eq!(f.log2().fract(), 0.0);
        }
    }

    #[test]
    fn extreme_magnitudes() {
        for s in [1e-300, 1e300, f64::MAX / 4.0] {
            let e = symmetric_eigen(&[[s, -s, 0.0], [-s, -s, 0.5 * s], [0.0, 0.5 * s, 0.25 * s]]);
            let trace = e.values.iter().sum::<f64>();
            assert!((trace - 0.25 * s).abs() <= 1e-14 * s, "{s}: {:?}", e.values);
            assert!(e.values.iter().all(|v| v.is_finite()));
        }
    }

    #[test]
    fn zero_matrix() {
        let e = symmetric_eigen(&[[0.0; 3]; 3]);
        assert_eq!(e.values, [0.0; 3]);
        assert!((e.vectors[0].cross(e.vectors[1]).dot(e.vectors[2]) - 1.0).abs() < 1e-15);
    }
}
