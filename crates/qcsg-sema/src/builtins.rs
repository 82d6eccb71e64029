//! Signatures of the built-in modules, functions and variables (docs/language.md), and the
//! OpenSCAD constructs the language rejects because no quadric represents them exactly.
//!
//! Parameter names and positional order follow OpenSCAD 2021.01 (`cylinder(h, r1, r2, center)`,
//! `sphere(r)` with `d` by name only, …). Every built-in module also accepts any `$`-argument
//! (`$fn = 32`), which sets a special variable for its subtree.

use crate::ty::{ParamTy, Ty};

/// One parameter of a built-in module or function.
#[derive(Clone, Copy, Debug)]
pub struct BuiltinParam {
    /// The parameter's name (for named arguments).
    pub name: &'static str,
    /// What it accepts.
    pub ty: ParamTy,
    /// Whether a call must supply it.
    pub required: bool,
    /// Whether it may be given by position (otherwise by name only, like `sphere(d = 2)`).
    pub positional: bool,
}

const fn pos(name: &'static str, ty: ParamTy) -> BuiltinParam {
    BuiltinParam {
        name,
        ty,
        required: false,
        positional: true,
    }
}

const fn req(name: &'static str, ty: ParamTy) -> BuiltinParam {
    BuiltinParam {
        name,
        ty,
        required: true,
        positional: true,
    }
}

const fn named(name: &'static str, ty: ParamTy) -> BuiltinParam {
    BuiltinParam {
        name,
        ty,
        required: false,
        positional: false,
    }
}

/// What kind of built-in module it is (for hover and the evaluator).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ModuleKind {
    /// A solid primitive such as `cube` or `ellipsoid`.
    Primitive,
    /// A transform of its children such as `translate`.
    Transform,
    /// A boolean operation on its children such as `difference`.
    Boolean,
    /// Anything else: `children`, `echo`, `assert`, `render`, `color`.
    Other,
}

/// A built-in module.
#[derive(Clone, Copy, Debug)]
pub struct BuiltinModule {
    /// Its name.
    pub name: &'static str,
    /// Its parameters, positional ones first in positional order.
    pub params: &'static [BuiltinParam],
    /// Whether it takes any number of arguments of any name (`echo`).
    pub variadic: bool,
    /// What kind of module it is.
    pub kind: ModuleKind,
    /// One line for hover.
    pub doc: &'static str,
}

/// What a built-in function returns.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Returns {
    /// A number.
    Number,
    /// A boolean.
    Bool,
    /// A string.
    String,
    /// A vector of unknown length.
    Vector,
    /// A vector of three numbers.
    Vector3,
    /// Depends on the arguments (`cross` of 2-vectors is a number, of 3-vectors a vector).
    Any,
}

impl Returns {
    /// The static type of the result.
    pub fn ty(self) -> Ty {
        match self {
            Returns::Number => Ty::Number,
            Returns::Bool => Ty::Bool,
            Returns::String => Ty::String,
            Returns::Vector => Ty::any_vector(),
            Returns::Vector3 => Ty::number_vector(Some(3)),
            Returns::Any => Ty::Any,
        }
    }
}

/// A built-in function.
#[derive(Clone, Copy, Debug)]
pub struct BuiltinFunction {
    /// Its name.
    pub name: &'static str,
    /// Its fixed parameters in positional order.
    pub params: &'static [BuiltinParam],
    /// For variadic functions (`min`, `str`, `concat`): what every further argument accepts.
    pub rest: Option<ParamTy>,
    /// At least this many arguments (for variadic functions).
    pub min_args: usize,
    /// What it returns.
    pub returns: Returns,
    /// One line for hover.
    pub doc: &'static str,
}

use ParamTy as P;

const VEC23: &[u32] = &[2, 3];
const VEC3: &[u32] = &[3];

