//! Planes touching curved surfaces without crossing them ("Tangent planes" in [`super`]): the
//! exact extent of an ellipsoid or elliptic cylinder along a plane's normal ([`Ellipsoidal`]),
//! found once per quadric of the DNF ([`Shapes`]), and which literals touch the sampled surface
//! inside its term's box ([`Tangency`]).

use super::abutting::{MADE_LITERAL, MAX_MERGED_PER_TERM, TermLiterals, abutting_unions};
use super::half_spaces::{HalfSpace, PlanarParts, planar_parts};
use super::sheet_views::SeenFromSheet;
use super::view::{PARALLEL, Shared};
use qcsg_csg::{Aabb, BoxIndex, Dnf};
use qcsg_quadric::{DVec3, PrincipalFrame, Quadric, QuadricKind, Tolerances};
use rustc_hash::FxHashMap;
use std::sync::{Mutex, PoisonError};

/// How a literal meets the sampled surface inside its term's box, when one of the two is
/// planar and the other a bounded ellipse in cross-section (see "Tangent planes").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Contact {
    /// The literal holds on all of it (up to rounding): its surface may touch it, never cross.
    Holds,
    /// The literal holds nowhere on it but where the two touch.
    Excludes,
    /// Anything else, or not known.
    Crosses,
}

impl Contact {
    /// The contact of the outside of a slab whose inside meets the surface as `self`, when
    /// `outside` (else `self`).
    pub(super) fn of_outside(self, outside: bool) -> Self {
        match (self, outside) {
            (Contact::Holds, true) => Contact::Excludes,
            (Contact::Excludes, true) => Contact::Holds,
            (contact, _) => contact,
        }
    }
}

/// Rounding slack of [`Tangency`], relative to the scene's diagonal: far below any radius (a
/// surface that bulges this far past a plane does so over a sliver about `2 sqrt(2 R · slack)`
/// wide), far above the rounding of an exact tangency built from transformed primitives.
pub(super) const TANGENT_SLACK: f64 = 1e-12;

/// A quadric `Σ λ_k u_k² + κ = 0` in its frame whose non-zero `λ_k` share a sign opposite to
/// `κ`'s: an ellipsoid or an elliptic cylinder (or their complements).
#[derive(Clone)]
pub(super) struct Ellipsoidal {
    pub(super) frame: PrincipalFrame,
    /// Whether its solid is the inside (`λ_k > 0`), not the outside.
    pub(super) inside: bool,
}

impl Ellipsoidal {
    /// The ellipsoidal form of a quadric that is not planar, from its frame.
    pub(super) fn from_frame(frame: PrincipalFrame) -> Option<Self> {
        let nonzero = || frame.eigenvalues.iter().filter(|&&l| l != 0.0);
        let inside = nonzero().all(|&l| l > 0.0) && frame.constant < 0.0;
        let outside = nonzero().all(|&l| l < 0.0) && frame.constant > 0.0;
        (frame.linear == [0.0; 3] && nonzero().count() > 0 && (inside || outside))
            .then_some(Self { frame, inside })
    }

    /// The range of `n · x` over the points `x` of its inside (the surface spans the same)
    /// within `bounds`, and how far either end may be off by rounding. Along the axes with
    /// `λ_k ≠ 0` the inside spans `±sqrt(−κ Σ n_k² / λ_k)` around the centre. `None` unless
    /// `n` is perpendicular to the null axes (a cylinder's), up to a tilt that moves `n · x` by
    /// at most the slack over the box: where the box cuts a cylinder, its faces would bound the
    /// span, and a plane through such a face meets the inside over an area, not a line.
    pub(super) fn span(&self, n: DVec3, bounds: &Aabb, slack: f64) -> Option<(f64, f64, f64)> {
        let frame = &self.frame;
        let mut ellipse = 0.0;
        let mut along_axes = 0.0;
        for (axis, lambda) in frame.axes.iter().zip(frame.eigenvalues) {
            let n_k = n.dot(*axis);
            if lambda != 0.0 {
                ellipse += n_k * n_k / lambda;
            } else if n_k != 0.0 {
                let reach = bounds
                    .corners()
                    .iter()
                    .map(|c| (*c - frame.centre).dot(*axis).abs())
                    .fold(0.0, f64::max);
                along_axes += n_k.abs() * reach;
            }
        }
        if along_axes > slack || along_axes.is_nan() {
            return None;
        }
        let half_width = (-frame.constant * ellipse).sqrt() + along_axes;
        let centre = n.dot(frame.centre);
        let rounding = 64.0 * f64::EPSILON * (centre.abs() + half_width) + slack;
        (half_width.is_finite() && rounding.is_finite()).then_some((
            centre - half_width,
            centre + half_width,
            rounding,
        ))
    }
}

