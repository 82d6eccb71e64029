//! What one cell is, from its corner distances ([`classify`]): on the surface, off it, a small
//! rectangle settled by one sample, or to be split.
//!
//! **Border regions.** A basic region across the border between two sampling planes' regions
//! is only the part of its rectangle where its plane is the best: sub-rectangles and fill cells
//! where another plane is the best throughout are dropped before anything else
//! ([`BasicRegion::owns_none_of`]), since that plane's regions hold those surface points.
//!
//! **Corner discs.** They cover the rectangle when each of its quarters lies in one of them
//! ([`discs_cover`]: one reaching the opposite corner, or each reaching the centre, are the
//! simplest cases).
//!
//! **Small regions.** A rectangle whose world footprint `δ_max · diagonal` is at most `r` needs
//! only one sample on the CSG surface anywhere inside it: the first corner with `d < 0` gets it
//! (the paper's special case), else the centre if `d(centre) < 0`; where `d(centre) > 0`, its disc
//! alone proves the rectangle off the surface once it reaches the corners (every point lies
//! within half the diagonal of the centre): beside a feature curve the corners are near the
//! curve and their discs small. The sample's radius is reduced to the footprint (§6.1: less
//! overdraw, same guarantee). Every point of a rectangle lies within half its footprint of its
//! centre, so one of footprint up to `2r` that the corner discs do not classify is covered by a
//! sample at its centre when `d(centre) < 0`, and split otherwise (unless the centre's disc
//! reaches the corners). Most such rectangles lie along feature curves. If one of the last
//! samples of the same quadric and term is near enough to cover a small rectangle with a radius
//! of at most `r`, no new sample is made and that sample's radius grows to reach it: along a
//! feature curve one sample often covers several small rectangles. The look-back reaches into
//! the earlier regions of the region's block (consecutive regions, [`crate::blocks`]): around a
//! cone's apex the region decomposition leaves thousands of tiny regions, one ring per level of
//! refinement, which would otherwise each take a sample of their own.

use super::RegionContext;
use super::cell::{Cell, Walk, cell_distortion, corner, in_one_quadrant, plane_values};
use super::cover::{SurfacePoint, grow_to_cover, may_cover};
use super::emit::emit;
use super::emitted::Emitted;
use super::fill::fill;
use crate::regions::{BasicRegion, Rect, region_point};
use crate::sample_point::Sample;
use qcsg_quadric::DVec3;

/// What a cell is after its corner distances are looked at.
pub(super) enum Verdict {
    /// Proven off the surface.
    Discarded,
    /// Proven on the surface and filled with samples.
    Filled,
    /// Small, with one sample on the surface.
    Small,
    /// Small, and its corners settle nothing: [`at_centre`] may still.
    Unproven { footprint: f64, distortion: f64 },
    /// To be split; its footprint is larger than `r`.
    Split { footprint: f64 },
}

/// Classifies one cell, emitting its samples when it is on the surface; `out[first..]` are the
/// samples that may cover its small rectangles (of the region's block, or of the refinement,
/// so far).
pub(super) fn classify(
    ctx: &RegionContext<'_>,
    region: &BasicRegion,
    cell: &Cell,
    (out, first): (&mut Emitted, usize),
    (memo, stats): Walk<'_>,
) -> Verdict {
    stats.rectangles += 1;
    let rect = cell.rect;
    let distortion = cell_distortion(region, cell);
    let diagonal = rect.diagonal();
    // The discs of radius `|d| / δ` over the rectangle, as discs of radius `|d|` over it
    // stretched by `δ`: two products instead of four divisions.
    let stretched = (distortion * rect.width(), distortion * rect.height());
    let covered = discs_cover(stretched, cell.d.map(f64::abs));
    if covered && cell.d.iter().all(|&d| d > 0.0) {
        stats.discarded += 1;
        return Verdict::Discarded;
    }
    let footprint = distortion * diagonal;
    if footprint > ctx.radius {
        let on = covered && cell.d.iter().all(|&d| d < 0.0);
        let slopes = in_one_quadrant(&rect).then_some(cell.slope);
        if on && fill(ctx, region, (&rect, cell.owned), (distortion, slopes), out) {
            stats.filled += 1;
            return Verdict::Filled;
        }
        // Every point of the rectangle is within half its footprint of its centre, so up to
        // `2r` one sample at the centre covers it: along a feature curve that halves the
        // samples the rectangles beside it take.
        if footprint <= 2.0 * ctx.radius {
            if covered_by_recent(ctx, region, &rect, footprint, &mut out[first..]) {
                stats.small += 1;
                return Verdict::Small;
            }
            if let Some(verdict) = at_centre(ctx, region, (&rect, distortion), out, (memo, stats)) {
                return verdict;
            }
        }
        return Verdict::Split { footprint };
    }
    if let Some(k) = cell.d.iter().position(|&d| d < 0.0) {
        if covered_by_recent(ctx, region, &rect, footprint, &mut out[first..]) {
            stats.small += 1;
            return Verdict::Small;
        }
        let (x, y) = corner(&rect, k);
        emit(ctx, region, x, y, footprint.min(ctx.radius), out);
        stats.small += 1;
        return Verdict::Small;
    }
    Verdict::Unproven {
        footprint,
        distortion,
    }
}

