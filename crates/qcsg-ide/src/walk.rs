//! A pre-order walk over the syntax tree, and the calls it contains.

use qcsg_syntax::ast::{
    Arg, Binding, Expr, ExprKind, Ident, ListElem, ListElemKind, Param, SourceFile, Span, Stmt,
    StmtKind,
};

/// A node met by [`walk`].
#[derive(Clone, Copy, Debug)]
pub(crate) enum Node<'a> {
    /// A statement.
    Stmt(&'a Stmt),
    /// An expression.
    Expr(&'a Expr),
}

/// A call written in the source: a module instantiation or a call of a named function.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Call<'a> {
    /// The called name.
    pub name: &'a Ident,
    /// The arguments.
    pub args: &'a [Arg],
    /// The parenthesised argument list.
    pub args_span: Span,
    /// Whether it instantiates a module (otherwise it calls a function).
    pub is_module: bool,
}

impl<'a> Node<'a> {
    /// The call this node is, if it is one.
    pub(crate) fn call(self) -> Option<Call<'a>> {
        match self {
            Node::Stmt(Stmt {
                kind:
                    StmtKind::Instantiate {
                        name,
                        args,
                        args_span,
                        ..
                    },
                ..
            }) => Some(Call {
                name,
                args,
                args_span: *args_span,
                is_module: true,
            }),
            Node::Expr(Expr {
                kind:
                    ExprKind::Call {
                        callee,
                        args,
                        args_span,
                    },
                ..
            }) => match &callee.kind {
                ExprKind::Ident(name) => Some(Call {
                    name,
                    args,
                    args_span: *args_span,
                    is_module: false,
                }),
                _ => None,
            },
            _ => None,
        }
    }
}

/// Visits every statement and expression of `file`, parents before children, in source order.
pub(crate) fn walk<'a>(file: &'a SourceFile, visit: &mut dyn FnMut(Node<'a>)) {
    for stmt in &file.stmts {
        walk_stmt(stmt, visit);
    }
}

/// Every call of `file`.
pub(crate) fn calls(file: &SourceFile) -> Vec<Call<'_>> {
    let mut out = Vec::new();
    walk(file, &mut |node| out.extend(node.call()));
    out
}

/// The innermost call whose argument list contains `offset` (strictly after its `(`).
pub(crate) fn call_at(file: &SourceFile, offset: usize) -> Option<Call<'_>> {
    let offset = offset as u32;
    calls(file)
        .into_iter()
        .filter(|call| call.args_span.start < offset && offset <= call.args_span.end)
        .filter(|call| offset < call.args_span.end || !closed(call))
        .min_by_key(|call| call.args_span.len())
}

/// Whether a call's argument list ends with its `)` (a broken one may run to the end).
fn closed(call: &Call<'_>) -> bool {
    call.args
        .last()
        .is_none_or(|arg| arg.span.end < call.args_span.end)
}

fn walk_stmt<'a>(stmt: &'a Stmt, visit: &mut dyn FnMut(Node<'a>)) {
    visit(Node::Stmt(stmt));
    match &stmt.kind {
        StmtKind::Assign { value, .. } => walk_expr(value, visit),
        StmtKind::ModuleDef { params, body, .. } => {
            walk_params(params, visit);
            walk_stmt(body, visit);
        }
        StmtKind::FunctionDef { params, body, .. } => {
            walk_params(params, visit);
            walk_expr(body, visit);
        }
        StmtKind::Block(stmts) => stmts.iter().for_each(|s| walk_stmt(s, visit)),
        StmtKind::If { cond, then, els } => {
            walk_expr(cond, visit);
            walk_stmt(then, visit);
            if let Some(els) = els {
                walk_stmt(els, visit);
            }
        }
        StmtKind::For { bindings, body } | StmtKind::Let { bindings, body } => {
            walk_bindings(bindings, visit);
            walk_stmt(body, visit);
        }
        StmtKind::Instantiate { args, child, .. } => {
            walk_args(args, visit);
            if let Some(child) = child {
                walk_stmt(child, visit);
            }
        }
        StmtKind::Modified { body, .. } => walk_stmt(body, visit),
        StmtKind::Empty | StmtKind::Include(_) | StmtKind::Use(_) | StmtKind::Error => {}
    }
}

