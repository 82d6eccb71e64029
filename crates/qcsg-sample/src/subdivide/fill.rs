//! Covering a rectangle proven on the surface ([`fill`]): rows of samples on a square grid whose
//! spacing the distortion bound sets ([`crate::fill_grid`]), the rectangle split where its
//! distortion varies much; in a border region, cells another sampling plane owns are skipped.

use super::RegionContext;
use super::cell::bounded_distortion;
use super::emit::{fallback_normal, onto_quadric, surface_sample};
use super::emitted::Emitted;
use crate::budget::CHARGE_EVERY;
use crate::fill_grid::{FillGrid, FillRow};
use crate::lanes::{HeightfieldLine, SurfaceTest};
use crate::regions::{
    BasicRegion, Owned, Rect, corner_bounds, split_for_distortion, split_for_distortion_at_corners,
};
use crate::sample_point::Sample;
use qcsg_quadric::DVec3;
use std::ops::Range;

/// Ratio of largest to smallest distortion above which [`fill`] fills the halves separately.
pub(super) const FILL_SPREAD: f64 = 1.1;

/// Cells a rectangle must span across its split for [`fill`] to split it.
pub(super) const FILL_SPLIT_CELLS: f64 = 4.0;

/// Covers a rectangle known to be on the CSG surface with rows of samples, a square grid or
/// staggered ([`FillGrid`]), so that every point of it lies within `r / δ` of a sample on the
/// sampling plane (`δ` the largest distortion over it), hence within `r` on the surface.
/// Returns `false` (nothing emitted) when the grid would be too large, so that the caller
/// splits first; emits nothing either when its samples would cross the run's sample limit
/// ([`Budget::admits`](crate::budget::Budget::admits)), which stops the run.
///
/// The spacing follows the largest distortion over the rectangle; where the distortion varies
/// by more than [`FILL_SPREAD`] and the rectangle is at least [`FILL_SPLIT_CELLS`] cells across
/// the direction it varies in, the halves are filled each with its own bound instead (no
/// query is needed: the whole rectangle is on the surface). That saves about a quarter of the
/// samples on curved parts. `owned` says that all of the rectangle is known to belong to the
/// region ([`BasicRegion::owns`]).
///
/// `slopes` are the squared slopes at the corners of a rectangle inside one quadrant
/// ([`Cell`](crate::subdivide::cell::Cell)), from which its distortion bounds and its halves' follow with four new slopes a
/// split ([`split_for_distortion_at_corners`]). Each half's bounds were computed anew three
/// times, from sixteen slopes, and a rectangle too narrow to split weighed both cuts all the
/// same: that took 8 % of the instructions of sampling a cube dimpled by 18 balls at 0.15 % of
/// the diagonal, 2 % now.
pub(super) fn fill(
    ctx: &RegionContext<'_>,
    region: &BasicRegion,
    (rect, owned): (&Rect, bool),
    (distortion, slopes): (f64, Option<[f64; 4]>),
    out: &mut Emitted,
) -> bool {
    let spacing = std::f64::consts::SQRT_2 * ctx.radius / distortion;
    let Some(grid) = FillGrid::over(rect.width(), rect.height(), ctx.radius / distortion) else {
        return false;
    };
    // A cut spans at most the longer side: where that is too short to split, how the
    // distortion varies does not matter.
    let across_at_most = rect.width().max(rect.height());
    let bounds = || match slopes {
        Some(slopes) => corner_bounds(slopes),
        None => region.heightfield.distortion_bounds(rect.x, rect.y),
    };
    if across_at_most >= FILL_SPLIT_CELLS * spacing
        && let Some((low, high)) = bounds()
        && high > FILL_SPREAD * low
    {
        let heightfield = &region.heightfield;
        let halves = match slopes {
            Some(slopes) => split_for_distortion_at_corners(heightfield, rect, slopes)
                .map(|(half, slopes)| (half, corner_bounds(slopes), Some(slopes))),
            None => {
                split_for_distortion(heightfield, rect).map(|(half, bounds)| (half, bounds, None))
            }
        };
        let across = if halves[0].0.width() < rect.width() {
            rect.width()
        } else {
            rect.height()
        };
        if across >= FILL_SPLIT_CELLS * spacing {
            for (half, bounds, slopes) in halves {
                let distortion = bounded_distortion(region, bounds.map(|(_, high)| high));
                fill(ctx, region, (&half, owned), (distortion, slopes), out);
            }
            return true;
        }
    }
    // A large fill asks the budget before its samples grow the buffer: they might cross the
    // limit many times over (the run stops then, and none are emitted).
    let count = grid.samples();
    if count > CHARGE_EVERY && !ctx.budget.admits(count, region.quadric) {
        return true;
    }
    let radius = (distortion * grid.reach).min(ctx.radius);
    let clipped = !owned && !region.owns_all_of(rect);
    // What was emitted before the fill gets boxes of its own.
    out.box_new();
    // A shifted row ends on the rectangle's side: not past it by rounding (a few steps down
    // suffice but where `x` is far larger than the width, and there the side is inside the
    // heightfield's domain anyway, as a filled rectangle has a bounded distortion).
    let mut dx = grid.spacing;
    for _ in 0..4 {
        if !grid.staggered || rect.x.0 + f64::from(grid.columns) * dx <= rect.x.1 {
            break;
        }
        dx = dx.next_down();
    }
    for k in 0..grid.rows {
        let FillRow { y, offset, samples } = grid.row(k);
        let row = Row {
            rect,
            dx,
            offset,
            y: rect.y.0 + y,
            half_height: grid.half_height,
            radius,
        };
        if clipped {
            fill_span(ctx, region, &row, 0..samples, out);
        } else {
            row.emit(ctx, region, 0..samples, out);
        }
    }
    out.box_fill();
    true
}

