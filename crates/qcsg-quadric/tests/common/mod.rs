//! Shared test support: a deterministic generator, a catalogue of quadrics of every kind, random
//! transforms, and an independent oracle for the true distance to a quadric surface.

#![allow(dead_code, clippy::needless_range_loop)]

use qcsg_quadric::{DVec3, Quadric, QuadricKind};

pub use qcsg_testkit::Rng;

/// One catalogue entry: a quadric built about the origin, its kind and a length scale.
pub struct Case {
    pub name: &'static str,
    pub quadric: Quadric,
    pub kind: QuadricKind,
    /// A typical feature size, for choosing test points.
    pub size: f64,
}

fn q(k: [f64; 10]) -> Quadric {
    Quadric::new(DVec3::ZERO, k).expect("finite coefficients")
}

/// Quadrics of every kind, about the world origin.
pub fn catalogue() -> Vec<Case> {
    use QuadricKind as K;
    let o = DVec3::ZERO;
    let c = |name, quadric: Option<Quadric>, kind, size| Case {
        name,
        quadric: quadric.expect("valid primitive"),
        kind,
        size,
    };
    vec![
        c("sphere", Quadric::sphere(o, 1.5), K::Sphere, 1.5),
        c(
            "spheroid",
            Quadric::ellipsoid(o, DVec3::new(1.0, 1.0, 3.0)),
            K::Spheroid,
            2.0,
        ),
        c(
            "ellipsoid",
            Quadric::ellipsoid(o, DVec3::new(0.5, 1.0, 2.0)),
            K::Ellipsoid,
            1.0,
        ),
        c(
            "cylinder",
            Quadric::cylinder(o, DVec3::new(1.0, 2.0, 3.0), 0.7),
            K::EllipticCylinder,
            0.7,
        ),
        // Along an axis, as `cylinder` and `cube` make them: the conservative distance takes
        // a shorter way there.
        c(
            "axis_cylinder",
            Quadric::cylinder(o, DVec3::Z, 0.7),
            K::EllipticCylinder,
            0.7,
        ),
        c(
            "axis_slab",
            Quadric::slab(o, DVec3::X, 0.3),
            K::ParallelPlanes,
            0.3,
        ),
        c(
            "elliptic_cylinder",
            Quadric::elliptic_cylinder(o, 1, (0.5, 2.0)),
            K::EllipticCylinder,
            1.0,
        ),
        c(
            "hyperbolic_cylinder",
            Some(q([1.0, -0.25, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0])),
            K::HyperbolicCylinder,
            1.0,
        ),
        c(
            "parabolic_cylinder",
            Some(q([1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -0.5, 0.0])),
            K::ParabolicCylinder,
            1.0,
        ),
        c(
            "cone",
            Quadric::cone(o, DVec3::new(0.0, 1.0, 1.0), 0.5),
            K::Cone,
            1.0,
        ),
        c(
            "hyperboloid_one_sheet",
            Quadric::hyperboloid_one_sheet(o, DVec3::Z, 1.0, 0.5),
            K::HyperboloidOneSheet,
            1.0,
        ),
        c(
            "hyperboloid_two_sheets",
            Quadric::hyperboloid_two_sheets(o, DVec3::X, 1.0, 0.5),
            K::HyperboloidTwoSheets,
            1.0,
        ),
        c(
            "elliptic_paraboloid",
            Quadric::paraboloid(o, DVec3::new(1.0, -1.0, 0.5), 0.25),
            K::EllipticParaboloid,
            1.0,
        ),
        c(
            "hyperbolic_paraboloid",
            Some(q([1.0, -2.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -0.5, 0.0])),
            K::HyperbolicParaboloid,
            1.0,
        ),
        c(
            "plane",
            Quadric::half_space(o, DVec3::new(1.0, 1.0, -1.0)),
            K::Plane,
            1.0,
        ),
        c(
            "slab",
            Quadric::slab(o, DVec3::new(0.0, 3.0, 4.0), 0.3),
            K::ParallelPlanes,
            0.3,
        ),
        c(
            "intersecting_planes",
            Some(q([1.0, -4.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0])),
            K::IntersectingPlanes,
            1.0,
        ),
        c(
            "coincident_planes",
            Some(q([0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0])),
            K::CoincidentPlanes,
            1.0,
        ),
        c(
            "line",
            Some(q([1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0])),
            K::Line,
            1.0,
        ),
        c(
            "point",
            Some(q([1.0, 2.0, 3.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0])),
            K::Point,
            1.0,
        ),
        c(
            "empty",
            Some(q([1.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0])),
            K::Empty,
            1.0,
        ),
        c(
            "all_space",
            Some(q([-1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0])),
            K::AllSpace,
            1.0,
        ),
    ]
}

