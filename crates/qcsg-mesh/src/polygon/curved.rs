//! Outlines of straight segments and quadratic Bézier arcs (TrueType glyphs) as a union of
//! convex cells, each cut by at most a few parabolas.
//!
//! A quadratic Bézier arc `P0, P1, P2` is a piece of a parabola, and the whole piece lies in the
//! triangle of its control points. In barycentric coordinates `λ` of that triangle the parabola
//! is `λ1² = 4 λ0 λ2`; its convex inside `λ1² − 4 λ0 λ2 ≤ 0` ([`BezierArc::conic`]) meets the side of
//! the chord `P0 P2` where `P1` lies in exactly the *lune* between the arc and its chord. As
//! chains, the arc is its chord plus the closed loop "arc, then chord back", whose winding number
//! is ±1 in the lune and 0 elsewhere; so the winding number of an outline is that of its chord
//! polygon plus the signed lunes that hold the point, and crossings of the arc along a segment are
//! counted exactly from the chord's (an exact predicate) and the lune membership of the two ends.
//!
//! The decomposition is [`super::bsp`]'s autopartition with one more kind of splitting line: an
//! arc's chord line. The part of the plane on `P1`'s side of the chord meets the parabola only
//! along the arc itself (the parabola crosses the chord's line at `P0` and `P2` only), so once a
//! region is known to lie on that side, the arc inside it is the parabola, and the region needs no
//! further cutting for it. A region that no straight edge touches and that lies on the `P1` side of
//! every arc touching it is finished: its points' winding number is the reference point's plus the
//! changes of lune membership, so the region becomes one cell per combination of the parabolas'
//! sides that is filled (one cell, with at most one parabola, unless lunes overlap).

use glam::DVec2;

use super::region::Piece;
use super::{HalfPlane, MAX_COORDINATE};
use crate::exact::orient2d;

/// A region with more rounded corners than this is halved by an axis-parallel line first.
const MAX_SIDES: usize = 6;

/// The most arcs one finished region may lie on the inner side of: the cells of a region are
/// the 2^k combinations of k parabolas' sides, so overlapping lunes are bounded.
pub const MAX_OVERLAPPING_ARCS: usize = 6;

/// A piece of an outline.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Segment {
    /// A straight edge from the first point to the second.
    Line(DVec2, DVec2),
    /// A quadratic Bézier arc from the first point to the third with the second as control point.
    Quad(DVec2, DVec2, DVec2),
}

/// How the outline's winding number decides what is inside.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FillRule {
    /// Inside where the winding number is odd.
    EvenOdd,
    /// Inside where the winding number is not zero.
    NonZero,
}

/// A quadratic Bézier arc that bounds some cell.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BezierArc {
    /// The start point.
    pub p0: DVec2,
    /// The control point (where the tangents at both ends meet).
    pub p1: DVec2,
    /// The end point.
    pub p2: DVec2,
}

impl BezierArc {
    /// The twice-signed areas `(o0, o1, o2)` = `D·λ` for the barycentric coordinates `λ` of `p`
    /// in the triangle `P0 P1 P2` (`D` its twice-signed area).
    fn weights(&self, p: DVec2) -> (f64, f64, f64) {
        let cross = |a: DVec2, b: DVec2, c: DVec2| (b - a).perp_dot(c - a);
        (
            cross(p, self.p1, self.p2),
            cross(self.p0, p, self.p2),
            cross(self.p0, self.p1, p),
        )
    }

    /// `D² (λ1² − 4 λ0 λ2)` at `p`: negative inside the parabola (its convex side), zero on it.
    pub fn value(&self, p: DVec2) -> f64 {
        let (o0, o1, o2) = self.weights(p);
        o1 * o1 - 4.0 * o0 * o2
    }

    /// The point at parameter `t` ∈ [0, 1].
    pub fn point(&self, t: f64) -> DVec2 {
        let s = 1.0 - t;
        self.p0 * (s * s) + self.p1 * (2.0 * s * t) + self.p2 * (t * t)
    }

