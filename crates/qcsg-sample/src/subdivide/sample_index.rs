//! The first pass's samples near the deferred rectangles ([`SampleIndex`]), bucketed by quadric
//! and by cubes of the radius's size, so that the second pass reads only the samples that may
//! cover a rectangle: the cubes wanted are marked first ([`WantedCubes`]), and only samples in
//! them are indexed.

use super::cover::{SurfacePoint, cover_by, inside_term};
use super::emitted::SampleBox;
use crate::sample_point::Sample;
use crate::samples::Samples;
use qcsg_csg::Dnf;
use qcsg_quadric::DVec3;
use rayon::prelude::*;
use rustc_hash::FxHashMap;

/// Most bits of one quadric's map of wanted cubes (256 KiB); past it the cubes grow (by
/// powers of two).
pub(super) const MAX_WANTED_BITS: i128 = 1 << 21;

/// The cubes around one quadric's deferred centres, as a bit map over their box: a cube of
/// `2^shift` fine cubes a side is wanted when a centre lies in it or in a neighbour. Testing a
/// sample costs a shift and a bit, where a hash set cost a hash and a probe for every sample.
pub(super) struct WantedCubes {
    pub(super) shift: u32,
    /// The box's lowest cube, one below the lowest centre's on each axis.
    pub(super) low: [i64; 3],
    pub(super) size: [i64; 3],
    pub(super) bits: Vec<u64>,
}

impl WantedCubes {
    /// An empty map for centres in the fine cubes from `low` to `high`, with cubes just large
    /// enough that the map's box holds at most [`MAX_WANTED_BITS`] of them.
    pub(super) fn new(low: [i64; 3], high: [i64; 3]) -> Self {
        // The index's own cubes where the map holds them: a sample within `r` of a point within
        // `r / 2` of a centre lies in the centre's cube of side `2r` or a neighbour. Cubes of four
        // a side let through more samples to sort, and made runs up to a tenth slower.
        let mut shift = 0;
        let size = loop {
            let size =
                [0, 1, 2].map(|a| i128::from(high[a] >> shift) - i128::from(low[a] >> shift) + 3);
            if size.iter().product::<i128>() <= MAX_WANTED_BITS || shift >= 63 {
                break size.map(|s| s as i64);
            }
            shift += 1;
        };
        let volume = size.iter().map(|&s| s as usize).product::<usize>();
        Self {
            shift,
            low: low.map(|v| (v >> shift) - 1),
            size,
            bits: vec![0; volume.div_ceil(64)],
        }
    }

    /// The bit of a coarse cube, if it lies in the box.
    pub(super) fn bit(&self, cube: [i64; 3]) -> Option<usize> {
        let mut bit = 0usize;
        for axis in (0..3).rev() {
            let offset = cube[axis] - self.low[axis];
            if !(0..self.size[axis]).contains(&offset) {
                return None;
            }
            bit = bit * self.size[axis] as usize + offset as usize;
        }
        Some(bit)
    }

    /// Marks the cube holding fine cube `fine` (a centre's).
    pub(super) fn mark(&mut self, fine: [i64; 3]) {
        self.mark_cube(fine.map(|v| v >> self.shift));
    }

    /// The map with every marked cube's neighbours marked too. Marking cubes, not centres,
    /// first: millions of deferred rectangles (a ball and an ellipsoid `1e-9` apart at a tiny
    /// radius) crowd into far fewer cubes. A centre's cube lies inside the box, one cube in
    /// from its faces, so its neighbours are three consecutive bits in each of nine rows, not
    /// 27 bits found one by one, each with its bounds. With [`Self::coarser_with_neighbours`]
    /// this took [`SampleIndex::new`] from 7.2 % to 6.2 % of the instructions of sampling three
    /// balls at 0.15 % of the diagonal.
    pub(super) fn with_neighbours(&self) -> Self {
        let mut out = Self {
            bits: vec![0; self.bits.len()],
            ..*self
        };
        let [sx, sy, _] = self.size;
        for cube in self.marked() {
            let [x, y, z] = [0, 1, 2].map(|a| cube[a] - self.low[a]);
            let inside = [x, y, z]
                .iter()
                .zip(self.size)
                .all(|(&v, s)| 1 <= v && v < s - 1);
            for (dy, dz) in (-1..=1).flat_map(|dz| (-1..=1).map(move |dy| (dy, dz))) {
                if !inside {
                    for dx in -1..=1 {
                        out.mark_cube([cube[0] + dx, cube[1] + dy, cube[2] + dz]);
                    }
                    continue;
                }
                let first = (((z + dz) * sy + y + dy) * sx + x - 1) as usize;
                for bit in first..first + 3 {
                    out.bits[bit / 64] |= 1 << (bit % 64);
                }
            }
        }
        out
    }

