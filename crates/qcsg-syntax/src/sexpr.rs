//! A compact S-expression printing of the tree, for tests and `qcsg compile --emit ast`.
//!
//! One statement per line at the top level; spans, comments and docs are not shown. Numbers are
//! printed with Rust's shortest round-trip formatting, strings with Rust's `{:?}` escaping.

use std::fmt::Write as _;

use crate::ast::*;

/// Prints every top-level statement of `file`, one per line.
pub fn file_to_sexpr(file: &SourceFile) -> String {
    let mut out = String::new();
    for stmt in &file.stmts {
        write_stmt(&mut out, stmt);
        out.push('\n');
    }
    out
}

/// Prints one statement.
pub fn stmt_to_sexpr(stmt: &Stmt) -> String {
    let mut out = String::new();
    write_stmt(&mut out, stmt);
    out
}

/// Prints one expression.
pub fn expr_to_sexpr(expr: &Expr) -> String {
    let mut out = String::new();
    write_expr(&mut out, expr);
    out
}

fn write_stmt(out: &mut String, stmt: &Stmt) {
    match &stmt.kind {
        StmtKind::Empty => out.push_str("(empty)"),
        StmtKind::Assign { name, value } => {
            let _ = write!(out, "(= {} ", name.name);
            write_expr(out, value);
            out.push(')');
        }
        StmtKind::ModuleDef { name, params, body } => {
            let _ = write!(out, "(module {} ", name.name);
            write_params(out, params);
            out.push(' ');
            write_stmt(out, body);
            out.push(')');
        }
        StmtKind::FunctionDef { name, params, body } => {
            let _ = write!(out, "(function {} ", name.name);
            write_params(out, params);
            out.push(' ');
            write_expr(out, body);
            out.push(')');
        }
        StmtKind::Block(stmts) => {
            out.push_str("(block");
            for s in stmts {
                out.push(' ');
                write_stmt(out, s);
            }
            out.push(')');
        }
        StmtKind::If { cond, then, els } => {
            out.push_str("(if ");
            write_expr(out, cond);
            out.push(' ');
            write_stmt(out, then);
            if let Some(els) = els {
                out.push(' ');
                write_stmt(out, els);
            }
            out.push(')');
        }
        StmtKind::For { bindings, body } => {
            out.push_str("(for ");
            write_bindings(out, bindings);
            out.push(' ');
            write_stmt(out, body);
            out.push(')');
        }
        StmtKind::Let { bindings, body } => {
            out.push_str("(let ");
            write_bindings(out, bindings);
            out.push(' ');
            write_stmt(out, body);
            out.push(')');
        }
        StmtKind::Instantiate {
            name, args, child, ..
        } => {
            let _ = write!(out, "({}", name.name);
            write_args(out, args);
            if let Some(child) = child {
                out.push(' ');
                write_stmt(out, child);
            }
            out.push(')');
        }
        StmtKind::Modified { modifier, body, .. } => {
            let _ = write!(out, "({} ", modifier.as_char());
            write_stmt(out, body);
            out.push(')');
        }
        StmtKind::Include(path) => {
            let _ = write!(out, "(include <{}>)", path.path);
        }
        StmtKind::Use(path) => {
            let _ = write!(out, "(use <{}>)", path.path);
        }
        StmtKind::Error => out.push_str("(error)"),
    }
}

fn write_params(out: &mut String, params: &[Param]) {
    out.push('(');
    for (i, p) in params.iter().enumerate() {
        if i > 0 {
            out.push(' ');
        }
        match &p.default {
            None => out.push_str(&p.name.name),
            Some(d) => {
                let _ = write!(out, "(= {} ", p.name.name);
                write_expr(out, d);
                out.push(')');
            }
        }
    }
    out.push(')');
}

fn write_bindings(out: &mut String, bindings: &[Binding]) {
    out.push('(');
    for (i, b) in bindings.iter().enumerate() {
        if i > 0 {
            out.push(' ');
        }
        let _ = write!(out, "(= {} ", b.name.name);
        write_expr(out, &b.value);
        out.push(')');
    }
    out.push(')');
}

/// Arguments, each preceded by a space.
fn write_args(out: &mut String, args: &[Arg]) {
    for a in args {
        out.push(' ');
        match &a.name {
            None => write_expr(out, &a.value),
            Some(name) => {
                let _ = write!(out, "(= {} ", name.name);
                write_expr(out, &a.value);
                out.push(')');
            }
        }
    }
}

