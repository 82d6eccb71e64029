//! The main document's diagnostics in editor coordinates.

use qcsg_diag::{Diagnostic, FileId, Severity};
use qcsg_sema::{FileLink, LinkKind, codes};

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
    /// The checker's diagnostics for the main document, in source order: its own, and the
    /// errors of the files it includes or uses, shown at the `include <…>` / `use <…>` that
    /// pulls them in (with related information pointing into the file).
    pub fn diagnostics(&self) -> Vec<IdeDiagnostic> {
        self.present(self.sema.diagnostics.iter())
    }

    /// The checker's diagnostics located in the included or used file `path` (errors and
    /// warnings, in that file's coordinates), for publishing them to that file when it is open.
    pub fn diagnostics_in(&self, path: &str) -> Vec<IdeDiagnostic> {
        self.diagnostics_located_in(self.sema.diagnostics.iter(), path)
    }

    /// The paths of every file this analysis read besides the main document.
    pub fn dependencies(&self) -> Vec<String> {
        self.sema
            .sources
            .iter()
            .filter(|(f, _)| *f != self.sema.main)
            .map(|(_, file)| file.name.clone())
            .collect()
    }

    /// `diagnostics` as the main document shows them (see [`Analysis::diagnostics`]): for the
    /// diagnostics of later stages (evaluation, the DNF), which the language server computes.
    pub fn present<'d>(
        &self,
        diagnostics: impl Iterator<Item = &'d Diagnostic>,
    ) -> Vec<IdeDiagnostic> {
        let mut out = Vec::new();
        for diagnostic in diagnostics {
            if diagnostic.file == self.sema.main {
                out.push(self.convert(diagnostic));
            } else if diagnostic.severity == Severity::Error
                && let Some(link) = self.link_into(diagnostic.file)
            {
                out.push(self.at_link(diagnostic, link));
            }
        }
        out
    }

    /// The errors and warnings of `diagnostics` located in the file named `path`.
    pub fn diagnostics_located_in<'d>(
        &self,
        diagnostics: impl Iterator<Item = &'d Diagnostic>,
        path: &str,
    ) -> Vec<IdeDiagnostic> {
        let Some(file) = self
            .sema
            .sources
            .iter()
            .find(|(f, source)| *f != self.sema.main && source.name == path)
            .map(|(f, _)| f)
        else {
            return Vec::new();
        };
        diagnostics
            .filter(|d| d.file == file && matches!(d.severity, Severity::Error | Severity::Warning))
            .map(|d| self.convert(d))
            .collect()
    }

    /// The `include`/`use` statement of the main document through which `file` was loaded
    /// (directly or through other files).
    fn link_into(&self, file: FileId) -> Option<&FileLink> {
        let mut current = file;
        // Each step moves one include level up; the bound guards against a cycle.
        for _ in 0..=self.sema.links.len() {
            let link = self
                .sema
                .links
                .iter()
                .find(|l| l.target == Some(current) && l.file != current)?;
            if link.file == self.sema.main {
                return Some(link);
            }
            current = link.file;
        }
        None
    }

    /// `diagnostic` (of another file) shown at the main document's `link`.
    fn at_link(&self, diagnostic: &Diagnostic, link: &FileLink) -> IdeDiagnostic {
        let mut shown = self.convert(diagnostic);
        let name = &self.sema.sources.get(diagnostic.file).name;
        let short = std::path::Path::new(name)
            .file_name()
            .map_or(name.as_str(), |n| n.to_str().unwrap_or(name));
        let verb = match link.kind {
            LinkKind::Include => "included",
            LinkKind::Use => "used",
        };
        shown.message = format!("in {verb} file `{short}`: {}", shown.message);
        shown.related.insert(
            0,
            RelatedInfo {
                location: self.file_range(diagnostic.file, diagnostic.span),
                message: diagnostic.message.clone(),
            },
        );
        shown.range = self.range(self.sema.main, link.span);
        shown.unnecessary = false;
        shown
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
