//! Which plane faces of a term are grown a little across a face it shares with another term,
//! so that touching pieces of one solid overlap and the union merges them.
//!
//! The normal form cuts polygons with holes, non-convex outlines, imported meshes and hulls
//! into convex cells that share faces: one cell has the literal `n·p ≥ o` and its neighbour the
//! complement `n·p ≤ o` of the same surface (`qcsg_csg::coincident`). Each cell is meshed on
//! its own, and the two meshes' faces on that plane lie a rounding error apart (each cut is
//! made by a half-space placed for its own piece's box), on either side: where they leave a
//! gap, the union keeps both faces, a wall inside the solid. Moving each such face outwards by
//! a length far above that rounding and far below the tolerance makes the pieces overlap, and
//! the union's exact booleans then remove both faces.
//!
//! A face is grown only where the complement of its surface is a literal of another term (the
//! only way another piece can lie flush on its other side) and not of the same term: a term
//! holding both sides of one plane is a flat shell (a cube's face and a flush pocket's), which
//! must stay flat to be dropped, not become a lid. Where the neighbour covers only part of the
//! face, the rest of it stands out by the growth: a step far below the tolerance.

use std::collections::HashSet;

use qcsg_csg::{Dnf, Term};

/// How far a shared face is moved, relative to the scene's half-diagonal: `2⁻³⁸ ≈ 3.6·10⁻¹²`.
/// It must be far above the rounding of a plane cut (a few ulps of the coordinates) and above
/// Manifold's own precision (`10⁻¹²` of the largest coordinate), below which its booleans
/// leave the walls in (`docs/export.md`); and below the margin by which a term's box is widened
/// (`10⁻⁹`), so that the box never clips a grown face.
pub(crate) const GROWTH: f64 = 1.0 / (1u64 << 38) as f64;

/// Edges shorter than this many times the growth are collapsed after the union when any face
/// was grown: the steps that grown faces leave where their neighbours cover only part of them
/// (`2⁻³²` of the half-diagonal, below the thinnest walls the compiler keeps).
pub(crate) const STEP_COLLAPSE: f64 = 64.0;

/// The one-sided plane sheets of the whole DNF, as `(surface, orientation)`, that some term
/// holds.
pub(crate) struct SharedFaces {
    held: HashSet<(u32, i8)>,
}

impl SharedFaces {
    /// Every one-sided plane sheet of every term.
    pub(crate) fn new(dnf: &Dnf) -> Self {
        let held = dnf
            .terms
            .iter()
            .flat_map(|t| plane_sheets(dnf, t))
            .collect();
        Self { held }
    }

    /// Whether any face of any term may be grown: some surface is held with both orientations.
    pub(crate) fn any(&self) -> bool {
        self.held.iter().any(|&(s, o)| self.held.contains(&(s, -o)))
    }

    /// The faces of `term` that are grown.
    pub(crate) fn of_term<'a>(&'a self, dnf: &'a Dnf, term: &'a Term) -> TermFaces<'a> {
        TermFaces {
            shared: self,
            dnf,
            own: plane_sheets(dnf, term).collect(),
        }
    }
}

/// The grown faces of one term.
pub(crate) struct TermFaces<'a> {
    shared: &'a SharedFaces,
    dnf: &'a Dnf,
    own: HashSet<(u32, i8)>,
}

impl TermFaces<'_> {
    /// For each sheet of the term's literal `literal`, whether it is grown: it is a one-sided
    /// plane sheet, another term holds its complement and this term does not.
    pub(crate) fn grown(&self, literal: u32) -> Vec<bool> {
        let Some(sheets) = self.dnf.surfaces.of(literal) else {
            return Vec::new();
        };
        sheets
            .iter()
            .map(|s| {
                let opposite = (s.surface, -s.orientation);
                s.one_sided
                    && is_planar(self.dnf, s.surface)
                    && self.shared.held.contains(&opposite)
                    && !self.own.contains(&opposite)
            })
            .collect()
    }
}

fn is_planar(dnf: &Dnf, surface: u32) -> bool {
    dnf.surfaces.surface(surface).is_some_and(|s| s.planar)
}

/// The one-sided plane sheets of a term's literals.
fn plane_sheets<'a>(dnf: &'a Dnf, term: &'a Term) -> impl Iterator<Item = (u32, i8)> + 'a {
    term.literals.iter().flat_map(move |&l| {
        dnf.surfaces
            .of(l)
            .unwrap_or_default()
            .iter()
            .filter(|s| s.one_sided && is_planar(dnf, s.surface))
            .map(|s| (s.surface, s.orientation))
    })
}
