//! The abstract syntax tree of a `.qcsg` / `.scad` file.
//!
//! Every node carries the byte [`Span`] of the source it came from. Parsing never fails: where the
//! source is broken the tree holds [`StmtKind::Error`] / [`ExprKind::Error`] nodes and the parser
//! reports diagnostics, so the language server always has a tree to work on.
//!
//! The shape follows OpenSCAD's grammar. `for` and `let` are keywords and get their own statement
//! kinds; `intersection_for`, `echo`, `assert`, `children` and every primitive or transform are
//! ordinary module instantiations ([`StmtKind::Instantiate`]) that name resolution recognises.

pub use qcsg_diag::Span;

/// A whole source file.
#[derive(Clone, Debug, PartialEq)]
pub struct SourceFile {
    /// Top-level statements in source order.
    pub stmts: Vec<Stmt>,
    /// Every comment of the file in source order, doc comments included (for formatting,
    /// folding and semantic tokens).
    pub comments: Vec<Comment>,
}

/// A comment kept by the lexer.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Comment {
    /// What kind of comment it is.
    pub kind: CommentKind,
    /// The whole comment including its delimiters.
    pub span: Span,
}

/// The four kinds of comment.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CommentKind {
    /// `// …`
    Line,
    /// `/* … */`
    Block,
    /// `/// …` (a doc comment when it directly precedes a definition or assignment)
    DocLine,
    /// `/** … */`
    DocBlock,
}

/// An identifier occurrence: a plain name or a `$`-variable such as `$fn`.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Ident {
    /// The name as written, including a leading `$`.
    pub name: String,
    /// Where it is written.
    pub span: Span,
}

impl Ident {
    /// Whether this is a dynamically scoped special variable (`$fn`, `$children`, …).
    pub fn is_special(&self) -> bool {
        self.name.starts_with('$')
    }
}

/// The doc comment attached to a definition or assignment, with the comment markers stripped.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Doc {
    /// The text, lines joined with `\n`, markers (`///`, `/**`, `*/`, leading ` * `) removed.
    pub text: String,
    /// The span of the comment(s) it came from.
    pub span: Span,
}

/// A statement.
#[derive(Clone, Debug, PartialEq)]
pub struct Stmt {
    /// What statement it is.
    pub kind: StmtKind,
    /// The whole statement, including a trailing `;`, modifiers and doc comment excluded.
    pub span: Span,
    /// The doc comment right before it (only for assignments and definitions).
    pub doc: Option<Doc>,
}

/// The statement forms (docs/language.md, "Statements").
#[derive(Clone, Debug, PartialEq)]
pub enum StmtKind {
    /// A lone `;`.
    Empty,
    /// `name = value;`
    Assign {
        /// The assigned variable.
        name: Ident,
        /// Its value.
        value: Expr,
    },
    /// `module name(params) body`
    ModuleDef {
        /// The module's name.
        name: Ident,
        /// Its parameters.
        params: Vec<Param>,
        /// Its body (usually a block).
        body: Box<Stmt>,
    },
    /// `function name(params) = body;`
    FunctionDef {
        /// The function's name.
        name: Ident,
        /// Its parameters.
        params: Vec<Param>,
        /// The expression it returns.
        body: Expr,
    },
    /// `{ stmts }`
    Block(Vec<Stmt>),
    /// `if (cond) then else els`
    If {
        /// The condition.
        cond: Expr,
        /// The statement run when it holds.
        then: Box<Stmt>,
        /// The `else` branch, if any.
        els: Option<Box<Stmt>>,
    },
    /// `for (a = r, b = s) body` — the nested loop over every binding, outermost first.
    For {
        /// The loop variables and what they iterate over.
        bindings: Vec<Binding>,
        /// The loop body.
        body: Box<Stmt>,
    },
    /// `let (a = 1, b = a + 1) body` — sequential bindings visible in `body`.
    Let {
        /// The bindings, in order.
        bindings: Vec<Binding>,
        /// The statement they scope over.
        body: Box<Stmt>,
    },
    /// `name(args) child` or `name(args);` — a module instantiation (primitives, transforms,
    /// `children`, `echo`, `assert`, `intersection_for` and user modules alike).
    Instantiate {
        /// The module's name.
        name: Ident,
        /// The call's arguments.
        args: Vec<Arg>,
        /// The span of the parenthesised argument list, parentheses included.
        args_span: Span,
        /// The child statement; `None` when the instantiation ends in `;`.
        child: Option<Box<Stmt>>,
    },
    /// A modifier in front of a statement: `*`, `!`, `#` or `%`. Several modifiers nest.
    Modified {
        /// Which modifier.
        modifier: Modifier,
        /// The span of the modifier character.
        modifier_span: Span,
        /// The modified statement.
        body: Box<Stmt>,
    },
    /// `include <path>`
    Include(PathLit),
    /// `use <path>`
    Use(PathLit),
    /// A statement the parser could not make sense of (its diagnostic has been reported).
    Error,
}