/// `xᵀ A x + 2 lᵀ x + j` written out independently of the crate.
pub fn raw_value(k: &[f64; 10], x: DVec3) -> f64 {
    let [a, b, c, d, e, f, g, h, i, j] = *k;
    a * x.x * x.x
        + b * x.y * x.y
        + c * x.z * x.z
        + 2.0 * (d * x.x * x.y + e * x.x * x.z + f * x.y * x.z)
        + 2.0 * (g * x.x + h * x.y + i * x.z)
        + j
}

/// Magnitude of the terms of [`raw_value`].
fn raw_terms(k: &[f64; 10], x: DVec3) -> f64 {
    let a = k.map(f64::abs);
    let x = x.abs();
    raw_value(&a, x)
}

/// Solves the 3×3 system `m y = r` by Gaussian elimination with partial pivoting.
fn solve3(mut m: [[f64; 3]; 3], mut r: [f64; 3]) -> Option<[f64; 3]> {
    for col in 0..3 {
        let pivot = (col..3).max_by(|&a, &b| m[a][col].abs().total_cmp(&m[b][col].abs()))?;
        if m[pivot][col] == 0.0 {
            return None;
        }
        m.swap(col, pivot);
        r.swap(col, pivot);
        for row in col + 1..3 {
            let f = m[row][col] / m[col][col];
            for c in col..3 {
                m[row][c] -= f * m[col][c];
            }
            r[row] -= f * r[col];
        }
    }
    let mut y = [0.0; 3];
    for row in (0..3).rev() {
        let mut s = r[row];
        for c in row + 1..3 {
            s -= m[row][c] * y[c];
        }
        y[row] = s / m[row][row];
    }
    y.iter().all(|v| v.is_finite()).then_some(y)
}

