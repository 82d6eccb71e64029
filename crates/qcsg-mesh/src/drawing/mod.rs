//! A drawing's region with OpenSCAD's fill rule, exactly: the even–odd region of all its paths
//! and circles, as straight cells plus discs and circular segments combined in order.
//!
//! A path with arcs bounds the same even–odd region as its chord polygon XOR, for each arc, the
//! circular segment between the arc and its chord (the closed curve arc + chord bounds exactly
//! that segment). So the region is `P ⊕ C₁ ⊕ … ⊕ Cₙ`: `P` the even–odd region of every chord
//! polygon ([`polygon_cells`]), `Cᵢ` the full circles' discs and the arcs' segments (a disc cut by
//! the chord's half-plane on the arc's side).
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
use crate::formats::{Drawing, DrawingPath};
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
}

impl CurvedPiece {
    fn center(&self) -> DVec2 {
        match *self {
            Self::Disc { center, .. } | Self::Segment { center, .. } => center,
        }
    }

    fn radius(&self) -> f64 {
        match *self {
            Self::Disc { radius, .. } | Self::Segment { radius, .. } => radius,
        }
    }

    fn chord(&self) -> Option<HalfPlane> {
        match *self {
            Self::Disc { .. } => None,
            Self::Segment { chord, .. } => Some(chord),
        }
    }

    /// Whether `p` lies in the open piece.
    pub fn contains(&self, p: DVec2) -> bool {
        (p - self.center()).length_squared() < self.radius() * self.radius()
            && self.chord().is_none_or(|h| h.value(p) < 0.0)
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
                "too many arcs and circles to compose exactly (stopped at DXF line {line})"
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
    /// The circle's arc as an angle interval `(start, sweep)`, counter-clockwise.
    arc: (f64, f64),
    /// The chord's position among the straight edges, for a segment.
    own_edge: Option<usize>,
    line: usize,
    name: &'static str,
}

impl Item {
    /// A box around the piece (its circle's).
    fn bounds(&self) -> (DVec2, DVec2) {
        let (c, r) = (self.piece.center(), self.piece.radius());
        (c - r, c + r)
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
    let mut edge_index = 0;
    for path in &drawing.paths {
        for e in &path.edges {
            let own = edge_index;
            edge_index += 1;
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
                chord: e.arc.is_some(),
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
    let c = item.piece.center();
    let r = item.piece.radius() - tol;
    if r <= 0.0 {
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
        if distance_to_segment(c, a, b) < r {
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

/// Whether `item`'s arc (or circle) enters the interior of `piece`, by more than `tol`.
fn arc_enters(item: &Item, piece: &CurvedPiece, tol: f64) -> bool {
    let (c2, r2) = (item.piece.center(), item.piece.radius());
    let (c, rho) = (piece.center(), piece.radius() - tol);
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

fn area(piece: &CurvedPiece) -> f64 {
    match *piece {
        CurvedPiece::Disc { radius, .. } => std::f64::consts::PI * radius * radius,
        CurvedPiece::Segment {
            center,
            radius,
            chord,
        } => {
            // The segment's area from the chord's distance to the centre (signed: positive when
            // the centre is outside the segment's half-plane).
            let h = (chord.value(center) / chord.normal.length()).clamp(-radius, radius);
            let theta = 2.0 * (h / radius).acos();
            0.5 * radius * radius * (theta - theta.sin())
        }
    }
}

/// A point well inside the piece, where the parity is counted: among a few candidates inside it
/// (its centre and a ring for a disc; points between chord and arc for a segment), the one
/// farthest from every straight edge (chords included) and every circle applied before it.
fn deep_point(piece: &CurvedPiece, straights: &[Straight], before: &[Item], near: &Near) -> DVec2 {
    let (center, radius) = (piece.center(), piece.radius());
    let mut candidates = Vec::new();
    match piece.chord() {
        None => {
            candidates.push(center);
            for k in 0..16 {
                let a = 0.3 + k as f64 * TAU / 16.0;
                candidates.push(center + DVec2::from_angle(a) * (0.5 * radius));
            }
        }
        Some(chord) => {
            // `n` points away from the segment; the chord's line is at signed distance `h` from
            // the centre along it, the arc's farthest point at `radius` against it.
            let n = chord.normal / chord.normal.length();
            let h = chord.value(center) / chord.normal.length();
            let (on_chord, on_arc) = (center - n * h, center - n * radius);
            for f in [0.5, 0.3, 0.7, 0.15, 0.85] {
                let axis = on_chord + (on_arc - on_chord) * f;
                for g in [0.0, 0.3, -0.3, 0.6, -0.6] {
                    let p = axis + n.perp() * (g * radius);
                    if piece.contains(p) {
                        candidates.push(p);
                    }
                }
            }
            if candidates.is_empty() {
                candidates.push(0.5 * (on_chord + on_arc));
            }
        }
    }
    let clearance = |p: DVec2| {
        let mut d = ((p - center).length() - radius).abs();
        if let Some(h) = piece.chord() {
            d = d.min(h.value(p).abs() / h.normal.length());
        }
        // Anything outside the piece's box is farther than the piece's own boundary.
        for &k in &near.straights {
            let s = &straights[k];
            d = d.min(distance_to_segment(p, s.a, s.b));
        }
        for &j in &near.done {
            let item = &before[j];
            let c = item.piece.center();
            d = d.min(((p - c).length() - item.piece.radius()).abs());
        }
        d
    };
    candidates
        .into_iter()
        .map(|p| (clearance(p), p))
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .map_or(center, |(_, p)| p)
}
