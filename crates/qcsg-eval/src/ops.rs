//! OpenSCAD's operators on values.
//!
//! Where OpenSCAD 2021.01 returns `undef` with an "undefined operation" warning, these return an
//! error message instead (the evaluator reports it at the operator's span). Vector arithmetic is
//! elementwise over the shorter length, `*` between vectors is the dot product, vector × matrix,
//! matrix × vector or matrix × matrix, as in OpenSCAD.

use std::cmp::Ordering;

use qcsg_syntax::ast::{BinaryOp, UnaryOp};

use crate::value::{Value, values_equal};

/// The result of an operator: a value, or why OpenSCAD would give `undef`.
pub type OpResult<'a> = Result<Value<'a>, String>;

fn undefined_operation<'a>(op: &str, a: &Value<'a>, b: &Value<'a>) -> OpResult<'a> {
    Err(format!(
        "undefined operation ({} {op} {})",
        a.type_name(),
        b.type_name()
    ))
}

/// `op operand`.
pub fn unary<'a>(op: UnaryOp, v: &Value<'a>) -> OpResult<'a> {
    match op {
        UnaryOp::Not => Ok(Value::Bool(!v.truthy())),
        UnaryOp::Neg => negate(v),
        UnaryOp::Plus => match v {
            Value::Number(_) | Value::Vector(_) => Ok(v.clone()),
            other => Err(format!("undefined operation (+{})", other.type_name())),
        },
    }
}

fn negate<'a>(v: &Value<'a>) -> OpResult<'a> {
    match v {
        Value::Number(x) => Ok(Value::Number(-x)),
        Value::Vector(items) => Ok(Value::vector(
            items.iter().map(negate).collect::<Result<_, _>>()?,
        )),
        other => Err(format!("undefined operation (-{})", other.type_name())),
    }
}

/// `lhs op rhs` for every operator except the short-circuiting `&&` and `||`.
pub fn binary<'a>(op: BinaryOp, a: &Value<'a>, b: &Value<'a>) -> OpResult<'a> {
    match op {
        BinaryOp::Or => Ok(Value::Bool(a.truthy() || b.truthy())),
        BinaryOp::And => Ok(Value::Bool(a.truthy() && b.truthy())),
        BinaryOp::Eq => Ok(Value::Bool(values_equal(a, b))),
        BinaryOp::Ne => Ok(Value::Bool(!values_equal(a, b))),
        BinaryOp::Lt | BinaryOp::Le | BinaryOp::Gt | BinaryOp::Ge => {
            let ord = compare(a, b).ok_or_else(|| {
                format!(
                    "undefined operation ({} {} {})",
                    a.type_name(),
                    op.as_str(),
                    b.type_name()
                )
            })?;
            Ok(Value::Bool(match op {
                BinaryOp::Lt => ord == Some(Ordering::Less),
                BinaryOp::Le => matches!(ord, Some(Ordering::Less | Ordering::Equal)),
                BinaryOp::Gt => ord == Some(Ordering::Greater),
                _ => matches!(ord, Some(Ordering::Greater | Ordering::Equal)),
            }))
        }
        BinaryOp::Add => elementwise("+", a, b, |x, y| x + y),
        BinaryOp::Sub => elementwise("-", a, b, |x, y| x - y),
        BinaryOp::Mul => multiply(a, b),
        BinaryOp::Div => divide(a, b),
        BinaryOp::Rem => match (a, b) {
            (Value::Number(x), Value::Number(y)) => Ok(Value::Number(x % y)),
            _ => undefined_operation("%", a, b),
        },
        BinaryOp::Pow => match (a, b) {
            (Value::Number(x), Value::Number(y)) => Ok(Value::Number(x.powf(*y))),
            _ => undefined_operation("^", a, b),
        },
    }
}

/// Ordering for `<` and friends: numbers, strings, booleans, and vectors lexicographically.
/// `None` when OpenSCAD calls the comparison undefined; `Some(None)` for unordered numbers (NaN),
/// which compare false.
pub fn compare(a: &Value<'_>, b: &Value<'_>) -> Option<Option<Ordering>> {
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => Some(x.partial_cmp(y)),
        (Value::String(x), Value::String(y)) => Some(Some(x.cmp(y))),
        (Value::Bool(x), Value::Bool(y)) => Some(Some(x.cmp(y))),
        (Value::Vector(x), Value::Vector(y)) => {
            for (p, q) in x.iter().zip(y.iter()) {
                match compare(p, q)? {
                    Some(Ordering::Equal) => continue,
                    other => return Some(other),
                }
            }
            Some(Some(x.len().cmp(&y.len())))
        }
        _ => None,
    }
}

