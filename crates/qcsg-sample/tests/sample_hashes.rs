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
    ("chess_bishop.qcsg", 0.01, 11278, 0xdc57aa34caec6c16),
    ("chess_bishop.qcsg", 0.002, 151876, 0x704bdc05111bc6ba),
    ("colours.qcsg", 0.01, 12621, 0x610d4ba91d17d3e8),
    ("colours.qcsg", 0.002, 167463, 0x996647321cdcd84b),
    ("customizer_box.qcsg", 0.01, 14773, 0xec5767da266e3fce),
    ("customizer_box.qcsg", 0.002, 259773, 0xb6174aa45780ee02),
    ("laser_cut_plate.scad", 0.01, 24724, 0x0ad64b28b54db80b),
    ("laser_cut_plate.scad", 0.002, 423985, 0x63cc944f66add0ac),
    ("machined_block.qcsg", 0.01, 39488, 0x33913094acd5da32),
    ("machined_block.qcsg", 0.002, 629743, 0xe74696b506c5a4f1),
    ("modifiers.qcsg", 0.01, 38944, 0x9ba20f758a0331bd),
    ("modifiers.qcsg", 0.002, 622796, 0x6711d5c71f8815dd),
    ("molecule_cage.qcsg", 0.01, 15468, 0x871584e3ed52bb9e),
    ("molecule_cage.qcsg", 0.002, 185000, 0xe59c130ff3da3bec),
    ("openscad_bracket.scad", 0.01, 12842, 0x33087a72fa53863b),
    ("openscad_bracket.scad", 0.002, 226050, 0xd723cb4b8f60cc0e),
    ("platonic_solids.qcsg", 0.01, 8720, 0xa891c8fda5de3dd5),
    ("platonic_solids.qcsg", 0.002, 121525, 0x0e100044b2b84352),
    ("precision_part.qcsg", 0.01, 18759, 0x5be8894a8fa3bff3),
    ("precision_part.qcsg", 0.002, 334292, 0x92edabb4d16b2aba),
    ("quadric_primitives.qcsg", 0.01, 4193, 0xa19f76652f67f357),
    ("quadric_primitives.qcsg", 0.002, 53065, 0xbef0df28d16d55b0),
    ("raw_quadrics.qcsg", 0.01, 5132, 0xb2685a97cb694221),
    ("raw_quadrics.qcsg", 0.002, 73636, 0xd6b610ecf62e513f),
    ("recursive_tree.qcsg", 0.01, 20757, 0x455e07391b97cdfe),
    ("recursive_tree.qcsg", 0.002, 241150, 0x0f54bfad3136b376),
    ("reuleaux.qcsg", 0.01, 4076, 0xf74860f6e22bed0c),
    ("reuleaux.qcsg", 0.002, 61208, 0x8da7c2d561210696),
    ("rocket.qcsg", 0.01, 6658, 0xd05813ea146525ed),
    ("rocket.qcsg", 0.002, 92853, 0x441a4ad2e9de569d),
    ("spiral_staircase.qcsg", 0.01, 8631, 0xf2d61b8cf77e0d91),
    ("spiral_staircase.qcsg", 0.002, 102637, 0x6e05d40fdd928422),
    ("three_spheres.qcsg", 0.01, 6471, 0xca583dbd2718a577),
    ("three_spheres.qcsg", 0.002, 110806, 0x638aeec91f73e958),
    ("turned_part.scad", 0.01, 15361, 0x6ded7cca9e9126e4),
    ("turned_part.scad", 0.002, 242140, 0x9642d9b2ddadd11a),
    ("unbounded_clipped.qcsg", 0.01, 9110, 0x5aba8cf8be5b9294),
    ("unbounded_clipped.qcsg", 0.002, 156870, 0x5656eda39055b6f7),
    ("wheel.qcsg", 0.01, 13640, 0xda814ba2f14242d6),
    ("wheel.qcsg", 0.002, 198924, 0x2eedfe8b7ca8e8ee),
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
