//! The qcsg evaluator: a checked program (`qcsg_sema::Analysis`) to an exact solid, a
//! transformed CSG [`Dag`] over quadric leaves, with OpenSCAD 2021.01's semantics.
//!
//! [`evaluate`] is the entry point. It runs the main file's top-level scope (an implicit union)
//! with `include`d files spliced in and `use`d files' definitions imported, applies `-D`
//! overrides ([`EvalOptions::defines`]), and returns the DAG and the diagnostics: `echo` output
//! (information [`codes::ECHO`], formatted exactly like OpenSCAD's `ECHO: …` lines), warnings,
//! and runtime errors. A crossed limit or a failed `assert` stops the evaluation, as it stops
//! OpenSCAD; any other runtime error (where OpenSCAD warns and goes on with `undef`) abandons
//! only its assignment (the variable is then `undef`) or statement, so one run reports them all
//! (each place once, at most 50). With errors the DAG is partial: tools may show it, nothing may
//! build a solid from it. Text is bounded like vectors: a string longer than
//! [`EvalOptions::max_string_len`] is a limit error; `echo` output past
//! [`EvalOptions::max_echo_len`] is cut with a warning and evaluation goes on, since `echo`
//! does not change the solid. Printing stops at those limits, so a value that shares its parts
//! (`[v, v]` forty times over) costs no more to print than the text the limit allows.
//!
//! Semantics follow OpenSCAD 2021.01, checked against it (see `tests/eval/`):
//! - Values: numbers (f64), booleans, strings, `undef`, vectors, ranges, functions. Where
//!   OpenSCAD would yield `undef` *with a warning* (`"a" + 1`, `sin("x")`, `len(5)`), qcsg
//!   reports an error at the span; where it yields `undef` silently (an index out of range)
//!   so does qcsg.
//! - Scoping: assignments of a scope run before its instantiations; a variable assigned twice
//!   takes the last value at the position of the first; `$`-variables are dynamically scoped
//!   (assignments and `$x = …` arguments reach callees and `children()`); default parameter
//!   values are evaluated in the definition's scope; a variable holding a function literal is
//!   called in preference to a function of the same name.
//! - Tail calls of user functions (through `?:`, `let` and parentheses) run in a loop, so tail
//!   recursion is bounded by [`EvalOptions::max_iterations`] only; other recursion by
//!   [`EvalOptions::max_recursion`], on a stack that grows as needed.
//! - Modifiers: `*` drops its subtree unevaluated; `%` evaluates it (echo runs) and keeps it
//!   out of the solid as a background part; `#` highlights; `!` makes its subtree (without the
//!   transforms above it) the whole solid.
//! - Primitives and their quadrics: see [`primitives`]; transforms: see [`transforms`].
//!   A singular transform (`scale(0)`) removes its object with a warning, as OpenSCAD does; a
//!   primitive of zero or negative size is an empty solid with a warning.
//! - Without a seed, `rands` uses seed 0, so output is always reproducible.

pub mod builtins_fn;
pub mod codes;
pub mod color;
pub mod env;
mod eval;
pub mod extrude;
pub mod glyphs;
pub mod hull;
pub mod hull_2d;
pub mod hull_balls;
pub mod hull_discs;
pub mod hull_frusta;
pub mod import;
pub mod math;
pub mod mesh_shadow;
pub mod minkowski;
pub mod minkowski_disc;
pub mod offset;
pub mod ops;
pub mod planar;
pub mod polygon;
pub mod polyhedron;
pub mod primitives;
pub mod primitives_2d;
pub mod printer;
pub mod revolve;
pub mod section;
pub mod surface;
pub mod text;
pub mod transforms;
pub mod value;

use std::collections::HashMap;

pub use qcsg_csg::Dag;
use qcsg_diag::{Diagnostic, FileId, Severity, Span};
use qcsg_sema::Analysis;
use qcsg_syntax::ast::{Expr, StmtKind};

/// Settings of an evaluation: limits and `-D` overrides.
#[derive(Clone, Debug)]
pub struct EvalOptions {
    /// `-D name=value` overrides of top-level variables of the main file, value as source text
    /// (an expression). As in OpenSCAD, an override replaces the value of the variable's
    /// assignment (or adds one at the end of the file).
    pub defines: Vec<(String, String)>,
    /// The deepest nesting of module and (non-tail) function calls.
    pub max_recursion: usize,
    /// The most loop iterations and function calls in total.
    pub max_iterations: u64,
    /// The most elements of one vector (ranges iterated or spliced count too).
    pub max_vector_len: u64,
    /// The most primitive instances.
    pub max_instances: u64,
    /// The most bytes (UTF-8) of one string that evaluation builds (`str`, `chr`).
    pub max_string_len: u64,
    /// The most bytes of `echo` output of one evaluation, each line counting its text and 64
    /// bytes more (about what holding and printing the line costs beside its text). The line
    /// that crosses it is cut and later lines are left out, with a warning.
    pub max_echo_len: u64,
    /// The most bytes of one file that `import` reads.
    pub max_import_bytes: u64,
    /// The most distinct points (corners and centres) a 3-D `hull` or one convex part of a
    /// `minkowski` is computed of (64 times as many in 2-D, where the hull costs less).
    pub max_hull_points: usize,
    /// The most distinct faces of one convex part of a `hull` or `minkowski` child.
    pub max_part_planes: usize,
    /// The most convex parts a `minkowski` is a union of.
    pub max_minkowski_parts: usize,
}

