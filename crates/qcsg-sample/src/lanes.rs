//! A fill row's samples computed up to eight at a time, one array per coordinate, so that the
//! compiler evaluates several samples' heights, quadric values, gradients, square roots and
//! divisions at once in vector registers: sample by sample, through `DVec3`s, each takes a scalar
//! instruction per operation (`docs/sampler-benchmarks.md` has what this saves).
//!
//! Every lane computes exactly what [`region_point`](crate::regions::region_point),
//! `Quadric::value`, `Quadric::gradient` and `Quadric::normal_from_gradient_squared` compute, in
//! the same order of operations (IEEE arithmetic gives the same result in a vector lane as in a
//! scalar register), so the samples are the same to the bit. A lane whose point needs more
//! than that (a Newton step onto the quadric, or a gradient whose squared length under- or
//! overflows) is marked, and the caller takes it the scalar way.

// A lane's loop reads and writes several arrays at the same index; that is the form the
// compiler turns into vector instructions.
#![allow(clippy::needless_range_loop)]

use qcsg_quadric::{DVec3, Heightfield, HeightfieldForm, PrincipalFrame, Quadric};

/// Points or vectors of a batch of `N` lanes, one array per coordinate.
#[derive(Clone, Copy, Debug)]
pub struct Points<const N: usize> {
    pub x: [f64; N],
    pub y: [f64; N],
    pub z: [f64; N],
}

impl<const N: usize> Points<N> {
    const ZERO: Self = Self {
        x: [0.0; N],
        y: [0.0; N],
        z: [0.0; N],
    };

    /// The point of lane `l`.
    pub fn at(&self, l: usize) -> DVec3 {
        DVec3::new(self.x[l], self.y[l], self.z[l])
    }
}

/// The surface points over the line `y` of a heightfield's plane, on one sheet (what
/// [`region_point`](crate::regions::region_point) gives at `(x, y)`), with the terms that do
/// not depend on `x` computed once.
pub struct HeightfieldLine {
    centre: DVec3,
    along: DVec3,
    /// `y u_j`.
    across: DVec3,
    up: DVec3,
    sheet: f64,
    height: LineHeight,
}

/// The height along a [`HeightfieldLine`], with its terms in `y` summed as
/// `Heightfield::height` sums them.
enum LineHeight {
    /// `h = √((α_x x + 2β_x) x + y_part + α_c)`.
    Root {
        alpha_x: f64,
        beta_x: f64,
        y_part: f64,
        alpha_c: f64,
    },
    /// `h = γ_x x x + y_part + γ_c`.
    Polynomial {
        gamma_x: f64,
        y_part: f64,
        gamma_c: f64,
    },
}

impl HeightfieldLine {
    /// The line `y` of `heightfield` in `frame` on sheet `sheet` (`±1`); `None` where the surface
    /// is ruled (it has no points over the plane).
    pub fn new(
        frame: &PrincipalFrame,
        heightfield: &Heightfield,
        sheet: f64,
        y: f64,
    ) -> Option<Self> {
        let height = match heightfield.form {
            HeightfieldForm::Root {
                alpha_x,
                alpha_y,
                alpha_c,
                beta_x,
                beta_y,
            } => LineHeight::Root {
                alpha_x,
                beta_x,
                y_part: (alpha_y * y + 2.0 * beta_y) * y,
                alpha_c,
            },
            HeightfieldForm::Polynomial {
                gamma_x,
                gamma_y,
                gamma_c,
            } => LineHeight::Polynomial {
                gamma_x,
                y_part: gamma_y * y * y,
                gamma_c,
            },
            HeightfieldForm::Ruled => return None,
        };
        let (i, j) = heightfield.plane_axes;
        Some(Self {
            centre: frame.centre,
            along: frame.axes[i],
            across: y * frame.axes[j],
            up: frame.axes[heightfield.normal_axis],
            sheet,
            height,
        })
    }

    /// The surface points over `x` (all lanes), and which lanes have one (the line through the
    /// others normal to the plane misses the surface).
    #[inline]
    pub fn points<const N: usize>(&self, x: &[f64; N]) -> (Points<N>, [bool; N]) {
        let mut h = [0.0; N];
        let mut found = [true; N];
        match self.height {
            LineHeight::Root {
                alpha_x,
                beta_x,
                y_part,
                alpha_c,
            } => {
                for l in 0..N {
                    let s = (alpha_x * x[l] + 2.0 * beta_x) * x[l] + y_part + alpha_c;
                    found[l] = s >= 0.0;
                    h[l] = s.sqrt();
                }
            }
            LineHeight::Polynomial {
                gamma_x,
                y_part,
                gamma_c,
            } => {
                for l in 0..N {
                    h[l] = gamma_x * x[l] * x[l] + y_part + gamma_c;
                }
            }
        }
        let mut p = Points::ZERO;
        let (c, a, b, u, sheet) = (self.centre, self.along, self.across, self.up, self.sheet);
        for l in 0..N {
            let t = sheet * h[l];
            p.x[l] = c.x + x[l] * a.x + b.x + t * u.x;
            p.y[l] = c.y + x[l] * a.y + b.y + t * u.y;
            p.z[l] = c.z + x[l] * a.z + b.z + t * u.z;
        }
        (p, found)
    }
}

/// A quadric's coefficients for [`SurfaceTest::normals`].
pub struct SurfaceTest {
    origin: DVec3,
    coefficients: [f64; 10],
    /// `settled²` where a point farther than `settled` from the quadric is moved onto it.
    settled_squared: f64,
}

impl SurfaceTest {
    /// The test of points on `quadric`: points within `settled` of it (`|Q| / ‖∇Q‖`) pass, the
    /// others are left to the caller's Newton steps.
    pub fn new(quadric: &Quadric, settled: f64) -> Self {
        Self {
            origin: quadric.origin(),
            coefficients: quadric.coefficients(),
            settled_squared: settled * settled,
        }
    }

