//! The quadric-relative conservative CSG distance `d_Q(S, p)` of paper eq. 22.
//!
//! For a point `p` on quadric `Q_ab` (literal `b` of term `a`):
//! `d = max(−min_{i≠a} max_j d(Q_ij, p), max_{j≠b} d(Q_aj, p))`, with `d(Q, p)` the conservative
//! distance of eqs. 10-12. Negative: `p` is on the CSG surface, and so is every point of `Q_ab`
//! within `|d|`; positive: neither `p` nor any point of `Q_ab` within `d` is. For a planar
//! `Q_ab` (a slab has two planes) "points of `Q_ab`" are those of the plane through `p` (see
//! "Planar sections").
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
//!   the curve is classified. Planes count as shared within the tolerance of "Shared planes",
//!   only terms whose boxes touch are paired, and at most four merged terms per other term are
//!   made (`MAX_MERGED_PER_TERM`).
//! - **Tangent planes.** Where a plane touches a curved surface without crossing it (a
//!   rounded rectangle's corner cylinder against the walls of its two boxes, a ball resting on
//!   a slab's face), the literal's distance vanishes quadratically towards the line or point of
//!   contact, and eq. 22 touches 0 there without a sign change. So, between a planar literal
//!   and a sampled ellipsoid or elliptic cylinder (and the other way round: an ellipsoidal
//!   literal and a sampled plane), the surface's extent along the plane's normal is computed
//!   exactly (`Ellipsoidal`; a cylinder only across its axis). A literal that holds on all of
//!   the sampled surface up to touching it is left out of every term (it changes no term's
//!   interior but on the contact, which is a curve or point of the surface, covered by the
//!   other quadric's samples); a literal that holds on none of it but the contact empties its
//!   term there: term `a` samples nothing, another term is left out (after its abutting unions
//!   are made: a merged term may still reach the surface). Rounding in transformed primitives
//!   is absorbed within `1e-12` of the diagonal (`TANGENT_SLACK`). Likewise a planar literal
//!   parallel to a sampled plane, but farther from it than the tolerance of "Shared planes",
//!   holds on all of the plane or on none of it (a countersink's top `0.01` above a face).
//! - **Planar sections.** Each sheet (plane) of a planar quadric gets its own view of the
//!   terms. A literal that crosses the sheet is replaced by its section by the sheet, extruded
//!   along the sheet's normal: a cylinder cut along its axis becomes the slab between its two
//!   lines, another plane its line, a cone or a ball its circle. On the sheet the section equals
//!   the literal, and its distance is the distance within the sheet, which bounds the distance
//!   along the sheet from below; so eq. 22's two properties hold for the points of the sheet,
//!   which is all a basic region holds. "Literals of both terms" then sees literals that two
//!   terms share on the sheet only: two cones (or a cylinder and a cone) whose rims meet with
//!   equal radii on the plane between their parts have one circle there (a pulley's groove, a
//!   chess piece's foot), and a face between two boxes ends where a cylinder's slab begins. It
//!   also tells nearly parallel planes apart at their distance within the sheet rather than in
//!   space (planes at 3e-4 rad). For planar sections the rule holds half-space by half-space:
//!   a slab of another term that shares one side with term `a` keeps only its other side.
//!   Planes within `1e-6` rad of the sheet keep their distance in space ("Shared planes"
//!   handles them).
//! - **Far terms.** Eq. 22 of a sampled literal is set up for the part of its quadric that
//!   its basic regions hold (a box around their patches, within term `a`'s box, grown by the
//!   length tolerance; `D` its diagonal). It keeps only the other terms whose box comes within
//!   `D` of that box; an R-tree of the terms' boxes finds them. Inside the box a term left out
//!   is more than `D` away, so, as in [`CsgDistance::near`], it enters as that constant: a
//!   negative result is at most `D` deep (enough to classify any rectangle of the box), and
//!   its ball stays clear of every term left out. At a point `e` outside the box the constant
//!   is `D − e`, and the result is at least `e`: no point of the box is nearer. Scenes of many
//!   separate parts then cost time and memory in proportion to the parts, not to their square
//!   (a grid of 4,096 parts took 16 GB and 3.6 minutes before).
//! - **Far literals.** Of a term with more than 32 literals (a plate drilled with many holes),
//!   those that hold on all of the box grown by `D` (`quadric_box::classify`) are left out too,
//!   and the term's distance is kept at least `−(D − e)` for the same reason. Per basic region
//!   ([`CsgDistance::near`], [`NearDistance::narrow`]) the same is done with the region's box
//!   and margin, and "Literals of both terms" still sees term `a`'s literals left out. A plate
//!   with 1,024 holes sampled in 45 s before, each query looking at all its literals.
//! - **Offset surfaces.** On the sampled quadric `q = 0`, so a literal `L` equals `L − λ q` there
//!   for any `λ`. Where `L`'s square part is `λ` times `q`'s (nested balls, coaxial cylinders:
//!   OpenSCAD models overlap parts by a small epsilon, a bore `0.01` wider than its pin, a
//!   cutter `1e-3` inside a ball), `L − λ q` is a plane or a constant, which interval
//!   arithmetic bounds over the box grown by `D` ("Far terms"): `L` holds on all of the sampled
//!   surface there or on none of it. A literal that holds is left out of its term, which keeps
//!   the floor `−(D − e)` of "Far literals"; another term with a literal that holds nowhere is
//!   left out like a far term. Near such a gap eq. 22 was the gap itself: a column `0.01`
//!   inside the steps around it could not be proven hidden above the cutoff of its rectangles
//!   (`spiral_staircase` at 1 % gave up 583 rectangles in 521,471 queries; now none in 88,778),
//!   and nested balls `1e-9` apart gave up 11.7 million.
//! - **Touching surfaces.** Where no `λ` cancels `L`'s square part, one may still leave a
//!   semidefinite remainder: a ball and a cylinder of its radius give `L − q = −z²` on the ball,
//!   so the cylinder holds on all of the ball but its equator, where the two touch (the rounded
//!   end of a capsule, a cup made of a cylinder and a ball). Where the square parts share their
//!   principal axes (coaxial cylinders, cones and ellipsoids, a ball with anything), the only
//!   candidates are the ratios of their diagonals in those axes, and the remainder is bounded in
//!   them. Where it reaches zero only within the margin the literal holds (or fails) on all the
//!   surface but a curve or a point, which is no area: it is left out as above, and a literal of
//!   term `a` that fails leaves the quadric no part in its term (no distance, nothing sampled).
//!   On an ellipsoid the remainder's plane part is also bounded over the surface itself: a ball
//!   touching the inside of another at a point lies inside it everywhere else. Where an
//!   ellipsoid shares no axes with the literal, the S-lemma decides instead: the literal holds
//!   (fails) on all of it exactly when some `L − λ q` is at most (at least) zero everywhere,
//!   and a golden-section search over `λ` finds the best. Eq. 22 by the
//!   cylinder's side alone was `z² / 2r` at a height `z` above the rim: `precision_part` at 1 %
//!   gave up 414 rectangles in 1,623,947 queries; now none in 106,887.
//! - **One side of a slab.** The outside of a slab is a union of two half-spaces, which no rule
//!   above can pair. Where a term's box lies on the inner side of one of the slab's planes (up
//!   to the length tolerance: a box flush with the plane lies on it), the literal is the
//!   half-space beyond the other plane within the term, and stands as that. A cut flush with
//!   three faces of a box (`crates/qcsg-splat/tests/scenes/coincident_faces.qcsg`) gave up
//!   24,584 rectangles at 1 % while the box had to lie strictly inside; a cube minus itself
//!   visited 1.6 million rectangles at 30 %.
//! - **Strips of no width.** On a sampled plane, two half-spaces of term `a` whose sections face
//!   each other across a strip no wider than the length tolerance within the term's box leave
//!   the term no area there: it samples nothing on that sheet. Cutting a box with another box
//!   turned by 45°, as OpenSCAD models make a triangular gusset, gives a DNF term for each of the
//!   cutter's faces; where the two faces meet on the gusset's bottom plane, the term of the face
//!   that misses the gusset is that line. Eq. 22 there was the distance to the line, and
//!   `openscad_bracket` at 1 % gave up 1,024 rectangles along it; now none. The same test tells
//!   which side of a slab a term holds where its box spans both planes (a turned part, see
//!   "One side of a slab"): the side that leaves no area is dropped
//!   (`tests/stability/tangent_rounded_tray_tilted.qcsg` at 1 % gave up 17,359 rectangles).

