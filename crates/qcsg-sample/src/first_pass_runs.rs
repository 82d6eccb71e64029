//! The first pass's runs of regions, appended in run order as soon as their predecessors are
//! ([`FirstPassRuns`]), each writing to buffers an earlier run of the same number left, so that
//! the output is the same for any thread count and no thread copies samples.

use crate::samples::Samples;

use crate::in_order::{InOrder, lock};
use crate::subdivide::{Deferred, Emitted, SampleBox, SubdivisionStats};
use std::sync::{Mutex, PoisonError};

/// The first pass's output of a run of regions.
pub(super) type FirstPass = (Emitted, Vec<Deferred>, SubdivisionStats);

/// The first pass's output of all runs, in run order: each run's samples as the run wrote them
/// ([`Samples`]), the boxes around them, the deferred rectangles and the counters.
#[derive(Default)]
pub(super) struct FirstPassOutput {
    pub(super) samples: Samples,
    pub(super) boxes: Vec<SampleBox>,
    pub(super) deferred: Vec<Deferred>,
    pub(super) counters: SubdivisionStats,
}

impl FirstPassOutput {
    /// Moves a run's output to the end, its samples without copying them, leaving it empty.
    pub(super) fn append(&mut self, (out, deferred, counters): &mut FirstPass) {
        out.box_new();
        let offset = self.samples.len() as u32;
        if self.boxes.is_empty() {
            // The first run's boxes are taken over, as they are.
            std::mem::swap(&mut self.boxes, &mut out.boxes);
        } else {
            self.boxes
                .extend(out.boxes.iter().map(|b| b.shifted(offset)));
        }
        self.samples.push_run(std::mem::take(&mut out.samples));
        out.clear();
        if self.deferred.is_empty() {
            std::mem::swap(&mut self.deferred, deferred);
        } else {
            self.deferred.extend_from_slice(deferred);
        }
        deferred.clear();
        self.counters.add(&std::mem::take(counters));
    }
}

/// The first pass's runs, appended in run order as soon as their predecessors are
/// ([`InOrder`]). Run `k` writes to the buffers of an earlier sampling's run `k`, of about the
/// size it needs when the scene is the same, so that the runs write to memory that is already
/// mapped: page faults were most of the cost of concatenating the runs at the end.
pub(super) struct FirstPassRuns {
    pub(super) runs: InOrder<(usize, FirstPass), FirstPassOutput>,
    /// Buffers by run number, taken by the run and given back once it is appended (its samples
    /// go on in the output).
    pub(super) buffers: Mutex<Vec<FirstPass>>,
}

impl FirstPassRuns {
    /// Buffers for run `run`.
    pub(super) fn buffer(&self, run: usize) -> FirstPass {
        lock(&self.buffers)
            .get_mut(run)
            .map(std::mem::take)
            .unwrap_or_default()
    }

    /// Hands in run `run`'s output.
    pub(super) fn finish(&self, run: usize, output: FirstPass) {
        self.runs
            .finish(run, (run, output), |all, (run, mut output)| {
                all.append(&mut output);
                give_back(&mut lock(&self.buffers), run, output);
            });
    }

    /// The whole output, once every run is in, and the runs' buffers by run number.
    pub(super) fn into_output(self) -> (FirstPassOutput, Vec<FirstPass>) {
        let (mut all, waiting) = self.runs.into_parts();
        let mut buffers = self
            .buffers
            .into_inner()
            .unwrap_or_else(PoisonError::into_inner);
        // Nothing is left waiting when every run has been handed in; appending what is keeps
        // the output whole regardless.
        for (run, mut output) in waiting {
            all.append(&mut output);
            give_back(&mut buffers, run, output);
        }
        (all, buffers)
    }
}

/// Puts run `run`'s emptied buffers back in its place.
pub(super) fn give_back(buffers: &mut Vec<FirstPass>, run: usize, output: FirstPass) {
    if buffers.len() <= run {
        buffers.resize_with(run + 1, FirstPass::default);
    }
    buffers[run] = output;
}
