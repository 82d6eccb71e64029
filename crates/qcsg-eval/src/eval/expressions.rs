//! Expressions to values, with OpenSCAD's operators, indexing, member access, ranges and variable
//! lookups (the built-in variables and `$`-defaults last).

use std::rc::Rc;

use qcsg_diag::{FileId, Span};
use qcsg_syntax::ast::{BinaryOp, Expr, ExprKind};

use crate::env::Callable;
use crate::value::{Range, Value};
use crate::{codes, ops};

use super::function_calls::Tail;
use super::{Cx, Evaluator, R, STACK_GROWTH, STACK_RED_ZONE};

impl<'a> Evaluator<'a> {
    pub(super) fn eval_expr(&mut self, expr: &'a Expr, cx: &Cx<'a>) -> R<Value<'a>> {
        stacker::maybe_grow(STACK_RED_ZONE, STACK_GROWTH, || {
            self.eval_expr_inner(expr, cx)
        })
    }

    fn eval_expr_inner(&mut self, expr: &'a Expr, cx: &Cx<'a>) -> R<Value<'a>> {
        let file = cx.file;
        match &expr.kind {
            ExprKind::Number(x) => Ok(Value::Number(*x)),
            ExprKind::String(s) => Ok(Value::string(s.as_str())),
            ExprKind::Bool(b) => Ok(Value::Bool(*b)),
            ExprKind::Undef => Ok(Value::Undef),
            ExprKind::Ident(ident) => self.lookup_variable(&ident.name, file, ident.span, cx),
            ExprKind::Paren(inner) => self.eval_expr(inner, cx),
            ExprKind::Unary {
                op,
                op_span,
                operand,
            } => {
                let v = self.eval_expr(operand, cx)?;
                ops::unary(*op, &v).map_err(|m| {
                    self.error(codes::OPERATOR_TYPE, m, file, op_span.cover(operand.span))
                })
            }
            ExprKind::Binary { op, lhs, rhs, .. } => {
                let a = self.eval_expr(lhs, cx)?;
                // `&&` and `||` short-circuit.
                match op {
                    BinaryOp::And if !a.truthy() => return Ok(Value::Bool(false)),
                    BinaryOp::Or if a.truthy() => return Ok(Value::Bool(true)),
                    _ => {}
                }
                let b = self.eval_expr(rhs, cx)?;
                ops::binary(*op, &a, &b)
                    .map_err(|m| self.error(codes::OPERATOR_TYPE, m, file, expr.span))
            }
            ExprKind::Ternary { cond, then, els } => {
                if self.eval_expr(cond, cx)?.truthy() {
                    self.eval_expr(then, cx)
                } else {
                    self.eval_expr(els, cx)
                }
            }
            ExprKind::Call { .. } => match self.eval_tail_call(expr, cx)? {
                Tail::Done(v) => Ok(v),
                Tail::Call(f, args, span, file) => self.call_function(f, args, span, file, cx),
            },
            ExprKind::Index { base, index } => {
                let b = self.eval_expr(base, cx)?;
                let i = self.eval_expr(index, cx)?;
                Ok(index_value(&b, &i))
            }
            ExprKind::Member { base, member } => {
                let b = self.eval_expr(base, cx)?;
                let i = match member.name.as_str() {
                    "x" => 0.0,
                    "y" => 1.0,
                    "z" => 2.0,
                    _ => return Ok(Value::Undef),
                };
                Ok(match b {
                    Value::Vector(_) => index_value(&b, &Value::Number(i)),
                    _ => Value::Undef,
                })
            }
            ExprKind::Vector(elems) => {
                let mut out = Vec::new();
                for e in elems {
                    self.eval_elem(e, cx, &mut out, expr.span)?;
                }
                Ok(Value::vector(out))
            }
            ExprKind::Range { start, step, end } => {
                let num = |this: &mut Self, e: &'a Expr| -> R<f64> {
                    match this.eval_expr(e, cx)? {
                        Value::Number(x) => Ok(x),
                        other => Err(this.error(
                            codes::OPERATOR_TYPE,
                            format!("a range needs numbers, got {}", other.type_name()),
                            file,
                            e.span,
                        )),
                    }
                };
                let mut begin = num(self, start)?;
                let step_value = match step {
                    Some(s) => Some(num(self, s)?),
                    None => None,
                };
                let mut end_value = num(self, end)?;
                if step_value.is_none() && begin > end_value {
                    self.warn(
                        codes::REVERSED_RANGE,
                        "a range [begin : end] with begin > end: OpenSCAD swaps the ends (deprecated)",
                        file,
                        expr.span,
                    );
                    std::mem::swap(&mut begin, &mut end_value);
                }
                Ok(Value::Range(Range {
                    begin,
                    step: step_value.unwrap_or(1.0),
                    end: end_value,
                }))
            }
            ExprKind::Let { bindings, body } => {
                let frame = self.bind_sequential(bindings, cx)?;
                self.eval_expr(body, &Cx { frame, file })
            }
            ExprKind::Assert { args, body, .. } => {
                let values = self.eval_args(args, cx)?;
                self.assert(&values, args, file, expr.span)?;
                match body {
                    Some(b) => self.eval_expr(b, cx),
                    None => Ok(Value::Undef),
                }
            }
            ExprKind::Echo { args, body, .. } => {
                let values = self.eval_args(args, cx)?;
                self.echo(&values, file, expr.span);
                match body {
                    Some(b) => self.eval_expr(b, cx),
                    None => Ok(Value::Undef),
                }
            }
            ExprKind::FunctionLit { params, body } => Ok(Value::Function(Rc::new(Callable {
                params,
                body,
                env: cx.frame.clone(),
                file,
            }))),
            ExprKind::Error => Err(self.error(
                codes::UNSUPPORTED,
                "this expression has a syntax error",
                file,
                expr.span,
            )),
        }
    }

    fn lookup_variable(
        &mut self,
        name: &str,
        file: FileId,
        span: Span,
        cx: &Cx<'a>,
    ) -> R<Value<'a>> {
        if let Some(v) = cx.frame.lookup(name) {
            return Ok(v);
        }
        if let Some(v) = builtin_variable(name) {
            return Ok(v);
        }
        if name.starts_with('$') {
            return Ok(Value::Undef);
        }
        Err(self.error(
            codes::UNDEFINED_NAME,
            format!("no variable named `{name}`"),
            file,
            span,
        ))
    }
}

