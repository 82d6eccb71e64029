//! Triangle meshes from a mesh-based peer (OpenSCAD's STL export) and their distance to the
//! exact surface.
//!
//! The Hausdorff distance between a mesh and the exact CSG surface is measured in both
//! directions: from every exact reference point to the mesh (exact point-triangle distances,
//! triangles found through a uniform grid), and from points spread over every triangle (its
//! vertices, edge midpoints and centroid, subdivided until no more than `spacing` apart) to the
//! exact surface (projected onto the quadrics and kept where the projection is on the CSG
//! surface; else bisected along the quadric to the feature curve between the projection and
//! the quadric's nearest reference point, then moved along that feature curve to its point
//! nearest the mesh point ([`crease`](crate::crease)); or the nearest reference point). Both directions
//! are upper bounds on the true directed distances up to the density of the points used, which
//! the report states.

use std::collections::HashMap;

use kiddo::{ImmutableKdTree, SquaredEuclidean};
use qcsg_csg::Dnf;
use qcsg_mesh::closest_point_on_triangle;
use qcsg_quadric::DVec3;

use crate::crease;
use crate::reference::{SurfacePoint, on_csg_surface, project, side_step};

/// A triangle soup.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    /// Triangles as three corners.
    pub triangles: Vec<[DVec3; 3]>,
}

/// Parses an STL file, ASCII or binary.
pub fn parse_stl(bytes: &[u8]) -> Result<Mesh, String> {
    let ascii = bytes.starts_with(b"solid")
        && std::str::from_utf8(&bytes[..bytes.len().min(512)]).is_ok_and(|s| s.contains("facet"));
    if ascii || (bytes.starts_with(b"solid") && bytes.len() < 84) {
        let text = std::str::from_utf8(bytes).map_err(|e| format!("STL is not text: {e}"))?;
        let mut triangles = Vec::new();
        let mut corners = Vec::with_capacity(3);
        for line in text.lines() {
            let mut words = line.split_whitespace();
            if words.next() != Some("vertex") {
                continue;
            }
            let v: Vec<f64> = words.filter_map(|w| w.parse().ok()).collect();
            if v.len() != 3 {
                return Err(format!("bad STL vertex line `{line}`"));
            }
            corners.push(DVec3::new(v[0], v[1], v[2]));
            if corners.len() == 3 {
                triangles.push([corners[0], corners[1], corners[2]]);
                corners.clear();
            }
        }
        return Ok(Mesh { triangles });
    }
    if bytes.len() < 84 {
        return Err("STL too short".into());
    }
    let count = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
    if bytes.len() < 84 + 50 * count {
        return Err("binary STL shorter than its triangle count".into());
    }
    let float = |at: usize| {
        f64::from(f32::from_le_bytes([
            bytes[at],
            bytes[at + 1],
            bytes[at + 2],
            bytes[at + 3],
        ]))
    };
    let triangles = (0..count)
        .map(|i| {
            let base = 84 + 50 * i + 12;
            let corner = |k: usize| {
                let at = base + 12 * k;
                DVec3::new(float(at), float(at + 4), float(at + 8))
            };
            [corner(0), corner(1), corner(2)]
        })
        .collect();
    Ok(Mesh { triangles })
}

/// Triangles bucketed in a uniform grid, for nearest-triangle queries.
struct TriangleGrid<'a> {
    mesh: &'a Mesh,
    origin: DVec3,
    cell: f64,
    cells: HashMap<(i64, i64, i64), Vec<u32>>,
}

impl<'a> TriangleGrid<'a> {
    fn new(mesh: &'a Mesh, cell: f64) -> Self {
        let origin = mesh
            .triangles
            .iter()
            .flatten()
            .fold(DVec3::splat(f64::INFINITY), |m, &v| m.min(v));
        let mut cells: HashMap<(i64, i64, i64), Vec<u32>> = HashMap::new();
        for (i, t) in mesh.triangles.iter().enumerate() {
            let lo = t[0].min(t[1]).min(t[2]);
            let hi = t[0].max(t[1]).max(t[2]);
            let (a, b) = (
                Self::key_of(origin, cell, lo),
                Self::key_of(origin, cell, hi),
            );
            for x in a.0..=b.0 {
                for y in a.1..=b.1 {
                    for z in a.2..=b.2 {
                        cells.entry((x, y, z)).or_default().push(i as u32);
                    }
                }
            }
        }
        Self {
            mesh,
            origin,
            cell,
            cells,
        }
    }

