//! Cone apices: a ring of samples that covers what the subdivision gives up around one.
//!
//! At a cone's apex the gradient vanishes and the normal takes every direction of the cone's
//! normal cone: no heightfield has bounded distortion there, so the region decomposition gives
//! up the rectangles next to the apex after [`crate::regions::MAX_REGION_DEPTH`] splits, and the
//! subdivision gives up rectangles a hair from it (`examples/quadric_primitives.qcsg`). Both lie within a distance `ε` of the apex `A`, far below the radius `r`.
//!
//! The rectangles are settled at the apex itself with eq. 22 of their literal:
//! - `d(A) > ε`: no point of the quadric within `ε` of `A` is on the CSG surface (eq. 22's
//!   positive claim), so none of the rectangles is;
//! - `d(A) < −(ρ + ε)`: every point of the quadric within `ρ + ε` of `A` is on the surface
//!   (the negative claim). Samples are placed at `ρ ≤ r/2` from `A` along `N` rulings of each
//!   nappe, with the radius `ρ + ε`, which reaches every point within `ε` of `A`. `ρ` is `r/2`,
//!   or a quarter of that and so on (while above `4ε`) where the part is smaller than the
//!   radius and a ring that far out leaves it (`RING_TRIES`). In the cone's
//!   principal frame `λ₁x² + λ₂y² − λ₃z² = 0` the ruling at parameter `φ` is
//!   `(cos φ / √λ₁, sin φ / √λ₂, ±1 / √λ₃)` and its normal is along
//!   `g(φ) = (√λ₁ cos φ, √λ₂ sin φ, ∓√λ₃)`, the same all along it; two rulings of one nappe
//!   at most `Δ` apart in `φ` have `g·g' ≥ (λ₁+λ₂)/2 · cos Δ − |λ₁−λ₂|/2 + λ₃`. With `Δ = π/N`
//!   and the smallest power of two `N` that makes this positive, every point within `ε` of `A`
//!   faces the same side as the ring sample on the nearest ruling of its nappe, as the
//!   guarantee asks ([`crate::Sample::same_side`]);
//! - otherwise the surface's border passes within `ρ` of the apex, as where a cone's apex is
//!   the tip of a part (`cylinder(h, r1, r2 = 0)` ends with a plane through the apex). Each
//!   nappe is then settled on its own: it is covered if eq. 22 puts every ring point of it on
//!   the surface (the ring samples reach every point of the nappe within `ε` of `A`, as above),
//!   and it is off the surface if a literal of the term fails on all of it near `A`: a literal
//!   `L` with `L(A) ≈ 0` grows along every ruling `A + t u(φ)` of the nappe at least at the rate
//!   `min_φ ∇L(A)·u(φ)` (exact, a sinusoid in `φ`), which bounds its square part within `ε`.
//!   The rectangles stay unresolved if either nappe is neither.

use std::f64::consts::PI;

use qcsg_quadric::{DVec3, PrincipalFrame, Quadric};

use crate::csg_distance::CsgDistance;
use crate::sample_point::Sample;

/// Most rulings per nappe of an apex ring; a cone too flat for this many is left alone.
const MAX_RULINGS: usize = 256;

/// Distances from the apex at which a ring is tried: `r/2`, then a quarter of the last each
/// time (while above four times the reach of the rectangles).
const RING_TRIES: usize = 6;

/// What became of the rectangles given up around one apex.
#[derive(Debug, PartialEq)]
pub enum Settled {
    /// None of them is on the CSG surface.
    Off,
    /// All are covered by these samples.
    Covered(Vec<Sample>),
    /// Neither could be shown.
    Unresolved,
}

/// Settles the rectangles of literal `quadric` of `term` given up within `reach` of its apex
/// (the centre of `frame`, a cone's), with `distance` its eq. 22 and `others` the term's other
/// literals, at sample radius `radius`.
pub fn settle(
    (quadric, term): (u32, u32),
    (q, frame): (&Quadric, &PrincipalFrame),
    (distance, others): (&CsgDistance, &[Quadric]),
    reach: f64,
    radius: f64,
) -> Settled {
    let apex = frame.centre;
    if reach.is_nan() || reach > 0.25 * radius {
        return Settled::Unresolved;
    }
    let d = distance.distance(apex);
    if d > reach {
        return Settled::Off;
    }
    let Some(cone) = Cone::new(frame) else {
        return Settled::Unresolved;
    };
    // Rings at `r/2` from the apex, then closer, for a part smaller than the radius.
    let alongs = std::iter::successors(Some(0.5 * radius), |a| Some(0.25 * a))
        .take_while(|&along| along > 4.0 * reach)
        .take(RING_TRIES);
    let mut samples = Vec::new();
    for nappe in [1.0, -1.0] {
        let mut placed = false;
        for along in alongs.clone() {
            let Some(points) = cone.ring(q, nappe, along) else {
                return Settled::Unresolved;
            };
            let whole = d < -(along + reach);
            if whole || points.iter().all(|(p, _)| distance.distance(*p) < 0.0) {
                samples.extend(points.into_iter().map(|(position, normal)| Sample {
                    position,
                    normal,
                    quadric,
                    term,
                    radius: (along + reach).min(radius),
                    clip_list: 0,
                }));
                placed = true;
                break;
            }
        }
        if !placed && !others.iter().any(|l| cone.misses(l, nappe, reach, radius)) {
            return Settled::Unresolved;
        }
    }
    if samples.is_empty() {
        Settled::Off
    } else {
        Settled::Covered(samples)
    }
}

