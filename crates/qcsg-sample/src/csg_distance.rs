//! The quadric-relative conservative CSG distance `d_Q(S, p)` of paper eq. 22.
//!
//! For a point `p` on quadric `Q_ab` (literal `b` of term `a`):
//! `d = max(−min_{i≠a} max_j d(Q_ij, p), max_{j≠b} d(Q_aj, p))`, with `d(Q, p)` the conservative
//! distance of eqs. 10-12. Negative: `p` is on the CSG surface, and so is every point of `Q_ab`
//! within `|d|`; positive: neither `p` nor any point of `Q_ab` within `d` is.
//!
//! Decisions beyond the paper, each keeping the two properties above:
//! - **The region as a literal.** With a region ([`qcsg_csg::Dnf::region`]) the solid is clipped
//!   to it ([`qcsg_csg::Dnf::contains`]), so the exact signed distance to the region's box joins
//!   the literals of every term. The per-term boxes are *not* used: they only bound their term
//!   (nothing is lost without them), and a box face often coincides with a sampled surface (a
//!   cube's box with its slabs), where the distance 0 would leave the face unclassifiable.
//! - **Shared surfaces.** A term `i ≠ a` that has `Q_ab` itself among its literals (the same
//!   index, or an equal quadric up to a positive factor) is a subset of `Q_ab`'s solid, so a
//!   point on `Q_ab` is never in its interior: the term is left out. Without this the distance
//!   would be 0 on all of `Q_ab` inside that term and subdivision could never classify it.
//! - **Complementary literals.** A literal of term `i` that is `Q_ab`'s complement is zero on
//!   `Q_ab`; the term's interior then touches `Q_ab` from the other side, and `p` is interior to
//!   the union exactly when it also lies inside the term's remaining literals. That literal is
//!   left out of term `i` (and an own literal equal to `Q_ab` is left out of term `a`: it holds
//!   on all of `Q_ab`).
//! - **Shared planes.** Two *different* quadrics can share a patch of surface only where both
//!   are made of planes (a half-space, a slab): two parts sharing a face, a difference flush
//!   with a face. When `Q_ab` is planar and `p` lies on a plane of another planar literal `L`
//!   (within [`CsgDistance`]'s length tolerance, normals parallel), that plane is `p`'s whole
//!   sheet of `Q_ab`, so what holds at `p` holds on the sheet: if `L`'s inside is on `Q_ab`'s
//!   inside, `L` is left out of term `a` (it holds up to the sheet) and a term `i ≠ a` holding
//!   `L` is left out (its interior never reaches the sheet); if `L`'s inside is on the other
//!   side, term `a` is empty along the sheet (distance `+∞`) and `L` is left out of term `i`
//!   (the complement rule, per plane). Without this, eq. 22 is 0 on the whole shared face, no
//!   corner classifies it, and where it is part of the surface no term samples it.
//! - **Literals of both terms.** A literal `L` of term `i ≠ a` that term `a` holds too is left
//!   out of term `i` (unless it shares `p`'s plane, above). Where `L` holds, term `i` is
//!   unchanged; where it fails, term `a` is empty, so its own distance is positive and the
//!   result stays positive. A negative result needs `p` inside `L` by at least `|d|`, so the
//!   claim for the ball of `|d|` holds; a positive one from term `i` covers points inside term
//!   `i` or outside `L`, neither on `Q_ab`'s patch of term `a`. Without this, on a face where two
//!   parts meet (the face inside a union of abutting boxes), the two terms' shared side literal
//!   makes eq. 22 `max(D, −D) = |D|`, which touches 0 along the face's border without a sign
//!   change and leaves rectangles there unclassified.
//! - **Abutting terms.** Two other terms that meet along a plane, one holding the half-space
//!   `n·x ≤ c` (a half-space literal, or one side of a slab) and the other `n·x ≥ c`, are pieces
//!   of one part that the DNF cut apart (a difference splits a part along the planes of what it
//!   removes; stacked parts meet on a face). Where the sampled quadric crosses that plane inside
//!   both pieces, each piece's distance is about the distance to the plane, one positive and one
//!   negative, so eq. 22 touches 0 along the crossing without a sign change. Each such pair
//!   also enters as a *merged* term: both terms' literals without the two shared half-spaces
//!   (a slab keeps its other side as a half-space). A point of the merged term lies in the first
//!   piece when `n·x ≤ c` and in the second otherwise, so the merged term is a subset of the
//!   solid and the two properties of eq. 22 hold with it; at the crossing it is well inside, so
//!   the curve is classified. Planes count as shared within the tolerance of "Shared planes";
//!   at most four merged terms per other term are made (`MAX_MERGED_PER_TERM`).

