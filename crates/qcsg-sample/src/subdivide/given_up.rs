//! Rectangles given up unclassified ([`GivenUp`]) and their settling against every sample.
//!
//! **The cutoff.** Only a proof keeps the guarantee: the paper's cut-off at a tenth of the splat
//! "can theoretically result in small holes", and a cutoff of `r / 16` here missed a sliver of
//! `examples/precision_part.qcsg` that the reference points found. A surface sliver that avoids
//! every corner and centre down to `r / 64` could still be missed; rectangles given up there are
//! settled against every sample at the end ([`settle_given_up`]); those with no sample of their
//! quadric within `r − footprint / 2` are probed a few levels further down, within a budget of
//! distance queries ([`super::probe_given_up`]), and those still unsettled are counted in
//! [`super::SubdivisionStats::unresolved`], so the count says whether a hole was possible at
//! all.

use super::SubdivisionStats;
use super::cover::SurfacePoint;
use super::emitted::SampleBox;
use super::sample_index::SampleIndex;
use crate::regions::Rect;
use crate::samples::Samples;
use qcsg_csg::Dnf;
use qcsg_quadric::DVec3;

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
/// at most `radius`); the rest are returned, for [`probe_given_up`](crate::subdivide::probe_given_up).
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

/// Whether all the parts a probe left of each given-up rectangle ([`Probed::Unresolved`](crate::subdivide::Probed::Unresolved)) are
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
pub(super) fn cover_given_up(
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
