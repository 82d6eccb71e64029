//! A drawing's region with OpenSCAD's fill rule, exactly: the even–odd region of all its paths,
//! circles and ellipses, as straight cells plus discs, elliptic discs and their segments combined
//! in order.
//!
//! A path with arcs bounds the same even–odd region as its chord polygon XOR, for each arc, the
//! segment between the arc and its chord (the closed curve arc + chord bounds exactly that
//! segment). So the region is `P ⊕ C₁ ⊕ … ⊕ Cₙ`: `P` the even–odd region of every chord polygon
//! ([`polygon_cells`]), `Cᵢ` the full circles' and ellipses' discs and the arcs' segments (a disc
//! cut by the chord's half-plane on the arc's side). Elliptic pieces are handled in the frame of
//! their conjugate semi-diameters, where the ellipse is the unit circle; where an elliptic arc
//! meets another piece, whether it enters that piece is found by minimising over the arc's
//! parameter (sampled, then refined), since the exact answer is the root of a quartic.
//!
//! XOR is not a boolean qcsg can keep small, but it needs none when each piece, in its turn,
//! lies wholly inside or wholly outside the region built before it: `R₀ = P`, `Rₖ = Rₖ₋₁ − Cₖ`
//! when `Cₖ` lies inside `Rₖ₋₁`, `Rₖ₋₁ ∪ Cₖ` otherwise ([`Step`]). That holds when no boundary
//! of `Rₖ₋₁` enters `Cₖ`'s interior: no drawn line, no chord of an arc not yet applied (an applied
//! arc's chord cancels against the same edge of `P`), no arc or circle of a piece applied before.
//! The order is found greedily: always the largest piece that qualifies (so a container comes
//! before what it holds, and a circle crossing only chords waits until their arcs are applied).
//! Whether a piece is inside is the parity of `P` and the applied pieces at a point deep in it.
//! When no piece qualifies, pieces cross ([`RegionError::Crossing`], naming what enters which);
//! nothing is tessellated.
//!
//! "Enters" allows a tolerance of about 1e-7 of the drawing's size (plus the rounding of its
//! coordinates' magnitude): a line that ends on a circle or runs tangent to it touches, it does not
//! cross, even when the file's digits put its end a little inside.

mod grid;

use std::f64::consts::TAU;
use std::fmt;

use glam::DVec2;

use self::grid::BoxGrid;
use crate::formats::{Drawing, DrawingPath, EllipticArc};
use crate::polygon::{HalfPlane, Polygon, PolygonError, PolygonLimits, polygon_cells};

/// A curved piece of a drawing's region.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CurvedPiece {
    /// A disc.
    Disc {
        /// The centre.
        center: DVec2,
        /// The radius.
        radius: f64,
    },
    /// A circular segment: the disc cut by the half-plane of its chord on the arc's side.
    Segment {
        /// The circle's centre.
        center: DVec2,
        /// The circle's radius.
        radius: f64,
        /// The chord's half-plane, holding the arc.
        chord: HalfPlane,
    },
    /// An elliptic disc: the points `center + axes[0] x + axes[1] y` with `x² + y² < 1`.
    Ellipse {
        /// The centre.
        center: DVec2,
        /// Two conjugate semi-diameters (linearly independent).
        axes: [DVec2; 2],
    },
    /// An elliptic segment: the elliptic disc cut by the half-plane of its chord on the arc's
    /// side.
    EllipticSegment {
        /// The ellipse's centre.
        center: DVec2,
        /// Its conjugate semi-diameters.
        axes: [DVec2; 2],
        /// The chord's half-plane, holding the arc.
        chord: HalfPlane,
    },
}

/// An ellipse's frame: its centre and two conjugate semi-diameters, the images of the unit
/// circle's `x` and `y` radii (a circle's are two perpendicular radii).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Frame {
    center: DVec2,
    axes: [DVec2; 2],
}

impl Frame {
    fn det(&self) -> f64 {
        self.axes[0].perp_dot(self.axes[1])
    }

    /// The coordinates of `p` in the frame (on the unit circle for points of the ellipse).
    fn local(&self, p: DVec2) -> DVec2 {
        let [a, b] = self.axes;
        let (d, det) = (p - self.center, self.det());
        DVec2::new(d.perp_dot(b) / det, a.perp_dot(d) / det)
    }

