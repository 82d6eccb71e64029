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
    fn shared(&self, literal: &Literal, p: DVec3) -> Shared {
        if !literal.planar || literal.quadric.conservative_distance(p).abs() > self.tolerance {
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
}

impl TermView {
    /// The view of `literals`, each with whether term `a` holds it too.
    fn new(literals: impl IntoIterator<Item = (Quadric, bool)>, bounds: Aabb) -> Self {
        Self {
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
            let shared = plane.map_or(Shared::No, |plane| plane.shared(literal, p));
            match (shared, own) {
                (Shared::No, false) if literal.in_own_term => {}
                (Shared::No, _) => d = d.max(literal.quadric.conservative_distance(p)),
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
        );
        let mut others = Vec::new();
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
            others.push(TermView::new(
                literals
                    .into_iter()
                    .filter(|(_, o)| !is_complement(o))
                    .map(|(i, o)| (o, in_own_term(i, &o))),
                region,
            ));
        }
        let diagonal = (dnf.bounds.max - dnf.bounds.min).length();
        Some(Self {
            own,
            others,
            planar: is_planar(&q).then_some(q),
            tolerance: if diagonal.is_finite() {
                1e-9 * diagonal
            } else {
                0.0
            },
        })
    }

    /// `d_{Q_ab}(S, p)` (eq. 22) for a point `p` on the quadric: negative on the CSG surface.
    /// NaN for non-finite `p`.
    pub fn distance(&self, p: DVec3) -> f64 {
        let plane = self.planar.and_then(|q| {
            Some(SheetPlane {
                normal: q.normal(p)?,
                tolerance: self
                    .tolerance
                    .max(8.0 * f64::EPSILON * p.abs().max_element()),
            })
        });
        let own = self.own.distance(p, plane.as_ref(), true);
        let mut nearest_other = f64::INFINITY;
        for term in &self.others {
            nearest_other = nearest_other.min(term.distance(p, plane.as_ref(), false));
        }
        own.max(-nearest_other)
    }
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