    /// The parabola's inside as the conic `xx X² + yy Y² + xy XY + x X + y Y + c ≤ 0` in
    /// `(X, Y) = p − origin`, returned as `[xx, yy, xy, x, y, c]` and scaled so that the
    /// quadratic part has unit size (the value is then about a distance near the arc).
    pub fn conic(&self, origin: DVec2) -> [f64; 6] {
        // Each D·λᵢ is affine: nᵢ · X + cᵢ, with nᵢ its gradient.
        let (a, b, c) = (self.p0 - origin, self.p1 - origin, self.p2 - origin);
        // cross(p, b, c) = (b − p) × (c − p): gradient (b − c)⊥ … written out per term.
        let affine = |u: DVec2, v: DVec2| {
            // cross(X, u, v) = (u − X) × (v − X) = u × v − X × v − u × X = u×v + X·(…)
            let constant = u.perp_dot(v);
            // −X × v − u × X = −(X.x v.y − X.y v.x) − (u.x X.y − u.y X.x)
            let gradient = DVec2::new(-v.y + u.y, v.x - u.x);
            (gradient, constant)
        };
        // o0 = cross(X, b, c); o1 = cross(a, X, c) = cross(X, c, a); o2 = cross(a, b, X) = cross(X, a, b).
        let (n0, c0) = affine(b, c);
        let (n1, c1) = affine(c, a);
        let (n2, c2) = affine(a, b);
        let mut k = [
            n1.x * n1.x - 4.0 * n0.x * n2.x,
            n1.y * n1.y - 4.0 * n0.y * n2.y,
            2.0 * n1.x * n1.y - 4.0 * (n0.x * n2.y + n0.y * n2.x),
            2.0 * n1.x * c1 - 4.0 * (n0.x * c2 + c0 * n2.x),
            2.0 * n1.y * c1 - 4.0 * (n0.y * c2 + c0 * n2.y),
            c1 * c1 - 4.0 * c0 * c2,
        ];
        let size = k[0].abs() + k[1].abs() + k[2].abs();
        if size > 0.0 {
            for v in &mut k {
                *v /= size;
            }
        }
        k
    }
}

/// One side of an arc's parabola, as a literal of a cell.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ArcSide {
    /// The arc's index in [`CurvedRegion::arcs`].
    pub arc: usize,
    /// `true` for the parabola's inside (`BezierArc::value ≤ 0`), `false` for its outside.
    pub inside: bool,
}

/// A convex cell cut by parabolas: its half-planes and the sides of the arcs it keeps.
#[derive(Clone, Debug, PartialEq)]
pub struct CurvedCell {
    /// The half-planes whose intersection is the convex part.
    pub half_planes: Vec<HalfPlane>,
    /// The parabola sides the cell is also within (usually none or one).
    pub sides: Vec<ArcSide>,
    /// The lower corner of a box containing the cell.
    pub min: DVec2,
    /// The upper corner of a box containing the cell.
    pub max: DVec2,
}

impl CurvedCell {
    /// Whether `p` lies in the closed cell (rounded parabola values; for tests).
    pub fn contains(&self, p: DVec2, arcs: &[BezierArc]) -> bool {
        self.half_planes.iter().all(|h| h.contains(p))
            && self.sides.iter().all(|s| {
                let v = arcs[s.arc].value(p);
                if s.inside { v <= 0.0 } else { v >= 0.0 }
            })
    }
}

/// A curved outline's region: cells with disjoint interiors and the arcs they refer to.
#[derive(Clone, Debug, PartialEq)]
pub struct CurvedRegion {
    /// The arcs some cell is cut by.
    pub arcs: Vec<BezierArc>,
    /// The cells; empty for an empty region.
    pub cells: Vec<CurvedCell>,
    /// The lower corner of a box containing every cell (zero when empty).
    pub min: DVec2,
    /// The upper corner of a box containing every cell (zero when empty).
    pub max: DVec2,
}

impl CurvedRegion {
    /// Whether `p` lies in some cell (a linear scan: for tests).
    pub fn contains(&self, p: DVec2) -> bool {
        self.cells.iter().any(|c| c.contains(p, &self.arcs))
    }
}

