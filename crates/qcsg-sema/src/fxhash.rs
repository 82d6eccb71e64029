//! A fast, deterministic hasher for the checker's name tables (the multiply-rotate hash of
//! rustc's `FxHasher`). Keys are identifiers and spans from local files, so resistance to
//! adversarial collisions (SipHash's reason to be slow) is not needed.
//!
//! Kept instead of the `rustc-hash` crate, whose `FxHasher` has the same step, because the two
//! hash bytes differently: this one in little-endian 64-bit words with the tail padded into one
//! word, on every target; `rustc-hash` 1.1 in native-endian `usize` words followed by 4-, 2- and
//! 1-byte tails. A scope's names are iterated in the order of their hashes, and the "did you
//! mean" search looks at them in that order; once the check's suggestion budget runs out partway
//! through a search (a program with tens of thousands of names and hundreds of misspellings),
//! which reads get a suggestion, and which one, depends on it. So this hasher keeps the checker's
//! output the same on every platform, and switching hashers would change it.

use std::collections::{HashMap, HashSet};
use std::hash::{BuildHasherDefault, Hasher};

/// The multiplier of the rotate-xor-multiply step.
const SEED: u64 = 0x51_7c_c1_b7_27_22_0a_95;

/// See the module documentation.
#[derive(Clone, Copy, Default)]
pub(crate) struct FxHasher {
    hash: u64,
}

impl FxHasher {
    fn add(&mut self, word: u64) {
        self.hash = (self.hash.rotate_left(5) ^ word).wrapping_mul(SEED);
    }
}

impl Hasher for FxHasher {
    fn write(&mut self, bytes: &[u8]) {
        let mut chunks = bytes.chunks_exact(8);
        for chunk in &mut chunks {
            let mut word = [0u8; 8];
            word.copy_from_slice(chunk);
            self.add(u64::from_le_bytes(word));
        }
        let rest = chunks.remainder();
        if !rest.is_empty() {
            let mut word = [0u8; 8];
            word[..rest.len()].copy_from_slice(rest);
            self.add(u64::from_le_bytes(word));
        }
    }

    fn write_u8(&mut self, value: u8) {
        self.add(u64::from(value));
    }

    fn write_u32(&mut self, value: u32) {
        self.add(u64::from(value));
    }

    fn write_u64(&mut self, value: u64) {
        self.add(value);
    }

    fn write_usize(&mut self, value: usize) {
        self.add(value as u64);
    }

    fn finish(&self) -> u64 {
        self.hash
    }
}

/// A `HashMap` with [`FxHasher`].
pub(crate) type FxHashMap<K, V> = HashMap<K, V, BuildHasherDefault<FxHasher>>;
/// A `HashSet` with [`FxHasher`].
pub(crate) type FxHashSet<T> = HashSet<T, BuildHasherDefault<FxHasher>>;
