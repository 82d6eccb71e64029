//! Adaptive longest-edge subdivision of one basic region (paper §4.2).
//!
//! At the corners of a rectangle the CSG distance `d` of eq. 22 is evaluated. A world radius
//! `|d|` becomes the 2-D radius `|d| / δ_max`, `δ_max` being the rectangle's maximum distortion
//! (§3.4 corner bound): the heightfield map is `δ_max`-Lipschitz on the convex rectangle, so 2-D
//! points within `|d| / δ_max` of a corner map to surface points within `|d|` of it in space.
//! The corner discs cover the rectangle when one reaches the opposite corner or each reaches the
//! centre; then the rectangle is wholly on the CSG surface (all `d < 0`: filled with a grid of
//! samples) or wholly off it (all `d > 0`: dropped). Otherwise it is split at its longer edge.
//!
//! **Small regions.** A rectangle whose world footprint `δ_max · diagonal` is at most `r` needs
//! only one sample on the CSG surface anywhere inside it: the first corner with `d < 0` gets it
//! (the paper's special case), else the centre if `d(centre) < 0`. The sample's radius is reduced
//! to the footprint (§6.1: less overdraw, same guarantee). If neither is on the surface the
//! rectangle keeps being split, because only a proof keeps the guarantee: the paper's cut-off
//! at a tenth of the splat "can theoretically result in small holes". The cut-off here is at
//! [`SMALL_REGION_FRACTION`] of the splat footprint: a surface sliver that avoids every corner
//! and centre down to that size could be missed. A given-up rectangle within `r − footprint` of a
//! sample of the same quadric is still covered (counted in
//! [`SubdivisionStats::unresolved_covered`]): samples of its own region are checked here, those
//! of other regions (a neighbouring region often holds the sample, since given-up rectangles sit
//! on feature curves that cross region borders) once all regions are done ([`GivenUp`]). The
//! rest are counted in [`SubdivisionStats::unresolved`], so the count says whether a hole was
//! possible at all.

use std::collections::{HashMap, HashSet};

use qcsg_quadric::{DVec3, PrincipalFrame, Quadric};

use crate::Sample;
use crate::csg_distance::CsgDistance;
use crate::regions::{BasicRegion, Rect, region_point};

/// Rectangles smaller than this fraction of the sample footprint are given up when unclassified.
pub const SMALL_REGION_FRACTION: f64 = 1.0 / 64.0;

/// Largest grid side used to fill one classified rectangle; bigger ones are split first.
const MAX_FILL_SIDE: f64 = 1024.0;

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
    /// Small rectangles that got a single sample.
    pub small: u64,
    /// Rectangles given up unclassified and not within reach of a sample of their region (see
    /// the module doc): the only places where the guarantee is not proven.
    pub unresolved: u64,
    /// Rectangles given up unclassified but proven covered by a sample of their region.
    pub unresolved_covered: u64,
}

impl SubdivisionStats {
    /// Adds another set of counters.
    pub fn add(&mut self, other: &Self) {
        self.distance_queries += other.distance_queries;
        self.rectangles += other.rectangles;
        self.filled += other.filled;
        self.discarded += other.discarded;
        self.small += other.small;
        self.unresolved += other.unresolved;
        self.unresolved_covered += other.unresolved_covered;
    }
}

/// A rectangle given up unclassified and not covered by a sample of its own region: covered
/// if some sample of the same quadric lies within `reach` of `point`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GivenUp {
    /// Index of the quadric in the DNF's quadric table.
    pub quadric: u32,
    /// A surface point of the rectangle (its first corner).
    pub point: DVec3,
    /// `r − footprint`: a sample this close to `point` covers the whole rectangle.
    pub reach: f64,
}

/// What one basic region needs to be sampled.
pub struct RegionContext<'a> {
    /// The quadric's principal frame.
    pub frame: &'a PrincipalFrame,
    /// The quadric itself (normals, snapping to the surface).
    pub quadric: &'a Quadric,
    /// Eq. 22 for this quadric and term.
    pub distance: &'a CsgDistance,
    /// The world-space sample radius `r`.
    pub radius: f64,
}

/// A rectangle with its corner distances `[x0y0, x1y0, x0y1, x1y1]`.
struct Cell {
    rect: Rect,
    d: [f64; 4],
}