impl EvalOptions {
    /// Default recursion limit.
    pub const DEFAULT_MAX_RECURSION: usize = 10_000;
    /// Default iteration limit.
    pub const DEFAULT_MAX_ITERATIONS: u64 = 10_000_000;
    /// Default vector-length limit.
    pub const DEFAULT_MAX_VECTOR_LEN: u64 = 10_000_000;
    /// Default primitive-instance limit.
    pub const DEFAULT_MAX_INSTANCES: u64 = 1_000_000;
    /// Default string-length limit: 16 MiB, a thousand times the longest text a scene plausibly
    /// needs (labels, generated names), while a string at the limit costs 16 MiB, as little as
    /// a vector of a million numbers.
    pub const DEFAULT_MAX_STRING_LEN: u64 = 16 << 20;
    /// Default echo-output limit: 4 MiB, some 50,000 short lines or one line of four million
    /// characters, more than anyone reads, and little enough that the diagnostics holding it and
    /// their rendering for a terminal stay within a couple of hundred MB.
    pub const DEFAULT_MAX_ECHO_LEN: u64 = 4 << 20;
    /// Default import-size limit: 256 MiB, a binary STL of five million triangles, more than the
    /// cells of the default vector-length limit make affordable, while bounding what a mistaken
    /// `import` of a huge file holds in memory.
    pub const DEFAULT_MAX_IMPORT_BYTES: u64 = 256 << 20;
    /// Default hull point limit: the exact 3-D hull is quartic in the number of points, and 400
    /// take a fraction of a second.
    pub const DEFAULT_MAX_HULL_POINTS: usize = 400;
    /// Default limit on the faces of one convex part: its corners are found from every triple of
    /// planes, cubic in their number.
    pub const DEFAULT_MAX_PART_PLANES: usize = 96;
    /// Default Minkowski part limit: the sum of two unions is one part per pair.
    pub const DEFAULT_MAX_MINKOWSKI_PARTS: usize = 4096;
}

impl Default for EvalOptions {
    fn default() -> Self {
        Self {
            defines: Vec::new(),
            max_recursion: Self::DEFAULT_MAX_RECURSION,
            max_iterations: Self::DEFAULT_MAX_ITERATIONS,
            max_vector_len: Self::DEFAULT_MAX_VECTOR_LEN,
            max_instances: Self::DEFAULT_MAX_INSTANCES,
            max_string_len: Self::DEFAULT_MAX_STRING_LEN,
            max_echo_len: Self::DEFAULT_MAX_ECHO_LEN,
            max_import_bytes: Self::DEFAULT_MAX_IMPORT_BYTES,
            max_hull_points: Self::DEFAULT_MAX_HULL_POINTS,
            max_part_planes: Self::DEFAULT_MAX_PART_PLANES,
            max_minkowski_parts: Self::DEFAULT_MAX_MINKOWSKI_PARTS,
        }
    }
}

/// The result of an evaluation.
#[derive(Debug)]
pub struct Evaluation {
    /// The solid: its root is the (possibly empty) union of the top level, or the `!` subtree.
    pub dag: Dag,
    /// Echo output, warnings and errors, in the order evaluation produced them.
    pub diagnostics: Vec<Diagnostic>,
    /// Which DAG node each module instantiation statement (its whole span, in its file)
    /// produced, sorted, once per distinct pair: a statement run several times with different
    /// results has several entries. Editors use it to show the geometry of a call.
    pub instantiations: Vec<(qcsg_csg::Source, qcsg_csg::NodeId)>,
    /// The files `import` read or tried to read, as resolved, in order, each once: what a
    /// viewer watches beside the sources.
    pub imports: Vec<std::path::PathBuf>,
}

impl Evaluation {
    /// Whether evaluation reported an error.
    pub fn has_errors(&self) -> bool {
        self.diagnostics.iter().any(Diagnostic::is_error)
    }

