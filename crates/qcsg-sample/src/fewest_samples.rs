//! The fewest samples a run can hold, known before it samples anything: a run whose radius is
//! far below the scene's size is refused at once ([`SampleError::TooManySamples`]) instead of
//! filling memory up to [`SampleLimits::max_samples`] first.
//!
//! The first pass leaves every point of a region's rectangle that is on the CSG surface in a
//! leaf that is either deferred to the second pass (a rectangle of footprint at most `r`, or
//! one too small to halve in floating point) or covered by a sample of the same literal of the
//! same term (a patch) within `r` in space: a fill's (each point within `r / δ` of one on the
//! plane, so within `r` of it on the surface), its own at a corner or the centre, or a recent
//! one whose radius grows to reach it. A sample lies within `ε` of its heightfield point
//! (Newton steps move it onto the quadric: at most about `1.2e-7` of the diagonal, see the
//! crate docs; `ε` is taken as `1e-6` of it). So, with `ρ = r + ε`:
//! - on one sampling plane and sheet, a sample reaches at most `π ρ²` of the plane: the frame
//!   is orthonormal, so a point's plane coordinates lie within `ρ` of the sample's projection;
//! - over all three planes and both sheets, whose owned parts are disjoint pieces of the
//!   surface, a sample reaches at most `4 π ρ²` of the quadric (a line meets a quadric in at
//!   most two points unless it lies in it; by Crofton's formula that bounds its area inside a
//!   ball as the ball's sphere is bounded), and an area on the plane is at most that on the
//!   surface;
//! - a deferred rectangle is smaller than either, or is too small to halve (sides within two
//!   units in the last place of its coordinates), which then counts as the unit.
//!
//! The samples and deferred rectangles of a patch, which count towards the limit
//! ([`crate::budget`]) and belong to no other patch, then number at least its proven area on
//! any one plane and sheet over `π ρ²`, and at least its proven area on all over `4 π ρ²`.
//!
//! The proven area comes from eq. 22 at the centres of a grid of pieces of each region's
//! rectangle: where it is `d < 0`, every point within `|d| / δ_max` of the centre on the plane
//! is on the surface (the subdivision's own argument), and the square inside that disc counts
//! where it lies in the piece and the region owns it (border regions own only part of their
//! rectangle). In a region all on the surface
//! ([`crate::csg_distance::NearDistance::everywhere_on_surface`]) every piece counts whole,
//! without a query. The queries are not counted in the run's statistics, and the bound is only
//! sought when the regions' estimated work ([`crate::blocks`]) exceeds the limit; a run within
//! the limit gives the same output with it as without. The bound is below the samples a run takes by
//! a factor of a few (docs/compiler.md, "Limits"), so a radius whose run would cross the limit
//! by less than that runs until the limit stops it ([`crate::budget`]).
//!
//! [`SampleError::TooManySamples`]: crate::SampleError::TooManySamples
//! [`SampleLimits::max_samples`]: crate::SampleLimits::max_samples

use qcsg_quadric::PrincipalFrame;
use rayon::prelude::*;

use crate::csg_distance::NearDistance;
use crate::regions::{BasicRegion, Rect, region_point};
use crate::subdivide::RegionContext;

/// Most pieces along each side of a region's rectangle whose centres are asked: at most 64
/// queries a region, against the millions of samples of a run this is sought for. A region
/// takes no more pieces along a side than the samples its whole rectangle could need there
/// (the tiny regions around a cone's apex take one).
const PIECES: usize = 8;

/// How far a sample may lie from its heightfield point, as a fraction of the scene's diagonal
/// (see the module docs).
const MOVED: f64 = 1e-6;

/// What the bound needs of one basic region that the run samples.
pub(crate) struct RegionView<'a> {
    /// Index of its patch (literal of a term); regions of one patch are consecutive.
    pub patch: usize,
    /// The region.
    pub region: &'a BasicRegion,
    /// Its quadric's principal frame.
    pub frame: &'a PrincipalFrame,
    /// Eq. 22 near the region.
    pub distance: &'a NearDistance<'a>,
    /// Whether all of it is on the surface.
    pub on_surface: bool,
}

impl<'a> RegionView<'a> {
    /// Region `region` of patch `patch`, sampled with `ctx`.
    pub fn new(patch: usize, region: &'a BasicRegion, ctx: &RegionContext<'a>) -> Self {
        Self {
            patch,
            region,
            frame: ctx.frame,
            distance: ctx.distance,
            on_surface: ctx.on_surface,
        }
    }
}