use qcsg_csg::{Aabb, Dnf};
use qcsg_quadric::{DVec3, Quadric, QuadricKind};

/// Relative tolerance for "the same quadric" when comparing literals.
const SAME_QUADRIC: f64 = 1e-12;

/// Relative tolerance for parallel normals of planes that share a point.
const PARALLEL: f64 = 1e-9;

/// Whether a quadric's surface is made of planes that may coincide with another's.
fn is_planar(q: &Quadric) -> bool {
    matches!(q.kind(), QuadricKind::Plane | QuadricKind::ParallelPlanes)
}

/// How a literal meets the sampled quadric's plane through `p`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Shared {
    /// Not on the plane (or not planar).
    No,
    /// On the plane, inside on the sampled quadric's inside.
    SameSide,
    /// On the plane, inside on the other side.
    OtherSide,
}

/// The sampled quadric's plane through `p`: its outward unit normal, when `Q_ab` is planar.
#[derive(Clone, Copy, Debug)]
struct SheetPlane {
    normal: DVec3,
    tolerance: f64,
}

impl SheetPlane {
    /// `distance` is the literal's conservative distance at `p`.
    fn shared(&self, literal: &Literal, p: DVec3, distance: f64) -> Shared {
        if !literal.planar || distance.abs() > self.tolerance {
            return Shared::No;
        }
        let Some(n) = literal.quadric.normal(p) else {
            return Shared::No;
        };
        if n.cross(self.normal).length() > PARALLEL {
            return Shared::No;
        }
        if n.dot(self.normal) > 0.0 {
            Shared::SameSide
        } else {
            Shared::OtherSide
        }
    }
}

/// One literal of a term view.
#[derive(Clone, Debug)]
struct Literal {
    quadric: Quadric,
    planar: bool,
    /// A literal of another term that term `a` holds too (see "Literals of both terms").
    in_own_term: bool,
}

/// A term of the DNF as seen from one quadric: the literals that matter and the box.
#[derive(Clone, Debug)]
struct TermView {
    literals: Vec<Literal>,
    bounds: Aabb,
    /// A box holding the whole term (for [`CsgDistance::near`]).
    extent: Aabb,
}

impl TermView {
    /// The view of `literals`, each with whether term `a` holds it too.
    fn new(
        literals: impl IntoIterator<Item = (Quadric, bool)>,
        bounds: Aabb,
        extent: Aabb,
    ) -> Self {
        Self {
            extent,
            literals: literals
                .into_iter()
                .map(|(quadric, in_own_term)| Literal {
                    planar: is_planar(&quadric),
                    in_own_term,
                    quadric,
                })
                .collect(),
            bounds,
        }
    }

    /// `max_j d(Q_j, p)` together with the region box: positive outside the term, negative
    /// inside. With the sampled quadric's `plane` at `p`, literals sharing it are treated as in
    /// the module docs: `own` says whether this is term `a`.
    fn distance(&self, p: DVec3, plane: Option<&SheetPlane>, own: bool) -> f64 {
        let mut d = box_distance(&self.bounds, p);
        for literal in &self.literals {
            let on_plane = plane.filter(|_| literal.planar);
            if !own && literal.in_own_term && on_plane.is_none() {
                continue;
            }
            // Evaluated once: a planar literal needs it for the plane test too.
            let distance = literal.quadric.conservative_distance(p);
            let shared = on_plane.map_or(Shared::No, |plane| plane.shared(literal, p, distance));
            match (shared, own) {
                (Shared::No, false) if literal.in_own_term => {}
                (Shared::No, _) => d = d.max(distance),
                (Shared::SameSide, true) | (Shared::OtherSide, false) => {}
                (Shared::OtherSide, true) | (Shared::SameSide, false) => return f64::INFINITY,
            }
        }
        d
    }
}

