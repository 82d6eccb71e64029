//! Code actions where the fix is obvious: declare an undefined variable, remove an unused one,
//! correct a misspelt name to the checker's "did you mean" suggestion.

use qcsg_sema::codes;
use qcsg_syntax::ast::StmtKind;

use crate::walk::{Node, walk};
use crate::{Analysis, Span, TextRange};

/// A replacement of a range of the main document.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TextEdit {
    /// What is replaced.
    pub range: TextRange,
    /// The new text.
    pub new_text: String,
}

/// A quick fix.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CodeAction {
    /// What it does, for the menu.
    pub title: String,
    /// The edits, all in the main document.
    pub edits: Vec<TextEdit>,
    /// The code of the diagnostic it fixes.
    pub diagnostic_code: &'static str,
    /// Whether it is the fix to apply without asking (the suggestion of a misspelling).
    pub preferred: bool,
}

impl Analysis {
    /// Quick fixes for the diagnostics that overlap `range` of the main document.
    pub fn code_actions(&self, range: TextRange) -> Vec<CodeAction> {
        let main = self.sema.main;
        let (start, end) = (
            self.offset(range.start) as u32,
            self.offset(range.end) as u32,
        );
        let mut actions = Vec::new();
        // Collected once: a document with thousands of undefined names must not walk its tree
        // once per name.
        let mut statements = None;
        for diagnostic in &self.sema.diagnostics {
            let span = diagnostic.span;
            if diagnostic.file != main || span.end < start || span.start > end {
                continue;
            }
            let name = self.text().get(span.range()).unwrap_or_default();
            if let Some(suggestion) = diagnostic.help.as_deref().and_then(suggested_name) {
                actions.push(CodeAction {
                    title: format!("Change `{name}` to `{suggestion}`"),
                    edits: vec![self.edit(span, suggestion)],
                    diagnostic_code: diagnostic.code,
                    preferred: true,
                });
            }
            match diagnostic.code {
                codes::UNDEFINED_VARIABLE if !name.is_empty() => {
                    let statements = statements.get_or_insert_with(|| self.statement_spans());
                    let at = self.statement_line_start(statements, span);
                    let indent: String = self.text()[at..]
                        .chars()
                        .take_while(|c| *c == ' ' || *c == '\t')
                        .collect();
                    actions.push(CodeAction {
                        title: format!("Declare `{name}`"),
                        edits: vec![
                            self.edit(Span::empty(at), &format!("{indent}{name} = undef;\n")),
                        ],
                        diagnostic_code: diagnostic.code,
                        preferred: false,
                    });
                }
                codes::UNUSED_VARIABLE => {
                    if let Some(remove) = self.assignment_lines(span) {
                        actions.push(CodeAction {
                            title: format!("Remove unused `{name}`"),
                            edits: vec![self.edit(remove, "")],
                            diagnostic_code: diagnostic.code,
                            preferred: false,
                        });
                    }
                }
                _ => {}
            }
        }
        actions
    }

    fn edit(&self, span: Span, new_text: &str) -> TextEdit {
        TextEdit {
            range: self.range(self.sema.main, span),
            new_text: new_text.to_owned(),
        }
    }

    /// The spans of the statements in blocks and at top level, sorted by their start.
    fn statement_spans(&self) -> Vec<Span> {
        let mut spans: Vec<Span> = self.tree().stmts.iter().map(|stmt| stmt.span).collect();
        walk(self.tree(), &mut |node| {
            if let Node::Stmt(stmt) = node
                && let StmtKind::Block(stmts) = &stmt.kind
            {
                spans.extend(stmts.iter().map(|stmt| stmt.span));
            }
        });
        spans.sort_by_key(|span| span.start);
        spans
    }

    /// The start of the line of the innermost statement in a block (or at top level) containing
    /// `span`, where a declaration can go. Statements nest, so the innermost is the one that
    /// starts last among those containing `span`: the first found going back from `span`.
    fn statement_line_start(&self, statements: &[Span], span: Span) -> usize {
        let before = statements.partition_point(|stmt| stmt.start <= span.start);
        let start = statements[..before]
            .iter()
            .rev()
            .find(|stmt| span.end <= stmt.end)
            .map_or(0, |stmt| stmt.start);
        let text = self.text();
        text[..start as usize].rfind('\n').map_or(0, |i| i + 1)
    }

    /// The assignment statement defining the name at `name_span`, with its line when nothing
    /// else is on it.
    fn assignment_lines(&self, name_span: Span) -> Option<Span> {
        let mut found = None;
        walk(self.tree(), &mut |node| {
            if let Node::Stmt(stmt) = node
                && let StmtKind::Assign { name, .. } = &stmt.kind
                && name.span == name_span
            {
                found = Some(stmt.span);
            }
        });
        let span = found?;
        let text = self.text();
        let line_start = text[..span.start as usize].rfind('\n').map_or(0, |i| i + 1);
        let line_end = text[span.end as usize..]
            .find('\n')
            .map_or(text.len(), |i| span.end as usize + i + 1);
        let alone = text[line_start..span.start as usize].trim().is_empty()
            && text[span.end as usize..line_end].trim().is_empty();
        Some(if alone {
            Span::new(line_start, line_end)
        } else {
            span
        })
    }
}

/// The name the checker suggests in a help text ("did you mean `name`?", "a variable with a
/// similar name exists: `name`").
fn suggested_name(help: &str) -> Option<&str> {
    let marker = ["did you mean `", "similar name exists: `"]
        .into_iter()
        .find(|m| help.contains(m))?;
    let rest = &help[help.find(marker)? + marker.len()..];
    Some(&rest[..rest.find('`')?])
}
