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
//!   looks at few (`tiles`); a rectangle of the subdivision [`subdivide::NARROW_RATIO`] times
//!   smaller than the box eq. 22 was kept to keeps it to its own patch again, and so does each
//!   rectangle the second pass refines (the cells of a line of text lie side by side, and the
//!   borders of their faces are split down to the cutoff). Setup, memory and a query cost what
//!   the nearby parts cost, not what the whole scene does;
//! - a basic region whose patch lies outside its term (a literal of the term fails on all of
//!   its box) or inside another term (every literal of it holds on all of the box) is left out
//!   before any query ([`csg_distance::NearDistance::nowhere_negative`]): eq. 22 is negative
//!   nowhere there, so the region would emit nothing (where parts sink into each other). One
//!   whose patch is all on the surface (inside every literal of its term, and its box missed
//!   by every other term, [`csg_distance::NearDistance::everywhere_on_surface`]) is sampled
//!   without a query, its corners taken as deep inside;
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
//!   where rounding left them farther off than `1e-9` of the diagonal; cones are left
//!   unrefined, because a step next to the apex can cross the literal that bounds the tip, and
//!   there samples may lie farther off than the `1e-9` asked for
//!   (`examples/quadric_primitives.qcsg`; measured in `docs/sampler-benchmarks.md`).
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
//!
//! The crate's modules: `run` is one run, from the regions of every patch (`patches`,
//! tiled by `tiles`) through the two passes (`first_pass_runs`, [`subdivide`]) to the
//! settling and the clip lists; its output is a [`Sampling`] (`sampling`) of [`Sample`]s
//! (`sample_point`, stored by [`samples`]), with [`SampleStats`] (`stats`), or a
//! [`SampleError`] (`error`); [`Progress`] reports its work (`progress`).

pub mod apex;
pub mod blocks;
pub mod budget;
pub mod clip;
pub mod csg_distance;
mod error;
mod fewest_samples;
mod fill_grid;
mod first_pass_runs;
mod in_order;
mod lanes;
mod memo;
mod patches;
mod progress;
mod region_cap;
pub mod regions;
mod run;
mod sample_point;
pub mod samples;
mod sampling;
mod small_patches;
mod stats;
pub mod subdivide;
pub mod threads;
mod tiles;

use qcsg_csg::Dnf;

pub use crate::budget::{DEFAULT_MAX_QUERIES, DEFAULT_MAX_SAMPLES, SampleLimits};
pub use crate::clip::ClipLists;
pub use crate::error::SampleError;
pub use crate::progress::{Progress, REFINE_WORK};
pub use crate::sample_point::Sample;
pub use crate::samples::Samples;
pub use crate::sampling::Sampling;
pub use crate::stats::SampleStats;

/// Samples the CSG surface of `dnf` with world radius `radius` on the current rayon pool.
pub fn sample(dnf: &Dnf, radius: f64) -> Result<Sampling, SampleError> {
    sample_with_progress(dnf, radius, &|_| {})
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
    let run = || {
        threads::with_workers_awake(|| run::sample_on_pool(dnf, radius, (limits, progress), memory))
    };
    if rayon::current_thread_index().is_none() {
        return rayon::scope(|_| run());
    }
    run()
}
