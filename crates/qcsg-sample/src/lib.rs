//! The adaptive sampler of paper 000 (Trettner & Kobbelt, "Sampling from Quadric-Based CSG
//! Surfaces", §4-5): points exactly on a CSG surface given in DNF, with the guarantee that every
//! point of the CSG surface has a sample on the same quadric within the radius `r`, and every
//! sample lies on the CSG surface.
//!
//! For every literal of every term ([`qcsg_csg::Dnf`]), the quadric's three sampling planes are
//! decomposed into basic regions of low distortion inside the term's box ([`regions`]); each basic
//! region is subdivided adaptively, driven by the quadric-relative CSG distance of eq. 22
//! ([`csg_distance`]) at its corners and the distortion bounds of §3.4 ([`subdivide`]). Regions
//! are sampled in parallel with rayon, in runs of blocks sized by their estimated work
//! ([`blocks`]), large rectangles split between threads ([`subdivide`], "Threads"), then the
//! small rectangles the first pass left unproven ([`subdivide`], "Two passes"); the output is
//! the concatenation in region order, then in deferred order, so it is byte-identical for any
//! thread count. It keeps the runs as the threads wrote them instead of copying them into one
//! vector ([`Samples`]). [`threads::pool_builder`] builds a pool whose threads keep to a core
//! each, which a virtual machine's scheduler otherwise stacks on one core.
//!
//! Decisions where the paper leaves room, each documented and tested in its module:
//! - basic regions are axis-aligned rectangles found by an exact refinement of eqs. 15-16 with
//!   the §3.4 distortion bound instead of the analytic split into triangles, elliptic and
//!   hyperbolic triangles ([`regions`]); a rectangle across the border between two planes'
//!   regions (distortion at most [`regions::KEEP_DISTORTION`]) keeps only its part where its
//!   plane is the best, so the regions still end at the paper's conics, to the resolution of
//!   the subdivision;
//! - eq. 22 leaves out terms sharing the sampled quadric and complementary literals, and uses
//!   the DNF's region, not the per-term boxes; it leaves out planes that only touch a sampled
//!   ellipsoid or cylinder, and on a sampled plane it takes each literal by its section with
//!   that plane ([`csg_distance`]);
//! - small regions get one sample at a corner or the centre proven on the surface, with the
//!   radius reduced to the region's footprint (at the centre, up to a footprint of `2r`), or
//!   none when a recent sample of the region reaches them with its radius grown to at most `r`;
//!   unproven ones wait for a second pass, where a nearby sample whose splat draws them (same
//!   side, same term or one holding them) covers them, or they are split down to
//!   [`subdivide::SMALL_REGION_FRACTION`] of the footprint; what is given up there and no
//!   sample reaches is probed a few levels further down within a budget
//!   ([`subdivide::probe_given_up`], `PROBE_QUERIES`), around one point down to a speck of
//!   the length tolerance (`SPECK`), and downhill along eq. 22 from the centre, which finds a
//!   band of surface too thin for any probe to land on; the parts left are settled against
//!   every sample ([`subdivide::settle_parts`]), and counted when still unsettled
//!   ([`subdivide::SubdivisionStats::unresolved`]);
//! - eq. 22 of each sampled literal keeps only the other terms near the part its regions hold,
//!   found in an R-tree of the terms' boxes, and, of a term of many literals, only those that
//!   may fail near it; eq. 22 of each basic region keeps only what comes near the region's
//!   patch ([`csg_distance::CsgDistance::near`]), and a region that still looks at many
//!   literals (a face of a plate drilled with thousands of holes) is tiled until each tile
//!   looks at few (`tiles`). Setup, memory and a query cost what the nearby parts cost, not
//!   what the whole scene does;
//! - a basic region whose patch lies outside its term (a literal of the term fails on all of
//!   its box) or inside another term (every literal of it holds on all of the box) is left out
//!   before any query ([`csg_distance::NearDistance::nowhere_negative`]): eq. 22 is negative
//!   nowhere there, so the region would emit nothing (a quarter of the regions of a cage of
//!   balls and rods, where their ends sink into each other, and a fifth of its queries). One
//!   whose patch is all on the surface (inside every literal of its term, and its box missed
//!   by every other term, [`csg_distance::NearDistance::everywhere_on_surface`]) is sampled
//!   without a query, its corners taken as deep inside (on a cube pitted by 28 balls at 1 %
//!   of the diagonal, 37 % fewer queries);
//! - faces shared by parts (coincident planes of different quadrics: boxes sharing a face, a
//!   difference flush with a face, a cylinder's cap on a box face) are resolved per sheet in
//!   eq. 22 ([`csg_distance`], "Shared planes"), so the shared face is sampled where it is part
//!   of the surface and discarded where it is not; a literal that another term shares with the
//!   sampled term is left out of the other term ("Literals of both terms"), so the border of a
//!   face inside a union of abutting parts is classified too; two other terms that meet along a
//!   plane also enter merged, so a quadric crossing or touching the plane between them inside
//!   both is classified ([`csg_distance`], "Abutting terms").
//!
//! Known limits, found by the program and random-scene tests (`tests/scenes.rs`), which check the
//! guarantee against ray-cast reference points on every example and stiff scene:
//! - where eq. 22 only touches zero without changing sign along a curve, no corner bound
//!   classifies the rectangles beside it: they are split down to the cutoff and counted as
//!   unresolved. Planes touching ellipsoids and cylinders, cylinders cut along their axes and
//!   parts whose rims meet on the plane between them are resolved in eq. 22 ([`csg_distance`],
//!   "Tangent planes", "Planar sections": the rounded boxes of `examples/customizer_box.qcsg`,
//!   the chess bishop's foot, a countersink's top `0.01` above a face), and so are surfaces a
//!   small gap apart when one is an offset of the other (nested balls, coaxial cylinders:
//!   "Offset surfaces") and curved surfaces that touch or nest with shared principal axes or on
//!   an ellipsoid (a ball and a cylinder of its radius, a ball inside another touching it, an
//!   ellipsoid touching the inside of another turned differently: "Touching surfaces"). This
//!   is left where curved surfaces cross at a grazing angle over an area (two ellipsoids `1e-9`
//!   apart, turned differently, each poking out of the other): nothing is lost there, but the
//!   cost can be high. Where a cut face between two such surfaces is a ring `1e-9` wide
//!   (`tests/stability/nested_spheres_shell.qcsg`), the given-up rectangles across it are
//!   settled by searching downhill along eq. 22 for a point of the ring;
//! - around a cone's apex, where no heightfield has bounded distortion, what the region
//!   decomposition and the subdivision give up is settled at the apex by a ring of samples
//!   ([`apex`]); a plane that meets the cone only at its apex is probed around that point
//!   down to a speck of the length tolerance, `1e-9` of the diagonal (`SPECK`), where the
//!   apex is a double point known only to rounding;
//! - positions come from the heightfields, moved onto the quadric by up to two Newton steps
//!   (which bring samples on a slab of half-width `1e-6` from `1.2e-7` of the diagonal off the
//!   quadric to within `1e-9`); cones are left unrefined, because a step next to the apex can
//!   cross the literal that bounds the tip, and there samples lie up to about `6e-8` of the
//!   diagonal off (`examples/quadric_primitives.qcsg`), above the `1e-9` asked for.
//!
//! A run is bounded ([`budget`]): past [`SampleLimits::max_samples`] samples or
//! [`SampleLimits::max_queries`] distance queries it stops with an error instead of running out
//! of memory or time, and the second pass refines each deferred rectangle only so far
//! ([`subdivide`], "Two passes"). A radius whose run would cross the sample limit many times
//! over is refused before anything is sampled, from a lower bound of the samples the regions
//! need (`fewest_samples`), and a large fill asks the budget before it emits.
//!
//! Every sample carries its clip list (§6): the other literals of its term that come within its
//! radius, deduplicated into one indirection buffer ([`clip`]).
//!
//! Quadrics without a surface area (empty, all-space, a point, a line) contribute no samples;
//! every other kind, degenerate ones included, is sampled through its heightfields. Terms whose
//! box is unbounded are skipped and counted ([`SampleStats::unbounded_terms`]): the DNF builder
//! requires a region for unbounded scenes.

