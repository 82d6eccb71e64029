//! How the first pass shares its basic regions out: into blocks, within which a region's small
//! rectangles may be covered by the samples of the regions before it ([`crate::subdivide`]), and
//! runs of whole blocks, which the threads take in order.
//!
//! Both go by an estimate of each region's work made before any is sampled ([`region_cost`]),
//! so that no block and no run holds much more of it than the others. In region order a
//! cube's faces come first: blocks of 64 regions had put half the samples of a cube dimpled by
//! 18 balls into the first block, and on two threads one thread sampled that block while the
//! other, done with all the rest, waited for it and then copied every other block's samples
//! after it. The blocks depend on the regions and the radius alone, so the samples are the same
//! for any number of threads; the runs depend on the number of threads too.

use std::ops::Range;

use crate::regions::BasicRegion;

/// Most regions of a block: around a cone's apex the region decomposition leaves thousands of
/// tiny regions, whose small rectangles the samples of the regions before them cover.
pub const REGION_BLOCK: usize = 64;

/// A block ends before a region that would take its estimated work past this share of all
/// regions' ([`blocks`]), and a region above a quarter of it is a block of its own.
const BLOCK_SHARE: f64 = 1.0 / 16.0;

/// Runs per thread ([`runs`]): enough that a thread done early finds others to take.
const RUNS_PER_THREAD: f64 = 8.0;

/// The estimated work of subdividing a region, in samples, beyond those it may emit.
const REGION_OVERHEAD: f64 = 16.0;

/// A region's estimated work, in samples: those a fill of its whole rectangle at its greatest
/// distortion would emit (a fill's cells have a diagonal of `2r / δ`), plus
/// `REGION_OVERHEAD`. It overestimates regions the surface only partly holds. It places the
/// borders of blocks, and a border only limits which earlier samples may cover a region's small
/// rectangles: the guarantee does not depend on it.
pub fn region_cost(region: &BasicRegion, radius: f64) -> f64 {
    // A small patch takes one sample at most (`crate::small_patches`).
    if region.max_distortion == f64::INFINITY {
        return REGION_OVERHEAD + 1.0;
    }
    let stretched = region.max_distortion / radius;
    let samples = 0.5 * region.rect.width() * region.rect.height() * stretched * stretched;
    // Unbounded or NaN estimates (never for a bounded region) still give a finite total.
    let samples = if samples >= 0.0 {
        samples.min(1e15)
    } else {
        0.0
    };
    REGION_OVERHEAD + samples
}

/// The regions with estimated works `costs` in blocks of consecutive regions: at most
/// [`REGION_BLOCK`] regions, and no more than `BLOCK_SHARE` of the total work unless a
/// single region is; a region of more than a quarter of that share is a block of its own.
pub fn blocks(costs: &[f64]) -> Vec<Range<usize>> {
    let share = BLOCK_SHARE * costs.iter().sum::<f64>();
    let heavy = 0.25 * share;
    let mut blocks = Vec::new();
    let (mut start, mut work) = (0, 0.0);
    for (i, &cost) in costs.iter().enumerate() {
        let full = i - start == REGION_BLOCK || work + cost > share;
        if i > start && (full || cost > heavy || costs[i - 1] > heavy) {
            blocks.push(start..i);
            (start, work) = (i, 0.0);
        }
        work += cost;
    }
    if start < costs.len() {
        blocks.push(start..costs.len());
    }
    blocks
}

/// The blocks in runs of consecutive blocks for `threads` threads: one run on one thread
/// (nothing to balance, nothing to copy), else runs of about `1 / (RUNS_PER_THREAD · threads)`
/// of the estimated work each (a block is never divided).
pub fn runs(blocks: &[Range<usize>], costs: &[f64], threads: usize) -> Vec<Range<usize>> {
    if threads <= 1 {
        return std::iter::once(0..blocks.len()).collect();
    }
    let target = costs.iter().sum::<f64>() / (RUNS_PER_THREAD * threads as f64);
    let mut runs = Vec::new();
    let (mut start, mut work) = (0, 0.0);
    for (i, block) in blocks.iter().enumerate() {
        work += costs[block.clone()].iter().sum::<f64>();
        if work >= target {
            runs.push(start..i + 1);
            (start, work) = (i + 1, 0.0);
        }
    }
    if start < blocks.len() {
        runs.push(start..blocks.len());
    }
    runs
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every index once, in order.
    fn assert_partition(ranges: &[Range<usize>], count: usize) {
        let mut next = 0;
        for range in ranges {
            assert_eq!(range.start, next, "{ranges:?}");
            assert!(range.end > range.start, "{ranges:?}");
            next = range.end;
        }
        assert_eq!(next, count, "{ranges:?}");
    }

    #[test]
    fn like_regions_fill_whole_blocks() {
        let costs = vec![20.0; 300];
        let blocks = blocks(&costs);
        assert_partition(&blocks, 300);
        // A sixteenth of the work is under 19 regions: blocks are capped by work, not count.
        assert!(
            blocks[..blocks.len() - 1].iter().all(|b| b.len() == 18),
            "{blocks:?}"
        );
        let costs = vec![20.0; 5000];
        let blocks = super::blocks(&costs);
        assert_partition(&blocks, 5000);
        assert!(
            blocks[..blocks.len() - 1]
                .iter()
                .all(|b| b.len() == REGION_BLOCK)
        );
    }

    #[test]
    fn heavy_regions_stand_alone() {
        // Six heavy faces first, then many light regions.
        let mut costs = vec![50_000.0; 6];
        costs.extend(vec![20.0; 3000]);
        let blocks = blocks(&costs);
        assert_partition(&blocks, costs.len());
        assert!(
            blocks[..6].iter().all(|b| b.len() == 1),
            "{:?}",
            &blocks[..8]
        );
        assert_eq!(blocks[6].len(), REGION_BLOCK);
        // On two threads no run holds much more than its share, but for a single heavy block.
        let runs = runs(&blocks, &costs, 2);
        assert_partition(&runs, blocks.len());
        let total: f64 = costs.iter().sum();
        for run in &runs {
            let work: f64 = blocks[run.clone()]
                .iter()
                .map(|b| costs[b.clone()].iter().sum::<f64>())
                .sum();
            assert!(
                run.len() == 1 || work < 2.0 * total / 16.0,
                "{run:?}: {work}"
            );
        }
    }

    #[test]
    fn one_thread_takes_one_run() {
        let costs = vec![1.0, 1e9, 3.0, 0.0, 7.0];
        let blocks = blocks(&costs);
        assert_partition(&blocks, costs.len());
        let whole: Vec<Range<usize>> = std::iter::once(0..blocks.len()).collect();
        assert_eq!(runs(&blocks, &costs, 1), whole);
        assert_partition(&runs(&blocks, &costs, 4), blocks.len());
        assert!(super::blocks(&[]).is_empty());
        assert!(runs(&[], &[], 2).is_empty());
    }
}
