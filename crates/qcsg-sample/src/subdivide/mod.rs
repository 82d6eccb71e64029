//! Adaptive longest-edge subdivision of one basic region (paper §4.2).
//!
//! At the corners of a rectangle the CSG distance `d` of eq. 22 is evaluated. A world radius `|d|`
//! becomes the 2-D radius `|d| / δ_max`, `δ_max` being the rectangle's maximum distortion (§3.4
//! corner bound): the heightfield map is `δ_max`-Lipschitz on the convex rectangle, so 2-D points
//! within `|d| / δ_max` of a corner map to surface points within `|d|` of it in space. The corner
//! discs cover the rectangle when each of its quarters lies in one of them (`classify`); then
//! the rectangle is wholly on the CSG surface (all `d < 0`: filled with a grid of samples,
//! `fill`) or wholly off it (all `d > 0`: dropped). Otherwise it is split at its longer edge.
//! An edge's midpoint is a corner of the cells on both sides of it: eq. 22 at a point a walk of
//! the subdivision met lately comes from a small memo (`crate::memo`).
//!
//! The modules, in the order a rectangle meets them:
//! - `cell`: a rectangle with its corner values, its distortion and footprint;
//! - `classify`: what the corner discs, a small rectangle's one sample or its centre settle;
//! - `first_pass`: the walk over each basic region, large cells shared between threads;
//! - `fill` and `emit`: rows of samples over a rectangle proven on the surface, each moved
//!   onto its quadric;
//! - `emitted`: the samples as emitted, with boxes around runs of them;
//! - `second_pass`: the small rectangles the first pass left unproven, against all samples;
//! - `sample_index`: the first pass's samples near those rectangles, found by cube;
//! - `cover`: when a sample's splat covers a rectangle;
//! - `given_up` and `probe`: what the second pass gives up, settled against every sample or
//!   probed further down.

mod cell;
mod classify;
mod cover;
mod emit;
mod emitted;
mod fill;
mod first_pass;
mod given_up;
mod probe;
mod sample_index;
mod second_pass;

use std::sync::Mutex;

use qcsg_quadric::{DVec3, PrincipalFrame, Quadric};

use crate::budget::Budget;
use crate::csg_distance::NearDistance;
use crate::memo::QueryMemo;

pub use cover::{SurfacePoint, cover_by, grow_radius};
pub use emitted::{BOX_SAMPLES, Emitted, SampleBox, box_runs};
pub use first_pass::{Deferred, NARROW_RATIO, TASK_FOOTPRINT, sample_region};
pub use given_up::{GivenUp, settle_given_up, settle_parts};
pub use probe::{Probed, probe_given_up};
pub use sample_index::{Member, SampleIndex};
pub use second_pass::{given_up_share, refine_deferred};

/// Rectangles smaller than this fraction of the sample footprint are given up when unclassified.
pub const SMALL_REGION_FRACTION: f64 = 1.0 / 64.0;

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
    /// for the same reason ([`BasicRegion::owns_none_of`](crate::regions::BasicRegion::owns_none_of)).
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
    /// steps (`snap_to_surface`).
    pub snap: f64,
    /// The apex of a cone, beside which those steps are kept short (`snap_to_surface`).
    pub apex: Option<DVec3>,
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
