//! The CPU reference ray tracer: exact CSG classification of a ray against a DNF.
//!
//! Per term whose box the ray crosses (found in an R-tree of the boxes, [`BoxIndex`], or for
//! a frame's rays in the list of their square of pixels, [`FrameTiles`](crate::tiles::FrameTiles)),
//! the ray is clipped to the term's box, then the inside-sets of the term's literals along it are
//! intersected ([`interval`](crate::interval)); the terms' sets are united and the first point
//! where the ray enters the union (in front of its start) is the hit. The quadric
//! that bounds the interval there gives the normal — its gradient, which is outward because
//! complements are folded into the literal's sign — and the colour. Intervals that merely
//! touch are merged, so touching solids show no inner faces; tangent roots and zero-length
//! intervals make no surface. A term is left out where the ray misses the box of where it may
//! hold ([`crate::cull`]), and of a term of several literals only those that may fail along the
//! ray are read; a literal read in several terms is crossed once per ray
//! ([`RayRoots`](crate::interval::RayRoots)).
//!
//! Literals are intersected through the surfaces the compiler found them on
//! ([`qcsg_csg::coincident`]), so literals of one surface cross it at one parameter: a hit is
//! where the solid's membership changes across the surface, taking all of them as crossing at
//! once. A cutter flush with a part's face shows the face where the solid ends there and
//! nothing where it goes on, never a speckle of both.

use qcsg_csg::quadric_box::{BoxClass, classify};
use qcsg_csg::{Aabb, BoxIndex, Dnf, Term};
use qcsg_quadric::{DVec3, Quadric};
use rayon::prelude::*;

use crate::eye::EyeValues;

use crate::interval::{Boundary, Interval, RayRoots, intersect_into, surface_literal_intervals};
use crate::tiles::{Square, TermBoxes};

/// A ray `origin + t · direction`, `t ≥ 0`; the direction is unit length for the renderer, so
/// that `t` is a distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Where it starts.
    pub origin: DVec3,
    /// Where it goes.
    pub direction: DVec3,
}

impl Ray {
    /// The point at parameter `t`.
    #[inline]
    pub fn at(&self, t: f64) -> DVec3 {
        self.origin + t * self.direction
    }

    /// The parameter range `[t_in, t_out]` in which the ray lies in `bounds` (either may be
    /// infinite), or `None` if it misses the box.
    pub fn clip_to(&self, bounds: &Aabb) -> Option<(f64, f64)> {
        if bounds.is_empty() {
            return None;
        }
        let (mut t_in, mut t_out) = (f64::NEG_INFINITY, f64::INFINITY);
        for axis in 0..3 {
            let (o, d) = (self.origin[axis], self.direction[axis]);
            let (lo, hi) = (bounds.min[axis], bounds.max[axis]);
            if d == 0.0 {
                if o < lo || o > hi {
                    return None;
                }
                continue;
            }
            let (a, b) = ((lo - o) / d, (hi - o) / d);
            let (near, far) = if a <= b { (a, b) } else { (b, a) };
            // NaN from an infinite bound minus an infinite origin never narrows the range.
            if near > t_in {
                t_in = near;
            }
            if far < t_out {
                t_out = far;
            }
        }
        (t_in <= t_out).then_some((t_in, t_out))
    }
}

/// Where a ray enters a solid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// The ray parameter of the entry point.
    pub t: f64,
    /// The entry point.
    pub point: DVec3,
    /// The outward unit normal of the solid there.
    pub normal: DVec3,
    /// The DNF quadric whose surface it is; `None` on a face of the term's box (a solid cut by
    /// the DNF's region).
    pub quadric: Option<u32>,
    /// The term whose interval begins there.
    pub term: u32,
}

impl Hit {
    /// The hit of `ray` on the surface of `quadric` (an index into `dnf`'s quadrics) at
    /// parameter `t`, for renderers that find `t` by other means: the point and the normal are
    /// computed here in f64, exactly as the ray tracer computes them. `None` if the quadric does
    /// not exist.
    pub fn on_quadric(dnf: &Dnf, ray: &Ray, t: f64, quadric: u32, term: u32) -> Option<Self> {
        let surface = &dnf.quadrics.get(quadric as usize)?.quadric;
        let point = ray.at(t);
        Some(Self {
            t,
            point,
            normal: surface.normal(point).unwrap_or(-ray.direction),
            quadric: Some(quadric),
            term,
        })
    }
}