    /// [`Self::with_neighbours`] with cubes `2^by` times as large a side: each marked where
    /// one of this map's marked cubes or a neighbour lies inside it, found from the marked
    /// cubes alone rather than from their neighbours, 27 times as many.
    pub(super) fn coarser_with_neighbours(&self, by: u32) -> Self {
        let low = self.low.map(|v| v >> by);
        let size = [0, 1, 2].map(|a| ((self.low[a] + self.size[a] - 1) >> by) - low[a] + 1);
        let volume = size.iter().map(|&s| s as usize).product::<usize>();
        let mut out = Self {
            shift: self.shift + by,
            low,
            size,
            bits: vec![0; volume.div_ceil(64)],
        };
        for cube in self.marked() {
            let [(x0, x1), (y0, y1), (z0, z1)] = cube.map(|v| ((v - 1) >> by, (v + 1) >> by));
            for z in z0..=z1 {
                for y in y0..=y1 {
                    for x in x0..=x1 {
                        out.mark_cube([x, y, z]);
                    }
                }
            }
        }
        out
    }

    /// The marked cubes.
    pub(super) fn marked(&self) -> impl Iterator<Item = [i64; 3]> + '_ {
        let [sx, sy, _] = self.size;
        self.bits.iter().enumerate().flat_map(move |(word, &bits)| {
            let mut rest = bits;
            std::iter::from_fn(move || {
                if rest == 0 {
                    return None;
                }
                let bit = (word * 64 + rest.trailing_zeros() as usize) as i64;
                rest &= rest - 1;
                Some([
                    self.low[0] + bit % sx,
                    self.low[1] + bit / sx % sy,
                    self.low[2] + bit / (sx * sy),
                ])
            })
        })
    }

    pub(super) fn mark_cube(&mut self, cube: [i64; 3]) {
        if let Some(bit) = self.bit(cube) {
            self.bits[bit / 64] |= 1 << (bit % 64);
        }
    }

    /// Whether the cube holding fine cube `fine` is wanted.
    pub(super) fn contains(&self, fine: [i64; 3]) -> bool {
        self.contains_cube(fine.map(|v| v >> self.shift))
    }

    /// Whether a wanted cube may hold a fine cube from `low` to `high` (also when the box
    /// spans more than [`MAX_BOX_CUBES`] cubes: testing it would cost about what reading its
    /// samples does).
    pub(super) fn meets(&self, low: [i64; 3], high: [i64; 3]) -> bool {
        let mut range = [(0, 0); 3];
        let mut cubes = 1;
        for axis in 0..3 {
            let first = (low[axis] >> self.shift).max(self.low[axis]);
            let last = (high[axis] >> self.shift).min(self.low[axis] + self.size[axis] - 1);
            if first > last {
                return false;
            }
            range[axis] = (first, last);
            cubes *= last - first + 1;
        }
        if cubes > MAX_BOX_CUBES {
            return true;
        }
        let [(x0, x1), (y0, y1), (z0, z1)] = range;
        let [sx, sy, _] = self.size;
        for z in z0..=z1 {
            for y in y0..=y1 {
                // The bits of the row, the range being inside the map's box.
                let row = ((z - self.low[2]) * sy + y - self.low[1]) * sx - self.low[0];
                if ((row + x0) as usize..=(row + x1) as usize).any(|bit| self.is_set(bit)) {
                    return true;
                }
            }
        }
        false
    }

    /// Whether coarse cube `cube` is wanted.
    pub(super) fn contains_cube(&self, cube: [i64; 3]) -> bool {
        self.bit(cube).is_some_and(|bit| self.is_set(bit))
    }

    /// Whether bit `bit` of the map is set.
    pub(super) fn is_set(&self, bit: usize) -> bool {
        self.bits[bit / 64] & (1 << (bit % 64)) != 0
    }
}

