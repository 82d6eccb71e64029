//! A triangle mesh read from STL, and the membership and distance queries that make it an
//! oracle for a solid's meaning.

use glam::DVec3;
use qcsg_mesh::closest_point_on_triangle;

/// A triangle soup (as STL stores it) with its box.
#[derive(Clone, Debug)]
pub struct TriangleMesh {
    /// The triangles, counter-clockwise seen from outside.
    pub triangles: Vec<[DVec3; 3]>,
    /// The smallest corner of the box of every vertex.
    pub min: DVec3,
    /// The largest corner of that box.
    pub max: DVec3,
}

impl TriangleMesh {
    /// The mesh of these triangles (at least one).
    pub fn new(triangles: Vec<[DVec3; 3]>) -> Result<Self, String> {
        if triangles.is_empty() {
            return Err("no triangles".to_owned());
        }
        let vertices = triangles.iter().flatten();
        let min = vertices.clone().fold(DVec3::INFINITY, |m, v| m.min(*v));
        let max = vertices.fold(DVec3::NEG_INFINITY, |m, v| m.max(*v));
        Ok(Self {
            triangles,
            min,
            max,
        })
    }

    /// Reads an STL file, ASCII (what OpenSCAD 2021.01 writes) or binary.
    pub fn from_stl(bytes: &[u8]) -> Result<Self, String> {
        let is_ascii = bytes.trim_ascii_start().starts_with(b"solid")
            && std::str::from_utf8(bytes).is_ok_and(|t| t.contains("vertex"));
        if is_ascii {
            Self::from_ascii_stl(std::str::from_utf8(bytes).unwrap_or_default())
        } else {
            Self::from_binary_stl(bytes)
        }
    }

    fn from_ascii_stl(text: &str) -> Result<Self, String> {
        let mut vertices = Vec::new();
        for line in text.lines() {
            let Some(rest) = line.trim().strip_prefix("vertex") else {
                continue;
            };
            let coords: Vec<f64> = rest
                .split_whitespace()
                .map(|c| c.parse::<f64>().map_err(|e| format!("{c:?}: {e}")))
                .collect::<Result<_, _>>()?;
            let [x, y, z] = coords[..] else {
                return Err(format!("vertex line with {} coordinates", coords.len()));
            };
            vertices.push(DVec3::new(x, y, z));
        }
        if vertices.len() % 3 != 0 {
            return Err(format!("{} vertices: not a triangle mesh", vertices.len()));
        }
        Self::new(vertices.chunks(3).map(|t| [t[0], t[1], t[2]]).collect())
    }

    fn from_binary_stl(bytes: &[u8]) -> Result<Self, String> {
        let count = bytes
            .get(80..84)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize)
            .ok_or("shorter than a binary STL header")?;
        let body = &bytes[84..];
        if body.len() < count * 50 {
            return Err(format!("{count} triangles announced, fewer stored"));
        }
        let float = |b: &[u8]| f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]]));
        let point = |b: &[u8]| DVec3::new(float(&b[0..4]), float(&b[4..8]), float(&b[8..12]));
        Self::new(
            body.chunks_exact(50)
                .take(count)
                .map(|r| [point(&r[12..24]), point(&r[24..36]), point(&r[36..48])])
                .collect(),
        )
    }

    /// The generalised winding number around `p`: 1 inside a closed, outward-oriented mesh,
    /// 0 outside (the sum of the triangles' signed solid angles over 4π, after Van Oosterom and
    /// Strackee).
    pub fn winding_number(&self, p: DVec3) -> f64 {
        let mut total = 0.0;
        for [a, b, c] in &self.triangles {
            let (a, b, c) = (*a - p, *b - p, *c - p);
            let (la, lb, lc) = (a.length(), b.length(), c.length());
            let numerator = a.dot(b.cross(c));
            let denominator = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
            total += 2.0 * numerator.atan2(denominator);
        }
        total / (4.0 * std::f64::consts::PI)
    }

    /// Whether `p` is inside (winding number above one half).
    pub fn contains(&self, p: DVec3) -> bool {
        self.winding_number(p) > 0.5
    }

    /// Whether some triangle comes closer to `p` than `distance`.
    pub fn is_within(&self, p: DVec3, distance: f64) -> bool {
        let squared = distance * distance;
        self.triangles
            .iter()
            .any(|t| closest_point_on_triangle(p, t).distance_squared(p) < squared)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit cube's twelve triangles, outward-facing.
    fn cube() -> Vec<[DVec3; 3]> {
        let v = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
        let quads = [
            [v(0., 0., 0.), v(0., 1., 0.), v(1., 1., 0.), v(1., 0., 0.)],
            [v(0., 0., 1.), v(1., 0., 1.), v(1., 1., 1.), v(0., 1., 1.)],
            [v(0., 0., 0.), v(1., 0., 0.), v(1., 0., 1.), v(0., 0., 1.)],
            [v(0., 1., 0.), v(0., 1., 1.), v(1., 1., 1.), v(1., 1., 0.)],
            [v(0., 0., 0.), v(0., 0., 1.), v(0., 1., 1.), v(0., 1., 0.)],
            [v(1., 0., 0.), v(1., 1., 0.), v(1., 1., 1.), v(1., 0., 1.)],
        ];
        quads
            .iter()
            .flat_map(|[a, b, c, d]| [[*a, *b, *c], [*a, *c, *d]])
            .collect()
    }

    fn ascii_stl(triangles: &[[DVec3; 3]]) -> String {
        let mut text = "solid t\n".to_owned();
        for [a, b, c] in triangles {
            text += &format!(
                "facet normal 0 0 0\nouter loop\nvertex {} {} {}\nvertex {} {} {}\n\
                 vertex {} {} {}\nendloop\nendfacet\n",
                a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z
            );
        }
        text + "endsolid t\n"
    }

    fn binary_stl(triangles: &[[DVec3; 3]]) -> Vec<u8> {
        let mut bytes = vec![0u8; 80];
        bytes.extend((triangles.len() as u32).to_le_bytes());
        for t in triangles {
            bytes.extend([0u8; 12]);
            for v in t {
                for c in v.to_array() {
                    bytes.extend((c as f32).to_le_bytes());
                }
            }
            bytes.extend([0u8; 2]);
        }
        bytes
    }

    #[test]
    fn winding_number_separates_inside_from_outside_of_a_cube() {
        for bytes in [ascii_stl(&cube()).into_bytes(), binary_stl(&cube())] {
            let mesh = TriangleMesh::from_stl(&bytes).expect("valid STL");
            assert_eq!(mesh.triangles.len(), 12);
            assert!((mesh.winding_number(DVec3::splat(0.5)) - 1.0).abs() < 1e-9);
            assert!(mesh.winding_number(DVec3::new(1.5, 0.5, 0.5)).abs() < 1e-9);
            assert!(mesh.is_within(DVec3::new(0.5, 0.5, 1.05), 0.1));
            assert!(!mesh.is_within(DVec3::new(0.5, 0.5, 1.2), 0.1));
            assert!(!mesh.is_within(DVec3::splat(0.5), 0.4));
        }
    }

    #[test]
    fn broken_files_are_errors() {
        assert!(TriangleMesh::from_stl(b"solid x\nvertex 1 2\nendsolid").is_err());
        assert!(TriangleMesh::from_stl(&[0u8; 40]).is_err());
        let mut short = binary_stl(&cube());
        short.truncate(200);
        assert!(TriangleMesh::from_stl(&short).is_err());
    }
}
