//! One sample made ([`emit`]): the heightfield point with the quadric's outward normal, moved
//! onto the quadric by up to two Newton steps where rounding left it off ([`snap_to_surface`]).

use super::RegionContext;
use crate::regions::{BasicRegion, region_point};
use crate::sample_point::Sample;
use qcsg_quadric::{DVec3, Quadric};

/// Emits the sample over `(x, y)` with the quadric's outward normal there.
pub(super) fn emit(
    ctx: &RegionContext<'_>,
    region: &BasicRegion,
    x: f64,
    y: f64,
    radius: f64,
    out: &mut Vec<Sample>,
) {
    if let Some(position) = region_point(ctx.frame, &region.heightfield, region.sheet, x, y) {
        let mut point = (position, DVec3::ZERO);
        onto_quadric(ctx, &mut point, fallback_normal(ctx, region));
        out.push(surface_sample(region, point, radius));
    }
}

/// A heightfield point (the first of the pair) moved onto the quadric where needed
/// ([`snap_to_surface`]), with the quadric's outward normal there (the second), or `fallback`
/// where the gradient vanishes ([`fallback_normal`]). The fills compute the same in lanes
/// ([`crate::lanes`]) and come here for the points that need more.
///
/// The point is written only where it moves: assigning the pair for every point took a dozen
/// moves through the stack per sample, 5 % of the instructions of sampling a lone ball. The
/// normal takes the gradient's squared length from the snap's test.
#[inline]
pub(super) fn onto_quadric(
    ctx: &RegionContext<'_>,
    (position, normal): &mut (DVec3, DVec3),
    fallback: DVec3,
) {
    let q = ctx.quadric;
    let (gradient, length_squared) = snap_to_surface(q, position, (ctx.snap, ctx.apex));
    *normal = Quadric::normal_from_gradient_squared(gradient, length_squared).unwrap_or(fallback);
}

/// The normal of samples of `region` where the gradient vanishes: the sampling plane's axis on
/// the region's sheet.
pub(super) fn fallback_normal(ctx: &RegionContext<'_>, region: &BasicRegion) -> DVec3 {
    ctx.frame.axes[region.heightfield.normal_axis] * region.sheet
}

/// The sample of `region` at a point of its quadric with its normal there.
#[inline]
pub(super) fn surface_sample(
    region: &BasicRegion,
    (position, normal): (DVec3, DVec3),
    radius: f64,
) -> Sample {
    Sample {
        position,
        normal,
        quadric: region.quadric,
        term: region.term,
        radius,
        clip_list: 0,
    }
}

/// Most Newton steps that move a sample onto its quadric ([`snap_to_surface`]).
pub(super) const SNAP_STEPS: usize = 2;

/// The longest step [`snap_to_surface`] takes on a cone, as a fraction of the point's distance
/// from the apex: the steps it is for are of the size of rounding.
pub(super) const APEX_STEP: f64 = 1e-3;

/// `position` moved onto the quadric by Newton steps along the gradient, each kept only while it
/// lowers `|Q| / ‖∇Q‖` (at most [`SNAP_STEPS`], none once it is at most `settled`). The heightfield
/// point can be off by more than the required `1e-9` of the scene where its square root cancels (a
/// slab of half-width `1e-6`, the thin edge of a flat cone); the move is of that size, far below
/// any sample radius. Beside a cone's `apex`, where the gradient vanishes, a step could leap
/// across the literal that bounds the tip: a step longer than [`APEX_STEP`] of the distance to
/// the apex is not taken. Returns the gradient at the point it leaves, with its squared length.
///
/// Nearly every heightfield point is settled already; that test comes first, squared, without
/// the square root and division of the residual: those waited on the divider, busy with the
/// normal's, and took 4 % of sampling a lone ball.
#[inline]
pub(super) fn snap_to_surface(
    q: &Quadric,
    position: &mut DVec3,
    (settled, apex): (f64, Option<DVec3>),
) -> (DVec3, f64) {
    let (value, gradient) = (q.value(*position), q.gradient(*position));
    let length_squared = gradient.length_squared();
    if value * value <= settled * settled * length_squared {
        return (gradient, length_squared);
    }
    let (moved, gradient) = newton_steps(q, *position, (settled, apex), (value, gradient));
    *position = moved;
    (gradient, gradient.length_squared())
}

/// The Newton steps of [`snap_to_surface`] from `p`, where `Q` and `∇Q` are `value` and
/// `gradient`; apart, so that the common case inlines into the loops that emit samples.
#[cold]
#[inline(never)]
pub(super) fn newton_steps(
    q: &Quadric,
    mut p: DVec3,
    (settled, apex): (f64, Option<DVec3>),
    (mut value, mut gradient): (f64, DVec3),
) -> (DVec3, DVec3) {
    // `|Q| / ‖∇Q‖`, infinite where the gradient vanishes.
    let residual_of = |value: f64, g: DVec3| {
        let length = g.length();
        if length > 0.0 {
            value.abs() / length
        } else {
            f64::INFINITY
        }
    };
    let residual = |p: DVec3| {
        let (value, g) = (q.value(p), q.gradient(p));
        (residual_of(value, g), value, g)
    };
    let mut current = residual_of(value, gradient);
    for _ in 0..SNAP_STEPS {
        if current <= settled || !current.is_finite() {
            break;
        }
        let step = (value / gradient.length_squared()) * gradient;
        if apex.is_some_and(|apex| step.length() > APEX_STEP * p.distance(apex)) {
            break;
        }
        let next = p - step;
        let (after, next_value, next_gradient) = residual(next);
        if !(next.is_finite() && after < current) {
            break;
        }
        (p, current, value, gradient) = (next, after, next_value, next_gradient);
    }
    (p, gradient)
}
