//! Scopes and definitions: a scope's assignments and definitions are registered first
//! (definitions hoisted, a reassigned variable kept at its first position), then its assignments
//! are resolved in that order and the rest of its statements after them. Parameters, `let` and
//! `for` bindings open scopes of their own.

use qcsg_diag::{FileId, Span};
use qcsg_syntax::ast::{BinaryOp, Binding, ExprKind, Ident, Param, Stmt, StmtKind};

use crate::fxhash::FxHashMap as HashMap;
use crate::ty::Ty;
use crate::{DefId, DefKind, Definition, ParamInfo, Target};
use qcsg_syntax::walk::{Node, walk};

use super::{Item, Resolver, Scope, VarBinding};

impl<'a> Resolver<'a> {
    /// Creates (or finds, for a file spliced more than once) the definition of a name.
    pub(super) fn define(
        &mut self,
        kind: DefKind,
        file: FileId,
        name: &Ident,
        span: Span,
        doc: Option<String>,
    ) -> (DefId, bool) {
        if let Some(&existing) = self.def_index.get(&(file, name.span, kind)) {
            return (existing, false);
        }
        let id = DefId(self.definitions.len() as u32);
        self.definitions.push(Definition {
            kind,
            name: name.name.clone(),
            file,
            name_span: name.span,
            span,
            doc,
            params: None,
            parent: self.enclosing.last().copied(),
            redefines: None,
            ty: Ty::Any,
        });
        self.used.push(false);
        self.def_index.insert((file, name.span, kind), id);
        (id, true)
    }

    /// Defines the parameters of a module, function or function literal owned by `owner`.
    fn define_params(
        &mut self,
        file: FileId,
        owner: DefId,
        params: &[Param],
        body: Node<'_>,
    ) -> Vec<ParamInfo> {
        let span = match body {
            Node::Stmt(stmt) => stmt.span,
            Node::Expr(expr) => expr.span,
            Node::Elem(elem) => elem.span,
        };
        let mut infos = Vec::with_capacity(params.len());
        for param in params {
            let tested = self.tested_for_undef(file, &param.name.name, span);
            let (def, _) = self.define(DefKind::Parameter, file, &param.name, param.span, None);
            if let Some(definition) = self.definitions.get_mut(def.0 as usize) {
                definition.parent = Some(owner);
            }
            infos.push(ParamInfo {
                name: param.name.name.clone(),
                name_span: param.name.span,
                span: param.span,
                has_default: param.default.is_some(),
                tested_for_undef: tested,
                def,
            });
        }
        infos
    }

    /// Whether `file` tests `name` for `undef` within `span`.
    fn tested_for_undef(&self, file: FileId, name: &str, span: Span) -> bool {
        let starts = self
            .undef_tests
            .get(file.0 as usize)
            .and_then(|tests| tests.get(name));
        starts.is_some_and(|starts| {
            let first = starts.partition_point(|&at| at < span.start);
            starts.get(first).is_some_and(|&at| at < span.end)
        })
    }

    pub(super) fn definition(&self, def: DefId) -> Option<&Definition> {
        self.definitions.get(def.0 as usize)
    }

