//! The harness's one source of randomness: a seeded ChaCha8 stream behind a few plain methods.
//!
//! Every random choice of a run comes from a [`Dice`] seeded from the run's seed and the input's
//! index ([`Dice::for_input`]), so input `i` of seed `s` is the same bytes on every machine and
//! for any number of workers, and a failure can be replayed from those two numbers alone.

use rand::rngs::ChaCha8Rng;
use rand::{Rng, RngExt, SeedableRng};

/// A seeded random stream.
pub struct Dice {
    rng: ChaCha8Rng,
}

impl Dice {
    /// A stream from a seed.
    pub fn new(seed: u64) -> Self {
        Self {
            rng: ChaCha8Rng::seed_from_u64(seed),
        }
    }

    /// The stream of input `index` of the run seeded with `seed`.
    pub fn for_input(seed: u64, index: u64) -> Self {
        // Mixing (SplitMix64's finaliser) keeps neighbouring indices' streams unrelated.
        let mut z = seed ^ index.wrapping_mul(0x9E37_79B9_7F4A_7C15);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        Self::new(z ^ (z >> 31))
    }

    /// A uniformly random 64-bit number.
    pub fn next_u64(&mut self) -> u64 {
        self.rng.next_u64()
    }

    /// A number in `0..n` (0 when `n` is 0).
    pub fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            0
        } else {
            self.rng.random_range(0..n)
        }
    }

    /// A number in `low..=high`.
    pub fn between(&mut self, low: usize, high: usize) -> usize {
        if high <= low {
            low
        } else {
            self.rng.random_range(low..=high)
        }
    }

    /// True with probability `p`.
    pub fn chance(&mut self, p: f64) -> bool {
        self.rng.random_bool(p.clamp(0.0, 1.0))
    }

    /// A uniformly random float in `[0, 1)`.
    pub fn unit(&mut self) -> f64 {
        self.rng.random::<f64>()
    }

    /// One element of a non-empty slice.
    pub fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }

    /// A length drawn mostly small, sometimes large: `1 ..= max`, skewed towards 1 (a
    /// log-uniform draw), so that both typical and extreme sizes come up.
    pub fn skewed(&mut self, max: usize) -> usize {
        let max = max.max(1) as f64;
        (max.powf(self.unit()).floor() as usize).max(1)
    }

    /// A random byte.
    pub fn byte(&mut self) -> u8 {
        (self.rng.next_u32() & 0xFF) as u8
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_same_seed_and_index_give_the_same_stream() {
        let a: Vec<u64> = (0..4)
            .map({
                let mut d = Dice::for_input(7, 3);
                move |_| d.next_u64()
            })
            .collect();
        let b: Vec<u64> = (0..4)
            .map({
                let mut d = Dice::for_input(7, 3);
                move |_| d.next_u64()
            })
            .collect();
        assert_eq!(a, b);
        assert_ne!(
            Dice::for_input(7, 3).next_u64(),
            Dice::for_input(7, 4).next_u64()
        );
    }

    #[test]
    fn skewed_stays_in_range_and_reaches_both_ends() {
        let mut dice = Dice::new(1);
        let draws: Vec<usize> = (0..2000).map(|_| dice.skewed(1000)).collect();
        assert!(draws.iter().all(|&d| (1..=1000).contains(&d)));
        assert!(draws.contains(&1));
        assert!(draws.iter().any(|&d| d > 300));
    }
}
