//! What a name refers to: variables (with the in-order rule for assignments and the dynamic
//! `$`-variables), functions and modules, looked up through the open scopes, then the libraries
//! brought in by `use`, then the built-ins.

use qcsg_diag::{Diagnostic, FileId};
use qcsg_syntax::ast::{ExprKind, Ident, ListElemKind, Stmt, StmtKind};

use crate::builtins::{self, BuiltinFunction, BuiltinModule};
use crate::fxhash::{FxHashMap as HashMap, FxHashSet as HashSet};
use crate::ty::Ty;
use crate::{DefId, Namespace, Target, codes};
use qcsg_syntax::walk::{Node, walk};

use super::{Resolver, Scope, VarBinding};

/// What a variable name resolves to.
pub(super) enum VarLookup {
    Found(VarBinding),
    Builtin(Ty),
    /// Only assigned later in the same scope than the assignment reading it.
    AssignedLater(Option<DefId>),
    Missing,
}

/// What a function name resolves to.
#[derive(Clone, Copy)]
pub(super) enum FunctionLookup {
    User(DefId),
    Builtin(&'static BuiltinFunction),
    Missing,
}

/// What a module name resolves to.
#[derive(Clone, Copy)]
pub(super) enum ModuleLookup {
    User(DefId),
    Builtin(&'static BuiltinModule),
    Missing,
}

impl<'a> Resolver<'a> {
    /// A variable read.
    pub(super) fn variable(&mut self, file: FileId, ident: &Ident) -> Ty {
        if ident.is_special() {
            if let Some(binding) = self.lookup_lexical(&ident.name) {
                self.use_binding(file, ident.span, &binding);
                return binding.ty;
            }
            if builtins::is_special_variable(&ident.name) {
                self.reference(file, ident.span, Namespace::Variable, Target::Builtin);
                return Ty::Any;
            }
            if !self.specials_set.contains(&ident.name) {
                self.diagnostics.push(
                    Diagnostic::warning(
                        codes::SPECIAL_NEVER_SET,
                        format!(
                            "special variable `{}` is never set, so it is always `undef`",
                            ident.name
                        ),
                        file,
                        ident.span,
                    )
                    .with_help(format!(
                        "set it with `{} = …;` or pass it as an argument `m({} = …)`",
                        ident.name, ident.name
                    )),
                );
            }
            return Ty::Any;
        }
        match self.lookup_var(&ident.name) {
            VarLookup::Found(binding) => {
                self.use_binding(file, ident.span, &binding);
                binding.ty
            }
            VarLookup::Builtin(ty) => {
                self.reference(file, ident.span, Namespace::Variable, Target::Builtin);
                ty
            }
            VarLookup::AssignedLater(def) => {
                let mut diagnostic = Diagnostic::error(
                    codes::USED_BEFORE_ASSIGNMENT,
                    format!("`{}` is read before it is assigned", ident.name),
                    file,
                    ident.span,
                )
                .with_help("a scope's assignments run in order and this one runs first, so the value would be `undef`; move the assignment up");
                if let Some(def) = def {
                    self.reference(
                        file,
                        ident.span,
                        Namespace::Variable,
                        Target::Definition(def),
                    );
                    self.mark_used(def);
                    if let Some(definition) = self.definition(def) {
                        diagnostic = diagnostic.with_label(
                            definition.file,
                            definition.name_span,
                            "assigned here",
                        );
                    }
                }
                self.diagnostics.push(diagnostic);
                Ty::Any
            }
            VarLookup::Missing => {
                let mut diagnostic = Diagnostic::error(
                    codes::UNDEFINED_VARIABLE,
                    format!("undefined variable `{}`", ident.name),
                    file,
                    ident.span,
                );
                if self.sibling_params.contains(&ident.name) {
                    diagnostic = diagnostic.with_help(format!(
                        "defaults are evaluated in the scope of the definition and cannot read other parameters (`{0}` is one); default to `undef` and compute the value in the body",
                        ident.name
                    ));
                } else if !matches!(self.lookup_function(&ident.name), FunctionLookup::Missing) {
                    diagnostic = diagnostic.with_help(format!(
                        "`{0}` is a function, and functions are not values; write `function (x) {0}(x)` for a function value",
                        ident.name
                    ));
                } else if !matches!(self.lookup_module(&ident.name), ModuleLookup::Missing) {
                    diagnostic = diagnostic.with_help(format!(
                        "`{}` is a module, and modules are not values",
                        ident.name
                    ));
                } else if let Some(similar) = self.suggest(&ident.name, Namespace::Variable) {
                    diagnostic = diagnostic.with_help(format!(
                        "a variable with a similar name exists: `{similar}`"
                    ));
                }
                self.diagnostics.push(diagnostic);
                Ty::Any
            }
        }
    }

