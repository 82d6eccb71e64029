//! Exact orientation predicates on f64 points.
//!
//! The decompositions classify pieces by the even–odd parity of crossings along segments; a
//! crossing decided wrongly by rounding would flip the parity of a whole subtree of cells, so the
//! sign of each orientation determinant is computed exactly: a floating-point filter first, and
//! where it cannot decide, the determinant's six products as exact two-term products (fused
//! multiply–add) summed into a non-overlapping expansion (Shewchuk's `grow_expansion`), whose
//! most significant component carries the sign. Exact for finite inputs whose products neither
//! overflow nor underflow (the callers bound coordinates to |x| ≤ 1e100).

use glam::DVec2;

/// `a + b` as the rounded sum and its exact error.
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let sum = a + b;
    let b_virtual = sum - a;
    let a_virtual = sum - b_virtual;
    (sum, (a - a_virtual) + (b - b_virtual))
}

/// `a · b` as the rounded product and its exact error.
fn two_product(a: f64, b: f64) -> (f64, f64) {
    let product = a * b;
    (product, a.mul_add(b, -product))
}

/// The sign (−1, 0 or 1) of the exact sum of `terms`, each term the exact product of a pair.
fn sign_of_product_sum(products: &[(f64, f64)]) -> i32 {
    // A non-overlapping expansion in increasing magnitude, zero components dropped.
    let mut expansion = [0.0_f64; 32];
    let mut len = 0;
    let mut scratch = [0.0_f64; 32];
    for &(a, b) in products {
        let (high, low) = two_product(a, b);
        for term in [low, high] {
            let mut carry = term;
            let mut out = 0;
            for &component in &expansion[..len] {
                let (sum, error) = two_sum(carry, component);
                if error != 0.0 {
                    scratch[out] = error;
                    out += 1;
                }
                carry = sum;
            }
            if carry != 0.0 {
                scratch[out] = carry;
                out += 1;
            }
            expansion[..out].copy_from_slice(&scratch[..out]);
            len = out;
        }
    }
    match len {
        0 => 0,
        _ if expansion[len - 1] > 0.0 => 1,
        _ => -1,
    }
}

/// The exact sign of the orientation of `a`, `b`, `c`: 1 counter-clockwise (c left of a→b), −1
/// clockwise, 0 collinear.
pub(crate) fn orient2d(a: DVec2, b: DVec2, c: DVec2) -> i32 {
    let left = (a.x - c.x) * (b.y - c.y);
    let right = (a.y - c.y) * (b.x - c.x);
    let det = left - right;
    // Shewchuk's first error bound for the filtered determinant.
    let bound = 3.330_669_073_875_471_6e-16 * (left.abs() + right.abs());
    if det > bound {
        return 1;
    }
    if -det > bound {
        return -1;
    }
    // (ax−cx)(by−cy) − (ay−cy)(bx−cx) expanded; the cx·cy terms cancel.
    sign_of_product_sum(&[
        (a.x, b.y),
        (-a.x, c.y),
        (-c.x, b.y),
        (-a.y, b.x),
        (a.y, c.x),
        (c.y, b.x),
    ])
}

/// Whether segment `p`–`q` crosses edge `a`–`b`, with `p` and `q` moved together by the
/// infinitesimal `(ε, ε²)` (simulation of simplicity): no vertex then lies on the segment's line
/// and neither end on the edge's line, so parities summed along chains of segments between the
/// same moved points are consistent even where a segment runs through a vertex or along an edge.
pub(crate) fn segment_crosses_edge(p: DVec2, q: DVec2, a: DVec2, b: DVec2) -> bool {
    // orient(p + δ, q + δ, c) = orient(p, q, c − δ) = orient(p, q, c) + (q.y − p.y) ε − (q.x − p.x) ε².
    let segment_tie = || {
        if q.y != p.y { q.y > p.y } else { p.x > q.x }
    };
    let side = |c: DVec2| match orient2d(p, q, c) {
        0 => segment_tie(),
        s => s > 0,
    };
    if side(a) == side(b) {
        return false;
    }
    // orient(a, b, c + δ) = orient(a, b, c) − (b.y − a.y) ε + (b.x − a.x) ε².
    let edge_tie = if b.y != a.y { a.y > b.y } else { b.x > a.x };
    let end_side = |c: DVec2| match orient2d(a, b, c) {
        0 => edge_tie,
        s => s > 0,
    };
    end_side(p) != end_side(q)
}

/// Whether edges `a`–`b` and `c`–`d` cross at a single point interior to both.
pub(crate) fn edges_cross_properly(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> bool {
    orient2d(a, b, c) * orient2d(a, b, d) < 0 && orient2d(c, d, a) * orient2d(c, d, b) < 0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decides_what_rounding_cannot() {
        // Nearly collinear points far from the origin: the naive determinant rounds to zero or
        // to the wrong sign.
        let a = DVec2::new(1e6, 1e6);
        let b = DVec2::new(1e6 + 1.0, 1e6 + 1.0);
        let on = DVec2::new(1e6 + 0.5, 1e6 + 0.5);
        assert_eq!(orient2d(a, b, on), 0);
        let above = DVec2::new(1e6 + 0.5, f64::from_bits((1e6_f64 + 0.5).to_bits() + 1));
        assert_eq!(orient2d(a, b, above), 1);
        let below = DVec2::new(1e6 + 0.5, f64::from_bits((1e6_f64 + 0.5).to_bits() - 1));
        assert_eq!(orient2d(a, b, below), -1);
        let tiny = DVec2::new(0.1, 0.1 + 1e-17);
        assert_eq!(orient2d(DVec2::ZERO, DVec2::new(0.3, 0.3), tiny), 1);
    }
}