/// Buffers reused from ray to ray, so that tracing allocates nothing in the steady state.
#[derive(Clone, Debug, Default)]
pub struct Scratch {
    terms: Vec<u32>,
    entries: Vec<Entry>,
    deferred: Vec<Entry>,
    term: TermBuffers,
    all: Vec<(Interval, u32)>,
}

/// Where a ray enters and leaves a term's box, the term, and its position in the square's list
/// ([`NO_SQUARE`] when the terms were not taken from a square).
type Entry = (f64, f64, u32, u32);

/// The position of a term found without a square.
const NO_SQUARE: u32 = u32::MAX;

/// The buffers of one term's intervals along a ray.
#[derive(Clone, Debug, Default)]
struct TermBuffers {
    literals: Vec<u32>,
    current: Vec<Interval>,
    literal: Vec<Interval>,
    merged: Vec<Interval>,
    roots: RayRoots,
    /// Per term, the literal that last left it empty along a ray (`u32::MAX`: none), read
    /// first by the next ray: neighbouring rays mostly leave a term through the same literal.
    emptied_by: Vec<u32>,
}

/// What `dnf`'s rays look at ([`TermIndex`]), with literal boxes for the terms of more than
/// [`LITERAL_INDEX_ABOVE`] literals.
pub fn term_index(dnf: &Dnf) -> TermIndex {
    TermIndex::new(dnf, LITERAL_INDEX_ABOVE)
}

/// Terms with more literals than this keep where each literal may fail.
pub const LITERAL_INDEX_ABOVE: usize = 4;

/// Terms with more literals than this keep those boxes in an R-tree; the others in a list,
/// which a ray walks (cheaper than a tree search for a few boxes).
const LITERAL_TREE_ABOVE: usize = 32;

/// What a ray looks at: the term boxes, each grown a little so that a face lying on the box (a
/// cube's slab) is met as the quadric's root, not as the box, in an R-tree (a ray looks only
/// at the terms whose box it crosses); and, for a term of several literals (a block drilled
/// with holes, a plate with many), a box around where each literal fails within the term's
/// box (a ray intersects only the literals whose box it crosses: it lies inside the others
/// throughout).
#[derive(Clone, Debug)]
pub struct TermIndex {
    boxes: BoxIndex,
    /// Per term, a box around where it may hold, when smaller than its box
    /// ([`crate::cull`]); the boxes of a frame's squares of pixels are these.
    holds: Vec<Option<Aabb>>,
    /// Per term, the box of `holds` or else the term's box.
    square_boxes: Vec<Aabb>,
    literals: Vec<Option<TermLiterals>>,
}

/// Where each literal of a term may fail, and the literals (DNF quadric ids, the term's).
#[derive(Clone, Debug)]
struct TermLiterals {
    boxes: LiteralBoxes,
    ids: Vec<u32>,
}

/// Where each literal of a term may fail.
#[derive(Clone, Debug)]
enum LiteralBoxes {
    /// In an R-tree, for a term of many literals.
    Indexed(BoxIndex),
    /// In the term's order, for a term of a few.
    Listed(Vec<Aabb>),
}

impl LiteralBoxes {
    /// The boxes, in the term's literal order.
    fn all(&self) -> &[Aabb] {
        match self {
            Self::Indexed(index) => index.boxes(),
            Self::Listed(boxes) => boxes,
        }
    }

    /// Writes into `out` the positions, ascending, of the literals whose box `meets` accepts.
    fn select(&self, meets: impl Fn(&Aabb) -> bool, out: &mut Vec<u32>) {
        match self {
            Self::Indexed(index) => {
                index.select(meets, out);
                out.sort_unstable();
            }
            Self::Listed(boxes) => out.extend(
                boxes
                    .iter()
                    .enumerate()
                    .filter(|(_, b)| !b.is_empty() && meets(b))
                    .map(|(k, _)| k as u32),
            ),
        }
    }
}