/// The parameters of `import` and of its deprecated aliases, in OpenSCAD's positional order.
const IMPORT_PARAMS: &[BuiltinParam] = &[
    pos("file", P::String),
    pos("layer", P::String),
    pos("convexity", P::Number),
    pos("origin", P::NumberVector(&[2])),
    pos("scale", P::Number),
    named("width", P::Number),
    named("height", P::Number),
    named("center", P::Bool),
    named("dpi", P::Number),
    named("id", P::String),
];

/// Every built-in module, OpenSCAD's supported subset and the quadric-native additions.
pub const MODULES: &[BuiltinModule] = &[
    BuiltinModule {
        name: "cube",
        params: &[pos("size", P::NumberOrVector(VEC3)), pos("center", P::Bool)],
        variadic: false,
        kind: ModuleKind::Primitive,
        doc: "cube(size = 1, center = false): a box spanning [0, size] per axis unless centred",
    },
    BuiltinModule {
        name: "sphere",
        params: &[pos("r", P::Number), named("d", P::Number)],
        variadic: false,
        kind: ModuleKind::Primitive,
        doc: "sphere(r = 1) or sphere(d = 2): a ball centred at the origin",
    },
    BuiltinModule {
        name: "cylinder",
        params: &[
            pos("h", P::Number),
            pos("r1", P::Number),
            pos("r2", P::Number),
            pos("center", P::Bool),
            named("r", P::Number),
            named("d", P::Number),
            named("d1", P::Number),
            named("d2", P::Number),
        ],
        variadic: false,
        kind: ModuleKind::Primitive,
        doc: "cylinder(h, r | r1, r2 | d | d1, d2, center = false): a cylinder or cone frustum along Z",
    },
    BuiltinModule {
        name: "ellipsoid",
        params: &[
            pos("r", P::NumberOrVector(VEC3)),
            named("d", P::NumberOrVector(VEC3)),
        ],
        variadic: false,
        kind: ModuleKind::Primitive,
        doc: "ellipsoid(r = [a, b, c]): an ellipsoid centred at the origin with semi-axes a, b, c",
    },
    BuiltinModule {
        name: "paraboloid",
        params: &[
            pos("h", P::Number),
            pos("r", P::NumberOrVector(&[2])),
            pos("center", P::Bool),
        ],
        variadic: false,
        kind: ModuleKind::Primitive,
        doc: "paraboloid(h, r): an elliptic paraboloid with its apex at the origin, radius r at height h",
    },
    BuiltinModule {
        name: "hyperboloid",
        params: &[
            pos("h", P::Number),
            pos("r", P::NumberOrVector(&[2])),
            pos("c", P::Number),
            pos("sheets", P::Number),
            pos("center", P::Bool),
        ],
        variadic: false,
        kind: ModuleKind::Primitive,
        doc: "hyperboloid(h, r, c, sheets = 1): a hyperboloid of one or two sheets along Z, cut at height h",
    },
    BuiltinModule {
        name: "cone",
        params: &[
            pos("h", P::Number),
            pos("r", P::NumberOrVector(&[2])),
            pos("center", P::Bool),
        ],
        variadic: false,
        kind: ModuleKind::Primitive,
        doc: "cone(h, r): an elliptic cone with its apex at the origin, radius r at height h",
    },
    BuiltinModule {
        name: "halfspace",
        params: &[
            req("normal", P::NumberVector(VEC3)),
            pos("offset", P::Number),
        ],
        variadic: false,
        kind: ModuleKind::Primitive,
        doc: "halfspace(normal, offset = 0): the unbounded solid normal · p <= offset",
    },
    BuiltinModule {
        name: "quadric",
        params: &[req("q", P::List(&[4, 10]))],
        variadic: false,
        kind: ModuleKind::Primitive,
        doc: "quadric(q): where the quadric form (4x4 symmetric matrix or 10 coefficients) is <= 0",
    },
    BuiltinModule {
        name: "square",
        params: &[pos("size", P::NumberOrVector(&[2])), pos("center", P::Bool)],
        variadic: false,
        kind: ModuleKind::Primitive,
        doc: "square(size = 1, center = false): a 2-D rectangle spanning [0, size] per axis unless centred",
    },
    BuiltinModule {
        name: "circle",
        params: &[pos("r", P::Number), named("d", P::Number)],
        variadic: false,
        kind: ModuleKind::Primitive,
        doc: "circle(r = 1) or circle(d = 2): a 2-D disc centred at the origin, exact",
    },
    BuiltinModule {
        name: "polygon",
        params: &[
            pos("points", P::List(&[])),
            pos("paths", P::List(&[])),
            pos("convexity", P::Number),
        ],
        variadic: false,
        kind: ModuleKind::Primitive,
        doc: "polygon(points, paths): the 2-D region the paths enclose (one outline through all points without paths), filled with the even-odd rule, exact",
    },
    BuiltinModule {
        name: "text",
        params: &[
            pos("text", P::String),
            pos("size", P::Number),
            pos("font", P::String),
            named("halign", P::String),
            named("valign", P::String),
            named("spacing", P::Number),
            named("direction", P::String),
            named("language", P::String),
            named("script", P::String),
        ],
        variadic: false,
        kind: ModuleKind::Primitive,
        doc: "text(text, size = 10, font, halign, valign, spacing, direction, language, script): the glyphs of a TrueType font as a 2-D shape, exact (straight edges and parabolic arcs)",
    },
    BuiltinModule {
        name: "polyhedron",
        params: &[
            pos("points", P::List(&[])),
            pos("faces", P::List(&[])),
            pos("convexity", P::Number),
            named("triangles", P::List(&[])),
        ],
        variadic: false,
        kind: ModuleKind::Primitive,
        doc: "polyhedron(points, faces): the solid a closed mesh bounds, faces listed clockwise seen from outside, exact (`triangles` is the deprecated name of `faces`)",
    },
    BuiltinModule {
        name: "import",
        params: IMPORT_PARAMS,
        variadic: false,
        kind: ModuleKind::Primitive,
        doc: "import(file): the solid a closed STL, OFF or 3MF mesh bounds, or the 2-D shape of a DXF drawing's layer, exact; the path is relative to the file that calls it",
    },
    BuiltinModule {
        name: "import_stl",
        params: IMPORT_PARAMS,
        variadic: false,
        kind: ModuleKind::Primitive,
        doc: "import_stl(file): deprecated OpenSCAD name of import(file)",
    },
    BuiltinModule {
        name: "import_off",
        params: IMPORT_PARAMS,
        variadic: false,
        kind: ModuleKind::Primitive,
        doc: "import_off(file): deprecated OpenSCAD name of import(file)",
    },
    BuiltinModule {
        name: "import_dxf",
        params: IMPORT_PARAMS,
        variadic: false,
        kind: ModuleKind::Primitive,
        doc: "import_dxf(file, layer, convexity, origin, scale): deprecated OpenSCAD name of import(file, layer, …)",
    },
    BuiltinModule {
        name: "surface",
        params: &[
            pos("file", P::String),
            pos("center", P::Bool),
            pos("convexity", P::Number),
            named("invert", P::Bool),
        ],
        variadic: false,
        kind: ModuleKind::Primitive,
        doc: "surface(file, center = false, invert = false): the solid under a height map (a .dat table of numbers or a PNG image's luminance, 0 to 100) down to one below its lowest point, exactly as OpenSCAD meshes it",
    },
    BuiltinModule {
        name: "linear_extrude",
        params: &[
            pos("height", P::Number),
            named("center", P::Bool),
            named("convexity", P::Number),
            named("twist", P::Number),
            named("slices", P::Number),
            named("segments", P::Number),
            named("scale", P::NumberOrVector(&[2])),
            named("file", P::String),
            named("layer", P::String),
            named("origin", P::NumberVector(&[2])),
        ],
        variadic: false,
        kind: ModuleKind::Other,
        doc: "linear_extrude(height = 100, center = false, scale = 1): the 2-D children swept along Z, scaled towards the top (twist is not supported)",
    },
    BuiltinModule {
        name: "rotate_extrude",
        params: &[
            named("angle", P::Number),
            named("convexity", P::Number),
            named("file", P::String),
            named("layer", P::String),
            named("origin", P::NumberVector(&[2])),
            named("scale", P::Number),
        ],
        variadic: false,
        kind: ModuleKind::Other,
        doc: "rotate_extrude(angle = 360): the 2-D children, read as (r, z) with r = x, swept about Z, counter-clockwise from +X (outlines off the axis, which sweep tori, are not supported)",
    },
    BuiltinModule {
        name: "dxf_linear_extrude",
        params: &[
            pos("file", P::String),
            pos("layer", P::String),
            pos("height", P::Number),
            pos("center", P::Bool),
            pos("convexity", P::Number),
            pos("twist", P::Number),
            pos("slices", P::Number),
            named("origin", P::NumberVector(&[2])),
            named("scale", P::Number),
        ],
        variadic: false,
        kind: ModuleKind::Other,
        doc: "dxf_linear_extrude(file, layer, height): deprecated OpenSCAD form of linear_extrude(height) import(file, layer); `scale` scales the drawing and, as in OpenSCAD, the top",
    },
    BuiltinModule {
        name: "dxf_rotate_extrude",
        params: &[
            pos("file", P::String),
            pos("layer", P::String),
            pos("origin", P::NumberVector(&[2])),
            pos("scale", P::Number),
            named("convexity", P::Number),
            named("angle", P::Number),
        ],
        variadic: false,
        kind: ModuleKind::Other,
        doc: "dxf_rotate_extrude(file, layer, origin, scale): deprecated OpenSCAD form of rotate_extrude() import(file, layer, origin = origin, scale = scale)",
    },
    BuiltinModule {
        name: "projection",
        params: &[named("cut", P::Bool), named("convexity", P::Number)],
        variadic: false,
        kind: ModuleKind::Other,
        doc: "projection(cut = false): the 3-D children as a 2-D shape: their section by z = 0 (cut = true, exact) or their shadow on it (boxes, balls, ellipsoids, vertical cylinders and their unions)",
    },
    BuiltinModule {
        name: "hull",
        params: &[],
        variadic: false,
        kind: ModuleKind::Other,
        doc: "hull(): the convex hull of the children, exactly, for convex polytopes (cubes, polyhedra, polygons, squares) with balls or circles of any radii (the rounded box of eight spheres, the tapered capsule of two), or with cylinders and cones of parallel axes (the rounded plate of four cylinders)",
    },
    BuiltinModule {
        name: "minkowski",
        params: &[named("convexity", P::Number)],
        variadic: false,
        kind: ModuleKind::Other,
        doc: "minkowski(): the Minkowski sum of the children, exactly, for unions of convex polytopes with balls, or with cylinders and cones of parallel axes (a box with a sphere: the box with rounded edges and corners; with a cylinder: the plate with rounded vertical edges)",
    },
    BuiltinModule {
        name: "offset",
        params: &[
            pos("r", P::Number),
            named("delta", P::Number),
            named("chamfer", P::Bool),
        ],
        variadic: false,
        kind: ModuleKind::Other,
        doc: "offset(r | delta = 1, chamfer = false): the 2-D children grown (or shrunk, when negative) by r with rounded corners or by delta with mitred or chamfered corners, exactly, for unions of convex polygons and circles (growing) and intersections of edges and circles (shrinking)",
    },
    BuiltinModule {
        name: "translate",
        params: &[pos("v", P::NumberVector(VEC23))],
        variadic: false,
        kind: ModuleKind::Transform,
        doc: "translate(v): moves the children by v",
    },
    BuiltinModule {
        name: "rotate",
        params: &[
            pos("a", P::NumberOrVector(&[1, 2, 3])),
            pos("v", P::NumberVector(VEC23)),
        ],
        variadic: false,
        kind: ModuleKind::Transform,
        doc: "rotate(a) about Z, rotate([x, y, z]) about X then Y then Z, rotate(a, v) about axis v (degrees)",
    },
    BuiltinModule {
        name: "scale",
        params: &[pos("v", P::NumberOrVector(VEC23))],
        variadic: false,
        kind: ModuleKind::Transform,
        doc: "scale(s) or scale([sx, sy, sz]): scales the children",
    },
    BuiltinModule {
        name: "mirror",
        params: &[pos("v", P::NumberVector(VEC23))],
        variadic: false,
        kind: ModuleKind::Transform,
        doc: "mirror(v): reflects the children across the plane through the origin with normal v",
    },
    BuiltinModule {
        name: "multmatrix",
        params: &[pos("m", P::List(&[3, 4]))],
        variadic: false,
        kind: ModuleKind::Transform,
        doc: "multmatrix(m): applies a 4x4 (or 3x4) matrix to the children",
    },
    BuiltinModule {
        name: "resize",
        params: &[
            pos("newsize", P::NumberOrVector(VEC23)),
            pos("auto", P::BoolOrVector),
            named("convexity", P::Number),
        ],
        variadic: false,
        kind: ModuleKind::Transform,
        doc: "resize(newsize, auto = false): scales the children to the given bounding-box size",
    },
    BuiltinModule {
        name: "color",
        params: &[
            pos("c", P::StringOrVector(&[3, 4])),
            pos("alpha", P::Number),
        ],
        variadic: false,
        kind: ModuleKind::Other,
        doc: "color(c, alpha = 1): colours the children (a name, \"#rrggbb\" or [r, g, b, a]); no effect on geometry",
    },
    BuiltinModule {
        name: "group",
        params: &[],
        variadic: false,
        kind: ModuleKind::Boolean,
        doc: "group(): OpenSCAD's internal name of union(): everything inside any child",
    },
    BuiltinModule {
        name: "union",
        params: &[],
        variadic: false,
        kind: ModuleKind::Boolean,
        doc: "union(): everything inside any child",
    },
    BuiltinModule {
        name: "intersection",
        params: &[],
        variadic: false,
        kind: ModuleKind::Boolean,
        doc: "intersection(): what is inside every child",
    },
    BuiltinModule {
        name: "difference",
        params: &[],
        variadic: false,
        kind: ModuleKind::Boolean,
        doc: "difference(): the first child minus all the others",
    },
    BuiltinModule {
        name: "complement",
        params: &[],
        variadic: false,
        kind: ModuleKind::Boolean,
        doc: "complement(): everything outside the children (must end up bounded)",
    },
    BuiltinModule {
        name: "intersection_for",
        params: &[],
        variadic: true,
        kind: ModuleKind::Boolean,
        doc: "intersection_for(i = range): the intersection of the child over every iteration",
    },
    BuiltinModule {
        name: "render",
        params: &[pos("convexity", P::Number)],
        variadic: false,
        kind: ModuleKind::Other,
        doc: "render(): accepted and passed through",
    },
    BuiltinModule {
        name: "children",
        params: &[pos("index", P::Selection)],
        variadic: false,
        kind: ModuleKind::Other,
        doc: "children(), children(i), children([i, j]): the children of the current module instance",
    },
    BuiltinModule {
        name: "child",
        params: &[pos("index", P::Any)],
        variadic: false,
        kind: ModuleKind::Other,
        doc: "child(i): deprecated OpenSCAD name of children(i); child() is children(0)",
    },
    BuiltinModule {
        name: "assign",
        params: &[],
        variadic: true,
        kind: ModuleKind::Other,
        doc: "assign(a = 1, b = 2): deprecated OpenSCAD form of let; every value is computed in the enclosing scope, then bound for the child",
    },
    BuiltinModule {
        name: "echo",
        params: &[],
        variadic: true,
        kind: ModuleKind::Other,
        doc: "echo(…): prints its arguments",
    },
    BuiltinModule {
        name: "assert",
        params: &[req("condition", P::Any), pos("message", P::Any)],
        variadic: false,
        kind: ModuleKind::Other,
        doc: "assert(condition, message): stops with an error when condition is false",
    },
];

