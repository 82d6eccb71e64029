//! The calls a syntax tree contains, found by the syntax crate's walk ([`qcsg_syntax::walk`]).

use qcsg_syntax::ast::{Arg, Expr, ExprKind, Ident, SourceFile, Span, Stmt, StmtKind};
pub(crate) use qcsg_syntax::walk::Node;

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

/// The call `node` is, if it is one.
fn call_of(node: Node<'_>) -> Option<Call<'_>> {
    match node {
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

/// Visits every node of `file`, parents before children, in source order (the syntax crate's
/// walk from the file's statements).
pub(crate) fn walk<'a>(file: &'a SourceFile, visit: &mut dyn FnMut(Node<'a>)) {
    qcsg_syntax::walk::walk(file.stmts.iter().map(Node::Stmt), visit);
}

/// Every call of `file`.
pub(crate) fn calls(file: &SourceFile) -> Vec<Call<'_>> {
    let mut out = Vec::new();
    walk(file, &mut |node| out.extend(call_of(node)));
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
