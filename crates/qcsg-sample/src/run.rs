//! One sampling run on the current pool ([`sample_on_pool`]): the basic regions of every
//! patch, each with eq. 22 narrowed to it and tiled where it looks at many literals; the first
//! pass over them in runs of blocks; the second pass over the rectangles the first left
//! unproven; the settling of what is given up (probes, then every sample, then cone apices);
//! and the clip lists.

use crate::budget::SampleLimits;
use crate::samples::Samples;
use crate::{apex, blocks, clip, fewest_samples};

use crate::budget::{Budget, Crossed};
use crate::csg_distance::NearDistance;
use crate::error::SampleError;
use crate::fewest_samples::RegionView;
use crate::first_pass_runs::{FirstPass, FirstPassOutput, FirstPassRuns};
use crate::in_order::InOrder;
use crate::memo::QueryMemo;
use crate::patches::{Patch, PlacedRegion, all_regions, near_margin};
use crate::progress::{Progress, REFINE_WORK};
use crate::regions::Held;
use crate::sample_point::Sample;
use crate::sampling::{Sampling, SpareBuffers};
use crate::small_patches;
use crate::stats::SampleStats;
use crate::subdivide::{
    Emitted, GivenUp, Probed, RegionContext, SampleIndex, SubdivisionStats, given_up_share,
    probe_given_up, refine_deferred, sample_region, settle_given_up, settle_parts,
};
use crate::tiles::{TILE_LITERALS, tiles};
use qcsg_csg::Dnf;
use qcsg_quadric::{DVec3, QuadricKind};
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, PoisonError};

/// Distance queries that probing given-up rectangles ([`probe_given_up`]) may make, on top of
/// a sixteenth of the run's queries before it; once they are spent, the rest are counted
/// unresolved. Ordinary scenes leave a handful of such rectangles, which probing mostly
/// settles; tangent and nearly coincident surfaces leave up to millions, most of which it
/// cannot settle, and this bounds what it adds to the run. Following parts down to a speck
/// takes tens of queries a rectangle (`docs/sampler-benchmarks.md`).
pub(super) const PROBE_QUERIES: u64 = 65_536;

/// Fraction of the DNF's diagonal within which a sample counts as on its quadric without
/// Newton steps.
pub(super) const SNAP_SETTLED: f64 = 1e-12;

/// Fraction of the DNF's diagonal below which a part of a rectangle on the surface is a speck
/// ([`RegionContext::speck`]): the length tolerance of the scene, below which eq. 22 takes a
/// point to lie on a plane.
pub(super) const SPECK: f64 = 1e-9;

/// Settles at their cone's apex ([`apex`]) the rectangles given up on each patch, `at_apex`
/// holding how many and how far from the apex they reach: ring samples join `samples`, and
/// the counts move from the unresolved to the covered or discarded ones. What is not on a
/// cone, or not settled, stays unresolved.
pub(super) fn settle_apices(
    dnf: &Dnf,
    (patches, at_apex): (&[Patch], &[(u64, f64)]),
    radius: f64,
    samples: &mut Samples,
    stats: &mut SampleStats,
) {
    for (patch, &(count, reach)) in patches.iter().zip(at_apex) {
        let from_regions = patch.given_up.0;
        if patch.kind != QuadricKind::Cone {
            stats.subdivision.unresolved += count - from_regions;
            continue;
        }
        if count == 0 {
            continue;
        }
        let literals = &dnf.terms[patch.term as usize].literals;
        let others: Vec<qcsg_quadric::Quadric> = (literals.iter())
            .filter(|&&l| l != patch.quadric)
            .filter_map(|&l| Some(dnf.quadrics.get(l as usize)?.quadric))
            .collect();
        let cone = &dnf.quadrics[patch.quadric as usize].quadric;
        let literal = (patch.quadric, patch.term);
        let eq22 = (&patch.distance, &others[..]);
        let counter = match apex::settle(literal, (cone, &patch.frame), eq22, reach, radius) {
            apex::Settled::Off => &mut stats.subdivision.discarded,
            apex::Settled::Covered(ring) => {
                samples.push_run(ring);
                &mut stats.subdivision.unresolved_covered
            }
            apex::Settled::Unresolved => {
                stats.subdivision.unresolved += count - from_regions;
                continue;
            }
        };
        *counter += count;
        stats.regions.unresolved -= from_regions;
    }
}

