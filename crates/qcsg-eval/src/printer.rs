//! Prints expressions the way OpenSCAD echoes a function value: `function(x) (x + 1)`.
//!
//! OpenSCAD prints the parsed expression, not the source: binary and ternary operations in
//! parentheses, parentheses of the source dropped, numbers in their `echo` form.
//!
//! `qcsg_syntax::sexpr` prints the same tree for another reader: the structure of a parse, for
//! tests and `--emit ast`. This one is user-visible output that must match OpenSCAD's text.

use std::fmt::Write as _;

use qcsg_syntax::ast::{Arg, Binding, Expr, ExprKind, ListElem, ListElemKind, Param, UnaryOp};

use crate::value::format_number;

/// `function(params) body` as OpenSCAD prints a function literal.
pub fn function_literal(params: &[Param], body: &Expr) -> String {
    let mut out = String::from("function(");
    write_params(&mut out, params);
    out.push_str(") ");
    write_expr(&mut out, body);
    out
}

fn write_params(out: &mut String, params: &[Param]) {
    for (i, p) in params.iter().enumerate() {
        if i > 0 {
            out.push_str(", ");
        }
        out.push_str(&p.name.name);
        if let Some(d) = &p.default {
            out.push_str(" = ");
            write_expr(out, d);
        }
    }
}

fn write_args(out: &mut String, args: &[Arg]) {
    for (i, a) in args.iter().enumerate() {
        if i > 0 {
            out.push_str(", ");
        }
        if let Some(n) = &a.name {
            out.push_str(&n.name);
            out.push_str(" = ");
        }
        write_expr(out, &a.value);
    }
}

fn write_bindings(out: &mut String, bindings: &[Binding]) {
    for (i, b) in bindings.iter().enumerate() {
        if i > 0 {
            out.push_str(", ");
        }
        out.push_str(&b.name.name);
        out.push_str(" = ");
        write_expr(out, &b.value);
    }
}

/// Appends the OpenSCAD print form of `expr`.
pub fn write_expr(out: &mut String, expr: &Expr) {
    match &expr.kind {
        ExprKind::Number(x) => out.push_str(&format_number(*x)),
        ExprKind::String(s) => {
            let _ = write!(out, "\"{s}\"");
        }
        ExprKind::Bool(b) => out.push_str(if *b { "true" } else { "false" }),
        ExprKind::Undef => out.push_str("undef"),
        ExprKind::Ident(i) => out.push_str(&i.name),
        ExprKind::Paren(inner) => write_expr(out, inner),
        ExprKind::Unary { op, operand, .. } => {
            out.push(match op {
                UnaryOp::Not => '!',
                UnaryOp::Neg => '-',
                UnaryOp::Plus => '+',
            });
            write_expr(out, operand);
        }
        ExprKind::Binary { op, lhs, rhs, .. } => {
            out.push('(');
            write_expr(out, lhs);
            let _ = write!(out, " {} ", op.as_str());
            write_expr(out, rhs);
            out.push(')');
        }
        ExprKind::Ternary { cond, then, els } => {
            out.push('(');
            write_expr(out, cond);
            out.push_str(" ? ");
            write_expr(out, then);
            out.push_str(" : ");
            write_expr(out, els);
            out.push(')');
        }
        ExprKind::Call { callee, args, .. } => {
            write_expr(out, callee);
            out.push('(');
            write_args(out, args);
            out.push(')');
        }
        ExprKind::Index { base, index } => {
            write_expr(out, base);
            out.push('[');
            write_expr(out, index);
            out.push(']');
        }
        ExprKind::Member { base, member } => {
            write_expr(out, base);
            out.push('.');
            out.push_str(&member.name);
        }
        ExprKind::Vector(elems) => {
            out.push('[');
            for (i, e) in elems.iter().enumerate() {
                if i > 0 {
                    out.push_str(", ");
                }
                write_elem(out, e);
            }
            out.push(']');
        }
        ExprKind::Range { start, step, end } => {
            out.push('[');
            write_expr(out, start);
            if let Some(step) = step {
                out.push_str(" : ");
                write_expr(out, step);
            }
            out.push_str(" : ");
            write_expr(out, end);
            out.push(']');
        }
        ExprKind::Let { bindings, body } => {
            out.push_str("let(");
            write_bindings(out, bindings);
            out.push_str(") ");
            write_expr(out, body);
        }
        ExprKind::Assert { args, body, .. } | ExprKind::Echo { args, body, .. } => {
            out.push_str(if matches!(expr.kind, ExprKind::Assert { .. }) {
                "assert("
            } else {
                "echo("
            });
            write_args(out, args);
            out.push(')');
            if let Some(body) = body {
                out.push(' ');
                write_expr(out, body);
            }
        }
        ExprKind::FunctionLit { params, body } => out.push_str(&function_literal(params, body)),
        ExprKind::Error => out.push_str("undef"),
    }
}

fn write_elem(out: &mut String, elem: &ListElem) {
    match &elem.kind {
        ListElemKind::Expr(e) => write_expr(out, e),
        ListElemKind::For { bindings, body } => {
            out.push_str("for(");
            write_bindings(out, bindings);
            out.push_str(") ");
            write_elem(out, body);
        }
        ListElemKind::CFor {
            init,
            cond,
            update,
            body,
        } => {
            out.push_str("for(");
            write_bindings(out, init);
            out.push_str("; ");
            write_expr(out, cond);
            out.push_str("; ");
            write_bindings(out, update);
            out.push_str(") ");
            write_elem(out, body);
        }
        ListElemKind::If { cond, then, els } => {
            out.push_str("if(");
            write_expr(out, cond);
            out.push_str(") ");
            write_elem(out, then);
            if let Some(els) = els {
                out.push_str(" else ");
                write_elem(out, els);
            }
        }
        ListElemKind::Each(inner) => {
            out.push_str("each ");
            write_elem(out, inner);
        }
        ListElemKind::Let { bindings, body } => {
            out.push_str("let(");
            write_bindings(out, bindings);
            out.push_str(") ");
            write_elem(out, body);
        }
        ListElemKind::Paren(inner) => {
            out.push('(');
            write_elem(out, inner);
            out.push(')');
        }
    }
}
