//! Expressions and their static types: every sub-expression is resolved, and an operator,
//! index or member is reported only where the known types make it fail whatever the unknown
//! parts turn out to be.

use qcsg_diag::{Diagnostic, FileId, Span};
use qcsg_syntax::ast::{BinaryOp, Expr, ExprKind, Ident, ListElem, ListElemKind, UnaryOp};

use crate::builtins;
use crate::ty::Ty;
use crate::{DefKind, Namespace, Target, codes};

use super::arguments::builtin_module_signature;
use super::{Resolver, STACK_GROWTH, STACK_RED_ZONE};

impl<'a> Resolver<'a> {
    pub(super) fn expr(&mut self, file: FileId, expr: &Expr) -> Ty {
        stacker::maybe_grow(STACK_RED_ZONE, STACK_GROWTH, || self.expr_inner(file, expr))
    }

    fn expr_inner(&mut self, file: FileId, expr: &Expr) -> Ty {
        match &expr.kind {
            ExprKind::Number(_) => Ty::Number,
            ExprKind::String(_) => Ty::String,
            ExprKind::Bool(_) => Ty::Bool,
            ExprKind::Undef => Ty::Undef,
            ExprKind::Error => Ty::Any,
            ExprKind::Ident(ident) => self.variable(file, ident),
            ExprKind::Paren(inner) => self.expr(file, inner),
            ExprKind::Unary {
                op,
                op_span,
                operand,
            } => {
                let ty = self.expr(file, operand);
                match op {
                    UnaryOp::Not => Ty::Bool,
                    UnaryOp::Neg | UnaryOp::Plus => {
                        if ty.never_arithmetic() || matches!(ty, Ty::Undef) {
                            let symbol = if *op == UnaryOp::Neg { "-" } else { "+" };
                            self.diagnostics.push(
                                Diagnostic::error(
                                    codes::OPERATOR_TYPE,
                                    format!("cannot apply unary `{symbol}` to {}", ty.describe()),
                                    file,
                                    *op_span,
                                )
                                .with_label(
                                    file,
                                    operand.span,
                                    format!("this is {}", ty.describe()),
                                ),
                            );
                            return Ty::Any;
                        }
                        match ty {
                            Ty::Number | Ty::Vector { .. } => ty,
                            _ => Ty::Any,
                        }
                    }
                }
            }
            ExprKind::Binary {
                op,
                op_span,
                lhs,
                rhs,
            } => {
                let left = self.expr(file, lhs);
                let right = self.expr(file, rhs);
                self.binary(file, *op, *op_span, lhs, rhs, &left, &right)
            }
            ExprKind::Ternary { cond, then, els } => {
                self.expr(file, cond);
                let a = self.expr(file, then);
                let b = self.expr(file, els);
                a.join(&b)
            }
            ExprKind::Call {
                callee,
                args,
                args_span,
            } => self.call(file, callee, args, *args_span),
            ExprKind::Index { base, index } => {
                let base_ty = self.expr(file, base);
                let index_ty = self.expr(file, index);
                if matches!(base_ty, Ty::Number | Ty::Bool | Ty::Undef | Ty::Function) {
                    self.diagnostics.push(
                        Diagnostic::error(
                            codes::NOT_INDEXABLE,
                            format!("cannot index {}", base_ty.describe()),
                            file,
                            index.span,
                        )
                        .with_label(
                            file,
                            base.span,
                            format!("this is {}", base_ty.describe()),
                        ),
                    );
                    return Ty::Any;
                }
                if index_ty.is_known() && index_ty != Ty::Number {
                    self.diagnostics.push(Diagnostic::error(
                        codes::NOT_INDEXABLE,
                        format!("an index must be a number, found {}", index_ty.describe()),
                        file,
                        index.span,
                    ));
                    return Ty::Any;
                }
                match base_ty {
                    Ty::Vector { elem, .. } => *elem,
                    Ty::String => Ty::String,
                    _ => Ty::Any,
                }
            }
            ExprKind::Member { base, member } => {
                let base_ty = self.expr(file, base);
                let is_axis = matches!(member.name.as_str(), "x" | "y" | "z");
                match &base_ty {
                    Ty::Vector { len, elem } => {
                        let axis = match member.name.as_str() {
                            "x" => 0,
                            "y" => 1,
                            _ => 2,
                        };
                        if !is_axis {
                            self.diagnostics.push(
                                Diagnostic::error(
                                    codes::UNKNOWN_MEMBER,
                                    format!("vectors have no member `{}`", member.name),
                                    file,
                                    member.span,
                                )
                                .with_help("a vector's members are `.x`, `.y` and `.z`; index it with `[i]` otherwise"),
                            );
                            Ty::Any
                        } else if len.is_some_and(|n| n <= axis) {
                            self.diagnostics.push(Diagnostic::error(
                                codes::UNKNOWN_MEMBER,
                                format!(
                                    "`.{}` of {} is out of range",
                                    member.name,
                                    base_ty.describe()
                                ),
                                file,
                                member.span,
                            ));
                            Ty::Any
                        } else {
                            (**elem).clone()
                        }
                    }
                    Ty::Number | Ty::Bool | Ty::String | Ty::Undef | Ty::Function => {
                        self.diagnostics.push(
                            Diagnostic::error(
                                codes::UNKNOWN_MEMBER,
                                format!(
                                    "{} has no member `{}`",
                                    capitalize(&base_ty.describe()),
                                    member.name
                                ),
                                file,
                                member.span,
                            )
                            .with_label(
                                file,
                                base.span,
                                format!("this is {}", base_ty.describe()),
                            ),
                        );
                        Ty::Any
                    }
                    _ => Ty::Any,
                }
            }
            ExprKind::Vector(elems) => {
                let plain = elems
                    .iter()
                    .all(|e| matches!(e.kind, ListElemKind::Expr(_)));
                let mut elem_ty: Option<Ty> = None;
                for elem in elems {
                    let ty = self.list_elem(file, elem);
                    if plain {
                        elem_ty = Some(match elem_ty {
                            None => ty,
                            Some(previous) => previous.join(&ty),
                        });
                    }
                }
                if plain {
                    Ty::Vector {
                        len: Some(elems.len() as u32),
                        elem: Box::new(elem_ty.unwrap_or(Ty::Any)),
                    }
                } else {
                    Ty::any_vector()
                }
            }
            ExprKind::Range { start, step, end } => {
                for part in [Some(start), step.as_ref(), Some(end)]
                    .into_iter()
                    .flatten()
                {
                    let ty = self.expr(file, part);
                    if ty.is_known() && ty != Ty::Number {
                        self.diagnostics.push(Diagnostic::error(
                            codes::OPERATOR_TYPE,
                            format!("a range bound must be a number, found {}", ty.describe()),
                            file,
                            part.span,
                        ));
                    }
                }
                Ty::Range
            }
            ExprKind::Let { bindings, body } => {
                self.push_scope();
                self.bindings(file, bindings, DefKind::LetVariable);
                let ty = self.expr(file, body);
                self.pop_scope();
                ty
            }
            ExprKind::Assert {
                args,
                args_span,
                body,
            } => {
                let tys = self.args(file, args);
                if let Some(module) = builtins::module("assert") {
                    let callee = Ident {
                        name: "assert".into(),
                        span: Span::new(
                            expr.span.start as usize,
                            expr.span.start as usize + 6.min(expr.span.len()),
                        ),
                    };
                    let signature = builtin_module_signature(module);
                    self.check_args(file, &callee, *args_span, args, &tys, &signature);
                }
                body.as_ref()
                    .map_or(Ty::Undef, |body| self.expr(file, body))
            }
            ExprKind::Echo { args, body, .. } => {
                self.args(file, args);
                body.as_ref()
                    .map_or(Ty::Undef, |body| self.expr(file, body))
            }
            ExprKind::FunctionLit { params, body } => {
                // The body runs when the function is called, after every assignment of the scope.
                let saved = self.assign_ctx.take();
                let owner = self.enclosing.last().copied();
                self.enter_params(file, params, owner);
                self.expr(file, body);
                self.pop_scope();
                self.assign_ctx = saved;
                Ty::Function
            }
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn binary(
        &mut self,
        file: FileId,
        op: BinaryOp,
        op_span: Span,
        lhs: &Expr,
        rhs: &Expr,
        left: &Ty,
        right: &Ty,
    ) -> Ty {
        use BinaryOp::*;
        match op {
            Or | And | Eq | Ne | Lt | Le | Gt | Ge => return Ty::Bool,
            Add | Sub | Mul | Div | Rem | Pow => {}
        }
        let number = |t: &Ty| *t == Ty::Number;
        let vector = |t: &Ty| matches!(t, Ty::Vector { .. });
        let invalid = left.never_arithmetic()
            || right.never_arithmetic()
            || match op {
                Add | Sub => (number(left) && vector(right)) || (vector(left) && number(right)),
                Div => vector(left) && vector(right),
                Rem | Pow => vector(left) || vector(right),
                _ => false,
            };
        if invalid {
            let mut diagnostic = Diagnostic::error(
                codes::OPERATOR_TYPE,
                format!(
                    "cannot apply `{}` to {} and {}",
                    op.as_str(),
                    left.describe(),
                    right.describe()
                ),
                file,
                op_span,
            );
            for (side, ty) in [(lhs, left), (rhs, right)] {
                if ty.is_known() {
                    diagnostic = diagnostic.with_label(
                        file,
                        side.span,
                        format!("this is {}", ty.describe()),
                    );
                }
            }
            if op == Add && (*left == Ty::String || *right == Ty::String) {
                diagnostic = diagnostic.with_help("join strings with `str(a, b)`");
            }
            self.diagnostics.push(diagnostic);
            return Ty::Any;
        }
        match (left, right) {
            (Ty::Number, Ty::Number) => Ty::Number,
            (Ty::Vector { len: a, elem }, Ty::Vector { len: b, .. }) if matches!(op, Add | Sub) => {
                Ty::Vector {
                    len: if a == b { *a } else { None },
                    elem: elem.clone(),
                }
            }
            // Scaling is element-wise: a number times a matrix is a matrix.
            (Ty::Number, Ty::Vector { len, elem }) | (Ty::Vector { len, elem }, Ty::Number)
                if op == Mul =>
            {
                Ty::Vector {
                    len: *len,
                    elem: elem.clone(),
                }
            }
            (Ty::Vector { len, elem }, Ty::Number) if op == Div => Ty::Vector {
                len: *len,
                elem: elem.clone(),
            },
            _ => Ty::Any,
        }
    }

    fn list_elem(&mut self, file: FileId, elem: &ListElem) -> Ty {
        stacker::maybe_grow(STACK_RED_ZONE, STACK_GROWTH, || match &elem.kind {
            ListElemKind::Expr(expr) => self.expr(file, expr),
            ListElemKind::For { bindings, body } => {
                self.push_scope();
                self.bindings(file, bindings, DefKind::LoopVariable);
                self.list_elem(file, body);
                self.pop_scope();
                Ty::Any
            }
            ListElemKind::CFor {
                init,
                cond,
                update,
                body,
            } => {
                self.push_scope();
                self.bindings(file, init, DefKind::LoopVariable);
                self.expr(file, cond);
                for binding in update {
                    self.expr(file, &binding.value);
                    let existing = self
                        .scopes
                        .last()
                        .and_then(|s| s.vars.get(&binding.name.name))
                        .and_then(|b| b.def);
                    match existing {
                        Some(def) => {
                            self.reference(
                                file,
                                binding.name.span,
                                Namespace::Variable,
                                Target::Definition(def),
                            );
                        }
                        None => {
                            let (def, _) = self.define(
                                DefKind::LoopVariable,
                                file,
                                &binding.name,
                                binding.span,
                                None,
                            );
                            self.bind(&binding.name.name, def, Ty::Any);
                        }
                    }
                }
                self.list_elem(file, body);
                self.pop_scope();
                Ty::Any
            }
            ListElemKind::If { cond, then, els } => {
                self.expr(file, cond);
                self.list_elem(file, then);
                if let Some(els) = els {
                    self.list_elem(file, els);
                }
                Ty::Any
            }
            ListElemKind::Each(inner) => {
                self.list_elem(file, inner);
                Ty::Any
            }
            ListElemKind::Let { bindings, body } => {
                self.push_scope();
                self.bindings(file, bindings, DefKind::LetVariable);
                self.list_elem(file, body);
                self.pop_scope();
                Ty::Any
            }
            ListElemKind::Paren(inner) => self.list_elem(file, inner),
        })
    }
}

fn capitalize(text: &str) -> String {
    let mut chars = text.chars();
    match chars.next() {
        Some(first) => first.to_uppercase().chain(chars).collect(),
        None => String::new(),
    }
}