/// `d_{Q_ab}(S, ·)` for one literal of one term, with the DNF's quadrics copied in.
#[derive(Clone, Debug)]
pub struct CsgDistance {
    own: TermView,
    others: Vec<TermView>,
    /// The sampled quadric, when it is planar (see "Shared planes" in the module docs).
    planar: Option<Quadric>,
    /// Length below which a point is on a plane: `1e-9` of the DNF's diagonal.
    tolerance: f64,
}

impl CsgDistance {
    /// The distance for quadric `quadric` sampled as a literal of term `term` of `dnf`.
    /// `None` if the indices are out of range.
    pub fn new(dnf: &Dnf, quadric: u32, term: u32) -> Option<Self> {
        let q = dnf.quadrics.get(quadric as usize)?.quadric;
        let own_term = dnf.terms.get(term as usize)?;
        let complement = q.negated();
        let is_same =
            |i: u32, other: &Quadric| i == quadric || q.approx_eq_up_to_scale(other, SAME_QUADRIC);
        let is_complement = |other: &Quadric| complement.approx_eq_up_to_scale(other, SAME_QUADRIC);
        let region = dnf.region.unwrap_or(Aabb::new(
            DVec3::splat(f64::NEG_INFINITY),
            DVec3::splat(f64::INFINITY),
        ));
        let literal = |i: u32| dnf.quadrics.get(i as usize).map(|d| d.quadric);
        let own_literals: Vec<(u32, Quadric)> = own_term
            .literals
            .iter()
            .filter_map(|&i| literal(i).map(|o| (i, o)))
            .collect();
        let in_own_term = |i: u32, other: &Quadric| {
            own_literals
                .iter()
                .any(|(j, o)| *j == i || o.approx_eq_up_to_scale(other, SAME_QUADRIC))
        };
        let own = TermView::new(
            own_term
                .literals
                .iter()
                .filter_map(|&i| literal(i).filter(|o| !is_same(i, o)))
                .map(|o| (o, false)),
            region,
            own_term.bounds,
        );
        let diagonal = (dnf.bounds.max - dnf.bounds.min).length();
        let tolerance = if diagonal.is_finite() {
            1e-9 * diagonal
        } else {
            0.0
        };
        let mut kept: Vec<TermLiterals> = Vec::new();
        let mut extents = Vec::new();
        for (index, other) in dnf.terms.iter().enumerate() {
            if index == term as usize {
                continue;
            }
            let literals: Vec<(u32, Quadric)> = other
                .literals
                .iter()
                .filter_map(|&i| literal(i).map(|o| (i, o)))
                .collect();
            if literals.iter().any(|(i, o)| is_same(*i, o)) {
                continue;
            }
            kept.push(literals);
            extents.push(other.bounds);
        }
        let merged = abutting_unions(&kept, tolerance, MAX_MERGED_PER_TERM * kept.len().max(1));
        let merged = merged
            .into_iter()
            .map(|(literals, (i, k))| (literals, extents[i].union(&extents[k])))
            .filter(|(l, _)| !l.iter().any(|(i, o)| is_same(*i, o)));
        let others = kept
            .into_iter()
            .zip(extents.iter().copied())
            .chain(merged)
            .map(|(literals, extent)| {
                TermView::new(
                    literals
                        .into_iter()
                        .filter(|(_, o)| !is_complement(o))
                        .map(|(i, o)| (o, in_own_term(i, &o))),
                    region,
                    extent,
                )
            })
            .collect();
        Some(Self {
            own,
            others,
            planar: is_planar(&q).then_some(q),
            tolerance,
        })
    }

    /// `d_{Q_ab}(S, p)` (eq. 22) for a point `p` on the quadric: negative on the CSG surface.
    /// NaN for non-finite `p`.
    pub fn distance(&self, p: DVec3) -> f64 {
        self.distance_over(p, self.others.iter(), f64::INFINITY)
    }