    /// The point of local coordinates `l`.
    fn point(&self, l: DVec2) -> DVec2 {
        self.center + self.axes[0] * l.x + self.axes[1] * l.y
    }

    /// Half the size of the ellipse's box along x and y.
    fn half_extent(&self) -> DVec2 {
        let [a, b] = self.axes;
        DVec2::new(a.x.hypot(b.x), a.y.hypot(b.y))
    }

    /// The semi-minor axis: the least distance from the centre to the ellipse.
    fn min_scale(&self) -> f64 {
        let [a, b] = self.axes;
        let sum = a.length_squared() + b.length_squared();
        let det = self.det().abs();
        let major = (0.5 * (sum + (sum * sum - 4.0 * det * det).max(0.0).sqrt())).sqrt();
        if major > 0.0 { det / major } else { 0.0 }
    }

    /// The half-plane's function in local coordinates: `h.value(point(l)) = n · l + k`.
    fn local_line(&self, h: HalfPlane) -> (DVec2, f64) {
        let [a, b] = self.axes;
        (
            DVec2::new(h.normal.dot(a), h.normal.dot(b)),
            h.value(self.center),
        )
    }
}

impl CurvedPiece {
    /// The circle's centre and radius, for a disc or circular segment.
    fn circle(&self) -> Option<(DVec2, f64)> {
        match *self {
            Self::Disc { center, radius } | Self::Segment { center, radius, .. } => {
                Some((center, radius))
            }
            Self::Ellipse { .. } | Self::EllipticSegment { .. } => None,
        }
    }

    fn frame(&self) -> Frame {
        match *self {
            Self::Disc { center, radius } | Self::Segment { center, radius, .. } => Frame {
                center,
                axes: [DVec2::X * radius, DVec2::Y * radius],
            },
            Self::Ellipse { center, axes } | Self::EllipticSegment { center, axes, .. } => {
                Frame { center, axes }
            }
        }
    }

    fn chord(&self) -> Option<HalfPlane> {
        match *self {
            Self::Disc { .. } | Self::Ellipse { .. } => None,
            Self::Segment { chord, .. } | Self::EllipticSegment { chord, .. } => Some(chord),
        }
    }

    /// Whether `p` lies in the open piece.
    pub fn contains(&self, p: DVec2) -> bool {
        let in_conic = match self.circle() {
            Some((center, radius)) => (p - center).length_squared() < radius * radius,
            None => self.frame().local(p).length_squared() < 1.0,
        };
        in_conic && self.chord().is_none_or(|h| h.value(p) < 0.0)
    }
}

/// How a piece joins the region built before it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    /// The piece lies outside: add it.
    Union,
    /// The piece lies inside: cut it out.
    Difference,
}

/// One step of the construction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Step {
    /// Union or difference.
    pub op: Op,
    /// The piece.
    pub piece: CurvedPiece,
    /// The DXF line of the entity it comes from.
    pub line: usize,
}

/// A drawing's region: `polygon`, then each step in order.
#[derive(Clone, Debug, PartialEq)]
pub struct DrawingRegion {
    /// The even–odd region of the chord polygons.
    pub polygon: Polygon,
    /// The curved pieces, largest first.
    pub steps: Vec<Step>,
}

impl DrawingRegion {
    /// Whether `p` lies in the region (boundaries aside; a linear scan: for tests).
    pub fn contains(&self, p: DVec2) -> bool {
        let mut inside = self.polygon.contains(p);
        for step in &self.steps {
            if step.piece.contains(p) {
                inside = step.op == Op::Union;
            }
        }
        inside
    }
}

/// The most elementary tests spent ordering the curved pieces (about a second's work).
const MAX_WORK: usize = 100_000_000;

/// Why a drawing's region cannot be built exactly.
#[derive(Clone, Debug, PartialEq)]
pub enum RegionError {
    /// The chord polygons were refused (too many points, a huge coordinate).
    Polygon(PolygonError),
    /// A curve qcsg cannot make a region of (see [`DrawingCurve`](crate::DrawingCurve)).
    Curve {
        /// The entity.
        entity: String,
        /// Its DXF line.
        line: usize,
    },
    /// Too many curved pieces to order within the work limit.
    TooComplex {
        /// The DXF line of the piece being ordered when the limit was reached.
        line: usize,
    },
    /// A curved piece crosses an edge or another curve.
    Crossing {
        /// The piece ("the circle", "the arc").
        piece: &'static str,
        /// Its DXF line.
        line: usize,
        /// What it crosses ("a line", "the arc", "the circle").
        other: &'static str,
        /// Its DXF line (0 for the straight edge that closes an open path).
        other_line: usize,
    },
}

