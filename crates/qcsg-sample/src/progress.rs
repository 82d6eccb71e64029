//! Progress of a sampling run ([`Progress`]), counted in units of about one sample's work.

/// Progress of a sampling run, reported from the worker threads. Its work is counted in units
/// of about one sample's: a basic region weighs its estimated samples
/// ([`blocks::region_cost`](crate::blocks::region_cost)), a rectangle the second pass refines [`REFINE_WORK`]. A progress
/// bar over the work moves about as time does, where one over regions would not: a few large
/// regions often hold most of the samples.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Progress {
    /// The basic regions are known.
    Regions {
        /// How many will be sampled.
        count: u64,
        /// Their work in all.
        work: u64,
    },
    /// One more basic region is done.
    RegionDone {
        /// Its work.
        work: u64,
    },
    /// The first pass is done: the rectangles it left unproven are refined now, against its
    /// samples (the second pass).
    Refining {
        /// How many.
        count: u64,
        /// Their work in all.
        work: u64,
    },
    /// One more of those rectangles is refined.
    RectangleRefined {
        /// Its work.
        work: u64,
    },
}

/// The work of refining one rectangle ([`Progress`]), in the units of the first pass's work:
/// about what the second pass takes a rectangle on the benchmark scenes
/// (`docs/sampler-benchmarks.md`).
pub const REFINE_WORK: u64 = 32;
