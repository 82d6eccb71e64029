//! The one diagnostic type of qcsg, shared by every stage from the lexer to the sampler.
//!
//! A [`Diagnostic`] is plain data: a severity, a stable code, a message, a primary byte [`Span`]
//! in a file known to [`SourceMap`], optional help and secondary labels. Terminal rendering (miette)
//! lives in the CLI and LSP conversion in the language server; both read positions through
//! [`LineIndex`], which maps byte offsets to zero-based lines and UTF-16 columns as LSP expects.

mod line_index;
mod source_map;

pub use line_index::{LineCol, LineIndex};
pub use source_map::{FileId, SourceFile, SourceMap};

use serde::Serialize;

/// A half-open byte range `start..end` into one source file.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
pub struct Span {
    /// First byte of the range.
    pub start: u32,
    /// One past the last byte of the range.
    pub end: u32,
}

impl Span {
    /// The span `start..end`.
    pub fn new(start: usize, end: usize) -> Self {
        debug_assert!(start <= end, "span start {start} after end {end}");
        Self {
            start: start as u32,
            end: end as u32,
        }
    }

    /// An empty span at `offset` (for "expected `;` here" at the end of a line).
    pub fn empty(offset: usize) -> Self {
        Self::new(offset, offset)
    }

    /// The smallest span covering both `self` and `other`.
    pub fn cover(self, other: Span) -> Self {
        Self {
            start: self.start.min(other.start),
            end: self.end.max(other.end),
        }
    }

    /// Length in bytes.
    pub fn len(self) -> usize {
        (self.end - self.start) as usize
    }

    /// Whether the span covers no byte.
    pub fn is_empty(self) -> bool {
        self.start == self.end
    }

    /// Whether `offset` lies inside the span (an empty span contains its own offset).
    pub fn contains(self, offset: usize) -> bool {
        let offset = offset as u32;
        self.start <= offset && (offset < self.end || (self.is_empty() && offset == self.start))
    }

    /// The span as a `Range<usize>` for slicing the source text.
    pub fn range(self) -> std::ops::Range<usize> {
        self.start as usize..self.end as usize
    }
}

impl From<std::ops::Range<usize>> for Span {
    fn from(range: std::ops::Range<usize>) -> Self {
        Span::new(range.start, range.end)
    }
}

/// How serious a diagnostic is. The order is from most to least severe.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Severity {
    /// The input is wrong: `qcsg check` exits 1.
    Error,
    /// Probably a mistake, but the input has a meaning.
    Warning,
    /// Information, such as the output of `echo`.
    Info,
    /// A suggestion, such as "`$fn` has no effect on exact surfaces".
    Hint,
}

impl Severity {
    /// The lower-case name used in JSON output and messages.
    pub fn as_str(self) -> &'static str {
        match self {
            Severity::Error => "error",
            Severity::Warning => "warning",
            Severity::Info => "info",
            Severity::Hint => "hint",
        }
    }
}

/// A secondary location attached to a diagnostic, such as "defined here".
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Label {
    /// The file the label points into (often, but not always, the diagnostic's own file).
    pub file: FileId,
    /// The labelled byte range.
    pub span: Span,
    /// What the range has to do with the diagnostic.
    pub message: String,
}

/// One problem (or piece of information) found in a source file.
///
/// `code` is stable across releases and documented in `docs/language.md`: tools and tests match on
/// it, never on the message.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Diagnostic {
    /// How serious it is.
    pub severity: Severity,
    /// Stable code such as `E0101`.
    pub code: &'static str,
    /// One-line description, lower case, no trailing period.
    pub message: String,
    /// The file of the primary span.
    pub file: FileId,
    /// The primary span: where the problem is.
    pub span: Span,
    /// How to fix it, when there is something useful to say.
    pub help: Option<String>,
    /// Secondary locations.
    pub labels: Vec<Label>,
}

impl Diagnostic {
    /// A diagnostic with no help and no labels.
    pub fn new(
        severity: Severity,
        code: &'static str,
        message: impl Into<String>,
        file: FileId,
        span: Span,
    ) -> Self {
        Self {
            severity,
            code,
            message: message.into(),
            file,
            span,
            help: None,
            labels: Vec::new(),
        }
    }

    /// An error at `span`.
    pub fn error(code: &'static str, message: impl Into<String>, file: FileId, span: Span) -> Self {
        Self::new(Severity::Error, code, message, file, span)
    }

    /// A warning at `span`.
    pub fn warning(
        code: &'static str,
        message: impl Into<String>,
        file: FileId,
        span: Span,
    ) -> Self {
        Self::new(Severity::Warning, code, message, file, span)
    }

    /// Adds help text.
    pub fn with_help(mut self, help: impl Into<String>) -> Self {
        self.help = Some(help.into());
        self
    }

    /// Adds a secondary label.
    pub fn with_label(mut self, file: FileId, span: Span, message: impl Into<String>) -> Self {
        self.labels.push(Label {
            file,
            span,
            message: message.into(),
        });
        self
    }

    /// Whether this diagnostic makes the input invalid.
    pub fn is_error(&self) -> bool {
        self.severity == Severity::Error
    }
}

/// Sorts diagnostics into a stable, reader-friendly order: by file, then position, then code.
pub fn sort_diagnostics(diagnostics: &mut [Diagnostic]) {
    diagnostics.sort_by(|a, b| {
        (a.file, a.span.start, a.span.end, a.code, &a.message).cmp(&(
            b.file,
            b.span.start,
            b.span.end,
            b.code,
            &b.message,
        ))
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn span_cover_and_contains() {
        let a = Span::new(3, 5);
        let b = Span::new(8, 9);
        assert_eq!(a.cover(b), Span::new(3, 9));
        assert!(a.contains(3) && a.contains(4) && !a.contains(5));
        assert!(Span::empty(7).contains(7));
    }
}
