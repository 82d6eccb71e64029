//! Hover: what a name is (kind, type, value, documentation) and what a call's callee accepts.

use std::collections::HashMap;

use qcsg_sema::builtins::{self, ModuleKind};
use qcsg_sema::{DefId, DefKind, Namespace, Target, Ty};
use qcsg_syntax::ast::StmtKind;

use crate::walk::{Node, walk};
use crate::{Analysis, FileId, LineCol, Span, TextRange};

/// Hover contents for the name under the cursor.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Hover {
    /// Markdown to show.
    pub markdown: String,
    /// The name the hover is about.
    pub range: TextRange,
}

/// Extra hover contents from later stages, such as the geometry a primitive becomes.
///
/// The language server implements this with the evaluated scene to show, for a primitive instantiation, the quadrics it turns
/// into with their classification, centre and axes; [`Analysis::hover_with`] appends its
/// markdown below the name's own description.
pub trait HoverExtension {
    /// Markdown about the module instantiation whose name is at `name_span` of `file`, or `None`.
    fn instantiation(&self, analysis: &Analysis, file: FileId, name_span: Span) -> Option<String>;
}

impl Analysis {
    /// The module instantiation statements of the main document, each by the start of its
    /// called name (the span a [`HoverExtension`] is given): what a later stage recorded per
    /// statement is found from them.
    pub fn instantiation_statements(&self) -> HashMap<u32, Span> {
        let mut statements = HashMap::new();
        walk(self.tree(), &mut |node| {
            if let Node::Stmt(stmt) = node
                && let StmtKind::Instantiate { name, .. } = &stmt.kind
            {
                statements.insert(name.span.start, stmt.span);
            }
        });
        statements
    }

    /// Hover for the name at `position` of the main document.
    pub fn hover(&self, position: LineCol) -> Option<Hover> {
        self.hover_with(position, None)
    }

    /// Hover with contents from an extension appended (see [`HoverExtension`]).
    pub fn hover_with(
        &self,
        position: LineCol,
        extension: Option<&dyn HoverExtension>,
    ) -> Option<Hover> {
        let offset = self.offset(position);
        let main = self.sema.main;
        // A cursor right after a name still means that name.
        for offset in [offset, offset.saturating_sub(1)] {
            if let Some(reference) = self.sema.reference_at(main, offset) {
                let name = self.text().get(reference.span.range())?;
                let mut markdown = match reference.target {
                    Target::Definition(id) => self.definition_markdown(id)?,
                    Target::Builtin => builtin_markdown(name, reference.namespace)?,
                    Target::CommandLine => {
                        format!("```qcsg\n{name}\n```\nset on the command line (`-D`)")
                    }
                };
                if reference.namespace == Namespace::Module
                    && let Some(extra) =
                        extension.and_then(|e| e.instantiation(self, main, reference.span))
                {
                    markdown.push_str("\n\n---\n\n");
                    markdown.push_str(&extra);
                }
                return Some(Hover {
                    markdown,
                    range: self.range(main, reference.span),
                });
            }
            if let Some((id, definition)) = self.sema.definition_at(main, offset) {
                return Some(Hover {
                    markdown: self.definition_markdown(id)?,
                    range: self.range(main, definition.name_span),
                });
            }
        }
        None
    }

    /// What hover says about a definition.
    pub(crate) fn definition_markdown(&self, id: DefId) -> Option<String> {
        let definition = self.sema.definition(id)?;
        let mut markdown = String::new();
        let kind = match definition.kind {
            DefKind::Variable => "variable",
            DefKind::Parameter => "parameter",
            DefKind::LoopVariable => "loop variable",
            DefKind::LetVariable => "`let` variable",
            DefKind::Module => "module",
            DefKind::Function => "function",
        };
        let code = match definition.kind {
            DefKind::Module | DefKind::Function => self.definition_signature(id)?.declaration(),
            _ => match self.constant_value(id) {
                Some(value) => format!("{} = {value}", definition.name),
                None => match &definition.params {
                    Some(_) => format!(
                        "{} = {}",
                        definition.name,
                        self.definition_signature(id)?.label().0.replacen(
                            &definition.name,
                            "function",
                            1
                        )
                    ),
                    None => definition.name.clone(),
                },
            },
        };
        markdown.push_str(&format!("```qcsg\n{code}\n```\n"));
        markdown.push_str(kind);
        if let Some(parent) = definition.parent.and_then(|p| self.sema.definition(p)) {
            markdown.push_str(&format!(" of `{}`", parent.name));
        }
        if !matches!(definition.kind, DefKind::Module | DefKind::Function)
            && definition.ty != Ty::Any
        {
            markdown.push_str(&format!(" · {}", definition.ty));
        }
        if definition.file != self.sema.main {
            markdown.push_str(&format!(
                " · in `{}`",
                self.sema.sources.get(definition.file).name
            ));
        }
        if let Some(doc) = &definition.doc {
            markdown.push_str("\n\n---\n\n");
            markdown.push_str(doc);
        }
        Some(markdown)
    }
}

/// What hover says about a built-in.
pub(crate) fn builtin_markdown(name: &str, namespace: Namespace) -> Option<String> {
    match namespace {
        Namespace::Module => {
            let module = builtins::module(name)?;
            let signature = Analysis::builtin_signature(name, true)?;
            let kind = match module.kind {
                ModuleKind::Primitive => "built-in primitive",
                ModuleKind::Transform => "built-in transform",
                ModuleKind::Boolean => "built-in boolean operation",
                ModuleKind::Other => "built-in module",
            };
            Some(format!(
                "```qcsg\n{}\n```\n{kind}\n\n---\n\n{}",
                signature.declaration(),
                module.doc
            ))
        }
        Namespace::Function => {
            let function = builtins::function(name)?;
            let signature = Analysis::builtin_signature(name, false)?;
            Some(format!(
                "```qcsg\n{}\n```\nbuilt-in function · returns {}\n\n---\n\n{}",
                signature.declaration(),
                function.returns.ty(),
                function.doc
            ))
        }
        Namespace::Variable => {
            if let Some((_, doc)) = builtins::SPECIAL_VARIABLES.iter().find(|(n, _)| *n == name) {
                return Some(format!(
                    "```qcsg\n{name}\n```\nspecial variable (dynamically scoped)\n\n---\n\n{doc}"
                ));
            }
            let (_, doc, ty) = builtins::VARIABLES.iter().find(|(n, _, _)| *n == name)?;
            Some(format!(
                "```qcsg\n{name}\n```\nbuilt-in constant · {ty}\n\n---\n\n{doc}"
            ))
        }
    }
}