/// A statement modifier.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Modifier {
    /// `*`: disable the subtree.
    Disable,
    /// `!`: show only this subtree.
    ShowOnly,
    /// `#`: highlight (still part of the solid).
    Highlight,
    /// `%`: background (shown translucent, not part of the solid).
    Background,
}

impl Modifier {
    /// The modifier's character.
    pub fn as_char(self) -> char {
        match self {
            Modifier::Disable => '*',
            Modifier::ShowOnly => '!',
            Modifier::Highlight => '#',
            Modifier::Background => '%',
        }
    }
}

/// The `<path>` of an `include` or `use`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PathLit {
    /// The path between the angle brackets, as written.
    pub path: String,
    /// The span of `<path>`, brackets included.
    pub span: Span,
}

/// A parameter of a module, function or function literal: `name` or `name = default`.
#[derive(Clone, Debug, PartialEq)]
pub struct Param {
    /// The parameter's name.
    pub name: Ident,
    /// Its default value.
    pub default: Option<Expr>,
    /// The whole parameter.
    pub span: Span,
}

/// A call argument: positional `value` or named `name = value`.
#[derive(Clone, Debug, PartialEq)]
pub struct Arg {
    /// The name of a named argument.
    pub name: Option<Ident>,
    /// The argument's value.
    pub value: Expr,
    /// The whole argument.
    pub span: Span,
}

/// `name = value` in `for`, `let` and comprehension heads.
#[derive(Clone, Debug, PartialEq)]
pub struct Binding {
    /// The bound name.
    pub name: Ident,
    /// Its value (the iterated range or vector in a `for`).
    pub value: Expr,
    /// The whole binding.
    pub span: Span,
}

/// An expression.
#[derive(Clone, Debug, PartialEq)]
pub struct Expr {
    /// What expression it is.
    pub kind: ExprKind,
    /// The whole expression.
    pub span: Span,
}

/// The expression forms (docs/language.md, "Expressions").
#[derive(Clone, Debug, PartialEq)]
pub enum ExprKind {
    /// A number literal.
    Number(f64),
    /// A string literal with escapes already decoded.
    String(String),
    /// `true` or `false`.
    Bool(bool),
    /// `undef`.
    Undef,
    /// A variable reference (or the name of a function being called, see [`ExprKind::Call`]).
    Ident(Ident),
    /// `( inner )`, kept so that the formatter and hover see what was written.
    Paren(Box<Expr>),
    /// `op operand`.
    Unary {
        /// The operator.
        op: UnaryOp,
        /// The operator's span.
        op_span: Span,
        /// The operand.
        operand: Box<Expr>,
    },
    /// `lhs op rhs`.
    Binary {
        /// The operator.
        op: BinaryOp,
        /// The operator's span.
        op_span: Span,
        /// The left operand.
        lhs: Box<Expr>,
        /// The right operand.
        rhs: Box<Expr>,
    },
    /// `cond ? then : els`.
    Ternary {
        /// The condition.
        cond: Box<Expr>,
        /// The value when it holds.
        then: Box<Expr>,
        /// The value otherwise.
        els: Box<Expr>,
    },
    /// `callee(args)`; the callee is usually an [`ExprKind::Ident`] naming a function.
    Call {
        /// What is called.
        callee: Box<Expr>,
        /// The arguments.
        args: Vec<Arg>,
        /// The span of the parenthesised argument list, parentheses included.
        args_span: Span,
    },
    /// `base[index]`.
    Index {
        /// The indexed value.
        base: Box<Expr>,
        /// The index.
        index: Box<Expr>,
    },
    /// `base.x`, `base.y`, `base.z` (any identifier parses; checking restricts it).
    Member {
        /// The value.
        base: Box<Expr>,
        /// The member name.
        member: Ident,
    },
    /// `[a, b, for (…) …, each …]`: a vector, possibly with comprehension elements.
    Vector(Vec<ListElem>),
    /// `[start : end]` or `[start : step : end]`.
    Range {
        /// First value.
        start: Box<Expr>,
        /// Step (1 when absent).
        step: Option<Box<Expr>>,
        /// Last value (inclusive).
        end: Box<Expr>,
    },
    /// `let (a = 1) body`.
    Let {
        /// The bindings, in order.
        bindings: Vec<Binding>,
        /// The value.
        body: Box<Expr>,
    },
    /// `assert(args) body` (the body may be absent, as in OpenSCAD).
    Assert {
        /// Condition and optional message.
        args: Vec<Arg>,
        /// The span of the argument list, parentheses included.
        args_span: Span,
        /// The value.
        body: Option<Box<Expr>>,
    },
    /// `echo(args) body` (the body may be absent, as in OpenSCAD).
    Echo {
        /// What to print.
        args: Vec<Arg>,
        /// The span of the argument list, parentheses included.
        args_span: Span,
        /// The value.
        body: Option<Box<Expr>>,
    },
    /// `function (params) body`.
    FunctionLit {
        /// The parameters.
        params: Vec<Param>,
        /// The returned expression.
        body: Box<Expr>,
    },
    /// An expression the parser could not make sense of (its diagnostic has been reported).
    Error,
}