impl TermIndex {
    /// The terms' boxes, grown a little, as rays test them.
    pub fn boxes(&self) -> &[Aabb] {
        self.boxes.boxes()
    }

    /// The index of `dnf`, with literal boxes for terms of more than `literals_above` literals.
    pub fn new(dnf: &Dnf, literals_above: usize) -> Self {
        Self::build(dnf, literals_above, true)
    }

    /// [`TermIndex::new`], with boxes of where each term may hold if `cull`.
    fn build(dnf: &Dnf, literals_above: usize, cull: bool) -> Self {
        let boxes = padded_boxes(dnf);
        let large = large_terms(&boxes);
        // Each term's bisections are its own: the terms are shared out among the threads, as a
        // scene of thousands of cells (an imported mesh) spends most of its set-up here.
        let (literals, holds): (Vec<_>, Vec<_>) = dnf
            .terms
            .par_iter()
            .zip(&boxes)
            .zip(&large)
            .map(|((term, bounds), &large)| {
                if !large {
                    return (None, None);
                }
                let literals = (term.literals.len() > literals_above && bounds.is_bounded())
                    .then(|| term_literals(dnf, term, bounds));
                let holds = cull
                    .then(|| crate::cull::where_it_may_hold(dnf, term, bounds))
                    .flatten();
                (literals, holds)
            })
            .unzip();
        let square_boxes = holds
            .iter()
            .zip(&boxes)
            .map(|(holds, bounds)| holds.unwrap_or(*bounds))
            .collect();
        Self {
            boxes: BoxIndex::new(boxes),
            holds,
            square_boxes,
            literals,
        }
    }

    /// The index of `dnf` without shortcuts: no literal boxes, no boxes of where terms hold.
    pub fn plain(dnf: &Dnf) -> Self {
        Self::build(dnf, usize::MAX, false)
    }
}

impl TermBoxes for TermIndex {
    fn square_boxes(&self) -> &[Aabb] {
        &self.square_boxes
    }

    fn literal_boxes(&self, term: usize) -> Option<(&[Aabb], &[u32])> {
        let literals = self.literals.get(term)?.as_ref()?;
        Some((literals.boxes.all(), &literals.ids))
    }
}

/// Where each literal of `term` may fail within `bounds`, the term's padded box.
fn term_literals(dnf: &Dnf, term: &Term, bounds: &Aabb) -> TermLiterals {
    let count = term.literals.len();
    // A few literals are cheap to read anyway: coarser boxes, found sooner.
    let many = count > LITERAL_TREE_ABOVE;
    let splits = if many {
        FAIL_SPLITS
    } else if count > FEWER_ABOVE {
        FEW_FAIL_SPLITS
    } else {
        FEWER_FAIL_SPLITS
    };
    let fails = term.literals.iter().map(|&id| {
        dnf.quadrics
            .get(id as usize)
            .map_or(*bounds, |q| where_it_fails(&q.quadric, bounds, splits))
    });
    let boxes = if many {
        LiteralBoxes::Indexed(BoxIndex::new(fails.collect()))
    } else {
        LiteralBoxes::Listed(fails.collect())
    };
    TermLiterals {
        boxes,
        ids: term.literals.clone(),
    }
}

/// Bisections of a term's box when looking for where a literal fails: down to 1/2^8 of its
/// size on each axis.
const FAIL_SPLITS: u32 = 24;
/// The same for a term of few literals: down to 1/2^4.
const FEW_FAIL_SPLITS: u32 = 12;
/// The same for a term of at most [`FEWER_ABOVE`] literals: down to 1/2^3 (a scene of
/// hundreds of such terms pays for the bisections at each rebuild).
const FEWER_FAIL_SPLITS: u32 = 8;
/// Terms of more literals than this have their literal boxes bisected further.
const FEWER_ABOVE: usize = 16;

/// A box around the points of `bounds` where `q ≤ 0` fails or holds only up to its surface:
/// for a plane in a finite box found directly ([`where_a_plane_fails`]), else by bisection
/// ([`where_it_fails_by_bisection`]).
fn where_it_fails(q: &Quadric, bounds: &Aabb, splits: u32) -> Aabb {
    where_a_plane_fails(q, bounds).unwrap_or_else(|| where_it_fails_by_bisection(q, bounds, splits))
}