/// Why an outline was refused.
#[derive(Clone, Debug, PartialEq)]
pub enum CurvedError {
    /// A point is not finite or beyond [`MAX_COORDINATE`].
    BadPoint,
    /// More than [`MAX_OVERLAPPING_ARCS`] lunes overlap in one place.
    TooManyOverlappingArcs,
}

impl std::fmt::Display for CurvedError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::BadPoint => write!(
                f,
                "a point of the outline is not finite or beyond the supported magnitude {MAX_COORDINATE:e}"
            ),
            Self::TooManyOverlappingArcs => write!(
                f,
                "more than {MAX_OVERLAPPING_ARCS} curved pieces of the outline overlap in one place"
            ),
        }
    }
}

impl std::error::Error for CurvedError {}

/// An edge of the outline: a straight one, or an arc with its chord.
#[derive(Clone, Copy, Debug)]
struct Edge {
    a: DVec2,
    b: DVec2,
    /// The half-plane left of `a → b` (for an arc, of its chord).
    line: HalfPlane,
    /// For an arc: its control point and the side of the chord `a → b` it lies on (+1 left).
    control: Option<(DVec2, i32)>,
    /// For an arc: at each end, the closed half-plane bounded by the line through the end normal
    /// to the arc's tangent there that holds the whole control triangle (`None` at an end whose
    /// triangle angle is not acute, where no such half-plane exists).
    ends: [Option<HalfPlane>; 2],
    /// For an arc: the closed half-planes of the tangent sides `a → control` and `control → b`
    /// of its control triangle that hold the triangle (a straight edge that joins the arc
    /// smoothly lies on one of these lines).
    tangents: [Option<HalfPlane>; 2],
}

impl Edge {
    /// Whether the piece lies beyond one of the arc's end lines or tangent sides (within
    /// `tolerance`): the arc's control triangle, and with it the chord and the lune, meets it at
    /// most along that line, and the arc itself at most in an end point.
    fn beyond_end(&self, piece: &Piece, tolerance: impl Fn(&HalfPlane) -> f64) -> bool {
        self.ends.iter().chain(&self.tangents).flatten().any(|h| {
            let slack = tolerance(h);
            piece.vertices.iter().all(|&v| h.value(v) >= -slack)
        })
    }

    fn arc(&self) -> Option<BezierArc> {
        self.control.map(|(p1, _)| BezierArc {
            p0: self.a,
            p1,
            p2: self.b,
        })
    }

    /// The winding number of the loop "arc, then chord back" at `p`: ±1 in the lune, else 0.
    fn lune_winding(&self, p: DVec2) -> i32 {
        let Some((p1, sign)) = self.control else {
            return 0;
        };
        let arc = BezierArc {
            p0: self.a,
            p1,
            p2: self.b,
        };
        // Forward along the arc on the chord's `sign` side and back along the chord: the loop
        // turns clockwise when that side is the left.
        if orient2d(self.a, self.b, p) == sign && arc.value(p) < 0.0 {
            -sign
        } else {
            0
        }
    }
}

/// The signed crossing of the directed edge `a → b` by the segment `p → q` (+1 when `q` ends on
/// the edge's left), with [`crate::exact::segment_crosses_edge`]'s simulation of simplicity.
fn signed_crossing(p: DVec2, q: DVec2, a: DVec2, b: DVec2) -> i32 {
    if !crate::exact::segment_crosses_edge(p, q, a, b) {
        return 0;
    }
    let edge_tie = if b.y != a.y { a.y > b.y } else { b.x > a.x };
    let left = match orient2d(a, b, q) {
        0 => edge_tie,
        s => s > 0,
    };
    if left { 1 } else { -1 }
}

/// A region awaiting its split.
struct Region {
    piece: Piece,
    reference: DVec2,
    winding: i32,
    /// Straight edges and arcs whose chord side is not yet known.
    edges: Vec<u32>,
    /// Arcs the region lies on the control point's side of.
    settled: Vec<u32>,
}

