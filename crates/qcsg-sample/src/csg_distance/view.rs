//! A term of the DNF as one sampled quadric sees it ([`TermView`]): the literals that matter
//! to eq. 22 there, how each meets the sampled quadric's plane through a point ([`Shared`],
//! [`SheetPlane`]: "Shared planes" in [`super`]), and, for terms of many literals, those near a
//! box ([`NearTerms`], [`NearLiterals`]). The literals name their quadrics by slot in the
//! sheet's table of distinct quadrics, whose distances at a point are found once however many
//! terms hold them ([`LiteralValues`]).

use super::near::box_distance;
use either::Either;
use qcsg_csg::Aabb;
use qcsg_csg::quadric_box::{self, BoxClass};
use qcsg_quadric::{DVec3, Quadric};

/// Relative tolerance for "the same quadric" when comparing literals.
pub(super) const SAME_QUADRIC: f64 = 1e-12;

/// Relative tolerance for parallel normals of planes that share a point.
pub(super) const PARALLEL: f64 = 1e-9;

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
    /// `distance` is the literal's conservative distance at `p`, `quadric` its quadric.
    pub(super) fn shared(
        &self,
        (literal, quadric): (&Literal, &Quadric),
        p: DVec3,
        distance: f64,
    ) -> Shared {
        if !literal.planar || distance.abs() > self.tolerance {
            return Shared::No;
        }
        let Some(n) = quadric.normal(p) else {
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
#[derive(Clone, Copy, Debug)]
pub(super) struct Literal {
    /// Its quadric, an index into the sheet's distinct quadrics
    /// ([`SheetViews::quadrics`](super::distance::SheetViews::quadrics)): hundreds of terms of a
    /// distributed difference hold the same few, kept and evaluated once.
    pub(super) slot: u32,
    pub(super) planar: bool,
    /// A literal of another term that term `a` holds too (see "Literals of both terms").
    pub(super) in_own_term: bool,
    /// How it lies on the sampled sheet, as the compiler's surfaces decided
    /// ([`SheetIdentity`](super::identity::SheetIdentity)); `None` where they did not (a
    /// literal made by the sampler, a DNF without surfaces): then the point test of
    /// [`SheetPlane::shared`] decides.
    pub(super) on_sheet: Option<Shared>,
}

/// A literal as [`TermView::new`] takes it: its quadric's slot, whether it is planar, whether
/// term `a` holds it too, and how it lies on the sheet.
pub(super) type ViewLiteral = (u32, bool, bool, Option<Shared>);

/// A term of the DNF as seen from one quadric: the literals that matter (the DNF's region,
/// which bounds every term, is the sheet's: [`SheetViews::region`](super::distance::SheetViews::region)).
#[derive(Clone, Debug)]
pub(super) struct TermView {
    pub(super) literals: Vec<Literal>,
    /// A box holding the whole term (for [`CsgDistance::near`](crate::csg_distance::CsgDistance::near)).
    pub(super) extent: Aabb,
    /// The least distance: `−reach` where literals that hold within `reach` of the sampled part
    /// were left out ("Far literals"), else `−∞`.
    pub(super) floor: f64,
}

/// Terms with more literals than this leave out, near a box, those that hold all around it
/// ("Far literals").
pub(super) const FEW_LITERALS: usize = 32;

/// The literals of a term that eq. 22 looks at, with the term's floor: those of `all` at the
/// positions `kept`, all of them when `None`.
pub(super) struct NearList<'a> {
    all: &'a [(u32, Quadric)],
    kept: Option<Vec<u32>>,
    pub(super) floor: f64,
}

impl<'a> NearList<'a> {
    pub(super) fn new(all: &'a [(u32, Quadric)], kept: Option<Vec<u32>>, floor: f64) -> Self {
        Self { all, kept, floor }
    }

    /// The literals kept, in the term's order.
    pub(super) fn iter(&self) -> impl Iterator<Item = &'a (u32, Quadric)> + Clone + '_ {
        let all = self.all;
        match &self.kept {
            Some(kept) => Either::Left(kept.iter().map(move |&k| &all[k as usize])),
            None => Either::Right(all.iter()),
        }
    }

    /// The literals left out, in the term's order.
    pub(super) fn left_out(&self) -> impl Iterator<Item = &'a (u32, Quadric)> + '_ {
        let mut kept = self.kept.as_ref().map(|k| k.iter().copied().peekable());
        (self.all.iter().enumerate())
            .filter(move |(k, _)| {
                kept.as_mut()
                    .is_some_and(|kept| kept.next_if_eq(&(*k as u32)).is_none())
            })
            .map(|(_, literal)| literal)
    }

    pub(super) fn len(&self) -> usize {
        self.kept.as_ref().map_or(self.all.len(), Vec::len)
    }
}

/// The terms eq. 22 of one sampled literal looks at, as the DNF has them: term `a`'s literals,
/// then every other term's literals and box; each list with its floor, `−reach` where literals
/// far from the sampled part were left out ("Far literals"), else `−∞`.
pub(super) struct NearTerms<'a> {
    pub(super) own: NearList<'a>,
    /// The indices of term `a`'s literals left out, ascending: "Literals of both terms" still
    /// applies to them.
    pub(super) own_far: Vec<u32>,
    pub(super) others: Vec<(NearList<'a>, Aabb)>,
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
        literals: impl IntoIterator<Item = ViewLiteral>,
        (extent, floor): (Aabb, f64),
    ) -> Self {
        let literals: Vec<Literal> = literals
            .into_iter()
            .map(|(slot, planar, in_own_term, on_sheet)| Literal {
                slot,
                planar,
                in_own_term,
                on_sheet,
            })
            .collect();
        Self {
            extent,
            literals,
            floor,
        }
    }

    /// The literals of a term of many that may fail within `margin` of `bounds`, among those of
    /// `within` (all when `None`), when that leaves some out ("Far literals"); `quadrics` are
    /// the sheet's.
    pub(super) fn near_literals(
        &self,
        quadrics: &[Quadric],
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
                let literal = &quadrics[self.literals[i as usize].slot as usize];
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
    /// the module docs: `own` says whether this is term `a`. Once the maximum reaches `above`,
    /// the rest is not looked at and what is returned is at least `above` (a term no nearer
    /// than one already found).
    pub(super) fn distance(
        &self,
        (p, plane, own): (DVec3, Option<&SheetPlane>, bool),
        near: Option<&NearLiterals>,
        (slack, above): (f64, f64),
        values: &mut LiteralValues<'_>,
    ) -> f64 {
        // The literals left out hold within `−floor − slack` of `p` (`p` is `slack` outside the
        // sampled part), and within `margin` of `p` for a box's ([`NearLiterals`]).
        let d = values.region_distance.max(self.floor + slack);
        let at = (p, plane, own);
        match near {
            Some(near) => self.max_over(
                near.indices.iter().map(|&i| &self.literals[i as usize]),
                (d.max(-near.margin), above),
                at,
                values,
            ),
            None => self.max_over(self.literals.iter(), (d, above), at, values),
        }
    }

    /// [`Self::distance`] over `literals`, from `d`.
    fn max_over<'a>(
        &self,
        literals: impl Iterator<Item = &'a Literal>,
        (mut d, above): (f64, f64),
        (p, plane, own): (DVec3, Option<&SheetPlane>, bool),
        values: &mut LiteralValues<'_>,
    ) -> f64 {
        for literal in literals {
            if d >= above {
                return d;
            }
            let on_plane = plane.filter(|_| literal.planar);
            if !own && literal.in_own_term && on_plane.is_none() {
                continue;
            }
            // Evaluated once: a planar literal needs it for the plane test too.
            let (distance, quadric) = values.at(literal.slot);
            let shared = on_plane.map_or(Shared::No, |plane| {
                (literal.on_sheet).unwrap_or_else(|| plane.shared((literal, quadric), p, distance))
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

/// What every term's distance at one point shares: the distance to the DNF's region, and the
/// conservative distances of the sheet's quadrics, each found once however many terms hold it.
pub(super) struct LiteralValues<'a> {
    region_distance: f64,
    quadrics: &'a [Quadric],
    point: DVec3,
    /// Per slot, the distance at `point` where found.
    found: Vec<Option<f64>>,
}

impl<'a> LiteralValues<'a> {
    pub(super) fn new(region: &Aabb, quadrics: &'a [Quadric], point: DVec3) -> Self {
        Self {
            region_distance: box_distance(region, point),
            quadrics,
            point,
            found: vec![None; quadrics.len()],
        }
    }

    /// The distance of quadric `slot` at the point, and the quadric.
    fn at(&mut self, slot: u32) -> (f64, &'a Quadric) {
        let quadric = &self.quadrics[slot as usize];
        let point = self.point;
        let found = &mut self.found[slot as usize];
        (
            *found.get_or_insert_with(|| quadric.conservative_distance(point)),
            quadric,
        )
    }
}
