//! Editor analyses of qcsg programs: diagnostics, hover, navigation, symbols, completion,
//! signature help, semantic tokens, inlay hints, folding, code actions and formatting.
//!
//! Everything here is plain data in editor coordinates (zero-based lines, UTF-16 columns, as
//! [`LineCol`]); the language server (`qcsg-lsp`) only converts these structs to LSP types, and
//! no LSP type appears in this crate. An [`Analysis`] is one checked snapshot of a document: it is
//! immutable, cheap to share between requests, and every query on it is a pure function.
//! What needs evaluation (runtime diagnostics, the quadrics a call becomes) comes from the
//! language server through [`HoverExtension`] and [`Analysis::present`]: this crate depends on
//! the syntax and the checker only.

mod actions;
mod arguments;
mod call_site;
mod completion;
mod consteval;
mod diagnostics;
mod folding;
pub mod format;
mod hover;
mod inlay;
mod navigation;
mod signature;
mod symbols;
mod tokens;
mod walk;

use std::path::Path;

pub use actions::{CodeAction, TextEdit};
pub use completion::{CompletionItem, CompletionKind};
pub use diagnostics::{IdeDiagnostic, RelatedInfo};
pub use folding::{FoldKind, FoldingRange};
pub use hover::{Hover, HoverExtension};
pub use inlay::{InlayHint, InlayKind};
pub use navigation::{RenameError, RenameTarget};
pub use qcsg_diag::{FileId, LineCol, Severity, Span};
pub use qcsg_sema::{CheckOptions, FileLoader, FsLoader};
pub use signature::{SignatureHelp, SignatureParam};
pub use symbols::{Symbol, SymbolKind};
pub use tokens::{SemanticToken, TokenKind, TokenModifiers};

/// A range of one file in editor coordinates.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct TextRange {
    /// Where it starts.
    pub start: LineCol,
    /// Where it ends (exclusive).
    pub end: LineCol,
}

/// A range in a named file (the main document or a file it includes or uses).
#[derive(Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct FileRange {
    /// The file's path as the checker knows it (the document's own path for the main file).
    pub file: String,
    /// The range in that file.
    pub range: TextRange,
}

/// One checked snapshot of a document and everything it includes or uses.
#[derive(Debug)]
pub struct Analysis {
    sema: qcsg_sema::Analysis,
}

impl Analysis {
    /// Parses and checks the document at `path` whose current text is `text`; `loader` serves the
    /// files it includes or uses (open editor buffers first, then the disk).
    pub fn new(path: &str, text: String, options: &CheckOptions, loader: &dyn FileLoader) -> Self {
        Self {
            sema: qcsg_sema::check_file(path, text, options, loader),
        }
    }

    /// Checks `text` as a file at `path` whose includes are read from the file system.
    pub fn from_disk(path: impl AsRef<Path>, text: String) -> Self {
        let path = path.as_ref().to_string_lossy().into_owned();
        Self::new(&path, text, &CheckOptions::default(), &FsLoader)
    }

    /// The checker's result, for analyses this crate does not offer.
    pub fn sema(&self) -> &qcsg_sema::Analysis {
        &self.sema
    }

    /// The main document's text.
    pub fn text(&self) -> &str {
        &self.sema.sources.get(self.sema.main).text
    }

    /// The main document's file handle.
    pub fn main(&self) -> FileId {
        self.sema.main
    }

    /// The byte offset of an editor position in the main document (clamped to the text).
    pub fn offset(&self, position: LineCol) -> usize {
        let file = self.sema.sources.get(self.sema.main);
        file.line_index.offset(&file.text, position)
    }

    /// The editor position of a byte offset in `file`.
    pub fn position(&self, file: FileId, offset: usize) -> LineCol {
        let source = self.sema.sources.get(file);
        source.line_index.line_col(&source.text, offset)
    }

    /// The editor range of a byte span in `file`.
    pub fn range(&self, file: FileId, span: Span) -> TextRange {
        TextRange {
            start: self.position(file, span.start as usize),
            end: self.position(file, span.end as usize),
        }
    }

    /// A span of `file` as a [`FileRange`].
    pub fn file_range(&self, file: FileId, span: Span) -> FileRange {
        FileRange {
            file: self.sema.sources.get(file).name.clone(),
            range: self.range(file, span),
        }
    }

    /// The main document's tree.
    pub(crate) fn tree(&self) -> &qcsg_syntax::SourceFile {
        &self.sema.trees[self.sema.main.0 as usize]
    }
}
