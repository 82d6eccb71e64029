//! OpenSCAD's deprecated modules that old files and libraries (MCAD) still use: `child(i)`, the
//! old name of `children(i)`, and `assign(a = 1, …) child`, the old form of `let`. Both keep
//! OpenSCAD 2021.01's meaning and get warning `W0109` at the name, with the modern form as help.
//!
//! `assign` binds its named arguments for its child like `let`, except that OpenSCAD evaluates
//! every value in the scope around it before binding any (`assign(a = 1, b = a + 1)` sees the
//! outer `a`), so the values are resolved first and the names bound afterwards.

use qcsg_diag::{Diagnostic, FileId};
use qcsg_syntax::ast::{Arg, Ident, Stmt};

use crate::{DefKind, codes};

use super::Resolver;

impl<'a> Resolver<'a> {
    /// `child(i)`: `children(i)` under its old name.
    pub(super) fn deprecated_child(&mut self, file: FileId, name: &Ident) {
        self.diagnostics.push(
            Diagnostic::warning(
                codes::DEPRECATED_MODULE,
                "`child` is deprecated in OpenSCAD: it is `children` with one child",
                file,
                name.span,
            )
            .with_help(
                "write `children(i)`: `child()` is `children(0)`, `child(i)` is `children(i)`",
            ),
        );
    }

    /// `assign(a = 1, b = 2) child`: the values resolved in the enclosing scope, then the names
    /// bound for the child as `let` binds them.
    pub(super) fn assign(
        &mut self,
        file: FileId,
        name: &Ident,
        args: &'a [Arg],
        child: Option<&'a Stmt>,
        chain: u32,
    ) {
        self.diagnostics.push(
            Diagnostic::warning(
                codes::DEPRECATED_MODULE,
                "`assign` is deprecated in OpenSCAD: it binds variables for its child",
                file,
                name.span,
            )
            .with_help(
                "write `let (a = 1, b = 2) { … }` (`let` binds in order: a value may use the \
                 bindings before it, where `assign` sees the enclosing scope's)",
            ),
        );
        let values: Vec<_> = args.iter().map(|a| self.expr(file, &a.value)).collect();
        self.push_scope();
        for (arg, ty) in args.iter().zip(values) {
            // OpenSCAD ignores positional arguments of `assign`; evaluation warns about them.
            let Some(binding) = &arg.name else { continue };
            let (def, _) = self.define(DefKind::LetVariable, file, binding, arg.span, None);
            self.definitions[def.0 as usize].ty = ty.clone();
            self.tessellation_hint(file, binding);
            self.bind(&binding.name, def, ty);
        }
        if let Some(child) = child {
            self.child_scope(file, chain, child);
        }
        self.pop_scope();
    }
}