    /// Registers a scope's assignments and definitions; returns the assignments grouped by
    /// variable, in the order of each variable's first assignment.
    pub(super) fn collect(&mut self, items: &[Item<'a>], scope: &mut Scope) -> Vec<Vec<usize>> {
        let mut groups: Vec<Vec<usize>> = Vec::new();
        for (index, item) in items.iter().enumerate() {
            let stmt = unmodified(item.stmt);
            let doc = stmt.doc.as_ref().map(|d| d.text.clone());
            match &stmt.kind {
                StmtKind::Assign { name, value } => {
                    let (def, fresh) =
                        self.define(DefKind::Variable, item.file, name, stmt.span, doc);
                    if fresh && let ExprKind::FunctionLit { params, body } = &value.kind {
                        let infos = self.define_params(item.file, def, params, Node::Expr(body));
                        self.definitions[def.0 as usize].params = Some(infos);
                    }
                    match scope.vars.get_mut(&name.name) {
                        Some(binding) => {
                            let previous = binding.def;
                            binding.def = Some(def);
                            binding.target = Target::Definition(def);
                            if let Some(group) = groups.get_mut(binding.first_pos as usize) {
                                group.push(index);
                            }
                            if let Some(previous) = previous.filter(|&p| p != def) {
                                // A file included twice repeats its assignments: link each
                                // definition once so that `redefines` chains stay acyclic.
                                if fresh {
                                    self.definitions[def.0 as usize].redefines = Some(previous);
                                }
                                self.report_reassignment(previous, def);
                            }
                        }
                        None => {
                            scope.vars.insert(
                                name.name.clone(),
                                VarBinding {
                                    def: Some(def),
                                    target: Target::Definition(def),
                                    first_pos: groups.len() as u32,
                                    ty: Ty::Any,
                                },
                            );
                            groups.push(vec![index]);
                        }
                    }
                }
                StmtKind::ModuleDef { name, params, body } => {
                    let (def, fresh) =
                        self.define(DefKind::Module, item.file, name, stmt.span, doc);
                    if fresh {
                        let infos = self.define_params(item.file, def, params, Node::Stmt(body));
                        self.definitions[def.0 as usize].params = Some(infos);
                    }
                    scope.modules.insert(name.name.clone(), def);
                }
                StmtKind::FunctionDef { name, params, body } => {
                    let (def, fresh) =
                        self.define(DefKind::Function, item.file, name, stmt.span, doc);
                    if fresh {
                        let infos = self.define_params(item.file, def, params, Node::Expr(body));
                        self.definitions[def.0 as usize].params = Some(infos);
                    }
                    scope.funcs.insert(name.name.clone(), def);
                }
                _ => {}
            }
        }
        groups
    }

    /// Resolves a scope whose names were collected into the innermost scope: assignments first
    /// (in first-assignment order, each with the value in effect), then everything else.
    pub(super) fn resolve_items(&mut self, items: &[Item<'a>], groups: &[Vec<usize>]) {
        let depth = self.scopes.len().saturating_sub(1);
        for (position, group) in groups.iter().enumerate() {
            let saved = self.assign_ctx.replace((depth, position as u32));
            let last = group.len().saturating_sub(1);
            for (k, &index) in group.iter().enumerate() {
                let Some(item) = items.get(index) else {
                    continue;
                };
                let StmtKind::Assign { name, value } = &unmodified(item.stmt).kind else {
                    continue;
                };
                let def = self
                    .def_index
                    .get(&(item.file, name.span, DefKind::Variable))
                    .copied();
                self.tessellation_hint(item.file, name);
                let is_literal = matches!(value.kind, ExprKind::FunctionLit { .. });
                if let (true, Some(def)) = (is_literal, def) {
                    self.enclosing.push(def);
                }
                let ty = self.expr(item.file, value);
                if let (true, Some(_)) = (is_literal, def) {
                    self.enclosing.pop();
                }
                if let Some(def) = def {
                    self.definitions[def.0 as usize].ty = ty.clone();
                }
                if k == last {
                    let overridden =
                        depth == 0 && self.current_unit == 0 && self.defines.contains(&name.name);
                    if let Some(binding) = self
                        .scopes
                        .get_mut(depth)
                        .and_then(|s| s.vars.get_mut(&name.name))
                    {
                        binding.ty = if overridden { Ty::Any } else { ty };
                    }
                }
            }
            self.assign_ctx = saved;
        }
        let saved = self.assign_ctx.take();
        // Function bodies first, so that statements anywhere in the scope see their result types.
        for item in items {
            if matches!(unmodified(item.stmt).kind, StmtKind::FunctionDef { .. }) {
                self.stmt(*item);
            }
        }
        for item in items {
            if !matches!(
                unmodified(item.stmt).kind,
                StmtKind::Assign { .. } | StmtKind::FunctionDef { .. }
            ) {
                self.stmt(*item);
            }
        }
        self.assign_ctx = saved;
    }

    /// Resolves `stmt` as a scope of its own (children of an instantiation, an `if` branch, a
    /// loop body, a module body).
    pub(super) fn child_scope(&mut self, file: FileId, chain: u32, stmt: &'a Stmt) {
        let mut items = Vec::new();
        self.flatten(file, chain, std::slice::from_ref(stmt), &mut items);
        let mut scope = Scope::default();
        let groups = self.collect(&items, &mut scope);
        self.scopes.push(scope);
        self.resolve_items(&items, &groups);
        self.scopes.pop();
    }

    pub(super) fn push_scope(&mut self) {
        self.scopes.push(Scope::default());
    }

    pub(super) fn pop_scope(&mut self) {
        self.scopes.pop();
    }

    /// Binds a name in the innermost scope (parameters, loop and `let` variables).
    pub(super) fn bind(&mut self, name: &str, def: DefId, ty: Ty) {
        if let Some(scope) = self.scopes.last_mut() {
            scope.vars.insert(
                name.to_string(),
                VarBinding {
                    def: Some(def),
                    target: Target::Definition(def),
                    first_pos: 0,
                    ty,
                },
            );
        }
    }

    /// Resolves parameter defaults, then opens a scope binding the parameters (closed by the
    /// caller with [`Self::pop_scope`]).
    pub(super) fn enter_params(&mut self, file: FileId, params: &[Param], owner: Option<DefId>) {
        // OpenSCAD evaluates defaults in the defining scope: they cannot read other parameters.
        let saved = std::mem::replace(
            &mut self.sibling_params,
            params.iter().map(|p| p.name.name.clone()).collect(),
        );
        for param in params {
            if let Some(default) = &param.default {
                self.expr(file, default);
            }
        }
        self.sibling_params = saved;
        self.push_scope();
        for param in params {
            let def = match self
                .def_index
                .get(&(file, param.name.span, DefKind::Parameter))
            {
                Some(&def) => def,
                None => {
                    let (def, _) =
                        self.define(DefKind::Parameter, file, &param.name, param.span, None);
                    if let Some(definition) = self.definitions.get_mut(def.0 as usize) {
                        definition.parent = owner;
                    }
                    def
                }
            };
            self.tessellation_hint(file, &param.name);
            self.bind(&param.name.name, def, Ty::Any);
        }
    }

    /// Binds `let` / `for` bindings sequentially in the innermost scope.
    pub(super) fn bindings(&mut self, file: FileId, bindings: &[Binding], kind: DefKind) {
        for binding in bindings {
            let value_ty = self.expr(file, &binding.value);
            let ty = if kind == DefKind::LoopVariable {
                element_type(&value_ty)
            } else {
                value_ty
            };
            let (def, _) = self.define(kind, file, &binding.name, binding.span, None);
            self.definitions[def.0 as usize].ty = ty.clone();
            if kind == DefKind::LetVariable {
                self.tessellation_hint(file, &binding.name);
            }
            self.bind(&binding.name.name, def, ty);
        }
    }
}

/// The statement under any modifiers.
fn unmodified(mut stmt: &Stmt) -> &Stmt {
    while let StmtKind::Modified { body, .. } = &stmt.kind {
        stmt = body;
    }
    stmt
}

/// The type of a loop variable iterating over a value of type `ty`.
pub(super) fn element_type(ty: &Ty) -> Ty {
    match ty {
        Ty::Range | Ty::Number => Ty::Number,
        Ty::Vector { elem, .. } => (**elem).clone(),
        Ty::String => Ty::String,
        _ => Ty::Any,
    }
}

/// Where each name is tested for `undef` (`is_undef(p)`, `p == undef`, `is_num(p)`, …) in one
/// file: the starts of the tests by name, in source order. A parameter tested anywhere in its
/// definition's body, nested definitions included, is treated as optional even without a
/// default; one walk per file, and a binary search per parameter, keep that linear where a walk
/// of every definition's body would be quadratic in their nesting.
pub(super) fn undef_tests(stmts: &[Stmt]) -> HashMap<String, Vec<u32>> {
    let mut tests: HashMap<String, Vec<u32>> = HashMap::default();
    walk(stmts.iter().map(Node::Stmt), |node| {
        let Node::Expr(expr) = node else { return };
        let tested = match &expr.kind {
            ExprKind::Call { callee, args, .. } => match (&callee.kind, args.as_slice()) {
                (ExprKind::Ident(function), [arg]) if function.name.starts_with("is_") => {
                    match &arg.value.kind {
                        ExprKind::Ident(tested) => Some(tested),
                        _ => None,
                    }
                }
                _ => None,
            },
            ExprKind::Binary {
                op: BinaryOp::Eq | BinaryOp::Ne,
                lhs,
                rhs,
                ..
            } => match (&lhs.kind, &rhs.kind) {
                (ExprKind::Ident(tested), ExprKind::Undef)
                | (ExprKind::Undef, ExprKind::Ident(tested)) => Some(tested),
                _ => None,
            },
            _ => None,
        };
        if let Some(tested) = tested {
            tests
                .entry(tested.name.clone())
                .or_default()
                .push(expr.span.start);
        }
    });
    // The walk is in source order already; sorted, the lookups need not rely on it.
    for starts in tests.values_mut() {
        starts.sort_unstable();
    }
    tests
}