impl fmt::Display for RegionError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Polygon(e) => write!(f, "{e}"),
            Self::Curve { entity, line } => write!(
                f,
                "the {entity} at DXF line {line} has no exact region in qcsg yet"
            ),
            Self::TooComplex { line } => write!(
                f,
                "too many arcs, circles and ellipses to compose exactly (stopped at DXF line {line})"
            ),
            Self::Crossing {
                piece,
                line,
                other,
                other_line,
            } => {
                write!(f, "{piece} at DXF line {line} crosses {other}")?;
                if *other_line > 0 {
                    write!(f, " at DXF line {other_line}")?;
                } else {
                    write!(f, " closing an open path")?;
                }
                Ok(())
            }
        }
    }
}

impl std::error::Error for RegionError {}

/// A curved piece with where it comes from.
#[derive(Clone)]
struct Item {
    piece: CurvedPiece,
    /// The conic's arc as a parameter interval `(start, sweep)` in its frame (for a circle, the
    /// angle, counter-clockwise).
    arc: (f64, f64),
    /// The chord's position among the straight edges, for a segment.
    own_edge: Option<usize>,
    line: usize,
    name: &'static str,
}

impl Item {
    /// A box around the piece (its conic's).
    fn bounds(&self) -> (DVec2, DVec2) {
        let frame = self.piece.frame();
        let e = frame.half_extent();
        (frame.center - e, frame.center + e)
    }
}

/// What lies near a piece: the straight edges and the applied pieces whose boxes meet its box.
struct Near {
    straights: Vec<usize>,
    done: Vec<usize>,
}

/// A straight edge of a chord polygon.
struct Straight {
    a: DVec2,
    b: DVec2,
    line: usize,
    /// Whether it is an arc's chord rather than a drawn line.
    chord: bool,
}