const NUM: &[BuiltinParam] = &[req("x", P::Number)];

const fn math(name: &'static str, doc: &'static str) -> BuiltinFunction {
    BuiltinFunction {
        name,
        params: NUM,
        rest: None,
        min_args: 1,
        returns: Returns::Number,
        doc,
    }
}

const ANY_X: &[BuiltinParam] = &[req("x", P::Any)];

const fn predicate(name: &'static str, doc: &'static str) -> BuiltinFunction {
    BuiltinFunction {
        name,
        params: ANY_X,
        rest: None,
        min_args: 1,
        returns: Returns::Bool,
        doc,
    }
}

/// Every built-in function.
pub const FUNCTIONS: &[BuiltinFunction] = &[
    math("abs", "abs(x): absolute value"),
    math("sign", "sign(x): -1, 0 or 1"),
    math("sin", "sin(x): sine of x degrees"),
    math("cos", "cos(x): cosine of x degrees"),
    math("tan", "tan(x): tangent of x degrees"),
    math("asin", "asin(x): arc sine in degrees"),
    math("acos", "acos(x): arc cosine in degrees"),
    math("atan", "atan(x): arc tangent in degrees"),
    BuiltinFunction {
        name: "atan2",
        params: &[req("y", P::Number), req("x", P::Number)],
        rest: None,
        min_args: 2,
        returns: Returns::Number,
        doc: "atan2(y, x): angle of (x, y) in degrees",
    },
    math("floor", "floor(x): largest integer <= x"),
    math("ceil", "ceil(x): smallest integer >= x"),
    math("round", "round(x): nearest integer, halves away from zero"),
    math("ln", "ln(x): natural logarithm"),
    BuiltinFunction {
        name: "log",
        params: &[req("x", P::Number), pos("y", P::Number)],
        rest: None,
        min_args: 1,
        returns: Returns::Number,
        doc: "log(x): base-10 logarithm; log(b, x): base-b logarithm",
    },
    math("exp", "exp(x): e to the power x"),
    BuiltinFunction {
        name: "pow",
        params: &[req("base", P::Number), req("exponent", P::Number)],
        rest: None,
        min_args: 2,
        returns: Returns::Number,
        doc: "pow(base, exponent)",
    },
    math("sqrt", "sqrt(x): square root"),
    BuiltinFunction {
        name: "min",
        params: &[],
        rest: Some(P::NumberOrVector(&[])),
        min_args: 1,
        returns: Returns::Number,
        doc: "min(a, b, …) or min(v): the smallest value",
    },
    BuiltinFunction {
        name: "max",
        params: &[],
        rest: Some(P::NumberOrVector(&[])),
        min_args: 1,
        returns: Returns::Number,
        doc: "max(a, b, …) or max(v): the largest value",
    },
    BuiltinFunction {
        name: "norm",
        params: &[req("v", P::NumberVector(&[]))],
        rest: None,
        min_args: 1,
        returns: Returns::Number,
        doc: "norm(v): Euclidean length of a vector",
    },
    BuiltinFunction {
        name: "cross",
        params: &[
            req("a", P::NumberVector(VEC23)),
            req("b", P::NumberVector(VEC23)),
        ],
        rest: None,
        min_args: 2,
        returns: Returns::Any,
        doc: "cross(a, b): cross product of two 3-vectors (a number for two 2-vectors)",
    },
    BuiltinFunction {
        name: "len",
        params: &[req("v", P::StringOrList)],
        rest: None,
        min_args: 1,
        returns: Returns::Number,
        doc: "len(v): number of elements of a vector or characters of a string",
    },
    BuiltinFunction {
        name: "concat",
        params: &[],
        rest: Some(P::Any),
        min_args: 0,
        returns: Returns::Vector,
        doc: "concat(a, b, …): the vectors joined (non-vectors count as one element)",
    },
    BuiltinFunction {
        name: "lookup",
        params: &[req("key", P::Number), req("table", P::List(&[]))],
        rest: None,
        min_args: 2,
        returns: Returns::Number,
        doc: "lookup(key, [[k, v], …]): linear interpolation in a table",
    },
    BuiltinFunction {
        name: "str",
        params: &[],
        rest: Some(P::Any),
        min_args: 0,
        returns: Returns::String,
        doc: "str(a, b, …): the values converted to text and joined",
    },
    BuiltinFunction {
        name: "chr",
        params: &[],
        rest: Some(P::Any),
        min_args: 1,
        returns: Returns::String,
        doc: "chr(code, …): the characters with these Unicode code points",
    },
    BuiltinFunction {
        name: "ord",
        params: &[req("c", P::String)],
        rest: None,
        min_args: 1,
        returns: Returns::Number,
        doc: "ord(c): the Unicode code point of a one-character string",
    },
    BuiltinFunction {
        name: "search",
        params: &[
            req("match_value", P::Any),
            req("string_or_vector", P::StringOrList),
            pos("num_returns_per_match", P::Number),
            pos("index_col_num", P::Number),
        ],
        rest: None,
        min_args: 2,
        returns: Returns::Vector,
        doc: "search(match_value, string_or_vector, num_returns_per_match = 1, index_col_num = 0)",
    },
    predicate("is_undef", "is_undef(x): whether x is undef"),
    predicate("is_bool", "is_bool(x): whether x is a boolean"),
    predicate("is_num", "is_num(x): whether x is a number"),
    predicate("is_string", "is_string(x): whether x is a string"),
    predicate("is_list", "is_list(x): whether x is a vector"),
    predicate("is_function", "is_function(x): whether x is a function"),
    BuiltinFunction {
        name: "rands",
        params: &[
            req("min_value", P::Number),
            req("max_value", P::Number),
            req("value_count", P::Number),
            pos("seed_value", P::Number),
        ],
        rest: None,
        min_args: 3,
        returns: Returns::Vector,
        doc: "rands(min, max, n, seed): n pseudo-random numbers, deterministic given a seed",
    },
    BuiltinFunction {
        name: "version",
        params: &[],
        rest: None,
        min_args: 0,
        returns: Returns::Vector3,
        doc: "version(): [2021, 1, 0], the OpenSCAD release whose semantics qcsg follows",
    },
    BuiltinFunction {
        name: "version_num",
        params: &[],
        rest: None,
        min_args: 0,
        returns: Returns::Number,
        doc: "version_num(): 20210100, the OpenSCAD release whose semantics qcsg follows",
    },
    BuiltinFunction {
        name: "parent_module",
        params: &[pos("n", P::Number)],
        rest: None,
        min_args: 0,
        returns: Returns::String,
        doc: "parent_module(n = 1): the name of the n-th enclosing module instantiation (0: the current one)",
    },
    BuiltinFunction {
        name: "dxf_dim",
        params: &[
            named("file", P::String),
            named("layer", P::String),
            named("name", P::String),
            named("origin", P::NumberVector(&[2])),
            named("scale", P::Number),
        ],
        rest: None,
        min_args: 1,
        returns: Returns::Number,
        doc: "dxf_dim(file, layer, name, origin, scale): the measure of the DXF drawing's dimension `name` (undef when absent)",
    },
    BuiltinFunction {
        name: "dxf_cross",
        params: &[
            named("file", P::String),
            named("layer", P::String),
            named("origin", P::NumberVector(&[2])),
            named("scale", P::Number),
        ],
        rest: None,
        min_args: 1,
        returns: Returns::Vector,
        doc: "dxf_cross(file, layer, origin, scale): where the first two lines of the DXF drawing's layer cross (undef when they do not)",
    },
];