    fn key_of(origin: DVec3, cell: f64, p: DVec3) -> (i64, i64, i64) {
        let k = ((p - origin) / cell).floor();
        (k.x as i64, k.y as i64, k.z as i64)
    }

    /// The distance from `p` to the nearest triangle: rings of cells around `p` until the
    /// best distance found is within the searched ring.
    fn nearest(&self, p: DVec3, max_ring: i64) -> f64 {
        let centre = Self::key_of(self.origin, self.cell, p);
        let mut best = f64::INFINITY;
        for ring in 0..=max_ring {
            for x in -ring..=ring {
                for y in -ring..=ring {
                    for z in -ring..=ring {
                        if x.abs().max(y.abs()).max(z.abs()) != ring {
                            continue;
                        }
                        let key = (centre.0 + x, centre.1 + y, centre.2 + z);
                        if let Some(list) = self.cells.get(&key) {
                            for &i in list {
                                let triangle = &self.mesh.triangles[i as usize];
                                best = best.min(closest_point_on_triangle(p, triangle).distance(p));
                            }
                        }
                    }
                }
            }
            if best <= ring as f64 * self.cell {
                break;
            }
        }
        best
    }
}

/// The Hausdorff distance between a mesh and the exact surface, both directions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshDistance {
    /// Largest distance from an exact reference point to the mesh.
    pub surface_to_mesh: f64,
    /// Largest distance from a point of the mesh to the exact surface.
    pub mesh_to_surface: f64,
    /// Mesh points measured.
    pub mesh_points: usize,
}

impl MeshDistance {
    /// The larger of the two directions.
    pub fn hausdorff(&self) -> f64 {
        self.surface_to_mesh.max(self.mesh_to_surface)
    }
}

/// Points spread over a triangle, no more than `spacing` apart (at most 64 per edge).
fn triangle_points(t: &[DVec3; 3], spacing: f64, out: &mut Vec<DVec3>) {
    let longest = (t[1] - t[0])
        .length()
        .max((t[2] - t[1]).length())
        .max((t[0] - t[2]).length());
    let n = ((longest / spacing).ceil() as usize).clamp(1, 64);
    for i in 0..=n {
        for j in 0..=(n - i) {
            let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
            out.push(t[0] + u * (t[1] - t[0]) + v * (t[2] - t[0]));
        }
    }
}

/// The reference points of each quadric in a k-d tree (with the points themselves).
struct RefsByQuadric {
    trees: Vec<Option<(ImmutableKdTree<f64, 3>, Vec<DVec3>)>>,
}

impl RefsByQuadric {
    fn new(dnf: &Dnf, refs: &[SurfacePoint]) -> Self {
        let mut lists: Vec<Vec<DVec3>> = vec![Vec::new(); dnf.quadrics.len()];
        for r in refs {
            if let Some(list) = lists.get_mut(r.quadric as usize) {
                list.push(r.position);
            }
        }
        let trees = lists
            .into_iter()
            .map(|list| {
                let array: Vec<[f64; 3]> = list.iter().map(|p| p.to_array()).collect();
                ImmutableKdTree::new_from_slice(&array)
                    .ok()
                    .map(|tree| (tree, list))
            })
            .collect();
        Self { trees }
    }

    /// The reference point of quadric `q` nearest to `p`.
    fn nearest(&self, q: usize, p: DVec3) -> Option<DVec3> {
        let (tree, points) = self.trees.get(q)?.as_ref()?;
        let found = tree
            .query(&p.to_array())
            .nearest_one::<SquaredEuclidean<f64>>()
            .execute();
        points.get(found.item as usize).copied()
    }
}