    /// The outward unit normals at `p` (all lanes), and which lanes are done: within the
    /// settled distance of the quadric, with a gradient whose squared length is a normal
    /// finite number.
    #[inline]
    pub fn normals<const N: usize>(&self, p: &Points<N>) -> (Points<N>, [bool; N]) {
        let [a, b, c, d, e, f, g, h, i, j] = self.coefficients;
        let o = self.origin;
        let mut n = Points::ZERO;
        let mut done = [true; N];
        for l in 0..N {
            let (x, y, z) = (p.x[l] - o.x, p.y[l] - o.y, p.z[l] - o.z);
            // `A x` (`Quadric::apply_a`), the value `x · (A x + 2 l) + j` and the gradient
            // `2 (A x + l)`.
            let ax = a * x + d * y + e * z;
            let ay = d * x + b * y + f * z;
            let az = e * x + f * y + c * z;
            let (gx, gy, gz) = (2.0 * (ax + g), 2.0 * (ay + h), 2.0 * (az + i));
            let length_squared = gx * gx + gy * gy + gz * gz;
            let value = x * (ax + 2.0 * g) + y * (ay + 2.0 * h) + z * (az + 2.0 * i) + j;
            let settled = value * value <= self.settled_squared * length_squared;
            let in_range = (f64::MIN_POSITIVE..=f64::MAX).contains(&length_squared);
            done[l] = settled && in_range;
            let inverse = 1.0 / length_squared.sqrt();
            (n.x[l], n.y[l], n.z[l]) = (gx * inverse, gy * inverse, gz * inverse);
        }
        (n, done)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::regions::region_point;
    use proptest::prelude::*;
    use qcsg_quadric::Tolerances;

    /// `f64`s of every size and sign, zero included.
    fn coefficient() -> impl Strategy<Value = f64> {
        prop_oneof![
            -4.0f64..4.0,
            Just(0.0),
            Just(1.0),
            (-1.0f64..1.0, -30i32..30).prop_map(|(m, e)| m * 10f64.powi(e)),
        ]
    }

    /// The lanes compute what the scalar code computes, bit for bit.
    fn check_lanes<const N: usize>(
        quadric: &Quadric,
        settled: f64,
        (y, sheet): (f64, f64),
        x: [f64; N],
    ) -> Result<(), TestCaseError> {
        let frame = PrincipalFrame::new(quadric, &Tolerances::default());
        let test = SurfaceTest::new(quadric, settled);
        for heightfield in frame.heightfields() {
            let line = HeightfieldLine::new(&frame, &heightfield, sheet, y);
            prop_assert_eq!(line.is_none(), heightfield.form == HeightfieldForm::Ruled);
            let Some(line) = line else { continue };
            let (points, found) = line.points(&x);
            let (normals, done) = test.normals(&points);
            for l in 0..N {
                let scalar = region_point(&frame, &heightfield, sheet, x[l], y);
                prop_assert_eq!(found[l], scalar.is_some());
                let Some(p) = scalar else { continue };
                let bits = |v: DVec3| v.to_array().map(f64::to_bits);
                prop_assert_eq!(bits(points.at(l)), bits(p));
                // The scalar test of `snap_to_surface` and `Quadric::normal_from_gradient_squared`.
                let (value, gradient) = (quadric.value(p), quadric.gradient(p));
                let length_squared = gradient.length_squared();
                let near = value * value <= settled * settled * length_squared;
                let normal = Quadric::normal_from_gradient_squared(gradient, length_squared);
                let in_range = (f64::MIN_POSITIVE..=f64::MAX).contains(&length_squared);
                prop_assert_eq!(done[l], near && in_range);
                if done[l] {
                    prop_assert_eq!(Some(bits(normals.at(l))), normal.map(bits));
                }
            }
        }
        Ok(())
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2048))]

        #[test]
        fn lanes_agree_with_the_scalar_code_to_the_bit(
            origin in proptest::array::uniform3(-100.0f64..100.0),
            coefficients in proptest::array::uniform10(coefficient()),
            settled in 1e-15f64..1e-3,
            (y, sheet) in (-5.0f64..5.0, prop_oneof![Just(1.0), Just(-1.0)]),
            x in proptest::array::uniform8(-5.0f64..5.0),
        ) {
            let Some(quadric) = Quadric::new(DVec3::from_array(origin), coefficients) else {
                return Ok(());
            };
            check_lanes(&quadric, settled, (y, sheet), x)?;
            check_lanes(&quadric, settled, (y, sheet), [x[0], x[1]])?;
            check_lanes(&quadric, settled, (y, sheet), [x[0]])?;
        }
    }

    /// Spheres give points on both sides of the rim, and planes and paraboloids the
    /// polynomial heightfield, which random coefficients seldom do.
    #[test]
    fn lanes_agree_on_primitives() {
        let quadrics = [
            Quadric::sphere(DVec3::new(3.0, -2.0, 1e6), 2.5),
            Quadric::new(
                DVec3::ZERO,
                [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.3, -0.2, 0.9, 1.5],
            ),
            Quadric::new(
                DVec3::ZERO,
                [1.0, 2.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -0.5, 0.0],
            ),
        ];
        let x = std::array::from_fn(|l| -3.0 + 0.8 * l as f64);
        for quadric in quadrics.into_iter().flatten() {
            for settled in [0.0, 1e-12] {
                for (y, sheet) in [(0.0, 1.0), (1.7, -1.0), (2.6, 1.0)] {
                    check_lanes::<8>(&quadric, settled, (y, sheet), x).unwrap();
                }
            }
        }
    }
}