/// Built-in special variables: never undefined.
pub const SPECIAL_VARIABLES: &[(&str, &str)] = &[
    ("$fn", "number of fragments (no effect: surfaces are exact)"),
    (
        "$fa",
        "minimum fragment angle (no effect: surfaces are exact)",
    ),
    (
        "$fs",
        "minimum fragment size (no effect: surfaces are exact)",
    ),
    ("$t", "animation time in [0, 1)"),
    (
        "$children",
        "number of children of the current module instance",
    ),
    (
        "$preview",
        "whether the scene is being previewed rather than rendered",
    ),
    ("$vpr", "viewport rotation"),
    ("$vpt", "viewport translation"),
    ("$vpd", "viewport camera distance"),
    ("$vpf", "viewport field of view"),
    (
        "$parent_modules",
        "number of modules in the instantiation stack",
    ),
];

/// Built-in ordinary variables.
pub const VARIABLES: &[(&str, &str, Ty)] = &[("PI", "the constant π", Ty::Number)];

/// An OpenSCAD construct that the language rejects.
#[derive(Clone, Copy, Debug)]
pub struct Unsupported {
    /// Its name.
    pub name: &'static str,
    /// Why it cannot be represented.
    pub reason: &'static str,
    /// What to use instead, where there is something.
    pub instead: Option<&'static str>,
}