/// An element of a vector literal or list comprehension.
#[derive(Clone, Debug, PartialEq)]
pub struct ListElem {
    /// What element it is.
    pub kind: ListElemKind,
    /// The whole element.
    pub span: Span,
}

/// The element forms of a vector literal or list comprehension.
#[derive(Clone, Debug, PartialEq)]
pub enum ListElemKind {
    /// A plain value.
    Expr(Expr),
    /// `for (a = r, b = s) body`: one element per iteration.
    For {
        /// The loop variables.
        bindings: Vec<Binding>,
        /// The element generated per iteration.
        body: Box<ListElem>,
    },
    /// `for (init; cond; update) body`: the C-style generator.
    CFor {
        /// Initial bindings.
        init: Vec<Binding>,
        /// Loop condition.
        cond: Expr,
        /// Bindings evaluated after each iteration.
        update: Vec<Binding>,
        /// The element generated per iteration.
        body: Box<ListElem>,
    },
    /// `if (cond) then else els`.
    If {
        /// The condition.
        cond: Expr,
        /// The element when it holds.
        then: Box<ListElem>,
        /// The element otherwise.
        els: Option<Box<ListElem>>,
    },
    /// `each value`: splices a vector or range.
    Each(Box<ListElem>),
    /// `let (a = 1) body`.
    Let {
        /// The bindings.
        bindings: Vec<Binding>,
        /// The element.
        body: Box<ListElem>,
    },
    /// `( elem )` around a comprehension element.
    Paren(Box<ListElem>),
}

/// Prefix operators.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum UnaryOp {
    /// `!`
    Not,
    /// `-`
    Neg,
    /// `+`
    Plus,
}

/// Infix operators, lowest precedence first.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BinaryOp {
    /// `||`
    Or,
    /// `&&`
    And,
    /// `==`
    Eq,
    /// `!=`
    Ne,
    /// `<`
    Lt,
    /// `<=`
    Le,
    /// `>`
    Gt,
    /// `>=`
    Ge,
    /// `+`
    Add,
    /// `-`
    Sub,
    /// `*`
    Mul,
    /// `/`
    Div,
    /// `%`
    Rem,
    /// `^` (right-associative)
    Pow,
}

impl BinaryOp {
    /// The operator as written.
    pub fn as_str(self) -> &'static str {
        use BinaryOp::*;
        match self {
            Or => "||",
            And => "&&",
            Eq => "==",
            Ne => "!=",
            Lt => "<",
            Le => "<=",
            Gt => ">",
            Ge => ">=",
            Add => "+",
            Sub => "-",
            Mul => "*",
            Div => "/",
            Rem => "%",
            Pow => "^",
        }
    }
}
