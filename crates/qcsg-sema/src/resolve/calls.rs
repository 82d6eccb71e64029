//! Function calls in expressions: OpenSCAD reads a variable of the callee's name first and calls
//! it if it holds a function, else the function of that name; the diagnostics say what the name
//! is when it is not a function.

use qcsg_diag::{Diagnostic, FileId, Span};
use qcsg_syntax::ast::{Arg, Expr, ExprKind};

use crate::builtins;
use crate::ty::Ty;
use crate::{Namespace, Target, codes};

use super::Resolver;
use super::arguments::builtin_function_signature;
use super::names::{FunctionLookup, ModuleLookup, VarLookup};

impl<'a> Resolver<'a> {
    pub(super) fn call(
        &mut self,
        file: FileId,
        callee: &Expr,
        args: &[Arg],
        args_span: Span,
    ) -> Ty {
        let ExprKind::Ident(name) = &callee.kind else {
            let callee_ty = self.expr(file, callee);
            self.args(file, args);
            if callee_ty.is_known() && callee_ty != Ty::Function {
                self.diagnostics.push(Diagnostic::error(
                    codes::NOT_CALLABLE,
                    format!("cannot call {}: it is not a function", callee_ty.describe()),
                    file,
                    callee.span,
                ));
            }
            return Ty::Any;
        };
        let variable = match self.lookup_var(&name.name) {
            VarLookup::Found(binding) => Some(binding),
            _ => None,
        };
        let function = self.lookup_function(&name.name);
        let tys = self.args(file, args);
        // OpenSCAD reads a variable of that name first and calls it if it holds a function. When
        // the variable's type is unknown and a function of the name exists too, either may run:
        // resolve to the function but check no arguments.
        let ambiguous = variable.as_ref().is_some_and(|b| b.ty == Ty::Any);
        if let Some(def) = variable.as_ref().filter(|_| ambiguous).and_then(|b| b.def) {
            self.mark_used(def);
        }
        if let Some(binding) = &variable {
            let through_variable = binding.ty == Ty::Function
                || (binding.ty == Ty::Any && matches!(function, FunctionLookup::Missing));
            if through_variable {
                self.use_binding(file, name.span, binding);
                if let Some(signature) = binding
                    .def
                    .and_then(|def| self.user_signature(def, "function"))
                {
                    self.check_args(file, name, args_span, args, &tys, &signature);
                }
                return Ty::Any;
            }
        }
        match function {
            FunctionLookup::User(def) => {
                self.reference(
                    file,
                    name.span,
                    Namespace::Function,
                    Target::Definition(def),
                );
                self.mark_used(def);
                if let Some(signature) = self.user_signature(def, "function")
                    && !ambiguous
                {
                    self.check_args(file, name, args_span, args, &tys, &signature);
                }
                // Known once the body has been resolved (so never for a recursive call).
                return if ambiguous {
                    Ty::Any
                } else {
                    self.definition(def).map_or(Ty::Any, |d| d.ty.clone())
                };
            }
            FunctionLookup::Builtin(function) => {
                self.reference(file, name.span, Namespace::Function, Target::Builtin);
                let signature = builtin_function_signature(function);
                if !ambiguous {
                    self.check_args(file, name, args_span, args, &tys, &signature);
                }
                return function.returns.ty();
            }
            FunctionLookup::Missing => {}
        }
        if let Some(binding) = variable {
            self.use_binding(file, name.span, &binding);
            let mut diagnostic = Diagnostic::error(
                codes::NOT_CALLABLE,
                format!(
                    "`{}` is {}, not a function",
                    name.name,
                    binding.ty.describe()
                ),
                file,
                name.span,
            );
            if let Some(definition) = binding.def.and_then(|def| self.definition(def)) {
                diagnostic =
                    diagnostic.with_label(definition.file, definition.name_span, "assigned here");
            }
            self.diagnostics.push(diagnostic);
            return Ty::Any;
        }
        if let Some(unsupported) = builtins::unsupported_function(&name.name) {
            self.diagnostics.push(Diagnostic::error(
                codes::UNSUPPORTED_FUNCTION,
                format!("`{}` is not supported: {}", name.name, unsupported.reason),
                file,
                name.span,
            ));
            return Ty::Any;
        }
        let module = self.lookup_module(&name.name);
        if !matches!(module, ModuleLookup::Missing)
            || builtins::unsupported_module(&name.name).is_some()
        {
            let mut diagnostic = Diagnostic::error(
                codes::MODULE_USED_AS_FUNCTION,
                format!("`{}` is a module, not a function", name.name),
                file,
                name.span,
            )
            .with_help("modules create solids and are instantiated as statements (`cube(1);`); they have no value");
            if let ModuleLookup::User(def) = module {
                self.reference(file, name.span, Namespace::Module, Target::Definition(def));
                self.mark_used(def);
                if let Some(definition) = self.definition(def) {
                    diagnostic = diagnostic.with_label(
                        definition.file,
                        definition.name_span,
                        "module defined here",
                    );
                }
            }
            self.diagnostics.push(diagnostic);
            return Ty::Any;
        }
        let mut diagnostic = Diagnostic::error(
            codes::UNDEFINED_FUNCTION,
            format!("undefined function `{}`", name.name),
            file,
            name.span,
        );
        if let Some(similar) = self.suggest(&name.name, Namespace::Function) {
            diagnostic = diagnostic.with_help(format!(
                "a function with a similar name exists: `{similar}`"
            ));
        }
        self.diagnostics.push(diagnostic);
        Ty::Any
    }
}
