//! Trigonometry in degrees exactly as OpenSCAD 2021.01 computes it, and its random numbers.
//!
//! Angles are reduced to `[0, 360)` and folded into the first quadrant first, so multiples of 90°
//! give exactly 0 and ±1, and 30°, 45° and 60° give the same doubles as OpenSCAD (`sin(30) ==
//! 0.5`, `cos(60) == 0.5`, `sin(45) == sqrt(2) / 2`, `tan(45) == 1`). [`Mt19937`] is the
//! 32-bit Mersenne Twister behind `rands(min, max, n, seed)`.

use std::f64::consts::{FRAC_1_SQRT_2, PI};

const SQRT3_2: f64 = 0.866_025_403_784_438_6;
const SQRT3: f64 = 1.732_050_807_568_877_2;

fn deg2rad(x: f64) -> f64 {
    x * PI / 180.0
}

/// Radians to degrees as OpenSCAD converts them.
pub fn rad2deg(x: f64) -> f64 {
    x * 180.0 / PI
}

/// Reduces an angle to `[0, 360)` (NaN and ±∞ become NaN).
fn reduce(mut x: f64) -> f64 {
    if (0.0..360.0).contains(&x) {
    } else if (-360.0..360.0).contains(&x) {
        x += 360.0;
    } else {
        x %= 360.0;
        if x < 0.0 {
            x += 360.0;
        }
    }
    x
}

/// `sin` of an angle in degrees.
pub fn sin_degrees(x: f64) -> f64 {
    let mut x = reduce(x);
    let oppose = x >= 180.0;
    if oppose {
        x -= 180.0;
    }
    if x > 90.0 {
        x = 180.0 - x;
    }
    let s = if x < 45.0 {
        if x == 30.0 { 0.5 } else { deg2rad(x).sin() }
    } else if x == 45.0 {
        FRAC_1_SQRT_2
    } else if x == 60.0 {
        SQRT3_2
    } else {
        deg2rad(90.0 - x).cos()
    };
    if oppose { -s } else { s }
}

/// `cos` of an angle in degrees.
pub fn cos_degrees(x: f64) -> f64 {
    let mut x = reduce(x);
    let mut oppose = x >= 180.0;
    if oppose {
        x -= 180.0;
    }
    if x > 90.0 {
        x = 180.0 - x;
        oppose = !oppose;
    }
    let c = if x > 45.0 {
        if x == 60.0 {
            0.5
        } else {
            deg2rad(90.0 - x).sin()
        }
    } else if x == 45.0 {
        FRAC_1_SQRT_2
    } else if x == 30.0 {
        SQRT3_2
    } else {
        deg2rad(x).cos()
    };
    if oppose { -c } else { c }
}

/// `tan` of an angle in degrees: exact at multiples of 45° and at ±60°, `inf` at 90° + k·180°.
pub fn tan_degrees(x: f64) -> f64 {
    if !x.is_finite() {
        return f64::NAN;
    }
    let reduced = x - (x / 180.0).floor() * 180.0;
    let special = [
        (0.0, 0.0),
        (45.0, 1.0),
        (60.0, SQRT3),
        (90.0, f64::INFINITY),
        (120.0, -SQRT3),
        (135.0, -1.0),
    ];
    special
        .iter()
        .find(|(angle, _)| *angle == reduced)
        .map_or_else(|| deg2rad(x).tan(), |&(_, value)| value)
}

/// The 32-bit Mersenne Twister (`std::mt19937`), seeded as C++ seeds it.
pub struct Mt19937 {
    state: [u32; 624],
    index: usize,
}

impl Mt19937 {
    /// The generator seeded with `seed`.
    pub fn new(seed: u32) -> Self {
        let mut state = [0u32; 624];
        state[0] = seed;
        for i in 1..624 {
            let prev = state[i - 1];
            state[i] = 1_812_433_253u32
                .wrapping_mul(prev ^ (prev >> 30))
                .wrapping_add(i as u32);
        }
        Self { state, index: 624 }
    }