/// The ring of both nappes of cone `q` at distance `along` from its apex, with the outward
/// normals there (see the module doc); `None` unless `q` is a cone that rings can cover.
pub fn ring(q: &Quadric, along: f64) -> Option<Vec<(DVec3, DVec3)>> {
    let frame = q.frame();
    let cone = Cone::new(&frame)?;
    let mut out = cone.ring(q, 1.0, along)?;
    out.extend(cone.ring(q, -1.0, along)?);
    Some(out)
}

/// A cone in its principal frame: `a x² + b y² − c z² = 0` along the world directions `axes`
/// (the last one its axis), up to the sign of the whole, with `a`, `b` and `c` positive.
struct Cone {
    apex: DVec3,
    axes: [DVec3; 3],
    /// `1/√a`, `1/√b`, `1/√c`.
    scales: [f64; 3],
    /// Rulings per nappe that a ring needs (see the module doc).
    rulings: usize,
}

impl Cone {
    /// The cone of `frame`; `None` unless its quadric is one, and one whose rings can cover
    /// every direction with at most [`MAX_RULINGS`] rulings.
    fn new(frame: &PrincipalFrame) -> Option<Self> {
        let lambda = frame.eigenvalues;
        // The axis is the eigenvalue of the other sign; flip the signs so that it is negative.
        let flip = match lambda.iter().filter(|&&l| l < 0.0).count() {
            1 => 1.0,
            2 => -1.0,
            _ => return None,
        };
        let axis = (0..3).find(|&k| flip * lambda[k] < 0.0)?;
        let (i, j) = ((axis + 1) % 3, (axis + 2) % 3);
        let (a, b, c) = (flip * lambda[i], flip * lambda[j], -flip * lambda[axis]);
        if !(a > 0.0 && b > 0.0 && c > 0.0) || frame.constant != 0.0 {
            return None;
        }
        let rulings = (2..)
            .map(|k| 1usize << k)
            .take_while(|&n| n <= MAX_RULINGS)
            .find(|&n| (a + b) * (PI / n as f64).cos() - (a - b).abs() + 2.0 * c > 0.0)?;
        Some(Self {
            apex: frame.centre,
            axes: [i, j, axis].map(|k| frame.axes[k]),
            scales: [a, b, c].map(|v| 1.0 / v.sqrt()),
            rulings,
        })
    }

    /// The direction of the ruling at parameter `phi` of nappe `nappe` (`±1`), in the world:
    /// `(cos φ / √a, sin φ / √b, ±1 / √c)` in the frame.
    fn ruling(&self, phi: f64, nappe: f64) -> DVec3 {
        let [i, j, axis] = self.axes;
        let [si, sj, sa] = self.scales;
        (phi.cos() * si) * i + (phi.sin() * sj) * j + (nappe * sa) * axis
    }

    /// Points of nappe `nappe` at distance `along` from the apex, on [`Self::rulings`] rulings,
    /// with the outward normals of `q` there.
    fn ring(&self, q: &Quadric, nappe: f64, along: f64) -> Option<Vec<(DVec3, DVec3)>> {
        (0..self.rulings)
            .map(|m| {
                let phi = 2.0 * PI * m as f64 / self.rulings as f64;
                let position = self.apex + along * self.ruling(phi, nappe).normalize();
                Some((position, q.normal(position)?))
            })
            .collect()
    }

    /// Whether `literal` fails on every point of nappe `nappe` within `reach` of the apex but
    /// those within `1e-9 radius` of it, which the guarantee's tolerance (`1e-9` of the
    /// diagonal) does not tell from the apex (see the module doc): along the ruling
    /// `A + t u(φ)` the literal is `L(A) + t ∇L(A)·u(φ) + t² uᵀ A_L u`, whose linear part is at
    /// least `t m` with `m = min_φ ∇L(A)·u(φ)`; it fails once `m > 0`, the square part (at most
    /// `t² ‖A_L‖ |u|²`) stays below half of it up to where the ruling leaves the ball, and
    /// `L(A)`, zero up to rounding, is made up for that close to the apex.
    fn misses(&self, literal: &Quadric, nappe: f64, reach: f64, radius: f64) -> bool {
        let gradient = literal.gradient(self.apex);
        let [si, sj, sa] = self.scales;
        let [i, j, axis] = self.axes;
        let (alpha, beta, gamma) = (
            gradient.dot(i) * si,
            gradient.dot(j) * sj,
            gradient.dot(axis) * sa,
        );
        let least_rate = nappe * gamma - alpha.hypot(beta);
        // |u|² lies between these: the ruling leaves the ball by `t = reach / |u|_min`.
        let (shortest, longest) = (si.min(sj).powi(2) + sa * sa, si.max(sj).powi(2) + sa * sa);
        let (lower, upper) = literal.eigenvalue_bounds();
        let square = lower.abs().max(upper.abs()) * longest;
        let t = reach / shortest.sqrt();
        let (value, error) = literal.value_with_error(self.apex);
        let close = 1e-9 * radius / longest.sqrt();
        least_rate > 0.0
            && 2.0 * square * t < least_rate
            && value - error >= -0.5 * least_rate * close
    }
}
