//! Warnings about names: unused definitions in the main file, reassigned variables, and settings
//! that have no effect on exact surfaces.

use qcsg_diag::{Diagnostic, FileId, Severity};
use qcsg_syntax::ast::Ident;

use crate::fxhash::FxHashSet as HashSet;
use crate::{DefId, DefKind, builtins, codes};

use super::Resolver;

impl<'a> Resolver<'a> {
    /// Unused-name warnings, for the main file only (a library need not use what it offers).
    pub(super) fn report_unused(&mut self) {
        let redefined: HashSet<DefId> = self
            .definitions
            .iter()
            .filter_map(|d| d.redefines)
            .collect();
        for (index, definition) in self.definitions.iter().enumerate() {
            let id = DefId(index as u32);
            if definition.file != self.main
                || self.used.get(index).copied().unwrap_or(true)
                || definition.name.starts_with('_')
                || definition.name.starts_with('$')
                || redefined.contains(&id)
            {
                continue;
            }
            let (code, message) = match definition.kind {
                DefKind::Variable | DefKind::LetVariable => {
                    if self.defines.contains(&definition.name) && definition.parent.is_none() {
                        continue;
                    }
                    (
                        codes::UNUSED_VARIABLE,
                        format!("variable `{}` is never used", definition.name),
                    )
                }
                DefKind::Parameter => (
                    codes::UNUSED_PARAMETER,
                    format!("parameter `{}` is never used", definition.name),
                ),
                DefKind::Module => (
                    codes::UNUSED_MODULE,
                    format!("module `{}` is never instantiated", definition.name),
                ),
                DefKind::Function => (
                    codes::UNUSED_FUNCTION,
                    format!("function `{}` is never called", definition.name),
                ),
                DefKind::LoopVariable => continue,
            };
            self.diagnostics.push(
                Diagnostic::warning(code, message, definition.file, definition.name_span)
                    .with_help(
                        "remove it, or start its name with `_` to mark it as intentionally unused",
                    ),
            );
        }
    }

    /// OpenSCAD's rule: warn when both assignments are in one file or the first is in the main
    /// file; overriding a library default after `include` is the customary idiom and stays quiet.
    pub(super) fn report_reassignment(&mut self, first: DefId, second: DefId) {
        let (Some(a), Some(b)) = (self.definition(first), self.definition(second)) else {
            return;
        };
        if a.file != b.file && a.file != self.main {
            return;
        }
        let diagnostic = Diagnostic::warning(
            codes::REASSIGNMENT,
            format!("`{}` is assigned again; the last assignment wins for the whole scope", b.name),
            b.file,
            b.name_span,
        )
        .with_label(a.file, a.name_span, "first assigned here")
        .with_help("OpenSCAD uses the last value everywhere in the scope, even before this line; use a new name or a `let`");
        self.diagnostics.push(diagnostic);
    }

    pub(super) fn tessellation_hint(&mut self, file: FileId, name: &Ident) {
        if builtins::is_tessellation_variable(&name.name) {
            self.diagnostics.push(
                Diagnostic::new(
                    Severity::Hint,
                    codes::TESSELLATION_NO_OP,
                    format!("`{}` has no effect: surfaces are exact", name.name),
                    file,
                    name.span,
                )
                .with_help("quadric surfaces are not tessellated; the setting is accepted for OpenSCAD compatibility"),
            );
        }
    }
}
