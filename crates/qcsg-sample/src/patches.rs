//! The literals of the DNF's terms ready to be sampled ([`Patch`]) and their basic regions
//! ([`all_regions`]), in a fixed order: term, literal, sampling plane, sheet, rectangle. Each
//! patch carries eq. 22 set up for the part of its quadric its regions hold.

use crate::csg_distance::{CsgDistance, Shapes};
use crate::regions::{
    BasicRegion, Held, RegionCap, RegionStats, SmallPatches, basic_regions_within, patch_bounds,
};
use crate::stats::SampleStats;
use qcsg_csg::{Aabb, Dnf};
use qcsg_quadric::{PrincipalFrame, QuadricKind};
use rayon::prelude::*;

/// One literal of one term, ready to be sampled.
pub(super) struct Patch {
    pub(super) frame: PrincipalFrame,
    pub(super) distance: CsgDistance,
    pub(super) quadric: u32,
    pub(super) term: u32,
    pub(super) kind: QuadricKind,
    /// A box around the quadric's part in all its regions.
    pub(super) bounds: Aabb,
    /// The rectangles the region decomposition gave up, and how far from the frame's centre
    /// the surface over them reaches ([`basic_regions`]).
    pub(super) given_up: (u64, f64),
}

/// A basic region with the index of its patch and a box around the patch's part in it.
pub(super) type PlacedRegion = (usize, BasicRegion, Aabb);

/// The box a term's surface is sampled in: its box within the DNF's region.
pub(super) fn term_box(dnf: &Dnf, term: usize) -> Option<Aabb> {
    let bounds = dnf.terms.get(term)?.bounds;
    Some(match dnf.region {
        Some(region) => bounds.intersection(&region),
        None => bounds,
    })
}

/// Every basic region of every literal of every term, in a fixed order (term, literal, plane,
/// sheet, rectangle), with the patch each belongs to. Literals are decomposed in parallel (a
/// scene of many parts has thousands of them), and so are each literal's sampling planes.
/// Rectangles whose surface fits in a box of diagonal `radius` are kept whole
/// ([`crate::small_patches`]). The regions and each patch's eq. 22 are charged as the samples
/// that take as much memory ([`RegionCap`]), at most `max_samples` in all; past that the
/// decomposition stops and the quadric being sampled when the cap was crossed is the error,
/// with what crossed it.
pub(super) fn all_regions(
    dnf: &Dnf,
    (radius, max_samples): (f64, u64),
    stats: &mut SampleStats,
) -> Result<(Vec<Patch>, Vec<PlacedRegion>), (u32, Held)> {
    let cap = RegionCap::new(max_samples);
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
    type Decomposed = (Patch, Vec<Vec<(BasicRegion, Aabb)>>, RegionStats, usize);
    let decomposed: Vec<Option<Decomposed>> = literals
        .par_iter()
        .map(|&(term, literal, bounds)| {
            let entry = dnf.quadrics.get(literal as usize)?;
            let kind = entry.quadric.kind();
            if kind.has_no_surface() || matches!(kind, QuadricKind::Point | QuadricKind::Line) {
                return None;
            }
            if cap.crossed().is_some() {
                return None;
            }
            let frame = entry.quadric.frame();
            // Around a cone's apex the normal turns all the way round within any distance: the
            // rectangle holding it is never a small patch, but is settled by a ring of samples
            // about the apex ([`crate::apex`]).
            let small_patch = SmallPatches {
                diagonal: radius,
                apex: kind == QuadricKind::Cone,
            };
            // The three sampling planes each on its own: a scene of a few quadrics has too few
            // literals to share out.
            let planes: Vec<_> = (frame.heightfields().into_par_iter())
                .map(|heightfield| {
                    let (mut found, mut counters) = (Vec::new(), RegionStats::default());
                    let key = (literal, term);
                    let reach = basic_regions_within(
                        &frame,
                        &heightfield,
                        (&bounds, small_patch),
                        key,
                        (&mut found, &cap),
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
            let held = distance.held_bytes();
            if !cap.charge_distance(held, literal) {
                return None;
            }
            let patch = Patch {
                frame,
                distance,
                quadric: literal,
                term,
                kind,
                bounds,
                given_up: (counters.unresolved, reach),
            };
            Some((patch, found, counters, held))
        })
        .collect();
    if let Some(crossed) = cap.crossed() {
        return Err(crossed);
    }
    let mut patches = Vec::new();
    let mut regions = Vec::new();
    for (patch, found, counters, held) in decomposed.into_iter().flatten() {
        let found = found.into_iter().flatten();
        regions.extend(found.map(|(r, b)| (patches.len(), r, b)));
        patches.push(patch);
        stats.regions.add(&counters);
        stats.distance_bytes += held as u64;
    }
    Ok((patches, regions))
}

/// The margin eq. 22 keeps around a patch's box `bounds` ([`CsgDistance::near`]): its diagonal
/// plus the radius, so that the terms left out are farther than any rectangle of the patch.
pub(super) fn near_margin(bounds: &Aabb, radius: f64) -> f64 {
    (bounds.max - bounds.min).length() + radius
}
