//! Inlay hints: parameter names at positional arguments, and the values of constant top-level
//! assignments.

use std::collections::HashMap;

use qcsg_syntax::ast::{ExprKind, ListElemKind, StmtKind};

use crate::walk::calls;
use crate::{Analysis, LineCol, TextRange};

/// At most this many value hints per request: each may fold a chain of references.
const MAX_VALUE_HINTS: usize = 500;

/// What an inlay hint shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum InlayKind {
    /// The name of the parameter a positional argument sets (`h =`).
    Parameter,
    /// The value of a constant expression (`= 42`).
    Value,
}

/// One inlay hint.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct InlayHint {
    /// Where it is shown.
    pub position: LineCol,
    /// Its text.
    pub label: String,
    /// What it shows.
    pub kind: InlayKind,
    /// Whether a space separates it from the text before.
    pub padding_left: bool,
    /// Whether a space separates it from the text after.
    pub padding_right: bool,
}

impl Analysis {
    /// The inlay hints inside `range` of the main document, in source order.
    pub fn inlay_hints(&self, range: TextRange) -> Vec<InlayHint> {
        let main = self.sema.main;
        let (start, end) = (
            self.offset(range.start) as u32,
            self.offset(range.end) as u32,
        );
        let references: HashMap<u32, &qcsg_sema::Reference> = self
            .sema
            .references
            .iter()
            .filter(|r| r.file == main && start <= r.span.start && r.span.start <= end)
            .map(|r| (r.span.start, r))
            .collect();
        let mut hints = Vec::new();
        for call in calls(self.tree()) {
            if call.args_span.end < start || call.args_span.start > end {
                continue;
            }
            let Some(reference) = references.get(&call.name.span.start) else {
                continue;
            };
            let Some(signature) = self.reference_signature(reference, call.is_module) else {
                continue;
            };
            let positional: Vec<&str> = signature
                .param_names()
                .zip(&signature.positional)
                .filter(|(_, positional)| **positional)
                .map(|(name, _)| name)
                .collect();
            for (arg, name) in call
                .args
                .iter()
                .take_while(|a| a.name.is_none())
                .zip(positional)
            {
                let obvious = matches!(&arg.value.kind, ExprKind::Ident(i) if i.name == name);
                if !obvious && (start..=end).contains(&arg.span.start) {
                    hints.push(InlayHint {
                        position: self.position(main, arg.span.start as usize),
                        label: format!("{name} ="),
                        kind: InlayKind::Parameter,
                        padding_left: false,
                        padding_right: true,
                    });
                }
            }
        }
        let mut values = 0;
        for stmt in &self.tree().stmts {
            let StmtKind::Assign { name, value } = &stmt.kind else {
                continue;
            };
            if value.span.end < start || value.span.start > end || is_literal(&value.kind) {
                continue;
            }
            if values == MAX_VALUE_HINTS {
                break;
            }
            values += 1;
            let Some((id, _)) = self.sema.definition_at(main, name.span.start as usize) else {
                continue;
            };
            if let Some(constant) = self.constant_value(id) {
                hints.push(InlayHint {
                    position: self.position(main, value.span.end as usize),
                    label: format!("= {constant}"),
                    kind: InlayKind::Value,
                    padding_left: true,
                    padding_right: false,
                });
            }
        }
        hints.sort_by_key(|h| h.position);
        hints
    }
}

/// Whether an expression already shows its value.
fn is_literal(kind: &ExprKind) -> bool {
    match kind {
        ExprKind::Number(_) | ExprKind::String(_) | ExprKind::Bool(_) | ExprKind::Undef => true,
        ExprKind::Unary { operand, .. } => matches!(operand.kind, ExprKind::Number(_)),
        ExprKind::Vector(elems) => elems
            .iter()
            .all(|e| matches!(&e.kind, ListElemKind::Expr(expr) if is_literal(&expr.kind))),
        _ => false,
    }
}