/// The region enclosed by closed `contours` under `rule`, as convex cells cut by parabolas.
///
/// A contour whose end is not its start is closed by a straight edge. Arcs whose control point is
/// on the chord's line are straight edges (their curve runs along the chord, there and back).
pub fn curved_cells(
    contours: &[Vec<Segment>],
    rule: FillRule,
) -> Result<CurvedRegion, CurvedError> {
    let edges = outline_edges(contours)?;
    Ok(decompose(&edges, rule, false)?.0)
}

/// The complement of an outline's region: everything outside the box `min..max` (which holds
/// every point and control point of the outline), and within it the cells `rule` leaves
/// unfilled. Its cells come from the same partition as [`curved_cells`]' and share its lines
/// and parabolas, with the opposite sides.
#[derive(Clone, Debug, PartialEq)]
pub struct CurvedComplement {
    /// The unfilled cells within the box (`region.min`/`region.max` bound those cells only).
    pub region: CurvedRegion,
    /// The lower corner of the partitioned box.
    pub min: DVec2,
    /// The upper corner of the partitioned box.
    pub max: DVec2,
}

/// The complement of the region enclosed by `contours` under `rule` ([`CurvedComplement`]);
/// `None` when the outline encloses nothing (its complement is the whole plane).
pub fn curved_complement_cells(
    contours: &[Vec<Segment>],
    rule: FillRule,
) -> Result<Option<CurvedComplement>, CurvedError> {
    let edges = outline_edges(contours)?;
    let (region, partitioned) = decompose(&edges, rule, true)?;
    Ok(partitioned.map(|(min, max)| CurvedComplement { region, min, max }))
}

/// The outline's edges: contours closed, flat arcs made straight, empty pieces dropped.
fn outline_edges(contours: &[Vec<Segment>]) -> Result<Vec<Edge>, CurvedError> {
    let mut edges: Vec<Edge> = Vec::new();
    let line = |a: DVec2, b: DVec2| Edge {
        a,
        b,
        line: HalfPlane::left_of(a, b),
        control: None,
        ends: [None, None],
        tangents: [None, None],
    };
    for contour in contours {
        let (Some(first), Some(last)) = (contour.first(), contour.last()) else {
            continue;
        };
        let start = match *first {
            Segment::Line(a, _) | Segment::Quad(a, _, _) => a,
        };
        let end = match *last {
            Segment::Line(_, b) | Segment::Quad(_, _, b) => b,
        };
        let closing = (end != start).then_some(Segment::Line(end, start));
        for segment in contour.iter().copied().chain(closing) {
            let points = match segment {
                Segment::Line(a, b) => vec![a, b],
                Segment::Quad(a, c, b) => vec![a, c, b],
            };
            if points
                .iter()
                .any(|p| !p.is_finite() || p.abs().max_element() > MAX_COORDINATE)
            {
                return Err(CurvedError::BadPoint);
            }
            match segment {
                Segment::Line(a, b) if a != b => edges.push(line(a, b)),
                // A control point on the chord's line, or within rounding of it, makes a flat
                // arc: its parabola degenerates to the chord's line doubled, whose sides no
                // rounded value can tell, so it is the straight edge it draws.
                Segment::Quad(a, c, b) if a != b && nearly_flat(a, c, b) => edges.push(line(a, b)),
                Segment::Quad(a, c, b) if a != b => match orient2d(a, b, c) {
                    0 => edges.push(line(a, b)),
                    _ => {
                        for (a, c, b) in acute_pieces(a, c, b) {
                            match orient2d(a, b, c) {
                                _ if nearly_flat(a, c, b) => edges.push(line(a, b)),
                                0 => edges.push(line(a, b)),
                                sign => edges.push(Edge {
                                    a,
                                    b,
                                    line: HalfPlane::left_of(a, b),
                                    control: Some((c, sign)),
                                    ends: [end_line(a, c, b), end_line(b, c, a)],
                                    tangents: [tangent_side(a, c, b), tangent_side(c, b, a)],
                                }),
                            }
                        }
                    }
                },
                // An arc from a point back to itself encloses nothing.
                _ => {}
            }
        }
    }
    Ok(edges)
}

