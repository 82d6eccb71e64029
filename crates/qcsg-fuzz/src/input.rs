//! Input `i` of a run: its bytes, the name it is checked under and its per-input options, all
//! drawn from the run's seed and `i` alone ([`Dice::for_input`]).
//!
//! Two inputs in five are generated programs ([`crate::generate`]), one in ten a generated
//! program mutated, the rest mutated corpus files ([`crate::mutate`]). A generated program is
//! checked as `main.qcsg` in the run's library directory ([`crate::libs`]); a mutated file under
//! its own path, so its includes resolve as they do for the original.

use std::path::{Path, PathBuf};

use crate::corpus::Corpus;
use crate::dice::Dice;
use crate::generate;
use crate::mutate;
use crate::protocol::Radius;

/// One input and how to run it.
#[derive(Clone, Debug)]
pub struct Input {
    /// Its index in the run.
    pub index: u64,
    /// The program's bytes (not necessarily UTF-8).
    pub bytes: Vec<u8>,
    /// The path it is checked under.
    pub name: PathBuf,
    /// The sampler's radius.
    pub radius: Radius,
    /// Seeds the language server session.
    pub session_seed: u64,
    /// Where it came from, for reports.
    pub origin: String,
}

/// Builds input `index` of the run seeded with `seed`.
pub fn make(seed: u64, index: u64, corpus: &Corpus, libs: &Path) -> Input {
    let mut dice = Dice::for_input(seed, index);
    let choice = dice.below(10);
    let (bytes, name, origin) = if choice < 4 || corpus.is_empty() {
        let text = generate::program(&mut dice);
        (
            text.into_bytes(),
            libs.join("main.qcsg"),
            "generated".to_owned(),
        )
    } else if choice == 4 {
        let text = generate::program(&mut dice);
        let (bytes, mutations) = mutate::mutate(&mut dice, text.as_bytes(), b"");
        let origin = format!("generated, then mutated by {mutations:?}");
        (bytes, libs.join("main.qcsg"), origin)
    } else {
        let file = &corpus.files[dice.below(corpus.files.len())];
        let other = &corpus.files[dice.below(corpus.files.len())];
        let (bytes, mutations) = mutate::mutate(&mut dice, &file.bytes, &other.bytes);
        let origin = format!(
            "{} mutated by {mutations:?} (splice source {})",
            file.path.display(),
            other.path.display()
        );
        (bytes, file.path.clone(), origin)
    };
    let radius = match dice.below(20) {
        0 | 1 => Radius::OfDiagonal(0.01),
        2 => Radius::OfDiagonal(1e-4),
        3 => Radius::Absolute(1e-9),
        4 => Radius::Absolute(0.05 + dice.unit() * 5.0),
        _ => Radius::OfDiagonal(0.05),
    };
    Input {
        index,
        bytes,
        name,
        radius,
        session_seed: dice.next_u64(),
        origin,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_input_depends_on_the_seed_and_index_only() {
        let corpus = Corpus::load(&crate::corpus::default_root());
        let libs = Path::new("/tmp/libs");
        for index in 0..20 {
            let a = make(11, index, &corpus, libs);
            let b = make(11, index, &corpus, libs);
            assert_eq!(
                (a.bytes, a.name, a.session_seed),
                (b.bytes, b.name, b.session_seed)
            );
        }
    }
}
