//! A term of the DNF as one sampled quadric sees it ([`TermView`]): the literals that matter
//! to eq. 22 there, how each meets the sampled quadric's plane through a point ([`Shared`],
//! [`SheetPlane`]: "Shared planes" in [`super`]), and, for terms of many literals, those near a
//! box ([`NearTerms`], [`NearLiterals`]).

use super::abutting::TermLiterals;
use super::near::box_distance;
use either::Either;
use qcsg_csg::Aabb;
use qcsg_csg::quadric_box::{self, BoxClass};
use qcsg_quadric::{DVec3, Quadric, QuadricKind};

/// Relative tolerance for "the same quadric" when comparing literals.
pub(super) const SAME_QUADRIC: f64 = 1e-12;

/// Relative tolerance for parallel normals of planes that share a point.
pub(super) const PARALLEL: f64 = 1e-9;

/// Whether a quadric's surface is made of planes that may coincide with another's.
pub(super) fn is_planar(q: &Quadric) -> bool {
    matches!(q.kind(), QuadricKind::Plane | QuadricKind::ParallelPlanes)
}

/// How a literal meets the sampled quadric's plane through `p`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Shared {
    /// Not on the plane (or not planar).
    No,
    /// On the plane, inside on the sampled quadric's inside.
    SameSide,
    /// On the plane, inside on the other side.
    OtherSide,
}

/// The sampled quadric's plane through `p`: its outward unit normal, when `Q_ab` is planar.
#[derive(Clone, Copy, Debug)]
pub(super) struct SheetPlane {
    pub(super) normal: DVec3,
    pub(super) tolerance: f64,
}