/// The region of `drawing` under OpenSCAD's even–odd rule, or why it has no exact form here.
pub fn drawing_region(
    drawing: &Drawing,
    limits: &PolygonLimits,
) -> Result<DrawingRegion, RegionError> {
    if let Some(curve) = drawing.curves.first() {
        return Err(RegionError::Curve {
            entity: curve.entity.clone(),
            line: curve.line,
        });
    }
    let (points, paths, straights) = chord_polygons(&drawing.paths);
    let tol = tolerance(&points, drawing);
    let mut items = Vec::new();
    for c in &drawing.circles {
        items.push(Item {
            piece: CurvedPiece::Disc {
                center: c.center,
                radius: c.radius,
            },
            arc: (0.0, TAU),
            own_edge: None,
            line: c.line,
            name: "the circle",
        });
    }
    for e in &drawing.ellipses {
        items.push(Item {
            piece: CurvedPiece::Ellipse {
                center: e.center,
                axes: e.axes,
            },
            arc: (0.0, TAU),
            own_edge: None,
            line: e.line,
            name: "the ellipse",
        });
    }
    let mut edge_index = 0;
    for path in &drawing.paths {
        for e in &path.edges {
            let own = edge_index;
            edge_index += 1;
            if let Some(ellipse) = e.ellipse {
                if let Some(item) = elliptic_item(e.from, e.to, &ellipse, tol) {
                    items.push(Item {
                        own_edge: Some(own),
                        line: e.line,
                        ..item
                    });
                }
                continue;
            }
            let Some(arc) = e.arc else { continue };
            let mid = arc.midpoint(e.from, e.to);
            // A segment thinner than the tolerance is its chord.
            let chord = HalfPlane::left_of(e.from, e.to);
            let sagitta = chord.value(mid).abs() / chord.normal.length();
            if sagitta.is_nan() || sagitta <= tol {
                continue;
            }
            let chord = if chord.value(mid) < 0.0 {
                chord
            } else {
                chord.flipped()
            };
            let (first, second) = if arc.ccw {
                (e.from, e.to)
            } else {
                (e.to, e.from)
            };
            let start = (first - arc.center).to_angle();
            let sweep = ((second - arc.center).to_angle() - start).rem_euclid(TAU);
            items.push(Item {
                piece: CurvedPiece::Segment {
                    center: arc.center,
                    radius: arc.radius,
                    chord,
                },
                arc: (start, if sweep == 0.0 { TAU } else { sweep }),
                own_edge: Some(own),
                line: e.line,
                name: "the arc",
            });
        }
    }
    let polygon = polygon_cells(&points, Some(&paths), limits).map_err(RegionError::Polygon)?;
    // Larger pieces first, so a container comes before what it contains; among those, the first
    // whose interior no boundary of the region built so far enters.
    items.sort_by(|a, b| area(&b.piece).total_cmp(&area(&a.piece)));
    // Grids over everything, so each test looks only at what lies near a piece's box.
    let mut lo = polygon.min;
    let mut hi = polygon.max;
    for s in &straights {
        lo = lo.min(s.a.min(s.b));
        hi = hi.max(s.a.max(s.b));
    }
    for item in &items {
        let (a, b) = item.bounds();
        lo = lo.min(a);
        hi = hi.max(b);
    }
    let mut straight_grid = BoxGrid::new(lo, hi, straights.len());
    for (k, s) in straights.iter().enumerate() {
        straight_grid.insert(k, s.a.min(s.b), s.a.max(s.b));
    }
    let mut cell_grid = BoxGrid::new(lo, hi, polygon.cells.len());
    for (k, c) in polygon.cells.iter().enumerate() {
        cell_grid.insert(k, c.min, c.max);
    }
    let mut done_grid = BoxGrid::new(lo, hi, items.len());
    let mut chord_done = vec![false; straights.len()];
    let mut done: Vec<Item> = Vec::with_capacity(items.len());
    let mut steps: Vec<Step> = Vec::with_capacity(items.len());
    let mut work = 0usize;
    // Items are taken in place (not removed: that would move the rest each time).
    let mut taken = vec![false; items.len()];
    let mut first = 0;
    loop {
        while first < items.len() && taken[first] {
            first += 1;
        }
        if first == items.len() {
            break;
        }
        let mut first_obstacle = None;
        let mut pick = None;
        for (i, item) in items.iter().enumerate().skip(first) {
            if taken[i] {
                continue;
            }
            let (a, b) = item.bounds();
            let near = Near {
                straights: straight_grid.query(a, b),
                done: done_grid.query(a, b),
            };
            work += 1 + near.straights.len() + near.done.len();
            if work > MAX_WORK {
                return Err(RegionError::TooComplex { line: item.line });
            }
            match obstacle(item, &straights, &chord_done, &done, &near, tol) {
                None => {
                    pick = Some(i);
                    break;
                }
                Some(o) => {
                    first_obstacle.get_or_insert((i, o));
                }
            }
        }
        let Some(i) = pick else {
            let (i, (other, other_line)) = first_obstacle.unwrap_or((0, ("a curve", 0)));
            return Err(RegionError::Crossing {
                piece: items[i].name,
                line: items[i].line,
                other,
                other_line,
            });
        };
        taken[i] = true;
        let item = items[i].clone();
        let (a, b) = item.bounds();
        let near = Near {
            straights: straight_grid.query(a, b),
            done: done_grid.query(a, b),
        };
        let p = deep_point(&item.piece, &straights, &done, &near);
        // The parity of the region built so far at `p`: in a cell of the chord polygons, then
        // flipped by each piece applied before that holds it.
        let mut inside = cell_grid
            .query(p, p)
            .into_iter()
            .any(|k| polygon.cells[k].contains(p));
        for j in done_grid.query(p, p) {
            if steps[j].piece.contains(p) {
                inside = !inside;
            }
        }
        steps.push(Step {
            op: if inside { Op::Difference } else { Op::Union },
            piece: item.piece,
            line: item.line,
        });
        if let Some(k) = item.own_edge {
            chord_done[k] = true;
        }
        done_grid.insert(done.len(), a, b);
        done.push(item);
    }
    Ok(DrawingRegion { polygon, steps })
}

/// The chord polygons: points, index paths (those of three or more corners, which can enclose
/// something), and every straight edge, chords included, in path order.
fn chord_polygons(paths: &[DrawingPath]) -> (Vec<DVec2>, Vec<Vec<usize>>, Vec<Straight>) {
    let mut points = Vec::new();
    let mut indices = Vec::new();
    let mut straights = Vec::new();
    for path in paths {
        let start = points.len();
        for e in &path.edges {
            points.push(e.from);
            straights.push(Straight {
                a: e.from,
                b: e.to,
                line: e.line,
                chord: e.arc.is_some() || e.ellipse.is_some(),
            });
        }
        if path.edges.len() >= 3 {
            indices.push((start..points.len()).collect());
        }
    }
    (points, indices, straights)
}

