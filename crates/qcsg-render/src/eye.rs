//! What every ray of a perspective frame shares: its starting point, the eye, and so the value
//! of each quadric there.
//!
//! Intersecting a ray with a quadric needs the quadric's value (with its rounding bound) at the
//! ray's start, about half the work of the intersection. All rays of a perspective frame start
//! at the eye, so the values of a layer's quadrics and surfaces are computed once per frame and
//! read by every ray ([`qcsg_quadric::Quadric::intersect_line_with_value`] gives the same roots,
//! bit for bit). A ray that does not start at the eye (an orthographic frame, a ray traced from
//! elsewhere) computes its own.

use qcsg_csg::Dnf;
use qcsg_quadric::DVec3;

use crate::raytrace::Ray;

/// The values, with their rounding bounds, of a DNF's quadrics and surfaces at one point.
#[derive(Clone, Debug)]
pub struct EyeValues {
    eye: DVec3,
    quadrics: Vec<(f64, f64)>,
    surfaces: Vec<(f64, f64)>,
}

impl EyeValues {
    /// The values of `dnf`'s quadrics and surfaces at `eye`.
    pub fn new(dnf: &Dnf, eye: DVec3) -> Self {
        Self {
            eye,
            quadrics: dnf
                .quadrics
                .iter()
                .map(|q| q.quadric.value_with_error(eye))
                .collect(),
            surfaces: (0..dnf.surfaces.len() as u32)
                .map(|id| {
                    dnf.surfaces
                        .surface(id)
                        .map_or((f64::NAN, f64::NAN), |s| s.quadric.value_with_error(eye))
                })
                .collect(),
        }
    }

    /// These values if `ray` starts exactly at their point (the same bits: `-0.0` is not
    /// `0.0` here, as the values may differ in the sign of a zero).
    pub fn for_ray(&self, ray: &Ray) -> Option<&Self> {
        let same = |a: f64, b: f64| a.to_bits() == b.to_bits();
        (same(self.eye.x, ray.origin.x)
            && same(self.eye.y, ray.origin.y)
            && same(self.eye.z, ray.origin.z))
        .then_some(self)
    }

    /// The value of the DNF quadric `id` at the eye.
    pub fn quadric(&self, id: u32) -> Option<(f64, f64)> {
        self.quadrics.get(id as usize).copied()
    }

    /// The value of the surface `id` at the eye.
    pub fn surface(&self, id: u32) -> Option<(f64, f64)> {
        self.surfaces.get(id as usize).copied()
    }
}
