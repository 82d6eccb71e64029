//! Clip lists (paper §6): for every sample, the other quadrics of its term whose surface comes
//! within the sample's radius, so that a renderer can clip the sample's splat locally.
//!
//! A literal `j` of the sample's term enters the list unless its conservative distance (eqs.
//! 10-12, a lower bound of the true distance) exceeds the radius at the sample: then no point of
//! `Q_j` lies within the radius, and nothing inside the splat can be cut by it. Nor does a
//! literal whose every sheet lies on a surface of the sampled quadric, as the compiler found
//! them (`on_its_surface`): it cuts no splat of that quadric. The test is
//! conservative: a quadric whose surface does reach into the splat is never left out.
//!
//! The work goes by spans, the boxes the first pass keeps around runs of consecutive samples of
//! one quadric and term ([`SampleBox`]): a literal whose surface provably stays farther than
//! the run's radius `r` from a span's box is left out for all its samples at once, and a span
//! with no literal left is not read at all; its samples keep list 0, the empty list. Most spans
//! lie inside faces, away from every other literal. A term of many literals (a plate drilled
//! with many holes) first leaves out those whose surface misses a box around a thousand of its
//! samples grown by `r`; the rest are tested per span as above.
//!
//! Identical lists are stored once: [`ClipLists`] is one indirection buffer, and each sample
//! holds the index of its list. Lists after the empty one are numbered in order of first use in
//! the (deterministic) sample order, so the buffer is the same for any thread count.

use qcsg_csg::quadric_box::{self, BoxClass};
use qcsg_csg::{Aabb, Dnf};
use qcsg_quadric::{DVec3, Quadric};
use rayon::prelude::*;
use rustc_hash::FxHashMap;
use std::ops::Range;
use std::sync::Mutex;

use crate::in_order::{InOrder, lock};
use crate::sample_point::Sample;
use crate::samples::Samples;
use crate::subdivide::{SampleBox, box_runs};

/// Deduplicated clip lists: list `k` is `indices[offsets[k]..offsets[k + 1]]`, indices into
/// [`Dnf::quadrics`], ascending. List 0 is the empty list.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ClipLists {
    /// Start of each list in `indices`, plus one final entry: `offsets.len()` is the number of
    /// lists plus one.
    pub offsets: Vec<u32>,
    /// The lists' quadric indices, concatenated.
    pub indices: Vec<u32>,
}

impl Default for ClipLists {
    /// The empty list alone, as list 0.
    fn default() -> Self {
        Self {
            offsets: vec![0, 0],
            indices: Vec::new(),
        }
    }
}

impl ClipLists {
    /// Number of distinct lists.
    pub fn len(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    /// Whether there is no list at all.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// List `k`, or `None` if out of range.
    pub fn get(&self, k: u32) -> Option<&[u32]> {
        let k = k as usize;
        let start = *self.offsets.get(k)? as usize;
        let end = *self.offsets.get(k + 1)? as usize;
        self.indices.get(start..end)
    }
}

/// Clip lists of one batch of samples before deduplication: the runs of samples (indices into
/// the batch) that need lists, and `lengths[i]` indices of the `i`-th sample of those runs,
/// concatenated in `indices`. The samples outside the runs keep the empty list.
#[derive(Clone, Debug, Default)]
struct RawClipLists {
    runs: Vec<Range<usize>>,
    lengths: Vec<u32>,
    indices: Vec<u32>,
}

impl RawClipLists {
    /// Appends the clip lists of the samples of `spans` (boxes around consecutive samples of
    /// one quadric and term, holding `samples`, which start at sample `offset`).
    ///
    /// A literal is left out for a whole span at once when its surface stays farther than
    /// `radius` (the largest radius of any sample) from the span's box; a span with no literal
    /// left needs nothing, and its samples are not read. Neighbouring samples and spans mostly
    /// lie far from the same literals, so each literal keeps the last point where its
    /// conservative distance `L` was evaluated: the true distance is 1-Lipschitz, so at a point
    /// `Δ` away it is at least `L − Δ`, and the literal is left out without evaluating it again
    /// when that exceeds the radius.
    fn push_spans(
        &mut self,
        dnf: &Dnf,
        (samples, offset): (&[Sample], usize),
        spans: &[SampleBox],
        radius: f64,
    ) {
        let mut anchors: Vec<Option<(DVec3, f64)>> = vec![None; dnf.quadrics.len()];
        let (mut near, mut close) = (Vec::new(), Vec::new());
        for run in spans.chunk_by(|a, b| a.term == b.term) {
            let Some(term) = dnf.terms.get(run[0].term as usize) else {
                continue;
            };
            for group in chunks_of_samples(run, CLIP_CHUNK) {
                let (low, high) = group.iter().fold(
                    (DVec3::INFINITY, DVec3::NEG_INFINITY),
                    |(low, high), span| (low.min(span.low), high.max(span.high)),
                );
                literals_near(dnf, (low, high, radius), &term.literals, &mut near);
                // Per span, the distance test alone: a box test of each literal for each span
                // took a sixth of the instructions of sampling a cube dimpled by 18 balls and
                // half of those of a plate drilled with 144 holes, and changed no list of the
                // examples and stability scenes.
                for span in group {
                    close.clear();
                    for &literal in &near {
                        let (Some(entry), Some(anchor)) = (
                            dnf.quadrics.get(literal as usize),
                            anchors.get_mut(literal as usize),
                        ) else {
                            continue;
                        };
                        if literal != span.quadric
                            && !on_its_surface(dnf, literal, span.quadric)
                            && !stays_away(&entry.quadric, (span.low, span.high, radius), anchor)
                        {
                            close.push(literal);
                        }
                    }
                    if close.is_empty() {
                        continue;
                    }
                    let (start, end) = (span.start as usize - offset, span.end as usize - offset);
                    let Some(samples) = samples.get(start..end) else {
                        continue;
                    };
                    self.push_run(dnf, samples, &close, &mut anchors);
                    match self.runs.last_mut() {
                        Some(last) if last.end == start => last.end = end,
                        _ => self.runs.push(start..end),
                    }
                }
            }
        }
    }

