//! The second pass ([`refine_deferred`]): the small rectangles the first pass set aside, taken
//! up once every region has its samples.
//!
//! **Two passes.** A rectangle is covered as soon as a sample of the same quadric lies within
//! `r − footprint / 2` of the surface point over its centre (every point of the rectangle is
//! within `footprint / 2` of that point), its radius grown to reach the rectangle; otherwise it is
//! split and classified again, down to [`super::SMALL_REGION_FRACTION`] of the footprint. Such
//! rectangles sit beside feature curves, and the samples on the other side of the curve, often
//! in a neighbouring region, usually cover them at once (where a curve runs along a region
//! border, splitting them down to the cutoff instead costs many times the queries). Where
//! surfaces nearly coincide over an area, no rectangle is ever proven, and the refinement of one
//! deferred rectangle stops after [`MAX_UNPROVEN_PER_DEFERRED`] unproven rectangles; the
//! given-up rectangles kept for the final settling are bounded in all ([`given_up_share`]).
//! Second-pass samples are appended after the first pass's, in the order of the deferred
//! rectangles, so the output does not depend on the thread count.

use super::cell::{Cell, Walk, cell_distortion, cell_footprint};
use super::classify::{Verdict, at_centre, centre_point, classify, split};
use super::cover::{SurfacePoint, cover_by, grow_radius, grow_to_cover, may_cover};
use super::emitted::Emitted;
use super::first_pass::{Deferred, narrowed};
use super::given_up::GivenUp;
use super::sample_index::{Member, SampleIndex};
use super::{RegionContext, SMALL_REGION_FRACTION, SubdivisionStats};
use crate::budget::Meter;
use crate::regions::{BasicRegion, Rect, region_point};
use crate::sample_point::Sample;
use qcsg_quadric::DVec3;

/// Unproven rectangles one deferred rectangle may split into before the rest is given up. A
/// sliver along a curve leaves about 2·2ᵏ unproven rectangles at `k` halvings, so this reaches
/// the cutoff (`k = 6`) there; where surfaces nearly coincide over an area (two ellipsoids
/// `1e-9` apart, turned differently) every rectangle stays unproven, `4ᵏ` of them, and the
/// budget stops the refinement near `r / 20` instead of costing 4,096 leaves per rectangle.
pub(super) const MAX_UNPROVEN_PER_DEFERRED: usize = 512;

/// Given-up rectangles kept one by one for [`settle_given_up`](crate::subdivide::settle_given_up) over all deferred rectangles
/// (about 200 MB); each deferred rectangle may keep its share of them (at most
/// [`MAX_UNPROVEN_PER_DEFERRED`]) and settles the rest together, as the whole deferred
/// rectangle. Nested balls `1e-9` apart give up millions. The share depends
/// only on the number of deferred rectangles, so the output does not depend on the thread count.
pub(super) const MAX_GIVEN_UP_TOTAL: usize = 1 << 22;

/// How many given-up rectangles each of `deferred` deferred rectangles keeps one by one.
pub fn given_up_share(deferred: usize) -> usize {
    (MAX_GIVEN_UP_TOTAL / deferred.max(1)).min(MAX_UNPROVEN_PER_DEFERRED)
}

