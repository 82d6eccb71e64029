//! Reference points on the CSG surface, found independently of the sampler: every quadric of the
//! DNF is intersected exactly with random lines through the scene's box (and with lines through
//! its own origin, so that small features are found too), and a root is kept when the solid
//! changes across it (membership tested just before and just after it on the line).
//! Points on the feature curves, where coverage is hardest to achieve, are found by bisection
//! along a quadric between a surface hit and a nearby hit of the same quadric off the surface.

use qcsg_csg::{Aabb, Dnf};
use qcsg_quadric::{DVec3, Quadric};

/// A small deterministic generator (SplitMix64), so that every run sees the same points.
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    /// A generator from a seed.
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)`.
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in `[a, b)`.
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.unit()
    }

    /// Uniform on the unit sphere.
    pub fn direction(&mut self) -> DVec3 {
        loop {
            let v = DVec3::new(
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
            );
            let l = v.length();
            if l > 1e-3 && l <= 1.0 {
                return v / l;
            }
        }
    }

    /// Uniform in a bounded box.
    pub fn point_in(&mut self, b: &Aabb) -> DVec3 {
        DVec3::new(
            self.range(b.min.x, b.max.x),
            self.range(b.min.y, b.max.y),
            self.range(b.min.z, b.max.z),
        )
    }
}

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
        let origin = rng.point_in(&widened);
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

/// Whether the solid changes across quadric `q` at `x` (`±eps` along its normal).
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
