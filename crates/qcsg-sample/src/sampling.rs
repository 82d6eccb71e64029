//! The output of one run ([`Sampling`]): the samples, their clip lists and the counters, and
//! the run's emptied working buffers, kept for the next run ([`crate::resample`]).

use crate::clip::ClipLists;
use crate::samples::Samples;

use crate::first_pass_runs::FirstPass;
use crate::stats::SampleStats;
use crate::subdivide::{Deferred, Emitted, HalfBuffers};

/// The samples and counters of one run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Sampling {
    /// The samples, in region order.
    pub samples: Samples,
    /// The deduplicated clip lists the samples point into.
    pub clip_lists: ClipLists,
    /// The counters.
    pub stats: SampleStats,
    /// The run's working buffers but the samples', emptied, kept for [`resample`](crate::resample): the boxes
    /// and deferred rectangles of the first pass's runs and of the whole, and those of halves
    /// of large cells. Freed with the rest.
    pub(super) spare: SpareBuffers,
}

impl Sampling {
    /// Bytes of memory it keeps beyond its output for the next run ([`resample`](crate::resample)): the
    /// threads' buffers but the samples' (the output's runs), emptied: one set for each run of
    /// regions and for each half of a large cell a run gave away at once, so they do not add up
    /// over runs.
    pub fn spare_bytes(&self) -> usize {
        let bytes = |out: &Emitted, deferred: &Vec<Deferred>| {
            out.heap_bytes() + deferred.capacity() * size_of::<Deferred>()
        };
        let spare = &self.spare;
        let runs = (spare.runs.iter()).map(|(out, d, _)| bytes(out, d));
        let halves = (spare.halves.iter()).map(|(out, d, memo)| bytes(out, d) + memo.heap_bytes());
        runs.chain(halves).sum()
    }

    /// How many buffers [`Self::spare_bytes`] counts.
    pub fn spare_buffers(&self) -> usize {
        self.spare.runs.len() + self.spare.halves.len()
    }
}

/// Empty buffers with their memory, for the next run ([`resample`](crate::resample)), which then writes to
/// memory that is mapped already instead of growing new buffers. They are not part
/// of the output: copies and comparisons leave them out. The samples' own buffers are the
/// output's runs ([`Samples`]).
#[derive(Default)]
pub(super) struct SpareBuffers {
    /// The boxes and deferred rectangles of the first pass's runs by run number (their samples
    /// went to the output); run 0's are those of the whole, which it handed on.
    pub(super) runs: Vec<FirstPass>,
    /// The buffers of halves of large cells that another thread took.
    pub(super) halves: Vec<HalfBuffers>,
}

impl Clone for SpareBuffers {
    fn clone(&self) -> Self {
        Self::default()
    }
}

impl PartialEq for SpareBuffers {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl std::fmt::Debug for SpareBuffers {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} spare buffers", self.runs.len() + 1)
    }
}