/// [`where_it_fails`] by bisection: the union of the pieces of `bounds`, bisected along their
/// longest side at most `splits` times, that `quadric_box::classify` does not prove inside.
fn where_it_fails_by_bisection(q: &Quadric, bounds: &Aabb, splits: u32) -> Aabb {
    let mut found = Aabb::EMPTY;
    let mut stack = vec![(*bounds, 0)];
    while let Some((piece, depth)) = stack.pop() {
        match classify(q, &piece) {
            BoxClass::Inside => {}
            BoxClass::Cuts if depth < splits => {
                let axis = (piece.max - piece.min).max_position();
                let middle = 0.5 * (piece.min[axis] + piece.max[axis]);
                let (mut low, mut high) = (piece, piece);
                low.max[axis] = middle;
                high.min[axis] = middle;
                stack.push((low, depth + 1));
                stack.push((high, depth + 1));
            }
            _ => found = found.union(&piece),
        }
    }
    found
}

/// For a plane, [`where_it_fails`] found directly and more tightly than by bisection: the box
/// of the part of the finite `bounds` where `q ≥ −2e`, `e` the largest bound on the rounding of
/// `q` at its corners (which bounds it over the box), from the corners on that side and the
/// points where the plane `q = −2e` crosses the box's edges, grown by `1e-9` of the box's size
/// for the rounding of those crossings. `None` for a quadric that is not a plane or a box that
/// is not finite.
fn where_a_plane_fails(q: &Quadric, bounds: &Aabb) -> Option<Aabb> {
    let planar = q.matrix_a().iter().flatten().all(|&a| a == 0.0);
    if !planar || bounds.is_empty() || !bounds.is_bounded() {
        return None;
    }
    let corners = bounds.corners();
    let values = corners.map(|c| q.value_with_error(c));
    let slack = 2.0 * values.iter().fold(0.0f64, |m, &(_, e)| m.max(e));
    let shifted = values.map(|(v, _)| v + slack);
    if shifted.iter().any(|s| !s.is_finite()) {
        return None;
    }
    let mut found = Aabb::EMPTY;
    let mut add = |p: DVec3| found = found.union(&Aabb::new(p, p));
    for (corner, &s) in corners.iter().zip(&shifted) {
        if s >= 0.0 {
            add(*corner);
        }
    }
    // The edges join corners whose indices differ in one bit (one per axis).
    for a in 0..8 {
        for bit in [1, 2, 4] {
            let b = a | bit;
            let (sa, sb) = (shifted[a], shifted[b]);
            if b != a && (sa < 0.0) != (sb < 0.0) {
                add(corners[a] + (corners[b] - corners[a]) * (sa / (sa - sb)));
            }
        }
    }
    if found.is_empty() {
        return Some(found);
    }
    let margin = 1e-9 * (bounds.max - bounds.min);
    Some(
        Aabb {
            min: found.min - margin,
            max: found.max + margin,
        }
        .intersection(bounds),
    )
}

/// A term whose box is under this fraction of the scene's on its longest side is small.
const SMALL_TERM: f64 = 1.0 / 16.0;

/// Which terms' boxes are large within the scene: only those are worth bisecting for where
/// their literals fail or where they may hold. A small box already covers few squares of
/// pixels, and a scene of many terms is nearly all small ones (the cells of an imported mesh:
/// bisecting each of 30,000 took several times as long as tracing the whole frame).
fn large_terms(boxes: &[Aabb]) -> Vec<bool> {
    let longest = |b: &Aabb| (b.max - b.min).max_element();
    let scene = boxes
        .iter()
        .filter(|b| b.is_bounded() && !b.is_empty())
        .fold(Aabb::EMPTY, |all, b| all.union(b));
    let scene_side = if scene.is_empty() {
        0.0
    } else {
        longest(&scene)
    };
    boxes
        .iter()
        .map(|b| !b.is_bounded() || longest(b) >= SMALL_TERM * scene_side)
        .collect()
}

