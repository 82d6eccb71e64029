//! When a sample covers a rectangle: coverage is by what a sample's splat draws.
//!
//! Wherever a rectangle counts as covered by an existing sample, that sample's disc must reach
//! all of it: its radius is at most `r` and is the radius a renderer draws it with, so a sample
//! within `r` whose reduced radius falls short has its radius grown (never beyond `r`,
//! [`grow_radius`]). Its normal must be less than 90° from the quadric's at every point of the
//! rectangle (a splat draws only its own side: a sample on one face of a thin slab, the same
//! quadric, draws nothing on the other): the normal turns by at most `asin(bend · L)` within `L`
//! of the rectangle's centre ([`SurfacePoint::faces`]), which the sample's normal must leave
//! room for. Testing the centre's normal alone let a sample on a small ball's far sheet cover a
//! rectangle as large as the ball at a radius near its size. A sample of another term counts
//! only if the rectangle's part in its own term lies inside that term (a splat is clipped to its
//! term; literals both terms hold are skipped). Without the last two rules a splat image shows
//! gaps along walls' rims (`examples/customizer_box.qcsg`).

use crate::sample_point::Sample;
use qcsg_csg::Dnf;
use qcsg_quadric::{DVec3, Quadric};

/// Whether one of the samples `out[i]` for `i` in `indices` that `draws` accepts covers the
/// ball of radius `extent` around `point` with a radius of at most `radius` ([`cover_by`]);
/// that sample's radius grows to reach it if need be.
pub(super) fn grow_to_cover(
    out: &mut [Sample],
    indices: impl Iterator<Item = usize>,
    point: SurfacePoint,
    extent: f64,
    radius: f64,
    draws: impl Fn(&Sample) -> bool,
) -> bool {
    let candidates = indices.map(|i| (i as u32, &out[i]));
    match cover_by(candidates, point, extent, radius, draws) {
        Some((i, needed)) => {
            grow_radius(out, i, needed);
            true
        }
        None => false,
    }
}

/// Grows sample `i`'s radius to `needed` (never shrinks it).
pub fn grow_radius(samples: &mut [Sample], i: u32, needed: f64) {
    if let Some(sample) = samples.get_mut(i as usize) {
        sample.radius = sample.radius.max(needed);
    }
}

/// Whether the part of the ball of radius `extent` around `p` that lies in term `own` lies
/// inside every literal of `sample`'s term but its own quadric (by the conservative distance),
/// so that the sample's clipping keeps it. Literals both terms hold are skipped: inside term
/// `own` they hold anyway.
pub(super) fn inside_term(dnf: &Dnf, sample: &Sample, own: u32, p: DVec3, extent: f64) -> bool {
    let (Some(term), Some(own)) = (
        dnf.terms.get(sample.term as usize),
        dnf.terms.get(own as usize),
    ) else {
        return false;
    };
    term.literals.iter().all(|&j| {
        j == sample.quadric
            || own.literals.contains(&j)
            || dnf
                .quadrics
                .get(j as usize)
                .is_some_and(|q| q.quadric.conservative_distance(p) <= -extent)
    })
}

/// A point of a quadric's surface with its outward unit normal, and how fast the normal turns
/// around it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    /// The point.
    pub position: DVec3,
    /// The quadric's outward unit normal there.
    pub normal: DVec3,
    /// Within distance `d` of the point, the quadric's normal is less than `asin(bend · d)`
    /// from [`Self::normal`]: `∇Q(p) = ∇Q(c) + 2 A (p − c)`, so `bend = 2 ‖A‖ / ‖∇Q(c)‖`.
    pub bend: f64,
}

impl SurfacePoint {
    /// `position` with `normal`, on a surface taken as flat around it (`bend = 0`).
    pub fn new(position: DVec3, normal: DVec3) -> Self {
        Self {
            position,
            normal,
            bend: 0.0,
        }
    }

    /// The point of `quadric` at `position`; `None` where the normal is undefined (a cone's
    /// apex).
    pub fn on(quadric: &Quadric, position: DVec3) -> Option<Self> {
        let gradient = quadric.gradient(position);
        let (lower, upper) = quadric.eigenvalue_bounds();
        Some(Self {
            position,
            normal: Quadric::normal_from_gradient(gradient)?,
            // A hair more, for the rounding of the bound itself.
            bend: 2.0 * lower.abs().max(upper) / gradient.length() * (1.0 + 1e-12),
        })
    }

    /// Whether `sample` faces the same side ([`Sample::same_side`]) as every point of the
    /// quadric within `extent` of this one: its normal is less than `90° − asin(bend · extent)`
    /// from this point's, that is `n · normal > bend · extent`.
    pub fn faces(&self, sample: &Sample, extent: f64) -> bool {
        let spread = self.bend * extent;
        spread < 1.0 && sample.normal.dot(self.normal) > spread
    }
}

/// Whether a sample `offset` from a point may cover the ball of radius `extent` around it
/// with a radius of at most `radius`: passed by every sample that [`cover_by`] can take, with a
/// margin for rounding, and without a square root. Most candidates fail it.
pub(super) fn may_cover(offset: DVec3, extent: f64, radius: f64) -> bool {
    let reach = radius - extent;
    reach >= 0.0 && offset.length_squared() <= reach * reach * (1.0 + 1e-9)
}

/// Of `samples` that face the same side as every point of the ball of radius `extent` around
/// `point` ([`SurfacePoint::faces`]), the first whose disc already covers that ball
/// (`|position − point| + extent ≤ its radius`), else the nearest that would with a radius of
/// at most `radius`: its index and the radius it needs. Only samples `draws` accepts count; it
/// is asked last, of the samples near enough, as it can cost more than the distance.
pub fn cover_by<'s>(
    samples: impl Iterator<Item = (u32, &'s Sample)>,
    point: SurfacePoint,
    extent: f64,
    radius: f64,
    draws: impl Fn(&Sample) -> bool,
) -> Option<(u32, f64)> {
    let mut nearest: Option<(u32, f64)> = None;
    for (i, sample) in samples {
        let offset = sample.position - point.position;
        if !may_cover(offset, extent, radius) {
            continue;
        }
        if !point.faces(sample, extent) {
            continue;
        }
        let needed = offset.length() + extent;
        if needed <= sample.radius {
            if draws(sample) {
                return Some((i, sample.radius));
            }
        } else if needed <= radius && nearest.is_none_or(|(_, best)| needed < best) && draws(sample)
        {
            nearest = Some((i, needed));
        }
    }
    nearest
}