/// OpenSCAD modules with no exact quadric representation.
pub const UNSUPPORTED_MODULES: &[Unsupported] = &[];

/// OpenSCAD built-in functions the language does not provide.
pub const UNSUPPORTED_FUNCTIONS: &[Unsupported] = &[];

/// The built-in module called `name`.
pub fn module(name: &str) -> Option<&'static BuiltinModule> {
    MODULES.iter().find(|m| m.name == name)
}

/// The built-in function called `name`.
pub fn function(name: &str) -> Option<&'static BuiltinFunction> {
    FUNCTIONS.iter().find(|f| f.name == name)
}

/// The rejected OpenSCAD module called `name`.
pub fn unsupported_module(name: &str) -> Option<&'static Unsupported> {
    UNSUPPORTED_MODULES.iter().find(|m| m.name == name)
}

/// The rejected OpenSCAD function called `name`.
pub fn unsupported_function(name: &str) -> Option<&'static Unsupported> {
    UNSUPPORTED_FUNCTIONS.iter().find(|f| f.name == name)
}

/// Whether `$name` is a built-in special variable.
pub fn is_special_variable(name: &str) -> bool {
    SPECIAL_VARIABLES.iter().any(|(n, _)| *n == name)
}

/// The built-in ordinary variable called `name` and its type.
pub fn variable(name: &str) -> Option<&'static Ty> {
    VARIABLES
        .iter()
        .find(|(n, _, _)| *n == name)
        .map(|(_, _, ty)| ty)
}

