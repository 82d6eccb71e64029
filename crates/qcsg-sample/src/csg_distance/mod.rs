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
//! - **One notion of the same surface.** Which literals are `Q_ab` itself, its complement, or
//!   lie on a sheet of it is what the compiler decided (`qcsg_csg::coincident`, read through
//!   [`Dnf::surfaces`](qcsg_csg::Dnf::surfaces) by `identity`): one surface up to a non-zero
//!   factor, within the rounding of the transforms that placed each quadric, so flush faces
//!   are found alike near the origin, far from it, turned and scaled, curved or flat, and a wall
//!   `1e-9` thick is two surfaces. Only literals the sampler makes itself (halves of slabs in
//!   merged terms and planar sections) and DNFs without surfaces fall back to comparing values
//!   (`1e-12` relative) and, on a plane, the point test below.
//! - **Shared surfaces.** A term `i ≠ a` that has `Q_ab` itself among its literals (the same
//!   index, or the same surface with the same orientation) is a subset of `Q_ab`'s solid, so a
//!   point on `Q_ab` is never in its interior: the term is left out. Without this the distance
//!   would be 0 on all of `Q_ab` inside that term and subdivision could never classify it.
//! - **Complementary literals.** A literal of term `i` that is `Q_ab`'s complement is zero on
//!   `Q_ab`; the term's interior then touches `Q_ab` from the other side, and `p` is interior to
//!   the union exactly when it also lies inside the term's remaining literals. That literal is
//!   left out of term `i` (and an own literal equal to `Q_ab` is left out of term `a`: it holds
//!   on all of `Q_ab`).
//! - **Shared planes.** Two *different* quadrics can share a patch of surface only where both
//!   are made of planes (a half-space, a slab): two parts sharing a face, a difference flush
//!   with a face. (Curved quadrics share a surface only whole: the rules above.) When `Q_ab` is
//!   planar and another planar literal `L` has a sheet on the surface of `p`'s sheet of `Q_ab`
//!   (for a literal the sampler made: `p` lies on its plane within [`CsgDistance`]'s length
//!   tolerance, normals parallel), what holds at `p` holds on the whole sheet: if `L`'s inside is on `Q_ab`'s
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
//!   made (`MAX_MERGED_PER_TERM`). A merged term enters eq. 22 of a sampled part only where the
//!   box of its two terms meets the part's: at a point outside both pieces it fails a literal
//!   that the piece on the point's side of the plane fails, so it is no nearer than that piece
//!   (where only literals that term `a` holds too fail, term `a` fails as well). The cells of a
//!   glyph abut in many pairs, and a part near them kept two to three unions per term.
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
//!   holds on all of the plane or on none of it (a countersink's top `0.01` above a face); where
//!   the surfaces say the two planes differ, only rounding is allowed for, however close they
//!   are (a wall `1e-9` thick).
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
//!   separate parts then cost time and memory in proportion to the parts, not to their square.
//! - **Far literals.** Of a term with more than 32 literals (a plate drilled with many holes),
//!   those that hold on all of the box grown by `D` (`quadric_box::classify`) are left out too,
//!   and the term's distance is kept at least `−(D − e)` for the same reason. Per basic region
//!   ([`CsgDistance::near`], [`NearDistance::narrow`]) the same is done with the region's box
//!   and margin, and "Literals of both terms" still sees term `a`'s literals left out, so a query
//!   on a plate drilled with many holes looks at the holes near it only.
//! - **Offset surfaces.** On the sampled quadric `q = 0`, so a literal `L` equals `L − λ q` there
//!   for any `λ`. Where `L`'s square part is `λ` times `q`'s (nested balls, coaxial cylinders:
//!   OpenSCAD models overlap parts by a small epsilon, a bore `0.01` wider than its pin, a
//!   cutter `1e-3` inside a ball), `L − λ q` is a plane or a constant, which interval
//!   arithmetic bounds over the box grown by `D` ("Far terms"): `L` holds on all of the sampled
//!   surface there or on none of it. A literal that holds is left out of its term, which keeps
//!   the floor `−(D − e)` of "Far literals"; another term with a literal that holds nowhere is
//!   left out like a far term. Near such a gap eq. 22 would be the gap itself: a column `0.01`
//!   inside the steps around it could not be proven hidden above the cutoff of its rectangles.
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
//!   cylinder's side alone would be `z² / 2r` at a height `z` above the rim, touching zero
//!   along it.
//! - **One side of a slab.** The outside of a slab is a union of two half-spaces, which no rule
//!   above can pair. Where a term's box lies on the inner side of one of the slab's planes (up
//!   to the length tolerance: a box flush with the plane lies on it), the literal is the
//!   half-space beyond the other plane within the term, and stands as that. A cut flush with
//!   three faces of a box (`crates/qcsg-splat/tests/scenes/coincident_faces.qcsg`) is
//!   classified so.
//! - **Strips of no width.** On a sampled plane, two half-spaces of term `a` whose sections face
//!   each other across a strip no wider than the length tolerance within the term's box leave
//!   the term no area there: it samples nothing on that sheet. Cutting a box with another box
//!   turned by 45°, as OpenSCAD models make a triangular gusset, gives a DNF term for each of the
//!   cutter's faces; where the two faces meet on the gusset's bottom plane, the term of the face
//!   that misses the gusset is that line. Eq. 22 there would be the distance to the line,
//!   touching zero along it (`examples/openscad_bracket.scad`). The same test tells
//!   which side of a slab a term holds where its box spans both planes (a turned part, see
//!   "One side of a slab"): the side that leaves no area is dropped
//!   (`tests/stability/tangent_rounded_tray_tilted.qcsg`).
//!
//! The modules: `distance` sets eq. 22 up for one sampled literal and queries it, through
//! the terms as the sampled quadric sees them (`view`) and as each sheet of it does
//! (`sheet_views`); `near` narrows it to a box. The rules above live in `abutting`,
//! `half_spaces`, `identity` (the compiler's surfaces as a sheet reads them), `sections`
//! (planar sections, sides of slabs, strips of no width),
//! `surface_sign` (offset and touching surfaces) and `tangency` (tangent planes).

mod abutting;
mod distance;
mod half_spaces;
mod identity;
mod near;
mod positions;
mod sections;
mod sheet_views;
mod surface_sign;
mod tangency;
mod view;

pub use distance::CsgDistance;
pub use near::{NearDistance, box_distance};
pub(crate) use tangency::Shapes;
