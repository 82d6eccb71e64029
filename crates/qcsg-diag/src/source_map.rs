//! The set of source files a run has read, addressed by [`FileId`].

use crate::LineIndex;

/// Handle of a file in a [`SourceMap`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct FileId(pub u32);

/// One source file: its name as shown to users, its text and its line index.
#[derive(Clone, Debug)]
pub struct SourceFile {
    /// The path as given (or `<stdin>`), used in messages and JSON output.
    pub name: String,
    /// The full text.
    pub text: String,
    /// Line starts of `text`.
    pub line_index: LineIndex,
}

/// All files of one run (the main file and everything it includes or uses).
#[derive(Clone, Debug, Default)]
pub struct SourceMap {
    files: Vec<SourceFile>,
}

impl SourceMap {
    /// An empty map.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a file and returns its handle.
    pub fn add(&mut self, name: impl Into<String>, text: impl Into<String>) -> FileId {
        let text = text.into();
        let line_index = LineIndex::new(&text);
        self.files.push(SourceFile {
            name: name.into(),
            text,
            line_index,
        });
        FileId(self.files.len() as u32 - 1)
    }

    /// The file behind a handle.
    ///
    /// # Panics
    /// If the handle came from another map.
    pub fn get(&self, id: FileId) -> &SourceFile {
        &self.files[id.0 as usize]
    }

    /// Finds a file by the name it was added under.
    pub fn find(&self, name: &str) -> Option<FileId> {
        self.files
            .iter()
            .position(|f| f.name == name)
            .map(|i| FileId(i as u32))
    }

    /// All files with their handles.
    pub fn iter(&self) -> impl Iterator<Item = (FileId, &SourceFile)> {
        self.files
            .iter()
            .enumerate()
            .map(|(i, f)| (FileId(i as u32), f))
    }
}