/// Most cubes [`WantedCubes::meets`] tests one by one.
pub(super) const MAX_BOX_CUBES: i64 = 4096;

/// A box is first tested on a map of cubes `2^COARSER_BY` times as large a side
/// ([`WantedCubes::coarser_with_neighbours`]), where the boxes far from every deferred
/// rectangle (most of them) take a test or two.
pub(super) const COARSER_BY: u32 = 3;

/// A fine cube of one quadric as one hashable number. Coordinates wrap at 2³²: cubes that far
/// apart share a bucket, which only adds candidates that [`cover_by`] then rejects by distance.
pub(super) fn bucket_key([x, y, z]: [i64; 3], quadric: u32) -> u128 {
    (u128::from(x as u32) << 96)
        | (u128::from(y as u32) << 64)
        | (u128::from(z as u32) << 32)
        | u128::from(quadric)
}

/// The first pass's samples near deferred rectangles, bucketed by quadric and by cubes of side
/// `2r`: every sample within `r` of a point within `r / 2` of a deferred centre is found (it
/// lies in one of the fine cubes that the ball of radius `r` around the point touches, inside a
/// wanted cube next to the centre's). Only the boxes of samples ([`Emitted`](crate::subdivide::Emitted)) that meet a
/// wanted cube are read: at 0.15 % of the diagonal, 7 % of the samples of three balls and 4 %
/// of those of a cube dimpled by 18 balls. With its grouping by counting instead of sorting,
/// this took the index from 11 % to 6 % of the instructions of sampling three balls there.
pub struct SampleIndex<'a> {
    pub(super) dnf: &'a Dnf,
    pub(super) radius: f64,
    pub(super) anchor: DVec3,
    /// Fine cubes per unit length, `1 / 2r`.
    pub(super) per_length: f64,
    /// The fine cubes' samples in shards ([`shard`]), one per thread, each grouped on a thread
    /// of its own.
    pub(super) shards: Vec<IndexShard<'a>>,
}

/// A sample of a [`SampleIndex`]: its index among all samples, and the sample.
pub type Member<'a> = (u32, &'a Sample);

/// The fine cubes of one shard of a [`SampleIndex`] with their samples.
pub(super) struct IndexShard<'a> {
    /// Each fine cube's samples ([`bucket_key`]): a range of `members`.
    pub(super) buckets: FxHashMap<u128, (u32, u32)>,
    /// The samples, grouped by fine cube, ascending within each.
    pub(super) members: Vec<Member<'a>>,
}