fn tolerance(points: &[DVec2], drawing: &Drawing) -> f64 {
    let mut lo = DVec2::splat(f64::INFINITY);
    let mut hi = DVec2::splat(f64::NEG_INFINITY);
    for &p in points {
        lo = lo.min(p);
        hi = hi.max(p);
    }
    for c in &drawing.circles {
        lo = lo.min(c.center - c.radius);
        hi = hi.max(c.center + c.radius);
    }
    for e in &drawing.ellipses {
        let half = Frame {
            center: e.center,
            axes: e.axes,
        }
        .half_extent();
        lo = lo.min(e.center - half);
        hi = hi.max(e.center + half);
    }
    if !lo.is_finite() || !hi.is_finite() {
        return 0.0;
    }
    let extent = (hi - lo).max_element();
    let magnitude = lo.abs().max(hi.abs()).max_element();
    1e-7 * extent + 1e-12 * magnitude
}

/// What of the region built so far enters `item`'s interior, if anything: a drawn line, the
/// chord of an arc not yet applied (applied chords cancel against the polygon's edge), or the
/// arc or circle of a piece already applied.
fn obstacle(
    item: &Item,
    straights: &[Straight],
    chord_done: &[bool],
    done: &[Item],
    near: &Near,
    tol: f64,
) -> Option<(&'static str, usize)> {
    // In the piece's frame its conic is the unit circle, shrunk by the tolerance (measured
    // along the semi-minor axis, so at least that much everywhere).
    let frame = item.piece.frame();
    let r = 1.0 - tol / frame.min_scale();
    if r.is_nan() || r <= 0.0 {
        return None;
    }
    for &k in &near.straights {
        let s = &straights[k];
        if Some(k) == item.own_edge || (s.chord && chord_done[k]) {
            continue;
        }
        // The part of the edge strictly beyond the chord (all of it for a disc).
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        if let Some(h) = item.piece.chord() {
            let limit = -tol * h.normal.length();
            let (fa, fb) = (h.value(s.a) - limit, h.value(s.b) - limit);
            if fa >= 0.0 && fb >= 0.0 {
                continue;
            }
            if fa >= 0.0 {
                t0 = fa / (fa - fb);
            } else if fb >= 0.0 {
                t1 = fa / (fa - fb);
            }
        }
        let (a, b) = (s.a + (s.b - s.a) * t0, s.a + (s.b - s.a) * t1);
        if distance_to_segment(DVec2::ZERO, frame.local(a), frame.local(b)) < r {
            let what = match (s.chord, s.line) {
                (true, _) => "the chord of the arc",
                (false, 0) => "the straight edge",
                (false, _) => "a line",
            };
            return Some((what, s.line));
        }
    }
    near.done
        .iter()
        .map(|&j| &done[j])
        .find(|d| arc_enters(d, &item.piece, tol))
        .map(|d| (d.name, d.line))
}

