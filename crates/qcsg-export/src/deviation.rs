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
//! - Where the points are too sparse for that (the sampler gives up small rectangles unproven,
//!   which happens along the many cell walls of imported meshes and polygons), the solid itself
//!   supplies surface points ([`SurfaceProbe`]): the point where the line through `m` along a
//!   nearby quadric's gradient meets that quadric, kept where the solid's membership changes
//!   across it within a small step `h`. Some surface point then lies within `h` of it, so its
//!   distance plus `h` bounds `d(m, surface)` as soundly as a sample does.

use kiddo::{ImmutableKdTree, SquaredEuclidean};
use qcsg_csg::{Aabb, BoxIndex, Dnf};
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
    /// Triangles, of those farther than the tolerance from the surface, that have the mesh's
    /// inside on both sides (at most the first thousand such triangles are looked at).
    pub interior_triangles: usize,
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
    measure(mesh, points, None, coverage, tolerance, spacing)
}

/// [`measure_deviation`], with surface points found from `dnf` itself where `points` are too
/// sparse to bound the mesh's distance to the surface within `tolerance`.
pub fn measure_deviation_of_solid(
    dnf: &Dnf,
    mesh: &TriangleMesh,
    points: &[DVec3],
    coverage: f64,
    tolerance: f64,
    spacing: f64,
) -> Deviation {
    let probe = SurfaceProbe::new(dnf, tolerance * 1e-4);
    measure(mesh, points, Some(&probe), coverage, tolerance, spacing)
}

fn measure(
    mesh: &TriangleMesh,
    points: &[DVec3],
    probe: Option<&SurfaceProbe>,
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
        interior_triangles: 0,
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
    // The distance to the nearest point, and where that is farther than `enough`, to the
    // nearest surface point the probe finds if that is nearer.
    let nearest = |p: DVec3, enough: f64| {
        let sampled = kd
            .query(&p.to_array())
            .nearest_one::<SquaredEuclidean<f64>>()
            .execute()
            .distance
            .sqrt();
        match probe {
            Some(probe) if sampled > enough => sampled.min(probe.distance_bound(p, sampled)),
            _ => sampled,
        }
    };
    let bounds: Vec<(f64, usize)> = mesh
        .triangles
        .par_iter()
        .map(|t| triangle_bound(mesh.corners(t), &nearest, tolerance, spacing, 0))
        .collect();
    result.mesh_to_surface = bounds.iter().map(|b| b.0).fold(0.0, f64::max);
    result.mesh_points = bounds.iter().map(|b| b.1).sum();
    let far: Vec<usize> = (0..bounds.len())
        .filter(|&i| bounds[i].0 > tolerance)
        .take(MAX_WALL_CHECKS)
        .collect();
    result.interior_triangles = far
        .par_iter()
        .filter(|&&i| is_interior(mesh, mesh.corners(&mesh.triangles[i])))
        .count();
    result
}

/// The most of the triangles farther than the tolerance that are checked for being walls inside
/// the mesh (each check visits every triangle).
const MAX_WALL_CHECKS: usize = 1000;

/// Whether the mesh is inside on both sides of the triangle: a wall between two touching
/// pieces that the booleans left in, which no refinement removes.
fn is_interior(mesh: &TriangleMesh, [a, b, c]: [DVec3; 3]) -> bool {
    let normal = (b - a).cross(c - a);
    let size = (b - a).length().max((c - a).length());
    let Some(normal) = normal.try_normalize() else {
        return false;
    };
    let centroid = (a + b + c) / 3.0;
    let step = 1e-3 * size;
    winding_number(mesh, centroid + step * normal) > 0.5
        && winding_number(mesh, centroid - step * normal) > 0.5
}

/// The mesh's generalized winding number at `p` (Van Oosterom and Strackee's solid angles).
fn winding_number(mesh: &TriangleMesh, p: DVec3) -> f64 {
    let total: f64 = mesh
        .triangles
        .iter()
        .map(|t| {
            let [a, b, c] = mesh.corners(t).map(|v| v - p);
            let (la, lb, lc) = (a.length(), b.length(), c.length());
            let numerator = a.dot(b.cross(c));
            let denominator = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
            2.0 * numerator.atan2(denominator)
        })
        .sum();
    total / (4.0 * std::f64::consts::PI)
}

/// The most levels a triangle is split: 4²⁰ pieces of a triangle is far past any useful count.
const MAX_DEPTH: u32 = 20;