    /// Appends the clip list of each of `samples` (of one quadric and term), among `literals`.
    fn push_run(
        &mut self,
        dnf: &Dnf,
        samples: &[Sample],
        literals: &[u32],
        anchors: &mut [Option<(DVec3, f64)>],
    ) {
        for sample in samples {
            let start = self.indices.len();
            for &literal in literals {
                let (Some(entry), Some(anchor)) = (
                    dnf.quadrics.get(literal as usize),
                    anchors.get_mut(literal as usize),
                ) else {
                    continue;
                };
                // `L − Δ > radius`, squared: no square root per literal and sample.
                if let Some((point, distance)) = *anchor {
                    let slack = distance - sample.radius;
                    if slack > 0.0 && (sample.position - point).length_squared() < slack * slack {
                        continue;
                    }
                }
                let distance = entry.quadric.conservative_distance(sample.position).abs();
                // NaN (never for finite samples) keeps the literal: conservative.
                if distance.is_nan() || distance <= sample.radius {
                    self.indices.push(literal);
                    *anchor = None;
                } else {
                    *anchor = Some((sample.position, distance));
                }
            }
            let list = &mut self.indices[start..];
            list.sort_unstable();
            let mut unique = 0;
            for i in 0..list.len() {
                if i == 0 || list[i] != list[unique - 1] {
                    list[unique] = list[i];
                    unique += 1;
                }
            }
            self.indices.truncate(start + unique);
            self.lengths.push(unique as u32);
        }
    }
}

/// Whether every sheet of `literal` lies on a surface of `quadric`, as the compiler found them
/// ([`Dnf::surfaces`]): a literal that is the sampled quadric written again (a face of a part
/// flush with a face of another, turned or moved so that its coefficients differ in their last
/// bits). On a sheet they share it is zero, and on another sheet of the sampled quadric it
/// holds wherever the term has samples, so it cuts no splat; on the GPU its value on the shared
/// sheet would be rounding noise in `f32`, and would cut pixels out of the splats at random.
fn on_its_surface(dnf: &Dnf, literal: u32, quadric: u32) -> bool {
    let surfaces = &dnf.surfaces;
    if surfaces.quadric_count() != dnf.quadrics.len() {
        return false;
    }
    let (Some(own), Some(other)) = (surfaces.of(quadric), surfaces.of(literal)) else {
        return false;
    };
    !other.is_empty() && (other.iter()).all(|sheet| own.iter().any(|s| s.surface == sheet.surface))
}

/// Whether the surface of `quadric` provably stays farther than `radius` from every point of
/// the box `low..high`: by the literal's last evaluation (`anchor`, see
/// [`RawClipLists::push_spans`]) and the box's farthest corner from it, or else by an
/// evaluation at the box's centre, which becomes the anchor when it decides.
fn stays_away(
    quadric: &Quadric,
    (low, high, radius): (DVec3, DVec3, f64),
    anchor: &mut Option<(DVec3, f64)>,
) -> bool {
    if let Some((point, distance)) = *anchor {
        let slack = distance - radius;
        let farthest = (point - low).abs().max((point - high).abs());
        if slack > 0.0 && farthest.length_squared() < slack * slack {
            return true;
        }
    }
    let centre = 0.5 * (low + high);
    let distance = quadric.conservative_distance(centre).abs();
    // NaN (a box of infinite or unknown size) decides nothing.
    if distance - 0.5 * (high - low).length() > radius {
        *anchor = Some((centre, distance));
        return true;
    }
    false
}

/// `spans` in consecutive groups of about `samples` samples (a span is never divided).
fn chunks_of_samples(spans: &[SampleBox], samples: usize) -> impl Iterator<Item = &[SampleBox]> {
    let mut rest = spans;
    std::iter::from_fn(move || {
        if rest.is_empty() {
            return None;
        }
        let mut count = 0;
        let cut = rest
            .iter()
            .position(|span| {
                count += (span.end - span.start) as usize;
                count >= samples
            })
            .map_or(rest.len(), |i| i + 1);
        let (group, after) = rest.split_at(cut);
        rest = after;
        Some(group)
    })
}

/// Samples per parallel batch when clip lists are computed.
const CLIP_BATCH: usize = 4096;

/// Consecutive samples of one term whose literals are first sorted out together, on a box
/// around them all ([`literals_near`]), then again per span.
const CLIP_CHUNK: usize = 1024;

/// Terms with more literals than this sort them out by box before testing each span.
const FEW_LITERALS: usize = 16;

/// Into `out`, the literals of `literals` whose surface may come within `radius` of the box
/// `low..high`: all of them when they are few, else those whose surface may cross the box grown
/// by `radius` (`quadric_box::classify`). A literal left out has no surface point in the grown
/// box, so none within the radius of any sample in the box.
fn literals_near(
    dnf: &Dnf,
    (low, high, radius): (DVec3, DVec3, f64),
    literals: &[u32],
    out: &mut Vec<u32>,
) {
    out.clear();
    if literals.len() <= FEW_LITERALS {
        out.extend_from_slice(literals);
        return;
    }
    let grown = Aabb::new(low, high).expanded(radius);
    out.extend(literals.iter().copied().filter(|&literal| {
        dnf.quadrics
            .get(literal as usize)
            .is_none_or(|entry| quadric_box::classify(&entry.quadric, &grown) == BoxClass::Cuts)
    }));
}

/// Computes every sample's clip list (in parallel batches), stores each distinct list once and
/// sets `clip_list` of each sample; list 0 is the empty list, and the others are numbered in
/// sample order. `boxes` are boxes around runs of the samples from the first on, as the first
/// pass leaves them ([`SampleBox`]; what they do not hold is boxed here), and no sample's radius
/// exceeds `radius`. Samples arrive with list 0, which those whose spans need no list keep
/// unread: on a lone ball at 0.05 % of the diagonal, reading every sample's term had taken a
/// fifth of the run. Each batch is numbered as soon as the batches before it are
/// ([`InOrder`]), by whichever thread holds the numbering, while the other computes: numbering
/// after all batches left one thread idle for a twentieth of a two-thread run of a dimpled
/// cube at 0.15 % of the diagonal.
pub(crate) fn assign(
    dnf: &Dnf,
    samples: &mut Samples,
    boxes: &[SampleBox],
    radius: f64,
) -> ClipLists {
    debug_assert!(
        samples
            .iter()
            .all(|s| s.radius <= radius || s.radius.is_nan()),
        "a sample's radius exceeds the run's, which the boxes are tested with"
    );
    // The boxes while they follow one another from the first sample, then boxes of the rest,
    // each within one run of the samples.
    let (mut following, mut boxed) = (0, 0);
    for b in boxes {
        if b.start as usize != boxed || b.end <= b.start || b.end as usize > samples.len() {
            break;
        }
        (following, boxed) = (following + 1, b.end as usize);
    }
    let mut rest = Vec::new();
    for (start, piece) in samples.pieces(boxed..samples.len()) {
        let before = rest.len();
        box_runs(piece, 0, &mut rest);
        for span in &mut rest[before..] {
            *span = span.shifted(start as u32);
        }
    }
    // Batches of whole spans, each within one run of the samples (no span crosses runs), then
    // each with its samples.
    let ends: Vec<usize> = (samples.runs())
        .scan(0, |end, run| {
            *end += run.len();
            Some(*end)
        })
        .collect();
    let mut batches = Vec::new();
    for mut spans in [&boxes[..following], &rest[..]] {
        while let Some(first) = spans.first() {
            let run = ends.partition_point(|&end| end <= first.start as usize);
            let end = ends.get(run).copied().unwrap_or(usize::MAX);
            let (in_run, after) = spans.split_at(spans.partition_point(|s| s.end as usize <= end));
            batches.extend(chunks_of_samples(in_run, CLIP_BATCH));
            spans = after;
        }
    }
    // The batches cover the runs one after the other.
    let mut runs = samples.runs_mut();
    let mut unbatched: &mut [Sample] = &mut [];
    let mut with_samples = Vec::with_capacity(batches.len());
    for spans in batches {
        let (Some(first), Some(last)) = (spans.first(), spans.last()) else {
            continue;
        };
        let (start, end) = (first.start as usize, last.end as usize);
        if unbatched.is_empty() {
            let Some((_, run)) = runs.next() else { break };
            unbatched = run;
        }
        let Some((batch, tail)) = std::mem::take(&mut unbatched).split_at_mut_checked(end - start)
        else {
            break;
        };
        with_samples.push((spans, start, batch));
        unbatched = tail;
    }
    let numbered = InOrder::new(ClipListBuilder::default());
    // Threads take the batches in order, so that the numbering can follow close behind.
    let batches = Mutex::new(with_samples.into_iter().enumerate());
    (0..rayon::current_num_threads())
        .into_par_iter()
        .for_each(|_| {
            loop {
                // The guard goes at the end of this statement, before the batch's work.
                let next = lock(&batches).next();
                let Some((k, (spans, offset, batch))) = next else {
                    break;
                };
                let mut raw = RawClipLists::default();
                raw.push_spans(dnf, (batch, offset), spans, radius);
                numbered.finish(k, (raw, batch), |builder, (raw, batch)| {
                    builder.assign(&raw, batch);
                });
            }
        });
    let (mut builder, waiting) = numbered.into_parts();
    for (raw, batch) in waiting {
        builder.assign(&raw, batch);
    }
    builder.lists
}

/// Assigns every sample its list index, sharing identical lists, in sample order.
struct ClipListBuilder {
    lists: ClipLists,
    known: FxHashMap<Vec<u32>, u32>,
    /// The last list's index: neighbouring samples mostly share their list.
    last: u32,
}

impl Default for ClipListBuilder {
    /// The empty list only, as list 0.
    fn default() -> Self {
        Self {
            lists: ClipLists::default(),
            known: FxHashMap::from_iter([(Vec::new(), 0)]),
            last: 0,
        }
    }
}

impl ClipListBuilder {
    /// Sets `clip_list` of each sample of the raw lists' runs (indices into `samples`).
    fn assign(&mut self, raw: &RawClipLists, samples: &mut [Sample]) {
        let mut start = 0usize;
        let in_runs = raw.runs.iter().flat_map(|run| run.clone());
        for (i, &length) in in_runs.zip(&raw.lengths) {
            let end = start + length as usize;
            let list = &raw.indices[start..end];
            start = end;
            let Some(sample) = samples.get_mut(i) else {
                continue;
            };
            // Element by element: the lists are a few entries long, shorter than a call to
            // memcmp (which slice equality uses) costs.
            if let Some(last) = self.lists.get(self.last)
                && last.len() == list.len()
                && last.iter().zip(list).all(|(a, b)| a == b)
            {
                sample.clip_list = self.last;
                continue;
            }
            let id = match self.known.get(list) {
                Some(&id) => id,
                None => {
                    let lists = &mut self.lists;
                    let id = lists.len() as u32;
                    lists.indices.extend_from_slice(list);
                    lists.offsets.push(lists.indices.len() as u32);
                    self.known.insert(list.to_vec(), id);
                    id
                }
            };
            sample.clip_list = id;
            self.last = id;
        }
    }
}
