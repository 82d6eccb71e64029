//! Statements: `if`, `for`, `let`, blocks, instantiations and the modifiers `*`, `%`, `#` and
//! `!`, each to the DAG edge it produces (or none).

use qcsg_csg::{Edge, Source};
use qcsg_syntax::ast::{Modifier, Stmt, StmtKind};

use crate::codes;
use crate::env::Frame;

use super::bindings::heads;
use super::scopes::ScopeItems;
use super::{Cx, Evaluator, R, STACK_GROWTH, STACK_RED_ZONE};

impl<'a> Evaluator<'a> {
    pub(super) fn eval_stmt(&mut self, stmt: &'a Stmt, cx: &Cx<'a>) -> R<Option<Edge>> {
        stacker::maybe_grow(STACK_RED_ZONE, STACK_GROWTH, || {
            self.eval_stmt_inner(stmt, cx)
        })
    }

    fn eval_stmt_inner(&mut self, stmt: &'a Stmt, cx: &Cx<'a>) -> R<Option<Edge>> {
        let source = Source::new(cx.file, stmt.span);
        match &stmt.kind {
            StmtKind::If { cond, then, els } => {
                let branch = if self.eval_expr(cond, cx)?.truthy() {
                    Some(&**then)
                } else {
                    els.as_deref()
                };
                let edges = self.eval_body(branch, cx)?;
                Ok(self.group(edges, source))
            }
            StmtKind::For { bindings, body } => {
                let mut edges = Vec::new();
                self.for_each(&heads(bindings), cx, &mut |this, frame| {
                    let inner = Cx {
                        frame,
                        file: cx.file,
                    };
                    let items = this.collect_body(cx.file, Some(body));
                    edges.extend(this.eval_scope(&items, &inner.frame)?);
                    Ok(())
                })?;
                Ok(self.group(edges, source))
            }
            StmtKind::Let { bindings, body } => {
                let frame = self.bind_sequential(bindings, cx)?;
                let items = self.collect_body(cx.file, Some(body));
                let edges = self.eval_scope(&items, &frame)?;
                Ok(self.group(edges, source))
            }
            StmtKind::Instantiate {
                name, args, child, ..
            } => {
                let made =
                    self.instantiate(&name.name, name.span, args, child.as_deref(), stmt.span, cx)?;
                if let Some(edge) = made {
                    self.instantiations.insert((source, edge.child));
                }
                Ok(made)
            }
            StmtKind::Modified {
                modifier,
                modifier_span,
                body,
            } => match modifier {
                Modifier::Disable => Ok(None),
                Modifier::Background => {
                    if let Some(edge) = self.eval_stmt(body, cx)? {
                        let edge = self.top_level_plate(edge, source);
                        self.dag.add_background(edge);
                    }
                    Ok(None)
                }
                Modifier::Highlight => {
                    let edge = self.eval_stmt(body, cx)?;
                    Ok(edge.map(|e| self.dag.highlight(e, source).into()))
                }
                Modifier::ShowOnly => {
                    let edge = self.eval_stmt(body, cx)?;
                    if self.root_override.is_some() {
                        self.warn(
                            codes::SEVERAL_ROOTS,
                            "more than one `!` modifier: the first one is the root",
                            cx.file,
                            *modifier_span,
                        );
                    } else {
                        let empty = Source::new(cx.file, stmt.span);
                        let edge = match edge {
                            Some(e) => e,
                            None => self.dag.empty(empty).into(),
                        };
                        self.root_override = Some(edge);
                    }
                    Ok(edge)
                }
            },
            StmtKind::Block(stmts) => {
                let mut items = ScopeItems::default();
                self.collect(cx.file, stmts, &mut items);
                let frame = Frame::nested(&cx.frame);
                let edges = self.eval_scope(&items, &frame)?;
                Ok(self.group(edges, source))
            }
            _ => Ok(None),
        }
    }
}
