//! Loop and `let` bindings: a `for` runs its body once per combination of its bindings' values,
//! counted against the iteration limit first; `let` binds in order, each binding seeing the ones
//! before it; OpenSCAD's deprecated `assign` computes every value first, in the scope around it.

use std::rc::Rc;

use qcsg_csg::{Edge, Source};
use qcsg_diag::{FileId, Span};
use qcsg_syntax::ast::{Arg, Binding, Expr, Stmt};

use crate::codes;
use crate::env::Frame;
use crate::value::Value;

use super::{Cx, Evaluator, R};

impl<'a> Evaluator<'a> {
    /// Runs `body` once per combination of the bindings' values (outermost first), each in a
    /// new scope holding the loop variables.
    pub(super) fn for_each(
        &mut self,
        bindings: &[(&'a str, &'a Expr)],
        cx: &Cx<'a>,
        body: &mut dyn FnMut(&mut Self, Rc<Frame<'a>>) -> R<()>,
    ) -> R<()> {
        let Some((&(name, value), rest)) = bindings.split_first() else {
            return body(self, cx.frame.clone());
        };
        let values = self.eval_expr(value, cx)?;
        let count = self.iteration_count(&values, cx.file, value.span)?;
        for i in 0..count {
            let frame = Frame::nested(&cx.frame);
            frame.set(name, iteration_value(&values, i));
            let inner = Cx {
                frame,
                file: cx.file,
            };
            if rest.is_empty() {
                body(self, inner.frame.clone())?;
            } else {
                self.for_each(rest, &inner, body)?;
            }
        }
        Ok(())
    }

    /// How many times a `for` over `values` runs (checked against the iteration limit first).
    fn iteration_count(&mut self, values: &Value<'a>, file: FileId, span: Span) -> R<u64> {
        let n = match values {
            Value::Range(r) => r.len(),
            Value::Vector(v) => v.len() as u64,
            Value::String(s) => s.chars().count() as u64,
            Value::Undef => 0,
            _ => 1,
        };
        self.tick(n, file, span)?;
        Ok(n)
    }

    pub(super) fn bind_sequential(
        &mut self,
        bindings: &'a [Binding],
        cx: &Cx<'a>,
    ) -> R<Rc<Frame<'a>>> {
        let frame = Frame::nested(&cx.frame);
        let inner = Cx {
            frame: frame.clone(),
            file: cx.file,
        };
        for b in bindings {
            let v = self.eval_expr(&b.value, &inner)?;
            frame.set(&b.name.name, v);
        }
        Ok(frame)
    }
}

impl<'a> Evaluator<'a> {
    /// `assign(a = 1, b = 2) child` (deprecated in OpenSCAD; warning W0109 is static), as
    /// OpenSCAD 2021.01 evaluates it: each named value in turn, in a new scope that holds the
    /// `$`-variables bound so far (special variables are looked up dynamically, so
    /// `assign($r = 5, s = $r)` gives `s = 5`) but no ordinary binding until all are evaluated
    /// (`assign(a = 1, b = a + 1)` sees the outer `a`). Positional arguments are ignored,
    /// unevaluated, as OpenSCAD ignores them.
    pub(super) fn assign_module(
        &mut self,
        args: &'a [Arg],
        child: Option<&'a Stmt>,
        span: Span,
        cx: &Cx<'a>,
    ) -> R<Option<Edge>> {
        let frame = Frame::nested(&cx.frame);
        let inner = Cx {
            frame: frame.clone(),
            file: cx.file,
        };
        let mut ordinary = Vec::with_capacity(args.len());
        for arg in args {
            let Some(name) = &arg.name else {
                self.warn(
                    codes::IGNORED_ARGUMENT,
                    "`assign` binds named arguments only: OpenSCAD ignores this one",
                    cx.file,
                    arg.span,
                );
                continue;
            };
            let value = self.eval_expr(&arg.value, &inner)?;
            if name.is_special() {
                frame.set(&name.name, value);
            } else {
                ordinary.push((name.name.as_str(), value));
            }
        }
        for (name, value) in ordinary {
            frame.set(name, value);
        }
        let items = self.collect_body(cx.file, child);
        let edges = self.eval_scope(&items, &frame)?;
        Ok(self.group(edges, Source::new(cx.file, span)))
    }
}

/// The `i`-th value a `for` takes over `values`.
fn iteration_value<'a>(values: &Value<'a>, i: u64) -> Value<'a> {
    match values {
        Value::Range(r) => Value::Number(r.at(i)),
        Value::Vector(v) => v.get(i as usize).cloned().unwrap_or(Value::Undef),
        Value::String(s) => s
            .chars()
            .nth(i as usize)
            .map_or(Value::Undef, |c| Value::string(c.to_string())),
        other => other.clone(),
    }
}

/// The `(name, value)` heads of bindings.
pub(super) fn heads(bindings: &[Binding]) -> Vec<(&str, &Expr)> {
    bindings
        .iter()
        .map(|b| (b.name.name.as_str(), &b.value))
        .collect()
}
