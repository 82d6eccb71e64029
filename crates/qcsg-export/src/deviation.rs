//! The two-way distance between a mesh and the exact surface, as upper bounds, from points on
//! the surface that come within a known radius `r` of every surface point (the sampler's
//! coverage guarantee).
//!
//! - Surface to mesh: every surface point `x` has a point `s` within `r`, so
//!   `d(x, mesh) ≤ d(s, mesh) + r`; `d(s, mesh)` is an exact point-triangle distance to the
//!   nearest triangle (an R-tree of the triangles' boxes).
//! - Mesh to surface: the points are on the surface, so `d(m, surface) ≤ min_s |m − s|` for every
//!   mesh point `m`. That bound is 1-Lipschitz in `m`, so over a triangle it is at most its value
//!   at the centroid plus the distance to the farthest corner: a triangle is split in four until
//!   that sum is within the tolerance, or the pieces are smaller than `spacing`, and the largest
//!   sum is the bound.

use kiddo::{ImmutableKdTree, SquaredEuclidean};
use qcsg_csg::Dnf;
use qcsg_mesh::closest_point_on_triangle;
use qcsg_quadric::DVec3;
use qcsg_sample::{SampleError, SampleLimits, sample_with_limits};
use rayon::prelude::*;
use rstar::{AABB, PointDistance, RTree, RTreeObject};

use crate::TriangleMesh;

/// The measured distances, each an upper bound on the true directed Hausdorff distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Deviation {
    /// The largest distance from a surface point to the mesh.
    pub surface_to_mesh: f64,
    /// The largest distance from a mesh point to the surface.
    pub mesh_to_surface: f64,
    /// How many surface points were used.
    pub surface_points: usize,
    /// How many points of the mesh the bound was evaluated at.
    pub mesh_points: usize,
    /// Sampler points left out as not on the surface (the solid on both sides or neither).
    pub points_off_surface: usize,
}

impl Deviation {
    /// The larger of the two directions: an upper bound on the Hausdorff distance.
    pub fn hausdorff(&self) -> f64 {
        self.surface_to_mesh.max(self.mesh_to_surface)
    }
}

/// Points on the exact surface within `radius` of every surface point, and how many of the
/// sampler's points were left out because the solid is on both sides of them or on neither:
/// points inside the solid would make a mesh with no surface there look wrong.
///
/// A point is on the surface when the solid's membership differs on the two sides of it at
/// some step along the normal, tried from `step` down by factors of 1000 to a few ulps of the
/// coordinates: one step alone either misses a wall or gap thinner than it (the faces of a
/// plate 10⁻⁶ thick, of plates 10⁻⁷ apart) or, at 10⁹ from the origin, rounds away.
pub(crate) fn surface_points(
    dnf: &Dnf,
    radius: f64,
    limits: SampleLimits,
    step: f64,
) -> Result<(Vec<DVec3>, usize), SampleError> {
    let sampling = sample_with_limits(dnf, radius, limits, &|_| {})?;
    let all = sampling.samples.to_vec();
    let kept: Vec<DVec3> = all
        .par_iter()
        .filter(|s| {
            let floor = 16.0 * f64::EPSILON * s.position.abs().max_element().max(f64::MIN_POSITIVE);
            let mut h = step;
            loop {
                let (a, b) = (s.position + h * s.normal, s.position - h * s.normal);
                if dnf.contains(a) != dnf.contains(b) {
                    return true;
                }
                if h <= floor {
                    return false;
                }
                h = (h * 1e-3).max(floor);
            }
        })
        .map(|s| s.position)
        .collect();
    let dropped = all.len() - kept.len();
    Ok((kept, dropped))
}

struct Triangle([DVec3; 3]);

impl RTreeObject for Triangle {
    type Envelope = AABB<[f64; 3]>;

    fn envelope(&self) -> Self::Envelope {
        let [a, b, c] = self.0;
        AABB::from_corners(a.min(b).min(c).to_array(), a.max(b).max(c).to_array())
    }
}

impl PointDistance for Triangle {
    fn distance_2(&self, point: &[f64; 3]) -> f64 {
        let p = DVec3::from_array(*point);
        (closest_point_on_triangle(p, &self.0) - p).length_squared()
    }
}