/// What the tangency rules need of a quadric (see "Tangent planes"), found once per quadric of
/// a DNF.
#[derive(Clone)]
pub(super) struct Shape {
    /// Its principal axes ([`PrincipalFrame::axes`]).
    pub(super) axes: [DVec3; 3],
    /// Points of its surface: its centre moved along each principal axis to the surface, both
    /// ways, where that meets it (an ellipsoid's six tips, a cylinder's four).
    pub(super) tips: Vec<DVec3>,
    pub(super) is_planar: bool,
    /// Its half-spaces, when planar ([`planar_parts`]).
    pub(super) planar: Option<PlanarParts>,
    pub(super) ellipsoidal: Option<Ellipsoidal>,
}

impl Shape {
    pub(super) fn of(q: &Quadric) -> Self {
        let frame = q.frame();
        let is_planar = matches!(
            qcsg_quadric::classify_frame(&frame, &Tolerances::default()),
            QuadricKind::Plane | QuadricKind::ParallelPlanes
        );
        let tips = (0..3)
            .filter(|&k| frame.linear[k] == 0.0 && frame.eigenvalues[k] != 0.0)
            .filter_map(|k| {
                let reach = (-frame.constant / frame.eigenvalues[k]).sqrt();
                (reach > 0.0 && reach.is_finite()).then(|| reach * frame.axes[k])
            })
            .flat_map(|half| [frame.centre + half, frame.centre - half])
            .collect();
        Self {
            axes: frame.axes,
            tips,
            is_planar,
            planar: is_planar.then(|| planar_parts(q)).flatten(),
            ellipsoidal: (!is_planar)
                .then(|| Ellipsoidal::from_frame(frame))
                .flatten(),
        }
    }
}

/// Most entries [`Shapes::seen_from_sheet`] keeps. They save a scene of a few hundred terms
/// (a difference of unions distributed) a tenth of its sampling, while a scene of thousands
/// of small terms (a line of text) would keep a million, most never asked for again, and
/// spend more on their memory than they save.
const MAX_SEEN_FROM_SHEETS: usize = 1 << 16;

/// What every distance of a DNF shares, found once ([`CsgDistance::with_shapes`](crate::csg_distance::CsgDistance::with_shapes)): the
/// [`Shape`] of each quadric, each term's literals, and the abutting unions of its terms
/// ("Abutting terms"), each with the indices of its two terms.
pub(crate) struct Shapes {
    /// The DNF's diagonal, and the length below which a point is on a plane: `1e-9` of it
    /// (`0` for an unbounded DNF).
    pub(super) diagonal: f64,
    pub(super) tolerance: f64,
    pub(super) shapes: Vec<Shape>,
    pub(super) terms: Vec<TermLiterals>,
    /// The terms' boxes, as the DNF has them.
    pub(super) boxes: BoxIndex,
    pub(super) merged: Vec<(TermLiterals, (usize, usize))>,
    /// The shapes of the literals made for `merged` (half-spaces of slabs), which are numbered
    /// after the DNF's quadrics, each once, in this order ([`Self::made_shape`]).
    pub(super) made: Vec<Shape>,
    /// For each term, the indices in `merged` of its unions.
    pub(super) merged_with: Vec<Vec<u32>>,
    /// Whether each quadric is a literal of more than one term.
    pub(super) shared: Vec<bool>,
    /// What the sheets of shared quadrics see of other literals ([`Shapes::seen_from_sheet`]), by
    /// sampled quadric, sheet and literal.
    pub(super) seen_from_sheets: Mutex<FxHashMap<(u32, u32, u32), SeenFromSheet>>,
}

impl Shapes {
    /// The shapes of `dnf`'s quadrics and the unions of its terms.
    pub(crate) fn new(dnf: &Dnf) -> Self {
        let diagonal = (dnf.bounds.max - dnf.bounds.min).length();
        let tolerance = if diagonal.is_finite() {
            1e-9 * diagonal
        } else {
            0.0
        };
        let terms: Vec<TermLiterals> = dnf
            .terms
            .iter()
            .map(|t| {
                t.literals
                    .iter()
                    .filter_map(|&i| Some((i, dnf.quadrics.get(i as usize)?.quadric)))
                    .collect()
            })
            .collect();
        let boxes = BoxIndex::new(dnf.terms.iter().map(|t| t.bounds).collect());
        // Each distance keeps at most `MAX_MERGED_PER_TERM` unions per other term, in this order.
        let limit = MAX_MERGED_PER_TERM * terms.len().max(1);
        let mut merged = abutting_unions(&terms, &boxes, tolerance, limit);
        let mut made = Vec::new();
        for (literals, _) in &mut merged {
            for (index, quadric) in literals.iter_mut().filter(|l| l.0 == MADE_LITERAL) {
                *index = (dnf.quadrics.len() + made.len()) as u32;
                made.push(Shape::of(quadric));
            }
        }
        let mut merged_with = vec![Vec::new(); terms.len()];
        for (m, (_, (i, k))) in merged.iter().enumerate() {
            merged_with[*i].push(m as u32);
            merged_with[*k].push(m as u32);
        }
        let mut terms_of = vec![0u32; dnf.quadrics.len()];
        for literals in &terms {
            for &(i, _) in literals {
                terms_of[i as usize] += 1;
            }
        }
        Self {
            diagonal,
            tolerance,
            shapes: dnf.quadrics.iter().map(|d| Shape::of(&d.quadric)).collect(),
            terms,
            boxes,
            merged,
            made,
            merged_with,
            shared: terms_of.into_iter().map(|count| count > 1).collect(),
            seen_from_sheets: Mutex::default(),
        }
    }

