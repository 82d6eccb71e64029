//! Triangles whose three corners are collinear in the written coordinates, removed without
//! changing the surface.
//!
//! Manifold's booleans can leave a triangle `(a, b, c)` whose corner `b` lies on the edge from
//! `c` to `a` (a pocket's rim meeting a face's edge), and moving the mesh back to world
//! coordinates can round a sliver onto a line. Such a triangle has no normal, so mesh checks
//! count it as degenerate. The neighbour across its longest edge, `(a, c, d)`, is then split at
//! `b` into `(a, b, d)` and `(b, c, d)`: these cover exactly the neighbour's area, their edges
//! `a→b` and `b→c` pair with the edges the degenerate triangle shared with its other two
//! neighbours, and the degenerate triangle is dropped, so the mesh stays closed, 2-manifold and
//! oriented, with the same vertices.

use std::collections::HashMap;

use qcsg_quadric::DVec3;

use crate::TriangleMesh;

/// Whether the corners are collinear (or coincide) in `vertices`, or after moving them by
/// `-centre`, as a checker that centres the mesh sees them.
fn collinear(corners: [DVec3; 3], centre: DVec3) -> bool {
    // `length` rather than a comparison with zero: a cross product whose square underflows has
    // no normal either, and checkers compute the area that way.
    let flat = |[a, b, c]: [DVec3; 3]| (b - a).cross(c - a).length() == 0.0;
    flat(corners) || flat(corners.map(|p| p - centre))
}

/// Removes the mesh's triangles with collinear corners where a neighbour can take them over
/// (see the module's documentation); returns how many were removed. A triangle with two corners
/// at one point, or whose neighbour's split would itself be flat, is left as it is.
pub fn remove_collinear(mesh: &mut TriangleMesh) -> usize {
    if mesh.triangles.is_empty() {
        return 0;
    }
    let (lo, hi) = mesh.vertices.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    let centre = (lo + hi) / 2.0;
    let mut removed = 0;
    // Each split can only make the two new triangles flat when `d` lies on the line too, which
    // is checked before splitting; a few rounds catch a chain of flat triangles along one line.
    for _ in 0..4 {
        let flat: Vec<usize> = (0..mesh.triangles.len())
            .filter(|&t| collinear(mesh.corners(&mesh.triangles[t]), centre))
            .collect();
        if flat.is_empty() {
            break;
        }
        let mut by_edge: HashMap<(u32, u32), usize> = HashMap::new();
        for (i, t) in mesh.triangles.iter().enumerate() {
            for k in 0..3 {
                by_edge.insert((t[k], t[(k + 1) % 3]), i);
            }
        }
        let mut dropped = vec![false; mesh.triangles.len()];
        let mut touched = vec![false; mesh.triangles.len()];
        let mut added = Vec::new();
        for t in flat {
            if touched[t] {
                continue;
            }
            let tri = mesh.triangles[t];
            let p = mesh.corners(&tri);
            // The corner opposite the longest edge lies between the other two.
            let lengths = [0, 1, 2].map(|k| (p[(k + 2) % 3] - p[(k + 1) % 3]).length_squared());
            let k = (0..3)
                .max_by(|&i, &j| lengths[i].total_cmp(&lengths[j]))
                .unwrap_or(0);
            let (b, c, a) = (tri[k], tri[(k + 1) % 3], tri[(k + 2) % 3]);
            let (pa, pb, pc) = (
                mesh.vertices[a as usize],
                mesh.vertices[b as usize],
                mesh.vertices[c as usize],
            );
            if pa == pb || pb == pc || pa == pc {
                continue;
            }
            let Some(&n) = by_edge.get(&(a, c)) else {
                continue;
            };
            if n == t || touched[n] {
                continue;
            }
            let nt = mesh.triangles[n];
            let Some(&d) = nt.iter().find(|&&v| v != a && v != c) else {
                continue;
            };
            let first = [a, b, d];
            let second = [b, c, d];
            if d == b
                || collinear(mesh.corners(&first), centre)
                || collinear(mesh.corners(&second), centre)
            {
                continue;
            }
            touched[t] = true;
            touched[n] = true;
            dropped[t] = true;
            dropped[n] = true;
            added.push(first);
            added.push(second);
            removed += 1;
        }
        if added.is_empty() {
            break;
        }
        let mut kept: Vec<[u32; 3]> = mesh
            .triangles
            .iter()
            .zip(&dropped)
            .filter(|(_, d)| !**d)
            .map(|(t, _)| *t)
            .collect();
        kept.extend(added);
        mesh.triangles = kept;
    }
    removed
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::topology;

    /// A tetrahedron whose face `(0, 2, 1)` is split by a vertex on its edge `0–1` seen from
    /// one side only: the other side holds the flat triangle `(0, 4, 1)`.
    fn tetrahedron_with_flat_triangle() -> TriangleMesh {
        let vertices = vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(0.0, 2.0, 0.0),
            DVec3::new(0.0, 0.0, 2.0),
            DVec3::new(1.0, 0.0, 0.0),
        ];
        // Faces of the tetrahedron (0, 1, 2, 3), outward: (0, 2, 1), (0, 1, 3), (0, 3, 2),
        // (1, 2, 3). The face (0, 1, 3) is split at 4 into (0, 4, 3) and (4, 1, 3); the face
        // (0, 2, 1) keeps its edge 1→0, which the flat triangle (0, 4, 1) closes.
        let triangles = vec![
            [0, 2, 1],
            [0, 4, 3],
            [4, 1, 3],
            [0, 3, 2],
            [1, 2, 3],
            [0, 1, 4],
        ];
        TriangleMesh {
            vertices,
            triangles,
        }
    }

    #[test]
    fn a_flat_triangle_is_taken_over_by_its_neighbour() {
        let mut mesh = tetrahedron_with_flat_triangle();
        let before = topology(&mesh);
        assert_eq!(
            (
                before.unpaired_edges,
                before.repeated_edges,
                before.degenerate_triangles
            ),
            (0, 0, 1),
            "{before:?}"
        );
        assert_eq!(remove_collinear(&mut mesh), 1);
        assert_eq!(mesh.triangles.len(), 6);
        let centre = DVec3::splat(1.0);
        assert!(
            mesh.triangles
                .iter()
                .all(|t| !collinear(mesh.corners(t), centre)),
            "{:?}",
            mesh.triangles
        );
        let after = topology(&mesh);
        assert!(after.is_closed_solid(), "{after:?}");
        // The same solid: its volume is the tetrahedron's, 8/6.
        let volume: f64 = mesh
            .triangles
            .iter()
            .map(|t| {
                let [a, b, c] = mesh.corners(t);
                a.dot(b.cross(c)) / 6.0
            })
            .sum();
        assert!((volume - 8.0 / 6.0).abs() < 1e-12, "{volume}");
    }

    #[test]
    fn a_mesh_without_flat_triangles_is_unchanged() {
        let mut mesh = tetrahedron_with_flat_triangle();
        remove_collinear(&mut mesh);
        let once = mesh.clone();
        assert_eq!(remove_collinear(&mut mesh), 0);
        assert_eq!(mesh, once);
    }
}