    fn twist(&mut self) {
        for i in 0..624 {
            let y = (self.state[i] & 0x8000_0000) | (self.state[(i + 1) % 624] & 0x7fff_ffff);
            let mut next = self.state[(i + 397) % 624] ^ (y >> 1);
            if y & 1 != 0 {
                next ^= 0x9908_b0df;
            }
            self.state[i] = next;
        }
        self.index = 0;
    }

    /// The next 32-bit output.
    pub fn next_u32(&mut self) -> u32 {
        if self.index >= 624 {
            self.twist();
        }
        let mut y = self.state[self.index];
        self.index += 1;
        y ^= y >> 11;
        y ^= (y << 7) & 0x9d2c_5680;
        y ^= (y << 15) & 0xefc6_0000;
        y ^= y >> 18;
        y
    }

    /// A uniform double in `[min, max)` as libstdc++'s `uniform_real_distribution<double>`
    /// draws it: `generate_canonical` from two 32-bit outputs, then `u · (max − min) + min`.
    pub fn uniform(&mut self, min: f64, max: f64) -> f64 {
        const R: f64 = 4_294_967_296.0;
        let low = self.next_u32() as f64;
        let high = self.next_u32() as f64;
        let mut u = (low + high * R) / (R * R);
        if u >= 1.0 {
            u = 1.0 - f64::EPSILON / 2.0;
        }
        u * (max - min) + min
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_angles() {
        assert_eq!(sin_degrees(90.0), 1.0);
        assert_eq!(cos_degrees(90.0), 0.0);
        assert_eq!(cos_degrees(180.0), -1.0);
        assert_eq!(sin_degrees(180.0), 0.0);
        assert_eq!(sin_degrees(-90.0), -1.0);
        assert_eq!(cos_degrees(270.0), 0.0);
        assert_eq!(sin_degrees(30.0), 0.5);
        assert_eq!(cos_degrees(60.0), 0.5);
        assert_eq!(sin_degrees(150.0), 0.5);
        assert_eq!(cos_degrees(120.0), -0.5);
        assert_eq!(sin_degrees(-30.0), -0.5);
        assert_eq!(sin_degrees(60.0), 3f64.sqrt() / 2.0);
        assert_eq!(sin_degrees(45.0), 2f64.sqrt() / 2.0);
        assert_eq!(cos_degrees(45.0), sin_degrees(45.0));
        assert_eq!(tan_degrees(45.0), 1.0);
        assert_eq!(tan_degrees(135.0), -1.0);
        assert_eq!(tan_degrees(60.0), 3f64.sqrt());
        assert_eq!(tan_degrees(90.0), f64::INFINITY);
        assert_eq!(cos_degrees(720.0), 1.0);
        assert_eq!(sin_degrees(-450.0), -1.0);
        assert!(sin_degrees(f64::INFINITY).is_nan());
        assert!((sin_degrees(1e10) - -0.984808).abs() < 1e-6);
    }

    #[test]
    fn mersenne_twister_reference_output() {
        // The C++ standard requires the 10000th output of a default-seeded mt19937.
        let mut mt = Mt19937::new(5489);
        let mut last = 0;
        for _ in 0..10000 {
            last = mt.next_u32();
        }
        assert_eq!(last, 4_123_659_995);
    }

    #[test]
    fn rands_match_openscad() {
        // OpenSCAD 2021.01: rands(0, 1, 3, 42) and rands(0, 10, 2, 1).
        let mut mt = Mt19937::new(42);
        let got: Vec<String> = (0..3)
            .map(|_| crate::value::format_number(mt.uniform(0.0, 1.0)))
            .collect();
        assert_eq!(got, ["0.796543", "0.183435", "0.779691"]);
        let mut mt = Mt19937::new(1);
        let got: Vec<String> = (0..2)
            .map(|_| crate::value::format_number(mt.uniform(0.0, 10.0)))
            .collect();
        assert_eq!(got, ["9.97185", "9.32557"]);
    }
}