/// What eq. 22 at the centre of a rectangle of footprint up to `2r` settles: every point lies
/// within half the diagonal of the centre, so a sample there covers it when the centre is on
/// the surface (`Small`), and the centre's disc proves it off the surface when it reaches the
/// corners (`Discarded`).
pub(super) fn at_centre(
    ctx: &RegionContext<'_>,
    region: &BasicRegion,
    (rect, distortion): (&Rect, f64),
    out: &mut Vec<Sample>,
    (memo, stats): Walk<'_>,
) -> Option<Verdict> {
    let half_diagonal = 0.5 * rect.diagonal();
    let (cx, cy) = rect.centre();
    let (centre, _) = plane_values(ctx, region, cx, cy, (memo, stats));
    if centre < 0.0 {
        let radius = (distortion * half_diagonal).min(ctx.radius);
        emit(ctx, region, cx, cy, radius, out);
        stats.small += 1;
        return Some(Verdict::Small);
    }
    if centre / distortion >= half_diagonal {
        stats.discarded += 1;
        return Some(Verdict::Discarded);
    }
    None
}

/// Whether the discs of radii `radii` around the corners of a rectangle `w × h` (in [`corner`]
/// order) cover it: each quadrant (the quarter at corner `k`) lies in some corner's disc,
/// corner `j`'s holding all of it when it reaches the quadrant's farthest vertex from `j`. This
/// takes in the rules "one disc reaches the opposite corner" and "every disc reaches the
/// centre", and also settles a rectangle where the discs at one end reach past the middle: on
/// the examples at 1 % of the diagonal, 4 % fewer queries and 1 % fewer samples (larger
/// rectangles filled).
pub(super) fn discs_cover((w, h): (f64, f64), radii: [f64; 4]) -> bool {
    let reaches = |j: usize, k: usize| {
        let dx = if (j ^ k) & 1 == 0 { 0.5 * w } else { w };
        let dy = if (j ^ k) & 2 == 0 { 0.5 * h } else { h };
        radii[j] * radii[j] >= dx * dx + dy * dy
    };
    (0..4).all(|k| (0..4).any(|j| reaches(j, k)))
}

/// Samples [`covered_by_recent`] looks back over.
pub(super) const RECENT_SAMPLES: usize = 16;

/// The surface point over the centre of `rect`, with the quadric's normal there; `None` where
/// there is no surface or the normal is undefined (a cone's apex).
pub(super) fn centre_point(
    ctx: &RegionContext<'_>,
    region: &BasicRegion,
    rect: &Rect,
) -> Option<SurfacePoint> {
    let (x, y) = rect.centre();
    let position = region_point(ctx.frame, &region.heightfield, region.sheet, x, y)?;
    SurfacePoint::on(ctx.quadric, position)
}

/// Whether one of the last samples of `out` (those of the region's block, or of the
/// refinement, so far) of the region's quadric and term covers the whole rectangle (of
/// footprint `footprint`), its radius grown to reach it if need be (never beyond `r`):
/// depth-first order puts a small rectangle's neighbours among them, and along a feature curve
/// one sample then covers several small rectangles instead of each taking its own.
pub(super) fn covered_by_recent(
    ctx: &RegionContext<'_>,
    region: &BasicRegion,
    rect: &Rect,
    footprint: f64,
    out: &mut [Sample],
) -> bool {
    let (x, y) = rect.centre();
    let Some(position) = region_point(ctx.frame, &region.heightfield, region.sheet, x, y) else {
        return false;
    };
    covered_near(ctx, region, (position, 0.5 * footprint), out)
}