/// The fewest and the most consecutive items of `count` that one thread folds into one output.
/// Rayon splits an indexed range only a few times and does not split a run a thread is working
/// through, so without a cap one thread could be left with a quarter of the regions while the
/// others idle: about eight runs per thread keep them busy. One thread takes them all as one run
/// (nothing to balance, nothing to concatenate).
pub(super) fn fold_runs(count: usize) -> (usize, usize) {
    match rayon::current_num_threads() {
        0 | 1 => (usize::MAX, usize::MAX),
        threads => (1, count.div_ceil(8 * threads).max(1)),
    }
}

/// [`resample_with_limits`](crate::resample_with_limits) on a thread of the current pool, the first pass's run `k` writing
/// to `memory[k]`.
pub(super) fn sample_on_pool(
    dnf: &Dnf,
    radius: f64,
    (limits, progress): (SampleLimits, &(dyn Fn(Progress) + Sync)),
    (memory, spare): (Vec<Vec<Sample>>, SpareBuffers),
) -> Result<Sampling, SampleError> {
    let budget = Budget::new(limits);
    let crossed = |budget: &Budget| match budget.crossed() {
        Some(Crossed::Samples { quadric }) => Err(SampleError::TooManySamples {
            limit: limits.max_samples,
            quadric,
        }),
        Some(Crossed::Queries { quadric }) => Err(SampleError::TooManyQueries {
            limit: limits.max_queries,
            quadric,
        }),
        None => Ok(()),
    };
    let mut stats = SampleStats::default();
    let too_many = |quadric| SampleError::TooManySamples {
        limit: limits.max_samples,
        quadric,
    };
    // Each region is held to the end of the run, and so is each patch's eq. 22: a
    // decomposition into more regions than the sample limit, or patches whose distances take
    // more memory than that many samples, is refused before eq. 22 is narrowed to each region
    // (a needle or a sharp waist cut into millions of regions took gigabytes here, and so did
    // thousands of overlapping parts).
    let (patches, regions) =
        all_regions(dnf, (radius, limits.max_samples), &mut stats).map_err(|(quadric, held)| {
            match held {
                Held::Regions => too_many(quadric),
                Held::Distances => SampleError::DistancesTooLarge {
                    limit: limits.max_samples,
                    quadric,
                },
            }
        })?;
    // Eq. 22 of each region keeps the terms and literals near the region's patch, narrowed
    // from its whole patch's; regions where that is still many literals are tiled.
    let wholes: Vec<NearDistance<'_>> = patches
        .par_iter()
        .map(|patch| {
            patch
                .distance
                .near(&patch.bounds, near_margin(&patch.bounds, radius))
        })
        .collect();
    // A region where eq. 22 is nowhere negative would emit nothing: it gets none, and is left
    // out.
    let near: Vec<Option<NearDistance<'_>>> = regions
        .par_iter()
        .map(|(patch, _, bounds)| {
            let near = wholes
                .get(*patch)?
                .narrow(bounds, near_margin(bounds, radius));
            (!near.nowhere_negative(bounds)).then_some(near)
        })
        .collect();
    drop(wholes);
    // Each small patch settled by eq. 22 at one point, or refined where a feature is near.
    let limit = (radius, limits.max_samples);
    let (regions, near) =
        small_patches::settle_all((regions, near), &patches, limit, &mut stats.regions)
            .map_err(too_many)?;
    let heavy = |near: &NearDistance<'_>| near.literals_of_large_terms() > TILE_LITERALS;
    let (regions, near): (Vec<PlacedRegion>, Vec<_>) = if near.iter().flatten().any(heavy) {
        regions
            .into_par_iter()
            .zip(near)
            .flat_map_iter(|(region, near)| match near {
                // A small patch takes one sample, whatever its literals.
                Some(near) if heavy(&near) && !small_patches::is_small_patch(&region.1) => {
                    tiles(&patches, region, near, radius)
                }
                near => vec![(region, near)],
            })
            .unzip()
    } else {
        (regions, near)
    };
    stats.basic_regions = near.iter().flatten().count() as u64;
    // Regions all of whose patch is on the surface: their corners need no query.
    let on_surface: Vec<bool> = (regions.par_iter().zip(&near))
        .map(|((_, _, bounds), near)| {
            near.as_ref()
                .is_some_and(|n| n.everywhere_on_surface(bounds))
        })
        .collect();
    // Heightfield points this close to their quadric are not refined (the guarantee asks for
    // 1e-9 of the diagonal; Newton steps are for cancellation far above this).
    let spare_halves = Mutex::new(spare.halves);
    let settled = SNAP_SETTLED * (dnf.bounds.max - dnf.bounds.min).length();
    let speck = SPECK * (dnf.bounds.max - dnf.bounds.min).length();
    let context = |index: usize| {
        let (patch, region, _) = regions.get(index)?;
        let patch = patches.get(*patch)?;
        let entry = dnf.quadrics.get(region.quadric as usize)?;
        (patch.quadric == region.quadric).then_some(RegionContext {
            frame: &patch.frame,
            quadric: &entry.quadric,
            distance: near.get(index)?.as_ref()?,
            on_surface: on_surface[index],
            radius,
            snap: settled,
            apex: (patch.kind == QuadricKind::Cone).then_some(patch.frame.centre),
            speck,
            budget: &budget,
            spare_halves: &spare_halves,
        })
    };
    // First pass: every region on its own. Threads take runs of whole blocks in order
    // ([`blocks`], sized by the regions' estimated work), and each run's output is appended to
    // the whole as soon as its predecessors' are ([`FirstPassRuns`]): the output is the same for
    // any thread count, and no thread copies samples.
    let costs: Vec<f64> = (regions.iter().zip(&near))
        .map(|((_, region, _), near)| {
            near.as_ref()
                .map_or(0.0, |_| blocks::region_cost(region, radius))
        })
        .collect();
    // Costs are finite (`region_cost`); the conversion saturates.
    let work = |region: usize| costs[region].round() as u64;
    let total = (0..costs.len()).fold(0u64, |sum, region| sum.saturating_add(work(region)));
    // A radius far below the scene's size is refused before anything is sampled
    // ([`fewest_samples`]); the bound is sought only where the estimate exceeds the limit.
    if total > limits.max_samples {
        let views: Vec<RegionView<'_>> = (0..regions.len())
            .filter_map(|i| Some(RegionView::new(regions[i].0, &regions[i].1, &context(i)?)))
            .collect();
        let diagonal = (dnf.bounds.max - dnf.bounds.min).length();
        let limit = limits.max_samples;
        if let Some(quadric) = fewest_samples::first_crossing(&views, radius, diagonal, limit) {
            return Err(SampleError::TooManySamples { limit, quadric });
        }
    }
    progress(Progress::Regions {
        count: stats.basic_regions,
        work: total,
    });
    let blocks = blocks::blocks(&costs);
    let runs = blocks::runs(&blocks, &costs, rayon::current_num_threads());
    // Run `k` writes its samples to an earlier sampling's run `k` (the samples of runs past
    // the first pass's are freed).
    let mut buffers = spare.runs;
    buffers.resize_with(runs.len(), FirstPass::default);
    for (buffer, memory) in buffers.iter_mut().zip(memory) {
        buffer.0.samples = memory;
    }
    let first_pass = FirstPassRuns {
        runs: InOrder::new(FirstPassOutput::default()),
        buffers: Mutex::new(buffers),
    };
    let next_run = AtomicUsize::new(0);
    (0..rayon::current_num_threads())
        .into_par_iter()
        .for_each(|_| {
            let mut memo = QueryMemo::default();
            loop {
                let run = next_run.fetch_add(1, Ordering::Relaxed);
                let Some(run_blocks) = runs.get(run) else {
                    break;
                };
                let (mut out, mut deferred, mut counters) = first_pass.buffer(run);
                for block in &blocks[run_blocks.clone()] {
                    let block_start = out.len();
                    for index in block.clone() {
                        if let Some(ctx) = context(index) {
                            let region = (index, &regions[index].1);
                            let walk = (&mut memo, &mut counters);
                            let out = (&mut out, block_start);
                            sample_region(&ctx, region, out, &mut deferred, walk);
                            progress(Progress::RegionDone { work: work(index) });
                        }
                    }
                }
                // A run past a limit ends in an error: its output is not copied on.
                if budget.stopped() {
                    out.clear();
                    deferred.clear();
                }
                first_pass.finish(run, (out, deferred, counters));
            }
        });
    let (first, mut spare_runs) = first_pass.into_output();
    let FirstPassOutput {
        mut samples,
        boxes,
        deferred,
        counters,
    } = first;
    stats.subdivision.add(&counters);
    crossed(&budget)?;
    let count = deferred.len() as u64;
    progress(Progress::Refining {
        count,
        work: count.saturating_mul(REFINE_WORK),
    });
    // Second pass: the rectangles the first left unproven, against all first-pass samples.
    let centres: Vec<(u32, DVec3)> = deferred
        .par_iter()
        .filter_map(|d| {
            let ctx = context(d.region)?;
            let region = &regions[d.region].1;
            Some((region.quadric, d.centre_point(&ctx, region)?))
        })
        .collect();
    let index = SampleIndex::new(dnf, (&samples, &boxes), &centres, radius);
    let share = given_up_share(deferred.len());
    type SecondPass = (
        Emitted,
        Vec<GivenUp>,
        Vec<(u32, f64)>,
        (QueryMemo, SubdivisionStats),
    );
    let (shortest, longest) = fold_runs(deferred.len());
    let refined: Vec<SecondPass> = deferred
        .par_iter()
        .with_min_len(shortest)
        .with_max_len(longest)
        .fold(
            SecondPass::default,
            |(mut out, mut given_up, mut grown, (mut memo, mut counters)), d| {
                if let Some(ctx) = context(d.region) {
                    let (region, index) = (&regions[d.region].1, &index);
                    let outputs = (&mut out, &mut given_up, &mut grown);
                    let walk = (&mut memo, &mut counters);
                    refine_deferred(&ctx, region, d, index, outputs, share, walk);
                }
                progress(Progress::RectangleRefined { work: REFINE_WORK });
                (out, given_up, grown, (memo, counters))
            },
        )
        .collect();
    drop(index);
    // Each part's samples are appended as they are, after the first pass's.
    let mut given_up = Vec::new();
    for (out, more_given_up, grown, (_, counters)) in refined {
        for (i, needed) in grown {
            samples.grow_radius(i, needed);
        }
        samples.push_run(out.samples);
        given_up.extend(more_given_up);
        stats.subdivision.add(&counters);
    }
    crossed(&budget)?;
    // Last: what the second pass gave up, against every sample.
    let uncovered = settle_given_up(
        dnf,
        &given_up,
        (&mut samples, &boxes),
        radius,
        &mut stats.subdivision,
    );
    // Probes write their samples to a run of their own, appended after them all.
    let mut probe_samples = Vec::new();
    let mut allowance = PROBE_QUERIES + stats.subdivision.distance_queries / 16;
    // What stays unresolved is settled at its cone's apex if it lies there: per patch, the
    // rectangles and how far from the frame's centre (a cone's apex) they reach.
    let mut at_apex: Vec<(u64, f64)> = patches.iter().map(|p| p.given_up).collect();
    let mut unsettled: Vec<(&GivenUp, Vec<GivenUp>)> = Vec::new();
    for leaf in &uncovered {
        let before = stats.subdivision.distance_queries;
        let probed = match context(leaf.region) {
            Some(ctx) if allowance > 0 => {
                let (region, out) = (&regions[leaf.region].1, (&mut probe_samples, 0));
                probe_given_up(&ctx, region, leaf, out, &mut stats.subdivision)
            }
            _ => Probed::Unresolved(Vec::new()),
        };
        allowance = allowance.saturating_sub(stats.subdivision.distance_queries - before);
        match probed {
            Probed::Covered => stats.subdivision.unresolved_covered += leaf.count,
            Probed::Off => stats.subdivision.discarded += leaf.count,
            Probed::Unresolved(parts) => unsettled.push((leaf, parts)),
        }
    }
    samples.push_run(probe_samples);
    // What probing left of each, against every sample; what stays unresolved is settled at its
    // cone's apex if it lies there.
    let parts: Vec<Vec<GivenUp>> = unsettled
        .iter_mut()
        .map(|(_, p)| std::mem::take(p))
        .collect();
    let covered = settle_parts(dnf, &parts, (&mut samples, &boxes), radius);
    for ((leaf, _), covered) in unsettled.into_iter().zip(covered) {
        let patch = regions.get(leaf.region).map(|(patch, _, _)| *patch);
        match (covered, patch) {
            (true, _) => stats.subdivision.unresolved_covered += leaf.count,
            (false, Some(p)) => {
                let reach = (leaf.point.position - patches[p].frame.centre).length() + leaf.extent;
                let (count, far) = &mut at_apex[p];
                (*count, *far) = (*count + leaf.count, far.max(reach));
            }
            (false, None) => stats.subdivision.unresolved += leaf.count,
        }
    }
    settle_apices(dnf, (&patches, &at_apex), radius, &mut samples, &mut stats);
    let clip_lists = clip::assign(dnf, &mut samples, &boxes, radius);
    // Run 0 handed its buffers on to the whole (appended first), which hands them back.
    if let Some((out, run_deferred, _)) = spare_runs.first_mut() {
        (out.boxes, *run_deferred) = (boxes, deferred);
        out.clear();
        run_deferred.clear();
    }
    let spare = SpareBuffers {
        runs: spare_runs,
        halves: spare_halves
            .into_inner()
            .unwrap_or_else(PoisonError::into_inner),
    };
    stats.samples = samples.len() as u64;
    stats.clip_lists = clip_lists.len() as u64;
    stats.clip_indices = clip_lists.indices.len() as u64;
    Ok(Sampling {
        samples,
        clip_lists,
        stats,
        spare,
    })
}