fn walk_params<'a>(params: &'a [Param], visit: &mut dyn FnMut(Node<'a>)) {
    for default in params.iter().filter_map(|p| p.default.as_ref()) {
        walk_expr(default, visit);
    }
}

fn walk_args<'a>(args: &'a [Arg], visit: &mut dyn FnMut(Node<'a>)) {
    args.iter().for_each(|a| walk_expr(&a.value, visit));
}

fn walk_bindings<'a>(bindings: &'a [Binding], visit: &mut dyn FnMut(Node<'a>)) {
    bindings.iter().for_each(|b| walk_expr(&b.value, visit));
}

fn walk_expr<'a>(expr: &'a Expr, visit: &mut dyn FnMut(Node<'a>)) {
    visit(Node::Expr(expr));
    match &expr.kind {
        ExprKind::Paren(inner) => walk_expr(inner, visit),
        ExprKind::Unary { operand, .. } => walk_expr(operand, visit),
        ExprKind::Binary { lhs, rhs, .. } => {
            walk_expr(lhs, visit);
            walk_expr(rhs, visit);
        }
        ExprKind::Ternary { cond, then, els } => {
            walk_expr(cond, visit);
            walk_expr(then, visit);
            walk_expr(els, visit);
        }
        ExprKind::Call { callee, args, .. } => {
            walk_expr(callee, visit);
            walk_args(args, visit);
        }
        ExprKind::Index { base, index } => {
            walk_expr(base, visit);
            walk_expr(index, visit);
        }
        ExprKind::Member { base, .. } => walk_expr(base, visit),
        ExprKind::Vector(elems) => elems.iter().for_each(|e| walk_elem(e, visit)),
        ExprKind::Range { start, step, end } => {
            walk_expr(start, visit);
            if let Some(step) = step {
                walk_expr(step, visit);
            }
            walk_expr(end, visit);
        }
        ExprKind::Let { bindings, body } => {
            walk_bindings(bindings, visit);
            walk_expr(body, visit);
        }
        ExprKind::Assert { args, body, .. } | ExprKind::Echo { args, body, .. } => {
            walk_args(args, visit);
            if let Some(body) = body {
                walk_expr(body, visit);
            }
        }
        ExprKind::FunctionLit { params, body } => {
            walk_params(params, visit);
            walk_expr(body, visit);
        }
        ExprKind::Number(_)
        | ExprKind::String(_)
        | ExprKind::Bool(_)
        | ExprKind::Undef
        | ExprKind::Ident(_)
        | ExprKind::Error => {}
    }
}

fn walk_elem<'a>(elem: &'a ListElem, visit: &mut dyn FnMut(Node<'a>)) {
    match &elem.kind {
        ListElemKind::Expr(expr) => walk_expr(expr, visit),
        ListElemKind::For { bindings, body } | ListElemKind::Let { bindings, body } => {
            walk_bindings(bindings, visit);
            walk_elem(body, visit);
        }
        ListElemKind::CFor {
            init,
            cond,
            update,
            body,
        } => {
            walk_bindings(init, visit);
            walk_expr(cond, visit);
            walk_bindings(update, visit);
            walk_elem(body, visit);
        }
        ListElemKind::If { cond, then, els } => {
            walk_expr(cond, visit);
            walk_elem(then, visit);
            if let Some(els) = els {
                walk_elem(els, visit);
            }
        }
        ListElemKind::Each(inner) | ListElemKind::Paren(inner) => walk_elem(inner, visit),
    }
}