    /// A variable visible here, honouring the in-order rule for assignments.
    pub(super) fn lookup_var(&self, name: &str) -> VarLookup {
        let mut later = None;
        for (depth, scope) in self.scopes.iter().enumerate().rev() {
            if let Some(binding) = scope.vars.get(name) {
                if let Some((assign_depth, position)) = self.assign_ctx
                    && assign_depth == depth
                    && binding.first_pos >= position
                {
                    later = Some(binding.def);
                    continue;
                }
                return VarLookup::Found(binding.clone());
            }
        }
        if let Some(ty) = builtins::variable(name) {
            return VarLookup::Builtin(ty.clone());
        }
        match later {
            Some(def) => VarLookup::AssignedLater(def),
            None => VarLookup::Missing,
        }
    }

    /// A binding in the lexical scopes, ignoring order (for `$`-variables).
    fn lookup_lexical(&self, name: &str) -> Option<VarBinding> {
        self.scopes
            .iter()
            .rev()
            .find_map(|scope| scope.vars.get(name))
            .cloned()
    }

    pub(super) fn used_units(&self) -> &[usize] {
        self.units
            .get(self.current_unit)
            .map_or(&[], |unit| unit.uses.as_slice())
    }

    pub(super) fn lookup_function(&self, name: &str) -> FunctionLookup {
        match self.lookup_user(name, |scope| &scope.funcs) {
            Some(def) => FunctionLookup::User(def),
            None => {
                builtins::function(name).map_or(FunctionLookup::Missing, FunctionLookup::Builtin)
            }
        }
    }

    pub(super) fn lookup_module(&self, name: &str) -> ModuleLookup {
        match self.lookup_user(name, |scope| &scope.modules) {
            Some(def) => ModuleLookup::User(def),
            None => builtins::module(name).map_or(ModuleLookup::Missing, ModuleLookup::Builtin),
        }
    }

    /// A user definition of `name` in the namespace `table` picks out: the innermost open scope
    /// first, then the files brought in by `use`.
    fn lookup_user(
        &self,
        name: &str,
        table: impl Fn(&Scope) -> &HashMap<String, DefId>,
    ) -> Option<DefId> {
        let in_scope = self
            .scopes
            .iter()
            .rev()
            .find_map(|scope| table(scope).get(name));
        in_scope
            .or_else(|| {
                self.used_units()
                    .iter()
                    .find_map(|&unit| self.units.get(unit).and_then(|u| table(&u.scope).get(name)))
            })
            .copied()
    }
}

/// Every `$`-variable the program sets anywhere: by assignment, as a parameter, as a binding or
/// as a named argument. Reading one of these is never reported.
pub(super) fn collect_specials(stmts: &[Stmt], out: &mut HashSet<String>) {
    let mut note = |ident: &Ident| {
        if ident.is_special() && !out.contains(&ident.name) {
            out.insert(ident.name.clone());
        }
    };
    walk(stmts.iter().map(Node::Stmt), |node| match node {
        Node::Stmt(stmt) => match &stmt.kind {
            StmtKind::Assign { name, .. } => note(name),
            StmtKind::ModuleDef { params, .. } | StmtKind::FunctionDef { params, .. } => {
                params.iter().for_each(|p| note(&p.name))
            }
            StmtKind::For { bindings, .. } | StmtKind::Let { bindings, .. } => {
                bindings.iter().for_each(|b| note(&b.name))
            }
            StmtKind::Instantiate { args, .. } => args
                .iter()
                .filter_map(|a| a.name.as_ref())
                .for_each(&mut note),
            _ => {}
        },
        Node::Expr(expr) => match &expr.kind {
            ExprKind::Call { args, .. } => args
                .iter()
                .filter_map(|a| a.name.as_ref())
                .for_each(&mut note),
            ExprKind::Let { bindings, .. } => bindings.iter().for_each(|b| note(&b.name)),
            ExprKind::FunctionLit { params, .. } => params.iter().for_each(|p| note(&p.name)),
            _ => {}
        },
        Node::Elem(elem) => match &elem.kind {
            ListElemKind::For { bindings, .. } | ListElemKind::Let { bindings, .. } => {
                bindings.iter().for_each(|b| note(&b.name))
            }
            ListElemKind::CFor { init, update, .. } => {
                init.iter().chain(update).for_each(|b| note(&b.name))
            }
            _ => {}
        },
    });
}
