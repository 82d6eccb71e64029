//! Eq. 22 for one literal of one term ([`CsgDistance`]): set up once per sampled literal with
//! the rules of [`super`] applied, narrowed to a box ([`CsgDistance::near`]) and queried at
//! points of the sampled quadric.

use super::abutting::MAX_MERGED_PER_TERM;
use super::half_spaces::HalfSpace;
use super::near::{NearDistance, box_distance};
use super::positions::Positions;
use super::surface_sign::on_surface;
use super::tangency::Shapes;
use super::view::{
    FEW_LITERALS, Literal, LiteralValues, NearList, NearLiterals, NearTerms, SAME_QUADRIC,
    SheetPlane, TermView,
};
use qcsg_csg::quadric_box::{self, BoxClass};
use qcsg_csg::{Aabb, Dnf};
use qcsg_quadric::{DVec3, Quadric};
use std::cell::RefCell;

/// `d_{Q_ab}(S, ·)` for one literal of one term, with the DNF's quadrics copied in.
#[derive(Clone, Debug)]
pub struct CsgDistance {
    /// The terms as seen from each sheet of the sampled quadric: one per plane of a planar
    /// quadric (see "Planar sections"), else one for the whole quadric.
    pub(super) sheets: Vec<SheetViews>,
    /// The sampled quadric, when it is planar (see "Shared planes" in the module docs).
    pub(super) planar: Option<Quadric>,
    /// Length below which a point is on a plane: `1e-9` of the DNF's diagonal.
    pub(super) tolerance: f64,
    /// The box the sampled part lies in, and the depth within which the terms and literals
    /// left out as far do not reach into it (see "Far terms"); `+∞` when none is.
    pub(super) extent: Aabb,
    pub(super) far: f64,
}

/// The terms as seen from one sheet of the sampled quadric.
#[derive(Clone, Debug)]
pub(super) struct SheetViews {
    /// The sheet's plane (`normal · x = offset`), for a planar quadric.
    pub(super) plane: Option<HalfSpace>,
    pub(super) own: TermView,
    /// The DNF's region, which bounds every term (everything where it has none).
    pub(super) region: Aabb,
    /// The distinct quadrics of the views' literals ([`Literal::slot`](super::view::Literal::slot)).
    pub(super) quadrics: Vec<Quadric>,
    /// A literal of term `a` holds on the sheet only where it touches it (see "Tangent
    /// planes"): no point of the sheet is on the surface through term `a`.
    pub(super) own_empty: bool,
    pub(super) others: Vec<TermView>,
}

impl CsgDistance {
    /// The distance for quadric `quadric` sampled as a literal of term `term` of `dnf`.
    /// `None` if the indices are out of range, or where another literal of the term fails on all
    /// of the quadric's surface (it has no part in the term: "Offset surfaces", "Touching
    /// surfaces").
    pub fn new(dnf: &Dnf, quadric: u32, term: u32) -> Option<Self> {
        Self::for_part(dnf, quadric, term, &Aabb::EVERYTHING)
    }

    /// [`Self::new`] for the points of the quadric inside `part`: the terms and literals far
    /// from it are left out (see "Far terms" and "Far literals"), and a positive distance only
    /// claims that no point of the quadric inside `part` within it is on the surface.
    pub fn for_part(dnf: &Dnf, quadric: u32, term: u32, part: &Aabb) -> Option<Self> {
        Self::with_shapes(dnf, &Shapes::new(dnf), (quadric, term), part)
    }