/// `base[index]`; `undef` out of range, as in OpenSCAD (which does not warn).
fn index_value<'a>(base: &Value<'a>, index: &Value<'a>) -> Value<'a> {
    let Value::Number(i) = index else {
        return Value::Undef;
    };
    if i.is_nan() || *i < 0.0 {
        return Value::Undef;
    }
    match base {
        Value::Vector(v) if *i < v.len() as f64 => v[*i as usize].clone(),
        Value::String(s) => s
            .chars()
            .nth(*i as usize)
            .map_or(Value::Undef, |c| Value::string(c.to_string())),
        Value::Range(r) if (*i as u64) < r.len() => Value::Number(r.at(*i as u64)),
        _ => Value::Undef,
    }
}

/// Built-in variables and the defaults of OpenSCAD's special variables.
fn builtin_variable<'a>(name: &str) -> Option<Value<'a>> {
    let n = |x: f64| Some(Value::Number(x));
    let v3 = |a: f64, b: f64, c: f64| {
        Some(Value::vector(vec![
            Value::Number(a),
            Value::Number(b),
            Value::Number(c),
        ]))
    };
    match name {
        "PI" => n(std::f64::consts::PI),
        "$fn" => n(0.0),
        "$fa" => n(12.0),
        "$fs" => n(2.0),
        "$t" => n(0.0),
        "$preview" => Some(Value::Bool(false)),
        "$vpr" => v3(55.0, 0.0, 25.0),
        "$vpt" => v3(0.0, 0.0, 0.0),
        "$vpd" => n(140.0),
        "$vpf" => n(22.5),
        "$children" | "$parent_modules" => n(0.0),
        _ => None,
    }
}
