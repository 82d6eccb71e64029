//! The compiler's surfaces as one sheet of the sampled quadric reads them ([`SheetIdentity`]):
//! which literals are the sampled quadric or its complement, and which lie on the sheet, with
//! which orientation ("Shared surfaces", "Shared planes" in [`super`]).
//!
//! The compiler decides once which quadrics of a DNF share a surface, within the rounding of
//! the transforms that placed them (`qcsg_csg::coincident`); the sampler takes that answer
//! rather than a tolerance of its own, so a curved flush face (a cylinder cut flush at half
//! height, a ball minus a turned copy of itself) is resolved like a flat one, far from the
//! origin and scaled down alike, and a real wall `1e-9` thick is never merged. A DNF without
//! surfaces (built by hand) falls back to the value and point tests of [`super::view`].

use super::half_spaces::HalfSpace;
use super::view::Shared;
use qcsg_csg::{Dnf, Sheet, Surfaces};

/// One sheet of the sampled quadric, as the compiler's surfaces have it.
pub(super) struct SheetIdentity<'a> {
    surfaces: &'a Surfaces,
    /// The sampled quadric's sheets; `None` when the DNF has no surfaces for it.
    own: Option<&'a [Sheet]>,
    /// The sheet sampled (the one facing the sampler's plane, for a planar quadric).
    sheet: Option<Sheet>,
}

impl<'a> SheetIdentity<'a> {
    /// Quadric `quadric` of `dnf`, on its sheet through the plane `plane` (a planar quadric), or
    /// whole (`None`: a curved quadric has one sheet).
    pub(super) fn new(dnf: &'a Dnf, quadric: u32, plane: Option<&HalfSpace>) -> Self {
        let surfaces = &dnf.surfaces;
        let own = surfaces
            .of(quadric)
            .filter(|_| surfaces.quadric_count() == dnf.quadrics.len());
        let sheet = own.and_then(|sheets| match plane {
            None => (sheets.len() == 1).then(|| sheets[0]),
            // A slab's two sheets are parallel planes apart: the one through the plane's point
            // (for the outside of a slab the plane faces the other way, so its normal cannot
            // tell).
            Some(plane) => {
                let off = |s: &Sheet| {
                    surfaces
                        .surface(s.surface)
                        .filter(|surface| surface.planar)
                        .map(|surface| {
                            let q = &surface.quadric;
                            q.value(plane.point).abs() / (2.0 * q.linear().length())
                        })
                };
                sheets
                    .iter()
                    .filter_map(|s| Some((*s, off(s)?)))
                    .min_by(|a, b| a.1.total_cmp(&b.1))
                    .map(|(s, _)| s)
            }
        });
        Self {
            surfaces,
            own,
            sheet,
        }
    }

    /// Whether literal `literal` is the sampled quadric (every sheet on the same surfaces, with
    /// the same orientations and sides) and whether it is its complement (the same surfaces,
    /// every orientation opposite); `None` without surfaces.
    pub(super) fn identity(&self, literal: u32) -> Option<(bool, bool)> {
        let own = self.own?;
        let other = self.surfaces.of(literal)?;
        if own.is_empty() || own.len() != other.len() {
            return Some((false, false));
        }
        let find = |s: &Sheet| other.iter().find(|o| o.surface == s.surface);
        let same = own.iter().all(|s| {
            find(s).is_some_and(|o| o.orientation == s.orientation && o.one_sided == s.one_sided)
        });
        // A half-space or curved quadric and its complement are each one-sided; a slab's
        // complement is not, and a slab is.
        let complement = own.iter().all(|s| {
            find(s).is_some_and(|o| {
                o.orientation != s.orientation && (own.len() == 1 || o.one_sided != s.one_sided)
            })
        });
        Some((same, complement))
    }

    /// How literal `literal` lies on the sampled sheet: on it with its inside on the sheet's
    /// inside ([`Shared::SameSide`]) or on the other side, or not on it; `None` without
    /// surfaces or for a curved sampled quadric.
    pub(super) fn on_sheet(&self, literal: u32) -> Option<Shared> {
        let sheet = self.sheet?;
        if !self.surfaces.surface(sheet.surface)?.planar {
            return None;
        }
        let other = self.surfaces.of(literal)?;
        Some(match other.iter().find(|o| o.surface == sheet.surface) {
            None => Shared::No,
            Some(o) if o.orientation == sheet.orientation => Shared::SameSide,
            Some(_) => Shared::OtherSide,
        })
    }

    /// [`Self::on_sheet`] for the one half-space `half` that a term keeps of literal `literal`
    /// (the outside of a slab whose two planes are `planes`: "One side of a slab"): the
    /// literal's relation when `half` is its plane nearer the sheet `plane`, else not on it.
    pub(super) fn half_on_sheet(
        &self,
        literal: u32,
        half: &HalfSpace,
        planes: &[HalfSpace],
        plane: &HalfSpace,
    ) -> Option<Shared> {
        let shared = self.on_sheet(literal)?;
        // `half` is one of `planes` (up to its sign): it is on the sheet when it is the nearer.
        let off = |h: &HalfSpace| (h.normal.dot(plane.point) - h.offset).abs();
        let nearest = planes.iter().map(off).fold(f64::INFINITY, f64::min);
        Some(if off(half) <= nearest {
            shared
        } else {
            Shared::No
        })
    }
}