/// Second pass over one deferred rectangle. It is covered as soon as a sample of the same
/// quadric lies within `r − footprint / 2` of its centre's surface point (one this refinement
/// emitted, or a first-pass sample from `index`); that sample's radius grows to reach the
/// whole rectangle (at once for its own samples, through `grown` for the first pass's), so a
/// splat of that radius covers it. Otherwise it is split and classified again (a part's
/// centre is asked, `at_centre`, only where no sample covers the part),
/// down to [`SMALL_REGION_FRACTION`] of the footprint (or until `MAX_UNPROVEN_PER_DEFERRED`
/// rectangles stayed unproven), where it goes to `given_up`: one by one up to `share` of them
/// ([`given_up_share`]), the rest as the whole deferred rectangle; it counts as unresolved when
/// no sample could reach it.
pub fn refine_deferred(
    ctx: &RegionContext<'_>,
    region: &BasicRegion,
    deferred: &Deferred,
    index: &SampleIndex<'_>,
    (out, given_up, grown): (&mut Emitted, &mut Vec<GivenUp>, &mut Vec<(u32, f64)>),
    share: usize,
    (memo, stats): Walk<'_>,
) {
    memo.clear();
    // Eq. 22 kept to what comes near the rectangle: it is split down to the cutoff where a
    // face's border crosses it, and each of those queries would otherwise look at every term
    // near the whole region.
    let near = narrowed(ctx, region, &deferred.cell, f64::INFINITY);
    let kept;
    let ctx = match &near {
        Some(near) => {
            kept = RegionContext {
                distance: near,
                ..*ctx
            };
            &kept
        }
        None => ctx,
    };
    let cutoff = SMALL_REGION_FRACTION * ctx.radius / region.max_distortion.max(1.0);
    let first_sample = out.len();
    let first_given_up = given_up.len();
    let mut unproven = 0usize;
    let mut overflow = 0u64;
    let mut settled_up_to = out.len();
    let mut stack = vec![(deferred.cell, true)];
    let mut meter = Meter::new(ctx.budget, region.quadric);
    let queries_before = stats.distance_queries;
    let done = |out: &[Sample], stats: &SubdivisionStats| {
        let samples = (out.len() - first_sample) as u64;
        (samples, stats.distance_queries - queries_before)
    };
    let root_footprint = cell_footprint(region, &deferred.cell);
    // The index's samples within `r` of the deferred rectangle's centre ([`SampleIndex::near`]),
    // with that centre, once it is looked up.
    let mut near_root: Option<(DVec3, Vec<Member<'_>>)> = None;
    while let Some((mut cell, classified)) = stack.pop() {
        let (samples, queries) = done(out, stats);
        if !meter.tick(samples, queries) {
            break;
        }
        // A part's centre is asked ([`at_centre`]) only once no sample covers it: most parts
        // that reach here are covered.
        let mut centre = None;
        let footprint = if classified {
            // The first pass has classified this one (the deferred rectangle) already.
            root_footprint
        } else if cell.owned_by_none(region) {
            stats.other_plane += 1;
            continue;
        } else {
            match classify(ctx, region, &cell, (out, first_sample), (memo, stats)) {
                Verdict::Discarded | Verdict::Filled | Verdict::Small => continue,
                Verdict::Unproven {
                    footprint,
                    distortion,
                } => {
                    centre = Some(distortion);
                    footprint
                }
                Verdict::Split { .. } => f64::INFINITY,
            }
        };
        let extent = 0.5 * footprint;
        let point = centre_point(ctx, region, &cell.rect).filter(|_| extent < ctx.radius);
        if let Some(point) = point
            && classified
        {
            let mut near = Vec::new();
            index.near(region.quadric, point.position, &mut near);
            near_root = Some((point.position, near));
        }
        // A sample that covers the ball of radius `extent` around a point lies within
        // `r − extent` of it: within `r` of the root's centre, and on its list, where the
        // point lies within `extent` of that centre.
        let listed = |p: DVec3, extent: f64| {
            let (centre, near) = near_root.as_ref()?;
            ((p - *centre).length() <= extent).then_some(near.as_slice())
        };
        if let Some(point) = point {
            let own = first_sample..out.len();
            if grow_to_cover(out, own, point, extent, ctx.radius, |_| true) {
                stats.unresolved_covered += 1;
                continue;
            }
            let cover = match listed(point.position, extent) {
                Some(near) => index.cover_among(near.iter().copied(), region.term, point, extent),
                None => index.cover((region.quadric, region.term), point, extent),
            };
            if let Some(cover) = cover {
                grown.push(cover);
                stats.unresolved_covered += 1;
                continue;
            }
        }
        if let Some(distortion) = centre
            && at_centre(ctx, region, (&cell.rect, distortion), out, (memo, stats)).is_some()
        {
            continue;
        }
        if point.is_some() {
            // Where samples cover both halves but none the whole, the split and its halves
            // need no query (three balls at 0.15 % of the diagonal: 9 % fewer queries, 5 %
            // fewer instructions; a failed try cost about a query while each try looked its
            // halves up in the index's cubes, before the list near the root's centre).
            let both_halves = (cell.rect.diagonal() > cutoff)
                .then(|| cover_halves(ctx, region, &cell, (out, first_sample), (index, &listed)))
                .flatten();
            if let Some(covers) = both_halves {
                for (own, i, needed) in covers {
                    if own {
                        grow_radius(out, i, needed);
                    } else {
                        grown.push((i, needed));
                    }
                }
                stats.unresolved_covered += 2;
                continue;
            }
        }
        unproven += 1;
        let halves = if cell.rect.diagonal() <= cutoff || unproven > MAX_UNPROVEN_PER_DEFERRED {
            None
        } else {
            split(ctx, region, &cell, (memo, stats))
        };
        match (halves, point) {
            (Some((low, high)), _) => {
                stack.push((high, false));
                stack.push((low, false));
            }
            (None, Some(point)) => {
                // A sample this refinement emits later may still cover it.
                let leaf = GivenUp {
                    quadric: region.quadric,
                    term: region.term,
                    point,
                    extent,
                    count: 1,
                    region: deferred.region,
                    rect: cell.rect,
                };
                if given_up.len() - first_given_up >= share && out.len() > settled_up_to {
                    let own = (first_sample, ctx.radius);
                    settle_locally(given_up, first_given_up, out, own, stats);
                    settled_up_to = out.len();
                }
                if given_up.len() - first_given_up < share {
                    given_up.push(leaf);
                } else {
                    overflow += 1;
                }
            }
            (None, None) => stats.unresolved += 1,
        }
    }
    settle_locally(
        given_up,
        first_given_up,
        out,
        (first_sample, ctx.radius),
        stats,
    );
    if overflow > 0 {
        let extent = 0.5 * root_footprint;
        match centre_point(ctx, region, &deferred.cell.rect) {
            Some(point) if extent < ctx.radius => given_up.push(GivenUp {
                quadric: region.quadric,
                term: region.term,
                point,
                extent,
                count: overflow,
                region: deferred.region,
                rect: deferred.cell.rect,
            }),
            _ => stats.unresolved += overflow,
        }
    }
    let (samples, queries) = done(out, stats);
    meter.finish(samples, queries);
}

/// Covers of both halves of an unproven cell ([`Rect::split_longest`]) by samples, without a
/// distance query: by the refinement's own samples `out[first..]` (`true`) or by the index's
/// samples that `listed` holds for a half's centre and extent (none where it holds none); each
/// with the sample's index and the radius it needs. `None` unless both are covered. Where a
/// sample covers each half but none the whole, this saves the split's queries and those of
/// its halves.
pub(super) fn cover_halves<'n>(
    ctx: &RegionContext<'_>,
    region: &BasicRegion,
    cell: &Cell,
    (out, first): (&[Sample], usize),
    (index, listed): (
        &SampleIndex<'n>,
        &impl Fn(DVec3, f64) -> Option<&'n [Member<'n>]>,
    ),
) -> Option<[(bool, u32, f64); 2]> {
    let (low, high, _) = cell.rect.split_longest();
    // The cell's distortion bound holds over its halves.
    let distortion = cell_distortion(region, cell);
    let own = || (first..out.len()).map(|i| (i as u32, &out[i]));
    let cover = |half: &Rect| {
        let extent = 0.5 * distortion * half.diagonal();
        let (x, y) = half.centre();
        let position = region_point(ctx.frame, &region.heightfield, region.sheet, x, y)?;
        let near = listed(position, extent).unwrap_or_default();
        // Where no sample is near enough (most halves), the centre needs no normal.
        let candidates = own().map(|(_, s)| s).chain(near.iter().map(|&(_, s)| s));
        if !candidates
            .into_iter()
            .any(|s| may_cover(s.position - position, extent, ctx.radius))
        {
            return None;
        }
        let point = SurfacePoint::on(ctx.quadric, position)?;
        if let Some((i, needed)) = cover_by(own(), point, extent, ctx.radius, |_| true) {
            return Some((true, i, needed));
        }
        let (i, needed) = index.cover_among(near.iter().copied(), region.term, point, extent)?;
        Some((false, i, needed))
    };
    Some([cover(&low)?, cover(&high)?])
}

/// Settles the given-up rectangles `given_up[from..]` against the samples `out[first..]` of the
/// same refinement (all of one quadric), within `radius`: covered ones are counted and removed.
pub(super) fn settle_locally(
    given_up: &mut Vec<GivenUp>,
    from: usize,
    out: &mut [Sample],
    (first, radius): (usize, f64),
    stats: &mut SubdivisionStats,
) {
    let mut kept = from;
    for i in from..given_up.len() {
        let g = given_up[i];
        if grow_to_cover(out, first..out.len(), g.point, g.extent, radius, |_| true) {
            stats.unresolved_covered += g.count;
        } else {
            given_up[kept] = g;
            kept += 1;
        }
    }
    given_up.truncate(kept);
}
