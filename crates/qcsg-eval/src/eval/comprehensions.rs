//! List comprehensions: the elements of a vector literal (`for`, C-style `for`, `if`, `each`,
//! `let`), appended to the vector being built within the vector-length limit.

use qcsg_diag::Span;
use qcsg_syntax::ast::{ListElem, ListElemKind};

use crate::env::Frame;
use crate::value::Value;

use super::bindings::heads;
use super::{Cx, Evaluator, R};

impl<'a> Evaluator<'a> {
    pub(super) fn eval_elem(
        &mut self,
        elem: &'a ListElem,
        cx: &Cx<'a>,
        out: &mut Vec<Value<'a>>,
        span: Span,
    ) -> R<()> {
        match &elem.kind {
            ListElemKind::Expr(e) => {
                let v = self.eval_expr(e, cx)?;
                self.check_len(out.len() as u64 + 1, cx.file, span)?;
                out.push(v);
            }
            ListElemKind::For { bindings, body } => {
                self.for_each(&heads(bindings), cx, &mut |this, frame| {
                    this.eval_elem(
                        body,
                        &Cx {
                            frame,
                            file: cx.file,
                        },
                        out,
                        span,
                    )
                })?;
            }
            ListElemKind::CFor {
                init,
                cond,
                update,
                body,
            } => {
                let mut frame = self.bind_sequential(init, cx)?;
                loop {
                    self.tick(1, cx.file, elem.span)?;
                    let inner = Cx {
                        frame: frame.clone(),
                        file: cx.file,
                    };
                    if !self.eval_expr(cond, &inner)?.truthy() {
                        break;
                    }
                    self.eval_elem(body, &inner, out, span)?;
                    let next = Frame::nested(&cx.frame);
                    for (name, value) in frame.locals() {
                        next.set(name, value);
                    }
                    for b in update {
                        let v = self.eval_expr(&b.value, &inner)?;
                        next.set(&b.name.name, v);
                    }
                    frame = next;
                }
            }
            ListElemKind::If { cond, then, els } => {
                if self.eval_expr(cond, cx)?.truthy() {
                    self.eval_elem(then, cx, out, span)?;
                } else if let Some(els) = els {
                    self.eval_elem(els, cx, out, span)?;
                }
            }
            ListElemKind::Each(inner) => {
                let mut values = Vec::new();
                self.eval_elem(inner, cx, &mut values, span)?;
                for v in values {
                    match &v {
                        Value::Vector(items) => {
                            self.check_len((out.len() + items.len()) as u64, cx.file, span)?;
                            out.extend(items.iter().cloned());
                        }
                        Value::Range(r) => {
                            let n = r.len();
                            self.check_len(out.len() as u64 + n, cx.file, span)?;
                            out.extend((0..n).map(|i| Value::Number(r.at(i))));
                        }
                        Value::String(s) => {
                            let n = s.chars().count() as u64;
                            self.check_len(out.len() as u64 + n, cx.file, span)?;
                            out.extend(s.chars().map(|c| Value::string(c.to_string())));
                        }
                        _ => {
                            self.check_len(out.len() as u64 + 1, cx.file, span)?;
                            out.push(v.clone());
                        }
                    }
                }
            }
            ListElemKind::Let { bindings, body } => {
                let frame = self.bind_sequential(bindings, cx)?;
                self.eval_elem(
                    body,
                    &Cx {
                        frame,
                        file: cx.file,
                    },
                    out,
                    span,
                )?;
            }
            ListElemKind::Paren(inner) => self.eval_elem(inner, cx, out, span)?,
        }
        Ok(())
    }
}
