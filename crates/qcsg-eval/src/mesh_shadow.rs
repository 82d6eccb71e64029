//! The shadow of a closed triangle mesh on the plane z = 0, exactly, as a union of convex
//! polygons whose edges join projected mesh points.
//!
//! A vertical line meets the solid a closed mesh bounds exactly when it crosses one of the
//! mesh's faces (outside the mesh's box the winding number is zero, and crossing a face changes
//! it). Seen from below, the crossings alternate between faces turned up and faces turned down,
//! so the faces that turn up (counter-clockwise once projected, for the orientation the mesh
//! has after its transform; a mirror turns them all, which changes nothing) cover the shadow
//! already: the shadow is the union of their projections, each a triangle, the intersection of
//! three half-planes. A face seen edge-on projects to a segment, which lies in the closure of
//! its neighbours' projections, and adds nothing. This needs triangles that tile each face
//! without overlap ([`MeshFaces`]): the fan a non-convex face is cut into for the cells folds
//! over itself, and its folded triangles cancel by parity there but not in a union.
//!
//! Fewer, larger pieces make the shadow cheaper downstream: two turned-up triangles sharing a
//! mesh edge project to opposite sides of it, so their projections meet along it only, and when
//! both corners where they meet stay convex the union is one convex polygon. [`shadow_polygons`]
//! grows such polygons greedily across shared edges. Orientations are decided with Shewchuk's
//! error bound on the f64 determinant: a corner is merged only when certainly convex, and a
//! face is dropped only when it certainly turns down (any face's projection lies in the shadow,
//! so keeping a doubtful one is safe).

use std::collections::HashMap;

use glam::{DMat4, DVec2, DVec3, DVec4};
use qcsg_mesh::Mesh;

/// A mesh's faces as triangles that tile each face with its orientation. A face whose fan from
/// its first point (as [`qcsg_mesh::polyhedron_cells`] splits it) turns one way throughout is
/// that fan, so the triangles bound the solid the cells fill even where a face is not planar. A
/// planar face whose fan folds over (a non-convex face: its overlapping triangles cancel by
/// parity in the cells) is cut into ears instead; a face that is both is marked, and the mesh's
/// shadow is then refused.
#[derive(Clone, Debug, Default)]
pub struct MeshFaces {
    points: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
    /// Whether the triangles are exactly the faces' (false: a folded non-planar face).
    exact: bool,
}

/// The most corners of a folded face cut into ears (the cutting is quadratic).
const MAX_EAR_CORNERS: usize = 4096;

/// How far from its plane, relative to its size, a folded face's corner may be for the face to
/// count as planar (rounding of coordinates written in decimal).
const PLANAR_TOLERANCE: f64 = 1e-9;

impl MeshFaces {
    /// The triangles of `mesh` (faces with fewer than three points and entries naming no point
    /// are skipped: a mesh that reached here has been validated).
    pub fn of(mesh: &Mesh) -> Self {
        let n = mesh.points.len();
        let mut out = Self {
            points: mesh.points.clone(),
            triangles: Vec::new(),
            exact: n <= u32::MAX as usize,
        };
        if !out.exact {
            return out;
        }
        for face in &mesh.faces {
            if face.len() < 3 || face.iter().any(|&i| i >= n) {
                continue;
            }
            let face: Vec<u32> = face.iter().map(|&i| i as u32).collect();
            if !out.add_face(&face) {
                out.exact = false;
            }
        }
        out
    }