/// Samples one basic region, appending to `out` in a deterministic (depth-first) order.
/// Given-up rectangles not covered by a sample of this region go to `pending` (not counted
/// yet: see [`GivenUp`]); those without a surface point at their corner count as unresolved.
pub fn sample_region(
    ctx: &RegionContext<'_>,
    region: &BasicRegion,
    out: &mut Vec<Sample>,
    pending: &mut Vec<GivenUp>,
    stats: &mut SubdivisionStats,
) {
    let root = region.rect;
    let cutoff = SMALL_REGION_FRACTION * ctx.radius / region.max_distortion.max(1.0);
    let corners = [
        (root.x.0, root.y.0),
        (root.x.1, root.y.0),
        (root.x.0, root.y.1),
        (root.x.1, root.y.1),
    ];
    let d = corners.map(|(x, y)| query(ctx, region, x, y, stats));
    let first_sample = out.len();
    let mut given_up = Vec::new();
    let mut stack = vec![Cell { rect: root, d }];
    while let Some(cell) = stack.pop() {
        stats.rectangles += 1;
        let rect = cell.rect;
        let distortion = rect_distortion(region, &rect);
        let diagonal = rect.diagonal();
        let radii = cell.d.map(|d| d.abs() / distortion);
        let covered =
            radii.iter().any(|&r| r >= diagonal) || radii.iter().all(|&r| r >= 0.5 * diagonal);
        if covered && cell.d.iter().all(|&d| d > 0.0) {
            stats.discarded += 1;
            continue;
        }
        let footprint = distortion * diagonal;
        if covered
            && cell.d.iter().all(|&d| d < 0.0)
            && footprint > ctx.radius
            && fill(ctx, region, &rect, distortion, out)
        {
            stats.filled += 1;
            continue;
        }
        if footprint <= ctx.radius {
            if let Some(k) = cell.d.iter().position(|&d| d < 0.0) {
                let (x, y) = corner(&rect, k);
                emit(ctx, region, x, y, footprint.min(ctx.radius), out);
                stats.small += 1;
                continue;
            }
            let (cx, cy) = (0.5 * (rect.x.0 + rect.x.1), 0.5 * (rect.y.0 + rect.y.1));
            if query(ctx, region, cx, cy, stats) < 0.0 {
                emit(ctx, region, cx, cy, (0.5 * footprint).min(ctx.radius), out);
                stats.small += 1;
                continue;
            }
            if diagonal <= cutoff {
                given_up.push((rect, footprint));
                continue;
            }
        }
        let (low, high, along_x) = rect.split_longest();
        let [d00, d10, d01, d11] = cell.d;
        let (low_d, high_d) = if along_x {
            let m0 = query(ctx, region, low.x.1, rect.y.0, stats);
            let m1 = query(ctx, region, low.x.1, rect.y.1, stats);
            ([d00, m0, d01, m1], [m0, d10, m1, d11])
        } else {
            let m0 = query(ctx, region, rect.x.0, low.y.1, stats);
            let m1 = query(ctx, region, rect.x.1, low.y.1, stats);
            ([d00, d10, m0, m1], [m0, m1, d01, d11])
        };
        if low.diagonal() >= diagonal || high.diagonal() >= diagonal {
            // No progress in floating point: the rectangle is as small as it gets.
            given_up.push((rect, footprint));
            continue;
        }
        stack.push(Cell {
            rect: high,
            d: high_d,
        });
        stack.push(Cell {
            rect: low,
            d: low_d,
        });
    }
    for (rect, footprint) in given_up {
        let reach = ctx.radius - footprint;
        let point = region_point(
            ctx.frame,
            &region.heightfield,
            region.sheet,
            rect.x.0,
            rect.y.0,
        );
        let Some(point) = point.filter(|_| reach > 0.0) else {
            stats.unresolved += 1;
            continue;
        };
        let samples = out.get(first_sample..).unwrap_or(&[]);
        if samples
            .iter()
            .any(|s| (s.position - point).length() <= reach)
        {
            stats.unresolved_covered += 1;
        } else {
            pending.push(GivenUp {
                quadric: region.quadric,
                point,
                reach,
            });
        }
    }
}