/// Whether `name` is one of the tessellation variables that have no effect on exact surfaces.
pub fn is_tessellation_variable(name: &str) -> bool {
    matches!(name, "$fn" | "$fa" | "$fs")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_across_tables() {
        let mut names = std::collections::HashSet::new();
        for name in MODULES
            .iter()
            .map(|m| m.name)
            .chain(UNSUPPORTED_MODULES.iter().map(|m| m.name))
        {
            assert!(names.insert(name), "module {name} listed twice");
        }
        let mut names = std::collections::HashSet::new();
        for name in FUNCTIONS
            .iter()
            .map(|f| f.name)
            .chain(UNSUPPORTED_FUNCTIONS.iter().map(|f| f.name))
        {
            assert!(names.insert(name), "function {name} listed twice");
        }
    }

    #[test]
    fn openscad_positional_orders() {
        let names = |m: &BuiltinModule| {
            m.params
                .iter()
                .filter(|p| p.positional)
                .map(|p| p.name)
                .collect::<Vec<_>>()
        };
        assert_eq!(
            names(module("cylinder").unwrap()),
            ["h", "r1", "r2", "center"]
        );
        assert_eq!(names(module("sphere").unwrap()), ["r"]);
        assert_eq!(names(module("cube").unwrap()), ["size", "center"]);
        for f in FUNCTIONS {
            let required = f.params.iter().filter(|p| p.required).count();
            assert!(f.min_args >= required, "{}", f.name);
        }
    }
}
