//! Function calls: user functions run in a loop over their tail calls (through `?:`, `let` and
//! parentheses), so tail recursion costs no stack; built-in functions get their named arguments
//! placed by position.

use std::rc::Rc;

use qcsg_diag::{FileId, Span};
use qcsg_syntax::ast::{Arg, Expr, ExprKind};

use crate::builtins_fn::{self, BuiltinError};
use crate::codes;
use crate::env::{Frame, FunctionDef};
use crate::value::Value;

use super::{ArgValue, Cx, Evaluator, R};

/// What evaluating a function body in tail position produced.
pub(super) enum Tail<'a> {
    Done(Value<'a>),
    Call(Rc<FunctionDef<'a>>, Vec<ArgValue<'a>>, Span, FileId),
}

impl<'a> Evaluator<'a> {
    /// Evaluates `expr` in tail position: a call of a user function is returned unevaluated so
    /// that the caller can loop instead of recursing (OpenSCAD also eliminates tail calls).
    fn eval_tail(&mut self, expr: &'a Expr, cx: &Cx<'a>) -> R<Tail<'a>> {
        match &expr.kind {
            ExprKind::Paren(inner) => self.eval_tail(inner, cx),
            ExprKind::Ternary { cond, then, els } => {
                if self.eval_expr(cond, cx)?.truthy() {
                    self.eval_tail(then, cx)
                } else {
                    self.eval_tail(els, cx)
                }
            }
            ExprKind::Let { bindings, body } => {
                let frame = self.bind_sequential(bindings, cx)?;
                self.eval_tail(
                    body,
                    &Cx {
                        frame,
                        file: cx.file,
                    },
                )
            }
            ExprKind::Call { .. } => self.eval_tail_call(expr, cx),
            _ => Ok(Tail::Done(self.eval_expr(expr, cx)?)),
        }
    }

    /// A call: built-ins are evaluated, user functions returned as a pending tail call.
    pub(super) fn eval_tail_call(&mut self, expr: &'a Expr, cx: &Cx<'a>) -> R<Tail<'a>> {
        let ExprKind::Call { callee, args, .. } = &expr.kind else {
            return Ok(Tail::Done(self.eval_expr(expr, cx)?));
        };
        let file = cx.file;
        let function = match &callee.kind {
            ExprKind::Ident(ident) => {
                let name = ident.name.as_str();
                match &cx.frame.lookup(name) {
                    Some(Value::Function(f)) => f.clone(),
                    found => {
                        if let Some(def) = cx.frame.lookup_function(name) {
                            def
                        } else if found.is_some() {
                            return Err(self.error(
                                codes::NOT_CALLABLE,
                                format!("`{name}` is not a function"),
                                file,
                                ident.span,
                            ));
                        } else if builtins_fn::is_builtin(name) {
                            let values = self.eval_args(args, cx)?;
                            return Ok(Tail::Done(
                                self.call_builtin(name, values, args, file, expr.span)?,
                            ));
                        } else if cx.frame.lookup_module(name).is_some()
                            || qcsg_sema::builtins::module(name).is_some()
                        {
                            return Err(self.error(
                                codes::WRONG_KIND,
                                format!("`{name}` is a module, not a function"),
                                file,
                                ident.span,
                            ));
                        } else {
                            return Err(self.error(
                                codes::UNDEFINED_NAME,
                                format!("no function named `{name}`"),
                                file,
                                ident.span,
                            ));
                        }
                    }
                }
            }
            _ => match &self.eval_expr(callee, cx)? {
                Value::Function(f) => f.clone(),
                other => {
                    return Err(self.error(
                        codes::NOT_CALLABLE,
                        format!("a {} is not a function", other.type_name()),
                        file,
                        callee.span,
                    ));
                }
            },
        };
        let values = self.eval_args(args, cx)?;
        Ok(Tail::Call(function, values, expr.span, file))
    }

    pub(super) fn call_function(
        &mut self,
        mut function: Rc<FunctionDef<'a>>,
        mut values: Vec<ArgValue<'a>>,
        span: Span,
        file: FileId,
        cx: &Cx<'a>,
    ) -> R<Value<'a>> {
        self.enter(file, span)?;
        self.tick(1, file, span)?;
        let result = loop {
            let frame = Frame::child(&function.env, &cx.frame);
            let f = function.clone();
            if let Err(stop) = self.bind_params(&frame, f.params, &f.env, f.file, values) {
                break Err(stop);
            }
            match self.eval_tail(
                f.body,
                &Cx {
                    frame,
                    file: f.file,
                },
            ) {
                Ok(Tail::Done(v)) => break Ok(v),
                Ok(Tail::Call(next, next_values, next_span, next_file)) => {
                    if let Err(stop) = self.tick(1, next_file, next_span) {
                        break Err(stop);
                    }
                    function = next;
                    values = next_values;
                }
                Err(stop) => break Err(stop),
            }
        };
        self.depth -= 1;
        result
    }

    fn call_builtin(
        &mut self,
        name: &str,
        values: Vec<ArgValue<'a>>,
        args: &'a [Arg],
        file: FileId,
        span: Span,
    ) -> R<Value<'a>> {
        let Some(signature) = qcsg_sema::builtins::function(name) else {
            return Err(self.error(
                codes::UNDEFINED_NAME,
                format!("no function named `{name}`"),
                file,
                span,
            ));
        };
        // Named arguments go to their parameter's position.
        let mut positional: Vec<Value<'a>> = Vec::new();
        let mut named: Vec<(&str, Value<'a>)> = Vec::new();
        for a in values {
            match a.name {
                Some(n) if n.starts_with('$') => {}
                Some(n) => named.push((n, a.value)),
                None => positional.push(a.value),
            }
        }
        for (n, v) in named {
            match signature.params.iter().position(|p| p.name == n) {
                Some(i) => {
                    if positional.len() <= i {
                        positional.resize(i + 1, Value::Undef);
                    }
                    positional[i] = v;
                }
                None => {
                    let at = args
                        .iter()
                        .find(|a| a.name.as_ref().is_some_and(|x| x.name == n))
                        .map_or(span, |a| a.span);
                    return Err(self.error(
                        codes::FUNCTION_ARGUMENT,
                        format!("{name}() has no parameter `{n}`"),
                        file,
                        at,
                    ));
                }
            }
        }
        if name == "parent_module" {
            // No argument means the parent (1), as in OpenSCAD.
            let n = positional.first().cloned().unwrap_or(Value::Number(1.0));
            return self.parent_module(&n, file, span);
        }
        if name == "dxf_dim" || name == "dxf_cross" {
            return self.drawing_function(name, &positional, file, span);
        }
        let mut warnings = Vec::new();
        let result = builtins_fn::call(name, &positional, self.options, &mut warnings);
        for w in warnings {
            self.warn(codes::SEARCH_TABLE, w, file, span);
        }
        match result {
            Ok(v) => Ok(v),
            Err(BuiltinError::Undefined(message)) => {
                Err(self.error(codes::FUNCTION_ARGUMENT, message, file, span))
            }
            Err(BuiltinError::TooLong(n)) => {
                self.check_len(n, file, span)?;
                Ok(Value::Undef)
            }
            Err(BuiltinError::StringTooLong) => Err(self.error(
                codes::STRING_LIMIT,
                format!(
                    "{name}() would make a string longer than the limit of {} bytes",
                    self.options.max_string_len
                ),
                file,
                span,
            )),
        }
    }
}
