//! Name resolution and static checking over the trees of a whole program.
//!
//! OpenSCAD's rules, which this module follows:
//! - three namespaces: variables, functions and modules;
//! - a scope is a file, a module body, a function body, a `let`, a `for`, a comprehension head, or
//!   the children of an instantiation / `if` branch. A bare `{ }` block is *not* a scope: its
//!   assignments belong to the enclosing one (OpenSCAD 2021.01's grammar adds them there);
//! - in a scope every assignment is evaluated before anything else, in order, and a reassigned
//!   variable keeps the position of its first assignment with the value of its last one. So an
//!   assignment may only read the scope's variables assigned before it (else OpenSCAD reads the
//!   enclosing scope's variable, or `undef`), while instantiations, module and function bodies and
//!   function literals see the whole scope;
//! - module and function definitions are hoisted: usable anywhere in their scope;
//! - `include` splices the file's statements in place; `use` makes the file's top-level modules and
//!   functions visible (after the file's own) and nothing else;
//! - `$`-variables are dynamically scoped and never undefined.

use crate::fxhash::{FxHashMap as HashMap, FxHashSet as HashSet};

use qcsg_diag::{Diagnostic, FileId, Severity, SourceMap, Span};
use qcsg_syntax::ast::{
    Arg, BinaryOp, Binding, Expr, ExprKind, Ident, ListElem, ListElemKind, Modifier, Param, Stmt,
    StmtKind, UnaryOp,
};

use crate::builtins::{self, BuiltinFunction, BuiltinModule};
use crate::loader::{LinkKind, Loaded};
use crate::suggest::Suggester;
use crate::ty::{Mismatch, ParamTy, Ty, format_lengths};
use crate::walk::{Node, walk};
use crate::{DefId, DefKind, Definition, Namespace, ParamInfo, Reference, Target, codes};

/// Stack space kept free before growing it for deeply nested trees.
const STACK_RED_ZONE: usize = 64 * 1024;
/// How much stack to add each time.
const STACK_GROWTH: usize = 2 * 1024 * 1024;

/// What resolution produced.
pub(crate) struct Resolved {
    pub definitions: Vec<Definition>,
    pub references: Vec<Reference>,
    pub diagnostics: Vec<Diagnostic>,
}

/// A variable visible in a scope.
#[derive(Clone, Debug)]
struct VarBinding {
    /// The definition in effect (the last assignment), if it has one in the source.
    def: Option<DefId>,
    /// Where the binding comes from, for references.
    target: Target,
    /// The position of the first assignment among the scope's assignments.
    first_pos: u32,
    /// The inferred type of the value in effect.
    ty: Ty,
}

/// One scope's names.
#[derive(Default, Debug)]
struct Scope {
    vars: HashMap<String, VarBinding>,
    funcs: HashMap<String, DefId>,
    modules: HashMap<String, DefId>,
}

/// A statement in a scope, with the file it is written in and the include chain that spliced it.
#[derive(Clone, Copy)]
struct Item<'a> {
    file: FileId,
    stmt: &'a Stmt,
    chain: u32,
}

/// A link of an include chain: `file` was spliced in by the include at `via`.
struct ChainNode {
    file: FileId,
    parent: Option<u32>,
    via: Option<(FileId, Span)>,
}

/// A root file (the main file or a used library) with its top-level scope.
struct Unit<'a> {
    scope: Scope,
    items: Vec<Item<'a>>,
    groups: Vec<Vec<usize>>,
    /// Units whose modules and functions this one sees through `use`.
    uses: Vec<usize>,
}

/// What a variable name resolves to.
enum VarLookup {
    Found(VarBinding),
    Builtin(Ty),
    /// Only assigned later in the same scope than the assignment reading it.
    AssignedLater(Option<DefId>),
    Missing,
}

/// What a function name resolves to.
#[derive(Clone, Copy)]
enum FunctionLookup {
    User(DefId),
    Builtin(&'static BuiltinFunction),
    Missing,
}

/// What a module name resolves to.
#[derive(Clone, Copy)]
enum ModuleLookup {
    User(DefId),
    Builtin(&'static BuiltinModule),
    Missing,
}

/// A parameter as argument checking sees it, for built-in and user callees alike.
struct SigParam {
    name: String,
    positional: bool,
    required: bool,
    ty: ParamTy,
    def: Option<DefId>,
}

/// A callee's signature.
struct Signature {
    /// "module `cube`", "function `f`".
    title: String,
    params: Vec<SigParam>,
    /// Type of further positional arguments, for variadic built-ins.
    rest: Option<ParamTy>,
    /// Whether any named argument is accepted (`echo`).
    any_named: bool,
    min_args: usize,
    defined_at: Option<(FileId, Span)>,
    /// Built-in functions match arguments by position only: OpenSCAD ignores their names.
    positional_only: bool,
}

/// Resolves every unit of a program over its loaded trees, collecting definitions, references and
/// diagnostics.
pub(crate) struct Resolver<'a> {
    loaded: &'a Loaded,
    sources: &'a SourceMap,
    main: FileId,
    defines: HashSet<String>,
    specials_set: HashSet<String>,
    definitions: Vec<Definition>,
    def_index: HashMap<(FileId, Span, DefKind), DefId>,
    used: Vec<bool>,
    references: Vec<Reference>,
    reference_index: HashSet<(FileId, Span, Namespace)>,
    diagnostics: Vec<Diagnostic>,
    scopes: Vec<Scope>,
    /// While resolving an assignment's value: (scope depth, position of the assignment).
    assign_ctx: Option<(usize, u32)>,
    chains: Vec<ChainNode>,
    units: Vec<Unit<'a>>,
    unit_of_file: HashMap<FileId, usize>,
    current_unit: usize,
    /// Definitions whose body is being resolved (self-references do not count as uses).
    enclosing: Vec<DefId>,
    /// What is left of the "did you mean" budget.
    suggester: Suggester,
    /// While resolving parameter defaults: the names of the parameters (for a better message).
    sibling_params: Vec<String>,
}

impl<'a> Resolver<'a> {
    pub(crate) fn new(
        loaded: &'a Loaded,
        sources: &'a SourceMap,
        main: FileId,
        defines: impl IntoIterator<Item = String>,
    ) -> Self {
        let mut specials_set = HashSet::default();
        for tree in &loaded.trees {
            collect_specials(&tree.stmts, &mut specials_set);
        }
        Resolver {
            loaded,
            sources,
            main,
            defines: defines.into_iter().collect(),
            specials_set,
            definitions: Vec::new(),
            def_index: HashMap::default(),
            used: Vec::new(),
            references: Vec::new(),
            reference_index: HashSet::default(),
            diagnostics: Vec::new(),
            scopes: Vec::new(),
            assign_ctx: None,
            chains: Vec::new(),
            units: Vec::new(),
            unit_of_file: HashMap::default(),
            current_unit: 0,
            enclosing: Vec::new(),
            suggester: Suggester::default(),
            sibling_params: Vec::new(),
        }
    }

