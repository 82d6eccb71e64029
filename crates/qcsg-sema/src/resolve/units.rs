//! Units and include splicing: a unit is a root file (the main file or a library brought in
//! by `use`) with its top-level scope; `include`d files and bare blocks are spliced into the
//! statements of the scope that holds them, along a chain that finds include cycles.

use qcsg_diag::{Diagnostic, FileId, Span};
use qcsg_syntax::ast::{Stmt, StmtKind};

use crate::fxhash::FxHashSet as HashSet;
use crate::loader::LinkKind;
use crate::ty::Ty;
use crate::{Target, codes};

use super::{ChainNode, Item, Resolver, STACK_GROWTH, STACK_RED_ZONE, Scope, Unit, VarBinding};

impl<'a> Resolver<'a> {
    /// The unit rooted at `root`, created (collected, not yet resolved) on first request.
    pub(super) fn unit_for(&mut self, root: FileId) -> usize {
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

    pub(super) fn resolve_unit(&mut self, index: usize) {
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
    pub(super) fn flatten(
        &mut self,
        file: FileId,
        chain: u32,
        stmts: &'a [Stmt],
        out: &mut Vec<Item<'a>>,
    ) {
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
}