    /// The shape of a quadric of the DNF (checked by the caller).
    pub(super) fn of(&self, quadric: u32) -> &Shape {
        &self.shapes[quadric as usize]
    }

    /// How many literals there are: the DNF's quadrics and those made for merged terms. Every
    /// literal's index is below this.
    pub(super) fn literal_count(&self) -> usize {
        self.shapes.len() + self.made.len()
    }

    /// The shape of literal `index`, made for a merged term; `None` for a quadric of the DNF.
    pub(super) fn made_shape(&self, index: u32) -> Option<&Shape> {
        self.made
            .get((index as usize).checked_sub(self.shapes.len())?)
    }

    /// What sheet `sheet` of `quadric` sees of `literal`: whether it is the sampled quadric or
    /// its complement (`identity`), and its section by the sheet (`section`) when `wanted`.
    /// A quadric that several terms hold (a DNF expanded from unions and differences repeats
    /// its literals in many terms) is sampled once per term, and each time its sheets would
    /// find the same sections (eigen decompositions of each literal): for such quadrics they
    /// are kept, and a view that wants a section where an earlier one did not makes it then.
    /// At most [`MAX_SEEN_FROM_SHEETS`] are kept: past that, the rest are found each time.
    pub(super) fn seen_from_sheet(
        &self,
        (quadric, sheet, literal): (u32, u32, u32),
        identity: impl Fn() -> (bool, bool),
        wanted: impl Fn(bool, bool) -> bool,
        section: impl Fn() -> Option<(Quadric, Option<PlanarParts>)>,
    ) -> SeenFromSheet {
        let complete = |known: Option<SeenFromSheet>| {
            let mut seen = known.unwrap_or_else(|| {
                let (same, complement) = identity();
                SeenFromSheet {
                    same,
                    complement,
                    section: None,
                }
            });
            let fill = seen.section.is_none() && wanted(seen.same, seen.complement);
            if fill {
                seen.section = Some(section());
            }
            (seen, fill)
        };
        if !self.shared.get(quadric as usize).copied().unwrap_or(false) {
            return complete(None).0;
        }
        let key = (quadric, sheet, literal);
        let lock = || {
            self.seen_from_sheets
                .lock()
                .unwrap_or_else(PoisonError::into_inner)
        };
        let known = lock().get(&key).cloned();
        let new = known.is_none();
        let (seen, filled) = complete(known);
        if new || filled {
            let mut kept = lock();
            if !new || kept.len() < MAX_SEEN_FROM_SHEETS {
                kept.insert(key, seen.clone());
            }
        }
        seen
    }
}

/// The sampled quadric as [`Contact`] sees it.
pub(super) enum Sampled {
    /// Curved, with bounded cross-sections: planar literals may touch it.
    Ellipsoidal(Ellipsoidal),
    /// One sheet of a planar quadric, as the half-space it bounds; ellipsoidal literals may
    /// touch it.
    Planar(HalfSpace),
    Other,
}

/// Which literals touch the sampled surface without crossing it, inside its term's box.
pub(super) struct Tangency {
    pub(super) sampled: Sampled,
    pub(super) bounds: Aabb,
    /// [`TANGENT_SLACK`] times the scene's diagonal.
    pub(super) slack: f64,
    /// The length below which planes count as one ("Shared planes").
    pub(super) shared: f64,
    /// The largest coordinate of the bounds' corners, for [`Tangency::parallel`].
    pub(super) reach: f64,
}