/// The quadric of the patch at which the fewest samples the regions `views` (in region order)
/// can hold at radius `radius` pass `limit`, in a scene of diagonal `diagonal`; `None` when
/// they do not.
pub(crate) fn first_crossing(
    views: &[RegionView<'_>],
    radius: f64,
    diagonal: f64,
    limit: u64,
) -> Option<u32> {
    let reach = radius + MOVED * diagonal;
    // Each region's proven area in units of what one sample reaches on its plane and sheet,
    // and on the whole quadric.
    let counts: Vec<(f64, f64)> = views
        .par_iter()
        .map(|view| {
            let (on_plane, on_quadric) = sample_reach(view.region, reach);
            let rect = &view.region.rect;
            let across = (rect.width() * rect.height() / on_plane).sqrt().ceil();
            let area = proven_area(view, (across as usize).clamp(1, PIECES));
            (area / on_plane, area / on_quadric)
        })
        .collect();
    let mut total = 0.0;
    let mut start = 0;
    while let Some(first) = views.get(start) {
        let end = (start..views.len())
            .find(|&i| views[i].patch != first.patch)
            .unwrap_or(views.len());
        // By sampling plane and sheet, and all of them.
        let mut by_plane = [0.0f64; 6];
        let mut all = 0.0;
        for (view, (on_plane, on_quadric)) in views[start..end].iter().zip(&counts[start..end]) {
            let axis = view.region.heightfield.normal_axis.min(2);
            by_plane[2 * axis + usize::from(view.region.sheet < 0.0)] += on_plane;
            all += on_quadric;
        }
        total += by_plane.iter().copied().fold(all, f64::max);
        // Compared as floating point: above `2⁵³` a count is far past any limit anyway.
        if total > limit as f64 {
            return Some(first.region.quadric);
        }
        start = end;
    }
    None
}

/// The most one sample or deferred rectangle of `region` accounts for (see the module docs), on
/// its plane and sheet and on the whole quadric: `π ρ²` and `4 π ρ²` for `ρ = reach`, and at
/// least the area of a rectangle too small to halve at the region's coordinates (on the
/// quadric, stretched by the region's distortion).
fn sample_reach(region: &BasicRegion, reach: f64) -> (f64, f64) {
    let rect = &region.rect;
    let far = [rect.x.0, rect.x.1, rect.y.0, rect.y.1]
        .iter()
        .fold(0.0f64, |far, v| far.max(v.abs()));
    let side = 2.0 * f64::EPSILON * far;
    let disc = std::f64::consts::PI * reach * reach;
    let smallest = side * side;
    (
        disc.max(smallest),
        (4.0 * disc).max(smallest * region.max_distortion),
    )
}

/// The area of the region's rectangle (in plane coordinates) proven on the surface at the
/// centres of its `pieces × pieces` pieces; `0` where nothing is proven or the region's
/// distortion is unbounded.
fn proven_area(view: &RegionView<'_>, pieces: usize) -> f64 {
    let region = view.region;
    let distortion = region.max_distortion;
    if !(distortion.is_finite() && distortion >= 1.0) {
        return 0.0;
    }
    let rect = region.rect;
    let (width, height) = (rect.width(), rect.height());
    let mut area = 0.0;
    for i in 0..pieces {
        for j in 0..pieces {
            let at = |start: f64, size: f64, k: usize| start + size * k as f64 / pieces as f64;
            let piece = Rect {
                x: (at(rect.x.0, width, i), at(rect.x.0, width, i + 1)),
                y: (at(rect.y.0, height, j), at(rect.y.0, height, j + 1)),
            };
            let (x, y) = piece.centre();
            let d = if view.on_surface {
                f64::NEG_INFINITY
            } else {
                match region_point(view.frame, &region.heightfield, region.sheet, x, y) {
                    Some(p) => view.distance.distance(p),
                    None => continue,
                }
            };
            // Off the surface, on its border or NaN (never classified).
            if d.is_nan() || d >= 0.0 {
                continue;
            }
            // Half the side of the square inside the disc of radius `|d| / δ`.
            let half = -d / distortion * std::f64::consts::FRAC_1_SQRT_2;
            let square = Rect {
                x: ((x - half).max(piece.x.0), (x + half).min(piece.x.1)),
                y: ((y - half).max(piece.y.0), (y + half).min(piece.y.1)),
            };
            let (w, h) = (square.width(), square.height());
            if w > 0.0 && h > 0.0 && region.owns_all_of(&square) {
                area += w * h;
            }
        }
    }
    area
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::regions::basic_regions;
    use qcsg_csg::Aabb;
    use qcsg_quadric::{DVec3, Quadric};

    /// The basic regions of a unit ball over its box.
    fn ball_regions() -> Vec<BasicRegion> {
        let ball = Quadric::sphere(DVec3::ZERO, 1.0).expect("a ball");
        let frame = ball.frame();
        let bounds = Aabb::new(DVec3::splat(-1.0), DVec3::splat(1.0));
        let mut regions = Vec::new();
        for heightfield in frame.heightfields() {
            let mut stats = Default::default();
            basic_regions(
                &frame,
                &heightfield,
                &bounds,
                (0, 0),
                &mut regions,
                &mut stats,
            );
        }
        regions
    }

    #[test]
    fn a_sample_accounts_for_its_disc_or_a_rectangle_too_small_to_halve() {
        for region in ball_regions() {
            let (on_plane, on_quadric) = sample_reach(&region, 0.5);
            assert!((on_plane - 0.25 * std::f64::consts::PI).abs() < 1e-12);
            assert!((on_quadric - std::f64::consts::PI).abs() < 1e-12);
            let (on_plane, on_quadric) = sample_reach(&region, 1e-300);
            assert!(on_plane > 0.0 && on_plane < 1e-30, "{on_plane}");
            assert!(on_quadric >= on_plane && on_quadric < 1e-30, "{on_quadric}");
        }
    }
}