impl SheetPlane {
    /// `distance` is the literal's conservative distance at `p`.
    pub(super) fn shared(&self, literal: &Literal, p: DVec3, distance: f64) -> Shared {
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
pub(super) struct Literal {
    pub(super) quadric: Quadric,
    pub(super) planar: bool,
    /// A literal of another term that term `a` holds too (see "Literals of both terms").
    pub(super) in_own_term: bool,
    /// How it lies on the sampled sheet, as the compiler's surfaces decided
    /// ([`SheetIdentity`](super::identity::SheetIdentity)); `None` where they did not (a
    /// literal made by the sampler, a DNF without surfaces): then the point test of
    /// [`SheetPlane::shared`] decides.
    pub(super) on_sheet: Option<Shared>,
}

/// A term of the DNF as seen from one quadric: the literals that matter and the box.
#[derive(Clone, Debug)]
pub(super) struct TermView {
    pub(super) literals: Vec<Literal>,
    pub(super) bounds: Aabb,
    /// A box holding the whole term (for [`CsgDistance::near`](crate::csg_distance::CsgDistance::near)).
    pub(super) extent: Aabb,
    /// The least distance: `−reach` where literals that hold within `reach` of the sampled part
    /// were left out ("Far literals"), else `−∞`.
    pub(super) floor: f64,
}

/// Terms with more literals than this leave out, near a box, those that hold all around it
/// ("Far literals").
pub(super) const FEW_LITERALS: usize = 32;

/// The terms eq. 22 of one sampled literal looks at, as the DNF has them: term `a`'s literals,
/// then every other term's literals and box; each list with its floor, `−reach` where literals
/// far from the sampled part were left out ("Far literals"), else `−∞`.
pub(super) struct NearTerms {
    pub(super) own: (TermLiterals, f64),
    /// The indices of term `a`'s literals left out, ascending: "Literals of both terms" still
    /// applies to them.
    pub(super) own_far: Vec<u32>,
    pub(super) others: Vec<((TermLiterals, f64), Aabb)>,
}

/// The literals of a term a [`NearDistance`](crate::csg_distance::NearDistance) looks at (indices into [`TermView::literals`]);
/// the others hold on all of its box and `margin` around it.
#[derive(Clone, Debug)]
pub(super) struct NearLiterals {
    pub(super) indices: Vec<u32>,
    pub(super) margin: f64,
}

impl TermView {
    /// The view of `literals`, each with whether it is planar, whether term `a` holds it too
    /// and how it lies on the sampled sheet ([`Literal::on_sheet`]).
    pub(super) fn new(
        literals: impl IntoIterator<Item = (Quadric, bool, bool, Option<Shared>)>,
        bounds: Aabb,
        (extent, floor): (Aabb, f64),
    ) -> Self {
        let literals: Vec<Literal> = literals
            .into_iter()
            .map(|(quadric, planar, in_own_term, on_sheet)| Literal {
                planar,
                in_own_term,
                quadric,
                on_sheet,
            })
            .collect();
        Self {
            extent,
            literals,
            bounds,
            floor,
        }
    }

    /// The literals of a term of many that may fail within `margin` of `bounds`, among those of
    /// `within` (all when `None`), when that leaves some out ("Far literals").
    pub(super) fn near_literals(
        &self,
        bounds: &Aabb,
        margin: f64,
        within: Option<&NearLiterals>,
    ) -> Option<NearLiterals> {
        if self.literals.len() <= FEW_LITERALS {
            return None;
        }
        let grown = bounds.expanded(margin);
        if !grown.is_bounded() {
            return within.cloned();
        }
        let all = 0..self.literals.len() as u32;
        let candidates: &mut dyn Iterator<Item = u32> = match within {
            Some(within) => &mut within.indices.iter().copied(),
            None => &mut all.into_iter(),
        };
        let indices: Vec<u32> = candidates
            .filter(|&i| {
                let literal = &self.literals[i as usize].quadric;
                quadric_box::classify(literal, &grown) != BoxClass::Inside
            })
            .collect();
        (indices.len() < self.literals.len()).then_some(NearLiterals { indices, margin })
    }

    /// The literals a distance with `near` looks at: those it lists, or all.
    pub(super) fn looked_at<'a>(
        &'a self,
        near: Option<&'a NearLiterals>,
    ) -> impl Iterator<Item = &'a Literal> + Clone + 'a {
        match near {
            Some(near) => Either::Left(near.indices.iter().map(|&i| &self.literals[i as usize])),
            None => Either::Right(self.literals.iter()),
        }
    }

    /// `max_j d(Q_j, p)` together with the region box: positive outside the term, negative
    /// inside. With the sampled quadric's `plane` at `p`, literals sharing it are treated as in
    /// the module docs: `own` says whether this is term `a`.
    pub(super) fn distance(
        &self,
        p: DVec3,
        plane: Option<&SheetPlane>,
        own: bool,
        near: Option<&NearLiterals>,
        slack: f64,
    ) -> f64 {
        // The literals left out hold within `−floor − slack` of `p` (`p` is `slack` outside the
        // sampled part), and within `margin` of `p` for a box's ([`NearLiterals`]).
        let d = box_distance(&self.bounds, p).max(self.floor + slack);
        match near {
            Some(near) => self.max_over(
                near.indices.iter().map(|&i| &self.literals[i as usize]),
                d.max(-near.margin),
                (p, plane, own),
            ),
            None => self.max_over(self.literals.iter(), d, (p, plane, own)),
        }
    }

    /// [`Self::distance`] over `literals`, from `d`.
    pub(super) fn max_over<'a>(
        &self,
        literals: impl Iterator<Item = &'a Literal>,
        mut d: f64,
        (p, plane, own): (DVec3, Option<&SheetPlane>, bool),
    ) -> f64 {
        for literal in literals {
            let on_plane = plane.filter(|_| literal.planar);
            if !own && literal.in_own_term && on_plane.is_none() {
                continue;
            }
            // Evaluated once: a planar literal needs it for the plane test too.
            let distance = literal.quadric.conservative_distance(p);
            let shared = on_plane.map_or(Shared::No, |plane| {
                (literal.on_sheet).unwrap_or_else(|| plane.shared(literal, p, distance))
            });
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
