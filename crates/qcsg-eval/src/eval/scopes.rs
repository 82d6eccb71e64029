//! Scopes: a scope's statements are sorted (includes and blocks spliced, definitions, assignments
//! and the rest), its definitions made visible throughout, its assignments run in order, then its
//! other statements; `use`d files are evaluated once into frames of their own.

use std::collections::HashMap;
use std::rc::Rc;

use qcsg_csg::{Edge, Source};
use qcsg_diag::{FileId, Span};
use qcsg_syntax::ast::{Expr, Modifier, Stmt, StmtKind};

use crate::env::{Callable, Frame};
use crate::value::Value;

use super::{Cx, Evaluator, R};

/// The statements of one scope, sorted by what evaluation does with them.
#[derive(Default)]
pub(super) struct ScopeItems<'a> {
    /// `(name, value, file of the value)`, the last value of a name at its first position.
    pub(super) assignments: Vec<(&'a str, &'a Expr, FileId)>,
    pub(super) definitions: Vec<(FileId, &'a Stmt)>,
    pub(super) uses: Vec<FileId>,
    pub(super) items: Vec<(FileId, &'a Stmt)>,
    /// Position of each name in `assignments`, once there are more than [`INDEX_FROM`].
    pub(super) assignment_index: HashMap<&'a str, usize>,
}

/// Scopes with more assignments than this find a reassigned name through a hash index; smaller
/// ones (most bodies, collected at every call) scan, which costs less than building the index.
const INDEX_FROM: usize = 16;

impl<'a> Evaluator<'a> {
    /// Evaluates the main file: the top-level scope with the `-D` overrides.
    pub fn run_main(&mut self, main: FileId) -> R<()> {
        let root = Frame::root();
        let mut items = ScopeItems::default();
        if let Some(tree) = self.trees.get(main.0 as usize) {
            self.collect(main, &tree.stmts, &mut items);
        }
        for (name, expr) in self.defines {
            items.assign(name.as_str(), expr, self.define_file);
        }
        let edges = self.eval_scope(&items, &root)?;
        let source = Source::new(main, Span::default());
        let (root_edge, first) = match self.root_override {
            Some(edge) => (edge, edge),
            None => {
                let (edges, _) = self.same_dimension(edges);
                let first = edges.first().copied();
                let root: Edge = self.dag.union(edges, source).into();
                (root, first.unwrap_or(root))
            }
        };
        // The warning about a 2-D top level points at its first shape.
        let at = self.dag.node(first.child).map_or(source, |n| n.source);
        let root_edge = self.top_level_plate(root_edge, at);
        self.dag.set_root(root_edge);
        Ok(())
    }

    /// Sorts `stmts` of `file` into `out`, splicing blocks and included files.
    pub(super) fn collect(&mut self, file: FileId, stmts: &'a [Stmt], out: &mut ScopeItems<'a>) {
        for stmt in stmts {
            match &stmt.kind {
                // A disabled statement is not evaluated, nor counted in `$children`.
                StmtKind::Empty
                | StmtKind::Error
                | StmtKind::Modified {
                    modifier: Modifier::Disable,
                    ..
                } => {}
                StmtKind::Assign { name, value } => out.assign(&name.name, value, file),
                StmtKind::ModuleDef { .. } | StmtKind::FunctionDef { .. } => {
                    out.definitions.push((file, stmt))
                }
                StmtKind::Block(inner) => self.collect(file, inner, out),
                StmtKind::Include(path) => {
                    if let Some(&target) = self.links.get(&(file, path.span.start))
                        && !self.include_stack.contains(&target)
                        && let Some(tree) = self.trees.get(target.0 as usize)
                    {
                        self.include_stack.push(target);
                        self.collect(target, &tree.stmts, out);
                        self.include_stack.pop();
                    }
                }
                StmtKind::Use(path) => {
                    if let Some(&target) = self.links.get(&(file, path.span.start)) {
                        out.uses.push(target);
                    }
                }
                _ => out.items.push((file, stmt)),
            }
        }
    }

    pub(super) fn collect_body(&mut self, file: FileId, body: Option<&'a Stmt>) -> ScopeItems<'a> {
        let mut items = ScopeItems::default();
        if let Some(body) = body {
            self.collect(file, std::slice::from_ref(body), &mut items);
        }
        items
    }

    /// Defines the functions and modules of `items` (and of the files it uses) in `frame`.
    pub(super) fn define(&mut self, items: &ScopeItems<'a>, frame: &Rc<Frame<'a>>) -> R<()> {
        for &used in &items.uses {
            let used_frame = self.used_frame(used)?;
            for (name, def) in used_frame.own_functions() {
                frame.define_function(name, def);
            }
            for (name, def) in used_frame.own_modules() {
                frame.define_module(name, def);
            }
        }
        for &(file, stmt) in &items.definitions {
            match &stmt.kind {
                StmtKind::FunctionDef { name, params, body } => frame.define_function(
                    &name.name,
                    Rc::new(Callable {
                        params,
                        body,
                        env: frame.clone(),
                        file,
                    }),
                ),
                StmtKind::ModuleDef { name, params, body } => frame.define_module(
                    &name.name,
                    Rc::new(Callable {
                        params,
                        body,
                        env: frame.clone(),
                        file,
                    }),
                ),
                _ => {}
            }
        }
        Ok(())
    }

    /// The top-level scope of a `use`d file: its definitions and variables, no geometry.
    fn used_frame(&mut self, file: FileId) -> R<Rc<Frame<'a>>> {
        if let Some(frame) = self.used_frames.get(&file) {
            return Ok(frame.clone());
        }
        let imports = Frame::root();
        let frame = Frame::nested(&imports);
        self.used_frames.insert(file, frame.clone());
        let mut items = ScopeItems::default();
        if let Some(tree) = self.trees.get(file.0 as usize) {
            self.include_stack.push(file);
            self.collect(file, &tree.stmts, &mut items);
            self.include_stack.pop();
        }
        let uses = std::mem::take(&mut items.uses);
        self.define(
            &ScopeItems {
                uses,
                ..ScopeItems::default()
            },
            &imports,
        )?;
        self.define(&items, &frame)?;
        self.assign(&items, &frame)?;
        Ok(frame)
    }

    pub(super) fn assign(&mut self, items: &ScopeItems<'a>, frame: &Rc<Frame<'a>>) -> R<()> {
        for &(name, expr, file) in &items.assignments {
            let value = self.eval_expr(
                expr,
                &Cx {
                    frame: frame.clone(),
                    file,
                },
            );
            frame.set(name, Self::recover(value)?.unwrap_or(Value::Undef));
        }
        Ok(())
    }

    /// Evaluates a scope: definitions, then assignments, then instantiations.
    pub(super) fn eval_scope(
        &mut self,
        items: &ScopeItems<'a>,
        frame: &Rc<Frame<'a>>,
    ) -> R<Vec<Edge>> {
        self.define(items, frame)?;
        self.assign(items, frame)?;
        let mut edges = Vec::new();
        for &(file, stmt) in &items.items {
            let made = self.eval_stmt(
                stmt,
                &Cx {
                    frame: frame.clone(),
                    file,
                },
            );
            if let Some(Some(edge)) = Self::recover(made)? {
                edges.push(edge);
            }
        }
        Ok(edges)
    }

    /// `body` as a scope nested in `cx`.
    pub(super) fn eval_body(&mut self, body: Option<&'a Stmt>, cx: &Cx<'a>) -> R<Vec<Edge>> {
        let items = self.collect_body(cx.file, body);
        let frame = Frame::nested(&cx.frame);
        self.eval_scope(&items, &frame)
    }

    /// The union of `edges`; `None` (nothing, skipped by the parent) when there are none.
    pub(super) fn group(&mut self, edges: Vec<Edge>, source: Source) -> Option<Edge> {
        let edges = if edges.len() > 1 {
            self.same_dimension(edges).0
        } else {
            edges
        };
        match edges.len() {
            0 => None,
            1 => edges.into_iter().next(),
            _ => Some(self.dag.union(edges, source).into()),
        }
    }
}

impl<'a> ScopeItems<'a> {
    /// Records `name = value`: a name assigned again keeps its first position, takes the last
    /// value.
    fn assign(&mut self, name: &'a str, value: &'a Expr, file: FileId) {
        let position = if self.assignments.len() > INDEX_FROM {
            self.assignment_index.get(name).copied()
        } else {
            self.assignments.iter().position(|(n, _, _)| *n == name)
        };
        match position {
            Some(i) => self.assignments[i] = (name, value, file),
            None => {
                self.assignments.push((name, value, file));
                if self.assignments.len() > INDEX_FROM {
                    if self.assignment_index.is_empty() {
                        self.assignment_index = self
                            .assignments
                            .iter()
                            .enumerate()
                            .map(|(i, (n, _, _))| (*n, i))
                            .collect();
                    } else {
                        self.assignment_index
                            .insert(name, self.assignments.len() - 1);
                    }
                }
            }
        }
    }
}
