//! Document and workspace symbols: the modules, functions and variables a file defines.

use qcsg_sema::{DefId, DefKind};

use crate::{Analysis, FileRange, TextRange};

/// What a symbol is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SymbolKind {
    /// A module.
    Module,
    /// A function.
    Function,
    /// A variable.
    Variable,
}

/// A definition shown in an outline or a workspace symbol search.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Symbol {
    /// Its name.
    pub name: String,
    /// What it is.
    pub kind: SymbolKind,
    /// Its signature, for modules and functions.
    pub detail: Option<String>,
    /// The whole definition.
    pub location: FileRange,
    /// Its name.
    pub selection: TextRange,
    /// The name of the module or function it is defined in.
    pub container: Option<String>,
    /// Variables defined inside it (for document symbols).
    pub children: Vec<Symbol>,
}

impl Analysis {
    fn symbol(&self, id: DefId) -> Option<Symbol> {
        let definition = self.sema.definition(id)?;
        let kind = match definition.kind {
            DefKind::Module => SymbolKind::Module,
            DefKind::Function => SymbolKind::Function,
            DefKind::Variable => SymbolKind::Variable,
            _ => return None,
        };
        let detail = match kind {
            SymbolKind::Variable => None,
            _ => self.definition_signature(id).map(|s| s.label().0),
        };
        Some(Symbol {
            name: definition.name.clone(),
            kind,
            detail,
            location: self.file_range(definition.file, definition.span),
            selection: self.range(definition.file, definition.name_span),
            container: definition
                .parent
                .and_then(|p| self.sema.definition(p))
                .map(|p| p.name.clone()),
            children: Vec::new(),
        })
    }

    /// The outline of the main document: top-level definitions, with what modules and functions
    /// define inside them as children.
    pub fn document_symbols(&self) -> Vec<Symbol> {
        let main = self.sema.main;
        let in_main = |d: &&qcsg_sema::Definition| d.file == main;
        let ids = || {
            self.sema
                .definitions
                .iter()
                .enumerate()
                .filter(move |(_, d)| in_main(d))
                .map(|(i, d)| (DefId(i as u32), d))
        };
        ids()
            .filter(|(_, d)| d.parent.is_none())
            .filter_map(|(id, _)| {
                let mut symbol = self.symbol(id)?;
                symbol.children = ids()
                    .filter(|(_, d)| d.parent == Some(id))
                    .filter_map(|(child, _)| self.symbol(child))
                    .collect();
                Some(symbol)
            })
            .collect()
    }

    /// The modules, functions and top-level variables of every file of the program whose name
    /// contains `query` (ignoring case).
    pub fn workspace_symbols(&self, query: &str) -> Vec<Symbol> {
        let query = query.to_lowercase();
        (0..self.sema.definitions.len())
            .map(|i| DefId(i as u32))
            .filter(|&id| {
                self.sema.definition(id).is_some_and(|d| {
                    (d.parent.is_none() || d.kind != DefKind::Variable)
                        && d.name.to_lowercase().contains(&query)
                })
            })
            .filter_map(|id| self.symbol(id))
            .collect()
    }
}