    /// Eq. 22 restricted to a part of the quadric inside `bounds` (a box around a basic region's
    /// patch): only the other terms whose box comes within `margin` of it are kept.
    pub fn near(&self, bounds: &Aabb, margin: f64) -> NearDistance<'_> {
        let mut terms = Vec::new();
        let mut far = f64::INFINITY;
        for (i, term) in self.others.iter().enumerate() {
            let gap = box_gap(bounds, &term.extent);
            if gap < margin {
                terms.push(i as u32);
            } else {
                far = far.min(gap);
            }
        }
        NearDistance {
            base: self,
            terms,
            far,
        }
    }

    /// Eq. 22 over the other terms `others`; the terms left out are at least `far` from `p`.
    fn distance_over<'a>(
        &'a self,
        p: DVec3,
        others: impl Iterator<Item = &'a TermView>,
        far: f64,
    ) -> f64 {
        let plane = self.planar.and_then(|q| {
            Some(SheetPlane {
                normal: q.normal(p)?,
                tolerance: self
                    .tolerance
                    .max(8.0 * f64::EPSILON * p.abs().max_element()),
            })
        });
        let own = self.own.distance(p, plane.as_ref(), true);
        let mut nearest_other = far;
        for term in others {
            nearest_other = nearest_other.min(term.distance(p, plane.as_ref(), false));
        }
        own.max(-nearest_other)
    }
}

/// [`CsgDistance`] for the points of one box ([`CsgDistance::near`]). A term whose box is at
/// least `far` away from every point of the box contributes at most `−far` to the maximum (its
/// interior is at least that far), so it is replaced by that constant: classifications stay
/// valid, only radii beyond `far` are cut.
#[derive(Clone, Debug)]
pub struct NearDistance<'a> {
    base: &'a CsgDistance,
    terms: Vec<u32>,
    far: f64,
}

impl NearDistance<'_> {
    /// Eq. 22 at `p`, for `p` inside the box given to [`CsgDistance::near`].
    pub fn distance(&self, p: DVec3) -> f64 {
        let others = self.terms.iter().map(|&i| &self.base.others[i as usize]);
        self.base.distance_over(p, others, self.far)
    }
}

/// The Euclidean gap between two boxes (0 when they touch or overlap, `+∞` if either is empty).
fn box_gap(a: &Aabb, b: &Aabb) -> f64 {
    if a.is_empty() || b.is_empty() {
        return f64::INFINITY;
    }
    let gap = (a.min - b.max).max(b.min - a.max).max(DVec3::ZERO);
    let gap = gap.length();
    if gap.is_nan() { 0.0 } else { gap }
}

/// Most abutting unions per other term (see "Abutting terms"); a guard against grids of many
/// parts, where the pairs would outnumber the terms by far.
const MAX_MERGED_PER_TERM: usize = 4;

/// Index given to literals made here (half-spaces of a slab): no literal of the DNF has it.
const MADE_LITERAL: u32 = u32::MAX;

/// The literals of a term, each with its index in the DNF's quadric table.
type TermLiterals = Vec<(u32, Quadric)>;

/// A half-space `{x : normal · x ≤ offset}`, `normal` a unit vector.
#[derive(Clone, Copy, Debug)]
struct HalfSpace {
    normal: DVec3,
    offset: f64,
    point: DVec3,
}

/// The half-spaces whose intersection is the solid of `q`: one for a half-space, two for a slab;
/// `None` for anything else (the outside of a slab is a union, not an intersection).
fn half_spaces(q: &Quadric) -> Option<Vec<HalfSpace>> {
    let make = |normal: DVec3, point: DVec3| HalfSpace {
        normal,
        offset: normal.dot(point),
        point,
    };
    match q.kind() {
        QuadricKind::Plane => {
            let (low, high) = q.eigenvalue_bounds();
            let normal = q.linear().try_normalize()?;
            if low != 0.0 || high != 0.0 {
                return None;
            }
            // Q = 2 l·(x − o) + j: the plane is at o − j / (2|l|) along the normal.
            let point = q.origin() - normal * (q.constant() / (2.0 * q.linear().length()));
            Some(vec![make(normal, point)])
        }
        QuadricKind::ParallelPlanes => {
            let frame = q.frame();
            let k = (0..3).find(|&k| frame.eigenvalues[k] != 0.0)?;
            let lambda = frame.eigenvalues[k];
            let others_zero = (0..3).all(|j| j == k || frame.eigenvalues[j] == 0.0);
            if !(others_zero && lambda > 0.0 && frame.constant < 0.0) || frame.linear != [0.0; 3] {
                return None;
            }
            let (u, half_width) = (frame.axes[k], (-frame.constant / lambda).sqrt());
            Some(vec![
                make(u, frame.centre + half_width * u),
                make(-u, frame.centre - half_width * u),
            ])
        }
        _ => None,
    }
}

