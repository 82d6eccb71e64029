//! An iterative walk over every statement, expression and list element of a subtree (no
//! recursion, so arbitrarily deep trees cannot overflow the stack).

use qcsg_syntax::ast::{Expr, ExprKind, ListElem, ListElemKind, Stmt, StmtKind};

/// A node of the syntax tree.
#[derive(Clone, Copy)]
pub(crate) enum Node<'t> {
    Stmt(&'t Stmt),
    Expr(&'t Expr),
    Elem(&'t ListElem),
}

/// Calls `visit` on every node under (and including) `roots`, parents before children.
pub(crate) fn walk<'t>(roots: impl IntoIterator<Item = Node<'t>>, mut visit: impl FnMut(Node<'t>)) {
    let mut stack: Vec<Node<'t>> = roots.into_iter().collect();
    while let Some(node) = stack.pop() {
        visit(node);
        match node {
            Node::Stmt(stmt) => push_stmt_children(stmt, &mut stack),
            Node::Expr(expr) => push_expr_children(expr, &mut stack),
            Node::Elem(elem) => push_elem_children(elem, &mut stack),
        }
    }
}

fn push_stmt_children<'t>(stmt: &'t Stmt, stack: &mut Vec<Node<'t>>) {
    match &stmt.kind {
        StmtKind::Assign { value, .. } => stack.push(Node::Expr(value)),
        StmtKind::ModuleDef { params, body, .. } => {
            stack.extend(
                params
                    .iter()
                    .filter_map(|p| p.default.as_ref())
                    .map(Node::Expr),
            );
            stack.push(Node::Stmt(body));
        }
        StmtKind::FunctionDef { params, body, .. } => {
            stack.extend(
                params
                    .iter()
                    .filter_map(|p| p.default.as_ref())
                    .map(Node::Expr),
            );
            stack.push(Node::Expr(body));
        }
        StmtKind::Block(stmts) => stack.extend(stmts.iter().map(Node::Stmt)),
        StmtKind::If { cond, then, els } => {
            stack.push(Node::Expr(cond));
            stack.push(Node::Stmt(then));
            stack.extend(els.as_deref().map(Node::Stmt));
        }
        StmtKind::For { bindings, body } | StmtKind::Let { bindings, body } => {
            stack.extend(bindings.iter().map(|b| Node::Expr(&b.value)));
            stack.push(Node::Stmt(body));
        }
        StmtKind::Instantiate { args, child, .. } => {
            stack.extend(args.iter().map(|a| Node::Expr(&a.value)));
            stack.extend(child.as_deref().map(Node::Stmt));
        }
        StmtKind::Modified { body, .. } => stack.push(Node::Stmt(body)),
        StmtKind::Empty | StmtKind::Include(_) | StmtKind::Use(_) | StmtKind::Error => {}
    }
}

fn push_expr_children<'t>(expr: &'t Expr, stack: &mut Vec<Node<'t>>) {
    match &expr.kind {
        ExprKind::Paren(inner) | ExprKind::Unary { operand: inner, .. } => {
            stack.push(Node::Expr(inner))
        }
        ExprKind::Binary { lhs, rhs, .. } => {
            stack.push(Node::Expr(lhs));
            stack.push(Node::Expr(rhs));
        }
        ExprKind::Ternary { cond, then, els } => {
            stack.extend([Node::Expr(cond), Node::Expr(then), Node::Expr(els)])
        }
        ExprKind::Call { callee, args, .. } => {
            stack.push(Node::Expr(callee));
            stack.extend(args.iter().map(|a| Node::Expr(&a.value)));
        }
        ExprKind::Index { base, index } => stack.extend([Node::Expr(base), Node::Expr(index)]),
        ExprKind::Member { base, .. } => stack.push(Node::Expr(base)),
        ExprKind::Vector(elems) => stack.extend(elems.iter().map(Node::Elem)),
        ExprKind::Range { start, step, end } => {
            stack.push(Node::Expr(start));
            stack.extend(step.as_deref().map(Node::Expr));
            stack.push(Node::Expr(end));
        }
        ExprKind::Let { bindings, body } => {
            stack.extend(bindings.iter().map(|b| Node::Expr(&b.value)));
            stack.push(Node::Expr(body));
        }
        ExprKind::Assert { args, body, .. } | ExprKind::Echo { args, body, .. } => {
            stack.extend(args.iter().map(|a| Node::Expr(&a.value)));
            stack.extend(body.as_deref().map(Node::Expr));
        }
        ExprKind::FunctionLit { params, body } => {
            stack.extend(
                params
                    .iter()
                    .filter_map(|p| p.default.as_ref())
                    .map(Node::Expr),
            );
            stack.push(Node::Expr(body));
        }
        ExprKind::Number(_)
        | ExprKind::String(_)
        | ExprKind::Bool(_)
        | ExprKind::Undef
        | ExprKind::Ident(_)
        | ExprKind::Error => {}
    }
}

fn push_elem_children<'t>(elem: &'t ListElem, stack: &mut Vec<Node<'t>>) {
    match &elem.kind {
        ListElemKind::Expr(expr) => stack.push(Node::Expr(expr)),
        ListElemKind::For { bindings, body } | ListElemKind::Let { bindings, body } => {
            stack.extend(bindings.iter().map(|b| Node::Expr(&b.value)));
            stack.push(Node::Elem(body));
        }
        ListElemKind::CFor {
            init,
            cond,
            update,
            body,
        } => {
            stack.extend(init.iter().chain(update).map(|b| Node::Expr(&b.value)));
            stack.push(Node::Expr(cond));
            stack.push(Node::Elem(body));
        }
        ListElemKind::If { cond, then, els } => {
            stack.push(Node::Expr(cond));
            stack.push(Node::Elem(then));
            stack.extend(els.as_deref().map(Node::Elem));
        }
        ListElemKind::Each(inner) | ListElemKind::Paren(inner) => stack.push(Node::Elem(inner)),
    }
}
