//! Whether a triangle mesh bounds a solid: every edge used by exactly two triangles in opposite
//! directions (watertight, 2-manifold at edges, consistently oriented), no triangle of zero
//! area, and a positive volume (oriented outwards).

use std::collections::HashMap;

use qcsg_quadric::DVec3;

use crate::TriangleMesh;

/// What [`topology`] found.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Topology {
    /// Directed edges that no triangle uses the other way (holes, flipped neighbours).
    pub unpaired_edges: usize,
    /// Directed edges used by more than one triangle (non-manifold edges, or a fold).
    pub repeated_edges: usize,
    /// Triangles whose corners are collinear or repeated (zero area in f64).
    pub degenerate_triangles: usize,
    /// Triangles that name a vertex that does not exist.
    pub bad_indices: usize,
    /// The signed volume (positive when the triangles face outwards).
    pub volume: f64,
    /// Connected shells (by shared edges).
    pub shells: usize,
    /// Vertices minus edges plus faces over the whole mesh (2 per sphere-like shell).
    pub euler_characteristic: i64,
}

impl Topology {
    /// Watertight, 2-manifold at every edge, consistently and outwards oriented, without
    /// degenerate triangles (an empty mesh passes).
    pub fn is_closed_solid(&self) -> bool {
        self.unpaired_edges == 0
            && self.repeated_edges == 0
            && self.degenerate_triangles == 0
            && self.bad_indices == 0
            && (self.shells == 0 || self.volume > 0.0)
    }
}

/// Checks the mesh.
pub fn topology(mesh: &TriangleMesh) -> Topology {
    let mut result = Topology::default();
    let n = mesh.vertices.len() as u32;
    let mut directed: HashMap<(u32, u32), u32> = HashMap::new();
    let mut good = Vec::with_capacity(mesh.triangles.len());
    // Volumes about a point near the mesh: about the world origin, a part 10⁶ away would lose
    // its volume to rounding.
    let reference =
        mesh.vertices.iter().fold(DVec3::ZERO, |s, v| s + *v) / (mesh.vertices.len().max(1) as f64);
    for t in &mesh.triangles {
        if t.iter().any(|&i| i >= n) {
            result.bad_indices += 1;
            continue;
        }
        let [a, b, c] = mesh.corners(t);
        if t[0] == t[1] || t[1] == t[2] || t[2] == t[0] || (b - a).cross(c - a).length() == 0.0 {
            result.degenerate_triangles += 1;
        }
        let (a, b, c) = (a - reference, b - reference, c - reference);
        result.volume += a.dot(b.cross(c)) / 6.0;
        for k in 0..3 {
            *directed.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
        }
        good.push(*t);
    }
    for (&(a, b), &count) in &directed {
        if count > 1 {
            result.repeated_edges += 1;
        }
        if !directed.contains_key(&(b, a)) {
            result.unpaired_edges += 1;
        }
    }
    // Shells: union-find over vertices joined by triangles.
    let mut parent: Vec<u32> = (0..n).collect();
    fn find(parent: &mut [u32], mut x: u32) -> u32 {
        while parent[x as usize] != x {
            parent[x as usize] = parent[parent[x as usize] as usize];
            x = parent[x as usize];
        }
        x
    }
    let mut used = vec![false; n as usize];
    for t in &good {
        for k in 0..3 {
            used[t[k] as usize] = true;
            let (x, y) = (find(&mut parent, t[k]), find(&mut parent, t[(k + 1) % 3]));
            if x != y {
                parent[x as usize] = y;
            }
        }
    }
    let mut roots = std::collections::HashSet::new();
    for v in 0..n {
        if used[v as usize] {
            roots.insert(find(&mut parent, v));
        }
    }
    result.shells = roots.len();
    let undirected = directed
        .keys()
        .map(|&(a, b)| (a.min(b), a.max(b)))
        .collect::<std::collections::HashSet<_>>()
        .len();
    let vertices = used.iter().filter(|u| **u).count();
    result.euler_characteristic = vertices as i64 - undirected as i64 + good.len() as i64;
    result
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tetrahedron() -> TriangleMesh {
        TriangleMesh {
            vertices: vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z],
            triangles: vec![[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]],
        }
    }

    #[test]
    fn tetrahedron_is_a_closed_solid() {
        let t = topology(&tetrahedron());
        assert!(t.is_closed_solid(), "{t:?}");
        assert!((t.volume - 1.0 / 6.0).abs() < 1e-15);
        assert_eq!((t.shells, t.euler_characteristic), (1, 2));
    }

    #[test]
    fn holes_flips_and_inside_out_are_found() {
        let mut open = tetrahedron();
        open.triangles.pop();
        assert_eq!(topology(&open).unpaired_edges, 3);
        let mut flipped = tetrahedron();
        flipped.triangles[0].swap(1, 2);
        let t = topology(&flipped);
        assert!(t.repeated_edges > 0 && !t.is_closed_solid());
        let mut inside_out = tetrahedron();
        for t in &mut inside_out.triangles {
            t.swap(1, 2);
        }
        let t = topology(&inside_out);
        assert!(t.volume < 0.0 && !t.is_closed_solid());
    }
}