/// Whether one of the last samples of `out` covers, with a radius of at most `r` (grown to
/// it), every point within `extent` of `position`, a point of the region's quadric.
pub(super) fn covered_near(
    ctx: &RegionContext<'_>,
    region: &BasicRegion,
    (position, extent): (DVec3, f64),
    out: &mut [Sample],
) -> bool {
    let recent = out.len().saturating_sub(RECENT_SAMPLES)..out.len();
    // Where no recent sample is near enough (most rectangles), the centre needs no normal.
    let near = |s: &Sample| may_cover(s.position - position, extent, ctx.radius);
    if !out[recent.clone()].iter().any(near) {
        return false;
    }
    let Some(centre) = SurfacePoint::on(ctx.quadric, position) else {
        return false;
    };
    // A sample of another term is clipped to that term, and might draw nothing here.
    let own_quadric = |s: &Sample| s.quadric == region.quadric && s.term == region.term;
    let recent = recent.rev();
    grow_to_cover(out, recent, centre, extent, ctx.radius, own_quadric)
}

/// The two halves of a cell across its longer edge, with their corner distances; `None` when
/// floating point cannot make them smaller.
pub(super) fn split(
    ctx: &RegionContext<'_>,
    region: &BasicRegion,
    cell: &Cell,
    (memo, stats): Walk<'_>,
) -> Option<(Cell, Cell)> {
    let rect = cell.rect;
    let (low, high, along_x) = rect.split_longest();
    if low.diagonal() >= rect.diagonal() || high.diagonal() >= rect.diagonal() {
        return None;
    }
    // The two new corners, shared by both halves: `k0` (`k1`) of the low half is `j0` (`j1`)
    // of the high one.
    let ((x0, y0), (x1, y1), [k0, k1], [j0, j1]) = if along_x {
        ((low.x.1, rect.y.0), (low.x.1, rect.y.1), [1, 3], [0, 2])
    } else {
        ((rect.x.0, low.y.1), (rect.x.1, low.y.1), [2, 3], [0, 1])
    };
    let m0 = plane_values(ctx, region, x0, y0, (memo, stats));
    let m1 = plane_values(ctx, region, x1, y1, (memo, stats));
    let (mut low_cell, mut high_cell) = (*cell, *cell);
    low_cell.rect = low;
    high_cell.rect = high;
    for (k, j, (d, slope)) in [(k0, j0, m0), (k1, j1, m1)] {
        (low_cell.d[k], low_cell.slope[k]) = (d, slope);
        (high_cell.d[j], high_cell.slope[j]) = (d, slope);
    }
    Some((low_cell, high_cell))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(4096))]

        /// Where [`discs_cover`] says so, every point of a fine grid over the rectangle lies in
        /// a corner disc (a grid point of the rectangle's own outline included).
        #[test]
        fn corner_discs_cover_what_they_claim(
            (x0, y0) in (-10.0f64..10.0, -10.0f64..10.0),
            (w, h) in (0.01f64..5.0, 0.01f64..5.0),
            fractions in proptest::array::uniform4(0.3f64..1.1),
        ) {
            // Radii around the diagonal, where whether the discs cover is in question.
            let rect = Rect { x: (x0, x0 + w), y: (y0, y0 + h) };
            let radii = fractions.map(|f| f * rect.diagonal());
            if discs_cover((w, h), radii) {
                const STEPS: u32 = 40;
                for i in 0..=STEPS {
                    for j in 0..=STEPS {
                        let x = x0 + w * f64::from(i) / f64::from(STEPS);
                        let y = y0 + h * f64::from(j) / f64::from(STEPS);
                        let inside = (0..4).any(|k| {
                            let (cx, cy) = corner(&rect, k);
                            (x - cx).hypot(y - cy) <= radii[k] * (1.0 + 1e-12)
                        });
                        prop_assert!(inside, "({x}, {y}) in no disc of {radii:?} over {rect:?}");
                    }
                }
            }
        }

        /// The rule claims at least what the two it replaces did.
        #[test]
        fn corner_discs_cover_the_old_cases(
            (w, h) in (0.01f64..5.0, 0.01f64..5.0),
            radii in proptest::array::uniform4(0.0f64..8.0),
        ) {
            let rect = Rect { x: (0.0, w), y: (0.0, h) };
            let diagonal = rect.diagonal();
            let old = radii.iter().any(|&r| r >= diagonal)
                || radii.iter().all(|&r| r >= 0.5 * diagonal);
            prop_assert!(!old || discs_cover((w, h), radii));
        }
    }
}
