//! Files from memory for `include` / `use`, as a language server's unsaved buffers are.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use qcsg_sema::FileLoader;

/// A [`FileLoader`] over files held in memory; any other path is not found.
#[derive(Clone, Debug, Default)]
pub struct MemoryFiles(HashMap<PathBuf, String>);

impl MemoryFiles {
    /// No files.
    pub fn new() -> Self {
        Self::default()
    }

    /// These files, and `text` at `path`.
    pub fn with(mut self, path: impl Into<PathBuf>, text: impl Into<String>) -> Self {
        self.0.insert(path.into(), text.into());
        self
    }
}

impl FileLoader for MemoryFiles {
    fn load(&self, path: &Path) -> std::io::Result<String> {
        self.0
            .get(path)
            .cloned()
            .ok_or_else(|| std::io::ErrorKind::NotFound.into())
    }
}
