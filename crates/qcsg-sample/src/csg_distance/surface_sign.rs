//! Whether a literal holds on all of a sampled curved surface, on none of it, or neither
//! ([`on_surface`]): by the remainder `L − λ q`, which equals `L` on the surface ("Offset
//! surfaces", "Touching surfaces" in [`super`]), with `λ` from the shared principal axes
//! ([`pencil`]) or, on an ellipsoid sharing none, from the S-lemma ([`s_lemma`]).

use super::tangency::{Ellipsoidal, Shape};
use qcsg_csg::Aabb;
use qcsg_csg::quadric_box::{self};
use qcsg_quadric::{DVec3, Quadric};

/// Whether `literal` holds on all of the surface of `q` inside `bounds` (`Some(true)`), on none of
/// it (`Some(false)`), or neither is known (`None`), for a `q` with a square part (not one
/// plane) ("Offset surfaces", "Touching surfaces"), with `q`'s shape and the literal's
/// principal axes where known. On the surface `q = 0`, so there the literal equals
/// `literal − λ q` for any `λ`. Tried are the `λ` that make the square part of that remainder
/// vanish (an offset: a plane or a constant is left) or semidefinite (surfaces that touch along
/// a curve, or nest without touching); the remainder is bounded over the box with a margin for
/// points that lie on `q` only up to rounding. Where the remainder reaches zero only within
/// that margin the surfaces touch: the literal holds (fails) on all the surface but a curve or
/// a point. A literal equal to `q` or to its complement leaves nothing and is `None` (other
/// rules handle those).
pub(super) fn on_surface(
    (q, shape): (&Quadric, &Shape),
    (literal, literal_axes): (&Quadric, Option<&[DVec3; 3]>),
    bounds: &Aabb,
) -> Option<bool> {
    const WEIGHTS: [f64; 6] = [1.0, 1.0, 1.0, 2.0, 2.0, 2.0];
    let (a, b) = (q.coefficients(), literal.coefficients());
    let dot = |u: &[f64; 10], v: &[f64; 10]| (0..6).map(|k| WEIGHTS[k] * u[k] * v[k]).sum::<f64>();
    let square = dot(&a, &a);
    if square.is_nan() || square <= 0.0 {
        return None;
    }
    let lambda = dot(&a, &b) / square;
    let residual: [f64; 10] = std::array::from_fn(|k| b[k] - lambda * a[k]);
    let offset = dot(&residual, &residual) <= 1e-18 * dot(&b, &b);
    let sampled = (q, shape.ellipsoidal.as_ref());
    // `q` about the literal's origin, where the literal's coefficients are exact.
    let moved = q.with_origin(literal.origin()).coefficients();
    let literal_moved = (literal, &moved);
    if offset && let Some(holds) = remainder_sign(sampled, literal_moved, (lambda, None), bounds) {
        return Some(holds);
    }
    // The literal above and below zero at points of the surface (in the box, for the rules
    // that bound it over the box; anywhere, for the S-lemma's, which are global): neither can
    // hold throughout. Most pairs are parts that cross, and this spares them the search.
    let margin = remainder_margin(q, literal_moved, 0.0, bounds);
    let signs = |tips: &mut dyn Iterator<Item = &DVec3>| {
        tips.fold((false, false), |(above, below), &tip| {
            let value = literal.value(tip);
            (above || value > margin, below || value < -margin)
        })
    };
    if signs(&mut shape.tips.iter().filter(|&&tip| bounds.contains(tip))) == (true, true) {
        return None;
    }
    let Some((basis, ratios)) = pencil(q, literal, [Some(&shape.axes), literal_axes]) else {
        return match signs(&mut shape.tips.iter()) {
            (true, true) => None,
            (above, below) => s_lemma(q, literal_moved, bounds, (!above, !below)),
        };
    };
    let tried = |ratio: f64| offset && (ratio - lambda).abs() <= 1e-12 * lambda.abs();
    ratios
        .into_iter()
        .filter(|&ratio| !tried(ratio))
        .find_map(|lambda| remainder_sign(sampled, literal_moved, (lambda, Some(&basis)), bounds))
}