    /// Resolves the program: the main unit and every library it uses, transitively.
    pub(crate) fn run(mut self) -> Resolved {
        let main_unit = self.unit_for(self.main);
        let mut next = 0;
        // `unit_for` appends units for the libraries each unit uses; resolve until none is new.
        while next < self.units.len() {
            self.resolve_unit(next);
            next += 1;
        }
        debug_assert_eq!(main_unit, 0);
        self.report_unused();
        let mut diagnostics = self.diagnostics;
        qcsg_diag::sort_diagnostics(&mut diagnostics);
        diagnostics.dedup();
        Resolved {
            definitions: self.definitions,
            references: self.references,
            diagnostics,
        }
    }

    // ----- units and scopes -------------------------------------------------------------------

    /// The unit rooted at `root`, created (collected, not yet resolved) on first request.
    fn unit_for(&mut self, root: FileId) -> usize {
        if let Some(&unit) = self.unit_of_file.get(&root) {
            return unit;
        }
        // A chain of libraries each using the next recurses once per library.
        stacker::maybe_grow(STACK_RED_ZONE, STACK_GROWTH, || self.new_unit(root))
    }

    fn new_unit(&mut self, root: FileId) -> usize {
        let index = self.units.len();
        self.unit_of_file.insert(root, index);
        self.units.push(Unit {
            scope: Scope::default(),
            items: Vec::new(),
            groups: Vec::new(),
            uses: Vec::new(),
        });
        let chain = self.new_chain(root, None, None);
        let mut items = Vec::new();
        if let Some(tree) = self.loaded.tree(root) {
            self.flatten(root, chain, &tree.stmts, &mut items);
        }
        let mut scope = Scope::default();
        let groups = self.collect(&items, &mut scope);
        if index == 0 {
            self.apply_defines(&mut scope);
        }
        let used_files = self.used_files(root);
        let uses = used_files
            .into_iter()
            .map(|file| self.unit_for(file))
            .collect();
        let unit = &mut self.units[index];
        unit.scope = scope;
        unit.items = items;
        unit.groups = groups;
        unit.uses = uses;
        index
    }

    /// The files `use`d by `root` or by any file it includes, in source order.
    fn used_files(&self, root: FileId) -> Vec<FileId> {
        let mut seen_files: HashSet<FileId> = std::iter::once(root).collect();
        let mut stack = vec![root];
        let mut used = Vec::new();
        while let Some(file) = stack.pop() {
            for link in self.loaded.links_of(file) {
                let Some(target) = link.target else { continue };
                match link.kind {
                    LinkKind::Include => {
                        if seen_files.insert(target) {
                            stack.push(target);
                        }
                    }
                    LinkKind::Use => {
                        if !used.contains(&target) {
                            used.push(target);
                        }
                    }
                }
            }
        }
        used
    }

    /// `-D name=value` overrides: the value is unknown statically; a new name becomes defined.
    fn apply_defines(&mut self, scope: &mut Scope) {
        let mut names: Vec<&String> = self.defines.iter().collect();
        names.sort();
        for name in names {
            match scope.vars.get_mut(name.as_str()) {
                Some(binding) => binding.ty = Ty::Any,
                None => {
                    scope.vars.insert(
                        name.clone(),
                        VarBinding {
                            def: None,
                            target: Target::CommandLine,
                            first_pos: 0,
                            ty: Ty::Any,
                        },
                    );
                }
            }
        }
    }

    fn resolve_unit(&mut self, index: usize) {
        self.current_unit = index;
        let scope = std::mem::take(&mut self.units[index].scope);
        let items = std::mem::take(&mut self.units[index].items);
        let groups = std::mem::take(&mut self.units[index].groups);
        self.scopes.push(scope);
        self.resolve_items(&items, &groups);
        let scope = self.scopes.pop().unwrap_or_default();
        let unit = &mut self.units[index];
        unit.scope = scope;
        unit.items = items;
        unit.groups = groups;
    }

    fn new_chain(&mut self, file: FileId, parent: Option<u32>, via: Option<(FileId, Span)>) -> u32 {
        self.chains.push(ChainNode { file, parent, via });
        (self.chains.len() - 1) as u32
    }

    /// Appends the statements of `stmts` to `out`, splicing bare blocks and included files.
    fn flatten(&mut self, file: FileId, chain: u32, stmts: &'a [Stmt], out: &mut Vec<Item<'a>>) {
        stacker::maybe_grow(STACK_RED_ZONE, STACK_GROWTH, || {
            for stmt in stmts {
                match &stmt.kind {
                    StmtKind::Block(inner) => self.flatten(file, chain, inner, out),
                    StmtKind::Include(path) => {
                        let Some(target) = self.loaded.target(file, path.span) else {
                            continue;
                        };
                        if let Some(cycle_start) = self.chain_entry(chain, target) {
                            self.report_cycle(file, path.span, target, cycle_start);
                            continue;
                        }
                        let inner = self.new_chain(target, Some(chain), Some((file, path.span)));
                        if let Some(tree) = self.loaded.tree(target) {
                            self.flatten(target, inner, &tree.stmts, out);
                        }
                    }
                    StmtKind::Use(_) | StmtKind::Empty => {}
                    _ => out.push(Item { file, stmt, chain }),
                }
            }
        })
    }

