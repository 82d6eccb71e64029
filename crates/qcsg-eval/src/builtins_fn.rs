//! The built-in functions (docs/language.md, "Built-in functions") with OpenSCAD 2021.01's
//! results.
//!
//! Arguments arrive evaluated and in positional order (named arguments already placed by the
//! caller). Where OpenSCAD returns `undef` with a warning, these return an error message, which
//! the evaluator reports at the call. Results are bounded by the evaluation's limits before they
//! are built: vectors by `max_vector_len`, strings by `max_string_len`, and the work of a call by
//! its arguments and result (a value's parts are shared, so nothing walks a value further than
//! the result it makes).

use std::collections::HashMap;

use crate::EvalOptions;
use crate::math::{Mt19937, cos_degrees, rad2deg, sin_degrees, tan_degrees};
use crate::ops::compare;
use crate::text::{BoundedText, Overflow, echo_text_cut};
use crate::value::{Value, values_equal};

/// The OpenSCAD release whose semantics the language follows, as `version()` reports it.
pub const OPENSCAD_VERSION: [u32; 3] = [2021, 1, 0];

/// How much of a value a warning or error message quotes, in bytes.
const QUOTED_VALUE_LEN: usize = 200;

/// Why a built-in function gave no value.
#[derive(Debug)]
pub enum BuiltinError {
    /// OpenSCAD would return `undef` (with this explanation).
    Undefined(String),
    /// The result would be longer than the vector-length limit.
    TooLong(u64),
    /// The result would be a string longer than the string-length limit.
    StringTooLong,
}

/// What a call produced: the value and any warnings.
pub type BuiltinResult<'a> = Result<Value<'a>, BuiltinError>;

fn undefined<T>(message: impl Into<String>) -> Result<T, BuiltinError> {
    Err(BuiltinError::Undefined(message.into()))
}

/// Whether `name` is a built-in function this module implements.
pub fn is_builtin(name: &str) -> bool {
    qcsg_sema::builtins::function(name).is_some()
}