/// The partition's state.
struct Partition<'a> {
    edges: &'a [Edge],
    rule: FillRule,
    /// Whether the cells wanted are the unfilled ones.
    complement: bool,
    magnitude: f64,
    min: DVec2,
    max: DVec2,
    /// The index in the output's arcs of each edge that is an arc, once used.
    arc_index: Vec<Option<usize>>,
    arcs: Vec<BezierArc>,
    cells: Vec<CurvedCell>,
}

/// The cells of the outline `edges` under `rule` (the unfilled ones if `complement`), and the box
/// partitioned (`None` when the outline has no area, so that nothing is filled).
fn decompose(
    edges: &[Edge],
    rule: FillRule,
    complement: bool,
) -> Result<(CurvedRegion, Option<(DVec2, DVec2)>), CurvedError> {
    let empty = CurvedRegion {
        arcs: Vec::new(),
        cells: Vec::new(),
        min: DVec2::ZERO,
        max: DVec2::ZERO,
    };
    if edges.is_empty() {
        return Ok((empty, None));
    }
    let (min, max) = edges.iter().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), e| {
            let c = e.control.map_or(e.a, |(c, _)| c);
            (lo.min(e.a).min(e.b).min(c), hi.max(e.a).max(e.b).max(c))
        },
    );
    if min.x == max.x || min.y == max.y {
        return Ok((empty, None));
    }
    // The box is kept clear of the outline: a wall through an extreme point of a curve would
    // stay a side of the cell that holds the curve there, a plane touching the parabola along a
    // line, whose two sides eq. 22 cannot tell apart near it.
    let margin = DVec2::splat((max - min).max_element() / 16.0);
    let (min, max) = (min - margin, max + margin);
    let mut partition = Partition {
        edges,
        rule,
        complement,
        magnitude: min.abs().max(max.abs()).max_element(),
        min,
        max,
        arc_index: vec![None; edges.len()],
        arcs: Vec::new(),
        cells: Vec::new(),
    };
    let outside = min - (max - min) * DVec2::new(0.25, 0.375);
    let piece = Piece::from_box(min, max);
    let reference = piece.interior_point();
    let all: Vec<u32> = (0..edges.len() as u32).collect();
    let winding = partition.winding_change(outside, reference, &all);
    partition.run(Region {
        piece,
        reference,
        winding,
        edges: all,
        settled: Vec::new(),
    })?;
    let cells = partition.cells;
    let (min, max) = if cells.is_empty() {
        (DVec2::ZERO, DVec2::ZERO)
    } else {
        cells.iter().fold(
            (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
            |(lo, hi), c| (lo.min(c.min), hi.max(c.max)),
        )
    };
    let partitioned = (partition.min, partition.max);
    Ok((
        CurvedRegion {
            arcs: partition.arcs,
            cells,
            min,
            max,
        },
        Some(partitioned),
    ))
}

