//! Reference points on the CSG surface, found independently of any sampler: every quadric of the
//! DNF is intersected exactly with random lines through the scene's box (and with lines through
//! its own origin, so that small features are found too), and a root is kept when the solid
//! changes across it (membership tested just before and just after it on the line). Points on
//! the feature curves, where coverage is hardest to achieve, are found by bisection along a
//! quadric between a surface hit and a nearby hit of the same quadric off the surface.
//!
//! This is the oracle that the sampler's tests and the benchmarks' report measure coverage and
//! distances against: it uses nothing but [`Dnf::contains`] and exact line-quadric
//! intersections, so it shares no code with what it checks. A seed names the same lines in
//! every run ([`Rng`]'s stream), so that a measured figure can be reproduced.

use qcsg_csg::{Aabb, Dnf};
use qcsg_quadric::{DVec3, Quadric};

use crate::Rng;

/// A point on the quadric with index `quadric` in [`Dnf::quadrics`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    /// Index into [`Dnf::quadrics`].
    pub quadric: u32,
    /// World position.
    pub position: DVec3,
}

/// The diagonal of the DNF's box (0 for an empty or unbounded box).
pub fn diagonal(dnf: &Dnf) -> f64 {
    let d = (dnf.bounds.max - dnf.bounds.min).length();
    if d.is_finite() { d } else { 0.0 }
}

/// The step used to test membership on either side of a root: 1e-11 of the diagonal, so that a
/// wall 1e-9 thick still has an inside, but never below a few units in the last place of the
/// coordinates (far from the origin smaller steps are not representable).
pub fn side_step(dnf: &Dnf) -> f64 {
    let magnitude = dnf.bounds.min.abs().max(dnf.bounds.max.abs()).max_element();
    (1e-11 * diagonal(dnf)).max(16.0 * f64::EPSILON * magnitude)
}

/// Ray hits on the quadrics inside the DNF's box: those where the solid changes across the hit
/// (on the CSG surface) and those where it does not (on the quadric, off the CSG surface).
pub fn ray_hits(dnf: &Dnf, rays: usize, seed: u64) -> (Vec<SurfacePoint>, Vec<SurfacePoint>) {
    let mut on = Vec::new();
    let mut off = Vec::new();
    if !dnf.bounds.is_bounded() || dnf.bounds.is_empty() {
        return (on, off);
    }
    let eps = side_step(dnf);
    let mut rng = Rng::new(seed);
    let half = 0.5 * (dnf.bounds.max - dnf.bounds.min) * 1.05;
    let widened = Aabb::from_centre_half(dnf.bounds.centre(), half);
    for _ in 0..rays {
        let origin = rng.in_box(widened.min, widened.max);
        let v = rng.direction();
        for (index, entry) in dnf.quadrics.iter().enumerate() {
            for t in entry.quadric.intersect_line(origin, v).roots() {
                let x = origin + t * v;
                if !x.is_finite() || !dnf.bounds.contains(x) {
                    continue;
                }
                let point = SurfacePoint {
                    quadric: index as u32,
                    position: x,
                };
                if dnf.contains(x - eps * v) != dnf.contains(x + eps * v) {
                    on.push(point);
                } else {
                    off.push(point);
                }
            }
        }
    }
    (on, off)
}

/// Reference points on the CSG surface from `rays` random lines.
pub fn reference_points(dnf: &Dnf, rays: usize, seed: u64) -> Vec<SurfacePoint> {
    ray_hits(dnf, rays, seed).0
}

/// Reference points aimed at every quadric: `lines` random lines through each quadric's origin
/// (its centre for central quadrics) when that lies in the DNF's box, keeping that quadric's
/// roots where the solid changes across them. Random lines through the whole box rarely meet a
/// feature a millionth of its size (a dent of radius 1 in a ball of radius 1e6); these do.
pub fn quadric_points(dnf: &Dnf, lines: usize, seed: u64) -> Vec<SurfacePoint> {
    let mut out = Vec::new();
    if !dnf.bounds.is_bounded() || dnf.bounds.is_empty() {
        return out;
    }
    let eps = side_step(dnf);
    let mut rng = Rng::new(seed);
    for (index, entry) in dnf.quadrics.iter().enumerate() {
        let origin = entry.quadric.origin();
        if !dnf.bounds.contains(origin) {
            continue;
        }
        for _ in 0..lines {
            let v = rng.direction();
            for t in entry.quadric.intersect_line(origin, v).roots() {
                let x = origin + t * v;
                if x.is_finite()
                    && dnf.bounds.contains(x)
                    && dnf.contains(x - eps * v) != dnf.contains(x + eps * v)
                {
                    out.push(SurfacePoint {
                        quadric: index as u32,
                        position: x,
                    });
                }
            }
        }
    }
    out
}

/// Whether the solid changes across quadric `q` at `x` (`±eps` along its normal); `None` where
/// the normal is undefined (a cone's apex).
pub fn on_csg_surface(dnf: &Dnf, q: &Quadric, x: DVec3, eps: f64) -> Option<bool> {
    let n = q.normal(x)?;
    Some(dnf.contains(x - eps * n) != dnf.contains(x + eps * n))
}