fn elementwise<'a>(op: &str, a: &Value<'a>, b: &Value<'a>, f: fn(f64, f64) -> f64) -> OpResult<'a> {
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => Ok(Value::Number(f(*x, *y))),
        (Value::Vector(x), Value::Vector(y)) => Ok(Value::vector(
            x.iter()
                .zip(y.iter())
                .map(|(p, q)| elementwise(op, p, q, f))
                .collect::<Result<_, _>>()?,
        )),
        _ => undefined_operation(op, a, b),
    }
}

fn scale_vector<'a>(v: &[Value<'a>], k: &Value<'a>, number_first: bool) -> OpResult<'a> {
    Ok(Value::vector(
        v.iter()
            .map(|e| {
                if number_first {
                    multiply(k, e)
                } else {
                    multiply(e, k)
                }
            })
            .collect::<Result<_, _>>()?,
    ))
}

fn numbers(v: &[Value<'_>]) -> Option<Vec<f64>> {
    v.iter().map(Value::as_number).collect()
}

/// `v · M` for a number vector `v` and a matrix `M` with `len(v)` rows of equal length.
fn vector_times_matrix<'a>(v: &[f64], m: &[Value<'a>]) -> Option<Value<'a>> {
    if v.len() != m.len() || m.is_empty() {
        return None;
    }
    let rows: Vec<Vec<f64>> = m
        .iter()
        .map(|r| r.as_vector().and_then(numbers))
        .collect::<Option<_>>()?;
    let cols = rows[0].len();
    if rows.iter().any(|r| r.len() != cols) {
        return None;
    }
    Some(Value::vector(
        (0..cols)
            .map(|j| Value::Number(v.iter().zip(&rows).map(|(x, r)| x * r[j]).sum()))
            .collect(),
    ))
}

fn multiply<'a>(a: &Value<'a>, b: &Value<'a>) -> OpResult<'a> {
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => Ok(Value::Number(x * y)),
        (Value::Vector(v), Value::Number(_)) => scale_vector(v, b, false),
        (Value::Number(_), Value::Vector(v)) => scale_vector(v, a, true),
        (Value::Vector(x), Value::Vector(y)) if !x.is_empty() && !y.is_empty() => {
            let product = match (&x[0], &y[0]) {
                (Value::Number(_), Value::Number(_)) if x.len() == y.len() => {
                    match (numbers(x), numbers(y)) {
                        (Some(p), Some(q)) => {
                            Some(Value::Number(p.iter().zip(&q).map(|(s, t)| s * t).sum()))
                        }
                        _ => None,
                    }
                }
                (Value::Number(_), Value::Vector(_)) => {
                    numbers(x).and_then(|v| vector_times_matrix(&v, y))
                }
                (Value::Vector(first_row), Value::Number(_)) if first_row.len() == y.len() => {
                    numbers(y).and_then(|v| {
                        x.iter()
                            .map(|row| {
                                let r = row.as_vector().and_then(numbers)?;
                                (r.len() == v.len()).then(|| {
                                    Value::Number(r.iter().zip(&v).map(|(s, t)| s * t).sum())
                                })
                            })
                            .collect::<Option<Vec<_>>>()
                            .map(Value::vector)
                    })
                }
                (Value::Vector(first_row), Value::Vector(_)) if first_row.len() == y.len() => x
                    .iter()
                    .map(|row| {
                        let r = row.as_vector().and_then(numbers)?;
                        vector_times_matrix(&r, y)
                    })
                    .collect::<Option<Vec<_>>>()
                    .map(Value::vector),
                _ => None,
            };
            product.map_or_else(|| undefined_operation("*", a, b), Ok)
        }
        _ => undefined_operation("*", a, b),
    }
}

