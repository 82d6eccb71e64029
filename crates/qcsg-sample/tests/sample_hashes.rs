//! The samples of every example scene, to the bit: each scene of `examples/` is sampled at 1 %
//! and 0.2 % of its diagonal, and a hash of every sample's bits (position, normal, quadric,
//! term, radius, clip list) and of the clip lists is compared with the recorded one.
//!
//! A change that should not move a single sample (a refactoring, a faster kernel) must leave
//! these hashes as they are. A change that means to move samples updates them in the same
//! commit and says why; `QCSG_PRINT_SAMPLE_HASHES=1` prints the table to paste.
//!
//! The run takes a while in a debug build; `cargo test -p qcsg-sample --release --test
//! sample_hashes` is the quick way.

mod common;

use common::{compile_file, diagonal, programs_in};
use qcsg_sample::{Sample, Sampling, sample};

/// Radii relative to each scene's diagonal.
const RELATIVE_RADII: [f64; 2] = [0.01, 0.002];

/// (scene, relative radius, sample count, hash), as recorded.
const RECORDED: &[(&str, f64, usize, u64)] = &[
    ("chess_bishop.qcsg", 0.01, 10764, 0x0956646bd70309e5),
    ("chess_bishop.qcsg", 0.002, 151867, 0x740e8b217263c6c6),
    ("colours.qcsg", 0.01, 12695, 0xa92d6839690d969a),
    ("colours.qcsg", 0.002, 165370, 0x603512f82795ea44),
    ("customizer_box.qcsg", 0.01, 14836, 0x517bce4e925921c1),
    ("customizer_box.qcsg", 0.002, 259597, 0x517dbaae8ed55389),
    ("machined_block.qcsg", 0.01, 39447, 0x1a6cf7f366bea6a9),
    ("machined_block.qcsg", 0.002, 629081, 0x9d270a92159fce1f),
    ("modifiers.qcsg", 0.01, 38961, 0x0ae30bb802165234),
    ("modifiers.qcsg", 0.002, 622884, 0x5ee97994826b11e5),
    ("molecule_cage.qcsg", 0.01, 15985, 0x902a1388163bb8e0),
    ("molecule_cage.qcsg", 0.002, 182585, 0x5b26ecfc2843093d),
    ("openscad_bracket.scad", 0.01, 12810, 0xc5aa2e1510801cdf),
    ("openscad_bracket.scad", 0.002, 226050, 0x8b13c403de583f22),
    ("platonic_solids.qcsg", 0.01, 8720, 0xa891c8fda5de3dd5),
    ("platonic_solids.qcsg", 0.002, 121525, 0x0e100044b2b84352),
    ("precision_part.qcsg", 0.01, 18755, 0xfba4017f1a09371c),
    ("precision_part.qcsg", 0.002, 334268, 0x6df12a2e4069202c),
    ("quadric_primitives.qcsg", 0.01, 3939, 0x8e0e9e1745a48f19),
    ("quadric_primitives.qcsg", 0.002, 52908, 0xa05d288c95aa5d0d),
    ("raw_quadrics.qcsg", 0.01, 5054, 0x69bf52b49ddda311),
    ("raw_quadrics.qcsg", 0.002, 73552, 0xb49b6b9e7b30f394),
    ("recursive_tree.qcsg", 0.01, 19380, 0x5b3be287241ca54c),
    ("recursive_tree.qcsg", 0.002, 242599, 0x015c981ccbff3b27),
    ("reuleaux.qcsg", 0.01, 4052, 0xdb967b22aa9297d4),
    ("reuleaux.qcsg", 0.002, 61208, 0x6699145e1506a916),
    ("rocket.qcsg", 0.01, 6541, 0x698ac3a6ed847aed),
    ("rocket.qcsg", 0.002, 92523, 0xce7f2f3f745ec35d),
    ("spiral_staircase.qcsg", 0.01, 7792, 0x0a9a06d0b0df4d89),
    ("spiral_staircase.qcsg", 0.002, 103479, 0x9e039ad7c2553ce9),
    ("three_spheres.qcsg", 0.01, 6411, 0x7196b1a40885f1d3),
    ("three_spheres.qcsg", 0.002, 110876, 0xdd68dd060d932d68),
    ("unbounded_clipped.qcsg", 0.01, 9069, 0x2de363940a7600eb),
    ("unbounded_clipped.qcsg", 0.002, 157140, 0x6b31a29a7a77e315),
    ("wheel.qcsg", 0.01, 13649, 0xb8917a59617579c3),
    ("wheel.qcsg", 0.002, 198944, 0x77e5d0f90fbfa80a),
];

/// FNV-1a over 64-bit words: stable across platforms and releases, unlike `DefaultHasher`.
struct Fnv(u64);

impl Fnv {
    fn new() -> Self {
        Self(0xcbf2_9ce4_8422_2325)
    }

    fn word(&mut self, word: u64) {
        for byte in word.to_le_bytes() {
            self.0 ^= u64::from(byte);
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }

    fn sample(&mut self, s: &Sample) {
        for v in [s.position, s.normal] {
            for c in v.to_array() {
                self.word(c.to_bits());
            }
        }
        self.word(u64::from(s.quadric));
        self.word(u64::from(s.term));
        self.word(s.radius.to_bits());
        self.word(u64::from(s.clip_list));
    }
}

fn hash(sampling: &Sampling) -> u64 {
    let mut fnv = Fnv::new();
    for s in sampling.samples.iter() {
        fnv.sample(s);
    }
    for &offset in &sampling.clip_lists.offsets {
        fnv.word(u64::from(offset));
    }
    for &index in &sampling.clip_lists.indices {
        fnv.word(u64::from(index));
    }
    fnv.0
}

#[test]
fn every_example_samples_to_the_bit() {
    let mut found = Vec::new();
    for path in programs_in("examples") {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let dnf = compile_file(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        for relative in RELATIVE_RADII {
            let sampling = sample(&dnf, relative * diagonal(&dnf))
                .unwrap_or_else(|e| panic!("{name} at {relative}: {e}"));
            found.push((
                name.clone(),
                relative,
                sampling.samples.len(),
                hash(&sampling),
            ));
        }
    }
    let table: String = (found.iter())
        .map(|(name, relative, count, hash)| {
            format!("    ({name:?}, {relative:?}, {count}, {hash:#018x}),\n")
        })
        .collect();
    if std::env::var_os("QCSG_PRINT_SAMPLE_HASHES").is_some() {
        eprintln!("{table}");
    }
    let recorded: Vec<(String, f64, usize, u64)> = (RECORDED.iter())
        .map(|&(name, relative, count, hash)| (name.to_owned(), relative, count, hash))
        .collect();
    assert_eq!(found, recorded, "samples changed; now:\n{table}");
}