/// A basis of eigenvectors that `A` and `B`, the square parts of `q` and `literal`, share
/// (one of the two `axes`), with the `λ` for which `B − λ A` is semidefinite: it is diagonal in
/// that basis, with entries `vᵀBv − λ vᵀAv`, so `λ` is one of the ratios `vᵀBv / vᵀAv`.
/// Coaxial cylinders, cones and balls share one, and a ball shares one with anything; other
/// pairs are `None`.
pub(super) fn pencil(
    q: &Quadric,
    literal: &Quadric,
    axes: [Option<&[DVec3; 3]>; 2],
) -> Option<([DVec3; 3], Vec<f64>)> {
    let (a, b) = (q.matrix_a(), literal.matrix_a());
    let form = quadratic_form;
    let (norm_a, norm_b) = (q.matrix_norm(), literal.matrix_norm());
    // Tight: parts turned by a transform share axes to rounding, while two ellipsoids `1e-9`
    // apart turned differently are off by about that much, and go to the S-lemma.
    let diagonalises = |basis: &[DVec3; 3]| {
        [(0, 1), (0, 2), (1, 2)].iter().all(|&(i, j)| {
            form(&a, basis[i], basis[j]).abs() <= 1e-12 * norm_a
                && form(&b, basis[i], basis[j]).abs() <= 1e-12 * norm_b
        })
    };
    let &basis = axes
        .into_iter()
        .flatten()
        .find(|basis| diagonalises(basis))?;
    let mut ratios: Vec<f64> = Vec::with_capacity(3);
    for v in basis {
        let across = form(&a, v, v);
        if across.abs() <= 1e-9 * norm_a {
            continue;
        }
        let ratio = form(&b, v, v) / across;
        let scale = ratio.abs().max(norm_b / norm_a);
        if ratio.is_finite() && ratios.iter().all(|r| (r - ratio).abs() > 1e-12 * scale) {
            ratios.push(ratio);
        }
    }
    Some((basis, ratios))
}

