//! The point of a triangle closest to a given point: the one distance query that mesh
//! checks (a mesh's deviation from the exact surface, an oracle mesh's nearness to a test point)
//! are built on.

use glam::DVec3;

/// The point of triangle `[a, b, c]` closest to `p`, by the Voronoi regions of its vertices,
/// edges and face (Ericson, Real-Time Collision Detection, 5.1.5). A degenerate triangle (its
/// corners collinear or equal) gives the closest point of its edges.
pub fn closest_point_on_triangle(p: DVec3, &[a, b, c]: &[DVec3; 3]) -> DVec3 {
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
    let denominator = va + vb + vc;
    if denominator == 0.0 || !denominator.is_finite() {
        // The face's barycentric weights are undefined: the point is nearest an edge.
        return [(a, b), (b, c), (c, a)]
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
            .min_by(|x, y| x.distance_squared(p).total_cmp(&y.distance_squared(p)))
            .unwrap_or(a);
    }
    a + ab * (vb / denominator) + ac * (vc / denominator)
}

#[cfg(test)]
mod tests {
    use super::*;

    const T: [DVec3; 3] = [DVec3::ZERO, DVec3::X, DVec3::Y];

    #[test]
    fn each_region_gives_its_exact_point() {
        let v = DVec3::new;
        // Face, each vertex, each edge.
        let cases = [
            (v(0.2, 0.3, 3.0), v(0.2, 0.3, 0.0)),
            (v(0.2, 0.3, -2.0), v(0.2, 0.3, 0.0)),
            (v(-1.0, -1.0, 0.5), v(0.0, 0.0, 0.0)),
            (v(3.0, -1.0, 0.0), v(1.0, 0.0, 0.0)),
            (v(-1.0, 3.0, 1.0), v(0.0, 1.0, 0.0)),
            (v(0.5, -2.0, 0.0), v(0.5, 0.0, 0.0)),
            (v(-2.0, 0.25, 1.0), v(0.0, 0.25, 0.0)),
            (v(1.0, 1.0, 0.0), v(0.5, 0.5, 0.0)),
        ];
        for (p, expected) in cases {
            let got = closest_point_on_triangle(p, &T);
            assert!(got.distance(expected) < 1e-15, "{p}: {got}, not {expected}");
        }
    }

    #[test]
    fn no_point_of_the_triangle_is_closer() {
        // Against a dense grid of the triangle's points: the answer is on the triangle and at
        // most as far as any of them.
        let t = [
            DVec3::new(0.3, -1.0, 2.0),
            DVec3::new(2.0, 0.5, -1.0),
            DVec3::new(-1.5, 1.0, 0.5),
        ];
        let n = 60;
        let grid: Vec<DVec3> = (0..=n)
            .flat_map(|i| (0..=n - i).map(move |j| (i, j)))
            .map(|(i, j)| {
                let (u, w) = (f64::from(i) / f64::from(n), f64::from(j) / f64::from(n));
                t[0] + (t[1] - t[0]) * u + (t[2] - t[0]) * w
            })
            .collect();
        let normal = (t[1] - t[0]).cross(t[2] - t[0]).normalize();
        for k in 0..200 {
            let k = f64::from(k);
            let p = DVec3::new((k * 0.37).sin(), (k * 0.71).cos(), (k * 0.13).sin()) * 4.0;
            let q = closest_point_on_triangle(p, &t);
            assert!((q - t[0]).dot(normal).abs() < 1e-12, "{q} off the plane");
            // Barycentric coordinates of q: all within [0, 1].
            let (e1, e2, d) = (t[1] - t[0], t[2] - t[0], q - t[0]);
            let (a, b, c) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
            let (x, y) = (d.dot(e1), d.dot(e2));
            let det = a * c - b * b;
            let (u, w) = ((c * x - b * y) / det, (a * y - b * x) / det);
            let eps = 1e-12;
            assert!(
                u >= -eps && w >= -eps && u + w <= 1.0 + eps,
                "{q} off the triangle"
            );
            let best = grid
                .iter()
                .map(|g| g.distance(p))
                .fold(f64::INFINITY, f64::min);
            assert!(q.distance(p) <= best + 1e-12, "{p}: {q} beaten by the grid");
        }
    }

    #[test]
    fn a_degenerate_triangle_is_its_edges() {
        let line = [DVec3::ZERO, DVec3::X, DVec3::X * 2.0];
        let q = closest_point_on_triangle(DVec3::new(1.5, 1.0, 0.0), &line);
        assert!(q.distance(DVec3::new(1.5, 0.0, 0.0)) < 1e-15);
        let point = [DVec3::ONE; 3];
        assert_eq!(closest_point_on_triangle(DVec3::ZERO, &point), DVec3::ONE);
    }
}
