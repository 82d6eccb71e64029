//! Statements: definitions' bodies, control flow, modifiers and module instantiations, with
//! the diagnostics for a module name that names no module.

use qcsg_diag::{Diagnostic, FileId, Span};
use qcsg_syntax::ast::{Arg, Ident, Modifier, Stmt, StmtKind};

use crate::builtins;
use crate::{DefKind, Namespace, Target, codes};

use super::arguments::builtin_module_signature;
use super::names::{FunctionLookup, ModuleLookup, VarLookup};
use super::scopes::element_type;
use super::{Item, Resolver, STACK_GROWTH, STACK_RED_ZONE};

const FUNCTION_AS_MODULE_HELP: &str =
    "functions compute values and are called in expressions (`x = f(1);`); they create no solid";

impl<'a> Resolver<'a> {
    pub(super) fn stmt(&mut self, item: Item<'a>) {
        stacker::maybe_grow(STACK_RED_ZONE, STACK_GROWTH, || self.stmt_inner(item))
    }

    fn stmt_inner(&mut self, item: Item<'a>) {
        let Item { file, stmt, chain } = item;
        match &stmt.kind {
            StmtKind::Empty
            | StmtKind::Error
            | StmtKind::Assign { .. }
            | StmtKind::Include(_)
            | StmtKind::Use(_) => {}
            StmtKind::Block(_) => self.child_scope(file, chain, stmt),
            StmtKind::ModuleDef { name, params, body } => {
                let def = self
                    .def_index
                    .get(&(file, name.span, DefKind::Module))
                    .copied();
                self.enclosing.extend(def);
                self.enter_params(file, params, def);
                self.child_scope(file, chain, body);
                self.pop_scope();
                if def.is_some() {
                    self.enclosing.pop();
                }
            }
            StmtKind::FunctionDef { name, params, body } => {
                let def = self
                    .def_index
                    .get(&(file, name.span, DefKind::Function))
                    .copied();
                self.enclosing.extend(def);
                self.enter_params(file, params, def);
                let returns = self.expr(file, body);
                if let Some(definition) = def.and_then(|d| self.definitions.get_mut(d.0 as usize)) {
                    definition.ty = returns;
                }
                self.pop_scope();
                if def.is_some() {
                    self.enclosing.pop();
                }
            }
            StmtKind::If { cond, then, els } => {
                self.expr(file, cond);
                self.child_scope(file, chain, then);
                if let Some(els) = els {
                    self.child_scope(file, chain, els);
                }
            }
            StmtKind::For { bindings, body } => {
                self.push_scope();
                self.bindings(file, bindings, DefKind::LoopVariable);
                self.child_scope(file, chain, body);
                self.pop_scope();
            }
            StmtKind::Let { bindings, body } => {
                self.push_scope();
                self.bindings(file, bindings, DefKind::LetVariable);
                self.child_scope(file, chain, body);
                self.pop_scope();
            }
            StmtKind::Instantiate {
                name,
                args,
                args_span,
                child,
            } => {
                self.instantiate(item, name, args, *args_span, child.as_deref());
            }
            StmtKind::Modified {
                modifier,
                modifier_span,
                body,
            } => {
                let (code, what) = match modifier {
                    Modifier::Background => {
                        (codes::BACKGROUND_SUBTREE, "`%` marks a background subtree")
                    }
                    Modifier::Disable => (codes::DISABLED_SUBTREE, "`*` disables this subtree"),
                    Modifier::ShowOnly | Modifier::Highlight => ("", ""),
                };
                if !code.is_empty() {
                    self.diagnostics.push(
                        Diagnostic::warning(code, format!("{what}: it is not part of the solid"), file, *modifier_span)
                            .with_help("remove the modifier when the subtree is meant to be part of the result"),
                    );
                }
                self.stmt(Item {
                    file,
                    stmt: body,
                    chain,
                });
            }
        }
    }