/// The point of `q` nearest to `x` along the normal at `x` (a projection for nearby points).
pub fn project(q: &Quadric, x: DVec3) -> Option<DVec3> {
    let n = q.normal(x)?;
    let t = q
        .intersect_line(x, n)
        .roots()
        .into_iter()
        .min_by(|a, b| a.abs().total_cmp(&b.abs()))?;
    Some(x + t * n)
}

/// Reference points on the feature curves: bisection along the quadric between a ray hit on the
/// CSG surface and a hit on the same quadric off it within a fifth of the diagonal, keeping the
/// last point on the CSG surface once the bracket is below a millionth of the diagonal.
pub fn edge_points(dnf: &Dnf, rays: usize, seed: u64) -> Vec<SurfacePoint> {
    let diag = diagonal(dnf);
    let eps = side_step(dnf);
    let (on, off) = ray_hits(dnf, rays, seed);
    let mut out = Vec::new();
    if off.is_empty() {
        return out;
    }
    for (k, hit) in on.iter().enumerate() {
        let q = dnf.quadrics[hit.quadric as usize].quadric;
        // The next off-surface hit on the same quadric, starting at a place that moves with
        // `k` so that the hits do not all pair with the same partner.
        let Some(partner) = off
            .iter()
            .cycle()
            .skip(k % off.len())
            .take(off.len())
            .find(|b| {
                b.quadric == hit.quadric && (b.position - hit.position).length() < 0.2 * diag
            })
        else {
            continue;
        };
        let (mut inside, mut outside) = (hit.position, partner.position);
        let mut ok = true;
        for _ in 0..45 {
            let Some(m) = project(&q, 0.5 * (inside + outside)) else {
                ok = false;
                break;
            };
            match on_csg_surface(dnf, &q, m, eps) {
                Some(true) => inside = m,
                Some(false) => outside = m,
                None => {
                    ok = false;
                    break;
                }
            }
        }
        if ok && (inside - outside).length() < 1e-6 * diag {
            out.push(SurfacePoint {
                quadric: hit.quadric,
                position: inside,
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use qcsg_csg::{Dag, DnfOptions, Source, build_dnf};

    use super::*;

    /// The lens of two unit spheres centred at `(±0.5, 0, 0)`: its feature curve is the circle
    /// of radius `√0.75` in the plane `x = 0`.
    fn lens() -> Dnf {
        let mut dag = Dag::new();
        let [a, b] = [-0.5, 0.5].map(|x| {
            let sphere = Quadric::sphere(DVec3::new(x, 0.0, 0.0), 1.0).expect("a sphere");
            dag.leaf(sphere, Source::default()).into()
        });
        let lens = dag.intersection([a, b], Source::default());
        dag.set_root(lens.into());
        build_dnf(&dag, &DnfOptions::default()).expect("a DNF")
    }

    #[test]
    fn reference_points_lie_on_the_surface_of_the_solid() {
        let dnf = lens();
        let points = reference_points(&dnf, 500, 3);
        assert!(points.len() > 500, "only {} points", points.len());
        for p in &points {
            // The half with x < 0 is bounded by the sphere about (0.5, 0, 0) and lies inside the
            // other one, and the other way round.
            let x = if p.position.x < 0.0 { 0.5 } else { -0.5 };
            let (bounding, other) = (DVec3::new(x, 0.0, 0.0), DVec3::new(-x, 0.0, 0.0));
            assert!(
                ((p.position - bounding).length() - 1.0).abs() < 1e-12,
                "{p:?} is not on the sphere about {bounding}"
            );
            assert!(
                (p.position - other).length() <= 1.0 + 1e-12,
                "{p:?} off the lens"
            );
        }
        // The same seed gives the same points; another seed others.
        assert_eq!(points, reference_points(&dnf, 500, 3));
        assert_ne!(points, reference_points(&dnf, 500, 4));
    }

    #[test]
    fn edge_points_lie_on_the_feature_curve() {
        let dnf = lens();
        let points = edge_points(&dnf, 300, 7);
        assert!(points.len() > 50, "only {} points", points.len());
        for p in &points {
            let x = p.position;
            assert!(x.x.abs() < 1e-5, "{p:?} is not in the plane of the circle");
            let radius = (x.y * x.y + x.z * x.z).sqrt();
            assert!(
                (radius - 0.75f64.sqrt()).abs() < 1e-5,
                "{p:?} off the circle"
            );
        }
    }

    #[test]
    fn quadric_points_find_a_dent_too_small_for_random_lines() {
        // A ball of radius 1e6 with a dent of radius 1 at its top, centred just inside it.
        let centre = DVec3::new(0.0, 0.0, 1e6 - 0.5);
        let mut dag = Dag::new();
        let ball = Quadric::sphere(DVec3::ZERO, 1e6).expect("a sphere");
        let dent = Quadric::sphere(centre, 1.0).expect("a sphere");
        let ball = dag.leaf(ball, Source::default()).into();
        let dent = dag.leaf(dent, Source::default()).into();
        let solid = dag.difference([ball, dent], Source::default());
        dag.set_root(solid.into());
        let dnf = build_dnf(&dag, &DnfOptions::default()).expect("a DNF");
        let on_dent = |points: &[SurfacePoint]| {
            points
                .iter()
                .filter(|p| (p.position - centre).length() < 1.0 + 1e-6)
                .count()
        };
        assert_eq!(on_dent(&reference_points(&dnf, 200, 1)), 0);
        assert!(on_dent(&quadric_points(&dnf, 200, 1)) > 50);
    }
}