/// Calls the built-in function `name`, within the length limits of `limits`. `warnings`
/// receives messages that do not make the result undefined.
pub fn call<'a>(
    name: &str,
    args: &[Value<'a>],
    limits: &EvalOptions,
    warnings: &mut Vec<String>,
) -> BuiltinResult<'a> {
    let max_len = limits.max_vector_len;
    let arg = |i: usize| args.get(i).cloned().unwrap_or(Value::Undef);
    let num = |i: usize| -> Result<f64, BuiltinError> {
        match args.get(i) {
            Some(Value::Number(x)) => Ok(*x),
            Some(other) => undefined(format!(
                "{name}() parameter could not be converted: expected a number, got {}",
                other.type_name()
            )),
            None => undefined(format!("{name}() needs argument {}", i + 1)),
        }
    };
    let math1 = |f: fn(f64) -> f64| -> BuiltinResult<'a> { Ok(Value::Number(f(num(0)?))) };
    match name {
        "abs" => math1(f64::abs),
        "sign" => math1(|x| {
            if x < 0.0 {
                -1.0
            } else if x > 0.0 {
                1.0
            } else {
                0.0
            }
        }),
        "sin" => math1(sin_degrees),
        "cos" => math1(cos_degrees),
        "tan" => math1(tan_degrees),
        "asin" => math1(|x| rad2deg(x.asin())),
        "acos" => math1(|x| rad2deg(x.acos())),
        "atan" => math1(|x| rad2deg(x.atan())),
        "atan2" => Ok(Value::Number(rad2deg(num(0)?.atan2(num(1)?)))),
        "floor" => math1(f64::floor),
        "ceil" => math1(f64::ceil),
        "round" => math1(f64::round),
        "ln" => math1(f64::ln),
        "log" => {
            if args.len() >= 2 {
                Ok(Value::Number(num(1)?.ln() / num(0)?.ln()))
            } else {
                math1(f64::log10)
            }
        }
        "exp" => math1(f64::exp),
        "pow" => Ok(Value::Number(num(0)?.powf(num(1)?))),
        "sqrt" => math1(f64::sqrt),
        "min" | "max" => min_max(name, args),
        "norm" => match args.first() {
            Some(Value::Vector(v)) => {
                let mut sum = 0.0;
                for e in v.iter() {
                    match e {
                        Value::Number(x) => sum += x * x,
                        _ => return undefined("norm() needs a vector of numbers"),
                    }
                }
                Ok(Value::Number(sum.sqrt()))
            }
            _ => undefined("norm() needs a vector of numbers"),
        },
        "cross" => cross(&arg(0), &arg(1)),
        "len" => match args.first() {
            Some(Value::Vector(v)) => Ok(Value::Number(v.len() as f64)),
            Some(Value::String(s)) => Ok(Value::Number(s.chars().count() as f64)),
            Some(other) => undefined(format!(
                "len() parameter could not be converted: {} has no length",
                other.type_name()
            )),
            None => undefined("len() needs an argument"),
        },
        "concat" => {
            let total: u64 = args
                .iter()
                .map(|a| a.as_vector().map_or(1, |v| v.len() as u64))
                .sum();
            if total > max_len {
                return Err(BuiltinError::TooLong(total));
            }
            let mut out = Vec::with_capacity(total as usize);
            for a in args {
                match a {
                    Value::Vector(v) => out.extend(v.iter().cloned()),
                    other => out.push(other.clone()),
                }
            }
            Ok(Value::vector(out))
        }
        "lookup" => lookup(num(0)?, &arg(1)),
        "str" => {
            let mut s = BoundedText::new(limits.max_string_len);
            for a in args {
                s.push_str_form(a)
                    .map_err(|Overflow| BuiltinError::StringTooLong)?;
            }
            Ok(Value::string(s.into_string()))
        }
        "chr" => chr(args, max_len, limits.max_string_len),
        "ord" => match args.first() {
            Some(Value::String(s)) if s.chars().count() == 1 => Ok(Value::Number(
                s.chars().next().map_or(0, |c| c as u32) as f64,
            )),
            _ => undefined("ord() needs a string of one character"),
        },
        "search" => search(args, max_len, warnings),
        "is_undef" => Ok(Value::Bool(matches!(arg(0), Value::Undef))),
        "is_bool" => Ok(Value::Bool(matches!(arg(0), Value::Bool(_)))),
        "is_num" => Ok(Value::Bool(
            matches!(arg(0), Value::Number(x) if !x.is_nan()),
        )),
        "is_string" => Ok(Value::Bool(matches!(arg(0), Value::String(_)))),
        "is_list" => Ok(Value::Bool(matches!(arg(0), Value::Vector(_)))),
        "is_function" => Ok(Value::Bool(matches!(arg(0), Value::Function(_)))),
        "rands" => rands(args, max_len),
        // The OpenSCAD release whose semantics qcsg follows.
        "version" => Ok(Value::vector(
            OPENSCAD_VERSION.map(|x| Value::Number(x as f64)).to_vec(),
        )),
        "version_num" => Ok(Value::Number(
            (OPENSCAD_VERSION[0] * 10_000 + OPENSCAD_VERSION[1] * 100 + OPENSCAD_VERSION[2]) as f64,
        )),
        other => undefined(format!("unknown built-in function `{other}`")),
    }
}

fn min_max<'a>(name: &str, args: &[Value<'a>]) -> BuiltinResult<'a> {
    let want_min = name == "min";
    if let [Value::Vector(v)] = args
        && let Some(first) = v.first()
    {
        let mut best = first.clone();
        for e in v.iter().skip(1) {
            let better = if want_min {
                compare(e, &best) == Some(Some(std::cmp::Ordering::Less))
            } else {
                compare(e, &best) == Some(Some(std::cmp::Ordering::Greater))
            };
            if better {
                best = e.clone();
            }
        }
        return Ok(best);
    }
    let mut best = match args.first() {
        Some(Value::Number(x)) => *x,
        _ => return undefined(format!("{name}() parameter could not be converted")),
    };
    for a in &args[1..] {
        match a {
            Value::Number(x) => {
                if (want_min && *x < best) || (!want_min && *x > best) {
                    best = *x;
                }
            }
            _ => return undefined(format!("{name}() parameter could not be converted")),
        }
    }
    Ok(Value::Number(best))
}

