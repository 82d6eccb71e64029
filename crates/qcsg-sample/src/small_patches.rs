//! Small patches: basic regions whose whole surface fits in a world box no larger than the
//! sample radius, kept whole by the region partition instead of refined.
//!
//! The partition ([`crate::regions`]) refines a rectangle until its distortion is bounded
//! and it is on one side of the border between sampling planes, or until the rim of a `Root`
//! heightfield (where the slope is unbounded) no longer crosses a part of it where its plane
//! is the best. Both happen at the scale of the surface's own features, not of the radius: a
//! hyperboloid whose waist turns within `10⁻³` around a circle `1,400` long, or a needle
//! seen from the side, took millions of regions at a radius of `126`, each of which costs a
//! sample and the memory of eq. 22 narrowed to it. A rectangle still to be refined whose
//! surface (both sheets) lies in a world box of diagonal at most the radius is kept instead,
//! as a small patch (its `max_distortion` is `∞`: nothing is bounded about it but its box).
//!
//! One sample settles a small patch, whatever its distortion: eq. 22 at one point `p` of its
//! surface (where the radicand is largest, so that the surface is there), and with `E` the
//! diagonal of its box,
//! - `d(p) > E`: every point of the patch is within `E` of `p`, closer than the CSG surface,
//!   so none is on it ([`Settled::Off`]);
//! - `d(q) < 0` at `p` or at another point `q` of the patch (its centre, corners and the
//!   middles of its edges are tried, [`on_surface_point`]): `q` is on the CSG surface and
//!   within `E` of every point of the patch, so a sample there of radius `E` covers it
//!   ([`Settled::Sample`]). A feature that crosses the patch (a part's cap through the rim of
//!   a thin blade) leaves part of it on the surface, where one of these lands;
//! - otherwise a feature curve of the CSG surface passes near: the patch is refined as the
//!   partition would have ([`refine`]), and its regions are subdivided as any others. This
//!   costs the features' scale only where a feature of the solid meets the patch (a dent of
//!   radius 1 in a ball of radius `10⁶` at a radius of `10⁵`: the dent's regions are those of
//!   before).
//!
//! No small patch holds a cone's apex: around it the given-up rectangles are settled by
//! [`crate::apex`].

use qcsg_quadric::{DVec3, PrincipalFrame};
use rayon::prelude::*;

use crate::csg_distance::NearDistance;
use crate::patches::{Patch, PlacedRegion, near_margin};
use crate::regions::{
    BasicRegion, Partition, REGION_SAMPLES, Rect, RegionCap, RegionStats, SmallPatches,
    patch_bounds, radicand_peak, region_point,
};

/// Whether `region` is a small patch.
pub fn is_small_patch(region: &BasicRegion) -> bool {
    region.max_distortion == f64::INFINITY
}

/// The diagonal `E` of the box around a small patch's surface.
pub fn extent(frame: &PrincipalFrame, region: &BasicRegion) -> f64 {
    patch_bounds(frame, region).map_or(f64::INFINITY, |b| (b.max - b.min).length())
}

/// The point of the plane where a small patch is tested first: where the radicand is largest,
/// so that the surface is there.
pub fn test_point(region: &BasicRegion) -> (f64, f64) {
    radicand_peak(&region.heightfield, &region.rect)
}

/// The points of the plane where a small patch is tried for a point on the CSG surface, in
/// order: its [`test_point`], centre, corners and the middles of its edges.
fn tried_points(region: &BasicRegion) -> [(f64, f64); 10] {
    let Rect { x, y } = region.rect;
    let (mx, my) = region.rect.centre();
    [
        test_point(region),
        (mx, my),
        (x.0, y.0),
        (x.1, y.0),
        (x.0, y.1),
        (x.1, y.1),
        (mx, y.0),
        (mx, y.1),
        (x.0, my),
        (x.1, my),
    ]
}

/// The first of a small patch's [`tried_points`] on the CSG surface (where `distance`, eq. 22
/// at a point of the patch, is negative), where its one sample goes: every point of the patch
/// is within the diagonal of its box of it. A feature of the solid that crosses the patch (the
/// cap of a part through a rim) leaves most of these on the surface even where the test point
/// is not, and the patch then needs no refining down to the scale of its rim.
pub fn on_surface_point(
    frame: &PrincipalFrame,
    region: &BasicRegion,
    mut distance: impl FnMut(DVec3) -> f64,
) -> Option<(f64, f64)> {
    tried_points(region).into_iter().find(|&(x, y)| {
        region_point(frame, &region.heightfield, region.sheet, x, y)
            .is_some_and(|p| distance(p) < 0.0)
    })
}