/// The order in which edges split: a fixed scramble of their indices.
fn priority(index: u32) -> u64 {
    let mut z = u64::from(index).wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

impl Partition<'_> {
    fn tolerance(&self, line: &HalfPlane) -> f64 {
        64.0 * f64::EPSILON
            * ((line.normal.x.abs() + line.normal.y.abs()) * self.magnitude + line.offset.abs())
    }

    /// Whether a winding number makes a wanted cell: filled, or unfilled for the complement.
    fn filled(&self, winding: i32) -> bool {
        let filled = match self.rule {
            FillRule::EvenOdd => winding % 2 != 0,
            FillRule::NonZero => winding != 0,
        };
        filled != self.complement
    }

    /// The change of winding number from `p` to `q` over the edges in `list` (the segment must
    /// not leave the region those edges were gathered for).
    fn winding_change(&self, p: DVec2, q: DVec2, list: &[u32]) -> i32 {
        list.iter()
            .map(|&i| {
                let e = &self.edges[i as usize];
                signed_crossing(p, q, e.a, e.b) + e.lune_winding(q) - e.lune_winding(p)
            })
            .sum()
    }

    /// Whether the edge (for an arc, its control triangle) may touch the piece. An arc that
    /// meets the piece only in an end point, the piece lying beyond the line normal to the arc
    /// there, does not: so the two cells on either side of that line at the join of two tangent
    /// arcs keep one arc each, not two parabolas that stay close over a stretch.
    fn may_touch(&self, piece: &Piece, edge: &Edge) -> bool {
        let tolerance = |h: &HalfPlane| self.tolerance(h);
        match edge.control {
            None => piece.may_touch(edge.a, edge.b, tolerance),
            Some(_) if edge.beyond_end(piece, tolerance) => false,
            Some((c, _)) => {
                piece.may_touch(edge.a, edge.b, tolerance)
                    || piece.may_touch(edge.a, c, tolerance)
                    || piece.may_touch(c, edge.b, tolerance)
                    || inside_triangle(piece.interior_point(), edge.a, c, edge.b)
            }
        }
    }

    fn run(&mut self, root: Region) -> Result<(), CurvedError> {
        let mut stack = vec![root];
        while let Some(mut region) = stack.pop() {
            if region.piece.vertices.len() > MAX_SIDES {
                let line = halving_line(&region.piece);
                if let Some((low, high)) = region.piece.split(line, self.tolerance(&line)) {
                    stack.extend(self.children(&region, low, high, None));
                    continue;
                }
            }
            let Some(&splitter) = region.edges.iter().min_by_key(|&&i| priority(i)) else {
                if let Some((low, high)) = self.end_split(&region) {
                    stack.extend(self.children(&region, low, high, None));
                } else {
                    self.finish(region)?;
                }
                continue;
            };
            let edge = self.edges[splitter as usize];
            // An arc's end lines first: its chord's line then cuts only the slab between them,
            // which holds the arc's triangle, and never runs on past the arc's end into the
            // cells of the next arc, which it would cross at the small angle of its turn.
            let end_cut = edge
                .ends
                .iter()
                .flatten()
                .find_map(|&h| region.piece.split(h, self.tolerance(&h)));
            if let Some((low, high)) = end_cut {
                stack.extend(self.children(&region, low, high, None));
                continue;
            }
            match region.piece.split(edge.line, self.tolerance(&edge.line)) {
                Some((low, high)) => {
                    stack.extend(self.children(&region, low, high, Some(splitter)));
                }
                None => {
                    region.edges.retain(|&i| i != splitter);
                    if let Some((_, sign)) = edge.control {
                        // The whole piece lies on one side of the chord's line.
                        let side: f64 = region
                            .piece
                            .vertices
                            .iter()
                            .map(|&v| edge.line.value(v))
                            .sum();
                        // `line` holds the chord's left; the control point is left when sign > 0.
                        if (side < 0.0) == (sign > 0) {
                            region.settled.push(splitter);
                        }
                    }
                    stack.push(region);
                }
            }
        }
        Ok(())
    }

    /// For a finished region on the inner side of several arcs, its split by an end line of one
    /// of them (the line through the end normal to the arc's tangent), if one cuts it: the arcs
    /// that join there fall on different sides, each child keeping one.
    fn end_split(&self, region: &Region) -> Option<(Piece, Piece)> {
        if region.settled.len() < 2 {
            return None;
        }
        region.settled.iter().find_map(|&i| {
            self.edges[i as usize]
                .ends
                .iter()
                .flatten()
                .find_map(|&h| region.piece.split(h, self.tolerance(&h)))
        })
    }

    /// The cells of a region that no straight edge touches and that lies on the inner side of
    /// the chords of its arcs.
    fn finish(&mut self, region: Region) -> Result<(), CurvedError> {
        let arcs = region.settled;
        if arcs.len() > MAX_OVERLAPPING_ARCS {
            return Err(CurvedError::TooManyOverlappingArcs);
        }
        // The winding number at a point is `base` plus the signed lunes that hold it.
        let mut base = region.winding;
        for &i in &arcs {
            base -= self.edges[i as usize].lune_winding(region.reference);
        }
        let signs: Vec<i32> = arcs
            .iter()
            .map(|&i| self.edges[i as usize].control.map_or(0, |(_, s)| -s))
            .collect();
        let combinations = 1usize << arcs.len();
        let filled: Vec<bool> = (0..combinations)
            .map(|mask| {
                let w = base
                    + (0..arcs.len())
                        .filter(|k| mask & (1 << k) != 0)
                        .map(|k| signs[k])
                        .sum::<i32>();
                self.filled(w)
            })
            .collect();
        if !filled.iter().any(|&f| f) {
            return Ok(());
        }
        let pad = 1e-12 * self.magnitude.max(f64::MIN_POSITIVE);
        let (lo, hi) = region.piece.bounds();
        let (min, max) = ((lo - pad).max(self.min), (hi + pad).min(self.max));
        let planes = region.piece.planes;
        if filled.iter().all(|&f| f) {
            self.cells.push(CurvedCell {
                half_planes: planes,
                sides: Vec::new(),
                min,
                max,
            });
            return Ok(());
        }
        let indices: Vec<usize> = arcs.iter().map(|&i| self.arc_output(i)).collect();
        for (mask, _) in filled.iter().enumerate().filter(|(_, f)| **f) {
            // An arc whose side does not matter for this combination's neighbour is still kept:
            // the cells of one region stay disjoint.
            let sides: Vec<ArcSide> = indices
                .iter()
                .enumerate()
                .map(|(k, &arc)| ArcSide {
                    arc,
                    inside: mask & (1 << k) != 0,
                })
                .collect();
            // Inside a parabola the piece keeps only its lune, which lies in the arc's control
            // triangle: the cell's box need not reach the rest of the piece.
            let (mut lo, mut hi) = (min, max);
            for side in sides.iter().filter(|s| s.inside) {
                let arc = &self.arcs[side.arc];
                lo = lo.max(arc.p0.min(arc.p1).min(arc.p2) - pad);
                hi = hi.min(arc.p0.max(arc.p1).max(arc.p2) + pad);
            }
            if lo.cmpgt(hi).any() {
                // Lunes whose triangles are apart: the combination holds no point.
                continue;
            }
            self.cells.push(CurvedCell {
                half_planes: planes.clone(),
                sides,
                min: lo,
                max: hi,
            });
        }
        Ok(())
    }

    /// The index in the output of the arc of edge `i`, added on first use.
    fn arc_output(&mut self, i: u32) -> usize {
        if let Some(k) = self.arc_index[i as usize] {
            return k;
        }
        let arc = self.edges[i as usize]
            .arc()
            .expect("a settled edge is an arc");
        self.arcs.push(arc);
        let k = self.arcs.len() - 1;
        self.arc_index[i as usize] = Some(k);
        k
    }

    fn children(
        &mut self,
        parent: &Region,
        low: Piece,
        high: Piece,
        splitter: Option<u32>,
    ) -> [Region; 2] {
        let split_line = splitter.map(|s| self.edges[s as usize]);
        // Straight edges exactly on the splitting line lie on the wall between the children.
        let on_wall = |edge: &Edge| match split_line {
            Some(s) => {
                edge.control.is_none()
                    && orient2d(s.a, s.b, edge.a) == 0
                    && orient2d(s.a, s.b, edge.b) == 0
            }
            None => false,
        };
        let kept: Vec<u32> = parent
            .edges
            .iter()
            .copied()
            .filter(|&i| Some(i) != splitter && !on_wall(&self.edges[i as usize]))
            .collect();
        let mut all = parent.edges.clone();
        all.extend_from_slice(&parent.settled);
        // `low` is the side inside the splitting half-plane (left of the chord).
        [(low, true), (high, false)].map(|(mut piece, left)| {
            piece.prune(|h| self.tolerance(h));
            let mut edges: Vec<u32> = kept
                .iter()
                .copied()
                .filter(|&i| self.may_touch(&piece, &self.edges[i as usize]))
                .collect();
            let mut settled: Vec<u32> = parent
                .settled
                .iter()
                .copied()
                .filter(|&i| self.may_touch(&piece, &self.edges[i as usize]))
                .collect();
            if let Some(s) = split_line
                && let Some((_, sign)) = s.control
                && (sign > 0) == left
                && self.may_touch(&piece, &s)
            {
                settled.push(splitter.expect("a split line comes from an edge"));
            }
            edges.sort_unstable();
            let reference = piece.interior_point();
            let winding = parent.winding + self.winding_change(parent.reference, reference, &all);
            settled.sort_unstable();
            Region {
                piece,
                reference,
                winding,
                edges,
                settled,
            }
        })
    }
}

