//! Reference points on the CSG surface, found independently of the sampler. The oracle is
//! [`qcsg_testkit::reference`], the one the sampler's tests check coverage against; it is named
//! here too because the measurements are written in its terms.

pub use qcsg_testkit::reference::{
    SurfacePoint, diagonal, edge_points, on_csg_surface, project, quadric_points, ray_hits,
    reference_points, side_step,
};