fn write_expr(out: &mut String, expr: &Expr) {
    match &expr.kind {
        ExprKind::Number(n) => {
            let _ = write!(out, "{n}");
        }
        ExprKind::String(s) => {
            let _ = write!(out, "{s:?}");
        }
        ExprKind::Bool(b) => {
            let _ = write!(out, "{b}");
        }
        ExprKind::Undef => out.push_str("undef"),
        ExprKind::Ident(id) => out.push_str(&id.name),
        ExprKind::Paren(inner) => {
            out.push_str("(paren ");
            write_expr(out, inner);
            out.push(')');
        }
        ExprKind::Unary { op, operand, .. } => {
            let name = match op {
                UnaryOp::Not => "!",
                UnaryOp::Neg => "neg",
                UnaryOp::Plus => "pos",
            };
            let _ = write!(out, "({name} ");
            write_expr(out, operand);
            out.push(')');
        }
        ExprKind::Binary { op, lhs, rhs, .. } => {
            let _ = write!(out, "({} ", op.as_str());
            write_expr(out, lhs);
            out.push(' ');
            write_expr(out, rhs);
            out.push(')');
        }
        ExprKind::Ternary { cond, then, els } => {
            out.push_str("(? ");
            write_expr(out, cond);
            out.push(' ');
            write_expr(out, then);
            out.push(' ');
            write_expr(out, els);
            out.push(')');
        }
        ExprKind::Call { callee, args, .. } => {
            out.push_str("(call ");
            write_expr(out, callee);
            write_args(out, args);
            out.push(')');
        }
        ExprKind::Index { base, index } => {
            out.push_str("(index ");
            write_expr(out, base);
            out.push(' ');
            write_expr(out, index);
            out.push(')');
        }
        ExprKind::Member { base, member } => {
            out.push_str("(. ");
            write_expr(out, base);
            let _ = write!(out, " {})", member.name);
        }
        ExprKind::Vector(elems) => {
            out.push('[');
            for (i, e) in elems.iter().enumerate() {
                if i > 0 {
                    out.push(' ');
                }
                write_elem(out, e);
            }
            out.push(']');
        }
        ExprKind::Range { start, step, end } => {
            out.push_str("(range ");
            write_expr(out, start);
            if let Some(step) = step {
                out.push(' ');
                write_expr(out, step);
            }
            out.push(' ');
            write_expr(out, end);
            out.push(')');
        }
        ExprKind::Let { bindings, body } => {
            out.push_str("(let ");
            write_bindings(out, bindings);
            out.push(' ');
            write_expr(out, body);
            out.push(')');
        }
        ExprKind::Assert { args, body, .. } | ExprKind::Echo { args, body, .. } => {
            let name = if matches!(expr.kind, ExprKind::Assert { .. }) {
                "assert"
            } else {
                "echo"
            };
            let _ = write!(out, "({name} (args");
            write_args(out, args);
            out.push(')');
            if let Some(body) = body {
                out.push(' ');
                write_expr(out, body);
            }
            out.push(')');
        }
        ExprKind::FunctionLit { params, body } => {
            out.push_str("(fn ");
            write_params(out, params);
            out.push(' ');
            write_expr(out, body);
            out.push(')');
        }
        ExprKind::Error => out.push_str("(error)"),
    }
}

fn write_elem(out: &mut String, elem: &ListElem) {
    match &elem.kind {
        ListElemKind::Expr(e) => write_expr(out, e),
        ListElemKind::For { bindings, body } => {
            out.push_str("(for ");
            write_bindings(out, bindings);
            out.push(' ');
            write_elem(out, body);
            out.push(')');
        }
        ListElemKind::CFor {
            init,
            cond,
            update,
            body,
        } => {
            out.push_str("(cfor ");
            write_bindings(out, init);
            out.push(' ');
            write_expr(out, cond);
            out.push(' ');
            write_bindings(out, update);
            out.push(' ');
            write_elem(out, body);
            out.push(')');
        }
        ListElemKind::If { cond, then, els } => {
            out.push_str("(if ");
            write_expr(out, cond);
            out.push(' ');
            write_elem(out, then);
            if let Some(els) = els {
                out.push(' ');
                write_elem(out, els);
            }
            out.push(')');
        }
        ListElemKind::Each(inner) => {
            out.push_str("(each ");
            write_elem(out, inner);
            out.push(')');
        }
        ListElemKind::Let { bindings, body } => {
            out.push_str("(let ");
            write_bindings(out, bindings);
            out.push(' ');
            write_elem(out, body);
            out.push(')');
        }
        ListElemKind::Paren(inner) => {
            out.push_str("(paren ");
            write_elem(out, inner);
            out.push(')');
        }
    }
}