    /// The chain node at which `file` is already being spliced, if it is.
    fn chain_entry(&self, chain: u32, file: FileId) -> Option<u32> {
        let mut node = Some(chain);
        while let Some(index) = node {
            let entry = self.chains.get(index as usize)?;
            if entry.file == file {
                return Some(index);
            }
            node = entry.parent;
        }
        None
    }

    fn report_cycle(&mut self, file: FileId, span: Span, target: FileId, cycle_start: u32) {
        let target_name = self.sources.get(target).name.clone();
        let mut diagnostic = Diagnostic::error(
            codes::INCLUDE_CYCLE,
            format!("include cycle: `{target_name}` is already being included here"),
            file,
            span,
        );
        match self
            .chains
            .get(cycle_start as usize)
            .and_then(|node| node.via)
        {
            Some((via_file, via_span)) => {
                diagnostic = diagnostic.with_label(
                    via_file,
                    via_span,
                    format!("`{target_name}` is included here"),
                );
            }
            None => {
                diagnostic = diagnostic
                    .with_help("a file cannot include itself, directly or through other files");
            }
        }
        self.diagnostics.push(diagnostic);
    }

    /// Creates (or finds, for a file spliced more than once) the definition of a name.
    fn define(
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
        let tested = tested_for_undef(body);
        let mut infos = Vec::with_capacity(params.len());
        for param in params {
            let (def, _) = self.define(DefKind::Parameter, file, &param.name, param.span, None);
            if let Some(definition) = self.definitions.get_mut(def.0 as usize) {
                definition.parent = Some(owner);
            }
            infos.push(ParamInfo {
                name: param.name.name.clone(),
                name_span: param.name.span,
                span: param.span,
                has_default: param.default.is_some(),
                tested_for_undef: tested.contains(&param.name.name),
                def,
            });
        }
        infos
    }

    fn definition(&self, def: DefId) -> Option<&Definition> {
        self.definitions.get(def.0 as usize)
    }

