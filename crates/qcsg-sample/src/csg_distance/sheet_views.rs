//! The terms as seen from one sheet of the sampled quadric ([`SheetViews`]): each literal of the
//! DNF classified against the sheet once ([`Seen`]), and each term's literals refined by the
//! rules for shared, tangent and sectioned planes ([`Refined`]).

use super::abutting::{MADE_LITERAL, TermLiterals};
use super::distance::SheetViews;
use super::half_spaces::{HalfSpace, PlanarParts};
use super::identity::SheetIdentity;
use super::sections::{
    no_area_between, one_side, one_side_with_area, own_half_spaces, section, without_own_sides,
};
use super::tangency::{Contact, Shape, Shapes, Tangency};
use super::view::{NearTerms, SAME_QUADRIC, Shared, TermView};
use qcsg_csg::{Aabb, Dnf};
use qcsg_quadric::{DVec3, Quadric};
use rustc_hash::FxHashMap;

impl SheetViews {
    /// The views of every term from `plane`, sheet `sheet` of the sampled quadric `quadric` of
    /// term `term` (the whole quadric when `None`).
    pub(super) fn new(
        dnf: &Dnf,
        shapes: &Shapes,
        (quadric, term): (u32, u32),
        (sheet, plane): (u32, Option<HalfSpace>),
        terms: &NearTerms,
    ) -> Self {
        let tolerance = shapes.tolerance;
        let q = dnf.quadrics[quadric as usize].quadric;
        let own_term = &dnf.terms[term as usize];
        let region = dnf.region.unwrap_or(Aabb::new(
            DVec3::splat(f64::NEG_INFINITY),
            DVec3::splat(f64::INFINITY),
        ));
        let contact = Tangency::new(shapes, quadric, plane, &own_term.bounds);
        let complement = q.negated();
        let same_value = |o: &Quadric| q.approx_eq_up_to_scale(o, SAME_QUADRIC);
        let complement_value = |o: &Quadric| complement.approx_eq_up_to_scale(o, SAME_QUADRIC);
        // The compiler's surfaces decide which literals are the sampled quadric, its complement
        // or on the sheet; the value and point tests stand where a DNF has no surfaces.
        let identity = SheetIdentity::new(dnf, quadric, plane.as_ref());
        // Each quadric of the DNF in these terms as a literal seen from the sheet, found once.
        let (own_term_literals, own_floor) = &terms.own;
        let in_terms = own_term_literals.iter().map(|(i, _)| *i).chain(
            terms
                .others
                .iter()
                .flat_map(|((literals, _), _)| literals.iter().map(|(i, _)| *i)),
        );
        let seen: FxHashMap<u32, Seen> = in_terms
            .filter_map(|i| {
                Some((
                    i,
                    dnf.quadrics.get(i as usize)?,
                    shapes.shapes.get(i as usize)?,
                ))
            })
            .map(|(i, entry, shape)| {
                let o = entry.quadric;
                let on_sheet = identity.on_sheet(i);
                let contact = contact.of_identified(shape, on_sheet);
                let SeenFromSheet {
                    same,
                    complement,
                    section,
                } = shapes.seen_from_sheet(
                    (quadric, sheet, i),
                    || match identity.identity(i) {
                        Some((same, complement)) => (i == quadric || same, complement),
                        None => (i == quadric || same_value(&o), complement_value(&o)),
                    },
                    |same, complement| !(same || complement) && contact == Contact::Crosses,
                    || plane.and_then(|h| section(&o, &h)),
                );
                let section = section.flatten();
                let (refined, planar, parts) = match section {
                    Some((section, parts)) => (section, parts.is_some(), parts),
                    None => (o, shape.is_planar, shape.planar.clone()),
                };
                let seen = Seen {
                    contact,
                    same,
                    complement,
                    refined,
                    planar,
                    parts,
                    on_sheet,
                };
                (i, seen)
            })
            .collect();
        // A literal made here (merged terms) is looked at on its own.
        let made = |o: &Quadric| {
            let shape = Shape::of(o);
            Seen {
                contact: contact.of(&shape),
                same: same_value(o),
                complement: complement_value(o),
                refined: *o,
                planar: shape.is_planar,
                parts: shape.planar,
                on_sheet: None,
            }
        };
        let look = |i: u32, o: &Quadric| -> std::borrow::Cow<'_, Seen> {
            match seen.get(&i) {
                Some(s) if i != MADE_LITERAL => std::borrow::Cow::Borrowed(s),
                _ => std::borrow::Cow::Owned(made(o)),
            }
        };
        // The literals of a term as the sheet sees them: those that hold on all of it left out.
        let literals = |literals: &TermLiterals| -> TermLiterals {
            literals
                .iter()
                .filter(|(i, o)| look(*i, o).contact != Contact::Holds)
                .copied()
                .collect()
        };
        // Those that cross it replaced by their section by the plane where that is planar, and
        // the outside of a slab by one half-space where the term lies beyond the slab's other
        // plane (`bounds` holds the term). Each keeps its index: another term holding it holds
        // the same set ("Literals of both terms" compares indices). The sampled quadric and its
        // complement stay as they are: eq. 22 finds them by index and value. Abutting terms are
        // found before this: planes made here would pair up many more of them, each merged
        // term spanning two terms' boxes, for little.
        let refine = |literals: &TermLiterals, bounds: &Aabb| -> Vec<Refined> {
            literals
                .iter()
                .map(|&(index, o)| {
                    let seen = look(index, &o);
                    let as_is = seen.same || seen.complement || seen.contact == Contact::Excludes;
                    let side = (!as_is)
                        .then(|| one_side(seen.parts.as_ref(), bounds, tolerance))
                        .flatten();
                    match side {
                        Some(half) => {
                            let planes = seen.parts.as_ref().map_or(&[][..], |(p, _)| &p[..]);
                            let on_sheet = plane.as_ref().and_then(|plane| {
                                identity.half_on_sheet(index, &half, planes, plane)
                            });
                            Refined::one_side(index, half, seen.refined, on_sheet)
                        }
                        None => Refined {
                            index,
                            quadric: seen.refined,
                            planar: seen.planar,
                            parts: seen.parts.clone(),
                            same: seen.same,
                            complement: seen.complement,
                            on_sheet: seen.on_sheet,
                        },
                    }
                })
                .collect()
        };
        // A term with a literal that holds on the sheet only where it touches it has no
        // interior point on it: term `a` samples nothing there, another term is left out.
        let excludes = |literals: &TermLiterals| {
            literals
                .iter()
                .any(|(i, o)| look(*i, o).contact == Contact::Excludes)
        };
        let own_raw = literals(own_term_literals);
        let own_empty = excludes(&own_raw);
        let mut own_literals = refine(&own_raw, &own_term.bounds);
        let sides_empty = plane.is_some_and(|plane| {
            one_side_with_area(&mut own_literals, &plane, &own_term.bounds, tolerance)
        });
        let in_own_term = |r: &Refined| {
            terms.own_far.binary_search(&r.index).is_ok()
                || own_literals.iter().any(|o| {
                    o.index == r.index || o.quadric.approx_eq_up_to_scale(&r.quadric, SAME_QUADRIC)
                })
        };
        let own = TermView::new(
            own_literals
                .iter()
                .filter(|r| !r.same)
                .map(|r| (r.quadric, r.planar, false, r.on_sheet)),
            region,
            (own_term.bounds, *own_floor),
        );
        let own_sides = own_half_spaces(&own_literals, plane.as_ref());
        // Terms that the sheet excludes still abut others: their merged unions (made before)
        // may reach it.
        let others = terms
            .others
            .iter()
            .map(|((list, floor), extent)| (literals(list), (*extent, *floor)))
            .filter(|(literals, _)| !excludes(literals))
            .map(|(literals, (extent, floor))| {
                let literals = refine(&literals, &extent)
                    .into_iter()
                    .filter(|r| !r.complement)
                    .flat_map(|r| {
                        if in_own_term(&r) {
                            return vec![(r.quadric, r.planar, true, r.on_sheet)];
                        }
                        without_own_sides(&r, &own_sides, tolerance)
                    });
                TermView::new(literals, region, (extent, floor))
            })
            .collect();
        let own_empty = own_empty
            || sides_empty
            || plane.is_some_and(|plane| {
                no_area_between(&own_sides, &plane, &own_term.bounds, tolerance)
            });
        Self {
            plane,
            own,
            own_empty,
            others,
        }
    }
}

