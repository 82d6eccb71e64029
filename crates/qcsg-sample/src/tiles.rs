//! Tiling a basic region whose eq. 22 still looks at many literals ([`tiles`]): a face of a
//! plate drilled with thousands of holes is one region of one term, and each tile's eq. 22 keeps
//! only the holes near it ([`crate::csg_distance::NearDistance::narrow`]).

use crate::csg_distance::NearDistance;
use crate::patches::{Patch, PlacedRegion, near_margin};
use crate::regions::{BasicRegion, patch_bounds};
use qcsg_csg::Aabb;

/// Regions whose eq. 22 looks at more literals of terms of many than this are tiled until each
/// tile's patch sees fewer ([`NearDistance::literals_of_large_terms`]): a plate drilled with
/// thousands of holes is one term, and each hole's neighbourhood needs only the holes near it.
pub(super) const TILE_LITERALS: usize = 32;

/// Halvings of a tile tried at once ([`tiles`]).
pub(super) const TILE_TRIAL_DEPTH: u32 = 3;

/// Most tiles of one region: a bound on what tiling adds, whatever the scene.
pub(super) const MAX_TILES: usize = 4096;

/// `region` (with eq. 22 kept to its neighbourhood, `near`) as tiles, each with eq. 22 narrowed
/// to its own ([`NearDistance::narrow`]), while a tile looks at more than [`TILE_LITERALS`]
/// literals of terms of many and is larger than the radius. A tile is halved
/// [`TILE_TRIAL_DEPTH`] times at once (the margin shrinks with the tile, so counts fall only
/// after a few halvings), and the halves are kept only if they look at a quarter fewer
/// literals on average: elsewhere (a polyhedron's faces, all near each other) the tile stays
/// whole. A region makes at most [`MAX_TILES`] tiles. A tile keeps the region's distortion
/// bound and border flag, which hold on any part of it. In order, low half first.
pub(super) fn tiles<'a>(
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
