//! The run's cap on what it holds until it ends, in samples' worth of memory: the basic regions
//! the partition keeps ([`crate::regions`]) and eq. 22 set up for each sampled literal, charged
//! as they are made, so that a run is refused before it holds more than its sample limit
//! implies.

use std::sync::OnceLock;
use std::sync::atomic::{AtomicU64, Ordering};

use crate::regions::BasicRegion;
use crate::sample_point::Sample;
use qcsg_csg::Aabb;

/// The memory a basic region holds until the run ends, in samples of 72 bytes: the region with
/// the box around its part twice (in its sampling plane's list and in the run's, both held while
/// the one is made from the other) and eq. 22 narrowed to it (`NearDistance`, without what its
/// lists of near terms hold). Charged as one sample each, the 927,000 regions of a flat cone
/// took 2 GB where their charge came to 67 MB (`docs/fuzzing.md`, failure 5).
pub const REGION_SAMPLES: u64 = {
    let held = 2 * size_of::<(usize, BasicRegion, Aabb)>()
        + size_of::<Option<crate::csg_distance::NearDistance<'static>>>();
    held.div_ceil(size_of::<Sample>()) as u64
};

/// What a run holds until it ends, in samples' worth of memory (its sample limit): the basic
/// regions ([`REGION_SAMPLES`] each) and eq. 22 set up for each sampled literal
/// ([`CsgDistance::held_bytes`]). A run of more regions than its sample limit, or whose
/// literals see so many terms near them that their distances take more memory than that many
/// samples (thousands of overlapping parts), would hold more than the limit implies: the
/// decomposition stops as soon as the cap is crossed
/// ([`crate::regions::basic_regions_within`], and `all_regions` of the patches) and the run is
/// refused.
///
/// [`CsgDistance::held_bytes`]: crate::csg_distance::CsgDistance::held_bytes
#[derive(Debug)]
pub struct RegionCap {
    limit: u64,
    regions: AtomicU64,
    distances: AtomicU64,
    crossed: OnceLock<u32>,
}

/// What crossed a [`RegionCap`]: what holds more of it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Held {
    /// The basic regions.
    Regions,
    /// Eq. 22 set up for the sampled literals.
    Distances,
}

impl RegionCap {
    /// A cap of `limit` samples' worth of memory in all.
    pub fn new(limit: u64) -> Self {
        Self {
            limit,
            regions: AtomicU64::new(0),
            distances: AtomicU64::new(0),
            crossed: OnceLock::new(),
        }
    }

    /// Charges `count` more regions of `quadric`, [`REGION_SAMPLES`] each; `false` once the
    /// cap is crossed (by this charge or an earlier one).
    pub(crate) fn charge(&self, count: u64, quadric: u32) -> bool {
        self.charge_to(Held::Regions, count.saturating_mul(REGION_SAMPLES), quadric)
    }

    /// Charges eq. 22 of a literal of `quadric`, which holds `bytes`, as the samples that take
    /// as much memory; `false` once the cap is crossed.
    pub fn charge_distance(&self, bytes: usize, quadric: u32) -> bool {
        let samples = bytes.div_ceil(size_of::<Sample>()) as u64;
        self.charge_to(Held::Distances, samples, quadric)
    }

    fn charge_to(&self, held: Held, count: u64, quadric: u32) -> bool {
        if self.crossed.get().is_some() {
            return false;
        }
        let (counter, other) = match held {
            Held::Regions => (&self.regions, &self.distances),
            Held::Distances => (&self.distances, &self.regions),
        };
        let before = counter.fetch_add(count, Ordering::Relaxed);
        let total = before.saturating_add(count);
        if total.saturating_add(other.load(Ordering::Relaxed)) > self.limit {
            let _ = self.crossed.set(quadric);
            return false;
        }
        true
    }

    /// The quadric being sampled when the cap was first crossed, and what holds more of it
    /// (the same whichever thread's charge crossed it).
    pub fn crossed(&self) -> Option<(u32, Held)> {
        let quadric = *self.crossed.get()?;
        let distances = self.distances.load(Ordering::Relaxed);
        let held = if distances > self.regions.load(Ordering::Relaxed) {
            Held::Distances
        } else {
            Held::Regions
        };
        Some((quadric, held))
    }
}
