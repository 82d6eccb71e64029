//! A closed, non-convex test mesh of a chosen size: a sphere whose radius undulates with
//! latitude and longitude (dents and bulges all over), triangulated on a latitude-longitude grid
//! with a fan at each pole, written as binary STL.
//!
//! It stands in for a scanned or exported part in the mesh-scaling benchmark: every face plane
//! differs, neighbouring faces fold both ways, and the triangle count is set exactly, so the
//! growth of a stage's time with the number of faces can be read off one run. It is generated
//! at run time rather than stored, so that no multi-megabyte file sits in the repository.

use std::f64::consts::PI;

/// The mean radius of the mesh.
pub const RADIUS: f64 = 10.0;

/// The grid of a mesh of about `triangles` triangles: `(slices, stacks)` with
/// `2 · slices · (stacks − 1)` triangles, slices about the square root of half the count.
pub fn grid(triangles: usize) -> (usize, usize) {
    let slices = ((triangles as f64 / 2.0).sqrt().round() as usize).max(3);
    let stacks = (triangles / (2 * slices) + 1).max(2);
    (slices, stacks)
}

/// The radius at polar angle `theta` and azimuth `phi`: between 0.8 and 1.2 times [`RADIUS`],
/// so that the surface is star-shaped (closed and simple) but far from convex.
fn radius(theta: f64, phi: f64) -> f64 {
    RADIUS * (1.0 + 0.15 * (5.0 * theta).sin() * (4.0 * phi).sin() + 0.05 * (13.0 * phi).sin())
}

/// The triangles of the mesh of about `triangles` faces (exactly `2 · slices · (stacks − 1)`,
/// see [`grid`]), each listed counter-clockwise seen from outside, as STL wants them. Points are
/// rounded to `f32` first, as an STL file stores them, so that the faces are exactly those a
/// reader of the file sees.
pub fn triangles(triangles: usize) -> Vec<[[f32; 3]; 3]> {
    let (slices, stacks) = grid(triangles);
    let point = |i: usize, j: usize| -> [f32; 3] {
        let theta = PI * i as f64 / stacks as f64;
        let phi = 2.0 * PI * (j % slices) as f64 / slices as f64;
        let r = radius(theta, phi);
        [
            (r * theta.sin() * phi.cos()) as f32,
            (r * theta.sin() * phi.sin()) as f32,
            (r * theta.cos()) as f32,
        ]
    };
    let top = [0.0, 0.0, radius(0.0, 0.0) as f32];
    let bottom = [0.0, 0.0, -radius(PI, 0.0) as f32];
    let mut out = Vec::with_capacity(2 * slices * (stacks - 1));
    for j in 0..slices {
        out.push([top, point(1, j), point(1, j + 1)]);
        for i in 1..stacks - 1 {
            let (a, b, c, d) = (
                point(i, j),
                point(i + 1, j),
                point(i + 1, j + 1),
                point(i, j + 1),
            );
            out.push([a, b, c]);
            out.push([a, c, d]);
        }
        out.push([point(stacks - 1, j), bottom, point(stacks - 1, j + 1)]);
    }
    out
}

/// The mesh as a binary STL file (normals left zero, as readers recompute them).
pub fn binary_stl(faces: &[[[f32; 3]; 3]]) -> Vec<u8> {
    let mut bytes = Vec::with_capacity(84 + 50 * faces.len());
    bytes.extend_from_slice(&[0; 80]);
    bytes.extend_from_slice(&(faces.len() as u32).to_le_bytes());
    for face in faces {
        bytes.extend_from_slice(&[0; 12]);
        for corner in face {
            for v in corner {
                bytes.extend_from_slice(&v.to_le_bytes());
            }
        }
        bytes.extend_from_slice(&[0; 2]);
    }
    bytes
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    #[test]
    fn sizes_are_exact_and_the_mesh_is_closed() {
        for n in [2_000, 5_000, 20_000] {
            let faces = triangles(n);
            let (slices, stacks) = grid(n);
            assert_eq!(faces.len(), 2 * slices * (stacks - 1));
            assert!(faces.len().abs_diff(n) <= n / 50, "{n}: {}", faces.len());
            // Every directed edge has its reverse exactly once: closed and consistently oriented.
            let key = |p: [f32; 3]| p.map(f32::to_bits);
            let mut edges: HashMap<_, i32> = HashMap::new();
            for f in &faces {
                for k in 0..3 {
                    *edges.entry((key(f[k]), key(f[(k + 1) % 3]))).or_default() += 1;
                }
            }
            for (&(a, b), &count) in &edges {
                assert_eq!(count, 1);
                assert_eq!(edges.get(&(b, a)), Some(&1));
            }
        }
    }

    #[test]
    fn stl_has_the_declared_size() {
        let faces = triangles(2_000);
        let bytes = binary_stl(&faces);
        assert_eq!(bytes.len(), 84 + 50 * faces.len());
        assert_eq!(
            u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize,
            faces.len()
        );
    }
}