/// Settles the given-up rectangles of all regions against all samples: each one with a sample
/// of its quadric within its reach counts as covered, the rest as unresolved.
pub fn settle_given_up(pending: &[GivenUp], samples: &[Sample], stats: &mut SubdivisionStats) {
    if pending.is_empty() {
        return;
    }
    let cell = pending.iter().map(|g| g.reach).fold(0.0, f64::max);
    let anchor = pending[0].point;
    let key = |p: DVec3| {
        let c = ((p - anchor) / cell).floor();
        (c.x as i64, c.y as i64, c.z as i64)
    };
    // Samples of the pending quadrics, bucketed by (cell, quadric).
    let mut grid: HashMap<(i64, i64, i64, u32), Vec<usize>> = HashMap::new();
    let wanted: HashSet<u32> = pending.iter().map(|g| g.quadric).collect();
    for (index, sample) in samples.iter().enumerate() {
        if wanted.contains(&sample.quadric) {
            let (x, y, z) = key(sample.position);
            grid.entry((x, y, z, sample.quadric))
                .or_default()
                .push(index);
        }
    }
    for given_up in pending {
        let (x, y, z) = key(given_up.point);
        let mut covered = false;
        'search: for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let Some(list) = grid.get(&(x + dx, y + dy, z + dz, given_up.quadric)) else {
                        continue;
                    };
                    if list
                        .iter()
                        .any(|&i| (samples[i].position - given_up.point).length() <= given_up.reach)
                    {
                        covered = true;
                        break 'search;
                    }
                }
            }
        }
        if covered {
            stats.unresolved_covered += 1;
        } else {
            stats.unresolved += 1;
        }
    }
}

/// The maximum distortion over a sub-rectangle (§3.4), falling back to the region's bound.
fn rect_distortion(region: &BasicRegion, rect: &Rect) -> f64 {
    match region.heightfield.distortion_bounds(rect.x, rect.y) {
        Some((_, high)) if high.is_finite() && high >= 1.0 => high.min(region.max_distortion),
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

/// Covers a rectangle known to be on the CSG surface with a grid of samples at cell centres:
/// each cell's half-diagonal maps to at most `r`. Returns `false` (nothing emitted) when the
/// grid would be too large, so that the caller splits first.
fn fill(
    ctx: &RegionContext<'_>,
    region: &BasicRegion,
    rect: &Rect,
    distortion: f64,
    out: &mut Vec<Sample>,
) -> bool {
    let spacing = std::f64::consts::SQRT_2 * ctx.radius / distortion;
    let nx = (rect.width() / spacing).ceil().max(1.0);
    let ny = (rect.height() / spacing).ceil().max(1.0);
    if !(nx <= MAX_FILL_SIDE && ny <= MAX_FILL_SIDE) {
        return false;
    }
    let (dx, dy) = (rect.width() / nx, rect.height() / ny);
    let radius = (0.5 * distortion * dx.hypot(dy)).min(ctx.radius);
    for iy in 0..ny as u32 {
        let y = rect.y.0 + (f64::from(iy) + 0.5) * dy;
        for ix in 0..nx as u32 {
            let x = rect.x.0 + (f64::from(ix) + 0.5) * dx;
            emit(ctx, region, x, y, radius, out);
        }
    }
    true
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
    let Some(position) = region_point(ctx.frame, &region.heightfield, region.sheet, x, y) else {
        return;
    };
    let position = snap_to_surface(ctx.quadric, position);
    let axis = ctx.frame.axes[region.heightfield.normal_axis];
    let normal = ctx.quadric.normal(position).unwrap_or(axis * region.sheet);
    out.push(Sample {
        position,
        normal,
        quadric: region.quadric,
        term: region.term,
        radius,
        clip_list: 0,
    });
}

/// Most Newton steps that move a sample onto its quadric ([`snap_to_surface`]).
const SNAP_STEPS: usize = 2;

/// `p` moved onto the quadric by Newton steps along the gradient, each kept only while it lowers
/// `|Q| / ‖∇Q‖` (at most [`SNAP_STEPS`]). The heightfield point can be off by more than the
/// required `1e-9` of the scene where its square root cancels (a slab of half-width `1e-6`); the
/// move is of that size, far below any sample radius. Cones are left alone: next to the apex,
/// where the gradient vanishes, a step can cross the bounding literal at the tip.
fn snap_to_surface(q: &Quadric, mut p: DVec3) -> DVec3 {
    if q.kind() == qcsg_quadric::QuadricKind::Cone {
        return p;
    }
    let residual = |p: DVec3| {
        let g = q.gradient(p).length();
        if g > 0.0 {
            q.value(p).abs() / g
        } else {
            f64::INFINITY
        }
    };
    let mut current = residual(p);
    for _ in 0..SNAP_STEPS {
        if current == 0.0 || !current.is_finite() {
            break;
        }
        let g = q.gradient(p);
        let next = p - (q.value(p) / g.length_squared()) * g;
        let after = residual(next);
        if !(next.is_finite() && after < current) {
            break;
        }
        p = next;
        current = after;
    }
    p
}
