//! The first pass ([`sample_region`]): every basic region on its own, depth first, each cell
//! classified ([`super::classify`]), filled, dropped or split; a small rectangle with neither
//! corner nor centre on the surface is set aside ([`Deferred`]) for the second pass
//! ([`super::second_pass`]).
//!
//! **Threads.** Basic regions are shared out in runs ([`crate::sample`]), but one region can
//! hold much of the work (a face of a dimpled cube: a quarter of all samples). A rectangle whose
//! footprint is at least [`TASK_FOOTPRINT`] radii is split into halves of which the second may
//! be taken by an idle thread (rayon's work stealing over the subdivision tree, as paper 000
//! §7 suggests). The second half's small rectangles then look back only at its own samples,
//! on one thread as on many, so the output stays the same for any thread count; on one thread
//! it costs a join per large rectangle and nothing is copied.

use super::cell::{Cell, Walk};
use super::classify::{Verdict, at_centre, classify, covered_near, split};
use super::emit::emit;
use super::emitted::Emitted;
use super::{RegionContext, SubdivisionStats};
use crate::budget::Meter;
use crate::in_order::lock;
use crate::regions::{BasicRegion, region_point};
use crate::sample_point::Sample;
use crate::small_patches;
use qcsg_quadric::DVec3;
use std::sync::{Mutex, PoisonError};

/// A rectangle of footprint at most `r` that the first pass left unproven (no corner and not
/// its centre on the surface): [`refine_deferred`](crate::subdivide::refine_deferred) settles it once every region has its samples.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Deferred {
    /// Index of the basic region it belongs to.
    pub region: usize,
    pub(super) cell: Cell,
}

impl Deferred {
    /// The surface point over the rectangle's centre.
    pub fn centre_point(&self, ctx: &RegionContext<'_>, region: &BasicRegion) -> Option<DVec3> {
        let (x, y) = self.cell.rect.centre();
        region_point(ctx.frame, &region.heightfield, region.sheet, x, y)
    }
}

/// First pass over basic region number `index`, appending its samples to `out` in a
/// deterministic (depth-first) order. Rectangles of footprint at most `r` that it cannot prove
/// go to `deferred`, for [`refine_deferred`](crate::subdivide::refine_deferred). Both may hold earlier regions' output already;
/// `out[block_start..]` (the samples of the region's block so far, [`crate::blocks`]) may cover
/// its small rectangles.
pub fn sample_region(
    ctx: &RegionContext<'_>,
    (index, region): (usize, &BasicRegion),
    (out, block_start): (&mut Emitted, usize),
    deferred: &mut Vec<Deferred>,
    (memo, stats): Walk<'_>,
) {
    // The walk starts empty before the root's corners too: the memo knows points by their
    // plane coordinates alone, and the region before may have been another sheet, plane or
    // quadric, whose value at the same coordinates is that of another point.
    memo.clear();
    if small_patches::is_small_patch(region) {
        small_patch(ctx, region, (out, block_start), stats);
        out.box_new();
        return;
    }
    let root = Cell::new(ctx, region, region.rect, (memo, stats));
    subdivide(
        (ctx, index, region),
        root,
        (out, block_start),
        deferred,
        (memo, stats),
    );
    out.box_new();
}

/// A small patch's one sample ([`crate::small_patches`]): of radius the diagonal `E` of its box,
/// at the first of the points it is tried at where eq. 22 is negative (the settling of the run
/// kept it for that). Every point of the patch lies within `E` of its test point `p`: a recent
/// sample of the block that covers that ball (its radius grown up to `r`) covers the patch, as
/// for small rectangles ([`super::classify`]).
fn small_patch(
    ctx: &RegionContext<'_>,
    region: &BasicRegion,
    (out, block_start): (&mut Emitted, usize),
    stats: &mut SubdivisionStats,
) {
    stats.rectangles += 1;
    let (x, y) = small_patches::test_point(region);
    let Some(position) = region_point(ctx.frame, &region.heightfield, region.sheet, x, y) else {
        return;
    };
    let extent = small_patches::extent(ctx.frame, region);
    if covered_near(ctx, region, (position, extent), &mut out[block_start..]) {
        stats.small += 1;
        return;
    }
    let at = if ctx.on_surface {
        Some((x, y))
    } else {
        small_patches::on_surface_point(ctx.frame, region, |p| {
            stats.distance_queries += 1;
            ctx.distance.distance(p)
        })
    };
    let mut meter = Meter::new(ctx.budget, region.quadric);
    if let Some((x, y)) = at {
        let radius = extent.min(ctx.radius);
        emit(ctx, region, x, y, radius, out);
        stats.small += 1;
        meter.finish(1, 1);
    } else {
        meter.finish(0, 1);
    }
}