pub mod apex;
pub mod blocks;
pub mod budget;
pub mod clip;
pub mod csg_distance;
mod fewest_samples;
mod fill_grid;
mod in_order;
mod lanes;
mod memo;
pub mod regions;
pub mod samples;
pub mod subdivide;
pub mod threads;

use qcsg_csg::{Aabb, Dnf};
use qcsg_quadric::{DVec3, PrincipalFrame, QuadricKind};
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, PoisonError};

use crate::budget::{Budget, Crossed};
pub use crate::budget::{DEFAULT_MAX_QUERIES, DEFAULT_MAX_SAMPLES, SampleLimits};
pub use crate::clip::ClipLists;
use crate::csg_distance::NearDistance;
use crate::csg_distance::{CsgDistance, Shapes};
use crate::fewest_samples::RegionView;
use crate::in_order::{InOrder, lock};
use crate::memo::QueryMemo;
use crate::regions::{BasicRegion, RegionStats, basic_regions, patch_bounds};
pub use crate::samples::Samples;
use crate::subdivide::{
    Deferred, Emitted, GivenUp, HalfBuffers, Probed, RegionContext, SampleBox, SampleIndex,
    SubdivisionStats, given_up_share, probe_given_up, refine_deferred, sample_region,
    settle_given_up, settle_parts,
};

/// One sample on the CSG surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// World position, on the quadric.
    pub position: DVec3,
    /// Outward unit normal of the quadric at the position.
    pub normal: DVec3,
    /// Index into [`Dnf::quadrics`].
    pub quadric: u32,
    /// Index into [`Dnf::terms`] of the term it was sampled for.
    pub term: u32,
    /// The radius it covers (at most the requested radius; smaller for small regions).
    pub radius: f64,
    /// Index of its clip list in [`Sampling::clip_lists`] (0: the empty list).
    pub clip_list: u32,
}

impl Sample {
    /// Whether the sample's normal is less than 90° from `normal`, the outward unit normal of
    /// a point of the same quadric (the two face the same way). Coverage asks for it besides
    /// the distance: a splat draws only the side of its quadric it lies on, so a sample on one
    /// face of a thin slab (or the far side of a small ball) must not cover the other.
    pub fn same_side(&self, normal: DVec3) -> bool {
        self.normal.dot(normal) > 0.0
    }
}

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

