//! Constructors for the usual primitives, each about its natural centre so that its
//! coefficients are well-conditioned, scaled so that `|∇Q| ≈ 1` or `Q ≈ −1` at the centre.
//!
//! Directions need not be unit (they are normalised); a zero direction, a non-positive or
//! non-finite size gives `None`. Axis-aligned directions produce exact coefficients.

use glam::DVec3;

use crate::eigen::Sym3;
use crate::quadric::Quadric;

/// `Σ w_k u_k u_kᵀ`.
fn weighted_outer(terms: &[(f64, DVec3)]) -> Sym3 {
    let mut a = [[0.0; 3]; 3];
    for &(w, u) in terms {
        let u = u.to_array();
        for (r, row) in a.iter_mut().enumerate() {
            for (c, entry) in row.iter_mut().enumerate() {
                *entry += w * u[r] * u[c];
            }
        }
    }
    a
}

fn positive(x: f64) -> Option<f64> {
    (x.is_finite() && x > 0.0).then_some(x)
}

fn unit(v: DVec3) -> Option<DVec3> {
    let m = v.abs().max_element();
    if m == 0.0 || !m.is_finite() {
        return None;
    }
    (v / m).try_normalize()
}

/// The identity minus `(1 + s) u uᵀ`, i.e. `I − u uᵀ − s u uᵀ`, exact for axis-aligned `u`.
fn perpendicular_minus(axis: DVec3, s: f64) -> Sym3 {
    let mut a = weighted_outer(&[(-(1.0 + s), axis)]);
    for (k, row) in a.iter_mut().enumerate() {
        row[k] += 1.0;
    }
    a
}

impl Quadric {
    /// The ball `|p − centre| ≤ radius`: `|x|²/r² − 1`.
    pub fn sphere(centre: DVec3, radius: f64) -> Option<Self> {
        Self::ellipsoid(centre, DVec3::splat(radius))
    }

    /// The axis-aligned ellipsoid with semi-axes `radii`: `Σ x_k²/r_k² − 1`.
    pub fn ellipsoid(centre: DVec3, radii: DVec3) -> Option<Self> {
        let r = [positive(radii.x)?, positive(radii.y)?, positive(radii.z)?];
        let w = r.map(|r| 1.0 / (r * r));
        Self::new(
            centre,
            [w[0], w[1], w[2], 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0],
        )
    }

    /// The half-space `normal · (p − point) ≤ 0` bounded by a plane (normal pointing out).
    pub fn half_space(point: DVec3, normal: DVec3) -> Option<Self> {
        let n = unit(normal)?;
        Self::from_matrix(point, &[[0.0; 3]; 3], 0.5 * n, 0.0)
    }

    /// The slab `|normal · (p − centre)| ≤ half_width` between two parallel planes:
    /// `(n·x)²/a² − 1`.
    pub fn slab(centre: DVec3, normal: DVec3, half_width: f64) -> Option<Self> {
        let n = unit(normal)?;
        let a = positive(half_width)?;
        let m = weighted_outer(&[(1.0 / (a * a), n)]);
        Self::from_matrix(centre, &m, DVec3::ZERO, -1.0)
    }

    /// The infinite circular cylinder of `radius` around the line through `point` along `axis`:
    /// `(|x|² − (u·x)²)/r² − 1`.
    pub fn cylinder(point: DVec3, axis: DVec3, radius: f64) -> Option<Self> {
        let u = unit(axis)?;
        let r = positive(radius)?;
        let mut a = perpendicular_minus(u, 0.0);
        let w = 1.0 / (r * r);
        a.iter_mut().flatten().for_each(|e| *e *= w);
        Self::from_matrix(point, &a, DVec3::ZERO, -1.0)
    }

    /// The infinite elliptic cylinder along a coordinate axis (`axis` ∈ {0, 1, 2}) with the two
    /// other semi-axes `radii` (in cyclic order after `axis`).
    pub fn elliptic_cylinder(point: DVec3, axis: usize, radii: (f64, f64)) -> Option<Self> {
        let (i, j) = ((axis % 3 + 1) % 3, (axis % 3 + 2) % 3);
        let mut k = [0.0; 10];
        k[i] = 1.0 / positive(radii.0)?.powi(2);
        k[j] = 1.0 / positive(radii.1)?.powi(2);
        k[9] = -1.0;
        Self::new(point, k)
    }

    /// The infinite double cone with apex `apex`, axis `axis` and radius growth `slope` (the
    /// tangent of the half-angle): `|x_⊥|² − slope² (u·x)² ≤ 0`.
    pub fn cone(apex: DVec3, axis: DVec3, slope: f64) -> Option<Self> {
        let u = unit(axis)?;
        let s = positive(slope)?;
        Self::from_matrix(apex, &perpendicular_minus(u, s * s), DVec3::ZERO, 0.0)
    }

    /// The paraboloid `|x_⊥|² ≤ 4 f (u·x)` with vertex `vertex`, opening along `axis`, focal
    /// length `focal_length`.
    pub fn paraboloid(vertex: DVec3, axis: DVec3, focal_length: f64) -> Option<Self> {
        let u = unit(axis)?;
        let f = positive(focal_length)?;
        Self::from_matrix(vertex, &perpendicular_minus(u, 0.0), -2.0 * f * u, 0.0)
    }

    /// The one-sheet hyperboloid `|x_⊥|²/r² − (u·x)²/c² ≤ 1` (waist radius `r`, the solid inside
    /// the waist tube).
    pub fn hyperboloid_one_sheet(centre: DVec3, axis: DVec3, radius: f64, c: f64) -> Option<Self> {
        let u = unit(axis)?;
        let (r, c) = (positive(radius)?, positive(c)?);
        let mut a = perpendicular_minus(u, 0.0);
        a.iter_mut().flatten().for_each(|e| *e /= r * r);
        let extra = weighted_outer(&[(-1.0 / (c * c), u)]);
        for (row, extra_row) in a.iter_mut().zip(extra.iter()) {
            for (e, x) in row.iter_mut().zip(extra_row.iter()) {
                *e += x;
            }
        }
        Self::from_matrix(centre, &a, DVec3::ZERO, -1.0)
    }

    /// The two-sheet hyperboloid `(u·x)²/c² − |x_⊥|²/r² ≥ 1` (vertices at `±c` along `axis`, the
    /// solid inside the two bowls): `|x_⊥|²/r² − (u·x)²/c² + 1 ≤ 0`.
    pub fn hyperboloid_two_sheets(centre: DVec3, axis: DVec3, radius: f64, c: f64) -> Option<Self> {
        let mut k = Self::hyperboloid_one_sheet(centre, axis, radius, c)?.coefficients();
        k[9] = 1.0;
        Self::new(centre, k)
    }
}