use either::Either;
use qcsg_csg::quadric_box::{self, BoxClass};
use qcsg_csg::{Aabb, BoxIndex, Dnf};
use qcsg_quadric::{DVec3, PrincipalFrame, Quadric, QuadricKind, Tolerances};
use rustc_hash::FxHashMap;
use std::sync::{Mutex, PoisonError};

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
    /// The least distance: `−reach` where literals that hold within `reach` of the sampled part
    /// were left out ("Far literals"), else `−∞`.
    floor: f64,
}

/// Terms with more literals than this leave out, near a box, those that hold all around it
/// ("Far literals").
const FEW_LITERALS: usize = 32;

/// The terms eq. 22 of one sampled literal looks at, as the DNF has them: term `a`'s literals,
/// then every other term's literals and box; each list with its floor, `−reach` where literals
/// far from the sampled part were left out ("Far literals"), else `−∞`.
struct NearTerms {
    own: (TermLiterals, f64),
    /// The indices of term `a`'s literals left out, ascending: "Literals of both terms" still
    /// applies to them.
    own_far: Vec<u32>,
    others: Vec<((TermLiterals, f64), Aabb)>,
}

/// The literals of a term a [`NearDistance`] looks at (indices into [`TermView::literals`]);
/// the others hold on all of its box and `margin` around it.
#[derive(Clone, Debug)]
struct NearLiterals {
    indices: Vec<u32>,
    margin: f64,
}

