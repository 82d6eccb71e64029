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
/// sampler's points were left out because the solid is on both sides of them or on neither
/// (tested `step` along the normal): points inside the solid would make a mesh with no
/// surface there look wrong.
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
            dnf.contains(s.position + step * s.normal) != dnf.contains(s.position - step * s.normal)
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
        (closest_point(p, &self.0) - p).length_squared()
    }
}

/// The point of triangle `t` closest to `p` (Ericson, Real-Time Collision Detection, 5.1.5).
pub fn closest_point(p: DVec3, t: &[DVec3; 3]) -> DVec3 {
    let [a, b, c] = *t;
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = va + vb + vc;
    if denom.abs().is_nan() || denom == 0.0 {
        // Degenerate (collinear) triangle: the closest of its edges.
        let edges = [(a, b), (b, c), (c, a)];
        return edges
            .iter()
            .map(|&(u, v)| {
                let d = v - u;
                let l = d.length_squared();
                let s = if l > 0.0 {
                    ((p - u).dot(d) / l).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                u + s * d
            })
            .min_by(|x, y| {
                (*x - p)
                    .length_squared()
                    .total_cmp(&(*y - p).length_squared())
            })
            .unwrap_or(a);
    }
    let v = vb / denom;
    let w = vc / denom;
    a + ab * v + ac * w
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
    fn closest_point_by_region() {
        let t = [DVec3::ZERO, DVec3::X, DVec3::Y];
        let d = |p: DVec3| (closest_point(p, &t) - p).length();
        assert!((d(DVec3::new(0.2, 0.2, 3.0)) - 3.0).abs() < 1e-15);
        assert!((d(DVec3::new(-1.0, -1.0, 0.0)) - 2f64.sqrt()).abs() < 1e-15);
        assert!((d(DVec3::new(1.0, 1.0, 0.0)) - 0.5f64.sqrt()).abs() < 1e-15);
        assert!((d(DVec3::new(0.5, -2.0, 0.0)) - 2.0).abs() < 1e-15);
    }

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
