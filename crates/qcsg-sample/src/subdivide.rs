//! Adaptive longest-edge subdivision of one basic region (paper §4.2).
//!
//! At the corners of a rectangle the CSG distance `d` of eq. 22 is evaluated. A world radius `|d|`
//! becomes the 2-D radius `|d| / δ_max`, `δ_max` being the rectangle's maximum distortion (§3.4
//! corner bound): the heightfield map is `δ_max`-Lipschitz on the convex rectangle, so 2-D points
//! within `|d| / δ_max` of a corner map to surface points within `|d|` of it in space. The corner
//! discs cover the rectangle when each of its quarters lies in one of them (`discs_cover`: one
//! reaching the opposite corner, or each reaching the centre, are the simplest cases); then the
//! rectangle is wholly on the CSG surface (all `d < 0`: filled with a grid of samples) or wholly
//! off it (all `d > 0`: dropped). Otherwise it is split at its longer edge. An edge's midpoint is
//! a corner of the cells on both sides of it: eq. 22 at a point a walk of the subdivision met
//! lately comes from a small memo (`QueryMemo`), which took 15 % to 22 % of the queries off the
//! benchmark scenes at 0.15 % of the diagonal.
//!
//! **Border regions.** A basic region across the border between two sampling planes' regions
//! is only the part of its rectangle where its plane is the best: sub-rectangles and fill cells
//! where another plane is the best throughout are dropped before anything else
//! ([`BasicRegion::owns_none_of`]), since that plane's regions hold those surface points.
//!
//! **Small regions.** A rectangle whose world footprint `δ_max · diagonal` is at most `r` needs
//! only one sample on the CSG surface anywhere inside it: the first corner with `d < 0` gets it
//! (the paper's special case), else the centre if `d(centre) < 0`; where `d(centre) > 0`, its disc
//! alone proves the rectangle off the surface once it reaches the corners (every point lies
//! within half the diagonal of the centre): beside a feature curve the corners are near the
//! curve and their discs small, and this takes 9 % of the queries off three balls at 1 % of
//! the diagonal, without a sample more or less. The sample's radius is reduced
//! to the footprint (§6.1: less overdraw, same guarantee). Every point of a rectangle lies within
//! half its footprint of its centre, so one of footprint up to `2r` that the corner discs do not
//! classify is covered by a sample at its centre when `d(centre) < 0`, and split otherwise (unless
//! the centre's disc reaches the corners). Most
//! such rectangles lie along feature curves; the examples at 1 % of the diagonal take 8 % to 73 %
//! fewer samples in all than when they were split (a quarter to a third on most). If one of the
//! last samples of the same quadric and term is near enough to cover a small rectangle with a
//! radius of at most `r`, no new sample is made and that sample's radius grows to reach it: along
//! a feature curve one sample often covers several small rectangles. The look-back reaches into
//! the earlier regions of the region's block (consecutive regions, [`crate::blocks`]): around a
//! cone's apex the region decomposition leaves thousands of tiny regions, one ring per level of
//! refinement, and each had taken a sample of its own (`raw_quadrics` at 1 % took 16,308 samples,
//! 5,322 with the look-back).
//!
//! **Coverage is by what a sample's splat draws.** Wherever a rectangle counts as covered by an
//! existing sample, that sample's disc must reach all of it: its radius is at most `r` and is the
//! radius a renderer draws it with, so a sample within `r` whose reduced radius falls short has its
//! radius grown (never beyond `r`). Its normal must be less than 90° from the quadric's at every
//! point of the rectangle (a splat draws only its own side: a sample on one face of a thin slab,
//! the same quadric, draws nothing on the other): the normal turns by at most `asin(bend · L)`
//! within `L` of the rectangle's centre ([`SurfacePoint::faces`]), which the sample's normal must
//! leave room for. Testing the centre's normal alone let a sample on a small ball's far sheet cover
//! a rectangle as large as the ball at a radius near its size. A sample of another term counts
//! only if the rectangle's part in its own term lies inside that term (a splat is clipped to its
//! term; literals both terms hold are skipped). Without the last two rules `customizer_box` showed
//! gaps along its walls' rims at 1920×1080 (99.6 % of pixels agreeing with the ray tracer instead
//! of 99.997 %).
//!
//! **Two passes.** A small rectangle with neither corner nor centre on the surface is not split
//! further at once: the first pass ([`sample_region`]) sets it aside ([`Deferred`]), and the second
//! ([`refine_deferred`]) takes it up once every region has its samples. There it is covered as soon
//! as a sample of the same quadric lies within `r − footprint / 2` of the surface point over its
//! centre (every point of the rectangle is within `footprint / 2` of that point), its radius grown
//! to reach the rectangle; otherwise it is split and classified again, down to
//! [`SMALL_REGION_FRACTION`] of the footprint. Such rectangles sit beside feature curves, and the
//! samples on the other side of the curve, often in a neighbouring region, usually cover them at
//! once: where a curve runs along a region border (the lens edge of `examples/three_spheres.qcsg`),
//! splitting them down to the cutoff had cost 17× the queries. Where surfaces nearly coincide over
//! an area, no rectangle is ever proven, and the refinement of one deferred rectangle stops after
//! 512 unproven rectangles (`MAX_UNPROVEN_PER_DEFERRED`); the given-up rectangles kept for the
//! final settling are bounded in all (`given_up_share`). Second-pass samples are appended after the
//! first pass's, in the order of the deferred rectangles, so the output does not depend on the
//! thread count.
//!
//! **Threads.** Basic regions are shared out in runs ([`crate::sample`]), but one region can
//! hold much of the work (a face of a dimpled cube: a quarter of all samples). A rectangle whose
//! footprint is at least [`TASK_FOOTPRINT`] radii is split into halves of which the second may
//! be taken by an idle thread (rayon's work stealing over the subdivision tree, as paper 000
//! §7 suggests). The second half's small rectangles then look back only at its own samples,
//! on one thread as on many, so the output stays the same for any thread count; on one thread
//! it costs a join per large rectangle and nothing is copied.
//!
//! **The cutoff.** Only a proof keeps the guarantee: the paper's cut-off at a tenth of the splat
//! "can theoretically result in small holes", and a cutoff of `r / 16` here missed a sliver of
//! `examples/precision_part.qcsg` that the reference points found. A surface sliver that avoids
//! every corner and centre down to `r / 64` could still be missed; rectangles given up there are
//! settled against every sample at the end ([`settle_given_up`]); those with no sample of their
//! quadric within `r − footprint / 2` are probed a few levels further down, within a budget of
//! distance queries ([`probe_given_up`]), and those still unsettled are counted in
//! [`SubdivisionStats::unresolved`], so the count says whether a hole was possible at all.

use std::ops::Range;
use std::sync::{Mutex, PoisonError};

use rayon::prelude::*;
use rustc_hash::FxHashMap;

use qcsg_csg::Dnf;
use qcsg_quadric::{DVec3, PrincipalFrame, Quadric, QuadricKind};

use crate::budget::{Budget, CHARGE_EVERY, Meter};
use crate::csg_distance::NearDistance;
use crate::fill_grid::{FillGrid, FillRow};
use crate::in_order::lock;
use crate::lanes::{HeightfieldLine, SurfaceTest};
use crate::memo::QueryMemo;
use crate::regions::{
    BasicRegion, Owned, Rect, corner_bounds, region_point, split_for_distortion,
    split_for_distortion_at_corners,
};
use crate::{Sample, Samples};

/// Rectangles smaller than this fraction of the sample footprint are given up when unclassified.
pub const SMALL_REGION_FRACTION: f64 = 1.0 / 64.0;

/// Unproven rectangles one deferred rectangle may split into before the rest is given up. A
/// sliver along a curve leaves about 2·2ᵏ unproven rectangles at `k` halvings, so this reaches
/// the cutoff (`k = 6`) there; where surfaces nearly coincide over an area (two ellipsoids
/// `1e-9` apart, turned differently) every rectangle stays unproven, `4ᵏ` of them, and the
/// budget stops the refinement near `r / 20` instead of costing 4,096 leaves per rectangle.
const MAX_UNPROVEN_PER_DEFERRED: usize = 512;

/// Given-up rectangles kept one by one for [`settle_given_up`] over all deferred rectangles
/// (about 200 MB); each deferred rectangle may keep its share of them (at most
/// [`MAX_UNPROVEN_PER_DEFERRED`]) and settles the rest together, as the whole deferred
/// rectangle. Nested balls `1e-9` apart at 1 % had given up 13 M rectangles. The share depends
/// only on the number of deferred rectangles, so the output does not depend on the thread count.
const MAX_GIVEN_UP_TOTAL: usize = 1 << 22;

/// How many given-up rectangles each of `deferred` deferred rectangles keeps one by one.
pub fn given_up_share(deferred: usize) -> usize {
    (MAX_GIVEN_UP_TOTAL / deferred.max(1)).min(MAX_UNPROVEN_PER_DEFERRED)
}

/// Ratio of largest to smallest distortion above which [`fill`] fills the halves separately.
const FILL_SPREAD: f64 = 1.1;

/// Cells a rectangle must span across its split for [`fill`] to split it.
const FILL_SPLIT_CELLS: f64 = 4.0;

/// Counters of the subdivision.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SubdivisionStats {
    /// Evaluations of eq. 22.
    pub distance_queries: u64,
    /// Rectangles visited.
    pub rectangles: u64,
    /// Rectangles proven on the surface and filled.
    pub filled: u64,
    /// Rectangles proven off the surface.
    pub discarded: u64,
    /// Rectangles of border regions left to another sampling plane, and fill cells skipped
    /// for the same reason ([`BasicRegion::owns_none_of`]).
    pub other_plane: u64,
    /// Small rectangles settled by a single sample: their own, or a recent one that covers them.
    pub small: u64,
    /// Rectangles given up unclassified and not covered by any sample of their quadric (see
    /// the module doc): the only places where the guarantee is not proven.
    pub unresolved: u64,
    /// Rectangles left unclassified but covered by a sample of their quadric (second pass and
    /// final settling).
    pub unresolved_covered: u64,
}

impl SubdivisionStats {
    /// Adds another set of counters.
    pub fn add(&mut self, other: &Self) {
        self.distance_queries += other.distance_queries;
        self.rectangles += other.rectangles;
        self.filled += other.filled;
        self.discarded += other.discarded;
        self.other_plane += other.other_plane;
        self.small += other.small;
        self.unresolved += other.unresolved;
        self.unresolved_covered += other.unresolved_covered;
    }
}

