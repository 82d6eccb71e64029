//! Values of constant expressions, for hover and inlay hints.
//!
//! This is not the evaluator: it folds literals, arithmetic, vectors and references to other
//! constant variables, and gives up (returns `None`) on anything else, within a small budget so
//! that hover and inlay hints stay cheap on large files.
//!
//! It has its own small [`Value`] rather than the evaluator's: the editor layer depends on syntax
//! and sema only (the layering test in `qcsg-driver` holds it to that), and a hover needs none of
//! the evaluator's ranges, function values or shared, scope-bound storage.

use std::fmt;

use qcsg_sema::{DefId, DefKind, Target};
use qcsg_syntax::ast::{BinaryOp, Expr, ExprKind, ListElemKind, StmtKind, UnaryOp};

use crate::Analysis;
use crate::walk::{Node, walk};

/// How many references to other variables one evaluation may follow.
const MAX_DEPTH: usize = 16;
/// The longest vector shown.
const MAX_VECTOR: usize = 64;

/// A constant value.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Value {
    Number(f64),
    Bool(bool),
    String(String),
    Undef,
    Vector(Vec<Value>),
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Number(x) => f.write_str(&format_number(*x)),
            Value::Bool(b) => write!(f, "{b}"),
            Value::String(s) => write!(f, "{s:?}"),
            Value::Undef => f.write_str("undef"),
            Value::Vector(items) => {
                f.write_str("[")?;
                for (i, item) in items.iter().enumerate() {
                    if i > 0 {
                        f.write_str(", ")?;
                    }
                    write!(f, "{item}")?;
                }
                f.write_str("]")
            }
        }
    }
}

/// A number as people write it: integers without a fraction, at most ten decimals.
pub(crate) fn format_number(x: f64) -> String {
    if !x.is_finite() {
        return if x.is_nan() {
            "nan".into()
        } else if x > 0.0 {
            "inf".into()
        } else {
            "-inf".into()
        };
    }
    if x == 0.0 {
        return "0".into();
    }
    if !(1e-4..1e15).contains(&x.abs()) {
        return format!("{x:e}");
    }
    let text = format!("{x:.10}");
    let text = text.trim_end_matches('0').trim_end_matches('.');
    if text == "-0" {
        "0".into()
    } else {
        text.into()
    }
}

impl Analysis {
    /// The value of a variable whose assignment is a constant expression.
    pub(crate) fn constant_value(&self, id: DefId) -> Option<Value> {
        self.constant_value_at_depth(id, 0)
    }

    fn constant_value_at_depth(&self, id: DefId, depth: usize) -> Option<Value> {
        let definition = self.sema.definition(id)?;
        if definition.kind != DefKind::Variable || depth > MAX_DEPTH {
            return None;
        }
        let tree = self.sema.tree(definition.file)?;
        let mut value_expr = None;
        // Top-level assignments are found without a walk; nested ones need one.
        for stmt in &tree.stmts {
            if let StmtKind::Assign { name, value } = &stmt.kind
                && name.span == definition.name_span
            {
                value_expr = Some(value);
            }
        }
        if value_expr.is_none() {
            walk(tree, &mut |node| {
                if let Node::Stmt(stmt) = node
                    && let StmtKind::Assign { name, value } = &stmt.kind
                    && name.span == definition.name_span
                {
                    value_expr = Some(value);
                }
            });
        }
        Evaluator {
            analysis: self,
            file: definition.file,
            depth,
        }
        .eval(value_expr?)
    }
}

struct Evaluator<'a> {
    analysis: &'a Analysis,
    file: qcsg_diag::FileId,
    depth: usize,
}

