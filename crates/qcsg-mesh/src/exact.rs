//! Exact orientation predicates on f64 points.
//!
//! The decompositions classify pieces by the even–odd parity of crossings along segments; a
//! crossing decided wrongly by rounding would flip the parity of a whole subtree of cells, so the
//! sign of each orientation determinant is computed exactly: a floating-point filter first, and
//! where it cannot decide, the determinant's six products as exact two-term products (fused
//! multiply–add) summed into a non-overlapping expansion (Shewchuk's `grow_expansion`), whose
//! most significant component carries the sign. Exact for finite inputs whose products neither
//! overflow nor underflow (the callers bound coordinates to |x| ≤ 1e100 in 2-D and 1e60 in 3-D).
//! The 3-D predicates work the same way, with triple products split into four exact terms.

use glam::{DVec2, DVec3};

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

/// The sign (−1, 0 or 1) of the exact sum of `terms` (each a double, summed without rounding).
fn sign_of_sum(terms: impl IntoIterator<Item = f64>) -> i32 {
    // A non-overlapping expansion in increasing magnitude, zero components dropped.
    let mut expansion: Vec<f64> = Vec::with_capacity(32);
    let mut scratch: Vec<f64> = Vec::with_capacity(32);
    for term in terms {
        let mut carry = term;
        scratch.clear();
        for &component in &expansion {
            let (sum, error) = two_sum(carry, component);
            if error != 0.0 {
                scratch.push(error);
            }
            carry = sum;
        }
        if carry != 0.0 {
            scratch.push(carry);
        }
        std::mem::swap(&mut expansion, &mut scratch);
    }
    match expansion.last() {
        None => 0,
        Some(&top) if top > 0.0 => 1,
        Some(_) => -1,
    }
}

/// The sign of the exact sum of the products of the pairs.
fn sign_of_product_sum(products: &[(f64, f64)]) -> i32 {
    sign_of_sum(products.iter().flat_map(|&(a, b)| {
        let (high, low) = two_product(a, b);
        [low, high]
    }))
}