/// An independent estimate of the distance from `p` to the surface of `quadric`, never below the
/// true distance by more than rounding: the minimum over genuine surface points found by
/// (1) the Lagrange condition `y − y₀ = μ (A y + l)`, solved for `y(μ)` by elimination and for
/// `μ` by a dense scan plus bisection of `q(y(μ))`, and (2) first hits of rays from `p` in 400
/// directions. `f64::INFINITY` if no surface point is found.
pub fn true_distance(quadric: &Quadric, p: DVec3) -> f64 {
    let k = quadric.coefficients();
    let y0 = p - quadric.origin();
    let [a, b, c, d, e, f, g, h, i, _] = k;
    let am = [[a, d, e], [d, b, f], [e, f, c]];
    let l = [g, h, i];
    let norm = am.iter().flatten().map(|v| v * v).sum::<f64>().sqrt();
    let mut best = f64::INFINITY;
    let mut consider = |y: DVec3| {
        let residual = raw_value(&k, y).abs();
        if residual <= 1e-9 * raw_terms(&k, y).max(f64::MIN_POSITIVE) || residual == 0.0 {
            best = best.min((y - y0).length());
        }
    };

    let point_at = |mu: f64| -> Option<DVec3> {
        let mut m = [[0.0; 3]; 3];
        for r in 0..3 {
            for col in 0..3 {
                m[r][col] = if r == col { 1.0 } else { 0.0 } - mu * am[r][col];
            }
        }
        let rhs = [y0.x + mu * l[0], y0.y + mu * l[1], y0.z + mu * l[2]];
        solve3(m, rhs).map(DVec3::from_array)
    };
    let f_of = |theta: f64, scale: f64| -> Option<f64> {
        let mu = scale * theta.tan();
        point_at(mu).map(|y| raw_value(&k, y))
    };
    // μ has units of 1/A; scan a few scales so every pole and root gets resolved.
    let scales: Vec<f64> = if norm > 0.0 {
        vec![1.0 / norm, 1e-3 / norm, 1e3 / norm]
    } else {
        let ln = (l[0] * l[0] + l[1] * l[1] + l[2] * l[2]).sqrt().max(1e-300);
        vec![1.0 / ln, (y0.length() + 1.0) / ln]
    };
    const STEPS: usize = 400;
    let half_pi = std::f64::consts::FRAC_PI_2;
    for &scale in &scales {
        let mut previous: Option<(f64, f64)> = None;
        for step in 0..=STEPS {
            let theta =
                -half_pi + std::f64::consts::PI * (step as f64 + 0.5) / (STEPS as f64 + 1.0);
            let Some(value) = f_of(theta, scale) else {
                previous = None;
                continue;
            };
            if value == 0.0
                && let Some(y) = point_at(scale * theta.tan())
            {
                consider(y);
            }
            if let Some((t0, v0)) = previous
                && v0.signum() != value.signum()
            {
                let (mut lo, mut hi, mut vlo) = (t0, theta, v0);
                for _ in 0..80 {
                    let mid = 0.5 * (lo + hi);
                    let Some(vm) = f_of(mid, scale) else { break };
                    if vm.signum() == vlo.signum() {
                        lo = mid;
                        vlo = vm;
                    } else {
                        hi = mid;
                    }
                }
                for t in [lo, hi] {
                    if let Some(y) = point_at(scale * t.tan()) {
                        consider(y);
                    }
                }
            }
            previous = Some((theta, value));
        }
    }

    // Rays: first hits along a Fibonacci sphere of directions (naive quadratic, own code).
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    const RAYS: usize = 400;
    for n in 0..RAYS {
        let z = 1.0 - 2.0 * (n as f64 + 0.5) / RAYS as f64;
        let r = (1.0 - z * z).sqrt();
        let v = DVec3::new(
            r * (golden * n as f64).cos(),
            r * (golden * n as f64).sin(),
            z,
        );
        let av = DVec3::new(
            a * v.x + d * v.y + e * v.z,
            d * v.x + b * v.y + f * v.z,
            e * v.x + f * v.y + c * v.z,
        );
        let qa = v.dot(av);
        let qb = av.dot(y0) + DVec3::from_array(l).dot(v);
        let qc = raw_value(&k, y0);
        let mut roots = Vec::new();
        if qa.abs() < 1e-300 {
            if qb != 0.0 {
                roots.push(-qc / (2.0 * qb));
            }
        } else {
            let disc = qb * qb - qa * qc;
            if disc >= 0.0 {
                let s = disc.sqrt();
                roots.push((-qb - s) / qa);
                roots.push((-qb + s) / qa);
            }
        }
        for t in roots {
            if t.is_finite() && t >= 0.0 {
                // Polish with Newton steps along the ray.
                let mut t = t;
                for _ in 0..3 {
                    let val = raw_value(&k, y0 + t * v);
                    let der = 2.0 * (qa * t + qb);
                    if der != 0.0 {
                        t -= val / der;
                    }
                }
                consider(y0 + t.abs() * v);
            }
        }
    }
    best
}

/// Random test points around a case: at log-uniform distances from the centre, and near the
/// surface (a surface point found by a ray from the centre, offset by a log-uniform amount).
pub fn points_around(rng: &mut Rng, quadric: &Quadric, size: f64, count: usize) -> Vec<DVec3> {
    let centre = quadric.origin();
    let mut points = Vec::with_capacity(count);
    while points.len() < count {
        let dir = rng.direction();
        let start = centre + rng.direction() * size * rng.range(0.0, 0.5);
        if points.len() % 2 == 0 {
            points.push(start + dir * size * 10f64.powf(rng.range(-3.0, 1.0)));
        } else if let Some(t) = quadric.intersect_line(start, dir).first_at_or_after(0.0) {
            let surface = start + t * dir;
            let offset = rng.direction() * size * 10f64.powf(rng.range(-6.0, 0.0));
            points.push(surface + offset);
        } else {
            points.push(start + dir * size * rng.range(0.0, 3.0));
        }
    }
    points
}
