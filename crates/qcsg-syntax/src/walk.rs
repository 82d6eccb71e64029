//! The one walk over the syntax tree: every statement, expression and list element under some
//! roots, parents before children, in source order. It keeps its own stack instead of
//! recursing, so a tree as deep as the parser allows cannot overflow the thread's stack.

use crate::ast::{Expr, ExprKind, ListElem, ListElemKind, Stmt, StmtKind};

/// A node of the syntax tree.
#[derive(Clone, Copy, Debug)]
pub enum Node<'t> {
    /// A statement.
    Stmt(&'t Stmt),
    /// An expression.
    Expr(&'t Expr),
    /// An element of a vector literal or list comprehension.
    Elem(&'t ListElem),
}

/// Calls `visit` on every node under (and including) `roots`, each before its children and
/// the nodes in the order their text appears.
pub fn walk<'t>(roots: impl IntoIterator<Item = Node<'t>>, mut visit: impl FnMut(Node<'t>)) {
    let mut stack: Vec<Node<'t>> = roots.into_iter().collect();
    stack.reverse();
    let mut children = Vec::new();
    while let Some(node) = stack.pop() {
        visit(node);
        match node {
            Node::Stmt(stmt) => stmt_children(stmt, &mut children),
            Node::Expr(expr) => expr_children(expr, &mut children),
            Node::Elem(elem) => elem_children(elem, &mut children),
        }
        // Popped last-in first: the first child must go on top.
        stack.extend(children.drain(..).rev());
    }
}

fn stmt_children<'t>(stmt: &'t Stmt, out: &mut Vec<Node<'t>>) {
    match &stmt.kind {
        StmtKind::Assign { value, .. } => out.push(Node::Expr(value)),
        StmtKind::ModuleDef { params, body, .. } => {
            out.extend(
                params
                    .iter()
                    .filter_map(|p| p.default.as_ref())
                    .map(Node::Expr),
            );
            out.push(Node::Stmt(body));
        }
        StmtKind::FunctionDef { params, body, .. } => {
            out.extend(
                params
                    .iter()
                    .filter_map(|p| p.default.as_ref())
                    .map(Node::Expr),
            );
            out.push(Node::Expr(body));
        }
        StmtKind::Block(stmts) => out.extend(stmts.iter().map(Node::Stmt)),
        StmtKind::If { cond, then, els } => {
            out.push(Node::Expr(cond));
            out.push(Node::Stmt(then));
            out.extend(els.as_deref().map(Node::Stmt));
        }
        StmtKind::For { bindings, body } | StmtKind::Let { bindings, body } => {
            out.extend(bindings.iter().map(|b| Node::Expr(&b.value)));
            out.push(Node::Stmt(body));
        }
        StmtKind::Instantiate { args, child, .. } => {
            out.extend(args.iter().map(|a| Node::Expr(&a.value)));
            out.extend(child.as_deref().map(Node::Stmt));
        }
        StmtKind::Modified { body, .. } => out.push(Node::Stmt(body)),
        StmtKind::Empty | StmtKind::Include(_) | StmtKind::Use(_) | StmtKind::Error => {}
    }
}

fn expr_children<'t>(expr: &'t Expr, out: &mut Vec<Node<'t>>) {
    match &expr.kind {
        ExprKind::Paren(inner) | ExprKind::Unary { operand: inner, .. } => {
            out.push(Node::Expr(inner))
        }
        ExprKind::Binary { lhs, rhs, .. } => out.extend([Node::Expr(lhs), Node::Expr(rhs)]),
        ExprKind::Ternary { cond, then, els } => {
            out.extend([Node::Expr(cond), Node::Expr(then), Node::Expr(els)])
        }
        ExprKind::Call { callee, args, .. } => {
            out.push(Node::Expr(callee));
            out.extend(args.iter().map(|a| Node::Expr(&a.value)));
        }
        ExprKind::Index { base, index } => out.extend([Node::Expr(base), Node::Expr(index)]),
        ExprKind::Member { base, .. } => out.push(Node::Expr(base)),
        ExprKind::Vector(elems) => out.extend(elems.iter().map(Node::Elem)),
        ExprKind::Range { start, step, end } => {
            out.push(Node::Expr(start));
            out.extend(step.as_deref().map(Node::Expr));
            out.push(Node::Expr(end));
        }
        ExprKind::Let { bindings, body } => {
            out.extend(bindings.iter().map(|b| Node::Expr(&b.value)));
            out.push(Node::Expr(body));
        }
        ExprKind::Assert { args, body, .. } | ExprKind::Echo { args, body, .. } => {
            out.extend(args.iter().map(|a| Node::Expr(&a.value)));
            out.extend(body.as_deref().map(Node::Expr));
        }
        ExprKind::FunctionLit { params, body } => {
            out.extend(
                params
                    .iter()
                    .filter_map(|p| p.default.as_ref())
                    .map(Node::Expr),
            );
            out.push(Node::Expr(body));
        }
        ExprKind::Number(_)
        | ExprKind::String(_)
        | ExprKind::Bool(_)
        | ExprKind::Undef
        | ExprKind::Ident(_)
        | ExprKind::Error => {}
    }
}