/// One row of a fill ([`FillGrid`]) over `rect`: sample `i` lies at `x = rect.x.0 + (i +
/// offset)·dx` and `y`, of radius `radius`; every point of `rect` lies within `dx / 2` along `x`
/// and `half_height` along `y` of its nearest sample.
pub(super) struct Row<'a> {
    pub(super) rect: &'a Rect,
    pub(super) dx: f64,
    pub(super) offset: f64,
    pub(super) y: f64,
    pub(super) half_height: f64,
    pub(super) radius: f64,
}

impl Row<'_> {
    /// The part of the fill's rectangle whose points may have one of samples `cells` nearest.
    pub(super) fn span(&self, cells: &Range<u32>) -> Rect {
        let x = |i: f64| self.rect.x.0 + (i + self.offset) * self.dx;
        let (low, high) = (f64::from(cells.start) - 0.5, f64::from(cells.end) - 0.5);
        Rect {
            x: (x(low).max(self.rect.x.0), x(high).min(self.rect.x.1)),
            y: (
                (self.y - self.half_height).max(self.rect.y.0),
                (self.y + self.half_height).min(self.rect.y.1),
            ),
        }
    }

    /// Emits the samples of cells `cells`, in order, up to eight at a time ([`crate::lanes`];
    /// fewer where fewer are left, as unused lanes cost as much as used ones).
    pub(super) fn emit(
        &self,
        ctx: &RegionContext<'_>,
        region: &BasicRegion,
        cells: Range<u32>,
        out: &mut Vec<Sample>,
    ) {
        let Some(line) = HeightfieldLine::new(ctx.frame, &region.heightfield, region.sheet, self.y)
        else {
            return;
        };
        let lanes = (&line, &SurfaceTest::new(ctx.quadric, ctx.snap));
        let mut start = cells.start;
        while start < cells.end {
            start = match cells.end - start {
                8.. => self.emit_lanes::<8>(ctx, region, lanes, start, out),
                4.. => self.emit_lanes::<4>(ctx, region, lanes, start, out),
                2.. => self.emit_lanes::<2>(ctx, region, lanes, start, out),
                _ => self.emit_lanes::<1>(ctx, region, lanes, start, out),
            };
        }
    }

    /// Emits the samples of cells `start..start + N`; returns the next cell.
    #[inline]
    pub(super) fn emit_lanes<const N: usize>(
        &self,
        ctx: &RegionContext<'_>,
        region: &BasicRegion,
        (line, test): (&HeightfieldLine, &SurfaceTest),
        start: u32,
        out: &mut Vec<Sample>,
    ) -> u32 {
        let x = std::array::from_fn(|l| {
            self.rect.x.0 + (f64::from(start + l as u32) + self.offset) * self.dx
        });
        let (points, found) = line.points::<N>(&x);
        let (normals, done) = test.normals(&points);
        for l in (0..N).filter(|&l| found[l]) {
            let point = if done[l] {
                (points.at(l), normals.at(l))
            } else {
                // Rare: a Newton step, or a gradient too small or large to square.
                let mut point = (points.at(l), DVec3::ZERO);
                onto_quadric(ctx, &mut point, fallback_normal(ctx, region));
                point
            };
            out.push(surface_sample(region, point, self.radius));
        }
        start + N as u32
    }
}

/// Emits the samples of cells `cells` of a border region's row, in order, but for those where
/// another plane is the best throughout, which are that plane's ([`BasicRegion::owns`]). A span
/// of cells is decided whole where the plane is the best everywhere or nowhere over it, and
/// halved otherwise: a row costs a few tests near where the border crosses it instead of one
/// per cell. With the ownership a cell passes on to its parts ([`Cell::owned_by_none`](crate::subdivide::cell::Cell::owned_by_none)), this
/// cut the border tests from 9.5 % to 3.9 % of the instructions of sampling three balls at
/// 0.15 % of the diagonal.
pub(super) fn fill_span(
    ctx: &RegionContext<'_>,
    region: &BasicRegion,
    row: &Row,
    cells: Range<u32>,
    out: &mut Vec<Sample>,
) {
    match region.owns(&row.span(&cells)) {
        Owned::None => {}
        Owned::Part if cells.len() > 1 => {
            let middle = cells.start + (cells.end - cells.start) / 2;
            fill_span(ctx, region, row, cells.start..middle, out);
            fill_span(ctx, region, row, middle..cells.end, out);
        }
        Owned::All | Owned::Part => row.emit(ctx, region, cells, out),
    }
}