/// For an ellipsoid `q` and any `literal` without principal axes in common: whether some
/// `literal − λ q` is at most zero everywhere (the literal holds on all of `q`'s surface), or at
/// least zero everywhere (it fails there), up to the margin of [`remainder_sign`]. This is the
/// S-lemma: for such a pair one of these `λ` exists whenever the literal holds (fails) on the
/// whole surface. With `A` and `B` the square parts, `B − λ A` must be negative (positive)
/// definite, `λ` above (below) the largest (smallest) eigenvalue of `A^(−1/2) B A^(−1/2)`;
/// there the largest (smallest) value of the remainder is convex (concave) in `λ`, and a
/// golden-section search finds its best. An ellipsoid inside another turned differently,
/// touching it at its tips, is left out this way. `(may_hold, may_fail)`: which of the two the
/// literal's signs at the ellipsoid's tips leave open.
pub(super) fn s_lemma(
    q: &Quadric,
    (literal, moved): (&Quadric, &[f64; 10]),
    bounds: &Aabb,
    (may_hold, may_fail): (bool, bool),
) -> Option<bool> {
    // The surface is that of `−q` too: take the sign that makes `A` positive definite.
    let (low, high) = q.eigenvalue_bounds();
    let (q, moved) = match (low > 0.0, high < 0.0) {
        (true, _) => (*q, *moved),
        (_, true) => (q.negated(), moved.map(|c| -c)),
        _ => return None,
    };
    // The extreme `λ` of the pencil, in `q`'s axes scaled to make `A` the identity.
    let frame = q.eigen();
    let b = literal.matrix_a();
    let whiten: [DVec3; 3] = std::array::from_fn(|k| frame.vectors[k] / frame.values[k].sqrt());
    let c: [[f64; 3]; 3] =
        std::array::from_fn(|i| std::array::from_fn(|j| quadratic_form(&b, whiten[i], whiten[j])));
    let [smallest, _, largest] = qcsg_quadric::symmetric_eigen(&c).values;
    if !(smallest.is_finite() && largest.is_finite()) {
        return None;
    }
    let lb = literal.coefficients();
    // The largest value of `literal − λ q` over all of space, for `λ` where its square part is
    // negative definite (`holds`), or the negated smallest, where it is positive definite.
    let extreme = |lambda: f64, holds: bool| -> f64 {
        let r: [f64; 10] = std::array::from_fn(|k| lb[k] - lambda * moved[k]);
        let flip = if holds { -1.0 } else { 1.0 };
        // `R = xᵀMx + 2gᵀx + c`; with `N = ∓M` definite, the extreme is `c ± gᵀN⁻¹g`.
        let [a0, a1, a2, a3, a4, a5, g0, g1, g2, constant] = r.map(|v| flip * v);
        // `N⁻¹ = adj(N) / det N` for the symmetric `N = [[a0 a3 a4] [a3 a1 a5] [a4 a5 a2]]`.
        let adjugate = [
            [a1 * a2 - a5 * a5, a4 * a5 - a3 * a2, a3 * a5 - a4 * a1],
            [a4 * a5 - a3 * a2, a0 * a2 - a4 * a4, a3 * a4 - a0 * a5],
            [a3 * a5 - a4 * a1, a3 * a4 - a0 * a5, a0 * a1 - a3 * a3],
        ];
        let determinant = a0 * adjugate[0][0] + a3 * adjugate[0][1] + a4 * adjugate[0][2];
        let g = DVec3::new(g0, g1, g2);
        let value = -constant + quadratic_form(&adjugate, g, g) / determinant;
        // Definite: the leading minors are positive.
        let definite = a0 > 0.0 && adjugate[2][2] > 0.0 && determinant > 0.0;
        if definite && value.is_finite() {
            value
        } else {
            f64::INFINITY
        }
    };
    let spread =
        largest - smallest + (literal.matrix_norm() / q.matrix_norm()).max(f64::MIN_POSITIVE);
    let candidates = [(true, may_hold), (false, may_fail)];
    for holds in candidates.into_iter().filter(|c| c.1).map(|c| c.0) {
        // From just past the extreme `λ` outwards; the best is bracketed once the value grows.
        let (start, outwards) = if holds {
            (largest, 1.0)
        } else {
            (smallest, -1.0)
        };
        let at = |t: f64| extreme(start + outwards * t, holds);
        let (mut lo, mut hi) = (0.0, spread);
        while at(hi) < at(0.5 * hi) && hi < 1e6 * spread {
            hi *= 2.0;
        }
        let ratio = 0.5 * (5f64.sqrt() - 1.0);
        for _ in 0..GOLDEN_STEPS {
            let (m1, m2) = (hi - ratio * (hi - lo), lo + ratio * (hi - lo));
            if at(m1) <= at(m2) {
                hi = m2;
            } else {
                lo = m1;
            }
        }
        let best = 0.5 * (lo + hi);
        let lambda = start + outwards * best;
        let margin = remainder_margin(&q, (literal, &moved), lambda, bounds);
        let value = at(best);
        // Below zero by more than the margin everywhere, or touching zero within it.
        if value <= margin {
            return Some(holds);
        }
    }
    None
}

/// Steps of the golden-section search of [`s_lemma`]: they shrink its bracket to `1e-13`.
pub(super) const GOLDEN_STEPS: usize = 64;

/// `xᵀ M y` for a symmetric `M` given as rows.
pub(super) fn quadratic_form(m: &[[f64; 3]; 3], x: DVec3, y: DVec3) -> f64 {
    x.dot(DVec3::new(
        DVec3::from_array(m[0]).dot(y),
        DVec3::from_array(m[1]).dot(y),
        DVec3::from_array(m[2]).dot(y),
    ))
}

