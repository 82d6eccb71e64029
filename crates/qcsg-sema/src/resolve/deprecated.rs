//! OpenSCAD's deprecated modules that old files and libraries (MCAD) still use: `child(i)`, the
//! old name of `children(i)`; `import_stl`, `import_off`, `import_dxf`, old names of `import`;
//! `dxf_linear_extrude` and `dxf_rotate_extrude`, extrusions of an `import`; and
//! `assign(a = 1, …) child`, the old form of `let`. All keep OpenSCAD 2021.01's meaning and get
//! warning `W0109` at the name, with the modern form as help.
//!
//! `assign` binds its named arguments for its child like `let`, except that OpenSCAD evaluates
//! every value in the scope around it before binding any (`assign(a = 1, b = a + 1)` sees the
//! outer `a`), so the values are resolved first and the names bound afterwards.

use qcsg_diag::{Diagnostic, FileId};
use qcsg_syntax::ast::{Arg, Ident, Stmt};

use crate::{DefKind, codes};

use super::Resolver;

impl<'a> Resolver<'a> {
    /// A deprecated module that is another under an old name (`child`, `import_stl`, …): warning
    /// `W0109` with the modern form; nothing for a module that is not deprecated.
    pub(super) fn deprecated_module(&mut self, file: FileId, name: &Ident) {
        let Some((message, help)) = deprecation(&name.name) else {
            return;
        };
        self.diagnostics.push(
            Diagnostic::warning(codes::DEPRECATED_MODULE, message, file, name.span).with_help(help),
        );
    }

    /// `linear_extrude(file = …)` and `rotate_extrude(file = …)`: OpenSCAD's deprecated reading
    /// of a drawing by the extrusion itself, warned at the `file` argument.
    pub(super) fn deprecated_file_argument(&mut self, file: FileId, name: &Ident, args: &[Arg]) {
        if !matches!(name.name.as_str(), "linear_extrude" | "rotate_extrude") {
            return;
        }
        for arg in args {
            if arg.name.as_ref().is_some_and(|n| n.name == "file") {
                self.diagnostics.push(
                    Diagnostic::warning(
                        codes::DEPRECATED_MODULE,
                        format!(
                            "`{}(file = …)` is deprecated in OpenSCAD: the drawing is read by \
                             a child `import`",
                            name.name
                        ),
                        file,
                        arg.span,
                    )
                    .with_help(format!(
                        "write `{}(…) import(\"drawing.dxf\", layer = …);`",
                        name.name
                    )),
                );
            }
        }
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

/// The warning and help for a deprecated built-in module that is another under an old name.
fn deprecation(name: &str) -> Option<(&'static str, &'static str)> {
    Some(match name {
        "child" => (
            "`child` is deprecated in OpenSCAD: it is `children` with one child",
            "write `children(i)`: `child()` is `children(0)`, `child(i)` is `children(i)`",
        ),
        "import_stl" => (
            "`import_stl` is deprecated in OpenSCAD: it is `import`",
            "write `import(\"part.stl\")`",
        ),
        "import_off" => (
            "`import_off` is deprecated in OpenSCAD: it is `import`",
            "write `import(\"part.off\")`",
        ),
        "import_dxf" => (
            "`import_dxf` is deprecated in OpenSCAD: it is `import`",
            "write `import(\"drawing.dxf\", layer = …)`",
        ),
        "dxf_linear_extrude" => (
            "`dxf_linear_extrude` is deprecated in OpenSCAD: it is `linear_extrude` of an `import`",
            "write `linear_extrude(height = …) import(\"drawing.dxf\", layer = …);`",
        ),
        "dxf_rotate_extrude" => (
            "`dxf_rotate_extrude` is deprecated in OpenSCAD: it is `rotate_extrude` of an `import`",
            "write `rotate_extrude() import(\"drawing.dxf\", layer = …);`",
        ),
        _ => return None,
    })
}