impl TermView {
    /// The view of `literals`, each with whether it is planar and whether term `a` holds it
    /// too.
    fn new(
        literals: impl IntoIterator<Item = (Quadric, bool, bool)>,
        bounds: Aabb,
        (extent, floor): (Aabb, f64),
    ) -> Self {
        let literals: Vec<Literal> = literals
            .into_iter()
            .map(|(quadric, planar, in_own_term)| Literal {
                planar,
                in_own_term,
                quadric,
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
    fn near_literals(
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
    fn looked_at<'a>(
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
    fn distance(
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
    fn max_over<'a>(
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
    /// The terms as seen from each sheet of the sampled quadric: one per plane of a planar
    /// quadric (see "Planar sections"), else one for the whole quadric.
    sheets: Vec<SheetViews>,
    /// The sampled quadric, when it is planar (see "Shared planes" in the module docs).
    planar: Option<Quadric>,
    /// Length below which a point is on a plane: `1e-9` of the DNF's diagonal.
    tolerance: f64,
    /// The box the sampled part lies in, and the depth within which the terms and literals
    /// left out as far do not reach into it (see "Far terms"); `+∞` when none is.
    extent: Aabb,
    far: f64,
}

/// The terms as seen from one sheet of the sampled quadric.
#[derive(Clone, Debug)]
struct SheetViews {
    /// The sheet's plane (`normal · x = offset`), for a planar quadric.
    plane: Option<HalfSpace>,
    own: TermView,
    /// A literal of term `a` holds on the sheet only where it touches it (see "Tangent
    /// planes"): no point of the sheet is on the surface through term `a`.
    own_empty: bool,
    others: Vec<TermView>,
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
    pub(crate) fn with_shapes(
        dnf: &Dnf,
        shapes: &Shapes,
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
        let same = |i: u32, o: &Quadric| i == quadric || q.approx_eq_up_to_scale(o, SAME_QUADRIC);
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
        let limit = MAX_MERGED_PER_TERM * kept.len().max(1);
        let merged = unions
            .into_iter()
            .map(|m| &shapes.merged[m as usize])
            .take(limit)
            .filter(|(l, _)| !l.iter().any(|(i, o)| same(*i, o)))
            .map(|(literals, (i, k))| {
                (
                    literals.clone(),
                    dnf.terms[*i].bounds.union(&dnf.terms[*k].bounds),
                )
            });
        // Of a term of many literals, those that hold all around the sampled part are left out
        // ("Far literals"); the sampled quadric stays.
        let grown = extent.expanded(reach);
        // So are the literals that hold on all of the sampled surface in that box, and the other
        // terms with a literal that holds on none of it ("Offset surfaces").
        let bounded = !grown.is_empty() && grown.is_bounded();
        let near_literals = |literals: &[(u32, Quadric)]| {
            let many = literals.len() > FEW_LITERALS && bounded;
            let mut kept = TermLiterals::with_capacity(literals.len());
            for &(i, o) in literals {
                if i != quadric {
                    if many && quadric_box::classify(&o, &grown) == BoxClass::Inside {
                        continue;
                    }
                    // Made half-spaces have no entry, and are planes: no pencil needs them.
                    let axes = shapes.shapes.get(i as usize).map(|s| &s.axes);
                    let pair = ((&q, shape), (&o, axes));
                    match bounded
                        .then(|| on_surface(pair.0, pair.1, &grown))
                        .flatten()
                    {
                        Some(true) => continue,
                        Some(false) => return None,
                        None => {}
                    }
                }
                kept.push((i, o));
            }
            let floor = if kept.len() < literals.len() {
                -reach
            } else {
                f64::NEG_INFINITY
            };
            Some((kept, floor))
        };
        let own = near_literals(&shapes.terms[term as usize])?;
        // The kept literals are in the term's order: one walk finds the others.
        let mut kept_own = own.0.iter().peekable();
        let mut own_far: Vec<u32> = shapes.terms[term as usize]
            .iter()
            .filter(|(i, _)| kept_own.next_if(|(k, _)| k == i).is_none())
            .map(|(i, _)| *i)
            .collect();
        own_far.sort_unstable();
        let others: Vec<_> = kept
            .iter()
            .map(|&i| {
                (
                    shapes.terms[i as usize].clone(),
                    dnf.terms[i as usize].bounds,
                )
            })
            .chain(merged)
            .collect();
        let near_others = others.len();
        let terms = NearTerms {
            own,
            own_far,
            others: others
                .into_iter()
                .filter_map(|(literals, bounds)| Some((near_literals(&literals)?, bounds)))
                .collect(),
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
            terms.own.1.is_finite() || terms.others.iter().any(|((_, floor), _)| floor.is_finite());
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
    fn sheet_at(&self, p: DVec3) -> usize {
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
    fn near_on<'a>(
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
                    let list = term.near_literals(bounds, margin, within);
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
            own: views.own.near_literals(bounds, margin, own_within),
            terms,
            lists,
            far,
        }
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
    fn distance_over<'a>(
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
        let own = sheet.own.distance(p, plane.as_ref(), true, own_near, slack);
        let mut nearest_other = far.min(self.far - slack);
        for (term, near) in others {
            let distance = term.distance(p, plane.as_ref(), false, near, slack);
            nearest_other = nearest_other.min(distance);
        }
        let d = own.max(-nearest_other);
        if off > 0.0 { d.max(off) } else { d }
    }
}

impl SheetViews {
    /// The views of every term from `plane`, sheet `sheet` of the sampled quadric `quadric` of
    /// term `term` (the whole quadric when `None`).
    fn new(
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
                let contact = contact.of(shape);
                let SeenFromSheet {
                    same,
                    complement,
                    section,
                } = shapes.seen_from_sheet(
                    (quadric, sheet, i),
                    || (i == quadric || same_value(&o), complement_value(&o)),
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
                        Some(half) => Refined::one_side(index, half, seen.refined),
                        None => Refined {
                            index,
                            quadric: seen.refined,
                            planar: seen.planar,
                            parts: seen.parts.clone(),
                            same: seen.same,
                            complement: seen.complement,
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
                .map(|r| (r.quadric, r.planar, false)),
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
                            return vec![(r.quadric, r.planar, true)];
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
struct Seen {
    contact: Contact,
    /// The sampled quadric (by index or value).
    same: bool,
    /// Its complement.
    complement: bool,
    /// The literal, or its planar section by the sheet.
    refined: Quadric,
    planar: bool,
    /// The half-spaces of `refined`, when planar ([`planar_parts`]).
    parts: Option<PlanarParts>,
}

/// A literal of the DNF as a sheet of a sampled quadric sees it, whatever the term: whether it
/// is the sampled quadric or its complement, and its section by the sheet's plane (`None` until
/// a view has asked for it).
#[derive(Clone)]
struct SeenFromSheet {
    same: bool,
    complement: bool,
    section: Option<Option<(Quadric, Option<PlanarParts>)>>,
}

/// A literal of a term as the view holds it.
struct Refined {
    /// Its index in the DNF ([`MADE_LITERAL`] if made here).
    index: u32,
    quadric: Quadric,
    planar: bool,
    parts: Option<PlanarParts>,
    same: bool,
    complement: bool,
}

impl Refined {
    /// Literal `index`, the outside of a slab, as the one half-space `half` of it that the term
    /// holds ("One side of a slab"); `outside` stands if the half-space cannot be formed.
    fn one_side(index: u32, half: HalfSpace, outside: Quadric) -> Self {
        Self {
            index,
            quadric: Quadric::half_space(half.point, half.normal).unwrap_or(outside),
            planar: true,
            parts: Some((vec![half], false)),
            same: false,
            complement: false,
        }
    }
}

/// [`CsgDistance`] for the points of one box ([`CsgDistance::near`]). A term whose box is at
/// least `far` away from every point of the box contributes at most `−far` to the maximum (its
/// interior is at least that far), so it is replaced by that constant: classifications stay
/// valid, only radii beyond `far` are cut.
#[derive(Clone, Debug)]
pub struct NearDistance<'a> {
    base: &'a CsgDistance,
    /// The sheet of the box, when it has one.
    sheet: Option<usize>,
    /// The literals of term `a` near the box, for a term of many ("Far literals"); `None`: all.
    own: Option<NearLiterals>,
    /// The other terms near the box, and the literals of each near it (as `own`; empty when
    /// every term keeps all).
    terms: Vec<u32>,
    lists: Vec<Option<NearLiterals>>,
    far: f64,
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

    /// The literals of the `k`-th kept term near the box, where not all.
    fn list(&self, k: usize) -> Option<&NearLiterals> {
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
        any_fails(views.own.looked_at(self.own.as_ref()), &grown)
            || self.terms.iter().enumerate().any(|(k, &i)| {
                let view = &views.others[i as usize];
                // A term holding all of the box has a box holding it (`extent`), and its
                // distance is positive outside the DNF's region (`bounds`).
                (view.extent.contains_box(&grown) && view.bounds.contains_box(&grown))
                    && all_hold(view.looked_at(self.list(k)), &grown)
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
        let own = &views.own;
        (own.bounds.contains_box(&grown) && all_hold(own.looked_at(self.own.as_ref()), &grown))
            && self.terms.iter().enumerate().all(|(k, &i)| {
                let view = &views.others[i as usize];
                !view.extent.intersects(&grown) || any_fails(view.looked_at(self.list(k)), &grown)
            })
    }

    /// `patch` grown by more than the length tolerance of "Shared planes" and rounding, so that
    /// no literal `quadric_box::classify` decides over it is on the plane of a point of `patch`;
    /// `None` for an unbounded box.
    fn grown(&self, patch: &Aabb) -> Option<Aabb> {
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
/// instructions).
fn all_hold<'a>(literals: impl Iterator<Item = &'a Literal> + Clone, bounds: &Aabb) -> bool {
    let centre = bounds.centre();
    let mut looked_at = literals.filter(|literal| !literal.in_own_term);
    looked_at.clone().all(|l| l.quadric.value(centre) < 0.0)
        && looked_at.all(|l| quadric_box::classify(&l.quadric, bounds) == BoxClass::Inside)
}

/// Whether one of `literals` fails on all of `bounds` (it fails at the centre first).
fn any_fails<'a>(literals: impl Iterator<Item = &'a Literal>, bounds: &Aabb) -> bool {
    let centre = bounds.centre();
    (literals.filter(|l| l.quadric.value(centre) > 0.0))
        .any(|l| quadric_box::classify(&l.quadric, bounds) == BoxClass::Outside)
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

/// Whether `literal` holds on all of the surface of `q` inside `bounds` (`Some(true)`), on none of
/// it (`Some(false)`), or neither is known (`None`), for a `q` with a square part (not one
/// plane) ("Offset surfaces", "Touching surfaces"), with `q`'s shape and the literal's
/// principal axes where known. On the surface `q = 0`, so there the literal equals
/// `literal − λ q` for any `λ`. Tried are the `λ` that make the square part of that remainder
/// vanish (an offset: a plane or a constant is left) or semidefinite (surfaces that touch along
/// a curve, or nest without touching); the remainder is bounded over the box with a margin for
/// points that lie on `q` only up to rounding. Where the remainder reaches zero only within
/// that margin the surfaces touch: the literal holds (fails) on all the surface but a curve or
/// a point. A literal equal to `q` or to its complement leaves nothing and is `None` (other
/// rules handle those).
fn on_surface(
    (q, shape): (&Quadric, &Shape),
    (literal, literal_axes): (&Quadric, Option<&[DVec3; 3]>),
    bounds: &Aabb,
) -> Option<bool> {
    const WEIGHTS: [f64; 6] = [1.0, 1.0, 1.0, 2.0, 2.0, 2.0];
    let (a, b) = (q.coefficients(), literal.coefficients());
    let dot = |u: &[f64; 10], v: &[f64; 10]| (0..6).map(|k| WEIGHTS[k] * u[k] * v[k]).sum::<f64>();
    let square = dot(&a, &a);
    if square.is_nan() || square <= 0.0 {
        return None;
    }
    let lambda = dot(&a, &b) / square;
    let residual: [f64; 10] = std::array::from_fn(|k| b[k] - lambda * a[k]);
    let offset = dot(&residual, &residual) <= 1e-18 * dot(&b, &b);
    let sampled = (q, shape.ellipsoidal.as_ref());
    // `q` about the literal's origin, where the literal's coefficients are exact.
    let moved = q.with_origin(literal.origin()).coefficients();
    let literal_moved = (literal, &moved);
    if offset && let Some(holds) = remainder_sign(sampled, literal_moved, (lambda, None), bounds) {
        return Some(holds);
    }
    // The literal above and below zero at points of the surface (in the box, for the rules
    // that bound it over the box; anywhere, for the S-lemma's, which are global): neither can
    // hold throughout. Most pairs are parts that cross, and this spares them the search.
    let margin = remainder_margin(q, literal_moved, 0.0, bounds);
    let signs = |tips: &mut dyn Iterator<Item = &DVec3>| {
        tips.fold((false, false), |(above, below), &tip| {
            let value = literal.value(tip);
            (above || value > margin, below || value < -margin)
        })
    };
    if signs(&mut shape.tips.iter().filter(|&&tip| bounds.contains(tip))) == (true, true) {
        return None;
    }
    let Some((basis, ratios)) = pencil(q, literal, [Some(&shape.axes), literal_axes]) else {
        return match signs(&mut shape.tips.iter()) {
            (true, true) => None,
            (above, below) => s_lemma(q, literal_moved, bounds, (!above, !below)),
        };
    };
    let tried = |ratio: f64| offset && (ratio - lambda).abs() <= 1e-12 * lambda.abs();
    ratios
        .into_iter()
        .filter(|&ratio| !tried(ratio))
        .find_map(|lambda| remainder_sign(sampled, literal_moved, (lambda, Some(&basis)), bounds))
}

/// A basis of eigenvectors that `A` and `B`, the square parts of `q` and `literal`, share
/// (one of the two `axes`), with the `λ` for which `B − λ A` is semidefinite: it is diagonal in
/// that basis, with entries `vᵀBv − λ vᵀAv`, so `λ` is one of the ratios `vᵀBv / vᵀAv`.
/// Coaxial cylinders, cones and balls share one, and a ball shares one with anything; other
/// pairs are `None`.
fn pencil(
    q: &Quadric,
    literal: &Quadric,
    axes: [Option<&[DVec3; 3]>; 2],
) -> Option<([DVec3; 3], Vec<f64>)> {
    let (a, b) = (q.matrix_a(), literal.matrix_a());
    let form = quadratic_form;
    let (norm_a, norm_b) = (q.matrix_norm(), literal.matrix_norm());
    // Tight: parts turned by a transform share axes to rounding, while two ellipsoids `1e-9`
    // apart turned differently are off by about that much, and go to the S-lemma.
    let diagonalises = |basis: &[DVec3; 3]| {
        [(0, 1), (0, 2), (1, 2)].iter().all(|&(i, j)| {
            form(&a, basis[i], basis[j]).abs() <= 1e-12 * norm_a
                && form(&b, basis[i], basis[j]).abs() <= 1e-12 * norm_b
        })
    };
    let &basis = axes
        .into_iter()
        .flatten()
        .find(|basis| diagonalises(basis))?;
    let mut ratios: Vec<f64> = Vec::with_capacity(3);
    for v in basis {
        let across = form(&a, v, v);
        if across.abs() <= 1e-9 * norm_a {
            continue;
        }
        let ratio = form(&b, v, v) / across;
        let scale = ratio.abs().max(norm_b / norm_a);
        if ratio.is_finite() && ratios.iter().all(|r| (r - ratio).abs() > 1e-12 * scale) {
            ratios.push(ratio);
        }
    }
    Some((basis, ratios))
}

/// For an ellipsoid `q` and any `literal` without principal axes in common: whether some
/// `literal − λ q` is at most zero everywhere (the literal holds on all of `q`'s surface), or at
/// least zero everywhere (it fails there), up to the margin of [`remainder_sign`]. This is the
/// S-lemma: for such a pair one of these `λ` exists whenever the literal holds (fails) on the
/// whole surface. With `A` and `B` the square parts, `B − λ A` must be negative (positive)
/// definite, `λ` above (below) the largest (smallest) eigenvalue of `A^(−1/2) B A^(−1/2)`;
/// there the largest (smallest) value of the remainder is convex (concave) in `λ`, and a
/// golden-section search finds its best. An ellipsoid inside another turned differently,
/// touching it at its tips, is left out this way. `(may_hold, may_fail)`: which of the two the
/// literal's signs at the ellipsoid's tips leave open.
fn s_lemma(
    q: &Quadric,
    (literal, moved): (&Quadric, &[f64; 10]),
    bounds: &Aabb,
    (may_hold, may_fail): (bool, bool),
) -> Option<bool> {
    // The surface is that of `−q` too: take the sign that makes `A` positive definite.
    let (low, high) = q.eigenvalue_bounds();
    let (q, moved) = match (low > 0.0, high < 0.0) {
        (true, _) => (*q, *moved),
        (_, true) => (q.negated(), moved.map(|c| -c)),
        _ => return None,
    };
    // The extreme `λ` of the pencil, in `q`'s axes scaled to make `A` the identity.
    let frame = q.eigen();
    let b = literal.matrix_a();
    let whiten: [DVec3; 3] = std::array::from_fn(|k| frame.vectors[k] / frame.values[k].sqrt());
    let c: [[f64; 3]; 3] =
        std::array::from_fn(|i| std::array::from_fn(|j| quadratic_form(&b, whiten[i], whiten[j])));
    let [smallest, _, largest] = qcsg_quadric::symmetric_eigen(&c).values;
    if !(smallest.is_finite() && largest.is_finite()) {
        return None;
    }
    let lb = literal.coefficients();
    // The largest value of `literal − λ q` over all of space, for `λ` where its square part is
    // negative definite (`holds`), or the negated smallest, where it is positive definite.
    let extreme = |lambda: f64, holds: bool| -> f64 {
        let r: [f64; 10] = std::array::from_fn(|k| lb[k] - lambda * moved[k]);
        let flip = if holds { -1.0 } else { 1.0 };
        // `R = xᵀMx + 2gᵀx + c`; with `N = ∓M` definite, the extreme is `c ± gᵀN⁻¹g`.
        let [a0, a1, a2, a3, a4, a5, g0, g1, g2, constant] = r.map(|v| flip * v);
        // `N⁻¹ = adj(N) / det N` for the symmetric `N = [[a0 a3 a4] [a3 a1 a5] [a4 a5 a2]]`.
        let adjugate = [
            [a1 * a2 - a5 * a5, a4 * a5 - a3 * a2, a3 * a5 - a4 * a1],
            [a4 * a5 - a3 * a2, a0 * a2 - a4 * a4, a3 * a4 - a0 * a5],
            [a3 * a5 - a4 * a1, a3 * a4 - a0 * a5, a0 * a1 - a3 * a3],
        ];
        let determinant = a0 * adjugate[0][0] + a3 * adjugate[0][1] + a4 * adjugate[0][2];
        let g = DVec3::new(g0, g1, g2);
        let value = -constant + quadratic_form(&adjugate, g, g) / determinant;
        // Definite: the leading minors are positive.
        let definite = a0 > 0.0 && adjugate[2][2] > 0.0 && determinant > 0.0;
        if definite && value.is_finite() {
            value
        } else {
            f64::INFINITY
        }
    };
    let spread =
        largest - smallest + (literal.matrix_norm() / q.matrix_norm()).max(f64::MIN_POSITIVE);
    let candidates = [(true, may_hold), (false, may_fail)];
    for holds in candidates.into_iter().filter(|c| c.1).map(|c| c.0) {
        // From just past the extreme `λ` outwards; the best is bracketed once the value grows.
        let (start, outwards) = if holds {
            (largest, 1.0)
        } else {
            (smallest, -1.0)
        };
        let at = |t: f64| extreme(start + outwards * t, holds);
        let (mut lo, mut hi) = (0.0, spread);
        while at(hi) < at(0.5 * hi) && hi < 1e6 * spread {
            hi *= 2.0;
        }
        let ratio = 0.5 * (5f64.sqrt() - 1.0);
        for _ in 0..GOLDEN_STEPS {
            let (m1, m2) = (hi - ratio * (hi - lo), lo + ratio * (hi - lo));
            if at(m1) <= at(m2) {
                hi = m2;
            } else {
                lo = m1;
            }
        }
        let best = 0.5 * (lo + hi);
        let lambda = start + outwards * best;
        let margin = remainder_margin(&q, (literal, &moved), lambda, bounds);
        let value = at(best);
        // Below zero by more than the margin everywhere, or touching zero within it.
        if value <= margin {
            return Some(holds);
        }
    }
    None
}

/// Steps of the golden-section search of [`s_lemma`]: they shrink its bracket to `1e-13`.
const GOLDEN_STEPS: usize = 64;

/// `xᵀ M y` for a symmetric `M` given as rows.
fn quadratic_form(m: &[[f64; 3]; 3], x: DVec3, y: DVec3) -> f64 {
    x.dot(DVec3::new(
        DVec3::from_array(m[0]).dot(y),
        DVec3::from_array(m[1]).dot(y),
        DVec3::from_array(m[2]).dot(y),
    ))
}

/// The sign of `literal − λ q` over the surface of `q` inside `bounds` ([`on_surface`]):
/// `Some(true)` where it is at most zero, `Some(false)` where it is at least zero, up to a
/// margin for rounding, but not both. `moved` is `q` about the literal's origin; `basis`, where
/// given, diagonalises the remainder's square part.
fn remainder_sign(
    (q, solid): (&Quadric, Option<&Ellipsoidal>),
    (literal, moved): (&Quadric, &[f64; 10]),
    (lambda, basis): (f64, Option<&[DVec3; 3]>),
    bounds: &Aabb,
) -> Option<bool> {
    let b = literal.coefficients();
    let rest = Remainder::new(
        literal.origin(),
        std::array::from_fn(|k| b[k] - lambda * moved[k]),
    )?;
    let margin = remainder_margin(q, (literal, moved), lambda, bounds);
    let sign = |(low, high): (f64, f64)| match (high <= margin, low >= -margin) {
        // Zero throughout: the literal is `q` or its complement there.
        (true, true) => Some(None),
        (holds, fails) if holds != fails => Some(Some(holds)),
        _ => None,
    };
    // Interval arithmetic on the coefficients first (exact for a plane), then over the surface
    // of an ellipsoid, then in the basis that makes the square part a sum of squares.
    let tighter = |(low, high): (f64, f64), other: Option<(f64, f64)>| {
        other.map_or((low, high), |(l, h)| (low.max(l), high.min(h)))
    };
    let range = rest.range(bounds)?;
    if let Some(decided) = sign(range) {
        return decided;
    }
    let range = tighter(
        range,
        solid.and_then(|solid| range_on_ellipsoid(solid, &rest)),
    );
    if let Some(decided) = sign(range) {
        return decided;
    }
    let range = tighter(range, basis.and_then(|b| range_in_basis(&rest, b, bounds)));
    sign(range).flatten()
}

/// What rounding in `literal`, in `λ q` and in moving `q`'s origin to the literal's (`moved`)
/// can amount to over `bounds`: a tiny multiple of the sizes of their terms there (and of
/// `q`'s terms at the shift).
fn remainder_margin(
    q: &Quadric,
    (literal, moved): (&Quadric, &[f64; 10]),
    lambda: f64,
    bounds: &Aabb,
) -> f64 {
    let b = literal.coefficients();
    let shift = (literal.origin() - q.origin()).length();
    let reach = bounds
        .corners()
        .iter()
        .fold(0.0f64, |m, c| m.max((*c - literal.origin()).length()));
    let size = |c: &[f64; 10], at: f64| {
        let square = c[..3].iter().map(|v| v.abs()).sum::<f64>()
            + 2.0 * c[3..6].iter().map(|v| v.abs()).sum::<f64>();
        let linear = 2.0 * c[6..9].iter().map(|v| v.abs()).sum::<f64>();
        square * at * at + linear * at + c[9].abs()
    };
    1e-12 * (size(&b, reach) + lambda.abs() * (size(moved, reach) + size(&q.coefficients(), shift)))
}

/// Where the sampled quadric is an ellipsoid (`solid`, its principal form), a range of
/// `rest`'s values over its surface: exact for the plane part of `rest` (a linear function's
/// extremes over an ellipsoid, as in [`Ellipsoidal::span`]), widened by what its square part,
/// if any, can add there. Over the surface rather than a box around it, this sees that a ball
/// touching the inside of another at one point lies inside it everywhere else.
fn range_on_ellipsoid(solid: &Ellipsoidal, rest: &Remainder) -> Option<(f64, f64)> {
    // The surface is `Σ λ_k u_k² = −κ` in the frame, `u_k` along the axes from the centre.
    let frame = &solid.frame;
    if frame.eigenvalues.contains(&0.0) {
        return None;
    }
    // `rest = 2 gᵀ(x − o) + j + (x − o)ᵀ M (x − o)`: over the surface the plane part ranges over
    // its value at the centre ± `2 √(−κ Σ (g·u_k)² / λ_k)`, the square part at most `‖M‖` times
    // the farthest point's squared distance from `o`.
    let g = rest.linear();
    let middle = 2.0 * g.dot(frame.centre - rest.origin) + rest.constant();
    let across: f64 = (frame.axes.iter().zip(frame.eigenvalues))
        .map(|(axis, lambda)| g.dot(*axis).powi(2) / lambda)
        .sum();
    let half = 2.0 * (-frame.constant * across).max(0.0).sqrt();
    let semi_axis = (frame.eigenvalues.iter())
        .map(|lambda| (-frame.constant / lambda).sqrt())
        .fold(0.0, f64::max);
    let farthest = (frame.centre - rest.origin).length() + semi_axis;
    let spread = half + rest.matrix_norm() * farthest * farthest;
    spread
        .is_finite()
        .then_some((middle - spread, middle + spread))
}

/// A range of `q`'s values over `bounds` by interval arithmetic in `basis` over the box's
/// projections on it: exact for a square part that is a single square in that basis, as
/// `−z²`, whichever way it is turned.
fn range_in_basis(q: &Remainder, basis: &[DVec3; 3], bounds: &Aabb) -> Option<(f64, f64)> {
    let centre = 0.5 * (bounds.min + bounds.max) - q.origin;
    let half = 0.5 * (bounds.max - bounds.min);
    let along = |v: DVec3| (v.dot(centre), v.abs().dot(half));
    let [(c0, h0), (c1, h1), (c2, h2)] = basis.map(along);
    let (centres, halves) = (DVec3::new(c0, c1, c2), DVec3::new(h0, h1, h2));
    let a = q.matrix_a();
    let form = |i: usize, j: usize| quadratic_form(&a, basis[i], basis[j]);
    let l = q.linear();
    let turned = Remainder::new(
        DVec3::ZERO,
        [
            form(0, 0),
            form(1, 1),
            form(2, 2),
            form(0, 1),
            form(0, 2),
            form(1, 2),
            basis[0].dot(l),
            basis[1].dot(l),
            basis[2].dot(l),
            q.constant(),
        ],
    )?;
    turned.range(&Aabb::new(centres - halves, centres + halves))
}

/// A remainder `literal − λ q` of [`remainder_sign`]: a quadric's coefficients about `origin`
/// (in [`Quadric::coefficients`]' order), without the eigenvalue bounds that building a
/// [`Quadric`] finds, which its ranges do not use (they took a tenth of the setup of a run on
/// scenes of many terms).
struct Remainder {
    origin: DVec3,
    coefficients: [f64; 10],
}

impl Remainder {
    /// `None` if not finite.
    fn new(origin: DVec3, coefficients: [f64; 10]) -> Option<Self> {
        (origin.is_finite() && coefficients.iter().all(|c| c.is_finite())).then_some(Self {
            origin,
            coefficients,
        })
    }

    fn matrix_a(&self) -> [[f64; 3]; 3] {
        let [a, b, c, d, e, f, ..] = self.coefficients;
        [[a, d, e], [d, b, f], [e, f, c]]
    }

    fn linear(&self) -> DVec3 {
        DVec3::from_slice(&self.coefficients[6..9])
    }

    fn constant(&self) -> f64 {
        self.coefficients[9]
    }

    /// Frobenius norm of the square part.
    fn matrix_norm(&self) -> f64 {
        let [a, b, c, d, e, f, ..] = self.coefficients;
        (a * a + b * b + c * c + 2.0 * (d * d + e * e + f * f)).sqrt()
    }

    /// A rigorous enclosure of its values over `bounds` ([`quadric_box::coefficient_range`]).
    fn range(&self, bounds: &Aabb) -> Option<(f64, f64)> {
        quadric_box::coefficient_range(self.origin, &self.coefficients, bounds)
    }
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

/// For every two terms whose boxes touch and that meet along a plane (one holds `n·x ≤ c`, the
/// other `n·x ≥ c`), the merged term of [`merged_literals`] with the indices of the two, at
/// most `limit` of them, in a fixed order.
fn abutting_unions(
    terms: &[TermLiterals],
    boxes: &BoxIndex,
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
        // Terms whose boxes are apart cannot meet along a plane.
        let touching = boxes.near(&boxes.boxes()[i], tolerance);
        for k in touching.into_iter().map(|k| k as usize).filter(|&k| k > i) {
            let planes_k = &planes[k];
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

/// How a literal meets the sampled surface inside its term's box, when one of the two is
/// planar and the other a bounded ellipse in cross-section (see "Tangent planes").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Contact {
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
    fn of_outside(self, outside: bool) -> Self {
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
const TANGENT_SLACK: f64 = 1e-12;

/// A quadric `Σ λ_k u_k² + κ = 0` in its frame whose non-zero `λ_k` share a sign opposite to
/// `κ`'s: an ellipsoid or an elliptic cylinder (or their complements).
#[derive(Clone)]
struct Ellipsoidal {
    frame: PrincipalFrame,
    /// Whether its solid is the inside (`λ_k > 0`), not the outside.
    inside: bool,
}

impl Ellipsoidal {
    /// The ellipsoidal form of a quadric that is not planar, from its frame.
    fn from_frame(frame: PrincipalFrame) -> Option<Self> {
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
    fn span(&self, n: DVec3, bounds: &Aabb, slack: f64) -> Option<(f64, f64, f64)> {
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
struct Shape {
    /// Its principal axes ([`PrincipalFrame::axes`]).
    axes: [DVec3; 3],
    /// Points of its surface: its centre moved along each principal axis to the surface, both
    /// ways, where that meets it (an ellipsoid's six tips, a cylinder's four).
    tips: Vec<DVec3>,
    is_planar: bool,
    /// Its half-spaces, when planar ([`planar_parts`]).
    planar: Option<PlanarParts>,
    ellipsoidal: Option<Ellipsoidal>,
}

impl Shape {
    fn of(q: &Quadric) -> Self {
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

/// What every distance of a DNF shares, found once ([`CsgDistance::with_shapes`]): the
/// [`Shape`] of each quadric, each term's literals, and the abutting unions of its terms
/// ("Abutting terms"), each with the indices of its two terms.
pub(crate) struct Shapes {
    /// The DNF's diagonal, and the length below which a point is on a plane: `1e-9` of it
    /// (`0` for an unbounded DNF).
    diagonal: f64,
    tolerance: f64,
    shapes: Vec<Shape>,
    terms: Vec<TermLiterals>,
    /// The terms' boxes, as the DNF has them.
    boxes: BoxIndex,
    merged: Vec<(TermLiterals, (usize, usize))>,
    /// For each term, the indices in `merged` of its unions.
    merged_with: Vec<Vec<u32>>,
    /// Whether each quadric is a literal of more than one term.
    shared: Vec<bool>,
    /// What the sheets of shared quadrics see of other literals ([`Shapes::seen_from_sheet`]), by
    /// sampled quadric, sheet and literal.
    seen_from_sheets: Mutex<FxHashMap<(u32, u32, u32), SeenFromSheet>>,
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
        let merged = abutting_unions(&terms, &boxes, tolerance, limit);
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
            merged_with,
            shared: terms_of.into_iter().map(|count| count > 1).collect(),
            seen_from_sheets: Mutex::default(),
        }
    }

    /// The shape of a quadric of the DNF (checked by the caller).
    fn of(&self, quadric: u32) -> &Shape {
        &self.shapes[quadric as usize]
    }

    /// What sheet `sheet` of `quadric` sees of `literal`: whether it is the sampled quadric or
    /// its complement (`identity`), and its section by the sheet (`section`) when `wanted`.
    /// A quadric that several terms hold (a DNF expanded from unions and differences repeats
    /// its literals in many terms) is sampled once per term, and each time its sheets would
    /// find the same sections (eigen decompositions of each literal): for such quadrics they
    /// are kept, and a view that wants a section where an earlier one did not makes it then.
    fn seen_from_sheet(
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
            lock().insert(key, seen.clone());
        }
        seen
    }
}

/// The sampled quadric as [`Contact`] sees it.
enum Sampled {
    /// Curved, with bounded cross-sections: planar literals may touch it.
    Ellipsoidal(Ellipsoidal),
    /// One sheet of a planar quadric, as the half-space it bounds; ellipsoidal literals may
    /// touch it.
    Planar(HalfSpace),
    Other,
}

/// Which literals touch the sampled surface without crossing it, inside its term's box.
struct Tangency {
    sampled: Sampled,
    bounds: Aabb,
    /// [`TANGENT_SLACK`] times the scene's diagonal.
    slack: f64,
    /// The length below which planes count as one ("Shared planes").
    shared: f64,
    /// The largest coordinate of the bounds' corners, for [`Tangency::parallel`].
    reach: f64,
}

impl Tangency {
    /// Contacts with quadric `quadric` of the DNF, or with its sheet `plane` when it is planar.
    fn new(shapes: &Shapes, quadric: u32, plane: Option<HalfSpace>, bounds: &Aabb) -> Self {
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

    /// How `literal` meets the sampled surface.
    fn of(&self, literal: &Shape) -> Contact {
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
                    return self.parallel(sheet, spaces, *complement);
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
    /// none of it (a countersink's top `0.01` above a face). Planes within the tolerance of
    /// "Shared planes" are that rule's, and a half-space across the sheet crosses it.
    fn parallel(&self, sheet: &HalfSpace, spaces: &[HalfSpace], complement: bool) -> Contact {
        let reach = self.reach;
        let mut contact = Contact::Holds;
        for h in spaces {
            let side = h.normal.dot(sheet.normal).signum();
            let tilt = (h.normal - side * sheet.normal).length();
            // On the sheet `n·x = c`: `h.normal·x − h.offset = side c − h.offset` up to the tilt.
            let value = side * sheet.offset - h.offset;
            let margin = self.shared
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

/// The half-spaces of a planar quadric, and whether the quadric is the complement of their
/// intersection (the outside of a slab) rather than the intersection ([`planar_parts`]).
type PlanarParts = (Vec<HalfSpace>, bool);

/// The half-spaces of a planar literal ([`half_spaces`]), or those of the slab whose outside
/// it is, flagged `true`.
fn planar_parts(q: &Quadric) -> Option<PlanarParts> {
    if !is_planar(q) {
        return None;
    }
    half_spaces(q)
        .map(|spaces| (spaces, false))
        .or_else(|| half_spaces(&q.negated()).map(|spaces| (spaces, true)))
}

/// The section of `literal` by the sheet plane `plane`, as a quadric constant along the
/// plane's normal, with its half-spaces when it is planar: a cylinder cut along its axis gives
/// the slab between the two lines, another plane its line (a half-space across the sheet), a
/// cone or a ball its circle (a cylinder). On the plane it equals the literal, and off it its
/// distance to its surface is the distance within the plane, so it stands for the literal in
/// eq. 22 at points of the sheet (see "Planar sections"). With `P = I − n nᵀ` and the
/// literal's origin moved onto the plane by `δ = t n`: `A' = P A P`, `l' = P (A δ + l)`,
/// `j' = δᵀ A δ + 2 l·δ + j`.
///
/// Planar means `A'` of rank at most one, `λ u uᵀ`, with `l'` along `u`. Rounding leaves noise
/// in the other directions (a cylinder cut exactly along its axis after a rotation), which
/// would make the section a parabolic cylinder with its vertex at `10³¹`: parts below
/// [`SECTION_NOISE`] of the section's scale are dropped, which moves its surface by about that
/// fraction of the scene. `None` for a plane within [`SECTION_TILT`] of parallel to the sheet.
fn section(literal: &Quadric, plane: &HalfSpace) -> Option<(Quadric, Option<PlanarParts>)> {
    let n = plane.normal;
    let origin = literal.origin();
    let delta = (plane.offset - n.dot(origin)) * n;
    let rows = literal.matrix_a().map(DVec3::from);
    let a = |v: DVec3| DVec3::new(rows[0].dot(v), rows[1].dot(v), rows[2].dot(v));
    let project = |v: DVec3| v - n.dot(v) * n;
    // P A P, column by column: P A P e_k (symmetric, so also its rows).
    let columns = [DVec3::X, DVec3::Y, DVec3::Z].map(|e| project(a(project(e))));
    let matrix_of = |c: &[DVec3; 3]| [0, 1, 2].map(|r| [c[0][r], c[1][r], c[2][r]]);
    let norm = |m: &[DVec3; 3]| m.iter().map(|c| c.length_squared()).sum::<f64>().sqrt();
    let (a_norm, section_norm) = (norm(&rows), norm(&columns));
    let l = literal.linear();
    let linear = project(a(delta) + l);
    let constant = delta.dot(a(delta)) + 2.0 * l.dot(delta) + literal.constant();
    let at = origin + delta;
    let planar = |matrix: &[[f64; 3]; 3], linear: DVec3| {
        let section = Quadric::from_matrix(at, matrix, linear, constant)?;
        planar_parts(&section).map(|parts| (section, Some(parts)))
    };
    if section_norm <= SECTION_NOISE * a_norm {
        // Linear on the plane: a line, unless the literal is (nearly) parallel to the plane,
        // where `l'` is rounding noise and its line could lie anywhere ("Shared planes" handles
        // planes parallel to the sheet).
        let significant = if a_norm > 0.0 {
            l.length() + (constant.abs() * a_norm).sqrt()
        } else {
            l.length()
        };
        if linear.length() <= SECTION_TILT * significant || linear.length().is_nan() {
            return None;
        }
        return planar(&[[0.0; 3]; 3], linear);
    }
    // Rank one: every column is a multiple of `u`, the longest one's direction.
    let longest = columns
        .iter()
        .copied()
        .max_by(|p, q| p.length_squared().total_cmp(&q.length_squared()))?;
    let u = longest.try_normalize()?;
    let lambda = u.dot(columns[0] * u.x + columns[1] * u.y + columns[2] * u.z);
    let rest: f64 = columns
        .iter()
        .zip([u.x, u.y, u.z])
        .map(|(c, u_k)| (*c - lambda * u_k * u).length_squared())
        .sum::<f64>()
        .sqrt();
    if rest <= SECTION_NOISE * section_norm {
        let across = linear - linear.dot(u) * u;
        let scale = (constant.abs() / section_norm).sqrt();
        if across.length() <= SECTION_NOISE * (linear.length() + section_norm * scale) {
            let rank_one = [0, 1, 2].map(|r| [0, 1, 2].map(|c| lambda * u[r] * u[c]));
            if let Some(found) = planar(&rank_one, linear - across) {
                return Some(found);
            }
        }
    }
    // A conic: an ellipse, a hyperbola or a parabola on the plane.
    let section = Quadric::from_matrix(at, &matrix_of(&columns), linear, constant)?;
    Some((section, None))
}

/// Relative size below which [`section`] takes a part of a section for rounding.
const SECTION_NOISE: f64 = 1e-12;

/// Sine of the smallest angle between a planar literal and the sheet that [`section`] replaces
/// by its line on the sheet: closer to parallel, the line's position would be mostly
/// rounding, and the literal stays as it is.
const SECTION_TILT: f64 = 1e-6;

/// The half-space that the outside of a slab (its `parts`) is within `bounds`, when `bounds`
/// lies on the inner side of one of the slab's planes, up to `tolerance`: only the half-space
/// beyond the other plane is left there, but for a layer thinner than the tolerance, as where
/// a cut is flush with a face of the part it cuts.
fn one_side(parts: Option<&PlanarParts>, bounds: &Aabb, tolerance: f64) -> Option<HalfSpace> {
    let Some((spaces, true)) = parts else {
        return None;
    };
    let reach = |n: DVec3| {
        bounds
            .corners()
            .iter()
            .map(|c| n.dot(*c))
            .fold(f64::NEG_INFINITY, f64::max)
    };
    match spaces.as_slice() {
        [a, b] if reach(a.normal) <= a.offset + tolerance => Some(beyond(b)),
        [a, b] if reach(b.normal) <= b.offset + tolerance => Some(beyond(a)),
        _ => None,
    }
}

/// The closed complement of a half-space: a slab is `n·x ≤ c` for each of its half-spaces, its
/// outside `n·x ≥ c` for either.
fn beyond(h: &HalfSpace) -> HalfSpace {
    HalfSpace {
        normal: -h.normal,
        offset: -h.offset,
        point: h.point,
    }
}

/// On a sampled `plane`, the outsides of slabs among term `a`'s literals `own` where one side
/// leaves the term no area within its `bounds` (it faces the term's half-spaces across a strip
/// no wider than `tolerance`) stand as their other side, as "One side of a slab" does where
/// the term's box shows it, but for a box that spans both planes of a turned slab. `true` when
/// neither side leaves any: the term has no area on the plane ("Strips of no width").
fn one_side_with_area(
    own: &mut [Refined],
    plane: &HalfSpace,
    bounds: &Aabb,
    tolerance: f64,
) -> bool {
    let sides = own_half_spaces(own, Some(plane));
    let has_area = |h: HalfSpace| {
        let mut with = sides.clone();
        with.push(h);
        !no_area_between(&with, plane, bounds, tolerance)
    };
    for r in own.iter_mut() {
        let Some((spaces, true)) = &r.parts else {
            continue;
        };
        let [a, b] = spaces.as_slice() else {
            continue;
        };
        let (a, b) = (beyond(a), beyond(b));
        let half = match (has_area(a), has_area(b)) {
            (false, false) => return true,
            (true, false) => a,
            (false, true) => b,
            (true, true) => continue,
        };
        *r = Refined::one_side(r.index, half, r.quadric);
    }
    false
}

/// The half-spaces of term `a`'s planar literals (not the outsides of slabs), but for those
/// parallel to the sampled `plane`, which "Shared planes" handles.
fn own_half_spaces(own: &[Refined], plane: Option<&HalfSpace>) -> Vec<HalfSpace> {
    own.iter()
        .filter_map(|r| match &r.parts {
            Some((spaces, false)) => Some(spaces.iter().copied()),
            _ => None,
        })
        .flatten()
        .filter(|h| plane.is_none_or(|p| h.normal.cross(p.normal).length() > PARALLEL))
        .collect()
}

/// Whether two of term `a`'s half-spaces `sides` meet the sampled `plane` in half-planes facing
/// each other across a strip no wider than `tolerance` within the term's `bounds`: the term has
/// no area on the plane ("Strips of no width"). A gusset cut off by a 45° box: the cutter's two
/// faces meet on the gusset's bottom plane, and the DNF term of the face that misses the
/// gusset leaves only the line where they meet.
fn no_area_between(sides: &[HalfSpace], plane: &HalfSpace, bounds: &Aabb, tolerance: f64) -> bool {
    // `n · x ≤ c` on the plane `p · x = o` is `m · x ≤ (c − (n · p) o) / |m'|`, `m = m' / |m'|`
    // with `m' = n − (n · p) p` its normal within the plane.
    let sections: Vec<(DVec3, f64)> = sides
        .iter()
        .filter_map(|h| {
            let across = h.normal.dot(plane.normal);
            let within = h.normal - across * plane.normal;
            let length = within.length();
            (length > PARALLEL)
                .then(|| (within / length, (h.offset - across * plane.offset) / length))
        })
        .collect();
    let corners = bounds.corners();
    sections.iter().enumerate().any(|(i, &(m1, c1))| {
        sections[i + 1..].iter().any(|&(m2, c2)| {
            // Depth inside both half-planes is at most half the sum of the two depths, which is
            // linear in `x`: its largest value over the box is at a corner.
            m1.dot(m2) < 0.0
                && corners
                    .iter()
                    .all(|&x| c1 - m1.dot(x) + c2 - m2.dot(x) <= 2.0 * tolerance)
        })
    })
}

/// A planar literal of another term without the half-spaces that term `a` holds too (see
/// "Literals of both terms"), as `(quadric, planar, in term a)`: a slab sharing one side with
/// term `a` becomes its other side.
fn without_own_sides(
    literal: &Refined,
    own_sides: &[HalfSpace],
    tolerance: f64,
) -> Vec<(Quadric, bool, bool)> {
    let whole = vec![(literal.quadric, literal.planar, false)];
    let Some((spaces, false)) = &literal.parts else {
        return whole;
    };
    let shared = |h: &HalfSpace| {
        own_sides.iter().any(|g| {
            (h.normal - g.normal).length() <= PARALLEL && (h.offset - g.offset).abs() <= tolerance
        })
    };
    if !spaces.iter().any(shared) {
        return whole;
    }
    spaces
        .iter()
        .filter(|h| !shared(h))
        .filter_map(|h| Quadric::half_space(h.point, h.normal))
        .map(|q| (q, true, false))
        .collect()
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