impl Tangency {
    /// Contacts with quadric `quadric` of the DNF, or with its sheet `plane` when it is planar.
    pub(super) fn new(
        shapes: &Shapes,
        quadric: u32,
        plane: Option<HalfSpace>,
        bounds: &Aabb,
    ) -> Self {
        let diagonal = shapes.diagonal;
        let sampled = match (plane, &shapes.of(quadric).ellipsoidal) {
            (Some(plane), _) => Sampled::Planar(plane),
            (None, Some(curved)) => Sampled::Ellipsoidal(curved.clone()),
            (None, None) => Sampled::Other,
        };
        Self {
            sampled,
            bounds: *bounds,
            slack: if diagonal.is_finite() {
                TANGENT_SLACK * diagonal
            } else {
                0.0
            },
            shared: shapes.tolerance,
            reach: bounds
                .corners()
                .iter()
                .map(|c| c.abs().max_element())
                .fold(0.0, f64::max),
        }
    }

    /// [`Self::of`] for a literal whose relation to the sampled sheet the compiler's surfaces
    /// decided (`on_sheet`, [`super::identity::SheetIdentity::on_sheet`]): a literal on the sheet crosses it (the
    /// shared-plane rule takes it), and a planar one parallel to the sheet but not on it holds
    /// on all of it or on none, however near (a wall `1e-9` thick), up to rounding alone.
    pub(super) fn of_identified(&self, literal: &Shape, on_sheet: Option<Shared>) -> Contact {
        match (&self.sampled, on_sheet, &literal.planar) {
            (Sampled::Planar(_), Some(Shared::SameSide | Shared::OtherSide), _) => Contact::Crosses,
            (Sampled::Planar(sheet), Some(Shared::No), Some((spaces, complement))) => {
                self.parallel(sheet, spaces, *complement, 0.0)
            }
            _ => self.of(literal),
        }
    }

    /// How `literal` meets the sampled surface.
    pub(super) fn of(&self, literal: &Shape) -> Contact {
        match &self.sampled {
            // Each half-space of the literal holds on all of the surface, or one on none of it
            // (the other way round for the outside of a slab).
            Sampled::Ellipsoidal(surface) => {
                let Some((spaces, complement)) = &literal.planar else {
                    return Contact::Crosses;
                };
                let mut contact = Contact::Holds;
                for h in spaces {
                    let Some((low, high, rounding)) =
                        surface.span(h.normal, &self.bounds, self.slack)
                    else {
                        return Contact::Crosses;
                    };
                    if low >= h.offset - rounding {
                        contact = Contact::Excludes;
                        break;
                    }
                    if high > h.offset + rounding {
                        contact = Contact::Crosses;
                    }
                }
                contact.of_outside(*complement)
            }
            // No sheet of the surface meets the literal's inside: the surface lies in its
            // closed outside, which is its solid when it is a complement.
            Sampled::Planar(sheet) => {
                if let Some((spaces, complement)) = &literal.planar {
                    return self.parallel(sheet, spaces, *complement, self.shared);
                }
                let Some(solid) = &literal.ellipsoidal else {
                    return Contact::Crosses;
                };
                let Some((low, high, rounding)) =
                    solid.span(sheet.normal, &self.bounds, self.slack)
                else {
                    return Contact::Crosses;
                };
                if sheet.offset > low + rounding && sheet.offset < high - rounding {
                    return Contact::Crosses;
                }
                if solid.inside {
                    Contact::Excludes
                } else {
                    Contact::Holds
                }
            }
            Sampled::Other => Contact::Crosses,
        }
    }

    /// A planar literal (its half-spaces `spaces`, the outside of their slab if `complement`)
    /// seen from the sheet `sheet`: a half-space parallel to the sheet holds on all of it or on
    /// none of it (a countersink's top `0.01` above a face). Planes within `shared` of the sheet
    /// (the tolerance of "Shared planes" where the surfaces did not decide) are that rule's, and
    /// a half-space across the sheet crosses it.
    pub(super) fn parallel(
        &self,
        sheet: &HalfSpace,
        spaces: &[HalfSpace],
        complement: bool,
        shared: f64,
    ) -> Contact {
        let reach = self.reach;
        let mut contact = Contact::Holds;
        for h in spaces {
            let side = h.normal.dot(sheet.normal).signum();
            let tilt = (h.normal - side * sheet.normal).length();
            // On the sheet `n·x = c`: `h.normal·x − h.offset = side c − h.offset` up to the tilt.
            let value = side * sheet.offset - h.offset;
            let margin = shared
                + 3.0 * tilt * reach
                + 64.0 * f64::EPSILON * (sheet.offset.abs() + h.offset.abs() + reach);
            if !(margin.is_finite() && tilt <= PARALLEL) || value.abs() <= margin {
                return Contact::Crosses;
            }
            if value > 0.0 {
                contact = Contact::Excludes;
            }
        }
        contact.of_outside(complement)
    }
}
