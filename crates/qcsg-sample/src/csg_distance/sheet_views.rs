//! The terms as seen from one sheet of the sampled quadric ([`SheetViews`]): each literal of the
//! DNF classified against the sheet once ([`Seen`]), and each term's literals refined by the
//! rules for shared, tangent and sectioned planes ([`Refined`]).

use super::distance::SheetViews;
use super::half_spaces::{HalfSpace, PlanarParts};
use super::identity::SheetIdentity;
use super::positions::Positions;
use super::sections::{
    no_area_between, one_side, one_side_with_area, own_half_spaces, section, without_own_sides,
};
use super::tangency::{Contact, Shape, Shapes, Tangency};
use super::view::{NearList, NearTerms, SAME_QUADRIC, Shared, TermView, ViewLiteral};
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
        terms: &NearTerms<'_>,
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
        let own_list = &terms.own;
        // Each once: the terms of a distributed difference hold the same few hundreds of times.
        // Gathered from the lists, so that the work stays that of the terms near the patch
        // however many quadrics the DNF has.
        let lists = std::iter::once(own_list).chain(terms.others.iter().map(|(list, _)| list));
        // A literal of the DNF.
        let of_dnf = |i: u32, o: Quadric, shape: &Shape| {
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
            let (refined, planar, parts) = match section.flatten() {
                Some((section, parts)) => (section, parts.is_some(), parts),
                None => (o, shape.is_planar, shape.planar.clone()),
            };
            Seen {
                contact,
                same,
                complement,
                refined,
                planar,
                parts,
                on_sheet,
            }
        };
        // A literal made for a merged term is looked at on its own.
        let made = |o: &Quadric, shape: &Shape| Seen {
            contact: contact.of(shape),
            same: same_value(o),
            complement: complement_value(o),
            refined: *o,
            planar: shape.is_planar,
            parts: shape.planar.clone(),
            on_sheet: None,
        };
        let mut positions = Positions::new(shapes.literal_count());
        let mut seen: Vec<Seen> = Vec::new();
        for &(i, o) in lists.flat_map(NearList::iter) {
            positions.get_or_insert_with(i, || {
                seen.push(match shapes.made_shape(i) {
                    Some(shape) => made(&o, shape),
                    None => of_dnf(i, o, shapes.of(i)),
                });
                seen.len() - 1
            });
        }
        // Every literal of the lists is seen.
        let look = |i: u32| &seen[positions.get(i).expect("each listed literal is seen")];
        // The literals of a term as the sheet sees them leave out those that hold on all of it.
        let holds = |literal: &&(u32, Quadric)| look(literal.0).contact == Contact::Holds;
        // Those that cross it replaced by their section by the plane where that is planar, and
        // the outside of a slab by one half-space where the term lies beyond the slab's other
        // plane (`bounds` holds the term). Each keeps its index: another term holding it holds
        // the same set ("Literals of both terms" compares indices). The sampled quadric and its
        // complement stay as they are: eq. 22 finds them by index and value. Abutting terms are
        // found before this: planes made here would pair up many more of them, each merged
        // term spanning two terms' boxes, for little.
        let side_of = |seen: &Seen, bounds: &Aabb| {
            let as_is = seen.same || seen.complement || seen.contact == Contact::Excludes;
            (!as_is)
                .then(|| one_side(seen.parts.as_ref(), bounds, tolerance))
                .flatten()
        };
        let refined = |index: u32, seen: &Seen, side: Option<HalfSpace>| match side {
            Some(half) => {
                let planes = seen.parts.as_ref().map_or(&[][..], |(p, _)| &p[..]);
                let on_sheet = (plane.as_ref())
                    .and_then(|plane| identity.half_on_sheet(index, &half, planes, plane));
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
        };
        // A term with a literal that holds on the sheet only where it touches it has no
        // interior point on it: term `a` samples nothing there, another term is left out.
        let excludes = |list: &NearList<'_>| {
            list.iter()
                .any(|(i, _)| look(*i).contact == Contact::Excludes)
        };
        let own_empty = excludes(own_list);
        let mut own_literals: Vec<Refined> = (own_list.iter())
            .filter(|l| !holds(l))
            .map(|(index, _)| {
                let (index, seen) = (*index, look(*index));
                refined(index, seen, side_of(seen, &own_term.bounds))
            })
            .collect();
        let sides_empty = plane.is_some_and(|plane| {
            one_side_with_area(&mut own_literals, &plane, &own_term.bounds, tolerance)
        });
        let mut slots = Slots::default();
        let own = TermView::new(
            (own_literals.iter().filter(|r| !r.same))
                .map(|r| (slots.of(r.quadric), r.planar, false, r.on_sheet))
                .collect::<Vec<_>>(),
            (own_term.bounds, own_list.floor),
        );
        let in_own_term = |r: &Refined| {
            terms.own_far.binary_search(&r.index).is_ok()
                || own_literals.iter().any(|o| {
                    o.index == r.index || o.quadric.approx_eq_up_to_scale(&r.quadric, SAME_QUADRIC)
                })
        };
        let own_sides = own_half_spaces(&own_literals, plane.as_ref());
        // What each literal adds to another term's view, found once for the literal and the
        // side of a slab the term holds (none, or one of its planes by its bits): the terms of
        // a distributed difference hold the same few hundreds of times.
        type ViewKey = (u32, Option<[u64; 4]>);
        let mut view_literals: FxHashMap<ViewKey, Vec<ViewLiteral>> = FxHashMap::default();
        // Terms that the sheet excludes still abut others: their merged unions (made before)
        // may reach it.
        let others = terms
            .others
            .iter()
            .filter(|(list, _)| !excludes(list))
            .map(|(list, extent)| {
                let mut literals = Vec::with_capacity(list.len());
                for (index, _) in list.iter().filter(|l| !holds(l)) {
                    let (index, seen) = (*index, look(*index));
                    let side = side_of(seen, extent);
                    // The same in every term that holds it, or holds the same side of it.
                    let side_bits = side.map(|h| {
                        let n = h.normal;
                        [n.x, n.y, n.z, h.offset].map(f64::to_bits)
                    });
                    let key = (index, side_bits);
                    if let Some(done) = view_literals.get(&key) {
                        literals.extend_from_slice(done);
                        continue;
                    }
                    let r = refined(index, seen, side);
                    let start = literals.len();
                    if !r.complement {
                        let slot = slots.of(r.quadric);
                        if in_own_term(&r) {
                            literals.push((slot, r.planar, true, r.on_sheet));
                        } else if let Some(halves) = without_own_sides(&r, &own_sides, tolerance) {
                            let made = halves.into_iter().map(|h| slots.of(h));
                            literals.extend(made.map(|slot| (slot, true, false, None)));
                        } else {
                            literals.push((slot, r.planar, false, r.on_sheet));
                        }
                    }
                    view_literals.insert(key, literals[start..].to_vec());
                }
                TermView::new(literals, (*extent, list.floor))
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
            region,
            quadrics: slots.quadrics,
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
    /// Its index among the DNF's quadrics and the literals made for merged terms.
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

/// The distinct quadrics of a sheet's views ([`SheetViews::quadrics`]), each given its slot
/// once, by exact value.
#[derive(Default)]
struct Slots {
    by_value: FxHashMap<[u64; 13], u32>,
    quadrics: Vec<Quadric>,
}

impl Slots {
    /// The slot of `quadric`, by the bits of its coefficients and origin.
    fn of(&mut self, quadric: Quadric) -> u32 {
        let mut bits = [0; 13];
        let values = quadric.coefficients().into_iter();
        let values = values.chain(quadric.origin().to_array());
        bits.iter_mut()
            .zip(values)
            .for_each(|(b, v)| *b = v.to_bits());
        let quadrics = &mut self.quadrics;
        *self.by_value.entry(bits).or_insert_with(|| {
            quadrics.push(quadric);
            quadrics.len() as u32 - 1
        })
    }
}
