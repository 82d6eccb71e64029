//! Loop and `let` bindings: a `for` runs its body once per combination of its bindings' values,
//! counted against the iteration limit first; `let` binds in order, each binding seeing the ones
//! before it.

use std::rc::Rc;

use qcsg_diag::{FileId, Span};
use qcsg_syntax::ast::{Binding, Expr};

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