/// What eq. 22 at a small patch's test point settles (see the module doc).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Settled {
    /// On the CSG surface: one sample covers the patch.
    Sample,
    /// Off the CSG surface throughout.
    Off,
    /// Near a feature curve: refine it.
    Refine,
}

/// Settles a small patch with eq. 22 near it (`on_surface`: the patch is all on the CSG
/// surface, [`NearDistance::everywhere_on_surface`]).
pub fn settle(
    frame: &PrincipalFrame,
    region: &BasicRegion,
    (distance, on_surface): (&NearDistance<'_>, bool),
) -> Settled {
    let (x, y) = test_point(region);
    let Some(p) = region_point(frame, &region.heightfield, region.sheet, x, y) else {
        return Settled::Refine;
    };
    if on_surface {
        return Settled::Sample;
    }
    let d = distance.distance(p);
    if d > extent(frame, region) {
        Settled::Off
    } else if d < 0.0 || on_surface_point(frame, region, |p| distance.distance(p)).is_some() {
        Settled::Sample
    } else {
        Settled::Refine
    }
}

/// The basic regions of a small patch refined as the partition refines any rectangle, each
/// charged to `cap`.
pub fn refine(
    frame: &PrincipalFrame,
    region: &BasicRegion,
    cap: &RegionCap,
    stats: &mut RegionStats,
) -> Vec<BasicRegion> {
    let partition = Partition {
        frame,
        heightfield: &region.heightfield,
        small_patch: SmallPatches::NONE,
        sheets: 1,
        quadric: region.quadric,
        cap,
    };
    let (kept, _) = partition.run(vec![region.rect], stats);
    kept.into_iter()
        .map(|(rect, max_distortion, border)| BasicRegion {
            rect,
            max_distortion,
            border: border.then_some(region.border).flatten(),
            ..*region
        })
        .collect()
}

/// The run's regions with each small patch settled: kept (for its one sample), left out (no
/// eq. 22: it emits nothing), or replaced by its refinement, whose regions get eq. 22 narrowed
/// from the patch's, in the order of the regions they replace. Refined regions are charged,
/// with the regions there were, to `max_samples` ([`REGION_SAMPLES`] each); past it, the
/// quadric that crossed it is the error.
pub fn settle_all<'a>(
    (regions, near): (Vec<PlacedRegion>, Vec<Option<NearDistance<'a>>>),
    patches: &[Patch],
    (radius, max_samples): (f64, u64),
    stats: &mut RegionStats,
) -> Result<(Vec<PlacedRegion>, Vec<Option<NearDistance<'a>>>), u32> {
    if !regions.iter().any(|(_, region, _)| is_small_patch(region)) {
        return Ok((regions, near));
    }
    let held = (regions.len() as u64).saturating_mul(REGION_SAMPLES);
    let cap = RegionCap::new(max_samples.saturating_sub(held));
    type Outcome<'a> = (Vec<(PlacedRegion, Option<NearDistance<'a>>)>, RegionStats);
    let settled: Vec<Outcome<'a>> = regions
        .into_par_iter()
        .zip(near)
        .map(|(placed, near)| {
            let mut counters = RegionStats::default();
            let (patch, region, bounds) = &placed;
            let (Some(distance), Some(whole)) = (&near, patches.get(*patch)) else {
                return (vec![(placed, near)], counters);
            };
            if !is_small_patch(region) {
                return (vec![(placed, near)], counters);
            }
            let on_surface = distance.everywhere_on_surface(bounds);
            match settle(&whole.frame, region, (distance, on_surface)) {
                Settled::Sample => (vec![(placed, near)], counters),
                Settled::Off => (vec![(placed, None)], counters),
                Settled::Refine => {
                    let parts = refine(&whole.frame, region, &cap, &mut counters);
                    let parts = parts
                        .into_iter()
                        .map(|part| {
                            let part_bounds = patch_bounds(&whole.frame, &part)
                                .unwrap_or(qcsg_csg::Aabb::EVERYTHING);
                            let narrowed =
                                distance.narrow(&part_bounds, near_margin(&part_bounds, radius));
                            let narrowed =
                                (!narrowed.nowhere_negative(&part_bounds)).then_some(narrowed);
                            ((*patch, part, part_bounds), narrowed)
                        })
                        .collect();
                    (parts, counters)
                }
            }
        })
        .collect();
    if let Some((quadric, _)) = cap.crossed() {
        return Err(quadric);
    }
    let mut out = (Vec::new(), Vec::new());
    for (parts, counters) in settled {
        stats.add(&counters);
        for (placed, near) in parts {
            out.0.push(placed);
            out.1.push(near);
        }
    }
    Ok(out)
}