/// An upper bound on `nearest` over the triangle, and how many points it took. `nearest(p,
/// enough)` may stop looking once it has a distance within `enough`.
fn triangle_bound(
    t: [DVec3; 3],
    nearest: &(dyn Fn(DVec3, f64) -> f64 + Sync),
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
    // A triangle too large for any distance to pass is split anyway: no need to look further.
    let enough = if reach <= tolerance {
        tolerance - reach
    } else {
        f64::INFINITY
    };
    let bound = nearest(centroid, enough) + reach;
    if bound <= tolerance || reach <= spacing || depth >= MAX_DEPTH || !bound.is_finite() {
        return (bound, 1);
    }
    let (ab, bc, ca) = ((a + b) / 2.0, (b + c) / 2.0, (c + a) / 2.0);
    [[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]
        .into_iter()
        .map(|piece| triangle_bound(piece, nearest, tolerance, spacing, depth + 1))
        .fold((0.0, 0), |acc, x| (acc.0.max(x.0), acc.1 + x.1))
}

/// Surface points of a solid found from a point near it (see the module page).
pub(crate) struct SurfaceProbe<'a> {
    dnf: &'a Dnf,
    terms: BoxIndex,
    /// The step across a candidate point at which the solid's membership must change.
    step: f64,
}

impl<'a> SurfaceProbe<'a> {
    pub(crate) fn new(dnf: &'a Dnf, step: f64) -> Self {
        let terms = BoxIndex::new(dnf.terms.iter().map(|t| t.bounds).collect());
        Self { dnf, terms, step }
    }

    /// An upper bound on the distance from `m` to the surface, if one below `within` is found;
    /// `within` otherwise.
    pub(crate) fn distance_bound(&self, m: DVec3, within: f64) -> f64 {
        let mut quadrics: Vec<u32> = self
            .terms
            .near(&Aabb::new(m, m), within)
            .into_iter()
            .flat_map(|t| self.dnf.terms[t as usize].literals.iter().copied())
            .collect();
        quadrics.sort_unstable();
        quadrics.dedup();
        let mut best = within;
        for id in quadrics {
            let quadric = &self.dnf.quadrics[id as usize].quadric;
            for p in gradient_line_points(quadric, m, within) {
                let distance = (p - m).length() + self.step;
                if distance < best && self.crosses_surface(quadric, p) {
                    best = distance;
                }
            }
        }
        best
    }

    /// Whether the solid is on one side of `p` and not the other, `step` along the quadric's
    /// normal there.
    fn crosses_surface(&self, quadric: &qcsg_quadric::Quadric, p: DVec3) -> bool {
        quadric
            .normal(p)
            .is_some_and(|n| self.contains(p + self.step * n) != self.contains(p - self.step * n))
    }

    /// [`Dnf::contains`], over the terms whose boxes hold `p` only.
    fn contains(&self, p: DVec3) -> bool {
        if self.dnf.region.is_some_and(|r| !r.contains(p)) {
            return false;
        }
        self.terms.near(&Aabb::new(p, p), 0.0).into_iter().any(|t| {
            self.dnf.terms[t as usize]
                .literals
                .iter()
                .all(|&q| self.dnf.quadrics[q as usize].quadric.value(p) <= 0.0)
        })
    }
}

/// The points where the line through `m` along the quadric's gradient meets the quadric, within
/// `within` of `m`. Along a line a quadric is a quadratic in the parameter, fitted here from
/// three values (exact up to rounding, which the caller's membership test makes harmless).
fn gradient_line_points(quadric: &qcsg_quadric::Quadric, m: DVec3, within: f64) -> Vec<DVec3> {
    let Some(u) = quadric.normal(m) else {
        return Vec::new();
    };
    if !(within.is_finite() && within > 0.0) {
        return Vec::new();
    }
    let h = within;
    let (f0, f_plus, f_minus) = (
        quadric.value(m),
        quadric.value(m + h * u),
        quadric.value(m - h * u),
    );
    let a = (f_plus + f_minus - 2.0 * f0) / (2.0 * h * h);
    let b = (f_plus - f_minus) / (2.0 * h);
    let roots: Vec<f64> = if a.abs() * h <= 1e-12 * b.abs() {
        vec![-f0 / b]
    } else {
        let discriminant = b * b - 4.0 * a * f0;
        if discriminant < 0.0 {
            Vec::new()
        } else {
            // The numerically stable pair of roots.
            let q = -0.5 * (b + b.signum() * discriminant.sqrt());
            vec![q / a, f0 / q]
        }
    };
    roots
        .into_iter()
        .filter(|t| t.is_finite() && t.abs() <= within)
        .map(|t| m + t * u)
        .collect()
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
