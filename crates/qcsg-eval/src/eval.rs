//! The tree-walking evaluator: statements to DAG nodes, expressions to values.
//!
//! A scope is evaluated as OpenSCAD does: its `include`s are spliced in, its definitions are
//! visible throughout, its assignments run first and in order (a variable assigned twice keeps
//! the position of its first assignment and the value of its last), then its instantiations run
//! in order. Errors come in two kinds, as in OpenSCAD. A crossed limit or a failed `assert` is
//! fatal: it stops the evaluation (OpenSCAD stops there too). Any other runtime error stands where
//! OpenSCAD would print a warning and go on with `undef`: it abandons only the assignment (which
//! then holds `undef`) or the statement it occurred in, and evaluation continues, so that one run
//! reports all of them. An error repeated at the same span (in a loop, say) is reported once, and
//! the evaluation stops after [`MAX_ERRORS`] distinct ones. Warnings and `echo` output are
//! collected on the way. Deep recursion runs on a growing stack (`stacker`)
//! and every limit is checked before the work it bounds.

use std::collections::{HashMap, HashSet};
use std::rc::Rc;

use glam::DMat4;
use qcsg_csg::{Dag, Edge, NodeId, Source};
use qcsg_diag::{Diagnostic, FileId, Span};
use qcsg_syntax::ast::{
    Arg, BinaryOp, Binding, Expr, ExprKind, ListElem, ListElemKind, Modifier, Param, SourceFile,
    Stmt, StmtKind,
};

use crate::builtins_fn::{self, BuiltinError};
use crate::codes;
use crate::env::{Callable, Children, Frame, FunctionDef, ModuleDef};
use crate::primitives::{self, ArgLookup, Built};
use crate::text::BoundedText;
use crate::transforms;
use crate::value::{Range, Value};
use crate::{EvalOptions, color, ops, printer};

/// An error has been reported: the statement (or assignment) it occurred in is abandoned, and,
/// when it is fatal, the whole evaluation.
#[derive(Debug)]
pub(crate) struct Stop {
    fatal: bool,
}

/// What an `echo` line costs beside its text, in bytes of the echo-output limit: the diagnostic
/// that carries it and its printed form take about this much more, so that ten million empty
/// lines count as the burden they are.
pub(crate) const ECHO_LINE_COST: u64 = 64;

/// The most distinct runtime errors reported before the evaluation stops.
pub(crate) const MAX_ERRORS: usize = 50;

/// Whether an error of this code stops the evaluation (OpenSCAD 2021.01 stops on these too);
/// other errors stop only their statement, where OpenSCAD warns and continues with `undef`.
fn is_fatal(code: &str) -> bool {
    matches!(
        code,
        codes::RECURSION_LIMIT
            | codes::ITERATION_LIMIT
            | codes::VECTOR_LIMIT
            | codes::STRING_LIMIT
            | codes::INSTANCE_LIMIT
            | codes::ASSERTION_FAILED
    )
}

/// The command-line flag that raises the limit an error of this code reports.
fn limit_flag(code: &str) -> Option<&'static str> {
    match code {
        codes::RECURSION_LIMIT => Some("--max-recursion"),
        codes::ITERATION_LIMIT => Some("--max-iterations"),
        codes::VECTOR_LIMIT => Some("--max-vector-len"),
        codes::STRING_LIMIT => Some("--max-string-len"),
        codes::INSTANCE_LIMIT => Some("--max-instances"),
        _ => None,
    }
}

type R<T> = Result<T, Stop>;

/// Where code runs: the scope and the file whose spans it uses.
#[derive(Clone)]
struct Cx<'a> {
    frame: Rc<Frame<'a>>,
    file: FileId,
}

/// An evaluated call argument.
#[derive(Clone)]
struct ArgValue<'a> {
    name: Option<&'a str>,
    value: Value<'a>,
}