fn divide<'a>(a: &Value<'a>, b: &Value<'a>) -> OpResult<'a> {
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => Ok(Value::Number(x / y)),
        (Value::Vector(v), Value::Number(_)) => Ok(Value::vector(
            v.iter().map(|e| divide(e, b)).collect::<Result<_, _>>()?,
        )),
        (Value::Number(_), Value::Vector(v)) => Ok(Value::vector(
            v.iter().map(|e| divide(a, e)).collect::<Result<_, _>>()?,
        )),
        _ => undefined_operation("/", a, b),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn n<'a>(x: f64) -> Value<'a> {
        Value::Number(x)
    }
    fn v<'a>(xs: &[f64]) -> Value<'a> {
        Value::vector(xs.iter().map(|x| Value::Number(*x)).collect())
    }
    fn m<'a>(rows: &[&[f64]]) -> Value<'a> {
        Value::vector(rows.iter().map(|r| v(r)).collect())
    }
    fn show(r: OpResult<'_>) -> String {
        match r {
            Ok(v) => v.to_echo_string(),
            Err(e) => format!("error: {e}"),
        }
    }

    #[test]
    fn arithmetic_matches_openscad() {
        use BinaryOp::*;
        assert_eq!(show(binary(Mul, &v(&[1.0, 2.0]), &v(&[3.0, 4.0]))), "11");
        let mat = m(&[&[1.0, 2.0], &[3.0, 4.0]]);
        assert_eq!(show(binary(Mul, &mat, &v(&[1.0, 1.0]))), "[3, 7]");
        assert_eq!(show(binary(Mul, &v(&[1.0, 1.0]), &mat)), "[4, 6]");
        assert_eq!(show(binary(Mul, &v(&[2.0, 3.0]), &mat)), "[11, 16]");
        let id = m(&[&[1.0, 0.0], &[0.0, 1.0]]);
        assert_eq!(show(binary(Mul, &mat, &id)), "[[1, 2], [3, 4]]");
        assert_eq!(show(binary(Add, &v(&[1.0, 2.0]), &v(&[3.0]))), "[4]");
        assert_eq!(show(binary(Rem, &n(-5.0), &n(3.0))), "-2");
        assert_eq!(show(binary(Rem, &n(7.0), &n(0.0))), "nan");
        assert_eq!(show(binary(Pow, &n(2.0), &n(10.0))), "1024");
        assert_eq!(show(binary(Div, &v(&[1.0, 2.0]), &n(2.0))), "[0.5, 1]");
        assert_eq!(show(binary(Div, &n(2.0), &v(&[1.0, 2.0]))), "[2, 1]");
        assert_eq!(show(binary(Mul, &n(2.0), &m(&[&[1.0, 2.0]]))), "[[2, 4]]");
        assert!(binary(Add, &Value::string("a"), &n(1.0)).is_err());
        assert!(binary(Sub, &n(3.0), &Value::Undef).is_err());
        assert!(binary(Add, &v(&[1.0]), &n(1.0)).is_err());
    }

    #[test]
    fn comparisons_match_openscad() {
        use BinaryOp::*;
        assert_eq!(
            show(binary(Lt, &Value::string("a"), &Value::string("b"))),
            "true"
        );
        assert_eq!(show(binary(Lt, &v(&[1.0]), &v(&[2.0]))), "true");
        assert_eq!(
            show(binary(Lt, &Value::Bool(true), &Value::Bool(false))),
            "false"
        );
        assert_eq!(show(binary(Eq, &Value::Undef, &Value::Undef)), "true");
        assert_eq!(show(binary(Eq, &n(1.0), &Value::Bool(true))), "false");
        assert_eq!(
            show(binary(Eq, &v(&[1.0, 2.0]), &v(&[1.0, 2.0, 3.0]))),
            "false"
        );
        assert_eq!(show(binary(Lt, &n(f64::NAN), &n(1.0))), "false");
        assert!(binary(Lt, &n(1.0), &Value::string("a")).is_err());
    }

    #[test]
    fn unary_operators() {
        assert_eq!(
            show(unary(UnaryOp::Neg, &Value::vector(vec![n(1.0), v(&[2.0])]))),
            "[-1, [-2]]"
        );
        assert_eq!(show(unary(UnaryOp::Not, &Value::string(""))), "true");
        assert_eq!(show(unary(UnaryOp::Not, &Value::vector(vec![]))), "true");
        assert!(unary(UnaryOp::Neg, &Value::string("a")).is_err());
    }
}