/// The sign of `literal − λ q` over the surface of `q` inside `bounds` ([`on_surface`]):
/// `Some(true)` where it is at most zero, `Some(false)` where it is at least zero, up to a
/// margin for rounding, but not both. `moved` is `q` about the literal's origin; `basis`, where
/// given, diagonalises the remainder's square part.
pub(super) fn remainder_sign(
    (q, solid): (&Quadric, Option<&Ellipsoidal>),
    (literal, moved): (&Quadric, &[f64; 10]),
    (lambda, basis): (f64, Option<&[DVec3; 3]>),
    bounds: &Aabb,
) -> Option<bool> {
    let b = literal.coefficients();
    let rest = Remainder::new(
        literal.origin(),
        std::array::from_fn(|k| b[k] - lambda * moved[k]),
    )?;
    let margin = remainder_margin(q, (literal, moved), lambda, bounds);
    let sign = |(low, high): (f64, f64)| match (high <= margin, low >= -margin) {
        // Zero throughout: the literal is `q` or its complement there.
        (true, true) => Some(None),
        (holds, fails) if holds != fails => Some(Some(holds)),
        _ => None,
    };
    // Interval arithmetic on the coefficients first (exact for a plane), then over the surface
    // of an ellipsoid, then in the basis that makes the square part a sum of squares.
    let tighter = |(low, high): (f64, f64), other: Option<(f64, f64)>| {
        other.map_or((low, high), |(l, h)| (low.max(l), high.min(h)))
    };
    let range = rest.range(bounds)?;
    if let Some(decided) = sign(range) {
        return decided;
    }
    let range = tighter(
        range,
        solid.and_then(|solid| range_on_ellipsoid(solid, &rest)),
    );
    if let Some(decided) = sign(range) {
        return decided;
    }
    let range = tighter(range, basis.and_then(|b| range_in_basis(&rest, b, bounds)));
    sign(range).flatten()
}

/// What rounding in `literal`, in `λ q` and in moving `q`'s origin to the literal's (`moved`)
/// can amount to over `bounds`: a tiny multiple of the sizes of their terms there (and of
/// `q`'s terms at the shift).
pub(super) fn remainder_margin(
    q: &Quadric,
    (literal, moved): (&Quadric, &[f64; 10]),
    lambda: f64,
    bounds: &Aabb,
) -> f64 {
    let b = literal.coefficients();
    let shift = (literal.origin() - q.origin()).length();
    let reach = bounds
        .corners()
        .iter()
        .fold(0.0f64, |m, c| m.max((*c - literal.origin()).length()));
    let size = |c: &[f64; 10], at: f64| {
        let square = c[..3].iter().map(|v| v.abs()).sum::<f64>()
            + 2.0 * c[3..6].iter().map(|v| v.abs()).sum::<f64>();
        let linear = 2.0 * c[6..9].iter().map(|v| v.abs()).sum::<f64>();
        square * at * at + linear * at + c[9].abs()
    };
    1e-12 * (size(&b, reach) + lambda.abs() * (size(moved, reach) + size(&q.coefficients(), shift)))
}

/// Where the sampled quadric is an ellipsoid (`solid`, its principal form), a range of
/// `rest`'s values over its surface: exact for the plane part of `rest` (a linear function's
/// extremes over an ellipsoid, as in [`Ellipsoidal::span`]), widened by what its square part,
/// if any, can add there. Over the surface rather than a box around it, this sees that a ball
/// touching the inside of another at one point lies inside it everywhere else.
pub(super) fn range_on_ellipsoid(solid: &Ellipsoidal, rest: &Remainder) -> Option<(f64, f64)> {
    // The surface is `Σ λ_k u_k² = −κ` in the frame, `u_k` along the axes from the centre.
    let frame = &solid.frame;
    if frame.eigenvalues.contains(&0.0) {
        return None;
    }
    // `rest = 2 gᵀ(x − o) + j + (x − o)ᵀ M (x − o)`: over the surface the plane part ranges over
    // its value at the centre ± `2 √(−κ Σ (g·u_k)² / λ_k)`, the square part at most `‖M‖` times
    // the farthest point's squared distance from `o`.
    let g = rest.linear();
    let middle = 2.0 * g.dot(frame.centre - rest.origin) + rest.constant();
    let across: f64 = (frame.axes.iter().zip(frame.eigenvalues))
        .map(|(axis, lambda)| g.dot(*axis).powi(2) / lambda)
        .sum();
    let half = 2.0 * (-frame.constant * across).max(0.0).sqrt();
    let semi_axis = (frame.eigenvalues.iter())
        .map(|lambda| (-frame.constant / lambda).sqrt())
        .fold(0.0, f64::max);
    let farthest = (frame.centre - rest.origin).length() + semi_axis;
    let spread = half + rest.matrix_norm() * farthest * farthest;
    spread
        .is_finite()
        .then_some((middle - spread, middle + spread))
}