/// Whether the control point `c` lies within rounding of the chord `a b`'s line: the arc bulges
/// by half of `c`'s distance from the chord, here below about 1e-12 of its size.
fn nearly_flat(a: DVec2, c: DVec2, b: DVec2) -> bool {
    let chord = b - a;
    let scale = chord.length() * ((c - a).length() + (c - b).length());
    (c - a).perp_dot(chord).abs() <= 1e-12 * scale
}

/// The closed half-plane bounded by the line through `end` normal to the tangent `end → control`
/// that holds the triangle `end control other`, or `None` when the triangle's angle at `end` is
/// not clearly acute (the other end is then not on the control point's side of that line).
fn end_line(end: DVec2, control: DVec2, other: DVec2) -> Option<HalfPlane> {
    let normal = end - control;
    let reach = (other - end).dot(control - end);
    // Well clear of a right angle, so that the rounded half-plane still holds the triangle.
    (reach > 1e-6 * normal.length() * (other - end).length()).then(|| HalfPlane {
        normal,
        offset: normal.dot(end),
    })
}

/// The closed half-plane bounded by the line through `from` and `to` that holds `other` (a side
/// of a triangle and the triangle).
fn tangent_side(from: DVec2, to: DVec2, other: DVec2) -> Option<HalfPlane> {
    let h = HalfPlane::left_of(from, to);
    match orient2d(from, to, other) {
        0 => None,
        s if s > 0 => Some(h),
        _ => Some(h.flipped()),
    }
}

