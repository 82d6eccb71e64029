//! Clip lists (paper §6): for every sample, the other quadrics of its term whose surface comes
//! within the sample's radius, so that a renderer can clip the sample's splat locally.
//!
//! A literal `j` of the sample's term enters the list unless its conservative distance (eqs.
//! 10-12, a lower bound of the true distance) exceeds the radius at the sample: then no point of
//! `Q_j` lies within the radius, and nothing inside the splat can be cut by it. The test is
//! conservative: a quadric whose surface does reach into the splat is never left out. A term of
//! many literals (a plate drilled with many holes) first leaves out those whose surface provably
//! misses a box around a run of its samples grown by their radii, so each sample tests only the
//! literals near it.
//!
//! Identical lists are stored once: [`ClipLists`] is one indirection buffer, and each sample
//! holds the index of its list. Lists are numbered in order of first use in the (deterministic)
//! sample order, so the buffer is the same for any thread count.

use qcsg_csg::quadric_box::{self, BoxClass};
use qcsg_csg::{Aabb, Dnf};
use qcsg_quadric::DVec3;
use rayon::prelude::*;
use rustc_hash::FxHashMap;
use std::sync::Mutex;

use crate::Sample;
use crate::in_order::{InOrder, lock};

/// Deduplicated clip lists: list `k` is `indices[offsets[k]..offsets[k + 1]]`, indices into
/// [`Dnf::quadrics`], ascending.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ClipLists {
    /// Start of each list in `indices`, plus one final entry: `offsets.len()` is the number of
    /// lists plus one.
    pub offsets: Vec<u32>,
    /// The lists' quadric indices, concatenated.
    pub indices: Vec<u32>,
}

impl Default for ClipLists {
    fn default() -> Self {
        Self {
            offsets: vec![0],
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

/// Clip lists of one region's samples before deduplication: `lengths[i]` indices of sample `i`,
/// concatenated in `indices`.
#[derive(Clone, Debug, Default)]
struct RawClipLists {
    lengths: Vec<u32>,
    indices: Vec<u32>,
}

impl RawClipLists {
    /// Appends the clip list of each sample (the other literals of its term within its radius).
    ///
    /// Neighbouring samples mostly lie far from the same literals, so each literal keeps the
    /// last point where its conservative distance `L` was evaluated: the true distance is
    /// 1-Lipschitz, so at a sample `Δ` away it is at least `L − Δ`, and the literal is left out
    /// without evaluating it again when that exceeds the radius.
    fn push_samples(&mut self, dnf: &Dnf, samples: &[Sample]) {
        let mut anchors: Vec<Option<(DVec3, f64)>> = vec![None; dnf.quadrics.len()];
        let (mut near, mut nearer) = (Vec::new(), Vec::new());
        for run in samples.chunk_by(|a, b| a.term == b.term) {
            let Some(term) = dnf.terms.get(run[0].term as usize) else {
                self.lengths.extend(run.iter().map(|_| 0));
                continue;
            };
            for chunk in run.chunks(CLIP_CHUNK) {
                literals_near(dnf, chunk, &term.literals, &mut near);
                for samples in chunk.chunks(CLIP_CHUNK / 16) {
                    literals_near(dnf, samples, &near, &mut nearer);
                    self.push_run(dnf, samples, &nearer, &mut anchors);
                }
            }
        }
    }

    /// [`Self::push_samples`] for samples of one term, with the literals among `literals` that
    /// may come within their radii.
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
                if literal == sample.quadric {
                    continue;
                }
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

/// Samples per parallel batch when clip lists are computed.
const CLIP_BATCH: usize = 4096;

/// Consecutive samples of one term whose literals are first sorted out together, on a box
/// around them all ([`literals_near`]), then again in runs of a sixteenth of this.
const CLIP_CHUNK: usize = 1024;

/// Terms with more literals than this sort them out by box before testing each sample.
const FEW_LITERALS: usize = 16;

/// Into `out`, the literals of `literals` whose surface may come within its radius of one of
/// `samples`: all of them for a term of few, else those whose surface may cross a box around
/// the samples grown by their largest radius (`quadric_box::classify`). A literal left out has
/// no surface point in the box, so none within any sample's radius.
fn literals_near(dnf: &Dnf, samples: &[Sample], literals: &[u32], out: &mut Vec<u32>) {
    out.clear();
    if literals.len() <= FEW_LITERALS {
        out.extend_from_slice(literals);
        return;
    }
    let (mut min, mut max, mut radius) = (DVec3::INFINITY, DVec3::NEG_INFINITY, 0.0f64);
    for sample in samples {
        min = min.min(sample.position);
        max = max.max(sample.position);
        radius = radius.max(sample.radius);
    }
    let grown = Aabb::new(min, max).expanded(radius);
    out.extend(literals.iter().copied().filter(|&literal| {
        dnf.quadrics
            .get(literal as usize)
            .is_none_or(|entry| quadric_box::classify(&entry.quadric, &grown) == BoxClass::Cuts)
    }));
}

/// Computes every sample's clip list (in parallel batches), stores each distinct list once and
/// sets `clip_list` of each sample; lists are numbered in sample order. Each batch is numbered
/// as soon as the batches before it are ([`InOrder`]), by whichever thread holds the numbering,
/// while the other computes: numbering after all batches left one thread idle for a twentieth
/// of a two-thread run of a dimpled cube at 0.15 % of the diagonal.
pub(crate) fn assign(dnf: &Dnf, samples: &mut [Sample]) -> ClipLists {
    let numbered = InOrder::new(ClipListBuilder::default());
    // Threads take the batches in order, so that the numbering can follow close behind.
    let batches = Mutex::new(samples.chunks_mut(CLIP_BATCH).enumerate());
    (0..rayon::current_num_threads())
        .into_par_iter()
        .for_each(|_| {
            loop {
                // The guard goes at the end of this statement, before the batch's work.
                let next = lock(&batches).next();
                let Some((k, batch)) = next else {
                    break;
                };
                let mut raw = RawClipLists::default();
                raw.push_samples(dnf, batch);
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
#[derive(Default)]
struct ClipListBuilder {
    lists: ClipLists,
    known: FxHashMap<Vec<u32>, u32>,
    /// The last list's index: neighbouring samples mostly share their list.
    last: Option<u32>,
}

impl ClipListBuilder {
    /// Sets `clip_list` of each sample from its raw list (same order as `samples`).
    fn assign(&mut self, raw: &RawClipLists, samples: &mut [Sample]) {
        let mut start = 0usize;
        for (sample, &length) in samples.iter_mut().zip(&raw.lengths) {
            let end = start + length as usize;
            let list = &raw.indices[start..end];
            start = end;
            // Element by element: the lists are a few entries long, shorter than a call to
            // memcmp (which slice equality uses) costs.
            if let Some(id) = self.last
                && let Some(last) = self.lists.get(id)
                && last.len() == list.len()
                && last.iter().zip(list).all(|(a, b)| a == b)
            {
                sample.clip_list = id;
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
            self.last = Some(id);
        }
    }
}