fn cross<'a>(a: &Value<'a>, b: &Value<'a>) -> BuiltinResult<'a> {
    if let (Some(p), Some(q)) = (a.as_numbers(3), b.as_numbers(3)) {
        return Ok(Value::vector(vec![
            Value::Number(p[1] * q[2] - p[2] * q[1]),
            Value::Number(p[2] * q[0] - p[0] * q[2]),
            Value::Number(p[0] * q[1] - p[1] * q[0]),
        ]));
    }
    if let (Some(p), Some(q)) = (a.as_numbers(2), b.as_numbers(2)) {
        return Ok(Value::Number(p[0] * q[1] - p[1] * q[0]));
    }
    undefined("cross() needs two vectors of 2 or 3 numbers")
}

fn lookup<'a>(p: f64, table: &Value<'a>) -> BuiltinResult<'a> {
    let pair = |v: &Value<'a>| v.as_numbers(2).map(|xy| (xy[0], xy[1]));
    let rows = table.as_vector().unwrap_or(&[]);
    let Some(first) = rows.first().and_then(pair) else {
        return undefined("lookup() needs a table of [key, value] pairs");
    };
    let (mut low_p, mut low_v) = first;
    let (mut high_p, mut high_v) = first;
    for row in &rows[1..] {
        if let Some((this_p, this_v)) = pair(row) {
            if this_p <= p && (this_p > low_p || low_p > p) {
                low_p = this_p;
                low_v = this_v;
            }
            if this_p >= p && (this_p < high_p || high_p < p) {
                high_p = this_p;
                high_v = this_v;
            }
        }
    }
    if p <= low_p {
        return Ok(Value::Number(high_v));
    }
    if p >= high_p {
        return Ok(Value::Number(low_v));
    }
    let f = (p - low_p) / (high_p - low_p);
    Ok(Value::Number(high_v * f + low_v * (1.0 - f)))
}

/// `chr`: the characters of the code points in `args`, vectors flattened at any depth (ranges
/// too), anything else skipped. The walk visits at most `max_len` values, so a vector holding
/// one vector many times is not walked as if it were many.
fn chr<'a>(args: &[Value<'a>], max_len: u64, max_string_len: u64) -> BuiltinResult<'a> {
    let mut out = BoundedText::new(max_string_len);
    let mut visited: u64 = 0;
    // The vectors being walked, innermost last, with the elements still to visit.
    let mut open: Vec<std::slice::Iter<'_, Value<'a>>> = vec![args.iter()];
    while let Some(items) = open.last_mut() {
        let Some(item) = items.next() else {
            open.pop();
            continue;
        };
        visited += 1;
        if visited > max_len {
            return Err(BuiltinError::TooLong(visited));
        }
        match item {
            Value::Number(x) => push_code_point(&mut out, *x)?,
            Value::Vector(items) => open.push(items.iter()),
            Value::Range(r) => {
                let n = r.len();
                if visited.saturating_add(n) > max_len {
                    return Err(BuiltinError::TooLong(visited.saturating_add(n)));
                }
                visited += n;
                for i in 0..n {
                    push_code_point(&mut out, r.at(i))?;
                }
            }
            _ => {}
        }
    }
    Ok(Value::string(out.into_string()))
}

/// Appends the character of code point `x`, if it is one (OpenSCAD skips the others).
fn push_code_point(out: &mut BoundedText, x: f64) -> Result<(), BuiltinError> {
    if x >= 1.0
        && x <= u32::MAX as f64
        && let Some(c) = char::from_u32(x as u32)
    {
        out.push_str(c.encode_utf8(&mut [0; 4]))
            .map_err(|Overflow| BuiltinError::StringTooLong)?;
    }
    Ok(())
}

/// `(unsigned int)` of a double as C++ on x86-64 computes it for the values that matter.
fn as_count(x: f64) -> u64 {
    if x.is_nan() || x <= 0.0 {
        0
    } else {
        (x as u64) & 0xffff_ffff
    }
}