/// The statements of one scope, sorted by what evaluation does with them.
#[derive(Default)]
struct ScopeItems<'a> {
    /// `(name, value, file of the value)`, the last value of a name at its first position.
    assignments: Vec<(&'a str, &'a Expr, FileId)>,
    definitions: Vec<(FileId, &'a Stmt)>,
    uses: Vec<FileId>,
    items: Vec<(FileId, &'a Stmt)>,
    /// Position of each name in `assignments`, once there are more than [`INDEX_FROM`].
    assignment_index: HashMap<&'a str, usize>,
}

/// Scopes with more assignments than this find a reassigned name through a hash index; smaller
/// ones (most bodies, collected at every call) scan, which costs less than building the index.
const INDEX_FROM: usize = 16;

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

/// What evaluating a function body in tail position produced.
enum Tail<'a> {
    Done(Value<'a>),
    Call(Rc<FunctionDef<'a>>, Vec<ArgValue<'a>>, Span, FileId),
}

const STACK_RED_ZONE: usize = 128 * 1024;
const STACK_GROWTH: usize = 8 * 1024 * 1024;

/// The state of one evaluation.
pub(crate) struct Evaluator<'a> {
    trees: &'a [SourceFile],
    links: HashMap<(FileId, u32), FileId>,
    options: &'a EvalOptions,
    defines: &'a [(String, Expr)],
    define_file: FileId,
    pub dag: Dag,
    pub diagnostics: Vec<Diagnostic>,
    depth: usize,
    iterations: u64,
    instances: u64,
    /// Bytes of `echo` output still allowed; `None` once the limit has cut the output.
    echo_left: Option<u64>,
    root_override: Option<Edge>,
    used_frames: HashMap<FileId, Rc<Frame<'a>>>,
    include_stack: Vec<FileId>,
    /// The node each instantiation statement produced, once per distinct pair.
    pub instantiations: HashSet<(Source, NodeId)>,
    /// The errors reported so far, to report each (code, place) once.
    reported: HashSet<(&'static str, FileId, Span)>,
}

impl<'a> Evaluator<'a> {
    pub fn new(
        trees: &'a [SourceFile],
        links: HashMap<(FileId, u32), FileId>,
        options: &'a EvalOptions,
        defines: &'a [(String, Expr)],
        define_file: FileId,
    ) -> Self {
        Self {
            trees,
            links,
            options,
            defines,
            define_file,
            dag: Dag::new(),
            diagnostics: Vec::new(),
            depth: 0,
            iterations: 0,
            instances: 0,
            echo_left: Some(options.max_echo_len),
            root_override: None,
            used_frames: HashMap::new(),
            include_stack: Vec::new(),
            instantiations: HashSet::new(),
            reported: HashSet::new(),
        }
    }

    // ----- diagnostics -------------------------------------------------------------------

    fn error(
        &mut self,
        code: &'static str,
        message: impl Into<String>,
        file: FileId,
        span: Span,
    ) -> Stop {
        let mut fatal = is_fatal(code);
        if self.reported.insert((code, file, span)) {
            let mut diagnostic = Diagnostic::error(code, message, file, span);
            if let Some(flag) = limit_flag(code) {
                diagnostic = diagnostic.with_help(format!(
                    "if the program is right, raise the limit with `{flag} N` on the command line"
                ));
            }
            if self.reported.len() >= MAX_ERRORS {
                diagnostic = diagnostic.with_help(format!(
                    "evaluation stopped after {MAX_ERRORS} errors; fix these and run it again"
                ));
                fatal = true;
            }
            self.diagnostics.push(diagnostic);
        }
        Stop { fatal }
    }

    /// `result`, with a non-fatal error turned into `Ok(None)`: the caller goes on without it.
    fn recover<T>(result: R<T>) -> R<Option<T>> {
        match result {
            Ok(value) => Ok(Some(value)),
            Err(Stop { fatal: false }) => Ok(None),
            Err(stop) => Err(stop),
        }
    }

    fn warn(&mut self, code: &'static str, message: impl Into<String>, file: FileId, span: Span) {
        self.diagnostics
            .push(Diagnostic::warning(code, message, file, span));
    }

    fn tick(&mut self, n: u64, file: FileId, span: Span) -> R<()> {
        self.iterations = self.iterations.saturating_add(n);
        if self.iterations > self.options.max_iterations {
            return Err(self.error(
                codes::ITERATION_LIMIT,
                format!(
                    "more than {} loop iterations and function calls",
                    self.options.max_iterations
                ),
                file,
                span,
            ));
        }
        Ok(())
    }

    fn check_len(&mut self, n: u64, file: FileId, span: Span) -> R<()> {
        if n > self.options.max_vector_len {
            return Err(self.error(
                codes::VECTOR_LIMIT,
                format!(
                    "a vector of {n} elements is longer than the limit of {}",
                    self.options.max_vector_len
                ),
                file,
                span,
            ));
        }
        Ok(())
    }

    fn enter(&mut self, file: FileId, span: Span) -> R<()> {
        self.depth += 1;
        if self.depth > self.options.max_recursion {
            self.depth -= 1;
            return Err(self.error(
                codes::RECURSION_LIMIT,
                format!("calls nested deeper than {}", self.options.max_recursion),
                file,
                span,
            ));
        }
        Ok(())
    }

    // ----- scopes ------------------------------------------------------------------------

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
        let root_edge = match self.root_override {
            Some(edge) => edge,
            None => self.dag.union(edges, source).into(),
        };
        self.dag.set_root(root_edge);
        Ok(())
    }

    /// Sorts `stmts` of `file` into `out`, splicing blocks and included files.
    fn collect(&mut self, file: FileId, stmts: &'a [Stmt], out: &mut ScopeItems<'a>) {
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

    fn collect_body(&mut self, file: FileId, body: Option<&'a Stmt>) -> ScopeItems<'a> {
        let mut items = ScopeItems::default();
        if let Some(body) = body {
            self.collect(file, std::slice::from_ref(body), &mut items);
        }
        items
    }

    /// Defines the functions and modules of `items` (and of the files it uses) in `frame`.
    fn define(&mut self, items: &ScopeItems<'a>, frame: &Rc<Frame<'a>>) -> R<()> {
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

    fn assign(&mut self, items: &ScopeItems<'a>, frame: &Rc<Frame<'a>>) -> R<()> {
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
    fn eval_scope(&mut self, items: &ScopeItems<'a>, frame: &Rc<Frame<'a>>) -> R<Vec<Edge>> {
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
    fn eval_body(&mut self, body: Option<&'a Stmt>, cx: &Cx<'a>) -> R<Vec<Edge>> {
        let items = self.collect_body(cx.file, body);
        let frame = Frame::nested(&cx.frame);
        self.eval_scope(&items, &frame)
    }

    /// The union of `edges`; `None` (nothing, skipped by the parent) when there are none.
    fn group(&mut self, edges: Vec<Edge>, source: Source) -> Option<Edge> {
        match edges.len() {
            0 => None,
            1 => edges.into_iter().next(),
            _ => Some(self.dag.union(edges, source).into()),
        }
    }

    // ----- statements --------------------------------------------------------------------

    fn eval_stmt(&mut self, stmt: &'a Stmt, cx: &Cx<'a>) -> R<Option<Edge>> {
        stacker::maybe_grow(STACK_RED_ZONE, STACK_GROWTH, || {
            self.eval_stmt_inner(stmt, cx)
        })
    }

    fn eval_stmt_inner(&mut self, stmt: &'a Stmt, cx: &Cx<'a>) -> R<Option<Edge>> {
        let source = Source::new(cx.file, stmt.span);
        match &stmt.kind {
            StmtKind::If { cond, then, els } => {
                let branch = if self.eval_expr(cond, cx)?.truthy() {
                    Some(&**then)
                } else {
                    els.as_deref()
                };
                let edges = self.eval_body(branch, cx)?;
                Ok(self.group(edges, source))
            }
            StmtKind::For { bindings, body } => {
                let mut edges = Vec::new();
                self.for_each(&heads(bindings), cx, &mut |this, frame| {
                    let inner = Cx {
                        frame,
                        file: cx.file,
                    };
                    let items = this.collect_body(cx.file, Some(body));
                    edges.extend(this.eval_scope(&items, &inner.frame)?);
                    Ok(())
                })?;
                Ok(self.group(edges, source))
            }
            StmtKind::Let { bindings, body } => {
                let frame = self.bind_sequential(bindings, cx)?;
                let items = self.collect_body(cx.file, Some(body));
                let edges = self.eval_scope(&items, &frame)?;
                Ok(self.group(edges, source))
            }
            StmtKind::Instantiate {
                name, args, child, ..
            } => {
                let made =
                    self.instantiate(&name.name, name.span, args, child.as_deref(), stmt.span, cx)?;
                if let Some(edge) = made {
                    self.instantiations.insert((source, edge.child));
                }
                Ok(made)
            }
            StmtKind::Modified {
                modifier,
                modifier_span,
                body,
            } => match modifier {
                Modifier::Disable => Ok(None),
                Modifier::Background => {
                    if let Some(edge) = self.eval_stmt(body, cx)? {
                        self.dag.add_background(edge);
                    }
                    Ok(None)
                }
                Modifier::Highlight => {
                    let edge = self.eval_stmt(body, cx)?;
                    Ok(edge.map(|e| self.dag.highlight(e, source).into()))
                }
                Modifier::ShowOnly => {
                    let edge = self.eval_stmt(body, cx)?;
                    if self.root_override.is_some() {
                        self.warn(
                            codes::SEVERAL_ROOTS,
                            "more than one `!` modifier: the first one is the root",
                            cx.file,
                            *modifier_span,
                        );
                    } else {
                        let empty = Source::new(cx.file, stmt.span);
                        let edge = match edge {
                            Some(e) => e,
                            None => self.dag.empty(empty).into(),
                        };
                        self.root_override = Some(edge);
                    }
                    Ok(edge)
                }
            },
            StmtKind::Block(stmts) => {
                let mut items = ScopeItems::default();
                self.collect(cx.file, stmts, &mut items);
                let frame = Frame::nested(&cx.frame);
                let edges = self.eval_scope(&items, &frame)?;
                Ok(self.group(edges, source))
            }
            _ => Ok(None),
        }
    }

    /// Runs `body` once per combination of the bindings' values (outermost first), each in a
    /// new scope holding the loop variables.
    fn for_each(
        &mut self,
        bindings: &[(&'a str, &'a Expr)],
        cx: &Cx<'a>,
        body: &mut dyn FnMut(&mut Self, Rc<Frame<'a>>) -> R<()>,
    ) -> R<()> {
        let Some((&(name, value), rest)) = bindings.split_first() else {
            return body(self, cx.frame.clone());
        };
        let values = self.eval_expr(value, cx)?;
        let count = self.iteration_count(&values, cx.file, value.span)?;
        for i in 0..count {
            let frame = Frame::nested(&cx.frame);
            frame.set(name, iteration_value(&values, i));
            let inner = Cx {
                frame,
                file: cx.file,
            };
            if rest.is_empty() {
                body(self, inner.frame.clone())?;
            } else {
                self.for_each(rest, &inner, body)?;
            }
        }
        Ok(())
    }

    /// How many times a `for` over `values` runs (checked against the iteration limit first).
    fn iteration_count(&mut self, values: &Value<'a>, file: FileId, span: Span) -> R<u64> {
        let n = match values {
            Value::Range(r) => r.len(),
            Value::Vector(v) => v.len() as u64,
            Value::String(s) => s.chars().count() as u64,
            Value::Undef => 0,
            _ => 1,
        };
        self.tick(n, file, span)?;
        Ok(n)
    }

    fn bind_sequential(&mut self, bindings: &'a [Binding], cx: &Cx<'a>) -> R<Rc<Frame<'a>>> {
        let frame = Frame::nested(&cx.frame);
        let inner = Cx {
            frame: frame.clone(),
            file: cx.file,
        };
        for b in bindings {
            let v = self.eval_expr(&b.value, &inner)?;
            frame.set(&b.name.name, v);
        }
        Ok(frame)
    }

    // ----- module instantiation ----------------------------------------------------------

    fn eval_args(&mut self, args: &'a [Arg], cx: &Cx<'a>) -> R<Vec<ArgValue<'a>>> {
        let mut out = Vec::with_capacity(args.len());
        for a in args {
            out.push(ArgValue {
                name: a.name.as_ref().map(|n| n.name.as_str()),
                value: self.eval_expr(&a.value, cx)?,
            });
        }
        Ok(out)
    }

    #[allow(clippy::too_many_arguments)]
    fn instantiate(
        &mut self,
        name: &'a str,
        name_span: Span,
        args: &'a [Arg],
        child: Option<&'a Stmt>,
        span: Span,
        cx: &Cx<'a>,
    ) -> R<Option<Edge>> {
        if let Some(def) = cx.frame.lookup_module(name) {
            return self.call_module(def, args, child, span, cx);
        }
        let source = Source::new(cx.file, span);
        match name {
            "echo" => {
                let values = self.eval_args(args, cx)?;
                self.echo(&values, cx.file, span);
                let edges = self.eval_body(child, cx)?;
                return Ok(self.group(edges, source));
            }
            "assert" => {
                let values = self.eval_args(args, cx)?;
                self.assert(&values, args, cx.file, span)?;
                let edges = self.eval_body(child, cx)?;
                return Ok(self.group(edges, source));
            }
            "children" => return self.children(args, span, cx),
            "intersection_for" => return self.intersection_for(args, child, span, cx),
            _ => {}
        }
        let Some(builtin) = qcsg_sema::builtins::module(name) else {
            if let Some(unsupported) = qcsg_sema::builtins::unsupported_module(name) {
                return Err(self.error(
                    codes::UNSUPPORTED,
                    format!("`{name}` is not supported: {}", unsupported.reason),
                    cx.file,
                    name_span,
                ));
            }
            let code = if cx.frame.lookup_function(name).is_some() {
                codes::WRONG_KIND
            } else {
                codes::UNDEFINED_NAME
            };
            return Err(self.error(
                code,
                format!("no module named `{name}`"),
                cx.file,
                name_span,
            ));
        };
        let values = self.eval_args(args, cx)?;
        let named = self.place_builtin_args(builtin.params, &values, args, cx.file)?;
        // `$`-arguments set special variables for the subtree.
        let child_cx = if values
            .iter()
            .any(|a| a.name.is_some_and(|n| n.starts_with('$')))
        {
            let frame = Frame::nested(&cx.frame);
            for a in &values {
                if let Some(n) = a.name.filter(|n| n.starts_with('$')) {
                    frame.set(n, a.value.clone());
                }
            }
            Cx {
                frame,
                file: cx.file,
            }
        } else {
            cx.clone()
        };
        match builtin.kind {
            qcsg_sema::builtins::ModuleKind::Primitive => {
                self.instances += 1;
                if self.instances > self.options.max_instances {
                    return Err(self.error(
                        codes::INSTANCE_LIMIT,
                        format!(
                            "more than {} primitive instances",
                            self.options.max_instances
                        ),
                        cx.file,
                        span,
                    ));
                }
                match primitives::build(&mut self.dag, name, &named, source) {
                    Ok(Built::Node(node)) => Ok(Some(node.into())),
                    Ok(Built::Empty(reason)) => {
                        self.warn(codes::EMPTY_PRIMITIVE, reason, cx.file, span);
                        Ok(Some(self.dag.empty(source).into()))
                    }
                    Err(message) => Err(self.error(codes::MODULE_ARGUMENT, message, cx.file, span)),
                }
            }
            _ if name == "complement" => {
                let edges = self.eval_body(child, &child_cx)?;
                let inner = match self.group(edges, source) {
                    Some(e) => e,
                    None => self.dag.empty(source).into(),
                };
                Ok(Some(self.dag.complement(inner, source).into()))
            }
            qcsg_sema::builtins::ModuleKind::Boolean => {
                let edges = self.eval_body(child, &child_cx)?;
                if edges.is_empty() {
                    return Ok(None);
                }
                Ok(Some(match name {
                    "intersection" => self.dag.intersection(edges, source).into(),
                    "difference" => self.dag.difference(edges, source).into(),
                    _ => match self.group(edges, source) {
                        Some(e) => e,
                        None => return Ok(None),
                    },
                }))
            }
            qcsg_sema::builtins::ModuleKind::Transform => {
                let edges = self.eval_body(child, &child_cx)?;
                let Some(inner) = self.group(edges, source) else {
                    return Ok(None);
                };
                let mut warnings = Vec::new();
                let matrix = match name {
                    "translate" => transforms::translate(&named.get("v")),
                    "rotate" => transforms::rotate(&named.get("a"), &named.get("v"), &mut warnings),
                    "scale" => transforms::scale(&named.get("v")),
                    "mirror" => transforms::mirror(&named.get("v")),
                    "multmatrix" => transforms::multmatrix(&named.get("m")),
                    _ => {
                        let bounds = transforms::bounds_of(&self.dag, inner);
                        transforms::resize(
                            &named.get("newsize"),
                            &named.get("auto"),
                            bounds,
                            &mut warnings,
                        )
                    }
                };
                for w in warnings {
                    let code = if name == "resize" {
                        codes::RESIZE_IGNORED
                    } else {
                        codes::IGNORED_ARGUMENT
                    };
                    self.warn(code, w, cx.file, span);
                }
                let matrix =
                    matrix.map_err(|m| self.error(codes::MODULE_ARGUMENT, m, cx.file, span))?;
                self.apply_transform(inner, &matrix, cx.file, span)
            }
            _ => {
                let edges = self.eval_body(child, &child_cx)?;
                let Some(inner) = self.group(edges, source) else {
                    return Ok(None);
                };
                if name != "color" {
                    return Ok(Some(inner));
                }
                match self.color_of(&named, cx.file, span)? {
                    Some(rgba) => match self.dag.color(inner, rgba, source) {
                        Ok(node) => Ok(Some(node.into())),
                        Err(e) => {
                            self.warn(codes::UNKNOWN_COLOR, e.to_string(), cx.file, span);
                            Ok(Some(inner))
                        }
                    },
                    None => Ok(Some(inner)),
                }
            }
        }
    }

    fn apply_transform(
        &mut self,
        inner: Edge,
        m: &DMat4,
        file: FileId,
        span: Span,
    ) -> R<Option<Edge>> {
        let det = m.determinant();
        if det == 0.0 || !det.is_finite() || !m.is_finite() {
            self.warn(
                codes::SINGULAR_TRANSFORM,
                "the transform is singular or not finite: the object is removed",
                file,
                span,
            );
            return Ok(None);
        }
        match self.dag.transformed(inner, m) {
            Ok(edge) => Ok(Some(edge)),
            Err(e) => {
                self.warn(
                    codes::SINGULAR_TRANSFORM,
                    format!("{e}: the object is removed"),
                    file,
                    span,
                );
                Ok(None)
            }
        }
    }

    fn color_of(
        &mut self,
        named: &BuiltinArgs<'a>,
        file: FileId,
        span: Span,
    ) -> R<Option<[f64; 4]>> {
        let mut rgba = match &named.get("c") {
            Value::Vector(v) => {
                let mut out = [1.0; 4];
                for (o, e) in out.iter_mut().zip(v.iter()) {
                    *o = e.as_number().unwrap_or(1.0);
                }
                out
            }
            Value::String(s) => match color::parse_color(s) {
                Some(c) => c,
                None => {
                    self.warn(
                        codes::UNKNOWN_COLOR,
                        format!("unknown colour \"{s}\""),
                        file,
                        span,
                    );
                    return Ok(None);
                }
            },
            _ => return Ok(None),
        };
        if let Value::Number(alpha) = named.get("alpha") {
            rgba[3] = alpha;
        }
        Ok(Some(rgba))
    }

    /// Places the arguments of a built-in module call on its parameters.
    fn place_builtin_args(
        &mut self,
        params: &'static [qcsg_sema::builtins::BuiltinParam],
        values: &[ArgValue<'a>],
        args: &'a [Arg],
        file: FileId,
    ) -> R<BuiltinArgs<'a>> {
        let mut out = BuiltinArgs::default();
        let mut positional = params.iter().filter(|p| p.positional);
        for (a, syntax) in values.iter().zip(args) {
            match a.name {
                Some(n) if n.starts_with('$') => {}
                Some(n) => out.values.push((n, a.value.clone())),
                None => match positional.next() {
                    Some(p) => out.values.push((p.name, a.value.clone())),
                    None => {
                        return Err(self.error(
                            codes::MODULE_ARGUMENT,
                            "too many positional arguments",
                            file,
                            syntax.span,
                        ));
                    }
                },
            }
        }
        Ok(out)
    }

    fn call_module(
        &mut self,
        def: Rc<ModuleDef<'a>>,
        args: &'a [Arg],
        child: Option<&'a Stmt>,
        span: Span,
        cx: &Cx<'a>,
    ) -> R<Option<Edge>> {
        let values = self.eval_args(args, cx)?;
        self.enter(cx.file, span)?;
        let result = self.call_module_inner(&def, values, child, cx);
        self.depth -= 1;
        result
    }

    fn call_module_inner(
        &mut self,
        def: &Rc<ModuleDef<'a>>,
        values: Vec<ArgValue<'a>>,
        child: Option<&'a Stmt>,
        cx: &Cx<'a>,
    ) -> R<Option<Edge>> {
        let child_items = self.collect_body(cx.file, child);
        let children = Rc::new(Children {
            assignments: child_items.assignments,
            definitions: child_items.definitions,
            items: child_items.items,
            env: cx.frame.clone(),
        });
        let count = children.items.len();
        let frame = Frame::module_instance(&def.env, &cx.frame, children);
        self.bind_params(&frame, def.params, &def.env, def.file, values)?;
        frame.set("$children", Value::Number(count as f64));
        let items = self.collect_body(def.file, Some(def.body));
        let edges = self.eval_scope(&items, &frame)?;
        Ok(self.group(edges, Source::new(def.file, def.body.span)))
    }

    /// Binds call arguments to parameters in `frame`; defaults are evaluated in the
    /// definition's scope, as OpenSCAD 2021.01 does.
    fn bind_params(
        &mut self,
        frame: &Rc<Frame<'a>>,
        params: &'a [Param],
        def_env: &Rc<Frame<'a>>,
        def_file: FileId,
        values: Vec<ArgValue<'a>>,
    ) -> R<()> {
        let mut given: Vec<Option<Value<'a>>> = vec![None; params.len()];
        let mut position = 0;
        for a in values {
            match a.name {
                Some(n) if n.starts_with('$') => frame.set(n, a.value),
                Some(n) => {
                    if let Some(i) = params.iter().position(|p| p.name.name == n) {
                        given[i] = Some(a.value);
                    }
                }
                None => {
                    if position < params.len() {
                        given[position] = Some(a.value);
                    }
                    position += 1;
                }
            }
        }
        for (param, value) in params.iter().zip(given) {
            let value = match (value, &param.default) {
                (Some(v), _) => v,
                (None, Some(default)) => self.eval_expr(
                    default,
                    &Cx {
                        frame: def_env.clone(),
                        file: def_file,
                    },
                )?,
                (None, None) => Value::Undef,
            };
            frame.set(&param.name.name, value);
        }
        Ok(())
    }

    fn children(&mut self, args: &'a [Arg], span: Span, cx: &Cx<'a>) -> R<Option<Edge>> {
        let values = self.eval_args(args, cx)?;
        let Some(children) = cx.frame.module_children() else {
            return Ok(None);
        };
        let n = children.items.len();
        let selection = values
            .iter()
            .find(|a| a.name.is_none() || a.name == Some("index"))
            .map(|a| a.value.clone());
        let mut indices = Vec::new();
        let mut add = |this: &mut Self, x: f64| -> R<()> {
            if !(x >= 0.0 && x < n as f64) {
                return Err(this.error(
                    codes::MODULE_ARGUMENT,
                    format!(
                        "children index {} out of bounds ({n} children)",
                        crate::value::format_number(x)
                    ),
                    cx.file,
                    span,
                ));
            }
            indices.push(x as usize);
            Ok(())
        };
        match &selection {
            None | Some(Value::Undef) => indices.extend(0..n),
            Some(Value::Number(x)) => add(self, *x)?,
            Some(Value::Vector(v)) => {
                for e in v.iter() {
                    match e {
                        Value::Number(x) => add(self, *x)?,
                        _ => {
                            return Err(self.error(
                                codes::MODULE_ARGUMENT,
                                "children([…]) needs numbers",
                                cx.file,
                                span,
                            ));
                        }
                    }
                }
            }
            Some(Value::Range(r)) => {
                let count = r.len();
                self.tick(count, cx.file, span)?;
                for i in 0..count {
                    add(self, r.at(i))?;
                }
            }
            Some(other) => {
                return Err(self.error(
                    codes::MODULE_ARGUMENT,
                    format!(
                        "children() needs an index, a vector or a range, got {}",
                        other.type_name()
                    ),
                    cx.file,
                    span,
                ));
            }
        }
        // The children's own scope, entered from here so that `$`-variables set by the module
        // reach them.
        let frame = Frame::child(&children.env, &cx.frame);
        let items = ScopeItems {
            assignments: children.assignments.clone(),
            definitions: children.definitions.clone(),
            ..ScopeItems::default()
        };
        self.define(&items, &frame)?;
        self.assign(&items, &frame)?;
        let mut edges = Vec::new();
        for i in indices {
            let (file, stmt) = children.items[i];
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
        Ok(self.group(edges, Source::new(cx.file, span)))
    }

    fn intersection_for(
        &mut self,
        args: &'a [Arg],
        child: Option<&'a Stmt>,
        span: Span,
        cx: &Cx<'a>,
    ) -> R<Option<Edge>> {
        let mut bindings = Vec::new();
        for a in args {
            match &a.name {
                Some(name) => bindings.push((name.name.as_str(), &a.value)),
                None => {
                    return Err(self.error(
                        codes::MODULE_ARGUMENT,
                        "intersection_for needs `name = values` arguments",
                        cx.file,
                        a.span,
                    ));
                }
            }
        }
        let mut parts = Vec::new();
        let body_source = Source::new(cx.file, child.map_or(span, |c| c.span));
        self.for_each(&bindings, cx, &mut |this, frame| {
            let edges = this.eval_body(
                child,
                &Cx {
                    frame,
                    file: cx.file,
                },
            )?;
            if let Some(edge) = this.group(edges, body_source) {
                parts.push(edge);
            }
            Ok(())
        })?;
        if parts.is_empty() {
            return Ok(None);
        }
        Ok(Some(
            self.dag
                .intersection(parts, Source::new(cx.file, span))
                .into(),
        ))
    }

    // ----- echo and assert ---------------------------------------------------------------

    /// Reports an `echo` line, within what is left of the echo-output limit: the line that
    /// crosses it is cut, with a warning, and later lines are left out.
    fn echo(&mut self, values: &[ArgValue<'a>], file: FileId, span: Span) {
        let Some(left) = self.echo_left else {
            return;
        };
        let mut text = BoundedText::new(left.saturating_sub(ECHO_LINE_COST));
        let written = text.push_echo_line(values.iter().map(|a| (a.name, &a.value)));
        self.echo_left = Some(left.saturating_sub(text.len() as u64 + ECHO_LINE_COST));
        let mut line = text.into_string();
        if written.is_err() {
            line.push('…');
            self.echo_left = None;
        }
        self.diagnostics.push(Diagnostic::new(
            qcsg_diag::Severity::Info,
            codes::ECHO,
            line,
            file,
            span,
        ));
        if written.is_err() {
            self.diagnostics.push(
                Diagnostic::warning(
                    codes::ECHO_LIMIT,
                    format!(
                        "echo output passed the limit of {} bytes: this line is cut and later echo output is left out",
                        self.options.max_echo_len
                    ),
                    file,
                    span,
                )
                .with_help(
                    "if you need all of it, raise the limit with `--max-echo-len N` on the command line",
                ),
            );
        }
    }

    fn assert(
        &mut self,
        values: &[ArgValue<'a>],
        args: &'a [Arg],
        file: FileId,
        span: Span,
    ) -> R<()> {
        let pick = |name: &str, position: usize| {
            values
                .iter()
                .zip(args)
                .find(|(a, _)| a.name == Some(name))
                .or_else(|| {
                    values
                        .iter()
                        .zip(args)
                        .filter(|(a, _)| a.name.is_none())
                        .nth(position)
                })
        };
        let Some((cond, cond_arg)) = pick("condition", 0) else {
            return Err(self.error(
                codes::ASSERTION_FAILED,
                "assert() needs a condition",
                file,
                span,
            ));
        };
        if cond.value.truthy() {
            return Ok(());
        }
        let mut condition_text = String::new();
        printer::write_expr(&mut condition_text, &cond_arg.value);
        let mut message = format!("assertion `{condition_text}` failed");
        if let Some((m, _)) = pick("message", 1) {
            message.push_str(": ");
            // The message is quoted as echo prints it, as long as a string may be at most.
            let mut text = BoundedText::new(self.options.max_string_len);
            let cut = text.push_echo(&m.value).is_err();
            message.push_str(text.as_str());
            if cut {
                message.push('…');
            }
        }
        Err(self.error(codes::ASSERTION_FAILED, message, file, span))
    }

    // ----- expressions -------------------------------------------------------------------

    fn eval_expr(&mut self, expr: &'a Expr, cx: &Cx<'a>) -> R<Value<'a>> {
        stacker::maybe_grow(STACK_RED_ZONE, STACK_GROWTH, || {
            self.eval_expr_inner(expr, cx)
        })
    }

    fn eval_expr_inner(&mut self, expr: &'a Expr, cx: &Cx<'a>) -> R<Value<'a>> {
        let file = cx.file;
        match &expr.kind {
            ExprKind::Number(x) => Ok(Value::Number(*x)),
            ExprKind::String(s) => Ok(Value::string(s.as_str())),
            ExprKind::Bool(b) => Ok(Value::Bool(*b)),
            ExprKind::Undef => Ok(Value::Undef),
            ExprKind::Ident(ident) => self.lookup_variable(&ident.name, file, ident.span, cx),
            ExprKind::Paren(inner) => self.eval_expr(inner, cx),
            ExprKind::Unary {
                op,
                op_span,
                operand,
            } => {
                let v = self.eval_expr(operand, cx)?;
                ops::unary(*op, &v).map_err(|m| {
                    self.error(codes::OPERATOR_TYPE, m, file, op_span.cover(operand.span))
                })
            }
            ExprKind::Binary { op, lhs, rhs, .. } => {
                let a = self.eval_expr(lhs, cx)?;
                // `&&` and `||` short-circuit.
                match op {
                    BinaryOp::And if !a.truthy() => return Ok(Value::Bool(false)),
                    BinaryOp::Or if a.truthy() => return Ok(Value::Bool(true)),
                    _ => {}
                }
                let b = self.eval_expr(rhs, cx)?;
                ops::binary(*op, &a, &b)
                    .map_err(|m| self.error(codes::OPERATOR_TYPE, m, file, expr.span))
            }
            ExprKind::Ternary { cond, then, els } => {
                if self.eval_expr(cond, cx)?.truthy() {
                    self.eval_expr(then, cx)
                } else {
                    self.eval_expr(els, cx)
                }
            }
            ExprKind::Call { .. } => match self.eval_tail_call(expr, cx)? {
                Tail::Done(v) => Ok(v),
                Tail::Call(f, args, span, file) => self.call_function(f, args, span, file, cx),
            },
            ExprKind::Index { base, index } => {
                let b = self.eval_expr(base, cx)?;
                let i = self.eval_expr(index, cx)?;
                Ok(index_value(&b, &i))
            }
            ExprKind::Member { base, member } => {
                let b = self.eval_expr(base, cx)?;
                let i = match member.name.as_str() {
                    "x" => 0.0,
                    "y" => 1.0,
                    "z" => 2.0,
                    _ => return Ok(Value::Undef),
                };
                Ok(match b {
                    Value::Vector(_) => index_value(&b, &Value::Number(i)),
                    _ => Value::Undef,
                })
            }
            ExprKind::Vector(elems) => {
                let mut out = Vec::new();
                for e in elems {
                    self.eval_elem(e, cx, &mut out, expr.span)?;
                }
                Ok(Value::vector(out))
            }
            ExprKind::Range { start, step, end } => {
                let num = |this: &mut Self, e: &'a Expr| -> R<f64> {
                    match this.eval_expr(e, cx)? {
                        Value::Number(x) => Ok(x),
                        other => Err(this.error(
                            codes::OPERATOR_TYPE,
                            format!("a range needs numbers, got {}", other.type_name()),
                            file,
                            e.span,
                        )),
                    }
                };
                let mut begin = num(self, start)?;
                let step_value = match step {
                    Some(s) => Some(num(self, s)?),
                    None => None,
                };
                let mut end_value = num(self, end)?;
                if step_value.is_none() && begin > end_value {
                    self.warn(
                        codes::REVERSED_RANGE,
                        "a range [begin : end] with begin > end: OpenSCAD swaps the ends (deprecated)",
                        file,
                        expr.span,
                    );
                    std::mem::swap(&mut begin, &mut end_value);
                }
                Ok(Value::Range(Range {
                    begin,
                    step: step_value.unwrap_or(1.0),
                    end: end_value,
                }))
            }
            ExprKind::Let { bindings, body } => {
                let frame = self.bind_sequential(bindings, cx)?;
                self.eval_expr(body, &Cx { frame, file })
            }
            ExprKind::Assert { args, body, .. } => {
                let values = self.eval_args(args, cx)?;
                self.assert(&values, args, file, expr.span)?;
                match body {
                    Some(b) => self.eval_expr(b, cx),
                    None => Ok(Value::Undef),
                }
            }
            ExprKind::Echo { args, body, .. } => {
                let values = self.eval_args(args, cx)?;
                self.echo(&values, file, expr.span);
                match body {
                    Some(b) => self.eval_expr(b, cx),
                    None => Ok(Value::Undef),
                }
            }
            ExprKind::FunctionLit { params, body } => Ok(Value::Function(Rc::new(Callable {
                params,
                body,
                env: cx.frame.clone(),
                file,
            }))),
            ExprKind::Error => Err(self.error(
                codes::UNSUPPORTED,
                "this expression has a syntax error",
                file,
                expr.span,
            )),
        }
    }

    fn lookup_variable(
        &mut self,
        name: &str,
        file: FileId,
        span: Span,
        cx: &Cx<'a>,
    ) -> R<Value<'a>> {
        if let Some(v) = cx.frame.lookup(name) {
            return Ok(v);
        }
        if let Some(v) = builtin_variable(name) {
            return Ok(v);
        }
        if name.starts_with('$') {
            return Ok(Value::Undef);
        }
        Err(self.error(
            codes::UNDEFINED_NAME,
            format!("no variable named `{name}`"),
            file,
            span,
        ))
    }

    fn eval_elem(
        &mut self,
        elem: &'a ListElem,
        cx: &Cx<'a>,
        out: &mut Vec<Value<'a>>,
        span: Span,
    ) -> R<()> {
        match &elem.kind {
            ListElemKind::Expr(e) => {
                let v = self.eval_expr(e, cx)?;
                self.check_len(out.len() as u64 + 1, cx.file, span)?;
                out.push(v);
            }
            ListElemKind::For { bindings, body } => {
                self.for_each(&heads(bindings), cx, &mut |this, frame| {
                    this.eval_elem(
                        body,
                        &Cx {
                            frame,
                            file: cx.file,
                        },
                        out,
                        span,
                    )
                })?;
            }
            ListElemKind::CFor {
                init,
                cond,
                update,
                body,
            } => {
                let mut frame = self.bind_sequential(init, cx)?;
                loop {
                    self.tick(1, cx.file, elem.span)?;
                    let inner = Cx {
                        frame: frame.clone(),
                        file: cx.file,
                    };
                    if !self.eval_expr(cond, &inner)?.truthy() {
                        break;
                    }
                    self.eval_elem(body, &inner, out, span)?;
                    let next = Frame::nested(&cx.frame);
                    for (name, value) in frame.locals() {
                        next.set(name, value);
                    }
                    for b in update {
                        let v = self.eval_expr(&b.value, &inner)?;
                        next.set(&b.name.name, v);
                    }
                    frame = next;
                }
            }
            ListElemKind::If { cond, then, els } => {
                if self.eval_expr(cond, cx)?.truthy() {
                    self.eval_elem(then, cx, out, span)?;
                } else if let Some(els) = els {
                    self.eval_elem(els, cx, out, span)?;
                }
            }
            ListElemKind::Each(inner) => {
                let mut values = Vec::new();
                self.eval_elem(inner, cx, &mut values, span)?;
                for v in values {
                    match &v {
                        Value::Vector(items) => {
                            self.check_len((out.len() + items.len()) as u64, cx.file, span)?;
                            out.extend(items.iter().cloned());
                        }
                        Value::Range(r) => {
                            let n = r.len();
                            self.check_len(out.len() as u64 + n, cx.file, span)?;
                            out.extend((0..n).map(|i| Value::Number(r.at(i))));
                        }
                        Value::String(s) => {
                            let n = s.chars().count() as u64;
                            self.check_len(out.len() as u64 + n, cx.file, span)?;
                            out.extend(s.chars().map(|c| Value::string(c.to_string())));
                        }
                        _ => {
                            self.check_len(out.len() as u64 + 1, cx.file, span)?;
                            out.push(v.clone());
                        }
                    }
                }
            }
            ListElemKind::Let { bindings, body } => {
                let frame = self.bind_sequential(bindings, cx)?;
                self.eval_elem(
                    body,
                    &Cx {
                        frame,
                        file: cx.file,
                    },
                    out,
                    span,
                )?;
            }
            ListElemKind::Paren(inner) => self.eval_elem(inner, cx, out, span)?,
        }
        Ok(())
    }

    // ----- function calls ----------------------------------------------------------------

    /// Evaluates `expr` in tail position: a call of a user function is returned unevaluated so
    /// that the caller can loop instead of recursing (OpenSCAD also eliminates tail calls).
    fn eval_tail(&mut self, expr: &'a Expr, cx: &Cx<'a>) -> R<Tail<'a>> {
        match &expr.kind {
            ExprKind::Paren(inner) => self.eval_tail(inner, cx),
            ExprKind::Ternary { cond, then, els } => {
                if self.eval_expr(cond, cx)?.truthy() {
                    self.eval_tail(then, cx)
                } else {
                    self.eval_tail(els, cx)
                }
            }
            ExprKind::Let { bindings, body } => {
                let frame = self.bind_sequential(bindings, cx)?;
                self.eval_tail(
                    body,
                    &Cx {
                        frame,
                        file: cx.file,
                    },
                )
            }
            ExprKind::Call { .. } => self.eval_tail_call(expr, cx),
            _ => Ok(Tail::Done(self.eval_expr(expr, cx)?)),
        }
    }

    /// A call: built-ins are evaluated, user functions returned as a pending tail call.
    fn eval_tail_call(&mut self, expr: &'a Expr, cx: &Cx<'a>) -> R<Tail<'a>> {
        let ExprKind::Call { callee, args, .. } = &expr.kind else {
            return Ok(Tail::Done(self.eval_expr(expr, cx)?));
        };
        let file = cx.file;
        let function = match &callee.kind {
            ExprKind::Ident(ident) => {
                let name = ident.name.as_str();
                match &cx.frame.lookup(name) {
                    Some(Value::Function(f)) => f.clone(),
                    found => {
                        if let Some(def) = cx.frame.lookup_function(name) {
                            def
                        } else if found.is_some() {
                            return Err(self.error(
                                codes::NOT_CALLABLE,
                                format!("`{name}` is not a function"),
                                file,
                                ident.span,
                            ));
                        } else if builtins_fn::is_builtin(name) {
                            let values = self.eval_args(args, cx)?;
                            return Ok(Tail::Done(
                                self.call_builtin(name, values, args, file, expr.span)?,
                            ));
                        } else if cx.frame.lookup_module(name).is_some()
                            || qcsg_sema::builtins::module(name).is_some()
                        {
                            return Err(self.error(
                                codes::WRONG_KIND,
                                format!("`{name}` is a module, not a function"),
                                file,
                                ident.span,
                            ));
                        } else {
                            return Err(self.error(
                                codes::UNDEFINED_NAME,
                                format!("no function named `{name}`"),
                                file,
                                ident.span,
                            ));
                        }
                    }
                }
            }
            _ => match &self.eval_expr(callee, cx)? {
                Value::Function(f) => f.clone(),
                other => {
                    return Err(self.error(
                        codes::NOT_CALLABLE,
                        format!("a {} is not a function", other.type_name()),
                        file,
                        callee.span,
                    ));
                }
            },
        };
        let values = self.eval_args(args, cx)?;
        Ok(Tail::Call(function, values, expr.span, file))
    }

    fn call_function(
        &mut self,
        mut function: Rc<FunctionDef<'a>>,
        mut values: Vec<ArgValue<'a>>,
        span: Span,
        file: FileId,
        cx: &Cx<'a>,
    ) -> R<Value<'a>> {
        self.enter(file, span)?;
        self.tick(1, file, span)?;
        let result = loop {
            let frame = Frame::child(&function.env, &cx.frame);
            let f = function.clone();
            if let Err(stop) = self.bind_params(&frame, f.params, &f.env, f.file, values) {
                break Err(stop);
            }
            match self.eval_tail(
                f.body,
                &Cx {
                    frame,
                    file: f.file,
                },
            ) {
                Ok(Tail::Done(v)) => break Ok(v),
                Ok(Tail::Call(next, next_values, next_span, next_file)) => {
                    if let Err(stop) = self.tick(1, next_file, next_span) {
                        break Err(stop);
                    }
                    function = next;
                    values = next_values;
                }
                Err(stop) => break Err(stop),
            }
        };
        self.depth -= 1;
        result
    }

    fn call_builtin(
        &mut self,
        name: &str,
        values: Vec<ArgValue<'a>>,
        args: &'a [Arg],
        file: FileId,
        span: Span,
    ) -> R<Value<'a>> {
        let Some(signature) = qcsg_sema::builtins::function(name) else {
            return Err(self.error(
                codes::UNDEFINED_NAME,
                format!("no function named `{name}`"),
                file,
                span,
            ));
        };
        // Named arguments go to their parameter's position.
        let mut positional: Vec<Value<'a>> = Vec::new();
        let mut named: Vec<(&str, Value<'a>)> = Vec::new();
        for a in values {
            match a.name {
                Some(n) if n.starts_with('$') => {}
                Some(n) => named.push((n, a.value)),
                None => positional.push(a.value),
            }
        }
        for (n, v) in named {
            match signature.params.iter().position(|p| p.name == n) {
                Some(i) => {
                    if positional.len() <= i {
                        positional.resize(i + 1, Value::Undef);
                    }
                    positional[i] = v;
                }
                None => {
                    let at = args
                        .iter()
                        .find(|a| a.name.as_ref().is_some_and(|x| x.name == n))
                        .map_or(span, |a| a.span);
                    return Err(self.error(
                        codes::FUNCTION_ARGUMENT,
                        format!("{name}() has no parameter `{n}`"),
                        file,
                        at,
                    ));
                }
            }
        }
        let mut warnings = Vec::new();
        let result = builtins_fn::call(name, &positional, self.options, &mut warnings);
        for w in warnings {
            self.warn(codes::SEARCH_TABLE, w, file, span);
        }
        match result {
            Ok(v) => Ok(v),
            Err(BuiltinError::Undefined(message)) => {
                Err(self.error(codes::FUNCTION_ARGUMENT, message, file, span))
            }
            Err(BuiltinError::TooLong(n)) => {
                self.check_len(n, file, span)?;
                Ok(Value::Undef)
            }
            Err(BuiltinError::StringTooLong) => Err(self.error(
                codes::STRING_LIMIT,
                format!(
                    "{name}() would make a string longer than the limit of {} bytes",
                    self.options.max_string_len
                ),
                file,
                span,
            )),
        }
    }
}