    /// [`Self::for_part`] with what every distance of `dnf` shares ([`Shapes`]) found once
    /// (`patch`: a box around the quadric's basic regions).
    pub(crate) fn with_shapes<'a>(
        dnf: &Dnf,
        shapes: &'a Shapes,
        (quadric, term): (u32, u32),
        patch: &Aabb,
    ) -> Option<Self> {
        let q = dnf.quadrics.get(quadric as usize)?.quadric;
        let own_term = dnf.terms.get(term as usize)?;
        let shape = shapes.of(quadric);
        // Where the sampled part lies: in term `a`'s box and the patch (the whole box where they
        // miss), grown by the length tolerance (points rounded off its faces are in).
        let term_box = match dnf.region {
            Some(region) => own_term.bounds.intersection(&region),
            None => own_term.bounds,
        };
        let part = term_box.intersection(patch);
        let extent = if part.is_empty() { term_box } else { part }.expanded(shapes.tolerance);
        let reach = (extent.max - extent.min).length();
        let near = shapes.boxes.near(&extent, reach);
        let terms_left_out = near.len() < shapes.boxes.boxes().len();
        // The other terms and their abutting unions, as the DNF has them: what each sheet sees
        // of them follows. Terms holding the sampled quadric are left out ("Shared surfaces"),
        // and so are unions with them or with term `a`.
        // By index, once each: the same few literals recur in hundreds of terms.
        let literal_count = shapes.literal_count();
        let same_by_index = RefCell::new((Positions::new(literal_count), Vec::new()));
        let same = |i: u32, o: &Quadric| {
            let (positions, found) = &mut *same_by_index.borrow_mut();
            let at = positions.get_or_insert_with(i, || {
                found.push(i == quadric || q.approx_eq_up_to_scale(o, SAME_QUADRIC));
                found.len() - 1
            });
            found[at]
        };
        let kept: Vec<u32> = near
            .into_iter()
            .filter(|&index| {
                index != term
                    && !shapes.terms[index as usize]
                        .iter()
                        .any(|(i, o)| same(*i, o))
            })
            .collect();
        let is_kept = |index: usize| kept.binary_search(&(index as u32)).is_ok();
        // The unions of two kept terms, in the order of `shapes.merged`.
        let mut unions: Vec<u32> = kept
            .iter()
            .flat_map(|&i| &shapes.merged_with[i as usize])
            .copied()
            .filter(|&m| {
                let (i, k) = shapes.merged[m as usize].1;
                is_kept(i) && is_kept(k)
            })
            .collect();
        unions.sort_unstable();
        unions.dedup();
        unions.truncate(MAX_MERGED_PER_TERM * kept.len().max(1));
        // A point outside both terms' boxes is outside both pieces, where the merged term fails
        // a literal that the piece on the point's side of the plane fails: it is no nearer than
        // that piece, and adds nothing to eq. 22 ("Abutting terms").
        let merged: Vec<(&[(u32, Quadric)], Aabb)> = unions
            .into_iter()
            .map(|m| &shapes.merged[m as usize])
            .map(|(literals, (i, k))| {
                let bounds = dnf.terms[*i].bounds.union(&dnf.terms[*k].bounds);
                (&literals[..], bounds)
            })
            .filter(|(_, bounds)| bounds.intersects(&extent))
            .collect();
        // Of a term of many literals, those that hold all around the sampled part are left out
        // ("Far literals"); the sampled quadric stays.
        let grown = extent.expanded(reach);
        // So are the literals that hold on all of the sampled surface in that box, and the other
        // terms with a literal that holds on none of it ("Offset surfaces").
        let bounded = !grown.is_empty() && grown.is_bounded();
        // The same few quadrics recur in hundreds of terms (a difference of unions distributed
        // into a DNF): each literal's tests against the box are made once per patch, by index.
        let (mut tested, mut tests) = (Positions::new(literal_count), Vec::new());
        let mut near_literals = |literals: &'a [(u32, Quadric)]| {
            let many = literals.len() > FEW_LITERALS && bounded;
            // All until one is left out.
            let mut kept: Option<Vec<u32>> = None;
            for (k, (i, o)) in literals.iter().enumerate() {
                let i = *i;
                let mut leave_out = || {
                    if kept.is_none() {
                        kept = Some((0..k as u32).collect());
                    }
                };
                if i != quadric {
                    let test = || {
                        // Made half-spaces are planes: no pencil needs their axes.
                        let axes = shapes.shapes.get(i as usize).map(|s| &s.axes);
                        let pair = ((&q, shape), (o, axes));
                        LiteralTests {
                            on_surface: bounded
                                .then(|| on_surface(pair.0, pair.1, &grown))
                                .flatten(),
                            inside: None,
                        }
                    };
                    let at = tested.get_or_insert_with(i, || {
                        tests.push(test());
                        tests.len() - 1
                    });
                    let test = &mut tests[at];
                    if many
                        && *test.inside.get_or_insert_with(|| {
                            quadric_box::classify(o, &grown) == BoxClass::Inside
                        })
                    {
                        leave_out();
                        continue;
                    }
                    match test.on_surface {
                        Some(true) => {
                            leave_out();
                            continue;
                        }
                        Some(false) => return None,
                        None => {}
                    }
                }
                if let Some(kept) = &mut kept {
                    kept.push(k as u32);
                }
            }
            let floor = if kept.is_some() {
                -reach
            } else {
                f64::NEG_INFINITY
            };
            Some(NearList::new(literals, kept, floor))
        };
        let own = near_literals(&shapes.terms[term as usize])?;
        let mut own_far = own.left_out().map(|(i, _)| *i).collect::<Vec<u32>>();
        own_far.sort_unstable();
        let mut near_others = 0;
        let mut others = Vec::with_capacity(kept.len() + merged.len());
        let terms_and_unions = (kept.iter())
            .map(|&i| (&shapes.terms[i as usize][..], dnf.terms[i as usize].bounds))
            .chain(
                merged
                    .into_iter()
                    .filter(|(l, _)| !l.iter().any(|(i, o)| same(*i, o))),
            );
        for (literals, bounds) in terms_and_unions {
            near_others += 1;
            others.extend(near_literals(literals).map(|list| (list, bounds)));
        }
        // The sheets below take tables of their own.
        drop((same_by_index, tested));
        let terms = NearTerms {
            own,
            own_far,
            others,
        };
        let terms_left_out = terms_left_out || terms.others.len() < near_others;
        let planes: Vec<Option<HalfSpace>> = match &shape.planar {
            Some((planes, _)) => planes.iter().copied().map(Some).collect(),
            None => vec![None],
        };
        let sheets = planes
            .into_iter()
            .enumerate()
            .map(|(sheet, plane)| {
                let sheet = (sheet as u32, plane);
                SheetViews::new(dnf, shapes, (quadric, term), sheet, &terms)
            })
            .collect();
        let literals_left_out =
            terms.own.floor.is_finite() || terms.others.iter().any(|(l, _)| l.floor.is_finite());
        let far = if terms_left_out || literals_left_out {
            reach
        } else {
            f64::INFINITY
        };
        Some(Self {
            sheets,
            planar: shape.is_planar.then_some(q),
            tolerance: shapes.tolerance,
            extent,
            far,
        })
    }

    /// The sheet `p` lies on (the nearest plane of a planar quadric).
    pub(super) fn sheet_at(&self, p: DVec3) -> usize {
        let off = |s: &SheetViews| s.plane.map_or(0.0, |h| (h.normal.dot(p) - h.offset).abs());
        (1..self.sheets.len()).fold(0, |best, i| {
            if off(&self.sheets[i]) < off(&self.sheets[best]) {
                i
            } else {
                best
            }
        })
    }

    /// `d_{Q_ab}(S, p)` (eq. 22) for a point `p` on the quadric: negative on the CSG surface.
    /// NaN for non-finite `p`.
    pub fn distance(&self, p: DVec3) -> f64 {
        let sheet = &self.sheets[self.sheet_at(p)];
        let others = sheet.others.iter().map(|term| (term, None));
        self.distance_over(p, sheet, None, others, f64::INFINITY)
    }

    /// Eq. 22 restricted to a part of the quadric inside `bounds` (a box around a basic region's
    /// patch, on one sheet): only the other terms whose box comes within `margin` of it are kept.
    pub fn near(&self, bounds: &Aabb, margin: f64) -> NearDistance<'_> {
        // The sheet every corner of the box is nearest to; none when they differ (an unbounded
        // box), and then each point finds its own among all the terms.
        let corners = bounds.corners();
        let sheet = self.sheet_at(corners[0]);
        let Some(sheet) = corners
            .iter()
            .all(|c| self.sheet_at(*c) == sheet)
            .then_some(sheet)
        else {
            return NearDistance {
                base: self,
                sheet: None,
                own: None,
                terms: Vec::new(),
                lists: Vec::new(),
                far: f64::INFINITY,
            };
        };
        self.near_on(sheet, bounds, margin, None)
    }

    /// [`Self::near`] on `sheet`, from what `from` kept (all terms and literals when `None`).
    pub(super) fn near_on<'a>(
        &'a self,
        sheet: usize,
        bounds: &Aabb,
        margin: f64,
        from: Option<&NearDistance<'a>>,
    ) -> NearDistance<'a> {
        let views = &self.sheets[sheet];
        let (mut terms, mut lists) = (Vec::new(), Vec::new());
        let mut far = f64::INFINITY;
        // Every term's gap anew, for the exact `far`; a term `from` left out stays out (its
        // gap only grows), and its literals come from `from`'s lists.
        let mut kept_there = from.map(|from| {
            let lists = (0..from.terms.len()).map(|k| from.list(k));
            from.terms.iter().copied().zip(lists).peekable()
        });
        for (i, term) in views.others.iter().enumerate() {
            let i = i as u32;
            let within = match &mut kept_there {
                None => Some(None),
                Some(kept) => kept.next_if(|(k, _)| *k == i).map(|(_, list)| list),
            };
            let gap = bounds.gap(&term.extent);
            match within {
                Some(within) if gap < margin => {
                    terms.push(i);
                    let list = term.near_literals(&views.quadrics, bounds, margin, within);
                    if list.is_some() || !lists.is_empty() {
                        lists.resize(terms.len() - 1, None);
                        lists.push(list);
                    }
                }
                _ => far = far.min(gap),
            }
        }
        let own_within = from.and_then(|from| from.own.as_ref());
        NearDistance {
            base: self,
            sheet: Some(sheet),
            own: (views.own).near_literals(&views.quadrics, bounds, margin, own_within),
            terms,
            lists,
            far,
        }
    }

    /// The bytes its views hold on the heap: the sheets' distinct quadrics, term views and
    /// literals. A run holds every sampled literal's until it ends, and a scene of many
    /// overlapping terms needs as many views per literal as there are terms near it.
    pub fn held_bytes(&self) -> usize {
        let literals = |v: &TermView| v.literals.capacity() * size_of::<Literal>();
        (self.sheets.iter())
            .map(|s| {
                size_of::<SheetViews>()
                    + s.quadrics.capacity() * size_of::<Quadric>()
                    + literals(&s.own)
                    + s.others.capacity() * size_of::<TermView>()
                    + s.others.iter().map(literals).sum::<usize>()
            })
            .sum()
    }

    /// How many other terms (and abutting unions) eq. 22 looks at, on the sheet that looks at
    /// the most: the terms near term `a`'s box ("Far terms").
    pub fn other_terms(&self) -> usize {
        self.sheets
            .iter()
            .map(|s| s.others.len())
            .max()
            .unwrap_or(0)
    }

    /// Eq. 22 on `sheet` over its other terms `others`; the terms left out are at least `far`
    /// from `p`.
    pub(super) fn distance_over<'a>(
        &'a self,
        p: DVec3,
        sheet: &SheetViews,
        own_near: Option<&NearLiterals>,
        others: impl Iterator<Item = (&'a TermView, Option<&'a NearLiterals>)>,
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
        if sheet.own_empty {
            return f64::INFINITY;
        }
        // What was left out stays `far` away from the sampled part, so less from a point `off`
        // outside it; a point that far out is that far from the surface ("Far terms").
        let off = if self.far.is_finite() {
            box_distance(&self.extent, p)
        } else {
            f64::NEG_INFINITY
        };
        if off >= self.far {
            return off;
        }
        let slack = off.max(0.0);
        let mut values = LiteralValues::new(&sheet.region, &sheet.quadrics, p);
        let at = |own| (p, plane.as_ref(), own);
        let own = (sheet.own).distance(at(true), own_near, (slack, f64::INFINITY), &mut values);
        let mut nearest_other = far.min(self.far - slack);
        for (term, near) in others {
            let distance = term.distance(at(false), near, (slack, nearest_other), &mut values);
            nearest_other = nearest_other.min(distance);
        }
        let d = own.max(-nearest_other);
        if off > 0.0 { d.max(off) } else { d }
    }
}

/// What one literal's tests against a patch's grown box found ([`CsgDistance::with_shapes`]):
/// whether it holds on all of the sampled surface there (`Some(true)`) or on none of it
/// (`Some(false)`), and whether it holds on all of the box (found when a term of many literals
/// first asks).
#[derive(Clone, Copy)]
struct LiteralTests {
    on_surface: Option<bool>,
    inside: Option<bool>,
}
