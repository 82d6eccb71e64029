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
//!
//! The resolver's state is defined here; its work is spread over one module per concern:
//! [`units`] (root files and include splicing), [`scopes`] (definitions and the order of a
//! scope), [`statements`], [`expressions`], [`calls`], [`arguments`] (signatures and argument
//! checking), [`names`] (lookups), [`references`], [`suggestions`] and [`warnings`].

mod arguments;
mod calls;
mod deprecated;
mod expressions;
mod names;
mod references;
mod scopes;
mod statements;
mod suggestions;
mod units;
mod warnings;

use crate::fxhash::{FxHashMap as HashMap, FxHashSet as HashSet};

use qcsg_diag::{Diagnostic, FileId, SourceMap, Span};
use qcsg_syntax::ast::Stmt;

use crate::loader::Loaded;
use crate::suggest::Suggester;
use crate::ty::Ty;
use crate::{DefId, DefKind, Definition, Namespace, Reference, Target};

use names::collect_specials;
use scopes::undef_tests;

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
    /// Where each file tests names for `undef`, indexed by `FileId`.
    undef_tests: Vec<HashMap<String, Vec<u32>>>,
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
            undef_tests: loaded
                .trees
                .iter()
                .map(|tree| undef_tests(&tree.stmts))
                .collect(),
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
}