    /// The `echo` output, one `ECHO: …` line per echo, in evaluation order.
    pub fn echo_lines(&self) -> Vec<&str> {
        self.diagnostics
            .iter()
            .filter(|d| d.code == codes::ECHO)
            .map(|d| d.message.as_str())
            .collect()
    }
}

/// The file id under which `-D` values are parsed; their diagnostics are moved to the main file.
const DEFINE_FILE: FileId = FileId(u32::MAX);

/// Evaluates the program `analysis` checked. Call it when checking found no errors (names it
/// reports as undefined are runtime errors here). Never panics.
pub fn evaluate(analysis: &Analysis, options: &EvalOptions) -> Evaluation {
    let mut diagnostics = Vec::new();
    let mut defines: Vec<(String, Expr)> = Vec::new();
    for (name, text) in &options.defines {
        match parse_define(name, text) {
            Some(expr) => defines.push((name.clone(), expr)),
            None => diagnostics.push(
                Diagnostic::error(
                    codes::BAD_DEFINE,
                    format!("`-D {name}={text}`: the value is not an expression"),
                    analysis.main,
                    Span::default(),
                )
                .with_help(
                    "write the value as an expression, strings in quotes: -D 'name=\"text\"'",
                ),
            ),
        }
    }
    if !diagnostics.is_empty() {
        let mut dag = Dag::new();
        let root = dag.empty(qcsg_csg::Source::new(analysis.main, Span::default()));
        dag.set_root(root.into());
        return Evaluation {
            dag,
            diagnostics,
            instantiations: Vec::new(),
            imports: Vec::new(),
        };
    }
    let links: HashMap<(FileId, u32), FileId> = analysis
        .links
        .iter()
        .filter_map(|l| l.target.map(|t| ((l.file, l.span.start), t)))
        .collect();
    let run = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        let mut evaluator = eval::Evaluator::new(
            &analysis.trees,
            &analysis.sources,
            links,
            options,
            &defines,
            DEFINE_FILE,
        );
        evaluator.fonts = register_fonts(&analysis.fonts, &mut evaluator.diagnostics);
        let outcome = evaluator.run_main(analysis.main);
        let mut dag = std::mem::take(&mut evaluator.dag);
        if outcome.is_err() || dag.root().is_none() {
            let root = dag.empty(qcsg_csg::Source::new(analysis.main, Span::default()));
            dag.set_root(root.into());
        }
        let mut instantiations: Vec<_> = evaluator.instantiations.drain().collect();
        instantiations.sort_unstable();
        (
            dag,
            std::mem::take(&mut evaluator.diagnostics),
            instantiations,
            std::mem::take(&mut evaluator.imports),
        )
    }));
    let (dag, mut found, instantiations, imports) = match run {
        Ok(result) => result,
        Err(_) => {
            let mut dag = Dag::new();
            let root = dag.empty(qcsg_csg::Source::new(analysis.main, Span::default()));
            dag.set_root(root.into());
            let internal = Diagnostic::new(
                Severity::Error,
                codes::UNSUPPORTED,
                "internal error: the evaluator failed on this input",
                analysis.main,
                Span::default(),
            );
            (dag, vec![internal], Vec::new(), Vec::new())
        }
    };
    for d in &mut found {
        if d.file == DEFINE_FILE {
            d.file = analysis.main;
            d.span = Span::default();
        }
    }
    diagnostics.extend(found);
    Evaluation {
        dag,
        diagnostics,
        instantiations,
        imports,
    }
}

/// The expression of a `-D name=value` override.
fn parse_define(name: &str, text: &str) -> Option<Expr> {
    let source = format!("{name} = {text};");
    let parsed = qcsg_syntax::parse(&source, DEFINE_FILE);
    if !parsed.diagnostics.is_empty() || parsed.file.stmts.len() != 1 {
        return None;
    }
    match parsed.file.stmts.into_iter().next()?.kind {
        StmtKind::Assign { value, .. } => Some(value),
        _ => None,
    }
}

/// The faces of the font files named by `use <file.ttf>`, as OpenSCAD 2021.01 registers them
/// for `text(font = …)`; a file that cannot be read, is no font or draws with cubic curves is
/// error E0569 at its `<path>`.
fn register_fonts(
    uses: &[qcsg_sema::FontUse],
    diagnostics: &mut Vec<Diagnostic>,
) -> glyphs::fonts::RegisteredFonts {
    let mut fonts = glyphs::fonts::RegisteredFonts::default();
    for font in uses {
        if let Err(e) = fonts.register(&font.path) {
            diagnostics.push(Diagnostic::error(
                codes::FONT_UNUSABLE,
                format!(
                    "the font file `{}` named by `use` cannot be used: {e}",
                    font.path.display()
                ),
                font.file,
                font.span,
            ));
        }
    }
    fonts
}