/// Errors of [`sample`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SampleError {
    /// The radius is not a positive finite number.
    InvalidRadius(f64),
    /// The run would emit more than [`SampleLimits::max_samples`] samples (counting the
    /// rectangles the first pass holds for the second).
    TooManySamples {
        /// The limit.
        limit: u64,
        /// The quadric (index into [`Dnf::quadrics`]) being sampled when it was crossed.
        quadric: u32,
    },
    /// The run would make more than [`SampleLimits::max_queries`] distance queries.
    TooManyQueries {
        /// The limit.
        limit: u64,
        /// The quadric (index into [`Dnf::quadrics`]) being sampled when it was crossed.
        quadric: u32,
    },
}

impl std::fmt::Display for SampleError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::InvalidRadius(r) => {
                write!(f, "the sample radius must be positive and finite, got {r}")
            }
            Self::TooManySamples { limit, .. } => write!(
                f,
                "sampling at this radius needs more than {limit} samples (counting rectangles \
                 held for the second pass)"
            ),
            Self::TooManyQueries { limit, .. } => write!(
                f,
                "sampling at this radius needs more than {limit} distance queries (surfaces \
                 that nearly coincide defeat the subdivision's proofs)"
            ),
        }
    }
}

impl std::error::Error for SampleError {}

/// The samples and counters of one run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Sampling {
    /// The samples, in region order.
    pub samples: Samples,
    /// The deduplicated clip lists the samples point into.
    pub clip_lists: ClipLists,
    /// The counters.
    pub stats: SampleStats,
    /// The run's working buffers but the samples', emptied, kept for [`resample`]: the boxes
    /// and deferred rectangles of the first pass's runs and of the whole, and those of halves
    /// of large cells. Freed with the rest.
    spare: SpareBuffers,
}