fn search<'a>(args: &[Value<'a>], max_len: u64, warnings: &mut Vec<String>) -> BuiltinResult<'a> {
    let find = args.first().cloned().unwrap_or(Value::Undef);
    let table = args.get(1).cloned().unwrap_or(Value::Undef);
    let per_match = args.get(2).and_then(Value::as_number).map_or(1, as_count);
    let column = args.get(3).and_then(Value::as_number).map_or(0, as_count) as usize;
    let table_items: &[Value<'a>] = table.as_vector().unwrap_or(&[]);
    let entry_matches = |needle: &Value<'a>, entry: &Value<'a>| {
        (column == 0 && values_equal(needle, entry))
            || entry
                .as_vector()
                .and_then(|e| e.get(column))
                .is_some_and(|e| values_equal(needle, e))
    };
    let index = |j: usize| Value::Number(j as f64);
    match &find {
        Value::Number(_) => {
            let mut out = Vec::new();
            for (j, entry) in table_items.iter().enumerate() {
                if entry_matches(&find, entry) {
                    out.push(index(j));
                    if per_match != 0 && out.len() as u64 >= per_match {
                        break;
                    }
                }
            }
            Ok(Value::vector(out))
        }
        Value::String(needle) => {
            let haystack: Vec<Option<char>> = match &table {
                Value::String(s) => s.chars().map(Some).collect(),
                Value::Vector(rows) => {
                    let mut firsts = Vec::with_capacity(rows.len());
                    for (j, row) in rows.iter().enumerate() {
                        match row.as_vector().and_then(|r| r.get(column)) {
                            Some(cell) => firsts.push(first_str_char(cell)),
                            None => {
                                warnings.push(format!(
                                    "invalid entry in search vector at index {j}, required number of values in the entry: {}. Invalid entry: {}",
                                    column + 1,
                                    echo_text_cut(row, QUOTED_VALUE_LEN)
                                ));
                                return Ok(Value::vector(Vec::new()));
                            }
                        }
                    }
                    firsts
                }
                _ => return undefined("search() needs a string or vector to search in"),
            };
            search_characters(needle, &haystack, per_match, max_len)
        }
        Value::Vector(needles) => {
            let mut out = Vec::new();
            for needle in needles.iter() {
                let mut found = Vec::new();
                for (j, entry) in table_items.iter().enumerate() {
                    if entry_matches(needle, entry) {
                        found.push(index(j));
                        if per_match == 1 || (per_match > 1 && found.len() as u64 >= per_match) {
                            break;
                        }
                    }
                }
                if per_match == 1 {
                    match found.pop() {
                        Some(j) => out.push(j),
                        None => out.push(Value::vector(Vec::new())),
                    }
                } else {
                    out.push(Value::vector(found));
                }
            }
            Ok(Value::vector(out))
        }
        other => undefined(format!(
            "search term not supported: {}",
            echo_text_cut(other, QUOTED_VALUE_LEN)
        )),
    }
}

/// The first character of the text `str` makes of `value`, without printing the rest.
fn first_str_char(value: &Value<'_>) -> Option<char> {
    // A character is 4 bytes at most: the first one fits.
    let mut text = BoundedText::new(4);
    let _ = text.push_str_form(value);
    text.as_str().chars().next()
}

/// `search` of each character of `needle` in `haystack` (a string's characters, or the first
/// characters of a table's cells): for each, the first match's index when `per_match` is 1
/// (nothing when none), else a vector of the first `per_match` matches' indices (all for 0).
///
/// The haystack is indexed once, and each distinct character's answer is built once and shared
/// by its repetitions, so the work is linear in the two lengths and the answer's size, never
/// their product.
fn search_characters<'a>(
    needle: &str,
    haystack: &[Option<char>],
    per_match: u64,
    max_len: u64,
) -> BuiltinResult<'a> {
    let mut positions: HashMap<char, Vec<usize>> = HashMap::new();
    for (j, c) in haystack.iter().enumerate() {
        if let Some(c) = c {
            positions.entry(*c).or_default().push(j);
        }
    }
    let mut answers: HashMap<char, Value<'a>> = HashMap::new();
    let mut out = Vec::new();
    for c in needle.chars() {
        let found = positions.get(&c).map_or(&[][..], Vec::as_slice);
        if per_match == 1 {
            let Some(&j) = found.first() else {
                continue;
            };
            if out.len() as u64 >= max_len {
                return Err(BuiltinError::TooLong(out.len() as u64 + 1));
            }
            out.push(Value::Number(j as f64));
            continue;
        }
        if out.len() as u64 >= max_len {
            return Err(BuiltinError::TooLong(out.len() as u64 + 1));
        }
        let answer = answers.entry(c).or_insert_with(|| {
            let taken = if per_match == 0 {
                found.len()
            } else {
                found
                    .len()
                    .min(usize::try_from(per_match).unwrap_or(usize::MAX))
            };
            Value::vector(
                found[..taken]
                    .iter()
                    .map(|&j| Value::Number(j as f64))
                    .collect(),
            )
        });
        out.push(answer.clone());
    }
    Ok(Value::vector(out))
}