/// The distance from `p` to the exact CSG surface (an upper bound): over every quadric, the
/// foot of the normal through `p` when the solid changes across it; otherwise the feature
/// curve found by bisection along the quadric between that foot and the quadric's nearest
/// reference point; and the nearest reference point of all.
fn distance_to_surface(
    dnf: &Dnf,
    p: DVec3,
    refs: &ImmutableKdTree<f64, 3>,
    by_quadric: &RefsByQuadric,
    eps: f64,
) -> f64 {
    let mut best = refs
        .query(&p.to_array())
        .nearest_one::<SquaredEuclidean<f64>>()
        .execute()
        .distance
        .sqrt();
    for (index, entry) in dnf.quadrics.iter().enumerate() {
        let q = &entry.quadric;
        let Some(n) = q.normal(p) else { continue };
        for t in q.intersect_line(p, n).roots() {
            if t.abs() >= best {
                continue;
            }
            let x = p + t * n;
            match on_csg_surface(dnf, q, x, eps) {
                Some(true) => best = t.abs(),
                Some(false) => {
                    // Off the CSG surface: walk along the quadric towards a reference point of
                    // it, keeping the last point on the surface.
                    let Some(target) = by_quadric.nearest(index, x) else {
                        continue;
                    };
                    let (mut on, mut off) = (target, x);
                    for _ in 0..40 {
                        let Some(m) = project(q, 0.5 * (on + off)) else {
                            break;
                        };
                        match on_csg_surface(dnf, q, m, eps) {
                            Some(true) => on = m,
                            Some(false) => off = m,
                            None => break,
                        }
                    }
                    best = best.min((p - on).length());
                    // The walk crosses the crease where it happens to, often obliquely: the
                    // crease's point nearest to `p`, where the solid is seen to change.
                    if let Some(other) = crease::other_quadric(dnf, index, on) {
                        let q2 = &dnf.quadrics[other].quadric;
                        let delta = 1e3 * eps;
                        if let Some(y) = crease::nearest_on_curve(q, q2, on, p)
                            && crease::surface_within(dnf, q, q2, y, delta)
                        {
                            best = best.min((p - y).length() + delta);
                        }
                    }
                }
                None => {}
            }
        }
    }
    best
}

/// Measures the Hausdorff distance between `mesh` and the exact surface of `dnf`, with mesh
/// points at most `spacing` apart and the given exact reference points.
pub fn mesh_distance(dnf: &Dnf, mesh: &Mesh, refs: &[SurfacePoint], spacing: f64) -> MeshDistance {
    let mut result = MeshDistance {
        surface_to_mesh: f64::INFINITY,
        mesh_to_surface: f64::INFINITY,
        mesh_points: 0,
    };
    if mesh.triangles.is_empty() || refs.is_empty() {
        return result;
    }
    let diag = (dnf.bounds.max - dnf.bounds.min).length();
    let grid = TriangleGrid::new(mesh, diag / 48.0);
    result.surface_to_mesh = refs
        .iter()
        .map(|r| grid.nearest(r.position, 96))
        .fold(0.0, f64::max);
    let ref_array: Vec<[f64; 3]> = refs.iter().map(|r| r.position.to_array()).collect();
    let Ok(tree) = ImmutableKdTree::new_from_slice(&ref_array) else {
        return result;
    };
    let eps = side_step(dnf);
    let by_quadric = RefsByQuadric::new(dnf, refs);
    let mut points = Vec::new();
    for t in &mesh.triangles {
        triangle_points(t, spacing, &mut points);
    }
    result.mesh_points = points.len();
    use rayon::prelude::*;
    result.mesh_to_surface = points
        .par_iter()
        .map(|&p| distance_to_surface(dnf, p, &tree, &by_quadric, eps))
        .reduce(|| 0.0, f64::max);
    result
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ascii_stl_parses() {
        let text = b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid x\n";
        let mesh = parse_stl(text).expect("parses");
        assert_eq!(mesh.triangles.len(), 1);
        assert_eq!(mesh.triangles[0][1], DVec3::X);
    }
}