/// A range of `q`'s values over `bounds` by interval arithmetic in `basis` over the box's
/// projections on it: exact for a square part that is a single square in that basis, as
/// `−z²`, whichever way it is turned.
pub(super) fn range_in_basis(
    q: &Remainder,
    basis: &[DVec3; 3],
    bounds: &Aabb,
) -> Option<(f64, f64)> {
    let centre = 0.5 * (bounds.min + bounds.max) - q.origin;
    let half = 0.5 * (bounds.max - bounds.min);
    let along = |v: DVec3| (v.dot(centre), v.abs().dot(half));
    let [(c0, h0), (c1, h1), (c2, h2)] = basis.map(along);
    let (centres, halves) = (DVec3::new(c0, c1, c2), DVec3::new(h0, h1, h2));
    let a = q.matrix_a();
    let form = |i: usize, j: usize| quadratic_form(&a, basis[i], basis[j]);
    let l = q.linear();
    let turned = Remainder::new(
        DVec3::ZERO,
        [
            form(0, 0),
            form(1, 1),
            form(2, 2),
            form(0, 1),
            form(0, 2),
            form(1, 2),
            basis[0].dot(l),
            basis[1].dot(l),
            basis[2].dot(l),
            q.constant(),
        ],
    )?;
    turned.range(&Aabb::new(centres - halves, centres + halves))
}

/// A remainder `literal − λ q` of [`remainder_sign`]: a quadric's coefficients about `origin`
/// (in [`Quadric::coefficients`]' order), without the eigenvalue bounds that building a
/// [`Quadric`] finds, which its ranges do not use (they took a tenth of the setup of a run on
/// scenes of many terms).
pub(super) struct Remainder {
    pub(super) origin: DVec3,
    pub(super) coefficients: [f64; 10],
}

impl Remainder {
    /// `None` if not finite.
    pub(super) fn new(origin: DVec3, coefficients: [f64; 10]) -> Option<Self> {
        (origin.is_finite() && coefficients.iter().all(|c| c.is_finite())).then_some(Self {
            origin,
            coefficients,
        })
    }

    pub(super) fn matrix_a(&self) -> [[f64; 3]; 3] {
        let [a, b, c, d, e, f, ..] = self.coefficients;
        [[a, d, e], [d, b, f], [e, f, c]]
    }

    pub(super) fn linear(&self) -> DVec3 {
        DVec3::from_slice(&self.coefficients[6..9])
    }

    pub(super) fn constant(&self) -> f64 {
        self.coefficients[9]
    }

    /// Frobenius norm of the square part.
    pub(super) fn matrix_norm(&self) -> f64 {
        let [a, b, c, d, e, f, ..] = self.coefficients;
        (a * a + b * b + c * c + 2.0 * (d * d + e * e + f * f)).sqrt()
    }

    /// A rigorous enclosure of its values over `bounds` ([`quadric_box::coefficient_range`]).
    pub(super) fn range(&self, bounds: &Aabb) -> Option<(f64, f64)> {
        quadric_box::coefficient_range(self.origin, &self.coefficients, bounds)
    }
}
