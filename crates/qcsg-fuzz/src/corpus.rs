//! The seed corpus for mutation: every `.qcsg` and `.scad` file under the workspace's
//! `examples/` and `tests/`.
//!
//! Files are kept with their paths, so that a mutated file is checked under its own name and its
//! `include <lib/…>` statements still find the libraries beside it.

use std::path::{Path, PathBuf};

/// One corpus file.
#[derive(Clone, Debug)]
pub struct CorpusFile {
    /// Its path.
    pub path: PathBuf,
    /// Its contents.
    pub bytes: Vec<u8>,
}

/// The corpus, in a stable order (sorted by path) so that a seed means the same inputs.
#[derive(Clone, Debug, Default)]
pub struct Corpus {
    /// The files.
    pub files: Vec<CorpusFile>,
}

impl Corpus {
    /// Every program under `root/examples` and `root/tests`.
    pub fn load(root: &Path) -> Self {
        let mut paths = Vec::new();
        for dir in ["examples", "tests"] {
            collect(&root.join(dir), &mut paths);
        }
        paths.sort();
        let files = paths
            .into_iter()
            .filter_map(|path| {
                let bytes = std::fs::read(&path).ok()?;
                Some(CorpusFile { path, bytes })
            })
            .collect();
        Self { files }
    }

    /// Whether there is nothing to mutate.
    pub fn is_empty(&self) -> bool {
        self.files.is_empty()
    }
}

/// Appends the programs under `dir` (recursively) to `out`.
fn collect(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        let Ok(kind) = entry.file_type() else {
            continue;
        };
        if kind.is_dir() {
            collect(&path, out);
        } else if kind.is_file()
            && matches!(
                path.extension().and_then(|e| e.to_str()),
                Some("qcsg" | "scad")
            )
        {
            out.push(path);
        }
    }
}

/// The workspace this harness was built in (`crates/qcsg-fuzz/../..`).
pub fn default_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_workspace_corpus_has_examples_and_tests() {
        let corpus = Corpus::load(&default_root());
        let has = |part: &str| {
            corpus
                .files
                .iter()
                .any(|f| f.path.to_string_lossy().contains(part))
        };
        assert!(
            has("/examples/") && has("/tests/"),
            "{} files",
            corpus.files.len()
        );
        assert!(corpus.files.windows(2).all(|w| w[0].path < w[1].path));
    }
}