/// The literals of two terms, minus the two that meet along `shared` (a half-space of `a`'s
/// literal `la` and the opposite one of `b`'s `lb`), with the rest of each of those two put back
/// as half-spaces: a subset of the union of the two terms (see "Abutting terms").
fn merged_literals(
    a: &[(u32, Quadric)],
    b: &[(u32, Quadric)],
    (la, lb): (usize, usize),
    (rest_a, rest_b): (&[HalfSpace], &[HalfSpace]),
) -> TermLiterals {
    let keep = |literals: &[(u32, Quadric)], skip: usize| {
        literals
            .iter()
            .enumerate()
            .filter(move |&(j, _)| j != skip)
            .map(|(_, l)| *l)
            .collect::<Vec<_>>()
    };
    let rest = rest_a
        .iter()
        .chain(rest_b)
        .filter_map(|h| Quadric::half_space(h.point, h.normal).map(|q| (MADE_LITERAL, q)));
    let mut out = keep(a, la);
    out.extend(keep(b, lb));
    out.extend(rest);
    out
}

/// For every two terms that meet along a plane (one holds `n·x ≤ c`, the other `n·x ≥ c`),
/// the merged term of [`merged_literals`] with the indices of the two, at most `limit` of them,
/// in a fixed order.
fn abutting_unions(
    terms: &[TermLiterals],
    tolerance: f64,
    limit: usize,
) -> Vec<(TermLiterals, (usize, usize))> {
    let planes: Vec<Vec<Option<Vec<HalfSpace>>>> = terms
        .iter()
        .map(|t| t.iter().map(|(_, q)| half_spaces(q)).collect())
        .collect();
    let opposite = |h: &HalfSpace, g: &HalfSpace| {
        (h.normal + g.normal).length() <= PARALLEL && (h.offset + g.offset).abs() <= tolerance
    };
    let mut out = Vec::new();
    for (i, planes_i) in planes.iter().enumerate() {
        for (k, planes_k) in planes.iter().enumerate().skip(i + 1) {
            for (la, spaces_a) in planes_i.iter().enumerate() {
                let Some(spaces_a) = spaces_a else { continue };
                for (lb, spaces_b) in planes_k.iter().enumerate() {
                    let Some(spaces_b) = spaces_b else { continue };
                    for (ha, h) in spaces_a.iter().enumerate() {
                        let Some(hb) = spaces_b.iter().position(|g| opposite(h, g)) else {
                            continue;
                        };
                        if out.len() >= limit {
                            return out;
                        }
                        let rest = |spaces: &[HalfSpace], skip: usize| {
                            spaces
                                .iter()
                                .enumerate()
                                .filter(|&(j, _)| j != skip)
                                .map(|(_, h)| *h)
                                .collect::<Vec<_>>()
                        };
                        let (rest_a, rest_b) = (rest(spaces_a, ha), rest(spaces_b, hb));
                        let literals =
                            merged_literals(&terms[i], &terms[k], (la, lb), (&rest_a, &rest_b));
                        out.push((literals, (i, k)));
                    }
                }
            }
        }
    }
    out
}

/// Exact signed Euclidean distance to a closed box: positive outside, negative inside (the
/// distance to the nearest face); infinite sides are fine, an empty box is infinitely far.
pub fn box_distance(bounds: &Aabb, p: DVec3) -> f64 {
    if bounds.is_empty() {
        return f64::INFINITY;
    }
    let below = bounds.min - p;
    let above = p - bounds.max;
    let outside = below.max(above);
    if outside.max_element() > 0.0 {
        outside.max(DVec3::ZERO).length()
    } else {
        outside.max_element()
    }
}
