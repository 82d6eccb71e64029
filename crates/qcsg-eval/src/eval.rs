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
//! the evaluation stops after [`errors::MAX_ERRORS`] distinct ones. Warnings and `echo` output
//! are collected on the way. Deep recursion runs on a growing stack (`stacker`) and every limit
//! is checked before the work it bounds.
//!
//! The evaluator's state is defined here; its work is spread over one module per concern:
//! [`scopes`], [`statements`], [`dimensions`] (2-D or 3-D), [`bindings`] (`for` and `let`), [`instantiation`],
//! [`user_modules`] (with `children()`), [`meshes`] (`polyhedron`, `import`), [`arguments`], [`expressions`], [`comprehensions`],
//! [`function_calls`], [`echo_assert`], [`errors`] and [`limits`].

mod arguments;
mod bindings;
mod comprehensions;
mod dimensions;
mod drawing_functions;
mod drawings;
mod echo_assert;
mod errors;
mod expressions;
mod extrusions;
mod function_calls;
mod hulls;
mod instantiation;
mod limits;
mod meshes;
mod offsets;
mod projections;
mod revolutions;
mod scopes;
mod statements;
mod user_modules;

use std::collections::{HashMap, HashSet};
use std::rc::Rc;

use qcsg_csg::{Aabb, Dag, Edge, NodeId, Source};
use qcsg_diag::{Diagnostic, FileId, SourceMap, Span};
use qcsg_syntax::ast::{Expr, SourceFile};

use crate::EvalOptions;
use crate::env::Frame;
use crate::value::Value;

/// An error has been reported: the statement (or assignment) it occurred in is abandoned, and,
/// when it is fatal, the whole evaluation.
#[derive(Debug)]
pub(crate) struct Stop {
    fatal: bool,
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

const STACK_RED_ZONE: usize = 128 * 1024;
const STACK_GROWTH: usize = 8 * 1024 * 1024;

/// The state of one evaluation.
pub(crate) struct Evaluator<'a> {
    trees: &'a [SourceFile],
    /// The program's files, for their names: `import` paths are relative to the caller's.
    sources: &'a SourceMap,
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
    /// The names of the user module instantiations being evaluated, outermost first
    /// (`parent_module(n)`, `$parent_modules`).
    module_stack: Vec<&'a str>,
    /// The leaves that belong to 2-D shapes.
    planar_leaves: HashSet<NodeId>,
    /// The inner nodes built for 2-D shapes (see [`Evaluator::mark_planar`]).
    planar_nodes: HashSet<NodeId>,
    /// The nodes that made solids of 2-D shapes (extrusions): 3-D whatever their children.
    extruded: HashSet<NodeId>,
    /// The dimension of each DAG node so far (see [`dimensions`]).
    node_dims: Vec<dimensions::Dim>,
    /// A box of each DAG node so far, in its own frame.
    node_boxes: Vec<Aabb>,
    /// The files `import` read (or tried to), in order, each once.
    pub imports: Vec<std::path::PathBuf>,
    /// The cells of each mesh file imported so far, by resolved path.
    imported_meshes: HashMap<std::path::PathBuf, Rc<[crate::polyhedron::MeshShape]>>,
    /// The cells of each `surface` built so far, by resolved path, `invert` and `center`.
    surfaces: HashMap<(std::path::PathBuf, bool, bool), Rc<crate::polyhedron::MeshShape>>,
    /// The triangles of each mesh node (polyhedron, import, surface), for its shadow.
    mesh_faces: HashMap<NodeId, Rc<crate::mesh_shadow::MeshFaces>>,
    /// The fonts registered with `use <file.ttf>`.
    pub fonts: crate::glyphs::fonts::RegisteredFonts,
}

impl<'a> Evaluator<'a> {
    pub fn new(
        trees: &'a [SourceFile],
        sources: &'a SourceMap,
        links: HashMap<(FileId, u32), FileId>,
        options: &'a EvalOptions,
        defines: &'a [(String, Expr)],
        define_file: FileId,
    ) -> Self {
        Self {
            trees,
            sources,
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
            module_stack: Vec::new(),
            planar_leaves: HashSet::new(),
            planar_nodes: HashSet::new(),
            extruded: HashSet::new(),
            node_dims: Vec::new(),
            node_boxes: Vec::new(),
            imports: Vec::new(),
            imported_meshes: HashMap::new(),
            surfaces: HashMap::new(),
            mesh_faces: HashMap::new(),
            fonts: Default::default(),
        }
    }
}
