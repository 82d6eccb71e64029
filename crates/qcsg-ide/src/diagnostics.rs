//! The main document's diagnostics in editor coordinates.

use qcsg_diag::{Diagnostic, Severity};
use qcsg_sema::codes;

use crate::{Analysis, FileRange, TextRange};

/// A diagnostic of the main document.
#[derive(Clone, Debug, PartialEq)]
pub struct IdeDiagnostic {
    /// How serious it is.
    pub severity: Severity,
    /// The stable code such as `E0101`.
    pub code: &'static str,
    /// The message, with the help text on a second line when there is one.
    pub message: String,
    /// Where it is.
    pub range: TextRange,
    /// Secondary locations from the diagnostic's labels (possibly in other files).
    pub related: Vec<RelatedInfo>,
    /// Whether it flags code that does nothing (unused names, disabled subtrees): editors fade it.
    pub unnecessary: bool,
}

/// A secondary location of a diagnostic.
#[derive(Clone, Debug, PartialEq)]
pub struct RelatedInfo {
    /// Where.
    pub location: FileRange,
    /// What it has to do with the diagnostic.
    pub message: String,
}

impl Analysis {
    /// The diagnostics whose primary span is in the main document, in source order.
    pub fn diagnostics(&self) -> Vec<IdeDiagnostic> {
        self.sema
            .diagnostics
            .iter()
            .filter(|d| d.file == self.sema.main)
            .map(|d| self.convert(d))
            .collect()
    }

    fn convert(&self, diagnostic: &Diagnostic) -> IdeDiagnostic {
        let message = match &diagnostic.help {
            Some(help) => format!("{}\nhelp: {help}", diagnostic.message),
            None => diagnostic.message.clone(),
        };
        IdeDiagnostic {
            severity: diagnostic.severity,
            code: diagnostic.code,
            message,
            range: self.range(diagnostic.file, diagnostic.span),
            related: diagnostic
                .labels
                .iter()
                .map(|label| RelatedInfo {
                    location: self.file_range(label.file, label.span),
                    message: label.message.clone(),
                })
                .collect(),
            unnecessary: matches!(
                diagnostic.code,
                codes::UNUSED_VARIABLE
                    | codes::UNUSED_PARAMETER
                    | codes::UNUSED_MODULE
                    | codes::UNUSED_FUNCTION
                    | codes::DISABLED_SUBTREE
            ),
        }
    }
}
