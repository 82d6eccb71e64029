//! Eq. 22 for the points of one box ([`NearDistance`]): the terms and literals that come near
//! it, the others entering as a constant floor ("Far terms", "Far literals" in [`super`]), and
//! the tests that leave a basic region out before any query or sample it without one.

use super::distance::CsgDistance;
use super::view::{FEW_LITERALS, Literal, NearLiterals, TermView};
use qcsg_csg::Aabb;
use qcsg_csg::quadric_box::{self, BoxClass};
use qcsg_quadric::{DVec3, Quadric};

/// [`CsgDistance`] for the points of one box ([`CsgDistance::near`]). A term whose box is at
/// least `far` away from every point of the box contributes at most `−far` to the maximum (its
/// interior is at least that far), so it is replaced by that constant: classifications stay
/// valid, only radii beyond `far` are cut.
#[derive(Clone, Debug)]
pub struct NearDistance<'a> {
    pub(super) base: &'a CsgDistance,
    /// The sheet of the box, when it has one.
    pub(super) sheet: Option<usize>,
    /// The literals of term `a` near the box, for a term of many ("Far literals"); `None`: all.
    pub(super) own: Option<NearLiterals>,
    /// The other terms near the box, and the literals of each near it (as `own`; empty when
    /// every term keeps all).
    pub(super) terms: Vec<u32>,
    pub(super) lists: Vec<Option<NearLiterals>>,
    pub(super) far: f64,
}

