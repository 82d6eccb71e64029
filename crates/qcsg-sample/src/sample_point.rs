//! One sample on the CSG surface ([`Sample`]): a position on its quadric, the quadric's
//! outward normal there, the quadric and term it was sampled for, the radius it covers and its
//! clip list.

use qcsg_quadric::DVec3;

/// One sample on the CSG surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// World position, on the quadric.
    pub position: DVec3,
    /// Outward unit normal of the quadric at the position.
    pub normal: DVec3,
    /// Index into [`Dnf::quadrics`](qcsg_csg::Dnf::quadrics).
    pub quadric: u32,
    /// Index into [`Dnf::terms`](qcsg_csg::Dnf::terms) of the term it was sampled for.
    pub term: u32,
    /// The radius it covers (at most the requested radius; smaller for small regions).
    pub radius: f64,
    /// Index of its clip list in [`Sampling::clip_lists`](crate::Sampling::clip_lists) (0: the empty list).
    pub clip_list: u32,
}

impl Sample {
    /// Whether the sample's normal is less than 90° from `normal`, the outward unit normal of
    /// a point of the same quadric (the two face the same way). Coverage asks for it besides
    /// the distance: a splat draws only the side of its quadric it lies on, so a sample on one
    /// face of a thin slab (or the far side of a small ball) must not cover the other.
    pub fn same_side(&self, normal: DVec3) -> bool {
        self.normal.dot(normal) > 0.0
    }
}
