//! Runtime errors and warnings: each error is reported once per code and place, a crossed limit
//! says which flag raises it, and whether an error stops the whole evaluation or only its
//! statement is decided here.

use qcsg_diag::{Diagnostic, FileId, Span};

use crate::codes;

use super::{Evaluator, R, Stop};

/// The most distinct runtime errors reported before the evaluation stops.
pub(crate) const MAX_ERRORS: usize = 50;

impl<'a> Evaluator<'a> {
    pub(super) fn error(
        &mut self,
        code: &'static str,
        message: impl Into<String>,
        file: FileId,
        span: Span,
    ) -> Stop {
        self.error_diagnostic(Diagnostic::error(code, message, file, span))
    }

    /// An error with a help text.
    pub(super) fn error_with_help(
        &mut self,
        code: &'static str,
        message: impl Into<String>,
        help: impl Into<String>,
        file: FileId,
        span: Span,
    ) -> Stop {
        self.error_diagnostic(Diagnostic::error(code, message, file, span).with_help(help))
    }

    /// Reports the error `diagnostic` (once per code and place).
    pub(super) fn error_diagnostic(&mut self, diagnostic: Diagnostic) -> Stop {
        let (code, file, span) = (diagnostic.code, diagnostic.file, diagnostic.span);
        let mut fatal = is_fatal(code);
        if self.reported.insert((code, file, span)) {
            let mut diagnostic = diagnostic;
            if let Some(flag) = limit_flag(code) {
                diagnostic = diagnostic.with_help(format!(
                    "if the program is right, raise the limit with `{flag} N` on the command line"
                ));
            }
            if self.reported.len() >= MAX_ERRORS {
                diagnostic = diagnostic.with_help(format!(
                    "evaluation stopped after {MAX_ERRORS} errors; fix these and run it again"
                ));
                fatal = true;
            }
            self.diagnostics.push(diagnostic);
        }
        Stop { fatal }
    }

    /// `result`, with a non-fatal error turned into `Ok(None)`: the caller goes on without it.
    pub(super) fn recover<T>(result: R<T>) -> R<Option<T>> {
        match result {
            Ok(value) => Ok(Some(value)),
            Err(Stop { fatal: false }) => Ok(None),
            Err(stop) => Err(stop),
        }
    }

    pub(super) fn warn(
        &mut self,
        code: &'static str,
        message: impl Into<String>,
        file: FileId,
        span: Span,
    ) {
        self.diagnostics
            .push(Diagnostic::warning(code, message, file, span));
    }
}

/// Whether an error of this code stops the evaluation (OpenSCAD 2021.01 stops on these too);
/// other errors stop only their statement, where OpenSCAD warns and continues with `undef`.
fn is_fatal(code: &str) -> bool {
    matches!(
        code,
        codes::RECURSION_LIMIT
            | codes::ITERATION_LIMIT
            | codes::VECTOR_LIMIT
            | codes::STRING_LIMIT
            | codes::INSTANCE_LIMIT
            | codes::ASSERTION_FAILED
    )
}

/// The command-line flag that raises the limit an error of this code reports.
fn limit_flag(code: &str) -> Option<&'static str> {
    match code {
        codes::RECURSION_LIMIT => Some("--max-recursion"),
        codes::ITERATION_LIMIT => Some("--max-iterations"),
        codes::VECTOR_LIMIT => Some("--max-vector-len"),
        codes::STRING_LIMIT => Some("--max-string-len"),
        codes::INSTANCE_LIMIT => Some("--max-instances"),
        codes::IMPORT_SIZE_LIMIT => Some("--max-import-bytes"),
        codes::HULL_POINT_LIMIT => Some("--max-hull-points"),
        codes::PART_PLANE_LIMIT => Some("--max-part-planes"),
        codes::MINKOWSKI_PART_LIMIT => Some("--max-minkowski-parts"),
        _ => None,
    }
}
