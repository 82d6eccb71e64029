//! A rectangle of the subdivision ([`Cell`]): its corners' values of eq. 22 and squared slopes,
//! from which its distortion bound and world footprint follow (§3.4: the extrema lie at the
//! corners of a rectangle in one quadrant of its plane).

use super::{RegionContext, SubdivisionStats};
use crate::memo::QueryMemo;
use crate::regions::{BasicRegion, Owned, Rect, corner_bounds, region_point};

/// A rectangle with its corner distances `[x0y0, x1y0, x0y1, x1y1]` and the heightfield's
/// squared slopes there ([`qcsg_quadric::Heightfield::slope_squared`], NaN where it has none),
/// from which its distortion bound follows ([`cell_distortion`]). Cells are copied at every
/// split and push: NaN instead of `Option` keeps them a third smaller.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Cell {
    pub(super) rect: Rect,
    pub(super) d: [f64; 4],
    pub(super) slope: [f64; 4],
    /// Whether all of it is known to belong to the region ([`BasicRegion::owns`]); its parts
    /// are then too, and no more border tests are needed below it.
    pub(super) owned: bool,
}

impl Cell {
    /// The cell over `rect`, its corners evaluated.
    pub(super) fn new(
        ctx: &RegionContext<'_>,
        region: &BasicRegion,
        rect: Rect,
        (memo, stats): Walk<'_>,
    ) -> Self {
        let mut cell = Self {
            rect,
            d: [0.0; 4],
            slope: [f64::NAN; 4],
            owned: false,
        };
        for k in 0..4 {
            let (x, y) = corner(&rect, k);
            (cell.d[k], cell.slope[k]) = plane_values(ctx, region, x, y, (memo, stats));
        }
        cell
    }

    /// Whether none of the cell belongs to the region; otherwise `owned` records whether it all
    /// does.
    pub(super) fn owned_by_none(&mut self, region: &BasicRegion) -> bool {
        if !self.owned {
            match region.owns(&self.rect) {
                Owned::None => return true,
                Owned::All => self.owned = true,
                Owned::Part => {}
            }
        }
        false
    }
}

/// What a walk of the subdivision writes to as it queries: the memo of its queries and the
/// counters.
pub(super) type Walk<'a> = (&'a mut QueryMemo, &'a mut SubdivisionStats);

/// Eq. 22 ([`query`]) and the squared slope at a corner or centre (NaN where there is none),
/// from the walk's memo where it has them; eq. 22 is `−∞` without a query in a region all on
/// the surface ([`RegionContext::on_surface`]).
pub(super) fn plane_values(
    ctx: &RegionContext<'_>,
    region: &BasicRegion,
    x: f64,
    y: f64,
    (memo, stats): Walk<'_>,
) -> (f64, f64) {
    if ctx.on_surface {
        let slope = region.heightfield.slope_squared(x, y);
        return slope.map_or((f64::NAN, f64::NAN), |slope| (f64::NEG_INFINITY, slope));
    }
    memo.get_or(x, y, || {
        let slope = region.heightfield.slope_squared(x, y).unwrap_or(f64::NAN);
        (query(ctx, region, x, y, stats), slope)
    })
}

/// The maximum distortion over a sub-rectangle (§3.4), falling back to the region's bound.
pub(super) fn rect_distortion(region: &BasicRegion, rect: &Rect) -> f64 {
    let high = region.heightfield.distortion_bounds(rect.x, rect.y);
    bounded_distortion(region, high.map(|(_, high)| high))
}

/// [`rect_distortion`] of a cell, from its corners' slopes: basic regions lie in one quadrant
/// of their plane, where the corners bound the distortion, and so do their sub-rectangles.
pub(super) fn cell_distortion(region: &BasicRegion, cell: &Cell) -> f64 {
    if !in_one_quadrant(&cell.rect) {
        return rect_distortion(region, &cell.rect);
    }
    bounded_distortion(region, corner_bounds(cell.slope).map(|(_, high)| high))
}

/// Whether a rectangle lies in one quadrant of its plane (no axis runs through it), where the
/// squared slopes at its corners bound its distortion.
pub(super) fn in_one_quadrant(rect: &Rect) -> bool {
    let (x, y) = (rect.x, rect.y);
    !((x.0 < 0.0 && x.1 > 0.0) || (y.0 < 0.0 && y.1 > 0.0))
}

/// The world footprint of a cell: its diagonal times its distortion bound.
pub(super) fn cell_footprint(region: &BasicRegion, cell: &Cell) -> f64 {
    cell_distortion(region, cell) * cell.rect.diagonal()
}

/// A rectangle's distortion bound `high` (`None` where undefined), within the region's.
pub(super) fn bounded_distortion(region: &BasicRegion, high: Option<f64>) -> f64 {
    match high {
        Some(high) if high.is_finite() && high >= 1.0 => high.min(region.max_distortion),
        _ => region.max_distortion,
    }
}

pub(super) fn corner(rect: &Rect, k: usize) -> (f64, f64) {
    (
        if k & 1 == 0 { rect.x.0 } else { rect.x.1 },
        if k & 2 == 0 { rect.y.0 } else { rect.y.1 },
    )
}

/// Eq. 22 at the surface point over `(x, y)`; NaN (never classified) where there is none.
pub(super) fn query(
    ctx: &RegionContext<'_>,
    region: &BasicRegion,
    x: f64,
    y: f64,
    stats: &mut SubdivisionStats,
) -> f64 {
    stats.distance_queries += 1;
    match region_point(ctx.frame, &region.heightfield, region.sheet, x, y) {
        Some(p) => ctx.distance.distance(p),
        None => f64::NAN,
    }
}
