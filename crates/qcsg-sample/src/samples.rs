//! The samples of a sampling ([`Samples`]): one sequence, stored as the runs the threads wrote.
//!
//! On more threads than one, the first pass samples runs of regions in parallel, each into a
//! buffer of its own. Copying those buffers into one vector, in order, costs a visible share of
//! a two-thread run of sample-heavy scenes (`docs/sampler-benchmarks.md`); keeping the buffers
//! as they are costs nothing, and every consumer of the samples reads them once in order anyway (a splat upload, a PLY file). The sequence is
//! the same for any thread count; only where it is cut into runs differs.

use std::ops::Range;

use crate::sample_point::Sample;
use crate::subdivide::grow_radius;

/// Samples in order, stored as consecutive runs. Index `i` is the `i`-th sample of the whole
/// sequence; equality compares the sequences, not how they are cut.
#[derive(Clone, Default)]
pub struct Samples {
    /// The runs, none empty.
    runs: Vec<Vec<Sample>>,
    /// The index of each run's first sample.
    starts: Vec<usize>,
    len: usize,
}

/// The samples of [`Samples`], in order.
pub type Iter<'a> = std::iter::Flatten<std::slice::Iter<'a, Vec<Sample>>>;

impl Samples {
    /// How many samples.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether there is none.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The samples in order.
    pub fn iter(&self) -> Iter<'_> {
        self.runs.iter().flatten()
    }

    /// The runs the samples are stored in, in order: concatenated, they are the samples. For
    /// copies in bulk (an upload, a file).
    pub fn runs(&self) -> impl ExactSizeIterator<Item = &[Sample]> {
        self.runs.iter().map(Vec::as_slice)
    }

    /// Sample `i`, if there are that many.
    #[inline]
    pub fn get(&self, i: usize) -> Option<&Sample> {
        let (run, at) = self.locate(i)?;
        self.runs[run].get(at)
    }

    /// The samples in one vector.
    pub fn to_vec(&self) -> Vec<Sample> {
        let mut all = Vec::with_capacity(self.len);
        for run in &self.runs {
            all.extend_from_slice(run);
        }
        all
    }

    /// Bytes of memory the runs hold (their capacity).
    pub fn heap_bytes(&self) -> usize {
        let samples: usize = self.runs.iter().map(Vec::capacity).sum();
        samples * size_of::<Sample>()
    }

    /// Grows sample `i`'s radius to `needed` (never shrinks it; [`grow_radius`]).
    pub(crate) fn grow_radius(&mut self, i: u32, needed: f64) {
        if let Some((run, at)) = self.locate(i as usize) {
            grow_radius(&mut self.runs[run], at as u32, needed);
        }
    }

    /// Appends `run` as it is, without copying it (an empty one is dropped).
    pub fn push_run(&mut self, run: Vec<Sample>) {
        if run.is_empty() {
            return;
        }
        self.starts.push(self.len);
        self.len += run.len();
        self.runs.push(run);
    }

    /// The samples of `range`, run by run: each piece with the index of its first sample.
    pub(crate) fn pieces(&self, range: Range<usize>) -> Pieces<'_> {
        let run = self
            .locate(range.start)
            .map_or(self.runs.len(), |(run, _)| run);
        let end = range.end.min(self.len);
        Pieces {
            samples: self,
            run,
            range: range.start..end,
        }
    }

    /// The runs, each with the index of its first sample, to change their samples.
    pub(crate) fn runs_mut(&mut self) -> impl Iterator<Item = (usize, &mut [Sample])> {
        self.starts
            .iter()
            .copied()
            .zip(self.runs.iter_mut().map(Vec::as_mut_slice))
    }

    /// The runs' vectors, to write to again.
    pub(crate) fn into_runs(self) -> Vec<Vec<Sample>> {
        self.runs
    }

    /// The run holding sample `i` and its place in it.
    #[inline]
    fn locate(&self, i: usize) -> Option<(usize, usize)> {
        if i >= self.len {
            return None;
        }
        // One run (one thread's first pass): no search.
        let run = match self.runs.len() {
            1 => 0,
            _ => self.starts.partition_point(|&start| start <= i) - 1,
        };
        Some((run, i - self.starts[run]))
    }
}