/// A quadric of the DNF as a literal seen from one sheet ([`SheetViews::new`]).
#[derive(Clone)]
pub(super) struct Seen {
    pub(super) contact: Contact,
    /// The sampled quadric (by index or value).
    pub(super) same: bool,
    /// Its complement.
    pub(super) complement: bool,
    /// The literal, or its planar section by the sheet.
    pub(super) refined: Quadric,
    pub(super) planar: bool,
    /// The half-spaces of `refined`, when planar ([`planar_parts`](super::half_spaces::planar_parts)).
    pub(super) parts: Option<PlanarParts>,
    /// How it lies on the sheet, as the compiler's surfaces decided ([`SheetIdentity`]).
    pub(super) on_sheet: Option<Shared>,
}

/// A literal of the DNF as a sheet of a sampled quadric sees it, whatever the term: whether it
/// is the sampled quadric or its complement, and its section by the sheet's plane (`None` until
/// a view has asked for it).
#[derive(Clone)]
pub(super) struct SeenFromSheet {
    pub(super) same: bool,
    pub(super) complement: bool,
    pub(super) section: Option<Option<(Quadric, Option<PlanarParts>)>>,
}

/// A literal of a term as the view holds it.
pub(super) struct Refined {
    /// Its index in the DNF ([`MADE_LITERAL`] if made here).
    pub(super) index: u32,
    pub(super) quadric: Quadric,
    pub(super) planar: bool,
    pub(super) parts: Option<PlanarParts>,
    pub(super) same: bool,
    pub(super) complement: bool,
    /// How it lies on the sheet ([`Seen::on_sheet`]).
    pub(super) on_sheet: Option<Shared>,
}

impl Refined {
    /// Literal `index`, the outside of a slab, as the one half-space `half` of it that the term
    /// holds ("One side of a slab"); `outside` stands if the half-space cannot be formed.
    pub(super) fn one_side(
        index: u32,
        half: HalfSpace,
        outside: Quadric,
        on_sheet: Option<Shared>,
    ) -> Self {
        Self {
            index,
            quadric: Quadric::half_space(half.point, half.normal).unwrap_or(outside),
            planar: true,
            parts: Some((vec![half], false)),
            same: false,
            complement: false,
            on_sheet,
        }
    }
}