/// What one basic region needs to be sampled.
pub struct RegionContext<'a> {
    /// The quadric's principal frame.
    pub frame: &'a PrincipalFrame,
    /// The quadric itself (normals, snapping to the surface).
    pub quadric: &'a Quadric,
    /// Eq. 22 for this quadric and term, near the region.
    pub distance: &'a NearDistance<'a>,
    /// Every point of the region's patch is on the surface
    /// ([`NearDistance::everywhere_on_surface`]): eq. 22 is taken as `−∞` wherever the
    /// heightfield is defined, without a query, and the region is filled as its distortion
    /// allows.
    pub on_surface: bool,
    /// The world-space sample radius `r`.
    pub radius: f64,
    /// The run's limits, charged as the work goes.
    pub budget: &'a Budget,
    /// Samples farther than this from the quadric (`|Q| / ‖∇Q‖`) are moved onto it by Newton
    /// steps (`snap_to_surface`); `None` for cones, which are left alone.
    pub snap: Option<f64>,
    /// Parts of a rectangle no larger than this on the surface are specks, below the length
    /// tolerance of the scene ([`probe_given_up`]).
    pub speck: f64,
    /// Buffers for the halves other threads take (`split_in_parallel`), emptied and handed
    /// back once their contents are appended.
    pub spare_halves: &'a Mutex<Vec<HalfBuffers>>,
}

/// What the half of a large cell that another thread took writes to: its samples, its deferred
/// rectangles and its memo. Kept from half to half and from run to run ([`crate::resample`]),
/// as the runs' buffers are, so that a half writes to memory that is mapped already instead of
/// growing new buffers page by page.
pub type HalfBuffers = (Emitted, Vec<Deferred>, QueryMemo);

/// A rectangle with its corner distances `[x0y0, x1y0, x0y1, x1y1]` and the heightfield's
/// squared slopes there ([`qcsg_quadric::Heightfield::slope_squared`], NaN where it has none),
/// from which its distortion bound follows ([`cell_distortion`]). Cells are copied at every
/// split and push: NaN instead of `Option` keeps them a third smaller.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Cell {
    rect: Rect,
    d: [f64; 4],
    slope: [f64; 4],
    /// Whether all of it is known to belong to the region ([`BasicRegion::owns`]); its parts
    /// are then too, and no more border tests are needed below it.
    owned: bool,
}

impl Cell {
    /// The cell over `rect`, its corners evaluated.
    fn new(
        ctx: &RegionContext<'_>,
        region: &BasicRegion,
        rect: Rect,
        (memo, stats): Walk<'_>,
    ) -> Self {
        let mut cell = Self {
            rect,
            d: [0.0; 4],
            slope: [f64::NAN; 4],
            owned: false,
        };
        for k in 0..4 {
            let (x, y) = corner(&rect, k);
            (cell.d[k], cell.slope[k]) = plane_values(ctx, region, x, y, (memo, stats));
        }
        cell
    }

    /// Whether none of the cell belongs to the region; otherwise `owned` records whether it all
    /// does.
    fn owned_by_none(&mut self, region: &BasicRegion) -> bool {
        if !self.owned {
            match region.owns(&self.rect) {
                Owned::None => return true,
                Owned::All => self.owned = true,
                Owned::Part => {}
            }
        }
        false
    }
}

/// What a walk of the subdivision writes to as it queries: the memo of its queries and the
/// counters.
type Walk<'a> = (&'a mut QueryMemo, &'a mut SubdivisionStats);

/// Eq. 22 ([`query`]) and the squared slope at a corner or centre (NaN where there is none),
/// from the walk's memo where it has them; eq. 22 is `−∞` without a query in a region all on
/// the surface ([`RegionContext::on_surface`]).
fn plane_values(
    ctx: &RegionContext<'_>,
    region: &BasicRegion,
    x: f64,
    y: f64,
    (memo, stats): Walk<'_>,
) -> (f64, f64) {
    if ctx.on_surface {
        let slope = region.heightfield.slope_squared(x, y);
        return slope.map_or((f64::NAN, f64::NAN), |slope| (f64::NEG_INFINITY, slope));
    }
    memo.get_or(x, y, || {
        let slope = region.heightfield.slope_squared(x, y).unwrap_or(f64::NAN);
        (query(ctx, region, x, y, stats), slope)
    })
}

/// A rectangle of footprint at most `r` that the first pass left unproven (no corner and not
/// its centre on the surface): [`refine_deferred`] settles it once every region has its samples.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Deferred {
    /// Index of the basic region it belongs to.
    pub region: usize,
    cell: Cell,
}

impl Deferred {
    /// The surface point over the rectangle's centre.
    pub fn centre_point(&self, ctx: &RegionContext<'_>, region: &BasicRegion) -> Option<DVec3> {
        let (x, y) = self.cell.rect.centre();
        region_point(ctx.frame, &region.heightfield, region.sheet, x, y)
    }
}