/// The arc `a c b` as pieces of the same parabola whose triangles have acute angles at both ends:
/// halved by de Casteljau at the middle (exact up to rounding of the new points) while an end's
/// angle is not acute, at most twice.
fn acute_pieces(a: DVec2, c: DVec2, b: DVec2) -> Vec<(DVec2, DVec2, DVec2)> {
    let mut out = Vec::new();
    let mut todo = vec![(a, c, b, 0)];
    while let Some((a, c, b, depth)) = todo.pop() {
        if depth < 2 && (end_line(a, c, b).is_none() || end_line(b, c, a).is_none()) {
            let (ac, cb) = ((a + c) * 0.5, (c + b) * 0.5);
            let middle = (ac + cb) * 0.5;
            todo.push((middle, cb, b, depth + 1));
            todo.push((a, ac, middle, depth + 1));
        } else {
            out.push((a, c, b));
        }
    }
    out
}

/// Whether `p` lies in the closed triangle `a b c` (either orientation).
fn inside_triangle(p: DVec2, a: DVec2, b: DVec2, c: DVec2) -> bool {
    let (s0, s1, s2) = (orient2d(a, b, p), orient2d(b, c, p), orient2d(c, a, p));
    (s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0)
}

/// An axis-parallel line through the middle of the piece's longer extent.
fn halving_line(piece: &Piece) -> HalfPlane {
    let (lo, hi) = piece.bounds();
    let middle = 0.5 * (lo + hi);
    if hi.x - lo.x >= hi.y - lo.y {
        HalfPlane {
            normal: DVec2::X,
            offset: middle.x,
        }
    } else {
        HalfPlane {
            normal: DVec2::Y,
            offset: middle.y,
        }
    }
}

#[cfg(test)]
mod tests;