/// The term boxes, each grown a little (see [`TermIndex`]).
fn padded_boxes(dnf: &Dnf) -> Vec<Aabb> {
    dnf.terms
        .iter()
        .map(|term| {
            let b = term.bounds;
            if b.is_empty() {
                b
            } else {
                crate::cull::grow(&b)
            }
        })
        .collect()
}

/// The part of `ray` beyond `t_min` inside `bounds`, when it is not empty (NaN ranges are).
fn clipped(ray: &Ray, bounds: &Aabb, t_min: f64) -> Option<(f64, f64)> {
    let (t_in, t_out) = ray.clip_to(bounds)?;
    let t_in = t_in.max(t_min);
    (t_in.partial_cmp(&t_out) == Some(std::cmp::Ordering::Less)).then_some((t_in, t_out))
}

/// The first entry of `ray` into the solid `dnf` at a parameter `> t_min`, given the padded
/// term boxes from [`term_index`]. A ray that starts inside the solid sees the next entry.
pub fn trace(
    dnf: &Dnf,
    index: &TermIndex,
    ray: &Ray,
    t_min: f64,
    scratch: &mut Scratch,
) -> Option<Hit> {
    trace_from(dnf, index, ray, t_min, None, scratch)
}

/// [`trace`] with the values of `dnf`'s quadrics and surfaces at the frame's eye, used when
/// `ray` starts there ([`EyeValues`]): the same hit, sooner.
pub fn trace_from(
    dnf: &Dnf,
    index: &TermIndex,
    ray: &Ray,
    t_min: f64,
    eye: Option<&EyeValues>,
    scratch: &mut Scratch,
) -> Option<Hit> {
    trace_among(dnf, index, ray, t_min, eye, None, scratch)
}