impl Sampling {
    /// Bytes of memory it keeps beyond its output for the next run ([`resample`]): the
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

/// Empty buffers with their memory, for the next run ([`resample`]), which then writes to
/// memory that is mapped already instead of growing new buffers (one thread, 0.15 % of the
/// diagonal: three balls 20.1 -> 19.2 ms, a hollowed cube 75.5 -> 73.7 ms). They are not part
/// of the output: copies and comparisons leave them out. The samples' own buffers are the
/// output's runs ([`Samples`]).
#[derive(Default)]
struct SpareBuffers {
    /// The boxes and deferred rectangles of the first pass's runs by run number (their samples
    /// went to the output); run 0's are those of the whole, which it handed on.
    runs: Vec<FirstPass>,
    /// The buffers of halves of large cells that another thread took.
    halves: Vec<HalfBuffers>,
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

/// One literal of one term, ready to be sampled.
struct Patch {
    frame: PrincipalFrame,
    distance: CsgDistance,
    quadric: u32,
    term: u32,
    kind: QuadricKind,
    /// A box around the quadric's part in all its regions.
    bounds: Aabb,
    /// The rectangles the region decomposition gave up, and how far from the frame's centre
    /// the surface over them reaches ([`basic_regions`]).
    given_up: (u64, f64),
}

/// Distance queries that probing given-up rectangles ([`probe_given_up`]) may make, on top of
/// a sixteenth of the run's queries before it; once they are spent, the rest are counted
/// unresolved. Ordinary scenes leave a handful of such rectangles, which probing mostly
/// settles; tangent and nearly coincident surfaces leave up to millions, most of which it
/// cannot settle, and this bounds what it adds to the run. Following parts down to a speck
/// takes about 75 queries a rectangle: `recursive_tree` at 10 % of the diagonal probes about
/// 26,000 (a quarter of this was too little there).
const PROBE_QUERIES: u64 = 65_536;

/// Fraction of the DNF's diagonal within which a sample counts as on its quadric without
/// Newton steps.
const SNAP_SETTLED: f64 = 1e-12;

/// Fraction of the DNF's diagonal below which a part of a rectangle on the surface is a speck
/// ([`RegionContext::speck`]): the length tolerance of the scene, below which eq. 22 takes a
/// point to lie on a plane.
const SPECK: f64 = 1e-9;

/// A basic region with the index of its patch and a box around the patch's part in it.
type PlacedRegion = (usize, BasicRegion, Aabb);

/// The box a term's surface is sampled in: its box within the DNF's region.
fn term_box(dnf: &Dnf, term: usize) -> Option<Aabb> {
    let bounds = dnf.terms.get(term)?.bounds;
    Some(match dnf.region {
        Some(region) => bounds.intersection(&region),
        None => bounds,
    })
}

/// Every basic region of every literal of every term, in a fixed order (term, literal, plane,
/// sheet, rectangle), with the patch each belongs to. Literals are decomposed in parallel (a
/// scene of many parts has thousands of them), and so are each literal's sampling planes.
fn all_regions(dnf: &Dnf, stats: &mut SampleStats) -> (Vec<Patch>, Vec<PlacedRegion>) {
    let mut literals = Vec::new();
    for (term_index, term) in dnf.terms.iter().enumerate() {
        let Some(bounds) = term_box(dnf, term_index) else {
            continue;
        };
        if bounds.is_empty() {
            continue;
        }
        if !bounds.is_bounded() {
            stats.unbounded_terms += 1;
            continue;
        }
        literals.extend(
            term.literals
                .iter()
                .map(|&l| (term_index as u32, l, bounds)),
        );
    }
    let shapes = Shapes::new(dnf);
    // Each literal's patch, its regions (by sampling plane) with a box around each one's part,
    // and counters.
    type Decomposed = (Patch, Vec<Vec<(BasicRegion, Aabb)>>, RegionStats);
    let decomposed: Vec<Option<Decomposed>> = literals
        .par_iter()
        .map(|&(term, literal, bounds)| {
            let entry = dnf.quadrics.get(literal as usize)?;
            let kind = entry.quadric.kind();
            if kind.has_no_surface() || matches!(kind, QuadricKind::Point | QuadricKind::Line) {
                return None;
            }
            let frame = entry.quadric.frame();
            // The three sampling planes each on its own: a scene of a few quadrics has too few
            // literals to share out (three balls at 1 % of the diagonal on two threads: this
            // step took 0.21-0.26 ms instead of 0.27-0.37 ms, of about 2 ms).
            let planes: Vec<_> = (frame.heightfields().into_par_iter())
                .map(|heightfield| {
                    let (mut found, mut counters) = (Vec::new(), RegionStats::default());
                    let key = (literal, term);
                    let reach = basic_regions(
                        &frame,
                        &heightfield,
                        &bounds,
                        key,
                        &mut found,
                        &mut counters,
                    );
                    let found: Vec<(BasicRegion, Aabb)> = (found.into_iter())
                        .map(|region| {
                            let bounds = patch_bounds(&frame, &region);
                            (region, bounds.unwrap_or(Aabb::EVERYTHING))
                        })
                        .collect();
                    (found, counters, reach)
                })
                .collect();
            let mut found = Vec::new();
            let mut counters = RegionStats::default();
            let mut reach = 0.0f64;
            for (regions, more, given_up) in planes {
                found.push(regions);
                counters.add(&more);
                reach = reach.max(given_up);
            }
            // Eq. 22 for the part of the quadric its regions hold.
            let bounds =
                (found.iter().flatten()).fold(Aabb::EMPTY, |all, (_, bounds)| all.union(bounds));
            let distance = CsgDistance::with_shapes(dnf, &shapes, (literal, term), &bounds)?;
            let patch = Patch {
                frame,
                distance,
                quadric: literal,
                term,
                kind,
                bounds,
                given_up: (counters.unresolved, reach),
            };
            Some((patch, found, counters))
        })
        .collect();
    let mut patches = Vec::new();
    let mut regions = Vec::new();
    for (patch, found, counters) in decomposed.into_iter().flatten() {
        let found = found.into_iter().flatten();
        regions.extend(found.map(|(r, b)| (patches.len(), r, b)));
        patches.push(patch);
        stats.regions.add(&counters);
    }
    (patches, regions)
}

/// The margin eq. 22 keeps around a patch's box `bounds` ([`CsgDistance::near`]): its diagonal
/// plus the radius, so that the terms left out are farther than any rectangle of the patch.
fn near_margin(bounds: &Aabb, radius: f64) -> f64 {
    (bounds.max - bounds.min).length() + radius
}

/// Regions whose eq. 22 looks at more literals of terms of many than this are tiled until each
/// tile's patch sees fewer ([`NearDistance::literals_of_large_terms`]): a plate drilled with
/// thousands of holes is one term, and each hole's neighbourhood needs only the holes near it.
const TILE_LITERALS: usize = 32;

/// Halvings of a tile tried at once ([`tiles`]).
const TILE_TRIAL_DEPTH: u32 = 3;

/// Most tiles of one region: a bound on what tiling adds, whatever the scene.
const MAX_TILES: usize = 4096;

/// `region` (with eq. 22 kept to its neighbourhood, `near`) as tiles, each with eq. 22 narrowed
/// to its own ([`NearDistance::narrow`]), while a tile looks at more than [`TILE_LITERALS`]
/// literals of terms of many and is larger than the radius. A tile is halved
/// [`TILE_TRIAL_DEPTH`] times at once (the margin shrinks with the tile, so counts fall only
/// after a few halvings), and the halves are kept only if they look at a quarter fewer
/// literals on average: elsewhere (a polyhedron's faces, all near each other) the tile stays
/// whole. A region makes at most [`MAX_TILES`] tiles. A tile keeps the region's distortion
/// bound and border flag, which hold on any part of it. In order, low half first.
fn tiles<'a>(
    patches: &[Patch],
    (patch_index, region, bounds): PlacedRegion,
    near: NearDistance<'a>,
    radius: f64,
) -> Vec<(PlacedRegion, Option<NearDistance<'a>>)> {
    let Some(patch) = patches.get(patch_index) else {
        return vec![((patch_index, region, bounds), Some(near))];
    };
    let halve = |(region, _, near): &(BasicRegion, Aabb, NearDistance<'a>)| {
        let (low, high, _) = region.rect.split_longest();
        [low, high].map(|rect| {
            let half = BasicRegion { rect, ..*region };
            let bounds = patch_bounds(&patch.frame, &half).unwrap_or(Aabb::EVERYTHING);
            let narrowed = near.narrow(&bounds, near_margin(&bounds, radius));
            (half, bounds, narrowed)
        })
    };
    let mut out = Vec::new();
    let mut stack = vec![(region, bounds, near)];
    while let Some(tile) = stack.pop() {
        let literals = tile.2.literals_of_large_terms();
        let size = (tile.1.max - tile.1.min).length();
        let room = out.len() + stack.len() + (1 << TILE_TRIAL_DEPTH) <= MAX_TILES;
        if literals > TILE_LITERALS && size > radius && room {
            let mut halves = halve(&tile).to_vec();
            for _ in 1..TILE_TRIAL_DEPTH {
                halves = halves.iter().flat_map(halve).collect();
            }
            let after: usize = halves
                .iter()
                .map(|(_, _, near)| near.literals_of_large_terms())
                .sum();
            if 4 * after <= 3 * literals * halves.len() {
                stack.extend(halves.into_iter().rev());
                continue;
            }
        }
        let (region, bounds, near) = tile;
        out.push(((patch_index, region, bounds), Some(near)));
    }
    out
}

/// Settles at their cone's apex ([`apex`]) the rectangles given up on each patch, `at_apex`
/// holding how many and how far from the apex they reach: ring samples join `samples`, and
/// the counts move from the unresolved to the covered or discarded ones. What is not on a
/// cone, or not settled, stays unresolved.
fn settle_apices(
    dnf: &Dnf,
    (patches, at_apex): (&[Patch], &[(u64, f64)]),
    radius: f64,
    samples: &mut Samples,
    stats: &mut SampleStats,
) {
    for (patch, &(count, reach)) in patches.iter().zip(at_apex) {
        let from_regions = patch.given_up.0;
        if patch.kind != QuadricKind::Cone {
            stats.subdivision.unresolved += count - from_regions;
            continue;
        }
        if count == 0 {
            continue;
        }
        let literals = &dnf.terms[patch.term as usize].literals;
        let others: Vec<qcsg_quadric::Quadric> = (literals.iter())
            .filter(|&&l| l != patch.quadric)
            .filter_map(|&l| Some(dnf.quadrics.get(l as usize)?.quadric))
            .collect();
        let cone = &dnf.quadrics[patch.quadric as usize].quadric;
        let literal = (patch.quadric, patch.term);
        let eq22 = (&patch.distance, &others[..]);
        let counter = match apex::settle(literal, (cone, &patch.frame), eq22, reach, radius) {
            apex::Settled::Off => &mut stats.subdivision.discarded,
            apex::Settled::Covered(ring) => {
                samples.push_run(ring);
                &mut stats.subdivision.unresolved_covered
            }
            apex::Settled::Unresolved => {
                stats.subdivision.unresolved += count - from_regions;
                continue;
            }
        };
        *counter += count;
        stats.regions.unresolved -= from_regions;
    }
}

/// Samples the CSG surface of `dnf` with world radius `radius` on the current rayon pool.
pub fn sample(dnf: &Dnf, radius: f64) -> Result<Sampling, SampleError> {
    sample_with_progress(dnf, radius, &|_| {})
}

/// Progress of a sampling run, reported from the worker threads. Its work is counted in units
/// of about one sample's: a basic region weighs its estimated samples
/// ([`blocks::region_cost`]), a rectangle the second pass refines [`REFINE_WORK`]. A progress
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

/// The work of refining one rectangle ([`Progress`]): on the benchmark scenes the second pass
/// took 1.5 to 4 µs a rectangle, as long as the first pass took for 14 to 61 units.
pub const REFINE_WORK: u64 = 32;

/// The fewest and the most consecutive items of `count` that one thread folds into one output.
/// Rayon splits an indexed range only a few times and does not split a run a thread is working
/// through, so without a cap one thread could be left with a quarter of the regions while the
/// others idle: about eight runs per thread keep them busy. One thread takes them all as one run
/// (nothing to balance, nothing to concatenate).
fn fold_runs(count: usize) -> (usize, usize) {
    match rayon::current_num_threads() {
        0 | 1 => (usize::MAX, usize::MAX),
        threads => (1, count.div_ceil(8 * threads).max(1)),
    }
}

/// The first pass's output of a run of regions.
type FirstPass = (Emitted, Vec<Deferred>, SubdivisionStats);

/// The first pass's output of all runs, in run order: each run's samples as the run wrote them
/// ([`Samples`]), the boxes around them, the deferred rectangles and the counters.
#[derive(Default)]
struct FirstPassOutput {
    samples: Samples,
    boxes: Vec<SampleBox>,
    deferred: Vec<Deferred>,
    counters: SubdivisionStats,
}

impl FirstPassOutput {
    /// Moves a run's output to the end, its samples without copying them, leaving it empty.
    fn append(&mut self, (out, deferred, counters): &mut FirstPass) {
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
struct FirstPassRuns {
    runs: InOrder<(usize, FirstPass), FirstPassOutput>,
    /// Buffers by run number, taken by the run and given back once it is appended (its samples
    /// go on in the output).
    buffers: Mutex<Vec<FirstPass>>,
}

impl FirstPassRuns {
    /// Buffers for run `run`.
    fn buffer(&self, run: usize) -> FirstPass {
        lock(&self.buffers)
            .get_mut(run)
            .map(std::mem::take)
            .unwrap_or_default()
    }

    /// Hands in run `run`'s output.
    fn finish(&self, run: usize, output: FirstPass) {
        self.runs
            .finish(run, (run, output), |all, (run, mut output)| {
                all.append(&mut output);
                give_back(&mut lock(&self.buffers), run, output);
            });
    }

    /// The whole output, once every run is in, and the runs' buffers by run number.
    fn into_output(self) -> (FirstPassOutput, Vec<FirstPass>) {
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
fn give_back(buffers: &mut Vec<FirstPass>, run: usize, output: FirstPass) {
    if buffers.len() <= run {
        buffers.resize_with(run + 1, FirstPass::default);
    }
    buffers[run] = output;
}

/// [`sample`], calling `progress` when the work is known and as it gets done (from any thread;
/// the output does not depend on it).
pub fn sample_with_progress(
    dnf: &Dnf,
    radius: f64,
    progress: &(dyn Fn(Progress) + Sync),
) -> Result<Sampling, SampleError> {
    sample_with_limits(dnf, radius, SampleLimits::default(), progress)
}

/// [`sample_with_progress`] under `limits` instead of the defaults.
pub fn sample_with_limits(
    dnf: &Dnf,
    radius: f64,
    limits: SampleLimits,
    progress: &(dyn Fn(Progress) + Sync),
) -> Result<Sampling, SampleError> {
    resample_with_limits(dnf, radius, (limits, progress), Sampling::default())
}

/// [`sample`] into the memory of an earlier run's output `previous`, which it consumes; the
/// output is the same as [`sample`]'s. A program that samples again and again (a preview that
/// follows every edit, a benchmark) writes its samples to memory that is mapped already: the
/// operating system maps a fresh page at its first touch, and a run at 0.15 % of the diagonal
/// writes tens of megabytes of samples. On more threads than one, the buffers the other runs
/// of regions wrote to are reused too.
pub fn resample(dnf: &Dnf, radius: f64, previous: Sampling) -> Result<Sampling, SampleError> {
    let quiet: &(dyn Fn(Progress) + Sync) = &|_| {};
    resample_with_limits(dnf, radius, (SampleLimits::default(), quiet), previous)
}

/// [`resample`] under `limits`, calling `progress` as [`sample_with_progress`] does.
pub fn resample_with_limits(
    dnf: &Dnf,
    radius: f64,
    (limits, progress): (SampleLimits, &(dyn Fn(Progress) + Sync)),
    previous: Sampling,
) -> Result<Sampling, SampleError> {
    if !(radius.is_finite() && radius > 0.0) {
        return Err(SampleError::InvalidRadius(radius));
    }
    let mut memory = previous.samples.into_runs();
    memory.iter_mut().for_each(Vec::clear);
    let memory = (memory, previous.spare);
    // Called from outside the pool, every parallel step below would hand its work to the pool
    // and wait for it: a wake-up of a sleeping thread each, tens of microseconds on a virtual
    // machine. Moving the whole run onto a pool thread costs one.
    let run =
        || threads::with_workers_awake(|| sample_on_pool(dnf, radius, (limits, progress), memory));
    if rayon::current_thread_index().is_none() {
        return rayon::scope(|_| run());
    }
    run()
}

/// [`resample_with_limits`] on a thread of the current pool, the first pass's run `k` writing
/// to `memory[k]`.
fn sample_on_pool(
    dnf: &Dnf,
    radius: f64,
    (limits, progress): (SampleLimits, &(dyn Fn(Progress) + Sync)),
    (memory, spare): (Vec<Vec<Sample>>, SpareBuffers),
) -> Result<Sampling, SampleError> {
    let budget = Budget::new(limits);
    let crossed = |budget: &Budget| match budget.crossed() {
        Some(Crossed::Samples { quadric }) => Err(SampleError::TooManySamples {
            limit: limits.max_samples,
            quadric,
        }),
        Some(Crossed::Queries { quadric }) => Err(SampleError::TooManyQueries {
            limit: limits.max_queries,
            quadric,
        }),
        None => Ok(()),
    };
    let mut stats = SampleStats::default();
    let (patches, regions) = all_regions(dnf, &mut stats);
    // Eq. 22 of each region keeps the terms and literals near the region's patch, narrowed
    // from its whole patch's; regions where that is still many literals are tiled.
    let wholes: Vec<NearDistance<'_>> = patches
        .par_iter()
        .map(|patch| {
            patch
                .distance
                .near(&patch.bounds, near_margin(&patch.bounds, radius))
        })
        .collect();
    // A region where eq. 22 is nowhere negative would emit nothing: it gets none, and is left
    // out.
    let near: Vec<Option<NearDistance<'_>>> = regions
        .par_iter()
        .map(|(patch, _, bounds)| {
            let near = wholes
                .get(*patch)?
                .narrow(bounds, near_margin(bounds, radius));
            (!near.nowhere_negative(bounds)).then_some(near)
        })
        .collect();
    drop(wholes);
    let heavy = |near: &NearDistance<'_>| near.literals_of_large_terms() > TILE_LITERALS;
    let (regions, near): (Vec<PlacedRegion>, Vec<_>) = if near.iter().flatten().any(heavy) {
        regions
            .into_par_iter()
            .zip(near)
            .flat_map_iter(|(region, near)| match near {
                Some(near) if heavy(&near) => tiles(&patches, region, near, radius),
                near => vec![(region, near)],
            })
            .unzip()
    } else {
        (regions, near)
    };
    stats.basic_regions = near.iter().flatten().count() as u64;
    // Regions all of whose patch is on the surface: their corners need no query.
    let on_surface: Vec<bool> = (regions.par_iter().zip(&near))
        .map(|((_, _, bounds), near)| {
            near.as_ref()
                .is_some_and(|n| n.everywhere_on_surface(bounds))
        })
        .collect();
    // Heightfield points this close to their quadric are not refined (the guarantee asks for
    // 1e-9 of the diagonal; Newton steps are for cancellation far above this).
    let spare_halves = Mutex::new(spare.halves);
    let settled = SNAP_SETTLED * (dnf.bounds.max - dnf.bounds.min).length();
    let speck = SPECK * (dnf.bounds.max - dnf.bounds.min).length();
    let context = |index: usize| {
        let (patch, region, _) = regions.get(index)?;
        let patch = patches.get(*patch)?;
        let entry = dnf.quadrics.get(region.quadric as usize)?;
        (patch.quadric == region.quadric).then_some(RegionContext {
            frame: &patch.frame,
            quadric: &entry.quadric,
            distance: near.get(index)?.as_ref()?,
            on_surface: on_surface[index],
            radius,
            snap: (patch.kind != QuadricKind::Cone).then_some(settled),
            speck,
            budget: &budget,
            spare_halves: &spare_halves,
        })
    };
    // First pass: every region on its own. Threads take runs of whole blocks in order
    // ([`blocks`], sized by the regions' estimated work), and each run's output is appended to
    // the whole as soon as its predecessors' are ([`FirstPassRuns`]): the output is the same for
    // any thread count, and no thread copies samples.
    let costs: Vec<f64> = (regions.iter().zip(&near))
        .map(|((_, region, _), near)| {
            near.as_ref()
                .map_or(0.0, |_| blocks::region_cost(region, radius))
        })
        .collect();
    // Costs are finite (`region_cost`); the conversion saturates.
    let work = |region: usize| costs[region].round() as u64;
    let total = (0..costs.len()).fold(0u64, |sum, region| sum.saturating_add(work(region)));
    // A radius far below the scene's size is refused before anything is sampled
    // ([`fewest_samples`]); the bound is sought only where the estimate exceeds the limit.
    if total > limits.max_samples {
        let views: Vec<RegionView<'_>> = (0..regions.len())
            .filter_map(|i| Some(RegionView::new(regions[i].0, &regions[i].1, &context(i)?)))
            .collect();
        let diagonal = (dnf.bounds.max - dnf.bounds.min).length();
        let limit = limits.max_samples;
        if let Some(quadric) = fewest_samples::first_crossing(&views, radius, diagonal, limit) {
            return Err(SampleError::TooManySamples { limit, quadric });
        }
    }
    progress(Progress::Regions {
        count: stats.basic_regions,
        work: total,
    });
    let blocks = blocks::blocks(&costs);
    let runs = blocks::runs(&blocks, &costs, rayon::current_num_threads());
    // Run `k` writes its samples to an earlier sampling's run `k` (the samples of runs past
    // the first pass's are freed).
    let mut buffers = spare.runs;
    buffers.resize_with(runs.len(), FirstPass::default);
    for (buffer, memory) in buffers.iter_mut().zip(memory) {
        buffer.0.samples = memory;
    }
    let first_pass = FirstPassRuns {
        runs: InOrder::new(FirstPassOutput::default()),
        buffers: Mutex::new(buffers),
    };
    let next_run = AtomicUsize::new(0);
    (0..rayon::current_num_threads())
        .into_par_iter()
        .for_each(|_| {
            let mut memo = QueryMemo::default();
            loop {
                let run = next_run.fetch_add(1, Ordering::Relaxed);
                let Some(run_blocks) = runs.get(run) else {
                    break;
                };
                let (mut out, mut deferred, mut counters) = first_pass.buffer(run);
                for block in &blocks[run_blocks.clone()] {
                    let block_start = out.len();
                    for index in block.clone() {
                        if let Some(ctx) = context(index) {
                            let region = (index, &regions[index].1);
                            let walk = (&mut memo, &mut counters);
                            let out = (&mut out, block_start);
                            sample_region(&ctx, region, out, &mut deferred, walk);
                            progress(Progress::RegionDone { work: work(index) });
                        }
                    }
                }
                // A run past a limit ends in an error: its output is not copied on.
                if budget.stopped() {
                    out.clear();
                    deferred.clear();
                }
                first_pass.finish(run, (out, deferred, counters));
            }
        });
    let (first, mut spare_runs) = first_pass.into_output();
    let FirstPassOutput {
        mut samples,
        boxes,
        deferred,
        counters,
    } = first;
    stats.subdivision.add(&counters);
    crossed(&budget)?;
    let count = deferred.len() as u64;
    progress(Progress::Refining {
        count,
        work: count.saturating_mul(REFINE_WORK),
    });
    // Second pass: the rectangles the first left unproven, against all first-pass samples.
    let centres: Vec<(u32, DVec3)> = deferred
        .par_iter()
        .filter_map(|d| {
            let ctx = context(d.region)?;
            let region = &regions[d.region].1;
            Some((region.quadric, d.centre_point(&ctx, region)?))
        })
        .collect();
    let index = SampleIndex::new(dnf, (&samples, &boxes), &centres, radius);
    let share = given_up_share(deferred.len());
    type SecondPass = (
        Emitted,
        Vec<GivenUp>,
        Vec<(u32, f64)>,
        (QueryMemo, SubdivisionStats),
    );
    let (shortest, longest) = fold_runs(deferred.len());
    let refined: Vec<SecondPass> = deferred
        .par_iter()
        .with_min_len(shortest)
        .with_max_len(longest)
        .fold(
            SecondPass::default,
            |(mut out, mut given_up, mut grown, (mut memo, mut counters)), d| {
                if let Some(ctx) = context(d.region) {
                    let (region, index) = (&regions[d.region].1, &index);
                    let outputs = (&mut out, &mut given_up, &mut grown);
                    let walk = (&mut memo, &mut counters);
                    refine_deferred(&ctx, region, d, index, outputs, share, walk);
                }
                progress(Progress::RectangleRefined { work: REFINE_WORK });
                (out, given_up, grown, (memo, counters))
            },
        )
        .collect();
    drop(index);
    // Each part's samples are appended as they are, after the first pass's.
    let mut given_up = Vec::new();
    for (out, more_given_up, grown, (_, counters)) in refined {
        for (i, needed) in grown {
            samples.grow_radius(i, needed);
        }
        samples.push_run(out.samples);
        given_up.extend(more_given_up);
        stats.subdivision.add(&counters);
    }
    crossed(&budget)?;
    // Last: what the second pass gave up, against every sample.
    let uncovered = settle_given_up(
        dnf,
        &given_up,
        (&mut samples, &boxes),
        radius,
        &mut stats.subdivision,
    );
    // Probes write their samples to a run of their own, appended after them all.
    let mut probe_samples = Vec::new();
    let mut allowance = PROBE_QUERIES + stats.subdivision.distance_queries / 16;
    // What stays unresolved is settled at its cone's apex if it lies there: per patch, the
    // rectangles and how far from the frame's centre (a cone's apex) they reach.
    let mut at_apex: Vec<(u64, f64)> = patches.iter().map(|p| p.given_up).collect();
    let mut unsettled: Vec<(&GivenUp, Vec<GivenUp>)> = Vec::new();
    for leaf in &uncovered {
        let before = stats.subdivision.distance_queries;
        let probed = match context(leaf.region) {
            Some(ctx) if allowance > 0 => {
                let (region, out) = (&regions[leaf.region].1, (&mut probe_samples, 0));
                probe_given_up(&ctx, region, leaf, out, &mut stats.subdivision)
            }
            _ => Probed::Unresolved(Vec::new()),
        };
        allowance = allowance.saturating_sub(stats.subdivision.distance_queries - before);
        match probed {
            Probed::Covered => stats.subdivision.unresolved_covered += leaf.count,
            Probed::Off => stats.subdivision.discarded += leaf.count,
            Probed::Unresolved(parts) => unsettled.push((leaf, parts)),
        }
    }
    samples.push_run(probe_samples);
    // What probing left of each, against every sample; what stays unresolved is settled at its
    // cone's apex if it lies there.
    let parts: Vec<Vec<GivenUp>> = unsettled
        .iter_mut()
        .map(|(_, p)| std::mem::take(p))
        .collect();
    let covered = settle_parts(dnf, &parts, (&mut samples, &boxes), radius);
    for ((leaf, _), covered) in unsettled.into_iter().zip(covered) {
        let patch = regions.get(leaf.region).map(|(patch, _, _)| *patch);
        match (covered, patch) {
            (true, _) => stats.subdivision.unresolved_covered += leaf.count,
            (false, Some(p)) => {
                let reach = (leaf.point.position - patches[p].frame.centre).length() + leaf.extent;
                let (count, far) = &mut at_apex[p];
                (*count, *far) = (*count + leaf.count, far.max(reach));
            }
            (false, None) => stats.subdivision.unresolved += leaf.count,
        }
    }
    settle_apices(dnf, (&patches, &at_apex), radius, &mut samples, &mut stats);
    let clip_lists = clip::assign(dnf, &mut samples, &boxes, radius);
    // Run 0 handed its buffers on to the whole (appended first), which hands them back.
    if let Some((out, run_deferred, _)) = spare_runs.first_mut() {
        (out.boxes, *run_deferred) = (boxes, deferred);
        out.clear();
        run_deferred.clear();
    }
    let spare = SpareBuffers {
        runs: spare_runs,
        halves: spare_halves
            .into_inner()
            .unwrap_or_else(PoisonError::into_inner),
    };
    stats.samples = samples.len() as u64;
    stats.clip_lists = clip_lists.len() as u64;
    stats.clip_indices = clip_lists.indices.len() as u64;
    Ok(Sampling {
        samples,
        clip_lists,
        stats,
        spare,
    })
}