/// Rectangles whose footprint is at least this many radii are split into halves that other
/// threads may take (see "Threads" in the module docs): a large face is otherwise one piece of
/// work, which left one thread sampling a quarter of a dimpled cube while the other waited.
pub const TASK_FOOTPRINT: f64 = 32.0;

/// The subdivision of `root`, a cell of basic region number `index`, depth first; its small
/// rectangles may be covered by `out[look_back..]`. It starts from an empty memo, and empties
/// it again after the halves of a large cell: each half may run on another thread with a
/// memo of its own.
pub(super) fn subdivide(
    (ctx, index, region): (&RegionContext<'_>, usize, &BasicRegion),
    root: Cell,
    (out, look_back): (&mut Emitted, usize),
    deferred: &mut Vec<Deferred>,
    (memo, stats): Walk<'_>,
) {
    memo.clear();
    let scale = region.rect.diagonal();
    walk_cells(
        (ctx, index, region, scale),
        root,
        (out, look_back),
        deferred,
        (memo, stats),
    );
}

/// [`subdivide`] from `root` on, without emptying the memo; `scale` is the diagonal of the
/// rectangle `ctx`'s eq. 22 was kept to ([`narrowed`]).
fn walk_cells(
    (ctx, index, region, scale): (&RegionContext<'_>, usize, &BasicRegion, f64),
    root: Cell,
    (out, look_back): (&mut Emitted, usize),
    deferred: &mut Vec<Deferred>,
    (memo, stats): Walk<'_>,
) {
    let (first_sample, first_deferred) = (out.len(), deferred.len());
    let first_queries = stats.distance_queries;
    let mut stack = vec![root];
    let mut meter = Meter::new(ctx.budget, region.quadric);
    // Deferred rectangles count as samples: each one is held in memory until the second pass.
    let pending = |out: &[Sample], deferred: &[Deferred], stats: &SubdivisionStats| {
        let held = out.len() - first_sample + deferred.len() - first_deferred;
        (held as u64, stats.distance_queries - first_queries)
    };
    let defer = |cell| Deferred {
        region: index,
        cell,
    };
    while let Some(mut cell) = stack.pop() {
        let (held, queries) = pending(out, deferred, stats);
        if !meter.tick(held, queries) {
            break;
        }
        if cell.owned_by_none(region) {
            stats.other_plane += 1;
            continue;
        }
        match classify(ctx, region, &cell, (out, look_back), (memo, stats)) {
            Verdict::Discarded | Verdict::Filled | Verdict::Small => {}
            Verdict::Unproven { distortion, .. } => {
                // The centre at once. Deferring the cell to look for a covering sample first,
                // as the second pass does, saved more queries (three balls at 1 % of the
                // diagonal: 9 % against 6 %), but the larger second pass cost the cubes dimpled
                // or hollowed by balls 0.3-0.9 % more instructions than that saved.
                let centre = (&cell.rect, distortion);
                if at_centre(ctx, region, centre, out, (memo, stats)).is_none() {
                    deferred.push(defer(cell));
                }
            }
            Verdict::Split { footprint } => match split(ctx, region, &cell, (memo, stats)) {
                Some(halves) if footprint >= TASK_FOOTPRINT * ctx.radius => {
                    // The halves charge the budget themselves.
                    meter.finish(held, queries);
                    let task = (ctx, index, region);
                    split_in_parallel(task, halves, (out, look_back), deferred, (memo, stats));
                    memo.clear();
                    let (held, queries) = pending(out, deferred, stats);
                    meter.skip_to(held, queries);
                }
                Some((low, high)) => match narrowed(ctx, region, &cell, scale) {
                    // The cell's subtree with eq. 22 kept to what comes near it, in the order
                    // the stack would take it.
                    Some(near) => {
                        // The subtree charges the budget itself.
                        meter.finish(held, queries);
                        let ctx = RegionContext {
                            distance: &near,
                            ..*ctx
                        };
                        let scale = cell.rect.diagonal();
                        for half in [low, high] {
                            let walk = (&mut *memo, &mut *stats);
                            walk_cells(
                                (&ctx, index, region, scale),
                                half,
                                (out, look_back),
                                deferred,
                                walk,
                            );
                        }
                        let (held, queries) = pending(out, deferred, stats);
                        meter.skip_to(held, queries);
                    }
                    None => {
                        stack.push(high);
                        stack.push(low);
                    }
                },
                None => deferred.push(defer(cell)),
            },
        }
    }
    let (held, queries) = pending(out, deferred, stats);
    meter.finish(held, queries);
}

/// The subdivisions of the two halves of a large cell, low then high, the high one open to
/// another thread (rayon's work stealing). The low half continues in `out`; the high half's
/// small rectangles look back only at its own samples, whichever thread takes it, so the output
/// does not depend on the thread count. It writes to `out` too when the low half is done by
/// the time it starts (always on one thread), else to buffers of its own, appended after.
pub(super) fn split_in_parallel(
    task: (&RegionContext<'_>, usize, &BasicRegion),
    (low, high): (Cell, Cell),
    (out, look_back): (&mut Emitted, usize),
    deferred: &mut Vec<Deferred>,
    (memo, stats): Walk<'_>,
) {
    // The outputs, and whether the low half is done with them. Each half boxes its samples to
    // its end, as appending a half another thread took does: the boxes, which clip lists go by
    // (`clip`), are then the same on any number of threads.
    let shared = Mutex::new((out, deferred, (memo, stats), false));
    let (_, own) = rayon::join(
        || {
            let mut shared = shared.lock().unwrap_or_else(PoisonError::into_inner);
            let (out, deferred, (memo, stats), done) = &mut *shared;
            subdivide(task, low, (out, look_back), deferred, (memo, stats));
            out.box_new();
            *done = true;
        },
        || {
            // Busy: the low half holds them (this thread runs this half while the low one
            // waits for work it handed out, or another thread took this half).
            if let Ok(mut shared) = shared.try_lock()
                && shared.3
            {
                let (out, deferred, (memo, stats), _) = &mut *shared;
                let start = out.len();
                subdivide(task, high, (out, start), deferred, (memo, stats));
                out.box_new();
                return None;
            }
            let (mut out, mut deferred, mut memo) =
                lock(task.0.spare_halves).pop().unwrap_or_default();
            let mut stats = SubdivisionStats::default();
            let walk = (&mut memo, &mut stats);
            subdivide(task, high, (&mut out, 0), &mut deferred, walk);
            Some(((out, deferred, memo), stats))
        },
    );
    if let Some(((mut more, mut more_deferred, memo), counters)) = own {
        let (out, deferred, (_, stats), _) =
            shared.into_inner().unwrap_or_else(PoisonError::into_inner);
        // A run past a limit ends in an error: what the half holds is not copied on.
        if task.0.budget.stopped() {
            more.clear();
            more_deferred.clear();
        }
        out.append(&mut more);
        deferred.extend_from_slice(&more_deferred);
        more_deferred.clear();
        stats.add(&counters);
        // Appended to an empty `out`, `more` took over its buffers, which have no memory.
        if more.capacity() > 0 {
            lock(task.0.spare_halves).push((more, more_deferred, memo));
        }
    }
}

/// A cell this many times smaller (by diagonal) than the rectangle its eq. 22 was kept to
/// gets eq. 22 kept to its own patch ([`crate::csg_distance::NearDistance::narrow`]).
pub const NARROW_RATIO: f64 = 16.0;

/// Eq. 22 kept to what comes near `cell`'s patch, when the cell is [`NARROW_RATIO`] times
/// smaller than the rectangle `ctx`'s was kept to (`scale`) and that looked at other terms:
/// where many small terms lie side by side (the cells of a line of text), the rectangles
/// that a face's border leaves to split down to the cutoff otherwise query every term near
/// the whole region. The margin is the regions' own (`near_margin`), so what is left out is
/// farther than any point of the cell's subtree and radius; it only cuts values beyond that.
pub(super) fn narrowed<'a>(
    ctx: &RegionContext<'a>,
    region: &BasicRegion,
    cell: &Cell,
    scale: f64,
) -> Option<crate::csg_distance::NearDistance<'a>> {
    if ctx.on_surface
        || cell.rect.diagonal() * NARROW_RATIO > scale
        || !ctx.distance.has_other_terms()
    {
        return None;
    }
    let part = BasicRegion {
        rect: cell.rect,
        ..*region
    };
    let bounds = crate::regions::patch_bounds(ctx.frame, &part)?;
    Some(
        ctx.distance
            .narrow(&bounds, crate::patches::near_margin(&bounds, ctx.radius)),
    )
}