fn distance_to_segment(c: DVec2, a: DVec2, b: DVec2) -> f64 {
    let d = b - a;
    let len2 = d.length_squared();
    let t = if len2 > 0.0 {
        ((c - a).dot(d) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + d * t - c).length()
}

/// Whether `item`'s arc (or circle, or ellipse) enters the interior of `piece`, by more than
/// `tol`.
fn arc_enters(item: &Item, piece: &CurvedPiece, tol: f64) -> bool {
    let (Some((c2, r2)), Some((c, radius))) = (item.piece.circle(), piece.circle()) else {
        return conic_arc_enters(item, piece, tol);
    };
    let rho = radius - tol;
    if rho <= 0.0 {
        return false;
    }
    // The angles on the item's circle that lie inside the shrunk disc.
    let d = (c - c2).length();
    let inside = if d <= 1e-15 * (r2 + rho) {
        if r2 < rho { (0.0, TAU) } else { return false }
    } else {
        let k = (d * d + r2 * r2 - rho * rho) / (2.0 * d * r2);
        if k >= 1.0 {
            return false;
        }
        if k <= -1.0 {
            (0.0, TAU)
        } else {
            let half = k.acos();
            ((c - c2).to_angle() - half, 2.0 * half)
        }
    };
    let Some(h) = piece.chord() else {
        return !intersect(item.arc, inside).is_empty();
    };
    // The linear function's least value on each sub-arc: at its ends, or where the circle's
    // outward direction is −normal, if that lies in it.
    let limit = -tol * h.normal.length();
    let lowest = (-h.normal).to_angle();
    intersect(item.arc, inside).into_iter().any(|(s, w)| {
        let at = |a: f64| h.value(c2 + DVec2::from_angle(a) * r2);
        let mut least = at(s).min(at(s + w));
        if (lowest - s).rem_euclid(TAU) <= w {
            least = least.min(at(lowest));
        }
        least < limit
    })
}

/// Samples along an arc before the least ones are refined: enough that two crossings of a conic
/// (at most four in all) are rarely missed between samples, and the refinement finds the rest.
const ARC_SAMPLES: usize = 256;

/// [`arc_enters`] where either conic is an ellipse: the least, over the arc's parameter, of
/// `max(|local|² − ρ², chord)`, found on a grid of samples and refined about each local least
/// sample by golden-section search; the arc enters where that is negative.
fn conic_arc_enters(item: &Item, piece: &CurvedPiece, tol: f64) -> bool {
    let frame = piece.frame();
    let scale = frame.min_scale();
    let rho = 1.0 - tol / scale;
    if rho.is_nan() || rho <= 0.0 {
        return false;
    }
    let curve = item.piece.frame();
    let chord = piece.chord().map(|h| {
        let length = h.normal.length();
        (h, -tol * length, length * scale)
    });
    let value = |t: f64| {
        let p = curve.point(DVec2::from_angle(t));
        let inside = frame.local(p).length_squared() - rho * rho;
        match chord {
            None => inside,
            Some((h, limit, unit)) => inside.max((h.value(p) - limit) / unit),
        }
    };
    let (start, sweep) = item.arc;
    let step = sweep / ARC_SAMPLES as f64;
    let samples: Vec<f64> = (0..=ARC_SAMPLES)
        .map(|k| value(start + step * k as f64))
        .collect();
    if samples.iter().any(|&v| v < 0.0) {
        return true;
    }
    (0..=ARC_SAMPLES).any(|k| {
        let left = if k > 0 { samples[k - 1] } else { f64::INFINITY };
        let right = samples.get(k + 1).copied().unwrap_or(f64::INFINITY);
        if samples[k] > left || samples[k] > right {
            return false;
        }
        let t = start + step * k as f64;
        let (lo, hi) = ((t - step).max(start), (t + step).min(start + sweep));
        golden_minimum(&value, lo, hi) < 0.0
    })
}

/// The least value of `f` on `[lo, hi]` that golden-section search finds (exact for a function
/// with one minimum there, up to the interval's rounding).
fn golden_minimum(f: &impl Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
    let ratio = 0.5 * (5f64.sqrt() - 1.0);
    let mut x1 = hi - ratio * (hi - lo);
    let mut x2 = lo + ratio * (hi - lo);
    let (mut f1, mut f2) = (f(x1), f(x2));
    let mut least = f1.min(f2);
    for _ in 0..60 {
        if f1 < f2 {
            hi = x2;
            (x2, f2) = (x1, f1);
            x1 = hi - ratio * (hi - lo);
            f1 = f(x1);
        } else {
            lo = x1;
            (x1, f1) = (x2, f2);
            x2 = lo + ratio * (hi - lo);
            f2 = f(x2);
        }
        least = least.min(f1).min(f2);
        if least < 0.0 {
            break;
        }
    }
    least
}

/// The segment piece of an elliptic arc edge, as an item (its edge and line set by the caller);
/// `None` when it is thinner than the tolerance (its chord is the edge then).
fn elliptic_item(from: DVec2, to: DVec2, ellipse: &EllipticArc, tol: f64) -> Option<Item> {
    let mid = ellipse.midpoint(from, to);
    let chord = HalfPlane::left_of(from, to);
    let sagitta = chord.value(mid).abs() / chord.normal.length();
    if sagitta.is_nan() || sagitta <= tol {
        return None;
    }
    let chord = if chord.value(mid) < 0.0 {
        chord
    } else {
        chord.flipped()
    };
    let (first, second) = if ellipse.forward {
        (from, to)
    } else {
        (to, from)
    };
    let start = ellipse.param(first);
    let sweep = (ellipse.param(second) - start).rem_euclid(TAU);
    Some(Item {
        piece: CurvedPiece::EllipticSegment {
            center: ellipse.center,
            axes: ellipse.axes,
            chord,
        },
        arc: (start, if sweep == 0.0 { TAU } else { sweep }),
        own_edge: None,
        line: 0,
        name: "the elliptic arc",
    })
}

/// The intersection of two counter-clockwise angle intervals `(start, sweep)`.
fn intersect(a: (f64, f64), b: (f64, f64)) -> Vec<(f64, f64)> {
    let t = (b.0 - a.0).rem_euclid(TAU);
    let mut out = Vec::new();
    for shift in [t, t - TAU] {
        let lo = shift.max(0.0);
        let hi = (shift + b.1).min(a.1);
        if lo < hi {
            out.push((a.0 + lo, hi - lo));
        }
    }
    out
}

/// The piece's area: the frame's determinant times the area of its image in the unit circle.
fn area(piece: &CurvedPiece) -> f64 {
    let frame = piece.frame();
    let unit = match piece.chord() {
        None => std::f64::consts::PI,
        Some(chord) => {
            // The segment's area from the chord's distance to the centre (signed: positive when
            // the centre is outside the segment's half-plane).
            let (n, k) = frame.local_line(chord);
            let h = (k / n.length()).clamp(-1.0, 1.0);
            let theta = 2.0 * h.acos();
            0.5 * (theta - theta.sin())
        }
    };
    frame.det().abs() * unit
}

/// A point well inside the piece, where the parity is counted: among a few candidates inside it
/// (its centre and a ring for a disc; points between chord and arc for a segment), the one
/// farthest from every straight edge (chords included) and every circle applied before it.
fn deep_point(piece: &CurvedPiece, straights: &[Straight], before: &[Item], near: &Near) -> DVec2 {
    // Candidates are laid out in the piece's frame, where its conic is the unit circle.
    let frame = piece.frame();
    let mut local = Vec::new();
    match piece.chord() {
        None => {
            local.push(DVec2::ZERO);
            for k in 0..16 {
                let a = 0.3 + k as f64 * TAU / 16.0;
                local.push(DVec2::from_angle(a) * 0.5);
            }
        }
        Some(chord) => {
            // `n` points away from the segment; the chord's line is at signed distance `h` from
            // the centre along it, the arc's farthest point at 1 against it.
            let (normal, k) = frame.local_line(chord);
            let n = normal / normal.length();
            let h = k / normal.length();
            let (on_chord, on_arc) = (-n * h, -n);
            for f in [0.5, 0.3, 0.7, 0.15, 0.85] {
                let axis = on_chord + (on_arc - on_chord) * f;
                for g in [0.0, 0.3, -0.3, 0.6, -0.6] {
                    local.push(axis + n.perp() * g);
                }
            }
            local.push(0.5 * (on_chord + on_arc));
        }
    }
    let mut candidates: Vec<DVec2> = local.iter().map(|&l| frame.point(l)).collect();
    let fallback = candidates.pop().unwrap_or(frame.center);
    candidates.retain(|&p| piece.contains(p));
    if candidates.is_empty() {
        candidates.push(fallback);
    }
    // How far `p` is from a conic's boundary, at least: for a circle exactly, for an ellipse its
    // offset in the frame times the semi-minor axis.
    let from_conic = |conic: &CurvedPiece, p: DVec2| match conic.circle() {
        Some((c, r)) => ((p - c).length() - r).abs(),
        None => {
            let f = conic.frame();
            (f.local(p).length() - 1.0).abs() * f.min_scale()
        }
    };
    let clearance = |p: DVec2| {
        let mut d = from_conic(piece, p);
        if let Some(h) = piece.chord() {
            d = d.min(h.value(p).abs() / h.normal.length());
        }
        // Anything outside the piece's box is farther than the piece's own boundary.
        for &k in &near.straights {
            let s = &straights[k];
            d = d.min(distance_to_segment(p, s.a, s.b));
        }
        for &j in &near.done {
            d = d.min(from_conic(&before[j].piece, p));
        }
        d
    };
    candidates
        .into_iter()
        .map(|p| (clearance(p), p))
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .map_or(frame.center, |(_, p)| p)
}