/// Samples as a subdivision emits them, with boxes around runs of consecutive samples
/// ([`SampleBox`]): the second pass's index reads only the runs whose box comes near a
/// deferred rectangle ([`SampleIndex::new`]), a few percent of the samples at small radii. The
/// subdivision goes depth first and fills row by row, so consecutive samples lie close
/// together. It dereferences to the samples.
#[derive(Clone, Debug, Default)]
pub struct Emitted {
    /// The samples, in order.
    pub samples: Vec<Sample>,
    /// Boxes around `samples[..boxed]`, in order, one after the other.
    pub boxes: Vec<SampleBox>,
    boxed: usize,
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
    fn box_fill(&mut self) {
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

/// What a cell is after its corner distances are looked at.
enum Verdict {
    /// Proven off the surface.
    Discarded,
    /// Proven on the surface and filled with samples.
    Filled,
    /// Small, with one sample on the surface.
    Small,
    /// Small, and its corners settle nothing: [`at_centre`] may still.
    Unproven { footprint: f64, distortion: f64 },
    /// To be split; its footprint is larger than `r`.
    Split { footprint: f64 },
}

/// Classifies one cell, emitting its samples when it is on the surface; `out[first..]` are the
/// samples that may cover its small rectangles (of the region's block, or of the refinement,
/// so far).
fn classify(
    ctx: &RegionContext<'_>,
    region: &BasicRegion,
    cell: &Cell,
    (out, first): (&mut Emitted, usize),
    (memo, stats): Walk<'_>,
) -> Verdict {
    stats.rectangles += 1;
    let rect = cell.rect;
    let distortion = cell_distortion(region, cell);
    let diagonal = rect.diagonal();
    // The discs of radius `|d| / δ` over the rectangle, as discs of radius `|d|` over it
    // stretched by `δ`: two products instead of four divisions.
    let stretched = (distortion * rect.width(), distortion * rect.height());
    let covered = discs_cover(stretched, cell.d.map(f64::abs));
    if covered && cell.d.iter().all(|&d| d > 0.0) {
        stats.discarded += 1;
        return Verdict::Discarded;
    }
    let footprint = distortion * diagonal;
    if footprint > ctx.radius {
        let on = covered && cell.d.iter().all(|&d| d < 0.0);
        let slopes = in_one_quadrant(&rect).then_some(cell.slope);
        if on && fill(ctx, region, (&rect, cell.owned), (distortion, slopes), out) {
            stats.filled += 1;
            return Verdict::Filled;
        }
        // Every point of the rectangle is within half its footprint of its centre, so up to
        // `2r` one sample at the centre covers it: along a feature curve that halves the
        // samples the rectangles beside it take.
        if footprint <= 2.0 * ctx.radius {
            if covered_by_recent(ctx, region, &rect, footprint, &mut out[first..]) {
                stats.small += 1;
                return Verdict::Small;
            }
            if let Some(verdict) = at_centre(ctx, region, (&rect, distortion), out, (memo, stats)) {
                return verdict;
            }
        }
        return Verdict::Split { footprint };
    }
    if let Some(k) = cell.d.iter().position(|&d| d < 0.0) {
        if covered_by_recent(ctx, region, &rect, footprint, &mut out[first..]) {
            stats.small += 1;
            return Verdict::Small;
        }
        let (x, y) = corner(&rect, k);
        emit(ctx, region, x, y, footprint.min(ctx.radius), out);
        stats.small += 1;
        return Verdict::Small;
    }
    Verdict::Unproven {
        footprint,
        distortion,
    }
}

/// What eq. 22 at the centre of a rectangle of footprint up to `2r` settles: every point lies
/// within half the diagonal of the centre, so a sample there covers it when the centre is on
/// the surface (`Small`), and the centre's disc proves it off the surface when it reaches the
/// corners (`Discarded`).
fn at_centre(
    ctx: &RegionContext<'_>,
    region: &BasicRegion,
    (rect, distortion): (&Rect, f64),
    out: &mut Vec<Sample>,
    (memo, stats): Walk<'_>,
) -> Option<Verdict> {
    let half_diagonal = 0.5 * rect.diagonal();
    let (cx, cy) = rect.centre();
    let (centre, _) = plane_values(ctx, region, cx, cy, (memo, stats));
    if centre < 0.0 {
        let radius = (distortion * half_diagonal).min(ctx.radius);
        emit(ctx, region, cx, cy, radius, out);
        stats.small += 1;
        return Some(Verdict::Small);
    }
    if centre / distortion >= half_diagonal {
        stats.discarded += 1;
        return Some(Verdict::Discarded);
    }
    None
}

/// Whether the discs of radii `radii` around the corners of a rectangle `w × h` (in [`corner`]
/// order) cover it: each quadrant (the quarter at corner `k`) lies in some corner's disc,
/// corner `j`'s holding all of it when it reaches the quadrant's farthest vertex from `j`. This
/// takes in the rules "one disc reaches the opposite corner" and "every disc reaches the
/// centre", and also settles a rectangle where the discs at one end reach past the middle: on
/// the examples at 1 % of the diagonal, 4 % fewer queries and 1 % fewer samples (larger
/// rectangles filled).
fn discs_cover((w, h): (f64, f64), radii: [f64; 4]) -> bool {
    let reaches = |j: usize, k: usize| {
        let dx = if (j ^ k) & 1 == 0 { 0.5 * w } else { w };
        let dy = if (j ^ k) & 2 == 0 { 0.5 * h } else { h };
        radii[j] * radii[j] >= dx * dx + dy * dy
    };
    (0..4).all(|k| (0..4).any(|j| reaches(j, k)))
}

/// Samples [`covered_by_recent`] looks back over.
const RECENT_SAMPLES: usize = 16;

/// The surface point over the centre of `rect`, with the quadric's normal there; `None` where
/// there is no surface or the normal is undefined (a cone's apex).
fn centre_point(
    ctx: &RegionContext<'_>,
    region: &BasicRegion,
    rect: &Rect,
) -> Option<SurfacePoint> {
    let (x, y) = rect.centre();
    let position = region_point(ctx.frame, &region.heightfield, region.sheet, x, y)?;
    SurfacePoint::on(ctx.quadric, position)
}

/// Whether one of the last samples of `out` (those of the region's block, or of the
/// refinement, so far) of the region's quadric and term covers the whole rectangle (of
/// footprint `footprint`), its radius grown to reach it if need be (never beyond `r`):
/// depth-first order puts a small rectangle's neighbours among them, and along a feature curve
/// one sample then covers several small rectangles instead of each taking its own.
fn covered_by_recent(
    ctx: &RegionContext<'_>,
    region: &BasicRegion,
    rect: &Rect,
    footprint: f64,
    out: &mut [Sample],
) -> bool {
    let (x, y) = rect.centre();
    let Some(position) = region_point(ctx.frame, &region.heightfield, region.sheet, x, y) else {
        return false;
    };
    let extent = 0.5 * footprint;
    let recent = out.len().saturating_sub(RECENT_SAMPLES)..out.len();
    // Where no recent sample is near enough (most rectangles), the centre needs no normal.
    let near = |s: &Sample| may_cover(s.position - position, extent, ctx.radius);
    if !out[recent.clone()].iter().any(near) {
        return false;
    }
    let Some(centre) = SurfacePoint::on(ctx.quadric, position) else {
        return false;
    };
    // A sample of another term is clipped to that term, and might draw nothing here.
    let own_quadric = |s: &Sample| s.quadric == region.quadric && s.term == region.term;
    let recent = recent.rev();
    grow_to_cover(out, recent, centre, extent, ctx.radius, own_quadric)
}

/// The two halves of a cell across its longer edge, with their corner distances; `None` when
/// floating point cannot make them smaller.
fn split(
    ctx: &RegionContext<'_>,
    region: &BasicRegion,
    cell: &Cell,
    (memo, stats): Walk<'_>,
) -> Option<(Cell, Cell)> {
    let rect = cell.rect;
    let (low, high, along_x) = rect.split_longest();
    if low.diagonal() >= rect.diagonal() || high.diagonal() >= rect.diagonal() {
        return None;
    }
    // The two new corners, shared by both halves: `k0` (`k1`) of the low half is `j0` (`j1`)
    // of the high one.
    let ((x0, y0), (x1, y1), [k0, k1], [j0, j1]) = if along_x {
        ((low.x.1, rect.y.0), (low.x.1, rect.y.1), [1, 3], [0, 2])
    } else {
        ((rect.x.0, low.y.1), (rect.x.1, low.y.1), [2, 3], [0, 1])
    };
    let m0 = plane_values(ctx, region, x0, y0, (memo, stats));
    let m1 = plane_values(ctx, region, x1, y1, (memo, stats));
    let (mut low_cell, mut high_cell) = (*cell, *cell);
    low_cell.rect = low;
    high_cell.rect = high;
    for (k, j, (d, slope)) in [(k0, j0, m0), (k1, j1, m1)] {
        (low_cell.d[k], low_cell.slope[k]) = (d, slope);
        (high_cell.d[j], high_cell.slope[j]) = (d, slope);
    }
    Some((low_cell, high_cell))
}

/// First pass over basic region number `index`, appending its samples to `out` in a
/// deterministic (depth-first) order. Rectangles of footprint at most `r` that it cannot prove
/// go to `deferred`, for [`refine_deferred`]. Both may hold earlier regions' output already;
/// `out[block_start..]` (the samples of the region's block so far, [`crate::blocks`]) may cover
/// its small rectangles.
pub fn sample_region(
    ctx: &RegionContext<'_>,
    (index, region): (usize, &BasicRegion),
    (out, block_start): (&mut Emitted, usize),
    deferred: &mut Vec<Deferred>,
    (memo, stats): Walk<'_>,
) {
    // The walk starts empty before the root's corners too: the memo knows points by their
    // plane coordinates alone, and the region before may have been another sheet, plane or
    // quadric, whose value at the same coordinates is that of another point.
    memo.clear();
    let root = Cell::new(ctx, region, region.rect, (memo, stats));
    subdivide(
        (ctx, index, region),
        root,
        (out, block_start),
        deferred,
        (memo, stats),
    );
    out.box_new();
}

/// Rectangles whose footprint is at least this many radii are split into halves that other
/// threads may take (see "Threads" in the module docs): a large face is otherwise one piece of
/// work, which left one thread sampling a quarter of a dimpled cube while the other waited.
pub const TASK_FOOTPRINT: f64 = 32.0;

/// The subdivision of `root`, a cell of basic region number `index`, depth first; its small
/// rectangles may be covered by `out[look_back..]`. It starts from an empty memo, and empties
/// it again after the halves of a large cell: each half may run on another thread with a
/// memo of its own.
fn subdivide(
    (ctx, index, region): (&RegionContext<'_>, usize, &BasicRegion),
    root: Cell,
    (out, look_back): (&mut Emitted, usize),
    deferred: &mut Vec<Deferred>,
    (memo, stats): Walk<'_>,
) {
    memo.clear();
    let (first_sample, first_deferred) = (out.len(), deferred.len());
    let first_queries = stats.distance_queries;
    let mut stack = vec![root];
    let mut meter = Meter::new(ctx.budget, region.quadric);
    // Deferred rectangles count as samples: each one is held in memory until the second pass.
    let pending = |out: &[Sample], deferred: &[Deferred], stats: &SubdivisionStats| {
        let held = out.len() - first_sample + deferred.len() - first_deferred;
        (held as u64, stats.distance_queries - first_queries)
    };
    let defer = |cell| Deferred {
        region: index,
        cell,
    };
    while let Some(mut cell) = stack.pop() {
        let (held, queries) = pending(out, deferred, stats);
        if !meter.tick(held, queries) {
            break;
        }
        if cell.owned_by_none(region) {
            stats.other_plane += 1;
            continue;
        }
        match classify(ctx, region, &cell, (out, look_back), (memo, stats)) {
            Verdict::Discarded | Verdict::Filled | Verdict::Small => {}
            Verdict::Unproven { distortion, .. } => {
                // The centre at once. Deferring the cell to look for a covering sample first,
                // as the second pass does, saved more queries (three balls at 1 % of the
                // diagonal: 9 % against 6 %), but the larger second pass cost the cubes dimpled
                // or hollowed by balls 0.3-0.9 % more instructions than that saved.
                let centre = (&cell.rect, distortion);
                if at_centre(ctx, region, centre, out, (memo, stats)).is_none() {
                    deferred.push(defer(cell));
                }
            }
            Verdict::Split { footprint } => match split(ctx, region, &cell, (memo, stats)) {
                Some(halves) if footprint >= TASK_FOOTPRINT * ctx.radius => {
                    // The halves charge the budget themselves.
                    meter.finish(held, queries);
                    let task = (ctx, index, region);
                    split_in_parallel(task, halves, (out, look_back), deferred, (memo, stats));
                    memo.clear();
                    let (held, queries) = pending(out, deferred, stats);
                    meter.skip_to(held, queries);
                }
                Some((low, high)) => {
                    stack.push(high);
                    stack.push(low);
                }
                None => deferred.push(defer(cell)),
            },
        }
    }
    let (held, queries) = pending(out, deferred, stats);
    meter.finish(held, queries);
}

/// The subdivisions of the two halves of a large cell, low then high, the high one open to
/// another thread (rayon's work stealing). The low half continues in `out`; the high half's
/// small rectangles look back only at its own samples, whichever thread takes it, so the output
/// does not depend on the thread count. It writes to `out` too when the low half is done by
/// the time it starts (always on one thread), else to buffers of its own, appended after.
fn split_in_parallel(
    task: (&RegionContext<'_>, usize, &BasicRegion),
    (low, high): (Cell, Cell),
    (out, look_back): (&mut Emitted, usize),
    deferred: &mut Vec<Deferred>,
    (memo, stats): Walk<'_>,
) {
    // The outputs, and whether the low half is done with them. Each half boxes its samples to
    // its end, as appending a half another thread took does: the boxes, which clip lists go by
    // (`clip`), are then the same on any number of threads.
    let shared = Mutex::new((out, deferred, (memo, stats), false));
    let (_, own) = rayon::join(
        || {
            let mut shared = shared.lock().unwrap_or_else(PoisonError::into_inner);
            let (out, deferred, (memo, stats), done) = &mut *shared;
            subdivide(task, low, (out, look_back), deferred, (memo, stats));
            out.box_new();
            *done = true;
        },
        || {
            // Busy: the low half holds them (this thread runs this half while the low one
            // waits for work it handed out, or another thread took this half).
            if let Ok(mut shared) = shared.try_lock()
                && shared.3
            {
                let (out, deferred, (memo, stats), _) = &mut *shared;
                let start = out.len();
                subdivide(task, high, (out, start), deferred, (memo, stats));
                out.box_new();
                return None;
            }
            let (mut out, mut deferred, mut memo) =
                lock(task.0.spare_halves).pop().unwrap_or_default();
            let mut stats = SubdivisionStats::default();
            let walk = (&mut memo, &mut stats);
            subdivide(task, high, (&mut out, 0), &mut deferred, walk);
            Some(((out, deferred, memo), stats))
        },
    );
    if let Some(((mut more, mut more_deferred, memo), counters)) = own {
        let (out, deferred, (_, stats), _) =
            shared.into_inner().unwrap_or_else(PoisonError::into_inner);
        // A run past a limit ends in an error: what the half holds is not copied on.
        if task.0.budget.stopped() {
            more.clear();
            more_deferred.clear();
        }
        out.append(&mut more);
        deferred.extend_from_slice(&more_deferred);
        more_deferred.clear();
        stats.add(&counters);
        // Appended to an empty `out`, `more` took over its buffers, which have no memory.
        if more.capacity() > 0 {
            lock(task.0.spare_halves).push((more, more_deferred, memo));
        }
    }
}

/// Second pass over one deferred rectangle. It is covered as soon as a sample of the same
/// quadric lies within `r − footprint / 2` of its centre's surface point (one this refinement
/// emitted, or a first-pass sample from `index`); that sample's radius grows to reach the
/// whole rectangle (at once for its own samples, through `grown` for the first pass's), so a
/// splat of that radius covers it. Otherwise it is split and classified again (a part's
/// centre is asked, `at_centre`, only where no sample covers the part),
/// down to [`SMALL_REGION_FRACTION`] of the footprint (or until `MAX_UNPROVEN_PER_DEFERRED`
/// rectangles stayed unproven), where it goes to `given_up`: one by one up to `share` of them
/// ([`given_up_share`]), the rest as the whole deferred rectangle; it counts as unresolved when
/// no sample could reach it.
pub fn refine_deferred(
    ctx: &RegionContext<'_>,
    region: &BasicRegion,
    deferred: &Deferred,
    index: &SampleIndex<'_>,
    (out, given_up, grown): (&mut Emitted, &mut Vec<GivenUp>, &mut Vec<(u32, f64)>),
    share: usize,
    (memo, stats): Walk<'_>,
) {
    memo.clear();
    let cutoff = SMALL_REGION_FRACTION * ctx.radius / region.max_distortion.max(1.0);
    let first_sample = out.len();
    let first_given_up = given_up.len();
    let mut unproven = 0usize;
    let mut overflow = 0u64;
    let mut settled_up_to = out.len();
    let mut stack = vec![(deferred.cell, true)];
    let mut meter = Meter::new(ctx.budget, region.quadric);
    let queries_before = stats.distance_queries;
    let done = |out: &[Sample], stats: &SubdivisionStats| {
        let samples = (out.len() - first_sample) as u64;
        (samples, stats.distance_queries - queries_before)
    };
    let root_footprint = cell_footprint(region, &deferred.cell);
    // The index's samples within `r` of the deferred rectangle's centre ([`SampleIndex::near`]),
    // with that centre, once it is looked up.
    let mut near_root: Option<(DVec3, Vec<Member<'_>>)> = None;
    while let Some((mut cell, classified)) = stack.pop() {
        let (samples, queries) = done(out, stats);
        if !meter.tick(samples, queries) {
            break;
        }
        // A part's centre is asked ([`at_centre`]) only once no sample covers it: most parts
        // that reach here are covered.
        let mut centre = None;
        let footprint = if classified {
            // The first pass has classified this one (the deferred rectangle) already.
            root_footprint
        } else if cell.owned_by_none(region) {
            stats.other_plane += 1;
            continue;
        } else {
            match classify(ctx, region, &cell, (out, first_sample), (memo, stats)) {
                Verdict::Discarded | Verdict::Filled | Verdict::Small => continue,
                Verdict::Unproven {
                    footprint,
                    distortion,
                } => {
                    centre = Some(distortion);
                    footprint
                }
                Verdict::Split { .. } => f64::INFINITY,
            }
        };
        let extent = 0.5 * footprint;
        let point = centre_point(ctx, region, &cell.rect).filter(|_| extent < ctx.radius);
        if let Some(point) = point
            && classified
        {
            let mut near = Vec::new();
            index.near(region.quadric, point.position, &mut near);
            near_root = Some((point.position, near));
        }
        // A sample that covers the ball of radius `extent` around a point lies within
        // `r − extent` of it: within `r` of the root's centre, and on its list, where the
        // point lies within `extent` of that centre.
        let listed = |p: DVec3, extent: f64| {
            let (centre, near) = near_root.as_ref()?;
            ((p - *centre).length() <= extent).then_some(near.as_slice())
        };
        if let Some(point) = point {
            let own = first_sample..out.len();
            if grow_to_cover(out, own, point, extent, ctx.radius, |_| true) {
                stats.unresolved_covered += 1;
                continue;
            }
            let cover = match listed(point.position, extent) {
                Some(near) => index.cover_among(near.iter().copied(), region.term, point, extent),
                None => index.cover((region.quadric, region.term), point, extent),
            };
            if let Some(cover) = cover {
                grown.push(cover);
                stats.unresolved_covered += 1;
                continue;
            }
        }
        if let Some(distortion) = centre
            && at_centre(ctx, region, (&cell.rect, distortion), out, (memo, stats)).is_some()
        {
            continue;
        }
        if point.is_some() {
            // Where samples cover both halves but none the whole, the split and its halves
            // need no query (three balls at 0.15 % of the diagonal: 9 % fewer queries, 5 %
            // fewer instructions; a failed try cost about a query while each try looked its
            // halves up in the index's cubes, before the list near the root's centre).
            let both_halves = (cell.rect.diagonal() > cutoff)
                .then(|| cover_halves(ctx, region, &cell, (out, first_sample), (index, &listed)))
                .flatten();
            if let Some(covers) = both_halves {
                for (own, i, needed) in covers {
                    if own {
                        grow_radius(out, i, needed);
                    } else {
                        grown.push((i, needed));
                    }
                }
                stats.unresolved_covered += 2;
                continue;
            }
        }
        unproven += 1;
        let halves = if cell.rect.diagonal() <= cutoff || unproven > MAX_UNPROVEN_PER_DEFERRED {
            None
        } else {
            split(ctx, region, &cell, (memo, stats))
        };
        match (halves, point) {
            (Some((low, high)), _) => {
                stack.push((high, false));
                stack.push((low, false));
            }
            (None, Some(point)) => {
                // A sample this refinement emits later may still cover it.
                let leaf = GivenUp {
                    quadric: region.quadric,
                    term: region.term,
                    point,
                    extent,
                    count: 1,
                    region: deferred.region,
                    rect: cell.rect,
                };
                if given_up.len() - first_given_up >= share && out.len() > settled_up_to {
                    let own = (first_sample, ctx.radius);
                    settle_locally(given_up, first_given_up, out, own, stats);
                    settled_up_to = out.len();
                }
                if given_up.len() - first_given_up < share {
                    given_up.push(leaf);
                } else {
                    overflow += 1;
                }
            }
            (None, None) => stats.unresolved += 1,
        }
    }
    settle_locally(
        given_up,
        first_given_up,
        out,
        (first_sample, ctx.radius),
        stats,
    );
    if overflow > 0 {
        let extent = 0.5 * root_footprint;
        match centre_point(ctx, region, &deferred.cell.rect) {
            Some(point) if extent < ctx.radius => given_up.push(GivenUp {
                quadric: region.quadric,
                term: region.term,
                point,
                extent,
                count: overflow,
                region: deferred.region,
                rect: deferred.cell.rect,
            }),
            _ => stats.unresolved += overflow,
        }
    }
    let (samples, queries) = done(out, stats);
    meter.finish(samples, queries);
}

/// Covers of both halves of an unproven cell ([`Rect::split_longest`]) by samples, without a
/// distance query: by the refinement's own samples `out[first..]` (`true`) or by the index's
/// samples that `listed` holds for a half's centre and extent (none where it holds none); each
/// with the sample's index and the radius it needs. `None` unless both are covered. Where a
/// sample covers each half but none the whole, this saves the split's queries and those of
/// its halves.
fn cover_halves<'n>(
    ctx: &RegionContext<'_>,
    region: &BasicRegion,
    cell: &Cell,
    (out, first): (&[Sample], usize),
    (index, listed): (
        &SampleIndex<'n>,
        &impl Fn(DVec3, f64) -> Option<&'n [Member<'n>]>,
    ),
) -> Option<[(bool, u32, f64); 2]> {
    let (low, high, _) = cell.rect.split_longest();
    // The cell's distortion bound holds over its halves.
    let distortion = cell_distortion(region, cell);
    let own = || (first..out.len()).map(|i| (i as u32, &out[i]));
    let cover = |half: &Rect| {
        let extent = 0.5 * distortion * half.diagonal();
        let (x, y) = half.centre();
        let position = region_point(ctx.frame, &region.heightfield, region.sheet, x, y)?;
        let near = listed(position, extent).unwrap_or_default();
        // Where no sample is near enough (most halves), the centre needs no normal.
        let candidates = own().map(|(_, s)| s).chain(near.iter().map(|&(_, s)| s));
        if !candidates
            .into_iter()
            .any(|s| may_cover(s.position - position, extent, ctx.radius))
        {
            return None;
        }
        let point = SurfacePoint::on(ctx.quadric, position)?;
        if let Some((i, needed)) = cover_by(own(), point, extent, ctx.radius, |_| true) {
            return Some((true, i, needed));
        }
        let (i, needed) = index.cover_among(near.iter().copied(), region.term, point, extent)?;
        Some((false, i, needed))
    };
    Some([cover(&low)?, cover(&high)?])
}

/// Settles the given-up rectangles `given_up[from..]` against the samples `out[first..]` of the
/// same refinement (all of one quadric), within `radius`: covered ones are counted and removed.
fn settle_locally(
    given_up: &mut Vec<GivenUp>,
    from: usize,
    out: &mut [Sample],
    (first, radius): (usize, f64),
    stats: &mut SubdivisionStats,
) {
    let mut kept = from;
    for i in from..given_up.len() {
        let g = given_up[i];
        if grow_to_cover(out, first..out.len(), g.point, g.extent, radius, |_| true) {
            stats.unresolved_covered += g.count;
        } else {
            given_up[kept] = g;
            kept += 1;
        }
    }
    given_up.truncate(kept);
}

/// A rectangle given up unclassified: covered if some sample of the same quadric, from any
/// region or pass, covers the ball of radius `extent` around `point` ([`settle_given_up`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GivenUp {
    /// Index of the quadric in the DNF's quadric table.
    pub quadric: u32,
    /// Index of the term it was sampled for.
    pub term: u32,
    /// The surface point over the rectangle's centre.
    pub point: SurfacePoint,
    /// Half the footprint: every surface point of the rectangle is this close to `point`.
    pub extent: f64,
    /// How many given-up rectangles this stands for (more than one: all of them lie in it).
    pub count: u64,
    /// Index of the basic region it belongs to.
    pub region: usize,
    /// The rectangle (the deferred one it lies in when `count` is more than one).
    pub rect: Rect,
}

/// Settles given-up rectangles against all samples (`boxes` around runs of them, as
/// [`SampleIndex::new`] takes them): covered ones are counted in
/// [`SubdivisionStats::unresolved_covered`] (the covering sample's radius grown as needed, to
/// at most `radius`); the rest are returned, for [`probe_given_up`].
pub fn settle_given_up(
    dnf: &Dnf,
    given_up: &[GivenUp],
    (samples, boxes): (&mut Samples, &[SampleBox]),
    radius: f64,
    stats: &mut SubdivisionStats,
) -> Vec<GivenUp> {
    let covered = cover_given_up(dnf, given_up, (samples, boxes), radius);
    let mut uncovered = Vec::new();
    for (g, covered) in given_up.iter().zip(covered) {
        if covered {
            stats.unresolved_covered += g.count;
        } else {
            uncovered.push(*g);
        }
    }
    uncovered
}

/// Whether all the parts a probe left of each given-up rectangle ([`Probed::Unresolved`]) are
/// covered by samples, as [`settle_given_up`] covers (the covering samples' radii grown): a
/// rectangle that touches the surface only along its edge, where it meets a filled one, has
/// parts along that edge close enough to the filled one's samples when the whole is not.
pub fn settle_parts(
    dnf: &Dnf,
    parts: &[Vec<GivenUp>],
    (samples, boxes): (&mut Samples, &[SampleBox]),
    radius: f64,
) -> Vec<bool> {
    let all: Vec<GivenUp> = parts.iter().flatten().copied().collect();
    let covered = cover_given_up(dnf, &all, (samples, boxes), radius);
    let mut start = 0;
    parts
        .iter()
        .map(|p| {
            let of_this = &covered[start..start + p.len()];
            start += p.len();
            !p.is_empty() && of_this.iter().all(|&c| c)
        })
        .collect()
}

/// Whether a sample covers each given-up rectangle (the ball of radius `extent` around its
/// point), the covering samples' radii grown as needed to at most `radius`.
fn cover_given_up(
    dnf: &Dnf,
    given_up: &[GivenUp],
    (samples, boxes): (&mut Samples, &[SampleBox]),
    radius: f64,
) -> Vec<bool> {
    let centres: Vec<(u32, DVec3)> = given_up
        .iter()
        .map(|g| (g.quadric, g.point.position))
        .collect();
    let index = SampleIndex::new(dnf, (samples, boxes), &centres, radius);
    let covers: Vec<Option<(u32, f64)>> = given_up
        .iter()
        .map(|g| index.cover((g.quadric, g.term), g.point, g.extent))
        .collect();
    drop(index);
    covers
        .into_iter()
        .map(|cover| {
            cover
                .inspect(|&(i, needed)| samples.grow_radius(i, needed))
                .is_some()
        })
        .collect()
}

/// Levels of quadrants below a given-up rectangle that [`probe_given_up`] looks at: down to a
/// 4 × 4 grid, at most 21 distance queries. A third level (85) settled about 1 % more of them
/// on most stability scenes, for two to four times the queries spent probing.
const PROBE_LEVELS: u32 = 2;

/// Most parts a probe follows further down to a speck ([`probe_given_up`]): those around one
/// point, which is a corner of at most four.
const POINT_PARTS: usize = 4;

/// Most levels a probe follows parts around one point: far below any speck (`2⁻⁶⁰` of the
/// rectangle).
const POINT_LEVELS: u32 = 60;

/// The last resort for a given-up rectangle that no sample reaches. A sample of the same term
/// and quadric that an earlier probe made, `out[first..]`, covers it if it reaches (its radius
/// grown to at most `r`). Else the rectangle is probed at its centre and, where that settles
/// nothing, at its quadrants' centres, down to `PROBE_LEVELS` levels:
/// - the first centre on the CSG surface gets a sample whose radius, the rectangle's footprint,
///   reaches all of it (a sliver of surface that avoided every corner and centre down to the
///   cutoff);
/// - if every part is off the surface by a disc that reaches its corners, no point of the
///   rectangle is on it (the usual case: a rectangle within a hair of a surface it does not
///   cross, as where the hollowed cube's corner ball, a face and the big ball meet, at 0.15 % of
///   the diagonal);
/// - parts that are neither and lie around one point are followed further down
///   (`down_to_speck`);
/// - else eq. 22 is followed downhill from the centre, across a band of surface that may be too
///   thin for any centre to land on (`seek_surface`); a point found on the surface gets a sample
///   as above. What is left is returned, for [`settle_parts`].
///
/// Only a rectangle that stands for itself (`count` 1) is probed.
pub fn probe_given_up(
    ctx: &RegionContext<'_>,
    region: &BasicRegion,
    leaf: &GivenUp,
    (out, first): (&mut Vec<Sample>, usize),
    stats: &mut SubdivisionStats,
) -> Probed {
    let same = |s: &Sample| s.quadric == leaf.quadric && s.term == leaf.term;
    let made = first..out.len();
    if grow_to_cover(out, made, leaf.point, leaf.extent, ctx.radius, same) {
        return Probed::Covered;
    }
    if leaf.count != 1 {
        return Probed::Unresolved(Vec::new());
    }
    let distortion = rect_distortion(region, &leaf.rect);
    let probed = match probe(ctx, region, leaf.rect, distortion, PROBE_LEVELS, stats) {
        Probe::Unknown(parts) => match down_to_speck(ctx, region, parts, distortion, stats) {
            Probe::Unknown(parts) => match seek_surface(ctx, region, &leaf.rect, distortion, stats)
            {
                Some((x, y)) => Probe::Inside(x, y),
                None => Probe::Unknown(parts),
            },
            decided => decided,
        },
        decided => decided,
    };
    match probed {
        Probe::Inside(x, y) => {
            let footprint = distortion * leaf.rect.diagonal();
            let before = out.len();
            emit(ctx, region, x, y, footprint.min(ctx.radius), out);
            if out.len() > before {
                Probed::Covered
            } else {
                Probed::Unresolved(Vec::new())
            }
        }
        Probe::Off => Probed::Off,
        Probe::Unknown(parts) => Probed::Unresolved(
            parts
                .into_iter()
                .map(|rect| {
                    let point = centre_point(ctx, region, &rect);
                    let extent = 0.5 * distortion * rect.diagonal();
                    point.map(|point| GivenUp {
                        point,
                        extent,
                        rect,
                        ..*leaf
                    })
                })
                .collect::<Option<Vec<GivenUp>>>()
                .unwrap_or_default(),
        ),
    }
}

/// Follows the parts a probe left (`parts`, with `distortion`) further down while they lie
/// around one point ([`POINT_PARTS`]): where all the rest of a rectangle is proven off the
/// surface, that point is all that is left, as where three branches of a tree start at the
/// centre of their trunk's cap and eq. 22, which looks at one term at a time, is zero. Once
/// every part's footprint is a speck ([`RegionContext::speck`]), nothing of the rectangle but
/// a speck is on the surface: it is off. A point on the surface found on the way is `Inside`;
/// where the parts spread along a curve instead, `parts` are returned as they came.
fn down_to_speck(
    ctx: &RegionContext<'_>,
    region: &BasicRegion,
    parts: Vec<Rect>,
    distortion: f64,
    stats: &mut SubdivisionStats,
) -> Probe {
    // Around a cone's apex no heightfield point has a normal: that is for the apex rings.
    if ctx.quadric.kind() == QuadricKind::Cone {
        return Probe::Unknown(parts);
    }
    let mut left = parts.clone();
    for _ in 0..POINT_LEVELS {
        if left.len() > POINT_PARTS {
            break;
        }
        if left.iter().all(|p| distortion * p.diagonal() <= ctx.speck) {
            return Probe::Off;
        }
        // A part's centre was probed already, as a quadrant one level up.
        let mut smaller = Vec::new();
        for quadrant in left.iter().flat_map(Rect::quadrants) {
            match probe(ctx, region, quadrant, distortion, 0, stats) {
                Probe::Inside(x, y) => return Probe::Inside(x, y),
                Probe::Off => {}
                Probe::Unknown(quadrant) => smaller.extend(quadrant),
            }
        }
        if smaller.is_empty() {
            return Probe::Off;
        }
        left = smaller;
    }
    Probe::Unknown(parts)
}

/// Most steps [`seek_surface`] takes along its line.
const SEEK_STEPS: usize = 12;

/// [`seek_surface`]'s difference quotients step this fraction of the distance to the surface
/// that eq. 22 allows, so that both points lie on the same side of it.
const SEEK_STEP: f64 = 1e-3;

/// Relative to the coordinates, the shortest step of a difference quotient: far above their
/// rounding.
const SEEK_ROUNDING: f64 = 1e-12;

/// A point of `rect` on the CSG surface, found by following eq. 22 downhill from the centre:
/// where the surface is a band too thin for any corner or centre to land on (the cut rim of a
/// wall `1e-9` thick), eq. 22 along a line across the band falls to it at a steady slope and
/// rises past it, a V whose tip dips below zero only over the band's width. The line follows
/// the gradient at the centre (by difference quotients); Newton steps along the falling side
/// find the rising one, then the crossing of the two sides, taken as lines, is the next guess.
/// Only a point where eq. 22 is negative counts, so the search proves what it finds; it gives
/// up when the sides cross above zero (surfaces that touch without crossing), leave the
/// rectangle or after [`SEEK_STEPS`] steps.
fn seek_surface(
    ctx: &RegionContext<'_>,
    region: &BasicRegion,
    rect: &Rect,
    distortion: f64,
    stats: &mut SubdivisionStats,
) -> Option<(f64, f64)> {
    let (cx, cy) = rect.centre();
    let d0 = query(ctx, region, cx, cy, stats);
    if !(d0 > 0.0 && d0.is_finite()) {
        return None;
    }
    // Eq. 22 changes by at most `distortion` per unit of the plane.
    let shortest = SEEK_ROUNDING * (cx.abs().max(cy.abs()) + rect.diagonal());
    let step = |d: f64| (SEEK_STEP * d / distortion.max(1.0)).max(shortest);
    let h = step(d0);
    let gx = (query(ctx, region, cx + h, cy, stats) - d0) / h;
    let gy = (query(ctx, region, cx, cy + h, stats) - d0) / h;
    let g = gx.hypot(gy);
    if !(g > 0.0 && g.is_finite()) {
        return None;
    }
    let (ux, uy) = (-gx / g, -gy / g);
    let point = |t: f64| (cx + t * ux, cy + t * uy);
    // Each side as a point on it: (t, d, slope).
    let mut falling = (0.0, d0, -g);
    let mut rising: Option<(f64, f64, f64)> = None;
    for _ in 0..SEEK_STEPS {
        let t = match rising {
            None => falling.0 - falling.1 / falling.2,
            Some(rising) => {
                let t = (rising.1 - falling.1 + falling.2 * falling.0 - rising.2 * rising.0)
                    / (falling.2 - rising.2);
                if falling.1 + falling.2 * (t - falling.0) > 0.0 {
                    return None;
                }
                t
            }
        };
        let (x, y) = point(t);
        if !rect.contains(x, y) {
            return None;
        }
        let d = query(ctx, region, x, y, stats);
        if d < 0.0 {
            return Some((x, y));
        }
        let h = step(d);
        let (xh, yh) = point(t + h);
        let slope = (query(ctx, region, xh, yh, stats) - d) / h;
        if slope < 0.0 {
            falling = (t, d, slope);
        } else if slope > 0.0 {
            rising = Some((t, d, slope));
        } else {
            return None;
        }
    }
    None
}

/// What eq. 22 at the centres of a rectangle and its quadrants shows.
enum Probe {
    /// A point on the CSG surface.
    Inside(f64, f64),
    /// No point of the rectangle is on it.
    Off,
    /// Neither: the parts, at the deepest level, that are neither.
    Unknown(Vec<Rect>),
}

/// [`probe_given_up`]'s search below `rect`, `levels` levels of quadrants deep.
fn probe(
    ctx: &RegionContext<'_>,
    region: &BasicRegion,
    rect: Rect,
    distortion: f64,
    levels: u32,
    stats: &mut SubdivisionStats,
) -> Probe {
    let (cx, cy) = rect.centre();
    let d = query(ctx, region, cx, cy, stats);
    if d < 0.0 {
        return Probe::Inside(cx, cy);
    }
    // The centre's disc reaches the corners (NaN, no surface point there, proves nothing).
    if d >= 0.5 * distortion * rect.diagonal() {
        return Probe::Off;
    }
    if levels == 0 {
        return Probe::Unknown(vec![rect]);
    }
    let mut unknown = Vec::new();
    for quadrant in rect.quadrants() {
        match probe(ctx, region, quadrant, distortion, levels - 1, stats) {
            Probe::Inside(x, y) => return Probe::Inside(x, y),
            Probe::Off => {}
            Probe::Unknown(parts) => unknown.extend(parts),
        }
    }
    if unknown.is_empty() {
        Probe::Off
    } else {
        Probe::Unknown(unknown)
    }
}

/// What [`probe_given_up`] made of a rectangle.
#[derive(Clone, Debug, PartialEq)]
pub enum Probed {
    /// A sample covers it.
    Covered,
    /// No point of it is on the CSG surface.
    Off,
    /// Neither is proven. The rest of the rectangle is off the surface but for these parts,
    /// each smaller than it (none where it was not probed): if samples cover them all, they
    /// cover what of it is on the surface ([`settle_parts`]).
    Unresolved(Vec<GivenUp>),
}

/// Whether one of the samples `out[i]` for `i` in `indices` that `draws` accepts covers the
/// ball of radius `extent` around `point` with a radius of at most `radius` ([`cover_by`]);
/// that sample's radius grows to reach it if need be.
fn grow_to_cover(
    out: &mut [Sample],
    indices: impl Iterator<Item = usize>,
    point: SurfacePoint,
    extent: f64,
    radius: f64,
    draws: impl Fn(&Sample) -> bool,
) -> bool {
    let candidates = indices.map(|i| (i as u32, &out[i]));
    match cover_by(candidates, point, extent, radius, draws) {
        Some((i, needed)) => {
            grow_radius(out, i, needed);
            true
        }
        None => false,
    }
}

/// Grows sample `i`'s radius to `needed` (never shrinks it).
pub fn grow_radius(samples: &mut [Sample], i: u32, needed: f64) {
    if let Some(sample) = samples.get_mut(i as usize) {
        sample.radius = sample.radius.max(needed);
    }
}

/// Most bits of one quadric's map of wanted cubes (256 KiB); past it the cubes grow (by
/// powers of two).
const MAX_WANTED_BITS: i128 = 1 << 21;

/// The cubes around one quadric's deferred centres, as a bit map over their box: a cube of
/// `2^shift` fine cubes a side is wanted when a centre lies in it or in a neighbour. Testing a
/// sample costs a shift and a bit, where a hash set cost a hash and a probe for every sample.
struct WantedCubes {
    shift: u32,
    /// The box's lowest cube, one below the lowest centre's on each axis.
    low: [i64; 3],
    size: [i64; 3],
    bits: Vec<u64>,
}

impl WantedCubes {
    /// An empty map for centres in the fine cubes from `low` to `high`, with cubes just large
    /// enough that the map's box holds at most [`MAX_WANTED_BITS`] of them.
    fn new(low: [i64; 3], high: [i64; 3]) -> Self {
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
    fn bit(&self, cube: [i64; 3]) -> Option<usize> {
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
    fn mark(&mut self, fine: [i64; 3]) {
        self.mark_cube(fine.map(|v| v >> self.shift));
    }

    /// The map with every marked cube's neighbours marked too. Marking cubes, not centres,
    /// first: millions of deferred rectangles (a ball and an ellipsoid `1e-9` apart at a tiny
    /// radius) crowd into far fewer cubes. A centre's cube lies inside the box, one cube in
    /// from its faces, so its neighbours are three consecutive bits in each of nine rows, not
    /// 27 bits found one by one, each with its bounds. With [`Self::coarser_with_neighbours`]
    /// this took [`SampleIndex::new`] from 7.2 % to 6.2 % of the instructions of sampling three
    /// balls at 0.15 % of the diagonal.
    fn with_neighbours(&self) -> Self {
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
    fn coarser_with_neighbours(&self, by: u32) -> Self {
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
    fn marked(&self) -> impl Iterator<Item = [i64; 3]> + '_ {
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

    fn mark_cube(&mut self, cube: [i64; 3]) {
        if let Some(bit) = self.bit(cube) {
            self.bits[bit / 64] |= 1 << (bit % 64);
        }
    }

    /// Whether the cube holding fine cube `fine` is wanted.
    fn contains(&self, fine: [i64; 3]) -> bool {
        self.contains_cube(fine.map(|v| v >> self.shift))
    }

    /// Whether a wanted cube may hold a fine cube from `low` to `high` (also when the box
    /// spans more than [`MAX_BOX_CUBES`] cubes: testing it would cost about what reading its
    /// samples does).
    fn meets(&self, low: [i64; 3], high: [i64; 3]) -> bool {
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
    fn contains_cube(&self, cube: [i64; 3]) -> bool {
        self.bit(cube).is_some_and(|bit| self.is_set(bit))
    }

    /// Whether bit `bit` of the map is set.
    fn is_set(&self, bit: usize) -> bool {
        self.bits[bit / 64] & (1 << (bit % 64)) != 0
    }
}

/// Most cubes [`WantedCubes::meets`] tests one by one.
const MAX_BOX_CUBES: i64 = 4096;

/// A box is first tested on a map of cubes `2^COARSER_BY` times as large a side
/// ([`WantedCubes::coarser_with_neighbours`]), where the boxes far from every deferred
/// rectangle (most of them) take a test or two.
const COARSER_BY: u32 = 3;

/// A fine cube of one quadric as one hashable number. Coordinates wrap at 2³²: cubes that far
/// apart share a bucket, which only adds candidates that [`cover_by`] then rejects by distance.
fn bucket_key([x, y, z]: [i64; 3], quadric: u32) -> u128 {
    (u128::from(x as u32) << 96)
        | (u128::from(y as u32) << 64)
        | (u128::from(z as u32) << 32)
        | u128::from(quadric)
}

/// The first pass's samples near deferred rectangles, bucketed by quadric and by cubes of side
/// `2r`: every sample within `r` of a point within `r / 2` of a deferred centre is found (it
/// lies in one of the fine cubes that the ball of radius `r` around the point touches, inside a
/// wanted cube next to the centre's). Only the boxes of samples ([`Emitted`]) that meet a
/// wanted cube are read: at 0.15 % of the diagonal, 7 % of the samples of three balls and 4 %
/// of those of a cube dimpled by 18 balls. With its grouping by counting instead of sorting,
/// this took the index from 11 % to 6 % of the instructions of sampling three balls there.
pub struct SampleIndex<'a> {
    dnf: &'a Dnf,
    radius: f64,
    anchor: DVec3,
    /// Fine cubes per unit length, `1 / 2r`.
    per_length: f64,
    /// The fine cubes' samples in shards ([`shard`]), one per thread, each grouped on a thread
    /// of its own.
    shards: Vec<IndexShard<'a>>,
}

/// A sample of a [`SampleIndex`]: its index among all samples, and the sample.
pub type Member<'a> = (u32, &'a Sample);

/// The fine cubes of one shard of a [`SampleIndex`] with their samples.
struct IndexShard<'a> {
    /// Each fine cube's samples ([`bucket_key`]): a range of `members`.
    buckets: FxHashMap<u128, (u32, u32)>,
    /// The samples, grouped by fine cube, ascending within each.
    members: Vec<Member<'a>>,
}

impl<'a> IndexShard<'a> {
    /// The samples of the cubes among `hits` (pieces of the hits of this shard, each in
    /// ascending sample order, the pieces in order), in two passes (count, then place), each
    /// cube's samples in the order of the hits: sorting the hits by cube and index took
    /// longer, and a vector per cube costs an allocation each.
    fn new<'h>(hits: impl Iterator<Item = &'h [(u128, Member<'a>)]> + Clone) -> Self
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
    fn get(&self, key: u128) -> Option<&[Member<'a>]> {
        let &(start, end) = self.buckets.get(&key)?;
        self.members.get(start as usize..end as usize)
    }
}

/// The shard of `count` (a power of two) that holds cube `key` ([`bucket_key`]): by the sum
/// of its coordinates, so that neighbouring cubes alternate between shards. A mask, not a
/// remainder: with a division for each cube a look-up tries (up to eight),
/// [`SampleIndex::cover`] took 7.6 % of sampling three balls at 0.15 % of the diagonal
/// instead of 7.0 %.
fn shard(key: u128, count: usize) -> usize {
    let [x, y, z] = [96, 64, 32].map(|bits| (key >> bits) as u32);
    x.wrapping_add(y).wrapping_add(z) as usize & (count - 1)
}

impl<'a> SampleIndex<'a> {
    /// Indexes the samples of `samples` that may cover a point near one of `centres` (surface
    /// points with their quadric). Of the samples in `sample_boxes` ([`Emitted`]), only those
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

    fn key(&self, p: DVec3) -> [i64; 3] {
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
    fn cubes_near<'s>(
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

/// Whether the part of the ball of radius `extent` around `p` that lies in term `own` lies
/// inside every literal of `sample`'s term but its own quadric (by the conservative distance),
/// so that the sample's clipping keeps it. Literals both terms hold are skipped: inside term
/// `own` they hold anyway.
fn inside_term(dnf: &Dnf, sample: &Sample, own: u32, p: DVec3, extent: f64) -> bool {
    let (Some(term), Some(own)) = (
        dnf.terms.get(sample.term as usize),
        dnf.terms.get(own as usize),
    ) else {
        return false;
    };
    term.literals.iter().all(|&j| {
        j == sample.quadric
            || own.literals.contains(&j)
            || dnf
                .quadrics
                .get(j as usize)
                .is_some_and(|q| q.quadric.conservative_distance(p) <= -extent)
    })
}

/// A point of a quadric's surface with its outward unit normal, and how fast the normal turns
/// around it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    /// The point.
    pub position: DVec3,
    /// The quadric's outward unit normal there.
    pub normal: DVec3,
    /// Within distance `d` of the point, the quadric's normal is less than `asin(bend · d)`
    /// from [`Self::normal`]: `∇Q(p) = ∇Q(c) + 2 A (p − c)`, so `bend = 2 ‖A‖ / ‖∇Q(c)‖`.
    pub bend: f64,
}

impl SurfacePoint {
    /// `position` with `normal`, on a surface taken as flat around it (`bend = 0`).
    pub fn new(position: DVec3, normal: DVec3) -> Self {
        Self {
            position,
            normal,
            bend: 0.0,
        }
    }

    /// The point of `quadric` at `position`; `None` where the normal is undefined (a cone's
    /// apex).
    pub fn on(quadric: &Quadric, position: DVec3) -> Option<Self> {
        let gradient = quadric.gradient(position);
        let (lower, upper) = quadric.eigenvalue_bounds();
        Some(Self {
            position,
            normal: Quadric::normal_from_gradient(gradient)?,
            // A hair more, for the rounding of the bound itself.
            bend: 2.0 * lower.abs().max(upper) / gradient.length() * (1.0 + 1e-12),
        })
    }

    /// Whether `sample` faces the same side ([`Sample::same_side`]) as every point of the
    /// quadric within `extent` of this one: its normal is less than `90° − asin(bend · extent)`
    /// from this point's, that is `n · normal > bend · extent`.
    pub fn faces(&self, sample: &Sample, extent: f64) -> bool {
        let spread = self.bend * extent;
        spread < 1.0 && sample.normal.dot(self.normal) > spread
    }
}

/// Whether a sample `offset` from a point may cover the ball of radius `extent` around it
/// with a radius of at most `radius`: passed by every sample that [`cover_by`] can take, with a
/// margin for rounding, and without a square root. Most candidates fail it.
fn may_cover(offset: DVec3, extent: f64, radius: f64) -> bool {
    let reach = radius - extent;
    reach >= 0.0 && offset.length_squared() <= reach * reach * (1.0 + 1e-9)
}

/// Of `samples` that face the same side as every point of the ball of radius `extent` around
/// `point` ([`SurfacePoint::faces`]), the first whose disc already covers that ball
/// (`|position − point| + extent ≤ its radius`), else the nearest that would with a radius of
/// at most `radius`: its index and the radius it needs. Only samples `draws` accepts count; it
/// is asked last, of the samples near enough, as it can cost more than the distance.
pub fn cover_by<'s>(
    samples: impl Iterator<Item = (u32, &'s Sample)>,
    point: SurfacePoint,
    extent: f64,
    radius: f64,
    draws: impl Fn(&Sample) -> bool,
) -> Option<(u32, f64)> {
    let mut nearest: Option<(u32, f64)> = None;
    for (i, sample) in samples {
        let offset = sample.position - point.position;
        if !may_cover(offset, extent, radius) {
            continue;
        }
        if !point.faces(sample, extent) {
            continue;
        }
        let needed = offset.length() + extent;
        if needed <= sample.radius {
            if draws(sample) {
                return Some((i, sample.radius));
            }
        } else if needed <= radius && nearest.is_none_or(|(_, best)| needed < best) && draws(sample)
        {
            nearest = Some((i, needed));
        }
    }
    nearest
}

/// `⌊v⌋` as an integer (saturating), without a call into libm.
fn floor(v: f64) -> i64 {
    let t = v as i64;
    if (t as f64) > v { t - 1 } else { t }
}

/// The maximum distortion over a sub-rectangle (§3.4), falling back to the region's bound.
fn rect_distortion(region: &BasicRegion, rect: &Rect) -> f64 {
    let high = region.heightfield.distortion_bounds(rect.x, rect.y);
    bounded_distortion(region, high.map(|(_, high)| high))
}

/// [`rect_distortion`] of a cell, from its corners' slopes: basic regions lie in one quadrant
/// of their plane, where the corners bound the distortion, and so do their sub-rectangles.
fn cell_distortion(region: &BasicRegion, cell: &Cell) -> f64 {
    if !in_one_quadrant(&cell.rect) {
        return rect_distortion(region, &cell.rect);
    }
    bounded_distortion(region, corner_bounds(cell.slope).map(|(_, high)| high))
}

/// Whether a rectangle lies in one quadrant of its plane (no axis runs through it), where the
/// squared slopes at its corners bound its distortion.
fn in_one_quadrant(rect: &Rect) -> bool {
    let (x, y) = (rect.x, rect.y);
    !((x.0 < 0.0 && x.1 > 0.0) || (y.0 < 0.0 && y.1 > 0.0))
}

/// The world footprint of a cell: its diagonal times its distortion bound.
fn cell_footprint(region: &BasicRegion, cell: &Cell) -> f64 {
    cell_distortion(region, cell) * cell.rect.diagonal()
}

/// A rectangle's distortion bound `high` (`None` where undefined), within the region's.
fn bounded_distortion(region: &BasicRegion, high: Option<f64>) -> f64 {
    match high {
        Some(high) if high.is_finite() && high >= 1.0 => high.min(region.max_distortion),
        _ => region.max_distortion,
    }
}

fn corner(rect: &Rect, k: usize) -> (f64, f64) {
    (
        if k & 1 == 0 { rect.x.0 } else { rect.x.1 },
        if k & 2 == 0 { rect.y.0 } else { rect.y.1 },
    )
}

/// Eq. 22 at the surface point over `(x, y)`; NaN (never classified) where there is none.
fn query(
    ctx: &RegionContext<'_>,
    region: &BasicRegion,
    x: f64,
    y: f64,
    stats: &mut SubdivisionStats,
) -> f64 {
    stats.distance_queries += 1;
    match region_point(ctx.frame, &region.heightfield, region.sheet, x, y) {
        Some(p) => ctx.distance.distance(p),
        None => f64::NAN,
    }
}

/// Covers a rectangle known to be on the CSG surface with rows of samples, a square grid or
/// staggered ([`FillGrid`]), so that every point of it lies within `r / δ` of a sample on the
/// sampling plane (`δ` the largest distortion over it), hence within `r` on the surface.
/// Returns `false` (nothing emitted) when the grid would be too large, so that the caller
/// splits first; emits nothing either when its samples would cross the run's sample limit
/// ([`Budget::admits`]), which stops the run.
///
/// The spacing follows the largest distortion over the rectangle; where the distortion varies
/// by more than [`FILL_SPREAD`] and the rectangle is at least [`FILL_SPLIT_CELLS`] cells across
/// the direction it varies in, the halves are filled each with its own bound instead (no
/// query is needed: the whole rectangle is on the surface). That saves about a quarter of the
/// samples on curved parts. `owned` says that all of the rectangle is known to belong to the
/// region ([`BasicRegion::owns`]).
///
/// `slopes` are the squared slopes at the corners of a rectangle inside one quadrant
/// ([`Cell`]), from which its distortion bounds and its halves' follow with four new slopes a
/// split ([`split_for_distortion_at_corners`]). Each half's bounds were computed anew three
/// times, from sixteen slopes, and a rectangle too narrow to split weighed both cuts all the
/// same: that took 8 % of the instructions of sampling a cube dimpled by 18 balls at 0.15 % of
/// the diagonal, 2 % now.
fn fill(
    ctx: &RegionContext<'_>,
    region: &BasicRegion,
    (rect, owned): (&Rect, bool),
    (distortion, slopes): (f64, Option<[f64; 4]>),
    out: &mut Emitted,
) -> bool {
    let spacing = std::f64::consts::SQRT_2 * ctx.radius / distortion;
    let Some(grid) = FillGrid::over(rect.width(), rect.height(), ctx.radius / distortion) else {
        return false;
    };
    // A cut spans at most the longer side: where that is too short to split, how the
    // distortion varies does not matter.
    let across_at_most = rect.width().max(rect.height());
    let bounds = || match slopes {
        Some(slopes) => corner_bounds(slopes),
        None => region.heightfield.distortion_bounds(rect.x, rect.y),
    };
    if across_at_most >= FILL_SPLIT_CELLS * spacing
        && let Some((low, high)) = bounds()
        && high > FILL_SPREAD * low
    {
        let heightfield = &region.heightfield;
        let halves = match slopes {
            Some(slopes) => split_for_distortion_at_corners(heightfield, rect, slopes)
                .map(|(half, slopes)| (half, corner_bounds(slopes), Some(slopes))),
            None => {
                split_for_distortion(heightfield, rect).map(|(half, bounds)| (half, bounds, None))
            }
        };
        let across = if halves[0].0.width() < rect.width() {
            rect.width()
        } else {
            rect.height()
        };
        if across >= FILL_SPLIT_CELLS * spacing {
            for (half, bounds, slopes) in halves {
                let distortion = bounded_distortion(region, bounds.map(|(_, high)| high));
                fill(ctx, region, (&half, owned), (distortion, slopes), out);
            }
            return true;
        }
    }
    // A large fill asks the budget before its samples grow the buffer: they might cross the
    // limit many times over (the run stops then, and none are emitted).
    let count = grid.samples();
    if count > CHARGE_EVERY && !ctx.budget.admits(count, region.quadric) {
        return true;
    }
    let radius = (distortion * grid.reach).min(ctx.radius);
    let clipped = !owned && !region.owns_all_of(rect);
    // What was emitted before the fill gets boxes of its own.
    out.box_new();
    // A shifted row ends on the rectangle's side: not past it by rounding (a few steps down
    // suffice but where `x` is far larger than the width, and there the side is inside the
    // heightfield's domain anyway, as a filled rectangle has a bounded distortion).
    let mut dx = grid.spacing;
    for _ in 0..4 {
        if !grid.staggered || rect.x.0 + f64::from(grid.columns) * dx <= rect.x.1 {
            break;
        }
        dx = dx.next_down();
    }
    for k in 0..grid.rows {
        let FillRow { y, offset, samples } = grid.row(k);
        let row = Row {
            rect,
            dx,
            offset,
            y: rect.y.0 + y,
            half_height: grid.half_height,
            radius,
        };
        if clipped {
            fill_span(ctx, region, &row, 0..samples, out);
        } else {
            row.emit(ctx, region, 0..samples, out);
        }
    }
    out.box_fill();
    true
}

/// One row of a fill ([`FillGrid`]) over `rect`: sample `i` lies at `x = rect.x.0 + (i +
/// offset)·dx` and `y`, of radius `radius`; every point of `rect` lies within `dx / 2` along `x`
/// and `half_height` along `y` of its nearest sample.
struct Row<'a> {
    rect: &'a Rect,
    dx: f64,
    offset: f64,
    y: f64,
    half_height: f64,
    radius: f64,
}

impl Row<'_> {
    /// The part of the fill's rectangle whose points may have one of samples `cells` nearest.
    fn span(&self, cells: &Range<u32>) -> Rect {
        let x = |i: f64| self.rect.x.0 + (i + self.offset) * self.dx;
        let (low, high) = (f64::from(cells.start) - 0.5, f64::from(cells.end) - 0.5);
        Rect {
            x: (x(low).max(self.rect.x.0), x(high).min(self.rect.x.1)),
            y: (
                (self.y - self.half_height).max(self.rect.y.0),
                (self.y + self.half_height).min(self.rect.y.1),
            ),
        }
    }

    /// Emits the samples of cells `cells`, in order, up to eight at a time ([`crate::lanes`];
    /// fewer where fewer are left, as unused lanes cost as much as used ones).
    fn emit(
        &self,
        ctx: &RegionContext<'_>,
        region: &BasicRegion,
        cells: Range<u32>,
        out: &mut Vec<Sample>,
    ) {
        let Some(line) = HeightfieldLine::new(ctx.frame, &region.heightfield, region.sheet, self.y)
        else {
            return;
        };
        let lanes = (&line, &SurfaceTest::new(ctx.quadric, ctx.snap));
        let mut start = cells.start;
        while start < cells.end {
            start = match cells.end - start {
                8.. => self.emit_lanes::<8>(ctx, region, lanes, start, out),
                4.. => self.emit_lanes::<4>(ctx, region, lanes, start, out),
                2.. => self.emit_lanes::<2>(ctx, region, lanes, start, out),
                _ => self.emit_lanes::<1>(ctx, region, lanes, start, out),
            };
        }
    }

    /// Emits the samples of cells `start..start + N`; returns the next cell.
    #[inline]
    fn emit_lanes<const N: usize>(
        &self,
        ctx: &RegionContext<'_>,
        region: &BasicRegion,
        (line, test): (&HeightfieldLine, &SurfaceTest),
        start: u32,
        out: &mut Vec<Sample>,
    ) -> u32 {
        let x = std::array::from_fn(|l| {
            self.rect.x.0 + (f64::from(start + l as u32) + self.offset) * self.dx
        });
        let (points, found) = line.points::<N>(&x);
        let (normals, done) = test.normals(&points);
        for l in (0..N).filter(|&l| found[l]) {
            let point = if done[l] {
                (points.at(l), normals.at(l))
            } else {
                // Rare: a Newton step, or a gradient too small or large to square.
                let mut point = (points.at(l), DVec3::ZERO);
                onto_quadric(ctx, &mut point, fallback_normal(ctx, region));
                point
            };
            out.push(surface_sample(region, point, self.radius));
        }
        start + N as u32
    }
}

/// Emits the samples of cells `cells` of a border region's row, in order, but for those where
/// another plane is the best throughout, which are that plane's ([`BasicRegion::owns`]). A span
/// of cells is decided whole where the plane is the best everywhere or nowhere over it, and
/// halved otherwise: a row costs a few tests near where the border crosses it instead of one
/// per cell. With the ownership a cell passes on to its parts ([`Cell::owned_by_none`]), this
/// cut the border tests from 9.5 % to 3.9 % of the instructions of sampling three balls at
/// 0.15 % of the diagonal.
fn fill_span(
    ctx: &RegionContext<'_>,
    region: &BasicRegion,
    row: &Row,
    cells: Range<u32>,
    out: &mut Vec<Sample>,
) {
    match region.owns(&row.span(&cells)) {
        Owned::None => {}
        Owned::Part if cells.len() > 1 => {
            let middle = cells.start + (cells.end - cells.start) / 2;
            fill_span(ctx, region, row, cells.start..middle, out);
            fill_span(ctx, region, row, middle..cells.end, out);
        }
        Owned::All | Owned::Part => row.emit(ctx, region, cells, out),
    }
}

/// Emits the sample over `(x, y)` with the quadric's outward normal there.
fn emit(
    ctx: &RegionContext<'_>,
    region: &BasicRegion,
    x: f64,
    y: f64,
    radius: f64,
    out: &mut Vec<Sample>,
) {
    if let Some(position) = region_point(ctx.frame, &region.heightfield, region.sheet, x, y) {
        let mut point = (position, DVec3::ZERO);
        onto_quadric(ctx, &mut point, fallback_normal(ctx, region));
        out.push(surface_sample(region, point, radius));
    }
}

/// A heightfield point (the first of the pair) moved onto the quadric where needed
/// ([`snap_to_surface`]), with the quadric's outward normal there (the second), or `fallback`
/// where the gradient vanishes ([`fallback_normal`]). The fills compute the same in lanes
/// ([`crate::lanes`]) and come here for the points that need more.
///
/// The point is written only where it moves: assigning the pair for every point took a dozen
/// moves through the stack per sample, 5 % of the instructions of sampling a lone ball. The
/// normal takes the gradient's squared length from the snap's test.
#[inline]
fn onto_quadric(ctx: &RegionContext<'_>, (position, normal): &mut (DVec3, DVec3), fallback: DVec3) {
    let q = ctx.quadric;
    let (gradient, length_squared) = match ctx.snap {
        Some(settled) => snap_to_surface(q, position, settled),
        None => {
            let gradient = q.gradient(*position);
            (gradient, gradient.length_squared())
        }
    };
    *normal = Quadric::normal_from_gradient_squared(gradient, length_squared).unwrap_or(fallback);
}

/// The normal of samples of `region` where the gradient vanishes: the sampling plane's axis on
/// the region's sheet.
fn fallback_normal(ctx: &RegionContext<'_>, region: &BasicRegion) -> DVec3 {
    ctx.frame.axes[region.heightfield.normal_axis] * region.sheet
}

/// The sample of `region` at a point of its quadric with its normal there.
#[inline]
fn surface_sample(region: &BasicRegion, (position, normal): (DVec3, DVec3), radius: f64) -> Sample {
    Sample {
        position,
        normal,
        quadric: region.quadric,
        term: region.term,
        radius,
        clip_list: 0,
    }
}

/// Most Newton steps that move a sample onto its quadric ([`snap_to_surface`]).
const SNAP_STEPS: usize = 2;

/// `position` moved onto the quadric by Newton steps along the gradient, each kept only while it
/// lowers `|Q| / ‖∇Q‖` (at most [`SNAP_STEPS`], none once it is at most `settled`). The heightfield
/// point can be off by more than the required `1e-9` of the scene where its square root cancels (a
/// slab of half-width `1e-6`); the move is of that size, far below any sample radius. Cones are
/// left alone: next to the apex, where the gradient vanishes, a step can cross the bounding literal
/// at the tip. Returns the gradient at the point it leaves, with its squared length.
///
/// Nearly every heightfield point is settled already; that test comes first, squared, without
/// the square root and division of the residual: those waited on the divider, busy with the
/// normal's, and took 4 % of sampling a lone ball.
#[inline]
fn snap_to_surface(q: &Quadric, position: &mut DVec3, settled: f64) -> (DVec3, f64) {
    let (value, gradient) = (q.value(*position), q.gradient(*position));
    let length_squared = gradient.length_squared();
    if value * value <= settled * settled * length_squared {
        return (gradient, length_squared);
    }
    let (moved, gradient) = newton_steps(q, *position, settled, (value, gradient));
    *position = moved;
    (gradient, gradient.length_squared())
}

/// The Newton steps of [`snap_to_surface`] from `p`, where `Q` and `∇Q` are `value` and
/// `gradient`; apart, so that the common case inlines into the loops that emit samples.
#[cold]
#[inline(never)]
fn newton_steps(
    q: &Quadric,
    mut p: DVec3,
    settled: f64,
    (mut value, mut gradient): (f64, DVec3),
) -> (DVec3, DVec3) {
    // `|Q| / ‖∇Q‖`, infinite where the gradient vanishes.
    let residual_of = |value: f64, g: DVec3| {
        let length = g.length();
        if length > 0.0 {
            value.abs() / length
        } else {
            f64::INFINITY
        }
    };
    let residual = |p: DVec3| {
        let (value, g) = (q.value(p), q.gradient(p));
        (residual_of(value, g), value, g)
    };
    let mut current = residual_of(value, gradient);
    for _ in 0..SNAP_STEPS {
        if current <= settled || !current.is_finite() {
            break;
        }
        let next = p - (value / gradient.length_squared()) * gradient;
        let (after, next_value, next_gradient) = residual(next);
        if !(next.is_finite() && after < current) {
            break;
        }
        (p, current, value, gradient) = (next, after, next_value, next_gradient);
    }
    (p, gradient)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

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

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(4096))]

        /// Where [`discs_cover`] says so, every point of a fine grid over the rectangle lies in
        /// a corner disc (a grid point of the rectangle's own outline included).
        #[test]
        fn corner_discs_cover_what_they_claim(
            (x0, y0) in (-10.0f64..10.0, -10.0f64..10.0),
            (w, h) in (0.01f64..5.0, 0.01f64..5.0),
            fractions in proptest::array::uniform4(0.3f64..1.1),
        ) {
            // Radii around the diagonal, where whether the discs cover is in question.
            let rect = Rect { x: (x0, x0 + w), y: (y0, y0 + h) };
            let radii = fractions.map(|f| f * rect.diagonal());
            if discs_cover((w, h), radii) {
                const STEPS: u32 = 40;
                for i in 0..=STEPS {
                    for j in 0..=STEPS {
                        let x = x0 + w * f64::from(i) / f64::from(STEPS);
                        let y = y0 + h * f64::from(j) / f64::from(STEPS);
                        let inside = (0..4).any(|k| {
                            let (cx, cy) = corner(&rect, k);
                            (x - cx).hypot(y - cy) <= radii[k] * (1.0 + 1e-12)
                        });
                        prop_assert!(inside, "({x}, {y}) in no disc of {radii:?} over {rect:?}");
                    }
                }
            }
        }

        /// The rule claims at least what the two it replaces did.
        #[test]
        fn corner_discs_cover_the_old_cases(
            (w, h) in (0.01f64..5.0, 0.01f64..5.0),
            radii in proptest::array::uniform4(0.0f64..8.0),
        ) {
            let rect = Rect { x: (0.0, w), y: (0.0, h) };
            let diagonal = rect.diagonal();
            let old = radii.iter().any(|&r| r >= diagonal)
                || radii.iter().all(|&r| r >= 0.5 * diagonal);
            prop_assert!(!old || discs_cover((w, h), radii));
        }
    }
}