fn elem_children<'t>(elem: &'t ListElem, out: &mut Vec<Node<'t>>) {
    match &elem.kind {
        ListElemKind::Expr(expr) => out.push(Node::Expr(expr)),
        ListElemKind::For { bindings, body } | ListElemKind::Let { bindings, body } => {
            out.extend(bindings.iter().map(|b| Node::Expr(&b.value)));
            out.push(Node::Elem(body));
        }
        ListElemKind::CFor {
            init,
            cond,
            update,
            body,
        } => {
            out.extend(init.iter().map(|b| Node::Expr(&b.value)));
            out.push(Node::Expr(cond));
            out.extend(update.iter().map(|b| Node::Expr(&b.value)));
            out.push(Node::Elem(body));
        }
        ListElemKind::If { cond, then, els } => {
            out.push(Node::Expr(cond));
            out.push(Node::Elem(then));
            out.extend(els.as_deref().map(Node::Elem));
        }
        ListElemKind::Each(inner) | ListElemKind::Paren(inner) => out.push(Node::Elem(inner)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{FileId, parse};

    /// The spans' starts of every expression, in the order visited.
    fn expression_starts(text: &str) -> Vec<u32> {
        let parsed = parse(text, FileId(0));
        assert!(parsed.diagnostics.is_empty(), "{:?}", parsed.diagnostics);
        let mut starts = Vec::new();
        walk(parsed.file.stmts.iter().map(Node::Stmt), |node| {
            if let Node::Expr(expr) = node {
                starts.push(expr.span.start);
            }
        });
        starts
    }

    #[test]
    fn every_expression_is_visited_in_source_order() {
        let text = "function f(a = 1) = [for (i = [0 : 2]) if (i > a) i * 2, each [3]];\n\
                    module m(r = 2) { translate([r, 0, 0]) sphere(r); }\n\
                    x = let (y = 4) y ? f() : [for (i = 0; i < 2; i = i + 1) i][0];\n";
        let starts = expression_starts(text);
        let mut sorted = starts.clone();
        sorted.sort();
        assert_eq!(starts, sorted, "not in source order");
        // Expressions in every kind of place: a default, list-comprehension parts, a module's
        // arguments, a let, a ternary's branch, a C-style for's condition.
        let places = [
            "1)",
            "[0 : 2]",
            "i > a",
            "i * 2",
            "[3]",
            "[r, 0, 0]",
            "let (y",
            "4)",
            "f()",
            "i < 2",
        ];
        for place in places {
            let at = text.find(place).unwrap() as u32;
            assert!(starts.contains(&at), "{place} at {at} not visited");
        }
    }

    #[test]
    fn the_deepest_tree_the_parser_accepts_is_walked_whole() {
        let depth = crate::lexer::MAX_NESTING;
        let text = format!("x = {}1{};", "(".repeat(depth), ")".repeat(depth));
        let parsed = parse(&text, FileId(0));
        assert!(parsed.diagnostics.is_empty(), "{:?}", parsed.diagnostics);
        let mut count = 0usize;
        walk(parsed.file.stmts.iter().map(Node::Stmt), |_| count += 1);
        // The statement, each parenthesis and the number.
        assert_eq!(count, depth + 2);
    }
}