/// The samples of a range, run by run ([`Samples::pieces`]).
pub(crate) struct Pieces<'a> {
    samples: &'a Samples,
    /// The run holding the range's start.
    run: usize,
    range: Range<usize>,
}

impl<'a> Iterator for Pieces<'a> {
    type Item = (usize, &'a [Sample]);

    fn next(&mut self) -> Option<Self::Item> {
        if self.range.is_empty() {
            return None;
        }
        let (&start, run) = self
            .samples
            .starts
            .get(self.run)
            .zip(self.samples.runs.get(self.run))?;
        let end = self.range.end.min(start + run.len());
        let piece = run.get(self.range.start - start..end - start)?;
        let first = self.range.start;
        (self.range.start, self.run) = (end, self.run + 1);
        Some((first, piece))
    }
}

impl From<Vec<Sample>> for Samples {
    fn from(samples: Vec<Sample>) -> Self {
        let mut all = Self::default();
        all.push_run(samples);
        all
    }
}

impl FromIterator<Sample> for Samples {
    fn from_iter<I: IntoIterator<Item = Sample>>(samples: I) -> Self {
        Self::from(samples.into_iter().collect::<Vec<_>>())
    }
}

impl<'a> IntoIterator for &'a Samples {
    type Item = &'a Sample;
    type IntoIter = Iter<'a>;

    fn into_iter(self) -> Iter<'a> {
        self.iter()
    }
}

impl std::ops::Index<usize> for Samples {
    type Output = Sample;

    #[inline]
    fn index(&self, i: usize) -> &Sample {
        match self.get(i) {
            Some(sample) => sample,
            None => panic!("sample {i} of {}", self.len),
        }
    }
}

impl PartialEq for Samples {
    fn eq(&self, other: &Self) -> bool {
        self.len == other.len && self.iter().eq(other.iter())
    }
}

impl std::fmt::Debug for Samples {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list().entries(self.iter()).finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use qcsg_quadric::DVec3;

    fn sample(k: u32) -> Sample {
        Sample {
            position: DVec3::splat(f64::from(k)),
            normal: DVec3::Z,
            quadric: k,
            term: 0,
            radius: 1.0,
            clip_list: 0,
        }
    }

    /// Samples `0..n` cut into runs of the given lengths.
    fn cut(lengths: &[u32]) -> Samples {
        let mut all = Samples::default();
        let mut next = 0;
        for &length in lengths {
            all.push_run((next..next + length).map(sample).collect());
            next += length;
        }
        all
    }

    #[test]
    fn indices_run_across_the_runs() {
        let all = cut(&[3, 0, 1, 4]);
        assert_eq!(all.len(), 8);
        assert_eq!(all.runs().len(), 3, "the empty run is dropped");
        for i in 0..8 {
            assert_eq!(all[i].quadric, i as u32);
        }
        assert!(all.get(8).is_none());
        let order: Vec<u32> = all.iter().map(|s| s.quadric).collect();
        assert_eq!(order, (0..8).collect::<Vec<_>>());
    }

    #[test]
    fn the_same_sequence_cut_differently_is_equal() {
        assert_eq!(cut(&[3, 1, 4]), cut(&[8]));
        assert_eq!(cut(&[3, 1, 4]), Samples::from(cut(&[2, 6]).to_vec()));
        assert_ne!(cut(&[3, 1, 4]), cut(&[3, 1, 3]));
        let mut changed = cut(&[3, 1, 4]);
        changed.grow_radius(5, 2.0);
        assert_ne!(changed, cut(&[8]));
    }

    #[test]
    fn pieces_cover_a_range_run_by_run() {
        let all = cut(&[3, 1, 4]);
        let pieces: Vec<(usize, Vec<u32>)> = all
            .pieces(2..6)
            .map(|(start, run)| (start, run.iter().map(|s| s.quadric).collect()))
            .collect();
        assert_eq!(pieces, [(2, vec![2]), (3, vec![3]), (4, vec![4, 5])]);
        assert_eq!(all.pieces(8..8).count(), 0);
        assert_eq!(all.pieces(5..5).count(), 0);
    }
}