    /// Adds the triangles of `face`; false when it folds and is not planar (or too large).
    fn add_face(&mut self, face: &[u32]) -> bool {
        let p = |i: u32| self.points[i as usize];
        // Newell's normal; the face is seen along its largest axis, counter-clockwise when
        // that component is positive.
        let normal = (0..face.len()).fold(DVec3::ZERO, |acc, k| {
            acc + p(face[k]).cross(p(face[(k + 1) % face.len()]))
        });
        let axis = normal.abs().max_position();
        let flat = |i: u32| {
            let q = p(i);
            match axis {
                0 => DVec2::new(q.y, q.z),
                1 => DVec2::new(q.z, q.x),
                _ => DVec2::new(q.x, q.y),
            }
        };
        let up = normal[axis] >= 0.0;
        let folds = (1..face.len() - 1).any(|k| {
            let (a, b, c) = (flat(face[0]), flat(face[k]), flat(face[k + 1]));
            match turn(a, b, c) {
                Some(left) => left != up,
                None => det(a, b, c) != 0.0,
            }
        });
        if !folds {
            for k in 1..face.len() - 1 {
                self.triangles.push([face[0], face[k], face[k + 1]]);
            }
            return true;
        }
        // A folded face: planar, and not too large, to be cut into ears.
        let size = face
            .iter()
            .map(|&i| (p(i) - p(face[0])).length())
            .fold(0.0, f64::max);
        let unit = normal.normalize_or_zero();
        let planar = unit != DVec3::ZERO
            && face
                .iter()
                .all(|&i| unit.dot(p(i) - p(face[0])).abs() <= PLANAR_TOLERANCE * size);
        if !planar || face.len() > MAX_EAR_CORNERS {
            return false;
        }
        // Ears of the polygon made counter-clockwise, put back in the face's orientation.
        let mut ring: Vec<u32> = face.to_vec();
        if !up {
            ring.reverse();
        }
        while ring.len() > 3 {
            let m = ring.len();
            let ear = (0..m).find(|&k| {
                let (u, v, w) = (ring[(k + m - 1) % m], ring[k], ring[(k + 1) % m]);
                let (a, b, c) = (flat(u), flat(v), flat(w));
                turn(a, b, c) == Some(true)
                    && ring.iter().all(|&r| {
                        r == u
                            || r == v
                            || r == w
                            || turn(a, b, flat(r)) == Some(false)
                            || turn(b, c, flat(r)) == Some(false)
                            || turn(c, a, flat(r)) == Some(false)
                    })
            });
            let Some(k) = ear else {
                return false;
            };
            let (u, v, w) = (ring[(k + m - 1) % m], ring[k], ring[(k + 1) % m]);
            self.triangles.push(if up { [u, v, w] } else { [u, w, v] });
            ring.remove(k);
        }
        let [u, v, w] = [ring[0], ring[1], ring[2]];
        self.triangles.push(if up { [u, v, w] } else { [u, w, v] });
        true
    }

    /// How many triangles the faces make.
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }
}

/// Shewchuk's bound on the error of the f64 orientation determinant, relative to its terms.
const ORIENT_ERROR: f64 = (3.0 + 16.0 * f64::EPSILON / 2.0) * f64::EPSILON / 2.0;

/// The sign of the turn a → b → c: `Some(true)` certainly left (counter-clockwise),
/// `Some(false)` certainly right, `None` when the f64 determinant cannot tell (or it is zero).
fn turn(a: DVec2, b: DVec2, c: DVec2) -> Option<bool> {
    let left = (a.x - c.x) * (b.y - c.y);
    let right = (a.y - c.y) * (b.x - c.x);
    let det = left - right;
    let bound = ORIENT_ERROR * (left.abs() + right.abs());
    if det > bound {
        Some(true)
    } else if -det > bound {
        Some(false)
    } else {
        None
    }
}

/// The determinant of a → b → c, for a doubtful triangle's orientation.
fn det(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    (a.x - c.x) * (b.y - c.y) - (a.y - c.y) * (b.x - c.x)
}

/// One convex polygon being grown: its corners counter-clockwise, as point indices.
struct Piece {
    corners: Vec<u32>,
    alive: bool,
}