impl NearDistance<'_> {
    /// [`CsgDistance::near`] for a box inside this one's, with a margin no larger, from what
    /// this one kept: a term or literal left out here is left out there too.
    pub fn narrow(&self, bounds: &Aabb, margin: f64) -> Self {
        match self.sheet {
            Some(sheet) => self.base.near_on(sheet, bounds, margin, Some(self)),
            None => self.base.near(bounds, margin),
        }
    }

    /// Whether eq. 22 here looks at other terms than the sampled one.
    pub fn has_other_terms(&self) -> bool {
        self.sheet.is_none() || !self.terms.is_empty()
    }

    /// The literals of the `k`-th kept term near the box, where not all.
    pub(super) fn list(&self, k: usize) -> Option<&NearLiterals> {
        self.lists.get(k).and_then(Option::as_ref)
    }

    /// How many literals an evaluation looks at in the terms of many literals ("Far
    /// literals"): what keeping to a smaller box can cut down.
    pub fn literals_of_large_terms(&self) -> usize {
        let count = |view: &TermView, near: Option<&NearLiterals>| {
            if view.literals.len() <= FEW_LITERALS {
                return 0;
            }
            near.map_or(view.literals.len(), |n| n.indices.len())
        };
        let Some(sheet) = self.sheet else {
            return 0;
        };
        let views = &self.base.sheets[sheet];
        count(&views.own, self.own.as_ref())
            + (self.terms.iter().enumerate())
                .map(|(k, i)| count(&views.others[*i as usize], self.list(k)))
                .sum::<usize>()
    }

    /// Whether eq. 22 is nowhere negative in `patch` (a box inside the one given to
    /// [`CsgDistance::near`]), so that no point of the sampled quadric there is proven on the
    /// surface and sampling it would emit nothing: a literal of term `a` fails on all of
    /// `patch` (its own distance is positive), or another term's box holds `patch` and each of
    /// the literals it looks at holds on all of it (its distance is at most zero, and eq. 22
    /// at least zero). `quadric_box::classify` decides over `patch` grown by more than the
    /// length tolerance of "Shared planes", so that no literal it decides is on the plane of a
    /// point there. `false` where it cannot tell.
    pub fn nowhere_negative(&self, patch: &Aabb) -> bool {
        let Some(sheet) = self.sheet else {
            return false;
        };
        let views = &self.base.sheets[sheet];
        if views.own_empty {
            return true;
        }
        let Some(grown) = self.grown(patch) else {
            return false;
        };
        let quadrics = &views.quadrics[..];
        any_fails(views.own.looked_at(self.own.as_ref()), quadrics, &grown)
            || self.terms.iter().enumerate().any(|(k, &i)| {
                let view = &views.others[i as usize];
                // A term holding all of the box has a box holding it (`extent`), and its
                // distance is positive outside the DNF's region (`bounds`).
                (view.extent.contains_box(&grown) && views.region.contains_box(&grown))
                    && all_hold(view.looked_at(self.list(k)), quadrics, &grown)
            })
    }

    /// Whether every point of the sampled quadric in `patch` (a box inside the one given to
    /// [`CsgDistance::near`]) is on the surface: each literal of term `a` that eq. 22 looks at
    /// holds on all of `patch`, which the DNF's region holds, and every other term it keeps
    /// misses `patch` (its box does, or one of its literals fails on all of it); the terms it
    /// left out are farther. Decided as [`Self::nowhere_negative`] does.
    pub fn everywhere_on_surface(&self, patch: &Aabb) -> bool {
        let Some(sheet) = self.sheet else {
            return false;
        };
        let views = &self.base.sheets[sheet];
        let Some(grown) = self.grown(patch).filter(|_| !views.own_empty) else {
            return false;
        };
        let (own, quadrics) = (&views.own, &views.quadrics[..]);
        (views.region.contains_box(&grown)
            && all_hold(own.looked_at(self.own.as_ref()), quadrics, &grown))
            && self.terms.iter().enumerate().all(|(k, &i)| {
                let view = &views.others[i as usize];
                !view.extent.intersects(&grown)
                    || any_fails(view.looked_at(self.list(k)), quadrics, &grown)
            })
    }

    /// `patch` grown by more than the length tolerance of "Shared planes" and rounding, so that
    /// no literal `quadric_box::classify` decides over it is on the plane of a point of `patch`;
    /// `None` for an unbounded box.
    pub(super) fn grown(&self, patch: &Aabb) -> Option<Aabb> {
        let rounding = 16.0 * f64::EPSILON * patch.min.abs().max(patch.max.abs()).max_element();
        let grown = patch.expanded(4.0 * self.base.tolerance + rounding);
        grown.is_bounded().then_some(grown)
    }

    /// Eq. 22 at `p`, for `p` inside the box given to [`CsgDistance::near`].
    pub fn distance(&self, p: DVec3) -> f64 {
        let Some(sheet) = self.sheet else {
            return self.base.distance(p);
        };
        let sheet = &self.base.sheets[sheet];
        let others = (self.terms.iter().enumerate())
            .map(|(k, i)| (&sheet.others[*i as usize], self.list(k)));
        self.base
            .distance_over(p, sheet, self.own.as_ref(), others, self.far)
    }
}

/// Whether each of `literals` that a term's distance looks at (not those of another term that
/// term `a` holds too, [`TermView::max_over`]) holds on all of `bounds`: the signs at the
/// centre first, which most terms fail at once (`classify` costs up to a few hundred
/// instructions). `quadrics` are the sheet's.
pub(super) fn all_hold<'a>(
    literals: impl Iterator<Item = &'a Literal> + Clone,
    quadrics: &[Quadric],
    bounds: &Aabb,
) -> bool {
    let centre = bounds.centre();
    let quadric = |l: &Literal| &quadrics[l.slot as usize];
    let mut looked_at = literals.filter(|literal| !literal.in_own_term);
    looked_at.clone().all(|l| quadric(l).value(centre) < 0.0)
        && looked_at.all(|l| quadric_box::classify(quadric(l), bounds) == BoxClass::Inside)
}

/// Whether one of `literals` fails on all of `bounds` (it fails at the centre first).
pub(super) fn any_fails<'a>(
    literals: impl Iterator<Item = &'a Literal>,
    quadrics: &[Quadric],
    bounds: &Aabb,
) -> bool {
    let centre = bounds.centre();
    let quadric = |l: &Literal| &quadrics[l.slot as usize];
    (literals.filter(|l| quadric(l).value(centre) > 0.0))
        .any(|l| quadric_box::classify(quadric(l), bounds) == BoxClass::Outside)
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