impl Evaluator<'_> {
    fn eval(&self, expr: &Expr) -> Option<Value> {
        Some(match &expr.kind {
            ExprKind::Number(x) => Value::Number(*x),
            ExprKind::String(s) => Value::String(s.clone()),
            ExprKind::Bool(b) => Value::Bool(*b),
            ExprKind::Undef => Value::Undef,
            ExprKind::Paren(inner) => self.eval(inner)?,
            ExprKind::Ident(ident) => {
                let reference = self
                    .analysis
                    .sema
                    .reference_at(self.file, ident.span.start as usize)?;
                match reference.target {
                    Target::Definition(id) => {
                        self.analysis.constant_value_at_depth(id, self.depth + 1)?
                    }
                    Target::Builtin if ident.name == "PI" => Value::Number(std::f64::consts::PI),
                    _ => return None,
                }
            }
            ExprKind::Unary { op, operand, .. } => match (op, self.eval(operand)?) {
                (UnaryOp::Not, Value::Bool(b)) => Value::Bool(!b),
                (UnaryOp::Plus, Value::Number(x)) => Value::Number(x),
                (UnaryOp::Neg, value) => negate(value)?,
                _ => return None,
            },
            ExprKind::Binary { op, lhs, rhs, .. } => binary(*op, self.eval(lhs)?, self.eval(rhs)?)?,
            ExprKind::Ternary { cond, then, els } => match self.eval(cond)? {
                Value::Bool(true) => self.eval(then)?,
                Value::Bool(false) => self.eval(els)?,
                _ => return None,
            },
            ExprKind::Index { base, index } => match (self.eval(base)?, self.eval(index)?) {
                (Value::Vector(items), Value::Number(i)) if i >= 0.0 => {
                    items.get(i as usize).cloned().unwrap_or(Value::Undef)
                }
                _ => return None,
            },
            ExprKind::Member { base, member } => {
                let index = ["x", "y", "z"].iter().position(|m| *m == member.name)?;
                match self.eval(base)? {
                    Value::Vector(items) => items.get(index).cloned().unwrap_or(Value::Undef),
                    _ => return None,
                }
            }
            ExprKind::Vector(elems) if elems.len() <= MAX_VECTOR => {
                let mut items = Vec::with_capacity(elems.len());
                for elem in elems {
                    match &elem.kind {
                        ListElemKind::Expr(expr) => items.push(self.eval(expr)?),
                        _ => return None,
                    }
                }
                Value::Vector(items)
            }
            ExprKind::Call { callee, args, .. } => {
                let ExprKind::Ident(name) = &callee.kind else {
                    return None;
                };
                let reference = self
                    .analysis
                    .sema
                    .reference_at(self.file, name.span.start as usize)?;
                if reference.target != Target::Builtin || args.iter().any(|a| a.name.is_some()) {
                    return None;
                }
                let mut numbers = Vec::with_capacity(args.len());
                for arg in args {
                    match self.eval(&arg.value)? {
                        Value::Number(x) => numbers.push(x),
                        _ => return None,
                    }
                }
                Value::Number(math(&name.name, &numbers)?)
            }
            _ => return None,
        })
    }
}

fn negate(value: Value) -> Option<Value> {
    match value {
        Value::Number(x) => Some(Value::Number(-x)),
        Value::Vector(items) => items
            .into_iter()
            .map(negate)
            .collect::<Option<_>>()
            .map(Value::Vector),
        _ => None,
    }
}

fn binary(op: BinaryOp, lhs: Value, rhs: Value) -> Option<Value> {
    use BinaryOp::*;
    use Value::{Bool, Number, Vector};
    Some(match (op, lhs, rhs) {
        (Add, Number(a), Number(b)) => Number(a + b),
        (Sub, Number(a), Number(b)) => Number(a - b),
        (Mul, Number(a), Number(b)) => Number(a * b),
        (Div, Number(a), Number(b)) => Number(a / b),
        (Rem, Number(a), Number(b)) => Number(a % b),
        (Pow, Number(a), Number(b)) => Number(a.powf(b)),
        (Lt, Number(a), Number(b)) => Bool(a < b),
        (Le, Number(a), Number(b)) => Bool(a <= b),
        (Gt, Number(a), Number(b)) => Bool(a > b),
        (Ge, Number(a), Number(b)) => Bool(a >= b),
        (Eq, a, b) => Bool(a == b),
        (Ne, a, b) => Bool(a != b),
        (And, Bool(a), Bool(b)) => Bool(a && b),
        (Or, Bool(a), Bool(b)) => Bool(a || b),
        (Add | Sub, Vector(a), Vector(b)) if a.len() == b.len() => Vector(
            a.into_iter()
                .zip(b)
                .map(|(x, y)| binary(op, x, y))
                .collect::<Option<_>>()?,
        ),
        (Mul | Div, Vector(a), Number(k)) => Vector(
            a.into_iter()
                .map(|x| binary(op, x, Number(k)))
                .collect::<Option<_>>()?,
        ),
        (Mul, Number(k), Vector(a)) => Vector(
            a.into_iter()
                .map(|x| binary(op, Number(k), x))
                .collect::<Option<_>>()?,
        ),
        _ => return None,
    })
}

/// The built-in math functions worth folding, in degrees as the language defines them.
fn math(name: &str, args: &[f64]) -> Option<f64> {
    let degrees = |x: f64| x.to_radians();
    Some(match (name, args) {
        ("abs", [x]) => x.abs(),
        ("sqrt", [x]) => x.sqrt(),
        ("sin", [x]) => exact_trig(*x).map_or_else(|| degrees(*x).sin(), |(s, _)| s),
        ("cos", [x]) => exact_trig(*x).map_or_else(|| degrees(*x).cos(), |(_, c)| c),
        ("tan", [x]) => degrees(*x).tan(),
        ("floor", [x]) => x.floor(),
        ("ceil", [x]) => x.ceil(),
        ("round", [x]) => x.round(),
        ("pow", [x, y]) => x.powf(*y),
        ("min", [_, ..]) => args.iter().copied().fold(f64::INFINITY, f64::min),
        ("max", [_, ..]) => args.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        _ => return None,
    })
}

/// Sine and cosine of multiples of 90°, exactly.
fn exact_trig(degrees: f64) -> Option<(f64, f64)> {
    if degrees % 90.0 != 0.0 {
        return None;
    }
    Some(match (degrees / 90.0).rem_euclid(4.0) as u8 {
        0 => (0.0, 1.0),
        1 => (1.0, 0.0),
        2 => (0.0, -1.0),
        _ => (-1.0, 0.0),
    })
}