    fn instantiate(
        &mut self,
        item: Item<'a>,
        name: &Ident,
        args: &'a [Arg],
        args_span: Span,
        child: Option<&'a Stmt>,
    ) {
        let file = item.file;
        match self.lookup_module(&name.name) {
            ModuleLookup::User(def) => {
                self.reference(file, name.span, Namespace::Module, Target::Definition(def));
                self.mark_used(def);
                let tys = self.args(file, args);
                if let Some(signature) = self.user_signature(def, "module") {
                    self.check_args(file, name, args_span, args, &tys, &signature);
                }
            }
            ModuleLookup::Builtin(module) if module.name == "intersection_for" => {
                self.reference(file, name.span, Namespace::Module, Target::Builtin);
                self.push_scope();
                for arg in args {
                    match &arg.name {
                        Some(binding_name) => {
                            let value_ty = self.expr(file, &arg.value);
                            if binding_name.is_special() {
                                self.tessellation_hint(file, binding_name);
                                continue;
                            }
                            let (def, _) = self.define(
                                DefKind::LoopVariable,
                                file,
                                binding_name,
                                arg.span,
                                None,
                            );
                            let ty = element_type(&value_ty);
                            self.definitions[def.0 as usize].ty = ty.clone();
                            self.bind(&binding_name.name, def, ty);
                        }
                        None => {
                            self.expr(file, &arg.value);
                            self.diagnostics.push(
                                Diagnostic::error(
                                    codes::TOO_MANY_ARGUMENTS,
                                    "`intersection_for` takes loop bindings, not positional arguments",
                                    file,
                                    arg.span,
                                )
                                .with_help("write `intersection_for (i = [0 : 3])`"),
                            );
                        }
                    }
                }
                if let Some(child) = child {
                    self.child_scope(file, item.chain, child);
                }
                self.pop_scope();
                return;
            }
            ModuleLookup::Builtin(module) if module.name == "assign" => {
                self.reference(file, name.span, Namespace::Module, Target::Builtin);
                self.assign(file, name, args, child, item.chain);
                return;
            }
            ModuleLookup::Builtin(module) => {
                self.reference(file, name.span, Namespace::Module, Target::Builtin);
                self.deprecated_module(file, name);
                self.deprecated_file_argument(file, name, args);
                let tys = self.args(file, args);
                let signature = builtin_module_signature(module);
                self.check_args(file, name, args_span, args, &tys, &signature);
            }
            ModuleLookup::Missing => {
                self.args(file, args);
                self.unknown_module(file, name);
            }
        }
        if let Some(child) = child {
            self.child_scope(file, item.chain, child);
        }
    }

    fn unknown_module(&mut self, file: FileId, name: &Ident) {
        if let Some(unsupported) = builtins::unsupported_module(&name.name) {
            let mut diagnostic = Diagnostic::error(
                codes::UNSUPPORTED_MODULE,
                format!("`{}` is not supported: {}", name.name, unsupported.reason),
                file,
                name.span,
            );
            if let Some(instead) = unsupported.instead {
                diagnostic = diagnostic.with_help(instead);
            }
            self.diagnostics.push(diagnostic);
            return;
        }
        match self.lookup_function(&name.name) {
            FunctionLookup::User(def) => {
                self.reference(
                    file,
                    name.span,
                    Namespace::Function,
                    Target::Definition(def),
                );
                self.mark_used(def);
                let mut diagnostic = Diagnostic::error(
                    codes::FUNCTION_USED_AS_MODULE,
                    format!("`{}` is a function, not a module", name.name),
                    file,
                    name.span,
                )
                .with_help(FUNCTION_AS_MODULE_HELP);
                if let Some(definition) = self.definition(def) {
                    diagnostic = diagnostic.with_label(
                        definition.file,
                        definition.name_span,
                        "function defined here",
                    );
                }
                self.diagnostics.push(diagnostic);
                return;
            }
            FunctionLookup::Builtin(_) => {
                self.diagnostics.push(
                    Diagnostic::error(
                        codes::FUNCTION_USED_AS_MODULE,
                        format!("`{}` is a built-in function, not a module", name.name),
                        file,
                        name.span,
                    )
                    .with_help(FUNCTION_AS_MODULE_HELP),
                );
                return;
            }
            FunctionLookup::Missing => {}
        }
        let mut diagnostic = Diagnostic::error(
            codes::UNDEFINED_MODULE,
            format!("undefined module `{}`", name.name),
            file,
            name.span,
        );
        if let VarLookup::Found(_) = self.lookup_var(&name.name) {
            diagnostic = diagnostic.with_help(format!(
                "`{}` is a variable; modules live in a separate namespace",
                name.name
            ));
        } else if let Some(suggestion) = self.suggest(&name.name, Namespace::Module) {
            diagnostic = diagnostic.with_help(format!(
                "a module with a similar name exists: `{suggestion}`"
            ));
        }
        self.diagnostics.push(diagnostic);
    }
}