/// Measures both directions; `points` come within `coverage` of every surface point, and
/// triangles are split down to pieces of `spacing` where the bound needs it to reach
/// `tolerance`.
pub fn measure_deviation(
    mesh: &TriangleMesh,
    points: &[DVec3],
    coverage: f64,
    tolerance: f64,
    spacing: f64,
) -> Deviation {
    let mut result = Deviation {
        surface_to_mesh: f64::INFINITY,
        mesh_to_surface: f64::INFINITY,
        surface_points: points.len(),
        mesh_points: 0,
        points_off_surface: 0,
    };
    if points.is_empty() || mesh.triangles.is_empty() {
        if points.is_empty() && mesh.triangles.is_empty() {
            result.surface_to_mesh = 0.0;
            result.mesh_to_surface = 0.0;
        }
        return result;
    }
    let tree = RTree::bulk_load(
        mesh.triangles
            .iter()
            .map(|t| Triangle(mesh.corners(t)))
            .collect(),
    );
    result.surface_to_mesh = points
        .par_iter()
        .map(|p| {
            tree.nearest_neighbor(p.to_array())
                .map_or(f64::INFINITY, |t| t.distance_2(&p.to_array()).sqrt())
        })
        .reduce(|| 0.0, f64::max)
        + coverage;

    let arrays: Vec<[f64; 3]> = points.iter().map(|p| p.to_array()).collect();
    let Ok(kd) = ImmutableKdTree::<f64, 3>::new_from_slice(&arrays) else {
        return result;
    };
    let nearest = |p: DVec3| {
        kd.query(&p.to_array())
            .nearest_one::<SquaredEuclidean<f64>>()
            .execute()
            .distance
            .sqrt()
    };
    let (bound, count) = mesh
        .triangles
        .par_iter()
        .map(|t| triangle_bound(mesh.corners(t), &nearest, tolerance, spacing, 0))
        .reduce(|| (0.0, 0), |a, b| (a.0.max(b.0), a.1 + b.1));
    result.mesh_to_surface = bound;
    result.mesh_points = count;
    result
}

/// The most levels a triangle is split: 4²⁰ pieces of a triangle is far past any useful count.
const MAX_DEPTH: u32 = 20;

/// An upper bound on `nearest` over the triangle, and how many points it took.
fn triangle_bound(
    t: [DVec3; 3],
    nearest: &(dyn Fn(DVec3) -> f64 + Sync),
    tolerance: f64,
    spacing: f64,
    depth: u32,
) -> (f64, usize) {
    let [a, b, c] = t;
    let centroid = (a + b + c) / 3.0;
    let reach = (a - centroid)
        .length()
        .max((b - centroid).length())
        .max((c - centroid).length());
    let bound = nearest(centroid) + reach;
    if bound <= tolerance || reach <= spacing || depth >= MAX_DEPTH || !bound.is_finite() {
        return (bound, 1);
    }
    let (ab, bc, ca) = ((a + b) / 2.0, (b + c) / 2.0, (c + a) / 2.0);
    [[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]
        .into_iter()
        .map(|piece| triangle_bound(piece, nearest, tolerance, spacing, depth + 1))
        .fold((0.0, 0), |acc, x| (acc.0.max(x.0), acc.1 + x.1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bound_covers_the_triangle() {
        // Points on a plane 0.3 above a triangle: the bound is at least 0.3 and the split
        // stops once centroid distance plus reach fits the tolerance.
        let pts: Vec<DVec3> = (0..=20)
            .flat_map(|i| (0..=20).map(move |j| DVec3::new(i as f64 / 20.0, j as f64 / 20.0, 0.3)))
            .collect();
        let mesh = TriangleMesh {
            vertices: vec![DVec3::ZERO, DVec3::X, DVec3::Y],
            triangles: vec![[0, 1, 2]],
        };
        let d = measure_deviation(&mesh, &pts, 0.0, 0.4, 1e-3);
        assert!(
            d.mesh_to_surface >= 0.3 && d.mesh_to_surface <= 0.4,
            "{d:?}"
        );
        assert!((d.surface_to_mesh - 0.3).abs() < 1e-12 || d.surface_to_mesh > 0.3);
    }
}