fn rands<'a>(args: &[Value<'a>], max_len: u64) -> BuiltinResult<'a> {
    let num = |i: usize| args.get(i).and_then(Value::as_number);
    let (Some(a), Some(b), Some(count)) = (num(0), num(1), num(2)) else {
        return undefined("rands() needs numbers min, max and count");
    };
    let count = if count.is_nan() || count < 1.0 {
        0
    } else {
        count as u64
    };
    if count > max_len {
        return Err(BuiltinError::TooLong(count));
    }
    // Without a seed OpenSCAD draws from a random device; qcsg stays deterministic.
    let seed = match args.get(3) {
        Some(Value::Number(s)) => (*s as i64) as u32,
        Some(_) => return undefined("rands() seed must be a number"),
        None => 0,
    };
    let (min, max) = (a.min(b), a.max(b));
    let mut rng = Mt19937::new(seed);
    Ok(Value::vector(
        (0..count)
            .map(|_| Value::Number(rng.uniform(min, max)))
            .collect(),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn n<'a>(x: f64) -> Value<'a> {
        Value::Number(x)
    }
    fn s<'a>(x: &str) -> Value<'a> {
        Value::string(x)
    }
    fn v<'a>(xs: Vec<Value<'a>>) -> Value<'a> {
        Value::vector(xs)
    }
    fn run(name: &str, args: Vec<Value<'_>>) -> String {
        let limits = EvalOptions {
            max_vector_len: 1_000_000,
            max_string_len: 1_000,
            ..EvalOptions::default()
        };
        match call(name, &args, &limits, &mut Vec::new()) {
            Ok(v) => v.to_echo_string(),
            Err(BuiltinError::Undefined(_)) => "undef".into(),
            Err(BuiltinError::TooLong(n)) => format!("too long {n}"),
            Err(BuiltinError::StringTooLong) => "string too long".into(),
        }
    }

    #[test]
    fn math_functions() {
        assert_eq!(run("round", vec![n(-2.5)]), "-3");
        assert_eq!(run("round", vec![n(2.5)]), "3");
        assert_eq!(run("sign", vec![n(-3.0)]), "-1");
        assert_eq!(run("norm", vec![v(vec![n(3.0), n(4.0)])]), "5");
        assert_eq!(run("norm", vec![v(vec![])]), "0");
        assert_eq!(run("atan2", vec![n(1.0), n(1.0)]), "45");
        assert_eq!(run("acos", vec![n(2.0)]), "nan");
        assert_eq!(run("log", vec![n(100.0)]), "2");
        assert_eq!(run("log", vec![n(2.0), n(8.0)]), "3");
        assert_eq!(run("ln", vec![n(std::f64::consts::E)]), "1");
        assert_eq!(run("pow", vec![n(2.0), n(0.5)]), "1.41421");
        assert_eq!(run("ceil", vec![n(-1.5)]), "-1");
        assert_eq!(run("floor", vec![n(-1.5)]), "-2");
        assert_eq!(run("abs", vec![n(-0.0)]), "0");
        assert_eq!(run("sin", vec![s("a")]), "undef");
    }

    #[test]
    fn vector_and_string_functions() {
        assert_eq!(
            run(
                "cross",
                vec![
                    v(vec![n(1.0), n(0.0), n(0.0)]),
                    v(vec![n(0.0), n(1.0), n(0.0)])
                ]
            ),
            "[0, 0, 1]"
        );
        assert_eq!(
            run(
                "concat",
                vec![v(vec![n(1.0)]), v(vec![n(2.0), n(3.0)]), n(4.0)]
            ),
            "[1, 2, 3, 4]"
        );
        assert_eq!(run("concat", vec![s("ab"), v(vec![n(1.0)])]), "[\"ab\", 1]");
        assert_eq!(run("len", vec![s("abc")]), "3");
        assert_eq!(run("len", vec![s("é")]), "1");
        assert_eq!(run("len", vec![n(5.0)]), "undef");
        assert_eq!(run("chr", vec![n(65.0)]), "\"A\"");
        assert_eq!(run("chr", vec![v(vec![n(72.0), n(105.0)])]), "\"Hi\"");
        assert_eq!(run("ord", vec![s("A")]), "65");
        assert_eq!(run("ord", vec![s("é")]), "233");
        assert_eq!(run("str", vec![n(1.0), n(2.0), s("a")]), "\"12a\"");
        assert_eq!(run("str", vec![n(1.0 / 3.0)]), "\"0.333333\"");
        assert_eq!(run("max", vec![v(vec![n(1.0), n(5.0), n(3.0)])]), "5");
        assert_eq!(run("min", vec![n(4.0), n(2.0), n(8.0)]), "2");
        assert_eq!(run("max", vec![n(1.0)]), "1");
        assert_eq!(run("min", vec![v(vec![])]), "undef");
        assert_eq!(run("is_num", vec![n(f64::NAN)]), "false");
        assert_eq!(run("is_list", vec![v(vec![])]), "true");
    }

    #[test]
    fn lookup_interpolates_and_clamps() {
        let table = v(vec![v(vec![n(1.0), n(10.0)]), v(vec![n(2.0), n(20.0)])]);
        assert_eq!(run("lookup", vec![n(1.5), table.clone()]), "15");
        assert_eq!(run("lookup", vec![n(0.0), table.clone()]), "10");
        assert_eq!(run("lookup", vec![n(5.0), table]), "20");
    }

    #[test]
    fn search_forms() {
        assert_eq!(run("search", vec![s("a"), s("abcabc")]), "[0]");
        assert_eq!(
            run("search", vec![s("abc"), s("abcabc"), n(0.0)]),
            "[[0, 3], [1, 4], [2, 5]]"
        );
        let table = v(vec![
            v(vec![n(1.0), s("x")]),
            v(vec![n(2.0), s("y")]),
            v(vec![n(1.0), s("z")]),
        ]);
        assert_eq!(
            run("search", vec![v(vec![n(1.0), n(2.0)]), table]),
            "[0, 1]"
        );
        let flat = v(vec![n(1.0), n(2.0), n(1.0)]);
        assert_eq!(run("search", vec![n(1.0), flat, n(0.0)]), "[0, 2]");
        assert_eq!(run("search", vec![s("b"), s("abcb"), n(0.0)]), "[[1, 3]]");
        assert_eq!(run("search", vec![s("zz"), s("abc")]), "[]");
        let pairs = v(vec![v(vec![n(1.0), n(2.0)]), v(vec![n(3.0), n(4.0)])]);
        assert_eq!(
            run("search", vec![v(vec![v(vec![n(1.0), n(2.0)])]), pairs]),
            "[0]"
        );
        let rows = v(vec![
            v(vec![n(1.0), s("a"), n(3.0)]),
            v(vec![n(3.0), s("b"), n(4.0)]),
        ]);
        assert_eq!(run("search", vec![n(3.0), rows, n(0.0), n(2.0)]), "[0]");
        let strings = v(vec![s("x"), s("y"), s("x")]);
        assert_eq!(run("search", vec![s("x"), strings, n(0.0)]), "[]");
        let keyed = v(vec![v(vec![s("a"), n(1.0)]), v(vec![s("b"), n(2.0)])]);
        assert_eq!(
            run("search", vec![v(vec![s("a"), s("b")]), keyed]),
            "[0, 1]"
        );
    }

    #[test]
    fn rands_are_deterministic() {
        assert_eq!(
            run("rands", vec![n(0.0), n(1.0), n(3.0), n(42.0)]),
            "[0.796543, 0.183435, 0.779691]"
        );
        assert_eq!(
            run("rands", vec![n(0.0), n(1.0), n(1e12), n(1.0)]),
            "too long 1000000000000"
        );
    }
}