/// The shadow on z = 0 of the solid `faces` bound, seen through the affine `world`: convex
/// polygons, corners counter-clockwise, whose union is the shadow. `None` when `world` is not
/// affine (a projective row bends the picture), a projected point is not finite, or a face
/// folds and is not planar.
pub fn shadow_polygons(faces: &MeshFaces, world: &DMat4) -> Option<Vec<Vec<DVec2>>> {
    if !faces.exact || world.row(3) != DVec4::new(0.0, 0.0, 0.0, 1.0) {
        return None;
    }
    let flat: Vec<DVec2> = faces
        .points
        .iter()
        .map(|p| world.transform_point3(*p).truncate())
        .collect();
    if flat.iter().any(|p| !p.is_finite()) {
        return None;
    }
    let at = |i: u32| flat[i as usize];
    // The faces turned up (or doubtful), each a counter-clockwise triangle.
    let mut pieces: Vec<Piece> = Vec::new();
    for &[a, b, c] in &faces.triangles {
        let corners = match turn(at(a), at(b), at(c)) {
            Some(true) => vec![a, b, c],
            Some(false) => continue,
            None => match det(at(a), at(b), at(c)) {
                d if d > 0.0 => vec![a, b, c],
                d if d < 0.0 => vec![a, c, b],
                _ => continue,
            },
        };
        pieces.push(Piece {
            corners,
            alive: true,
        });
    }
    // Each directed edge of a piece → the piece (pieces from turned-up faces only; doubtful
    // ones may share a direction with a neighbour, and then are not merged).
    let mut owner: HashMap<(u32, u32), usize> = HashMap::new();
    let mut clash = Vec::new();
    for (p, piece) in pieces.iter().enumerate() {
        let c = &piece.corners;
        for k in 0..3 {
            let e = (c[k], c[(k + 1) % 3]);
            if owner.insert(e, p).is_some() {
                clash.push(e);
            }
        }
    }
    for e in clash {
        owner.remove(&e);
    }
    // Which piece each triangle now belongs to (a union–find over merges).
    let mut parent: Vec<usize> = (0..pieces.len()).collect();
    fn root(parent: &mut [usize], mut p: usize) -> usize {
        while parent[p] != p {
            parent[p] = parent[parent[p]];
            p = parent[p];
        }
        p
    }
    let edges: Vec<((u32, u32), usize)> = {
        let mut v: Vec<_> = owner.iter().map(|(&e, &p)| (e, p)).collect();
        // A fixed order, so the output does not depend on the hash map's.
        v.sort_unstable();
        v
    };
    for ((a, b), p) in edges {
        // The piece across a → b runs b → a.
        let Some(&q) = owner.get(&(b, a)) else {
            continue;
        };
        let (p, q) = (root(&mut parent, p), root(&mut parent, q));
        if p == q {
            continue;
        }
        if let Some(merged) = merge(&pieces[p].corners, &pieces[q].corners, a, b, &at) {
            pieces[p].corners = merged;
            pieces[q].alive = false;
            pieces[q].corners = Vec::new();
            parent[q] = p;
        }
    }
    Some(
        pieces
            .into_iter()
            .filter(|p| p.alive)
            .map(|p| p.corners.into_iter().map(at).collect())
            .collect(),
    )
}

/// The union of convex `p` (which runs a → b) and `q` (which runs b → a), when both corners
/// where they meet are certainly convex.
fn merge(p: &[u32], q: &[u32], a: u32, b: u32, at: &impl Fn(u32) -> DVec2) -> Option<Vec<u32>> {
    let (n, m) = (p.len(), q.len());
    let ia = (0..n).find(|&k| p[k] == a && p[(k + 1) % n] == b)?;
    let jb = (0..m).find(|&k| q[k] == b && q[(k + 1) % m] == a)?;
    // p from b round to a, then q from a round to b, each end once.
    let mut out = Vec::with_capacity(n + m - 2);
    for k in 0..n {
        out.push(p[(ia + 1 + k) % n]);
    }
    for k in 2..m {
        out.push(q[(jb + k) % m]);
    }
    let len = out.len();
    // The corners at a (index n − 1) and at b (index 0).
    for k in [n - 1, 0] {
        let prev = out[(k + len - 1) % len];
        let next = out[(k + 1) % len];
        if turn(at(prev), at(out[k]), at(next)) != Some(true) {
            return None;
        }
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube() -> Mesh {
        // OpenSCAD's cube([1, 1, 1]) as a polyhedron, faces clockwise from outside.
        let points = (0..8)
            .map(|i| DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, (i >> 2) as f64))
            .collect();
        let faces = vec![
            vec![0, 1, 3, 2],
            vec![4, 6, 7, 5],
            vec![0, 4, 5, 1],
            vec![2, 3, 7, 6],
            vec![0, 2, 6, 4],
            vec![1, 5, 7, 3],
        ];
        Mesh { points, faces }
    }

    #[test]
    fn a_cube_casts_one_square() {
        let faces = MeshFaces::of(&cube());
        let shadow = shadow_polygons(&faces, &DMat4::IDENTITY).unwrap();
        assert_eq!(shadow.len(), 1);
        assert_eq!(shadow[0].len(), 4);
    }

    #[test]
    fn a_projective_transform_is_refused() {
        let faces = MeshFaces::of(&cube());
        let mut m = DMat4::IDENTITY;
        m.x_axis.w = 0.5;
        assert!(shadow_polygons(&faces, &m).is_none());
    }
}