impl<'a> IndexShard<'a> {
    /// The samples of the cubes among `hits` (pieces of the hits of this shard, each in
    /// ascending sample order, the pieces in order), in two passes (count, then place), each
    /// cube's samples in the order of the hits: sorting the hits by cube and index took
    /// longer, and a vector per cube costs an allocation each.
    pub(super) fn new<'h>(hits: impl Iterator<Item = &'h [(u128, Member<'a>)]> + Clone) -> Self
    where
        'a: 'h,
    {
        // Consecutive hits mostly share their cube (a box's samples lie close together): one
        // look-up per run of them.
        let runs = || {
            hits.clone()
                .flat_map(|piece| piece.chunk_by(|a, b| a.0 == b.0))
        };
        let mut buckets = FxHashMap::default();
        buckets.reserve(hits.clone().map(<[_]>::len).sum::<usize>() / 2);
        let mut total = 0;
        for run in runs() {
            buckets.entry(run[0].0).or_insert((0, 0)).1 += run.len() as u32;
            total += run.len();
        }
        let mut start = 0;
        for range in buckets.values_mut() {
            let in_cube = range.1;
            *range = (start, start);
            start += in_cube;
        }
        // Every slot is written below; the first hit fills them until then.
        let mut members = match runs().next() {
            Some(run) => vec![run[0].1; total],
            None => Vec::new(),
        };
        for run in runs() {
            if let Some(range) = buckets.get_mut(&run[0].0) {
                let end = range.1 as usize + run.len();
                let slots = &mut members[range.1 as usize..end];
                for (slot, &(_, member)) in slots.iter_mut().zip(run) {
                    *slot = member;
                }
                range.1 = end as u32;
            }
        }
        Self { buckets, members }
    }

    /// The samples of cube `key`, if it has any.
    pub(super) fn get(&self, key: u128) -> Option<&[Member<'a>]> {
        let &(start, end) = self.buckets.get(&key)?;
        self.members.get(start as usize..end as usize)
    }
}

/// The shard of `count` (a power of two) that holds cube `key` ([`bucket_key`]): by the sum
/// of its coordinates, so that neighbouring cubes alternate between shards. A mask, not a
/// remainder: with a division for each cube a look-up tries (up to eight),
/// [`SampleIndex::cover`] took 7.6 % of sampling three balls at 0.15 % of the diagonal
/// instead of 7.0 %.
pub(super) fn shard(key: u128, count: usize) -> usize {
    let [x, y, z] = [96, 64, 32].map(|bits| (key >> bits) as u32);
    x.wrapping_add(y).wrapping_add(z) as usize & (count - 1)
}

impl<'a> SampleIndex<'a> {
    /// Indexes the samples of `samples` that may cover a point near one of `centres` (surface
    /// points with their quadric). Of the samples in `sample_boxes` ([`Emitted`](crate::subdivide::Emitted)), only those
    /// of the boxes that meet a cube near a centre are read.
    pub fn new(
        dnf: &'a Dnf,
        (samples, sample_boxes): (&'a Samples, &[SampleBox]),
        centres: &[(u32, DVec3)],
        radius: f64,
    ) -> Self {
        let mut index = Self {
            dnf,
            radius,
            anchor: centres.first().map_or(DVec3::ZERO, |c| c.1),
            per_length: 0.5 / radius,
            shards: Vec::new(),
        };
        if centres.is_empty() {
            return index;
        }
        // Per quadric: the box of its centres' cubes, then a map over it.
        let mut boxes = vec![None::<([i64; 3], [i64; 3])>; dnf.quadrics.len()];
        for &(quadric, point) in centres {
            if let Some(entry) = boxes.get_mut(quadric as usize) {
                let cube = index.key(point);
                let (low, high) = entry.get_or_insert((cube, cube));
                *low = [0, 1, 2].map(|a| low[a].min(cube[a]));
                *high = [0, 1, 2].map(|a| high[a].max(cube[a]));
            }
        }
        let mut marked: Vec<Option<WantedCubes>> = boxes
            .into_iter()
            .map(|entry| entry.map(|(low, high)| WantedCubes::new(low, high)))
            .collect();
        for &(quadric, point) in centres {
            if let Some(Some(map)) = marked.get_mut(quadric as usize) {
                map.mark(index.key(point));
            }
        }
        let wanted: Vec<Option<(WantedCubes, WantedCubes)>> = marked
            .par_iter()
            .map(|map| {
                let map = map.as_ref()?;
                Some((
                    map.with_neighbours(),
                    map.coarser_with_neighbours(COARSER_BY),
                ))
            })
            .collect();
        drop(marked);
        // The samples to read: those of the boxes that meet a wanted cube, and those after the
        // boxes (the boxes hold `samples[..boxed]`, one after the other).
        let boxed = sample_boxes.last().map_or(0, |b| b.end as usize);
        let near = |b: &&SampleBox| {
            let wanted = wanted.get(b.quadric as usize).and_then(Option::as_ref);
            let (low, high) = (index.key(b.low), index.key(b.high));
            wanted.is_some_and(|(fine, coarse)| coarse.meets(low, high) && fine.meets(low, high))
        };
        // Each piece of the hits comes split by shard ([`shard`], one per thread, or a few
        // more: a power of two): each shard then groups its own hits, on a thread of its own.
        // A piece folds a stretch of consecutive samples, and `collect` keeps the stretches in
        // order, so each shard's hits stay in ascending sample order.
        let count = rayon::current_num_threads().max(1).next_power_of_two();
        let pieces: Vec<Vec<Vec<(u128, Member<'a>)>>> = (sample_boxes.par_iter())
            .filter(near)
            .map(|b| b.start as usize..b.end as usize)
            .chain(rayon::iter::once(boxed..samples.len()))
            .flat_map_iter(|range| samples.pieces(range))
            .fold(
                || vec![Vec::new(); count],
                |mut by_shard, (start, piece)| {
                    for (i, sample) in (start..).zip(piece) {
                        let Some(Some((wanted, _))) = wanted.get(sample.quadric as usize) else {
                            continue;
                        };
                        let cube = index.key(sample.position);
                        if wanted.contains(cube) {
                            let key = bucket_key(cube, sample.quadric);
                            by_shard[shard(key, count)].push((key, (i as u32, sample)));
                        }
                    }
                    by_shard
                },
            )
            .collect();
        index.shards = (0..count)
            .into_par_iter()
            .map(|k| IndexShard::new(pieces.iter().map(|by_shard| by_shard[k].as_slice())))
            .collect();
        index
    }

    pub(super) fn key(&self, p: DVec3) -> [i64; 3] {
        let c = (p - self.anchor) * self.per_length;
        [floor(c.x), floor(c.y), floor(c.z)]
    }

    /// A sample of `quadric` that covers the ball of radius `extent` around `point`, with the
    /// radius it needs for that ([`cover_by`]).
    ///
    /// A sample of another term than `term` counts only if the ball lies inside its term:
    /// a splat is clipped to its term, so it draws nothing outside it.
    pub fn cover(
        &self,
        (quadric, term): (u32, u32),
        point: SurfacePoint,
        extent: f64,
    ) -> Option<(u32, f64)> {
        // Only a sample within `r − extent` of the point can cover the ball (no radius exceeds
        // `r`): at most eight cubes, but for rounding at their faces.
        let mut cubes: [&[Member<'a>]; 27] = [&[]; 27];
        let mut found = 0;
        self.cubes_near(quadric, point.position, self.radius - extent, |members| {
            if let Some(slot) = cubes.get_mut(found) {
                *slot = members;
                found += 1;
            }
        });
        let candidates = cubes[..found].iter().flat_map(|members| members.iter());
        self.cover_among(candidates.copied(), term, point, extent)
    }

    /// The samples of `quadric` (of any term) within `r` of `position`, into `out`, in a fixed
    /// order. A sample that covers the ball of radius `e` around a point within `e` of
    /// `position` is among them: a refinement gathers them once around the centre of its
    /// deferred rectangle, and its parts whose centres lie that near scan this short list
    /// instead of the index's cubes ([`Self::cover_among`]).
    pub fn near(&self, quadric: u32, position: DVec3, out: &mut Vec<Member<'a>>) {
        out.clear();
        let limit = self.radius * self.radius * (1.0 + 1e-9);
        self.cubes_near(quadric, position, self.radius, |members| {
            let near = |(_, s): &&Member<'_>| (s.position - position).length_squared() <= limit;
            out.extend(members.iter().filter(near));
        });
    }

    /// The samples of the cubes that the ball of radius `reach ≤ r` around `position` touches,
    /// cube by cube: with cubes of side `2r`, at most two along each axis, and one more often
    /// the smaller `reach` is.
    pub(super) fn cubes_near<'s>(
        &'s self,
        quadric: u32,
        position: DVec3,
        reach: f64,
        mut each: impl FnMut(&'s [Member<'a>]),
    ) {
        if reach.is_nan() || reach < 0.0 || self.shards.is_empty() {
            return;
        }
        let reach = DVec3::splat(reach);
        let (low, high) = (self.key(position - reach), self.key(position + reach));
        let count = self.shards.len();
        for z in low[2]..=high[2] {
            for y in low[1]..=high[1] {
                for x in low[0]..=high[0] {
                    let key = bucket_key([x, y, z], quadric);
                    if let Some(members) =
                        self.shards.get(shard(key, count)).and_then(|s| s.get(key))
                    {
                        each(members);
                    }
                }
            }
        }
    }

    /// [`Self::cover`] over the samples `candidates` (of the quadric), in their order.
    pub fn cover_among(
        &self,
        candidates: impl Iterator<Item = Member<'a>>,
        term: u32,
        point: SurfacePoint,
        extent: f64,
    ) -> Option<(u32, f64)> {
        cover_by(candidates, point, extent, self.radius, |s| {
            s.term == term || inside_term(self.dnf, s, term, point.position, extent)
        })
    }
}

/// `⌊v⌋` as an integer (saturating), without a call into libm.
pub(super) fn floor(v: f64) -> i64 {
    let t = v as i64;
    if (t as f64) > v { t - 1 } else { t }
}
