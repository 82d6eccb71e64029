//! The last resort for a given-up rectangle ([`probe_given_up`]): eq. 22 at the centres of its
//! quadrants a few levels down, around one point down to a speck of the length tolerance, and
//! downhill along eq. 22 from the centre ([`seek_surface`]), which finds a band of surface too
//! thin for any probe to land on.

use super::cell::{query, rect_distortion};
use super::classify::centre_point;
use super::cover::grow_to_cover;
use super::emit::emit;
use super::given_up::GivenUp;
use super::{RegionContext, SubdivisionStats};
use crate::regions::{BasicRegion, Rect};
use crate::sample_point::Sample;
use qcsg_quadric::QuadricKind;

/// Levels of quadrants below a given-up rectangle that [`probe_given_up`] looks at: down to a
/// 4 × 4 grid, at most 21 distance queries. A third level (85) settled about 1 % more of them
/// on most stability scenes, for two to four times the queries spent probing.
pub(super) const PROBE_LEVELS: u32 = 2;

/// Most parts a probe follows further down to a speck ([`probe_given_up`]): those around one
/// point, which is a corner of at most four.
pub(super) const POINT_PARTS: usize = 4;

/// Most levels a probe follows parts around one point: far below any speck (`2⁻⁶⁰` of the
/// rectangle).
pub(super) const POINT_LEVELS: u32 = 60;

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
///   as above. What is left is returned, for [`settle_parts`](crate::subdivide::settle_parts).
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
pub(super) fn down_to_speck(
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
pub(super) const SEEK_STEPS: usize = 12;

/// [`seek_surface`]'s difference quotients step this fraction of the distance to the surface
/// that eq. 22 allows, so that both points lie on the same side of it.
pub(super) const SEEK_STEP: f64 = 1e-3;

/// Relative to the coordinates, the shortest step of a difference quotient: far above their
/// rounding.
pub(super) const SEEK_ROUNDING: f64 = 1e-12;

/// A point of `rect` on the CSG surface, found by following eq. 22 downhill from the centre:
/// where the surface is a band too thin for any corner or centre to land on (the cut rim of a
/// wall `1e-9` thick), eq. 22 along a line across the band falls to it at a steady slope and
/// rises past it, a V whose tip dips below zero only over the band's width. The line follows
/// the gradient at the centre (by difference quotients); Newton steps along the falling side
/// find the rising one, then the crossing of the two sides, taken as lines, is the next guess.
/// Only a point where eq. 22 is negative counts, so the search proves what it finds; it gives
/// up when the sides cross above zero (surfaces that touch without crossing), leave the
/// rectangle or after [`SEEK_STEPS`] steps.
pub(super) fn seek_surface(
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
pub(super) enum Probe {
    /// A point on the CSG surface.
    Inside(f64, f64),
    /// No point of the rectangle is on it.
    Off,
    /// Neither: the parts, at the deepest level, that are neither.
    Unknown(Vec<Rect>),
}

/// [`probe_given_up`]'s search below `rect`, `levels` levels of quadrants deep.
pub(super) fn probe(
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
    /// cover what of it is on the surface ([`settle_parts`](crate::subdivide::settle_parts)).
    Unresolved(Vec<GivenUp>),
}