/// [`trace_from`] looking only at the terms of `square` (positions in [`TermIndex::boxes`],
/// which must hold every term whose box the ray crosses: a frame's
/// [`FrameTiles`](crate::tiles::FrameTiles)) instead of searching the tree, and at the literals
/// the square lists for them: the same hit.
pub fn trace_among(
    dnf: &Dnf,
    index: &TermIndex,
    ray: &Ray,
    t_min: f64,
    eye: Option<&EyeValues>,
    square: Option<Square<'_>>,
    scratch: &mut Scratch,
) -> Option<Hit> {
    let eye = eye.and_then(|e| e.for_ray(ray));
    scratch.term.roots.next_ray();
    scratch.all.clear();
    scratch.terms.clear();
    scratch.entries.clear();
    let boxes = &index.boxes;
    let listed = |entry: &Entry| {
        square
            .filter(|_| entry.3 != NO_SQUARE)
            .and_then(|s| s.literals(entry.3 as usize))
    };
    let entry = |(k, &term_index): (usize, &u32)| {
        let bounds = boxes.boxes().get(term_index as usize)?;
        let (t_in, t_out) = clipped(ray, bounds, t_min)?;
        // A ray that misses where the term may hold finds it empty: it is left out.
        if let Some(Some(holds)) = index.holds.get(term_index as usize) {
            ray.clip_to(holds).filter(|&(_, out)| out >= t_min)?;
        }
        Some((t_in, t_out, term_index, k as u32))
    };
    match square {
        // Each is tested as the tree's leaves are.
        Some(square) => scratch
            .entries
            .extend(square.boxes.iter().enumerate().filter_map(entry)),
        None => {
            // A larger box holds a longer piece of the ray, so the search may skip what misses.
            boxes.select(|b| clipped(ray, b, t_min).is_some(), &mut scratch.terms);
            scratch.entries.extend(
                scratch
                    .terms
                    .iter()
                    .enumerate()
                    .filter_map(entry)
                    .map(|(t_in, t_out, term, _)| (t_in, t_out, term, NO_SQUARE)),
            );
        }
    }
    // Front to back, by where the ray enters each term's box: once a term's interval begins
    // at `nearest` (and is a hit, not the ray's start inside the solid), a term whose box the
    // ray enters beyond it holds no interval that begins before it, so it cannot change the
    // union's first entry, nor which interval (and term) begins there. While some interval
    // begins at the ray's start, the sweep below reads past it, so every term counts.
    scratch
        .entries
        .sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.2.cmp(&b.2)));
    let candidate = |entry: &Interval| entry.start > t_min || entry.start_by != Boundary::Clip;
    let mut nearest = f64::INFINITY;
    let mut from_start = false;
    scratch.deferred.clear();
    for &(t_in, t_out, term_index, k) in &scratch.entries {
        if !from_start && t_in > nearest {
            break;
        }
        // While no interval begins at the ray's start, a term whose intervals all begin beyond
        // `nearest` cannot change the hit (its literals only narrow them further): it is left
        // as soon as that shows, and read whole below only if some interval turns out to begin
        // at the ray's start after all, when the sweep reads past `nearest`.
        let cutoff = if from_start { f64::INFINITY } else { nearest };
        let read = term_intervals(
            dnf,
            index,
            ray,
            (t_in, t_out, term_index),
            listed(&(t_in, t_out, term_index, k)),
            eye,
            cutoff,
            &mut scratch.term,
        );
        if !read {
            scratch.deferred.push((t_in, t_out, term_index, k));
            continue;
        }
        for interval in &scratch.term.current {
            if candidate(interval) {
                nearest = nearest.min(interval.start);
            } else {
                from_start = true;
            }
        }
        scratch
            .all
            .extend(scratch.term.current.iter().map(|&i| (i, term_index)));
    }
    if from_start {
        for deferred in &scratch.deferred {
            let (t_in, t_out, term_index, _) = *deferred;
            term_intervals(
                dnf,
                index,
                ray,
                (t_in, t_out, term_index),
                listed(deferred),
                eye,
                f64::INFINITY,
                &mut scratch.term,
            );
            scratch
                .all
                .extend(scratch.term.current.iter().map(|&i| (i, term_index)));
        }
    }
    if scratch.all.is_empty() {
        return None;
    }
    scratch
        .all
        .sort_unstable_by(|(a, ta), (b, tb)| a.start.total_cmp(&b.start).then(ta.cmp(tb)));

    // Sweep the union: the first merged interval that does not begin at the ray's start.
    let mut iter = scratch.all.iter();
    let &(first, first_term) = iter.next()?;
    let (mut entry, mut entry_term, mut end) = (first, first_term, first.end);
    if candidate(&entry) {
        return hit_at(dnf, ray, entry, entry_term);
    }
    for &(interval, term) in iter {
        if interval.start <= end {
            end = end.max(interval.end);
            continue;
        }
        entry = interval;
        entry_term = term;
        end = interval.end;
        if candidate(&entry) {
            return hit_at(dnf, ray, entry, entry_term);
        }
    }
    None
}

/// Writes into `buffers.current` the intervals of the term `term_index` along the piece
/// `(t_in, t_out)` of `ray` in its box; returns `false`, leaving them unfinished, as soon as
/// every one begins beyond `cutoff`. `listed`: the literals that may fail along the ray in the
/// term's box, when its square of pixels lists them (the others hold along all of it).
#[allow(clippy::too_many_arguments)]
fn term_intervals(
    dnf: &Dnf,
    index: &TermIndex,
    ray: &Ray,
    (t_in, t_out, term_index): (f64, f64, u32),
    listed: Option<&[u32]>,
    eye: Option<&EyeValues>,
    cutoff: f64,
    buffers: &mut TermBuffers,
) -> bool {
    buffers.current.clear();
    let Some(term) = dnf.terms.get(term_index as usize) else {
        return true;
    };
    buffers.current.push(Interval::clip(t_in, t_out));
    // Of a term of several literals, those whose failing part the ray's piece misses hold
    // along all of it: they change nothing.
    buffers.literals.clear();
    let literals = match (listed, index.literals.get(term_index as usize)) {
        (Some(listed), _) => listed,
        (None, Some(Some(fails))) => {
            let meets = |b: &Aabb| ray.clip_to(b).is_some_and(|(a, c)| a <= t_out && c >= t_in);
            fails.boxes.select(meets, &mut buffers.literals);
            for k in &mut buffers.literals {
                *k = term.literals[*k as usize];
            }
            &buffers.literals
        }
        _ => &term.literals,
    };
    // The order changes nothing but how soon an empty term shows ([`intersect_into`]).
    let first = buffers
        .emptied_by
        .get(term_index as usize)
        .copied()
        .filter(|id| literals.contains(id));
    let ordered = first
        .into_iter()
        .chain(literals.iter().copied().filter(|&id| Some(id) != first));
    for id in ordered {
        let Some(literal) = dnf.quadrics.get(id as usize) else {
            continue;
        };
        surface_literal_intervals(
            &dnf.surfaces,
            &literal.quadric,
            id,
            ray,
            Interval::clip(t_in, t_out),
            eye,
            &mut buffers.roots,
            &mut buffers.literal,
        );
        intersect_into(&buffers.current, &buffers.literal, &mut buffers.merged);
        std::mem::swap(&mut buffers.current, &mut buffers.merged);
        match buffers.current.first() {
            None => {
                let k = term_index as usize;
                if k >= buffers.emptied_by.len() {
                    buffers.emptied_by.resize(k + 1, u32::MAX);
                }
                buffers.emptied_by[k] = id;
                break;
            }
            Some(first) if first.start > cutoff => return false,
            Some(_) => {}
        }
    }
    true
}