/// The arguments of a built-in module call by parameter name.
#[derive(Default)]
struct BuiltinArgs<'a> {
    values: Vec<(&'a str, Value<'a>)>,
}

impl<'a> ArgLookup<'a> for BuiltinArgs<'a> {
    fn get(&self, name: &str) -> Value<'a> {
        self.values
            .iter()
            .rev()
            .find(|(n, _)| *n == name)
            .map_or(Value::Undef, |(_, v)| v.clone())
    }
}

/// The `i`-th value a `for` takes over `values`.
fn iteration_value<'a>(values: &Value<'a>, i: u64) -> Value<'a> {
    match values {
        Value::Range(r) => Value::Number(r.at(i)),
        Value::Vector(v) => v.get(i as usize).cloned().unwrap_or(Value::Undef),
        Value::String(s) => s
            .chars()
            .nth(i as usize)
            .map_or(Value::Undef, |c| Value::string(c.to_string())),
        other => other.clone(),
    }
}

/// `base[index]`; `undef` out of range, as in OpenSCAD (which does not warn).
fn index_value<'a>(base: &Value<'a>, index: &Value<'a>) -> Value<'a> {
    let Value::Number(i) = index else {
        return Value::Undef;
    };
    if i.is_nan() || *i < 0.0 {
        return Value::Undef;
    }
    match base {
        Value::Vector(v) if *i < v.len() as f64 => v[*i as usize].clone(),
        Value::String(s) => s
            .chars()
            .nth(*i as usize)
            .map_or(Value::Undef, |c| Value::string(c.to_string())),
        Value::Range(r) if (*i as u64) < r.len() => Value::Number(r.at(*i as u64)),
        _ => Value::Undef,
    }
}

/// Built-in variables and the defaults of OpenSCAD's special variables.
fn builtin_variable<'a>(name: &str) -> Option<Value<'a>> {
    let n = |x: f64| Some(Value::Number(x));
    let v3 = |a: f64, b: f64, c: f64| {
        Some(Value::vector(vec![
            Value::Number(a),
            Value::Number(b),
            Value::Number(c),
        ]))
    };
    match name {
        "PI" => n(std::f64::consts::PI),
        "$fn" => n(0.0),
        "$fa" => n(12.0),
        "$fs" => n(2.0),
        "$t" => n(0.0),
        "$preview" => Some(Value::Bool(false)),
        "$vpr" => v3(55.0, 0.0, 25.0),
        "$vpt" => v3(0.0, 0.0, 0.0),
        "$vpd" => n(140.0),
        "$vpf" => n(22.5),
        "$children" | "$parent_modules" => n(0.0),
        _ => None,
    }
}

/// The `(name, value)` heads of bindings.
fn heads(bindings: &[Binding]) -> Vec<(&str, &Expr)> {
    bindings
        .iter()
        .map(|b| (b.name.name.as_str(), &b.value))
        .collect()
}
