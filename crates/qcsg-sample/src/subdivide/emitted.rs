//! Samples as a subdivision emits them ([`Emitted`]), with boxes around runs of consecutive
//! samples of one quadric and term ([`SampleBox`]), through which the second pass and the
//! settling read only the runs near what they cover.

use crate::sample_point::Sample;
use qcsg_quadric::DVec3;

/// Samples as a subdivision emits them, with boxes around runs of consecutive samples
/// ([`SampleBox`]): the second pass's index reads only the runs whose box comes near a
/// deferred rectangle ([`SampleIndex::new`](crate::subdivide::SampleIndex::new)), a few percent of the samples at small radii. The
/// subdivision goes depth first and fills row by row, so consecutive samples lie close
/// together. It dereferences to the samples.
#[derive(Clone, Debug, Default)]
pub struct Emitted {
    /// The samples, in order.
    pub samples: Vec<Sample>,
    /// Boxes around `samples[..boxed]`, in order, one after the other.
    pub boxes: Vec<SampleBox>,
    pub(super) boxed: usize,
}

/// Consecutive samples of one quadric and term and a box that holds their positions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SampleBox {
    /// The first sample.
    pub start: u32,
    /// One past the last sample.
    pub end: u32,
    /// Their quadric.
    pub quadric: u32,
    /// Their term.
    pub term: u32,
    /// The box's lowest corner.
    pub low: DVec3,
    /// The box's highest corner.
    pub high: DVec3,
}

impl SampleBox {
    /// The same box, its samples `by` places later in the order.
    pub fn shifted(self, by: u32) -> Self {
        Self {
            start: self.start + by,
            end: self.end + by,
            ..self
        }
    }
}

/// Most samples of one box: a long row of a fill that passes near a deferred rectangle is read
/// only where it does.
pub const BOX_SAMPLES: usize = 32;

impl Emitted {
    /// Boxes the samples emitted since the last call ([`box_runs`]). Called after each fill,
    /// each region and before appending, so that a box holds one fill's samples (or the few
    /// emitted between fills), which lie close together.
    pub fn box_new(&mut self) {
        box_runs(&self.samples, self.boxed, &mut self.boxes);
        self.boxed = self.samples.len();
    }

    /// [`Self::box_new`] for the samples of one fill, all of one quadric and term: runs of
    /// [`BOX_SAMPLES`] without comparing each sample's.
    pub(super) fn box_fill(&mut self) {
        let rest = self.samples.get(self.boxed..).unwrap_or_default();
        let Some(&Sample { quadric, term, .. }) = rest.first() else {
            return;
        };
        debug_assert!(rest.iter().all(|s| (s.quadric, s.term) == (quadric, term)));
        let mut start = self.boxed;
        for run in rest.chunks(BOX_SAMPLES) {
            let first = run[0].position;
            let (low, high) = run.iter().fold((first, first), |(low, high), s| {
                (low.min(s.position), high.max(s.position))
            });
            self.boxes.push(SampleBox {
                start: start as u32,
                end: (start + run.len()) as u32,
                quadric,
                term,
                low,
                high,
            });
            start += run.len();
        }
        self.boxed = self.samples.len();
    }

    /// Moves `more` to the end, leaving it empty (with its buffers when they were copied;
    /// into an empty `self` they are taken over instead).
    pub fn append(&mut self, more: &mut Emitted) {
        more.box_new();
        if self.samples.is_empty() {
            std::mem::swap(self, more);
        } else {
            self.box_new();
            let offset = self.samples.len() as u32;
            self.boxes
                .extend(more.boxes.iter().map(|b| b.shifted(offset)));
            self.samples.extend_from_slice(&more.samples);
            self.boxed = self.samples.len();
        }
        more.clear();
    }

    /// Bytes of its buffers.
    pub fn heap_bytes(&self) -> usize {
        self.samples.capacity() * size_of::<Sample>()
            + self.boxes.capacity() * size_of::<SampleBox>()
    }

    /// Empties it, keeping its memory.
    pub fn clear(&mut self) {
        self.samples.clear();
        self.boxes.clear();
        self.boxed = 0;
    }
}

/// Appends boxes around `samples[first..]`, in runs of one quadric and term of at most
/// [`BOX_SAMPLES`].
pub fn box_runs(samples: &[Sample], first: usize, boxes: &mut Vec<SampleBox>) {
    // One pass: after a large fill the samples are no longer in the cache. A run at a time, in
    // a loop of its own: with the open box in an `Option` matched for every sample, this took a
    // tenth of the instructions of sampling a lone ball.
    let rest = samples.get(first..).unwrap_or_default();
    let mut start = 0;
    while let Some(head) = rest.get(start) {
        let (quadric, term) = (head.quadric, head.term);
        let limit = rest.len().min(start + BOX_SAMPLES);
        let (mut low, mut high) = (head.position, head.position);
        let mut end = start + 1;
        while let Some(sample) = rest
            .get(end)
            .filter(|s| s.quadric == quadric && s.term == term)
            && end < limit
        {
            (low, high) = (low.min(sample.position), high.max(sample.position));
            end += 1;
        }
        boxes.push(SampleBox {
            start: (first + start) as u32,
            end: (first + end) as u32,
            quadric,
            term,
            low,
            high,
        });
        start = end;
    }
}

impl From<Vec<Sample>> for Emitted {
    fn from(samples: Vec<Sample>) -> Self {
        Self {
            samples,
            ..Self::default()
        }
    }
}

impl std::ops::Deref for Emitted {
    type Target = Vec<Sample>;

    fn deref(&self) -> &Vec<Sample> {
        &self.samples
    }
}

impl std::ops::DerefMut for Emitted {
    fn deref_mut(&mut self) -> &mut Vec<Sample> {
        &mut self.samples
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use qcsg_quadric::DVec3;

    /// A fill's samples get the boxes [`Emitted::box_new`] would give them.
    #[test]
    fn a_fill_is_boxed_as_box_new_boxes_it() {
        let sample = |i: u32| Sample {
            position: DVec3::new(f64::from(i).sin(), f64::from(i * 7 % 13), -f64::from(i)),
            normal: DVec3::Z,
            quadric: 3,
            term: 1,
            radius: 0.1,
            clip_list: 0,
        };
        for count in [0, 1, 31, 32, 33, 100] {
            let mut before = Emitted::default();
            before.samples.push(Sample {
                quadric: 0,
                ..sample(999)
            });
            before.box_new();
            let (mut by_new, mut by_fill) = (before.clone(), before);
            by_new.samples.extend((0..count).map(sample));
            by_fill.samples.extend((0..count).map(sample));
            by_new.box_new();
            by_fill.box_fill();
            assert_eq!(by_fill.boxes, by_new.boxes, "{count} samples");
            assert_eq!(by_fill.boxed, by_new.boxed);
        }
    }
}