/// The hit at the start of `interval`.
fn hit_at(dnf: &Dnf, ray: &Ray, interval: Interval, term: u32) -> Option<Hit> {
    let t = interval.start;
    let point = ray.at(t);
    let (normal, quadric) = match interval.start_by {
        Boundary::Quadric(id) => {
            let q = &dnf.quadrics.get(id as usize)?.quadric;
            (q.normal(point).unwrap_or(-ray.direction), Some(id))
        }
        Boundary::Clip => (box_face_normal(ray), None),
    };
    Some(Hit {
        t,
        point,
        normal,
        quadric,
        term,
    })
}

/// The outward normal of the box face a ray enters through: along its dominant axis.
fn box_face_normal(ray: &Ray) -> DVec3 {
    let d = ray.direction;
    let a = d.abs();
    if a.x >= a.y && a.x >= a.z {
        DVec3::new(-d.x.signum(), 0.0, 0.0)
    } else if a.y >= a.z {
        DVec3::new(0.0, -d.y.signum(), 0.0)
    } else {
        DVec3::new(0.0, 0.0, -d.z.signum())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use qcsg_testkit::Rng;

    /// A plane's box of where it fails, found directly, holds every point of the box where the
    /// plane's literal fails and is no larger than the bisection's, at every scale and offset.
    #[test]
    fn a_plane_fails_within_its_direct_box_and_no_wider_than_bisected() {
        let mut rng = Rng::new(20261208);
        for case in 0..400 {
            let (scale, offset) = ([1e-6, 1.0, 1e6][case % 3], [0.0, 1e6][case / 3 % 2]);
            let centre =
                DVec3::splat(offset) + rng.in_box(DVec3::splat(-scale), DVec3::splat(scale));
            let half =
                DVec3::new(rng.unit(), rng.unit(), rng.unit()) * scale + DVec3::splat(1e-3 * scale);
            let bounds = Aabb::new(centre - half, centre + half);
            // Through a point of the box, or beside it (missing it or holding it whole).
            let through = centre + rng.in_box(-2.0 * half, 2.0 * half);
            let q = Quadric::half_space(through, rng.direction()).expect("a unit normal");
            let found = where_a_plane_fails(&q, &bounds).expect("a plane in a finite box");
            let bisected = where_it_fails_by_bisection(&q, &bounds, FAIL_SPLITS);
            let margin = 1e-8 * (bounds.max - bounds.min);
            assert!(
                found.is_empty()
                    || (found.min.cmpge(bisected.min - margin).all()
                        && found.max.cmple(bisected.max + margin).all()),
                "case {case}: {found:?} wider than {bisected:?}"
            );
            for _ in 0..200 {
                let p = rng.in_box(bounds.min, bounds.max);
                if q.value(p) >= 0.0 {
                    assert!(
                        found.contains(p),
                        "case {case}: {p} fails outside {found:?}"
                    );
                }
            }
        }
    }
}