    /// Registers a scope's assignments and definitions; returns the assignments grouped by
    /// variable, in the order of each variable's first assignment.
    fn collect(&mut self, items: &[Item<'a>], scope: &mut Scope) -> Vec<Vec<usize>> {
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

    /// OpenSCAD's rule: warn when both assignments are in one file or the first is in the main
    /// file; overriding a library default after `include` is the customary idiom and stays quiet.
    fn report_reassignment(&mut self, first: DefId, second: DefId) {
        let (Some(a), Some(b)) = (self.definition(first), self.definition(second)) else {
            return;
        };
        if a.file != b.file && a.file != self.main {
            return;
        }
        let diagnostic = Diagnostic::warning(
            codes::REASSIGNMENT,
            format!("`{}` is assigned again; the last assignment wins for the whole scope", b.name),
            b.file,
            b.name_span,
        )
        .with_label(a.file, a.name_span, "first assigned here")
        .with_help("OpenSCAD uses the last value everywhere in the scope, even before this line; use a new name or a `let`");
        self.diagnostics.push(diagnostic);
    }

    /// Resolves a scope whose names were collected into the innermost scope: assignments first
    /// (in first-assignment order, each with the value in effect), then everything else.
    fn resolve_items(&mut self, items: &[Item<'a>], groups: &[Vec<usize>]) {
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
    fn child_scope(&mut self, file: FileId, chain: u32, stmt: &'a Stmt) {
        let mut items = Vec::new();
        self.flatten(file, chain, std::slice::from_ref(stmt), &mut items);
        let mut scope = Scope::default();
        let groups = self.collect(&items, &mut scope);
        self.scopes.push(scope);
        self.resolve_items(&items, &groups);
        self.scopes.pop();
    }

    fn push_scope(&mut self) {
        self.scopes.push(Scope::default());
    }

    fn pop_scope(&mut self) {
        self.scopes.pop();
    }

    /// Binds a name in the innermost scope (parameters, loop and `let` variables).
    fn bind(&mut self, name: &str, def: DefId, ty: Ty) {
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

    // ----- statements -------------------------------------------------------------------------

    fn stmt(&mut self, item: Item<'a>) {
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

    /// Resolves parameter defaults, then opens a scope binding the parameters (closed by the
    /// caller with [`Self::pop_scope`]).
    fn enter_params(&mut self, file: FileId, params: &[Param], owner: Option<DefId>) {
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
    fn bindings(&mut self, file: FileId, bindings: &[Binding], kind: DefKind) {
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

    fn tessellation_hint(&mut self, file: FileId, name: &Ident) {
        if builtins::is_tessellation_variable(&name.name) {
            self.diagnostics.push(
                Diagnostic::new(
                    Severity::Hint,
                    codes::TESSELLATION_NO_OP,
                    format!("`{}` has no effect: surfaces are exact", name.name),
                    file,
                    name.span,
                )
                .with_help("quadric surfaces are not tessellated; the setting is accepted for OpenSCAD compatibility"),
            );
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
            ModuleLookup::Builtin(module) => {
                self.reference(file, name.span, Namespace::Module, Target::Builtin);
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

    // ----- arguments --------------------------------------------------------------------------

    fn args(&mut self, file: FileId, args: &[Arg]) -> Vec<Ty> {
        args.iter()
            .map(|arg| {
                if let Some(name) = &arg.name {
                    self.tessellation_hint(file, name);
                }
                self.expr(file, &arg.value)
            })
            .collect()
    }

    fn user_signature(&self, def: DefId, what: &str) -> Option<Signature> {
        let definition = self.definition(def)?;
        let params = definition.params.as_ref()?;
        Some(Signature {
            title: format!("{what} `{}`", definition.name),
            params: params
                .iter()
                .map(|p| SigParam {
                    name: p.name.clone(),
                    positional: true,
                    required: !p.has_default && !p.tested_for_undef && !p.name.starts_with('$'),
                    ty: ParamTy::Any,
                    def: Some(p.def),
                })
                .collect(),
            rest: None,
            any_named: false,
            min_args: 0,
            defined_at: Some((definition.file, definition.name_span)),
            positional_only: false,
        })
    }

    /// Checks a call's arguments against a signature. `$`-arguments are always accepted: they set
    /// special variables for the callee.
    fn check_args(
        &mut self,
        file: FileId,
        callee: &Ident,
        args_span: Span,
        args: &[Arg],
        tys: &[Ty],
        signature: &Signature,
    ) {
        let positional: Vec<usize> = (0..signature.params.len())
            .filter(|&i| signature.params[i].positional)
            .collect();
        let mut supplied: Vec<Option<Span>> = vec![None; signature.params.len()];
        let mut positional_count = 0usize;
        let mut extra: Option<Span> = None;
        for (arg, ty) in args.iter().zip(tys) {
            let name = match &arg.name {
                Some(name) if signature.positional_only && !name.is_special() => {
                    self.diagnostics.push(
                        Diagnostic::error(
                            codes::UNKNOWN_ARGUMENT,
                            format!(
                                "{} takes positional arguments only: the name `{}` would be ignored",
                                signature.title, name.name
                            ),
                            file,
                            name.span,
                        )
                        .with_help("OpenSCAD matches a built-in function's arguments by position whatever their names; remove the name"),
                    );
                    None
                }
                other => other.as_ref(),
            };
            match name {
                None => {
                    if let Some(&index) = positional.get(positional_count) {
                        supplied[index] = Some(arg.span);
                        self.check_arg_type(
                            file,
                            signature,
                            &signature.params[index].name,
                            signature.params[index].ty,
                            arg,
                            ty,
                        );
                    } else if let Some(rest) = signature.rest {
                        self.check_arg_type(file, signature, "", rest, arg, ty);
                    } else {
                        extra = Some(extra.map_or(arg.span, |s| s.cover(arg.span)));
                    }
                    positional_count += 1;
                }
                Some(name) if name.is_special() || signature.any_named => {}
                Some(name) => match signature.params.iter().position(|p| p.name == name.name) {
                    Some(index) => {
                        if let Some(param_def) = signature.params[index].def {
                            self.reference(
                                file,
                                name.span,
                                Namespace::Variable,
                                Target::Definition(param_def),
                            );
                        }
                        if let Some(previous) = supplied[index] {
                            self.diagnostics.push(
                                Diagnostic::error(
                                    codes::DUPLICATE_ARGUMENT,
                                    format!(
                                        "argument `{}` of {} is given more than once",
                                        name.name, signature.title
                                    ),
                                    file,
                                    name.span,
                                )
                                .with_label(
                                    file,
                                    previous,
                                    "first given here",
                                ),
                            );
                        } else {
                            supplied[index] = Some(name.span);
                            self.check_arg_type(
                                file,
                                signature,
                                &name.name,
                                signature.params[index].ty,
                                arg,
                                ty,
                            );
                        }
                    }
                    None => {
                        let mut diagnostic = Diagnostic::error(
                            codes::UNKNOWN_ARGUMENT,
                            format!("{} has no parameter `{}`", signature.title, name.name),
                            file,
                            name.span,
                        );
                        let names: Vec<&str> =
                            signature.params.iter().map(|p| p.name.as_str()).collect();
                        diagnostic = match self.suggester.closest(&name.name, names.iter().copied())
                        {
                            Some(similar) => {
                                diagnostic.with_help(format!("did you mean `{similar}`?"))
                            }
                            None if names.is_empty() => diagnostic
                                .with_help(format!("{} takes no arguments", signature.title)),
                            None => diagnostic
                                .with_help(format!("its parameters are {}", quoted_list(&names))),
                        };
                        if let Some((def_file, def_span)) = signature.defined_at {
                            diagnostic = diagnostic.with_label(def_file, def_span, "defined here");
                        }
                        self.diagnostics.push(diagnostic);
                    }
                },
            }
        }
        if let Some(extra_span) = extra {
            let count = positional.len();
            let mut diagnostic = Diagnostic::error(
                codes::TOO_MANY_ARGUMENTS,
                format!(
                    "{} takes {} positional argument{} but {} were given",
                    signature.title,
                    count,
                    if count == 1 { "" } else { "s" },
                    positional_count
                ),
                file,
                extra_span,
            )
            .with_help("remove the extra arguments (OpenSCAD would ignore them)");
            if let Some((def_file, def_span)) = signature.defined_at {
                diagnostic = diagnostic.with_label(def_file, def_span, "defined here");
            }
            self.diagnostics.push(diagnostic);
        }
        let missing: Vec<&str> = signature
            .params
            .iter()
            .zip(&supplied)
            .filter(|(p, s)| p.required && s.is_none())
            .map(|(p, _)| p.name.as_str())
            .collect();
        if !missing.is_empty() {
            let mut diagnostic = Diagnostic::error(
                codes::MISSING_ARGUMENT,
                format!(
                    "{} is missing argument{} {}",
                    signature.title,
                    if missing.len() == 1 { "" } else { "s" },
                    quoted_list(&missing)
                ),
                file,
                callee.span,
            )
            .with_label(file, args_span, "arguments given here")
            .with_help("give the parameter a default value in the definition (`name = undef`) if it is optional");
            if let Some((def_file, def_span)) = signature.defined_at {
                diagnostic = diagnostic.with_label(def_file, def_span, "defined here");
            }
            self.diagnostics.push(diagnostic);
        } else if signature.rest.is_some() && positional_count < signature.min_args {
            self.diagnostics.push(
                Diagnostic::error(
                    codes::MISSING_ARGUMENT,
                    format!(
                        "{} needs at least {} argument{}",
                        signature.title,
                        signature.min_args,
                        if signature.min_args == 1 { "" } else { "s" }
                    ),
                    file,
                    callee.span,
                )
                .with_label(file, args_span, "arguments given here"),
            );
        }
    }

    fn check_arg_type(
        &mut self,
        file: FileId,
        signature: &Signature,
        param: &str,
        expected: ParamTy,
        arg: &Arg,
        ty: &Ty,
    ) {
        let what = if param.is_empty() {
            "an argument".to_string()
        } else {
            format!("`{param}`")
        };
        let mismatch = match expected.check(ty) {
            Ok(()) => return,
            Err(mismatch) => mismatch,
        };
        // When the value comes from a variable, point at where its type comes from.
        let origin = match &arg.value.kind {
            ExprKind::Ident(ident) => match self.lookup_var(&ident.name) {
                VarLookup::Found(binding) => {
                    binding.def.and_then(|def| self.definition(def)).map(|d| {
                        (
                            d.file,
                            d.name_span,
                            format!("`{}` is assigned here", d.name),
                        )
                    })
                }
                _ => None,
            },
            _ => None,
        };
        let diagnostic = match mismatch {
            Mismatch::Type(expected) => {
                let mut diagnostic = Diagnostic::error(
                    codes::ARGUMENT_TYPE,
                    format!(
                        "{} expects {expected} for {what}, found {}",
                        signature.title,
                        ty.describe()
                    ),
                    file,
                    arg.value.span,
                );
                if expected.starts_with("a boolean") && *ty == Ty::Number {
                    diagnostic = diagnostic
                        .with_help("OpenSCAD ignores a number here; write `true` or `false`");
                }
                diagnostic
            }
            Mismatch::Length { given, allowed } => Diagnostic::error(
                codes::ARGUMENT_LENGTH,
                format!(
                    "{} expects {what} to have {} elements, found {given}",
                    signature.title,
                    format_lengths(allowed)
                ),
                file,
                arg.value.span,
            ),
        };
        let diagnostic = match origin {
            Some((def_file, def_span, message)) => {
                diagnostic.with_label(def_file, def_span, message)
            }
            None => diagnostic,
        };
        self.diagnostics.push(diagnostic);
    }

    // ----- expressions ------------------------------------------------------------------------

    fn expr(&mut self, file: FileId, expr: &Expr) -> Ty {
        stacker::maybe_grow(STACK_RED_ZONE, STACK_GROWTH, || self.expr_inner(file, expr))
    }

    fn expr_inner(&mut self, file: FileId, expr: &Expr) -> Ty {
        match &expr.kind {
            ExprKind::Number(_) => Ty::Number,
            ExprKind::String(_) => Ty::String,
            ExprKind::Bool(_) => Ty::Bool,
            ExprKind::Undef => Ty::Undef,
            ExprKind::Error => Ty::Any,
            ExprKind::Ident(ident) => self.variable(file, ident),
            ExprKind::Paren(inner) => self.expr(file, inner),
            ExprKind::Unary {
                op,
                op_span,
                operand,
            } => {
                let ty = self.expr(file, operand);
                match op {
                    UnaryOp::Not => Ty::Bool,
                    UnaryOp::Neg | UnaryOp::Plus => {
                        if ty.never_arithmetic() || matches!(ty, Ty::Undef) {
                            let symbol = if *op == UnaryOp::Neg { "-" } else { "+" };
                            self.diagnostics.push(
                                Diagnostic::error(
                                    codes::OPERATOR_TYPE,
                                    format!("cannot apply unary `{symbol}` to {}", ty.describe()),
                                    file,
                                    *op_span,
                                )
                                .with_label(
                                    file,
                                    operand.span,
                                    format!("this is {}", ty.describe()),
                                ),
                            );
                            return Ty::Any;
                        }
                        match ty {
                            Ty::Number | Ty::Vector { .. } => ty,
                            _ => Ty::Any,
                        }
                    }
                }
            }
            ExprKind::Binary {
                op,
                op_span,
                lhs,
                rhs,
            } => {
                let left = self.expr(file, lhs);
                let right = self.expr(file, rhs);
                self.binary(file, *op, *op_span, lhs, rhs, &left, &right)
            }
            ExprKind::Ternary { cond, then, els } => {
                self.expr(file, cond);
                let a = self.expr(file, then);
                let b = self.expr(file, els);
                a.join(&b)
            }
            ExprKind::Call {
                callee,
                args,
                args_span,
            } => self.call(file, callee, args, *args_span),
            ExprKind::Index { base, index } => {
                let base_ty = self.expr(file, base);
                let index_ty = self.expr(file, index);
                if matches!(base_ty, Ty::Number | Ty::Bool | Ty::Undef | Ty::Function) {
                    self.diagnostics.push(
                        Diagnostic::error(
                            codes::NOT_INDEXABLE,
                            format!("cannot index {}", base_ty.describe()),
                            file,
                            index.span,
                        )
                        .with_label(
                            file,
                            base.span,
                            format!("this is {}", base_ty.describe()),
                        ),
                    );
                    return Ty::Any;
                }
                if index_ty.is_known() && index_ty != Ty::Number {
                    self.diagnostics.push(Diagnostic::error(
                        codes::NOT_INDEXABLE,
                        format!("an index must be a number, found {}", index_ty.describe()),
                        file,
                        index.span,
                    ));
                    return Ty::Any;
                }
                match base_ty {
                    Ty::Vector { elem, .. } => *elem,
                    Ty::String => Ty::String,
                    _ => Ty::Any,
                }
            }
            ExprKind::Member { base, member } => {
                let base_ty = self.expr(file, base);
                let is_axis = matches!(member.name.as_str(), "x" | "y" | "z");
                match &base_ty {
                    Ty::Vector { len, elem } => {
                        let axis = match member.name.as_str() {
                            "x" => 0,
                            "y" => 1,
                            _ => 2,
                        };
                        if !is_axis {
                            self.diagnostics.push(
                                Diagnostic::error(
                                    codes::UNKNOWN_MEMBER,
                                    format!("vectors have no member `{}`", member.name),
                                    file,
                                    member.span,
                                )
                                .with_help("a vector's members are `.x`, `.y` and `.z`; index it with `[i]` otherwise"),
                            );
                            Ty::Any
                        } else if len.is_some_and(|n| n <= axis) {
                            self.diagnostics.push(Diagnostic::error(
                                codes::UNKNOWN_MEMBER,
                                format!(
                                    "`.{}` of {} is out of range",
                                    member.name,
                                    base_ty.describe()
                                ),
                                file,
                                member.span,
                            ));
                            Ty::Any
                        } else {
                            (**elem).clone()
                        }
                    }
                    Ty::Number | Ty::Bool | Ty::String | Ty::Undef | Ty::Function => {
                        self.diagnostics.push(
                            Diagnostic::error(
                                codes::UNKNOWN_MEMBER,
                                format!(
                                    "{} has no member `{}`",
                                    capitalize(&base_ty.describe()),
                                    member.name
                                ),
                                file,
                                member.span,
                            )
                            .with_label(
                                file,
                                base.span,
                                format!("this is {}", base_ty.describe()),
                            ),
                        );
                        Ty::Any
                    }
                    _ => Ty::Any,
                }
            }
            ExprKind::Vector(elems) => {
                let plain = elems
                    .iter()
                    .all(|e| matches!(e.kind, ListElemKind::Expr(_)));
                let mut elem_ty: Option<Ty> = None;
                for elem in elems {
                    let ty = self.list_elem(file, elem);
                    if plain {
                        elem_ty = Some(match elem_ty {
                            None => ty,
                            Some(previous) => previous.join(&ty),
                        });
                    }
                }
                if plain {
                    Ty::Vector {
                        len: Some(elems.len() as u32),
                        elem: Box::new(elem_ty.unwrap_or(Ty::Any)),
                    }
                } else {
                    Ty::any_vector()
                }
            }
            ExprKind::Range { start, step, end } => {
                for part in [Some(start), step.as_ref(), Some(end)]
                    .into_iter()
                    .flatten()
                {
                    let ty = self.expr(file, part);
                    if ty.is_known() && ty != Ty::Number {
                        self.diagnostics.push(Diagnostic::error(
                            codes::OPERATOR_TYPE,
                            format!("a range bound must be a number, found {}", ty.describe()),
                            file,
                            part.span,
                        ));
                    }
                }
                Ty::Range
            }
            ExprKind::Let { bindings, body } => {
                self.push_scope();
                self.bindings(file, bindings, DefKind::LetVariable);
                let ty = self.expr(file, body);
                self.pop_scope();
                ty
            }
            ExprKind::Assert {
                args,
                args_span,
                body,
            } => {
                let tys = self.args(file, args);
                if let Some(module) = builtins::module("assert") {
                    let callee = Ident {
                        name: "assert".into(),
                        span: Span::new(
                            expr.span.start as usize,
                            expr.span.start as usize + 6.min(expr.span.len()),
                        ),
                    };
                    let signature = builtin_module_signature(module);
                    self.check_args(file, &callee, *args_span, args, &tys, &signature);
                }
                body.as_ref()
                    .map_or(Ty::Undef, |body| self.expr(file, body))
            }
            ExprKind::Echo { args, body, .. } => {
                self.args(file, args);
                body.as_ref()
                    .map_or(Ty::Undef, |body| self.expr(file, body))
            }
            ExprKind::FunctionLit { params, body } => {
                // The body runs when the function is called, after every assignment of the scope.
                let saved = self.assign_ctx.take();
                let owner = self.enclosing.last().copied();
                self.enter_params(file, params, owner);
                self.expr(file, body);
                self.pop_scope();
                self.assign_ctx = saved;
                Ty::Function
            }
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn binary(
        &mut self,
        file: FileId,
        op: BinaryOp,
        op_span: Span,
        lhs: &Expr,
        rhs: &Expr,
        left: &Ty,
        right: &Ty,
    ) -> Ty {
        use BinaryOp::*;
        match op {
            Or | And | Eq | Ne | Lt | Le | Gt | Ge => return Ty::Bool,
            Add | Sub | Mul | Div | Rem | Pow => {}
        }
        let number = |t: &Ty| *t == Ty::Number;
        let vector = |t: &Ty| matches!(t, Ty::Vector { .. });
        let invalid = left.never_arithmetic()
            || right.never_arithmetic()
            || match op {
                Add | Sub => (number(left) && vector(right)) || (vector(left) && number(right)),
                Div => vector(left) && vector(right),
                Rem | Pow => vector(left) || vector(right),
                _ => false,
            };
        if invalid {
            let mut diagnostic = Diagnostic::error(
                codes::OPERATOR_TYPE,
                format!(
                    "cannot apply `{}` to {} and {}",
                    op.as_str(),
                    left.describe(),
                    right.describe()
                ),
                file,
                op_span,
            );
            for (side, ty) in [(lhs, left), (rhs, right)] {
                if ty.is_known() {
                    diagnostic = diagnostic.with_label(
                        file,
                        side.span,
                        format!("this is {}", ty.describe()),
                    );
                }
            }
            if op == Add && (*left == Ty::String || *right == Ty::String) {
                diagnostic = diagnostic.with_help("join strings with `str(a, b)`");
            }
            self.diagnostics.push(diagnostic);
            return Ty::Any;
        }
        match (left, right) {
            (Ty::Number, Ty::Number) => Ty::Number,
            (Ty::Vector { len: a, elem }, Ty::Vector { len: b, .. }) if matches!(op, Add | Sub) => {
                Ty::Vector {
                    len: if a == b { *a } else { None },
                    elem: elem.clone(),
                }
            }
            // Scaling is element-wise: a number times a matrix is a matrix.
            (Ty::Number, Ty::Vector { len, elem }) | (Ty::Vector { len, elem }, Ty::Number)
                if op == Mul =>
            {
                Ty::Vector {
                    len: *len,
                    elem: elem.clone(),
                }
            }
            (Ty::Vector { len, elem }, Ty::Number) if op == Div => Ty::Vector {
                len: *len,
                elem: elem.clone(),
            },
            _ => Ty::Any,
        }
    }

    fn list_elem(&mut self, file: FileId, elem: &ListElem) -> Ty {
        stacker::maybe_grow(STACK_RED_ZONE, STACK_GROWTH, || match &elem.kind {
            ListElemKind::Expr(expr) => self.expr(file, expr),
            ListElemKind::For { bindings, body } => {
                self.push_scope();
                self.bindings(file, bindings, DefKind::LoopVariable);
                self.list_elem(file, body);
                self.pop_scope();
                Ty::Any
            }
            ListElemKind::CFor {
                init,
                cond,
                update,
                body,
            } => {
                self.push_scope();
                self.bindings(file, init, DefKind::LoopVariable);
                self.expr(file, cond);
                for binding in update {
                    self.expr(file, &binding.value);
                    let existing = self
                        .scopes
                        .last()
                        .and_then(|s| s.vars.get(&binding.name.name))
                        .and_then(|b| b.def);
                    match existing {
                        Some(def) => {
                            self.reference(
                                file,
                                binding.name.span,
                                Namespace::Variable,
                                Target::Definition(def),
                            );
                        }
                        None => {
                            let (def, _) = self.define(
                                DefKind::LoopVariable,
                                file,
                                &binding.name,
                                binding.span,
                                None,
                            );
                            self.bind(&binding.name.name, def, Ty::Any);
                        }
                    }
                }
                self.list_elem(file, body);
                self.pop_scope();
                Ty::Any
            }
            ListElemKind::If { cond, then, els } => {
                self.expr(file, cond);
                self.list_elem(file, then);
                if let Some(els) = els {
                    self.list_elem(file, els);
                }
                Ty::Any
            }
            ListElemKind::Each(inner) => {
                self.list_elem(file, inner);
                Ty::Any
            }
            ListElemKind::Let { bindings, body } => {
                self.push_scope();
                self.bindings(file, bindings, DefKind::LetVariable);
                self.list_elem(file, body);
                self.pop_scope();
                Ty::Any
            }
            ListElemKind::Paren(inner) => self.list_elem(file, inner),
        })
    }

    /// A variable read.
    fn variable(&mut self, file: FileId, ident: &Ident) -> Ty {
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

    fn use_binding(&mut self, file: FileId, span: Span, binding: &VarBinding) {
        self.reference(file, span, Namespace::Variable, binding.target);
        if let Some(def) = binding.def {
            self.mark_used(def);
        }
    }

    fn call(&mut self, file: FileId, callee: &Expr, args: &[Arg], args_span: Span) -> Ty {
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

    // ----- lookups ----------------------------------------------------------------------------

    /// A variable visible here, honouring the in-order rule for assignments.
    fn lookup_var(&self, name: &str) -> VarLookup {
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

    fn used_units(&self) -> &[usize] {
        self.units
            .get(self.current_unit)
            .map_or(&[], |unit| unit.uses.as_slice())
    }

    fn lookup_function(&self, name: &str) -> FunctionLookup {
        match self.lookup_user(name, |scope| &scope.funcs) {
            Some(def) => FunctionLookup::User(def),
            None => {
                builtins::function(name).map_or(FunctionLookup::Missing, FunctionLookup::Builtin)
            }
        }
    }

    fn lookup_module(&self, name: &str) -> ModuleLookup {
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

    /// The visible name of `namespace` closest to `name`, for "did you mean".
    fn suggest(&mut self, name: &str, namespace: Namespace) -> Option<String> {
        // Gathering the candidates costs too: not for a name that gets no suggestion.
        if !self.suggester.wants(name) {
            return None;
        }
        let mut candidates: Vec<&str> = Vec::new();
        let used: Vec<&Scope> = self
            .used_units()
            .iter()
            .filter_map(|&u| self.units.get(u))
            .map(|u| &u.scope)
            .collect();
        for scope in self.scopes.iter().rev() {
            match namespace {
                Namespace::Variable => candidates.extend(scope.vars.keys().map(String::as_str)),
                Namespace::Function => {
                    candidates.extend(scope.funcs.keys().map(String::as_str));
                    candidates.extend(
                        scope
                            .vars
                            .iter()
                            .filter(|(_, b)| b.ty == Ty::Function)
                            .map(|(k, _)| k.as_str()),
                    );
                }
                Namespace::Module => candidates.extend(scope.modules.keys().map(String::as_str)),
            }
        }
        for scope in used {
            match namespace {
                Namespace::Variable => {}
                Namespace::Function => candidates.extend(scope.funcs.keys().map(String::as_str)),
                Namespace::Module => candidates.extend(scope.modules.keys().map(String::as_str)),
            }
        }
        match namespace {
            Namespace::Variable => candidates.extend(builtins::VARIABLES.iter().map(|v| v.0)),
            Namespace::Function => candidates.extend(builtins::FUNCTIONS.iter().map(|f| f.name)),
            Namespace::Module => candidates.extend(builtins::MODULES.iter().map(|m| m.name)),
        }
        // Scope maps iterate in arbitrary order; the choice among ties does not depend on it.
        self.suggester.closest(name, candidates).map(str::to_string)
    }

    // ----- bookkeeping ------------------------------------------------------------------------

    fn reference(&mut self, file: FileId, span: Span, namespace: Namespace, target: Target) {
        if self.reference_index.insert((file, span, namespace)) {
            self.references.push(Reference {
                file,
                span,
                namespace,
                target,
            });
        }
    }

    fn mark_used(&mut self, def: DefId) {
        if self.enclosing.contains(&def) {
            return;
        }
        let mut next = Some(def);
        while let Some(current) = next {
            match self.used.get_mut(current.0 as usize) {
                Some(flag) if !*flag => *flag = true,
                _ => break,
            }
            next = self
                .definitions
                .get(current.0 as usize)
                .and_then(|d| d.redefines);
        }
    }

    /// Unused-name warnings, for the main file only (a library need not use what it offers).
    fn report_unused(&mut self) {
        let redefined: HashSet<DefId> = self
            .definitions
            .iter()
            .filter_map(|d| d.redefines)
            .collect();
        for (index, definition) in self.definitions.iter().enumerate() {
            let id = DefId(index as u32);
            if definition.file != self.main
                || self.used.get(index).copied().unwrap_or(true)
                || definition.name.starts_with('_')
                || definition.name.starts_with('$')
                || redefined.contains(&id)
            {
                continue;
            }
            let (code, message) = match definition.kind {
                DefKind::Variable | DefKind::LetVariable => {
                    if self.defines.contains(&definition.name) && definition.parent.is_none() {
                        continue;
                    }
                    (
                        codes::UNUSED_VARIABLE,
                        format!("variable `{}` is never used", definition.name),
                    )
                }
                DefKind::Parameter => (
                    codes::UNUSED_PARAMETER,
                    format!("parameter `{}` is never used", definition.name),
                ),
                DefKind::Module => (
                    codes::UNUSED_MODULE,
                    format!("module `{}` is never instantiated", definition.name),
                ),
                DefKind::Function => (
                    codes::UNUSED_FUNCTION,
                    format!("function `{}` is never called", definition.name),
                ),
                DefKind::LoopVariable => continue,
            };
            self.diagnostics.push(
                Diagnostic::warning(code, message, definition.file, definition.name_span)
                    .with_help(
                        "remove it, or start its name with `_` to mark it as intentionally unused",
                    ),
            );
        }
    }
}

const FUNCTION_AS_MODULE_HELP: &str =
    "functions compute values and are called in expressions (`x = f(1);`); they create no solid";

/// The statement under any modifiers.
fn unmodified(mut stmt: &Stmt) -> &Stmt {
    while let StmtKind::Modified { body, .. } = &stmt.kind {
        stmt = body;
    }
    stmt
}

/// The type of a loop variable iterating over a value of type `ty`.
fn element_type(ty: &Ty) -> Ty {
    match ty {
        Ty::Range | Ty::Number => Ty::Number,
        Ty::Vector { elem, .. } => (**elem).clone(),
        Ty::String => Ty::String,
        _ => Ty::Any,
    }
}

fn quoted_list(names: &[&str]) -> String {
    names
        .iter()
        .map(|n| format!("`{n}`"))
        .collect::<Vec<_>>()
        .join(", ")
}

fn capitalize(text: &str) -> String {
    let mut chars = text.chars();
    match chars.next() {
        Some(first) => first.to_uppercase().chain(chars).collect(),
        None => String::new(),
    }
}

fn builtin_module_signature(module: &BuiltinModule) -> Signature {
    Signature {
        title: format!("`{}`", module.name),
        params: module
            .params
            .iter()
            .map(|p| SigParam {
                name: p.name.to_string(),
                positional: p.positional,
                required: p.required,
                ty: p.ty,
                def: None,
            })
            .collect(),
        rest: module.variadic.then_some(ParamTy::Any),
        any_named: module.variadic,
        min_args: 0,
        defined_at: None,
        positional_only: false,
    }
}

fn builtin_function_signature(function: &BuiltinFunction) -> Signature {
    Signature {
        title: format!("`{}`", function.name),
        params: function
            .params
            .iter()
            .map(|p| SigParam {
                name: p.name.to_string(),
                positional: p.positional,
                required: p.required,
                ty: p.ty,
                def: None,
            })
            .collect(),
        rest: function.rest,
        any_named: false,
        min_args: function.min_args,
        defined_at: None,
        positional_only: true,
    }
}

/// Every `$`-variable the program sets anywhere: by assignment, as a parameter, as a binding or
/// as a named argument. Reading one of these is never reported.
fn collect_specials(stmts: &[Stmt], out: &mut HashSet<String>) {
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

/// The names a definition's body tests for `undef` (`is_undef(p)`, `p == undef`, `is_num(p)`, …):
/// parameters it treats as optional even without a default.
fn tested_for_undef(root: Node<'_>) -> HashSet<String> {
    let mut names = HashSet::default();
    walk([root], |node| {
        let Node::Expr(expr) = node else { return };
        match &expr.kind {
            ExprKind::Call { callee, args, .. } => {
                if let (ExprKind::Ident(function), [arg]) = (&callee.kind, args.as_slice())
                    && function.name.starts_with("is_")
                    && let ExprKind::Ident(tested) = &arg.value.kind
                {
                    names.insert(tested.name.clone());
                }
            }
            ExprKind::Binary {
                op: BinaryOp::Eq | BinaryOp::Ne,
                lhs,
                rhs,
                ..
            } => match (&lhs.kind, &rhs.kind) {
                (ExprKind::Ident(tested), ExprKind::Undef)
                | (ExprKind::Undef, ExprKind::Ident(tested)) => {
                    names.insert(tested.name.clone());
                }
                _ => {}
            },
            _ => {}
        }
    });
    names
}
