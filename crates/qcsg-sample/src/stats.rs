//! The counters of one sampling run ([`SampleStats`]).

use crate::regions::RegionStats;
use crate::subdivide::SubdivisionStats;

/// Counters of one sampling run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SampleStats {
    /// Samples emitted.
    pub samples: u64,
    /// Basic regions sampled.
    pub basic_regions: u64,
    /// Region decomposition counters.
    pub regions: RegionStats,
    /// Subdivision counters (distance queries among them).
    pub subdivision: SubdivisionStats,
    /// Bytes that eq. 22 set up for the sampled literals holds until the run ends
    /// ([`CsgDistance::held_bytes`](crate::csg_distance::CsgDistance::held_bytes)), charged to the sample
    /// limit.
    pub distance_bytes: u64,
    /// Terms skipped because their box is unbounded.
    pub unbounded_terms: u64,
    /// Distinct clip lists.
    pub clip_lists: u64,
    /// Quadric indices in the deduplicated clip lists (paper Table 2's "clip indices").
    pub clip_indices: u64,
}

impl SampleStats {
    /// Rectangles given up unproven, in the region decomposition (around cone apices, where the
    /// distortion has no bound) and in the subdivision: where the guarantee is not proven.
    pub fn unresolved(&self) -> u64 {
        self.regions.unresolved + self.subdivision.unresolved
    }
}