/// The sign of the exact sum of the products of the triples.
fn sign_of_triple_product_sum(products: &[(f64, f64, f64)]) -> i32 {
    sign_of_sum(products.iter().flat_map(|&(a, b, c)| {
        let (high, low) = two_product(a, b);
        let (hh, hl) = two_product(high, c);
        let (lh, ll) = two_product(low, c);
        [ll, lh, hl, hh]
    }))
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

/// The exact sign of `det[a − d, b − d, c − d]`: positive when `d` lies on the side of the plane
/// through `a`, `b`, `c` opposite to `(b − a) × (c − a)`, zero when the four are coplanar.
pub(crate) fn orient3d(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> i32 {
    // A corner of the plane's own triangle (neighbouring triangles share corners): no need for
    // the exact sum.
    if d == a || d == b || d == c {
        return 0;
    }
    let (ad, bd, cd) = (a - d, b - d, c - d);
    let det = ad.dot(bd.cross(cd));
    let permanent = ad.x.abs() * ((bd.y * cd.z).abs() + (bd.z * cd.y).abs())
        + ad.y.abs() * ((bd.z * cd.x).abs() + (bd.x * cd.z).abs())
        + ad.z.abs() * ((bd.x * cd.y).abs() + (bd.y * cd.x).abs());
    // Generous beside Shewchuk's bound of about 7.8e-16 for the filtered determinant.
    let bound = 1e-14 * permanent;
    if det > bound {
        return 1;
    }
    if -det > bound {
        return -1;
    }
    // det[a−d, b−d, c−d] = −det(b,c,d) + det(a,c,d) − det(a,b,d) + det(a,b,c) over raw coordinates.
    let mut triples = Vec::with_capacity(24);
    for (sign, [p, q, r]) in [
        (-1.0, [b, c, d]),
        (1.0, [a, c, d]),
        (-1.0, [a, b, d]),
        (1.0, [a, b, c]),
    ] {
        triples.extend([
            (sign * p.x, q.y, r.z),
            (-sign * p.x, q.z, r.y),
            (-sign * p.y, q.x, r.z),
            (sign * p.y, q.z, r.x),
            (sign * p.z, q.x, r.y),
            (-sign * p.z, q.y, r.x),
        ]);
    }
    sign_of_triple_product_sum(&triples)
}

/// The exact signs of the components of `(b − a) × (c − a)`.
pub(crate) fn normal_signs(a: DVec3, b: DVec3, c: DVec3) -> [i32; 3] {
    [
        orient2d(
            DVec2::new(a.y, a.z),
            DVec2::new(b.y, b.z),
            DVec2::new(c.y, c.z),
        ),
        orient2d(
            DVec2::new(a.z, a.x),
            DVec2::new(b.z, b.x),
            DVec2::new(c.z, c.x),
        ),
        orient2d(
            DVec2::new(a.x, a.y),
            DVec2::new(b.x, b.y),
            DVec2::new(c.x, c.y),
        ),
    ]
}

/// Whether segment `p`–`q` crosses triangle `a`, `b`, `c` (which must not be degenerate), with
/// `p` and `q` moved together by the infinitesimal `(ε, ε², ε³)`: the segment then meets no edge
/// or vertex of any triangle and no end lies on a triangle's plane, so parities summed along
/// chains of segments between the same moved points are consistent.
pub(crate) fn segment_crosses_triangle(p: DVec3, q: DVec3, a: DVec3, b: DVec3, c: DVec3) -> bool {
    // det[a−x, b−x, c−x] = (a − x)·n with n = (b − a) × (c − a): moving x by δ adds −n·δ.
    let plane_tie = || {
        let n = normal_signs(a, b, c);
        let first = n.iter().copied().find(|&s| s != 0).unwrap_or(0);
        -first > 0
    };
    let side = |x: DVec3| match orient3d(a, b, c, x) {
        0 => plane_tie(),
        s => s > 0,
    };
    if side(p) == side(q) {
        return false;
    }
    // det[q−p, v−p, w−p] with p, q moved by δ gains δ·((q − p) × (w − v)).
    let u = (q, p);
    let edge_side = |v: DVec3, w: DVec3| match orient3d(q, v, w, p) {
        0 => {
            let (q, p) = u;
            // The components of (q − p) × (w − v), each as a sum of eight exact products.
            let components = [
                sign_of_product_sum(&[
                    (q.y, w.z),
                    (-q.y, v.z),
                    (-p.y, w.z),
                    (p.y, v.z),
                    (-q.z, w.y),
                    (q.z, v.y),
                    (p.z, w.y),
                    (-p.z, v.y),
                ]),
                sign_of_product_sum(&[
                    (q.z, w.x),
                    (-q.z, v.x),
                    (-p.z, w.x),
                    (p.z, v.x),
                    (-q.x, w.z),
                    (q.x, v.z),
                    (p.x, w.z),
                    (-p.x, v.z),
                ]),
                sign_of_product_sum(&[
                    (q.x, w.y),
                    (-q.x, v.y),
                    (-p.x, w.y),
                    (p.x, v.y),
                    (-q.y, w.x),
                    (q.y, v.x),
                    (p.y, w.x),
                    (-p.y, v.x),
                ]),
            ];
            components.iter().copied().find(|&s| s != 0).unwrap_or(0)
        }
        s => s,
    };
    let ab = edge_side(a, b);
    let bc = edge_side(b, c);
    let ca = edge_side(c, a);
    ab == bc && bc == ca && ab != 0
}

/// Whether edges `a`–`b` and `c`–`d` cross at a single point interior to both.
pub(crate) fn edges_cross_properly(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> bool {
    orient2d(a, b, c) * orient2d(a, b, d) < 0 && orient2d(c, d, a) * orient2d(c, d, b) < 0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orient3d_is_exact_far_from_the_origin() {
        let o = DVec3::splat(1e6);
        let (a, b, c) = (o, o + DVec3::X, o + DVec3::Y);
        assert_eq!(orient3d(a, b, c, o + DVec3::new(0.3, 0.3, 0.0)), 0);
        let above = DVec3::new(o.x + 0.3, o.y + 0.3, f64::from_bits(o.z.to_bits() + 1));
        let below = DVec3::new(o.x + 0.3, o.y + 0.3, f64::from_bits(o.z.to_bits() - 1));
        assert_eq!(orient3d(a, b, c, above), -orient3d(a, b, c, below));
        assert_ne!(orient3d(a, b, c, above), 0);
        // (b − a) × (c − a) = +z; d above it gives det[a−d, b−d, c−d] = (a − d)·n < 0.
        assert_eq!(orient3d(a, b, c, above), -1);
    }

    #[test]
    fn segments_through_triangle_edges_count_once() {
        // Two triangles sharing an edge; a segment through the shared edge crosses exactly one.
        let (a, b, c, d) = (DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::ONE.with_z(0.0));
        let p = DVec3::new(0.5, 0.5, -1.0);
        let q = DVec3::new(0.5, 0.5, 1.0);
        let count = [
            segment_crosses_triangle(p, q, a, b, c),
            segment_crosses_triangle(p, q, b, d, c),
        ]
        .iter()
        .filter(|&&x| x)
        .count();
        assert_eq!(count, 1);
        // Through a vertex shared by four triangles: once.
        let fan = [
            (DVec3::ZERO, DVec3::X, DVec3::Y),
            (DVec3::ZERO, DVec3::Y, DVec3::NEG_X),
            (DVec3::ZERO, DVec3::NEG_X, DVec3::NEG_Y),
            (DVec3::ZERO, DVec3::NEG_Y, DVec3::X),
        ];
        let (p, q) = (DVec3::NEG_Z, DVec3::Z);
        let count = fan
            .iter()
            .filter(|&&(a, b, c)| segment_crosses_triangle(p, q, a, b, c))
            .count();
        assert_eq!(count, 1);
    }

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
