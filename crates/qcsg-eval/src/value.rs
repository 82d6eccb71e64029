//! Run-time values, their equality, and numbers in OpenSCAD's text form.
//!
//! Values are cheap to clone: strings, vectors and closures are reference counted (the text
//! forms of whole values, which sharing can make far larger than the values, are in
//! [`text`](crate::text)). Numbers print as OpenSCAD 2021.01 prints them: six significant
//! digits, ties rounded away from zero, trailing zeros dropped, exponent form below `1e-5` and
//! from `1e6` on (`1e+6`, `1.5e-7`).

use std::fmt::Write as _;
use std::rc::Rc;

use crate::env::FunctionDef;

/// A run-time value.
#[derive(Clone, Debug)]
pub enum Value<'a> {
    /// `undef`.
    Undef,
    /// `true` / `false`.
    Bool(bool),
    /// A number (OpenSCAD has only doubles).
    Number(f64),
    /// A string.
    String(Rc<str>),
    /// A vector.
    Vector(Rc<Vec<Value<'a>>>),
    /// A range `[begin : step : end]`.
    Range(Range),
    /// A function value (a function literal and the scope it closes over).
    Function(Rc<FunctionDef<'a>>),
}

/// Takes a vector apart without recursion: dropping a value nested a million deep (which tail
/// recursion builds in a second) would otherwise overflow the stack, one frame per level.
impl Drop for Value<'_> {
    fn drop(&mut self) {
        let Value::Vector(items) = self else {
            return;
        };
        // Elements still shared elsewhere are not dropped now; nor are those of a vector with
        // no vector among them, which the ordinary drop handles in one level.
        let Some(elements) = Rc::get_mut(items) else {
            return;
        };
        if !elements.iter().any(|e| matches!(e, Value::Vector(_))) {
            return;
        }
        let mut pending = std::mem::take(elements);
        while let Some(mut value) = pending.pop() {
            if let Value::Vector(items) = &mut value
                && let Some(elements) = Rc::get_mut(items)
            {
                pending.append(elements);
            }
        }
    }
}

/// A numeric range as OpenSCAD 2021.01 iterates it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Range {
    /// The first value.
    pub begin: f64,
    /// The step.
    pub step: f64,
    /// The last value (inclusive, up to rounding).
    pub end: f64,
}

impl Range {
    /// The number of values, as OpenSCAD counts them (`u32::MAX` for an endless range): the
    /// quotient `(end − begin) / step` is nudged up by one ulp so that `[0 : 0.1 : 1]` includes 1.
    pub fn len(&self) -> u64 {
        let (b, s, e) = (self.begin, self.step, self.end);
        if b.is_nan() || s.is_nan() || e.is_nan() {
            return 0;
        }
        if (s < 0.0 && b < e) || (s >= 0.0 && b > e) {
            return 0;
        }
        if b == e || s.is_infinite() {
            return 1;
        }
        let max = u32::MAX as f64;
        if b.is_infinite() || e.is_infinite() || s == 0.0 {
            return u32::MAX as u64;
        }
        let steps = next_after_up((e - b) / s).floor();
        if steps >= max {
            u32::MAX as u64
        } else {
            steps as u64 + 1
        }
    }

    /// Whether the range has no values.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The `index`-th value.
    pub fn at(&self, index: u64) -> f64 {
        self.begin + self.step * index as f64
    }
}

/// The next double towards +∞ (C's `nextafter(x, UINT32_MAX)` for the values ranges produce).
fn next_after_up(x: f64) -> f64 {
    if x.is_nan() || x == f64::INFINITY {
        return x;
    }
    if x == 0.0 {
        return f64::from_bits(1);
    }
    let bits = x.to_bits();
    if x > 0.0 {
        f64::from_bits(bits + 1)
    } else {
        f64::from_bits(bits - 1)
    }
}

impl<'a> Value<'a> {
    /// A string value.
    pub fn string(s: impl Into<Rc<str>>) -> Self {
        Value::String(s.into())
    }

    /// A vector value.
    pub fn vector(v: Vec<Value<'a>>) -> Self {
        Value::Vector(Rc::new(v))
    }

    /// OpenSCAD's truth value.
    pub fn truthy(&self) -> bool {
        match self {
            Value::Undef => false,
            Value::Bool(b) => *b,
            Value::Number(x) => *x != 0.0,
            Value::String(s) => !s.is_empty(),
            Value::Vector(v) => !v.is_empty(),
            Value::Range(_) | Value::Function(_) => true,
        }
    }

    /// The number, if this is one.
    pub fn as_number(&self) -> Option<f64> {
        match self {
            Value::Number(x) => Some(*x),
            _ => None,
        }
    }

    /// The elements, if this is a vector.
    pub fn as_vector(&self) -> Option<&[Value<'a>]> {
        match self {
            Value::Vector(v) => Some(v),
            _ => None,
        }
    }

    /// The type's name as OpenSCAD's warnings spell it.
    pub fn type_name(&self) -> &'static str {
        match self {
            Value::Undef => "undefined",
            Value::Bool(_) => "bool",
            Value::Number(_) => "number",
            Value::String(_) => "string",
            Value::Vector(_) => "vector",
            Value::Range(_) => "range",
            Value::Function(_) => "function",
        }
    }

    /// A vector of exactly `n` finite or infinite numbers.
    pub fn as_numbers(&self, n: usize) -> Option<Vec<f64>> {
        let v = self.as_vector()?;
        if v.len() != n {
            return None;
        }
        v.iter().map(Value::as_number).collect()
    }

    /// OpenSCAD's `getVec3`: a vector of 2 or 3 numbers, the missing `z` being `default_z`.
    pub fn as_vec3(&self, default_z: f64) -> Option<[f64; 3]> {
        let v = self.as_vector()?;
        let n = |i: usize| v.get(i).and_then(Value::as_number);
        match v.len() {
            2 => Some([n(0)?, n(1)?, default_z]),
            3 => Some([n(0)?, n(1)?, n(2)?]),
            _ => None,
        }
    }

    /// The text `echo` prints for the value, whole: for tests, whose values are small. Evaluation
    /// prints through [`BoundedText`](crate::text::BoundedText), which stops at a limit.
    #[cfg(test)]
    pub(crate) fn to_echo_string(&self) -> String {
        let mut text = crate::text::BoundedText::new(u64::MAX);
        let _ = text.push_echo(self);
        text.into_string()
    }
}

/// OpenSCAD's `==`: same type and same value (vectors elementwise, `undef == undef`).
pub fn values_equal<'a>(a: &Value<'a>, b: &Value<'a>) -> bool {
    match (a, b) {
        (Value::Undef, Value::Undef) => true,
        (Value::Bool(x), Value::Bool(y)) => x == y,
        (Value::Number(x), Value::Number(y)) => x == y,
        (Value::String(x), Value::String(y)) => x == y,
        (Value::Vector(x), Value::Vector(y)) => {
            x.len() == y.len() && x.iter().zip(y.iter()).all(|(p, q)| values_equal(p, q))
        }
        (Value::Range(x), Value::Range(y)) => x == y,
        (Value::Function(x), Value::Function(y)) => Rc::ptr_eq(x, y),
        _ => false,
    }
}

/// A number as OpenSCAD 2021.01 prints it (double-conversion's `ToPrecision(6)` with trailing
/// zeros removed, `inf`, `-inf`, `nan`, and `-0` printed as `0`).
pub fn format_number(x: f64) -> String {
    if x.is_nan() {
        return "nan".into();
    }
    if x.is_infinite() {
        return if x > 0.0 { "inf".into() } else { "-inf".into() };
    }
    if x == 0.0 {
        return "0".into();
    }
    // An integer of at most six digits prints as itself: the common case, without the slow
    // 40-digit expansion below.
    if x.fract() == 0.0 && x.abs() < 1e6 {
        return (x as i64).to_string();
    }
    const PRECISION: usize = 6;
    // Far more digits than the tie decision needs: an f64 differs from a decimal tie within 17.
    let exact = format!("{:.40e}", x.abs());
    let (mantissa, exponent) = exact.split_once('e').unwrap_or((&exact, "0"));
    let mut exponent: i32 = exponent.parse().unwrap_or(0);
    let all: Vec<u8> = mantissa
        .bytes()
        .filter(u8::is_ascii_digit)
        .map(|b| b - b'0')
        .collect();
    let mut digits: Vec<u8> = all[..PRECISION].to_vec();
    // double-conversion rounds a remainder of one half or more up.
    if all[PRECISION] >= 5 {
        let mut i = PRECISION;
        loop {
            if i == 0 {
                digits.insert(0, 1);
                digits.pop();
                exponent += 1;
                break;
            }
            i -= 1;
            if digits[i] == 9 {
                digits[i] = 0;
            } else {
                digits[i] += 1;
                break;
            }
        }
    }
    while digits.len() > 1 && digits.last() == Some(&0) {
        digits.pop();
    }
    let mut out = String::new();
    if x < 0.0 {
        out.push('-');
    }
    let text: String = digits.iter().map(|d| char::from(b'0' + d)).collect();
    if exponent < -5 || exponent >= PRECISION as i32 {
        out.push_str(&text[..1]);
        if text.len() > 1 {
            out.push('.');
            out.push_str(&text[1..]);
        }
        out.push('e');
        out.push(if exponent < 0 { '-' } else { '+' });
        let _ = write!(out, "{}", exponent.abs());
    } else if exponent < 0 {
        out.push_str("0.");
        for _ in 0..(-exponent - 1) {
            out.push('0');
        }
        out.push_str(&text);
    } else {
        let int_len = exponent as usize + 1;
        if text.len() <= int_len {
            out.push_str(&text);
            for _ in text.len()..int_len {
                out.push('0');
            }
        } else {
            out.push_str(&text[..int_len]);
            out.push('.');
            out.push_str(&text[int_len..]);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_print_like_openscad() {
        let cases: &[(f64, &str)] = &[
            (1.0 / 3.0, "0.333333"),
            (1e6, "1e+6"),
            (1e-5, "0.00001"),
            (1e-6, "1e-6"),
            (123456789.0, "1.23457e+8"),
            (1234567.0, "1.23457e+6"),
            (0.1 + 0.2, "0.3"),
            (-0.0, "0"),
            (1e21, "1e+21"),
            (f64::INFINITY, "inf"),
            (f64::NEG_INFINITY, "-inf"),
            (f64::NAN, "nan"),
            (2.0 / 3.0 * 1e10, "6.66667e+9"),
            (100000.0, "100000"),
            (3.0, "3"),
            (1.5e-7, "1.5e-7"),
            (-1e-7, "-1e-7"),
            (1234565.0, "1.23457e+6"),
            (0.1234565, "0.123456"),
            (99999.95, "99999.9"),
            (999999.5, "1e+6"),
            (-1.5e-300, "-1.5e-300"),
            (123456.7, "123457"),
            (12345678901.0, "1.23457e+10"),
            (0.5, "0.5"),
            (-2.0, "-2"),
            (1.4142199, "1.41422"),
        ];
        for (x, want) in cases {
            assert_eq!(format_number(*x), *want, "{x}");
        }
    }

    #[test]
    fn dropping_a_deeply_nested_value_does_not_overflow_the_stack() {
        // A thread with a small stack, so that recursion a frame per level would overflow it.
        std::thread::Builder::new()
            .stack_size(256 * 1024)
            .spawn(|| {
                let mut v = Value::Number(1.0);
                for _ in 0..1_000_000 {
                    v = Value::vector(vec![v, Value::Undef]);
                }
                let shared = v.clone();
                drop(v);
                assert_eq!(shared.as_vector().map(<[_]>::len), Some(2));
            })
            .expect("a thread starts")
            .join()
            .expect("the value is dropped without overflowing the stack");
    }

    #[test]
    fn ranges_count_like_openscad() {
        let r = |b, s, e| Range {
            begin: b,
            step: s,
            end: e,
        };
        assert_eq!(r(0.0, 0.1, 1.0).len(), 11);
        assert_eq!(r(0.0, 0.1, 0.3).len(), 4);
        assert_eq!(r(0.0, -1.0, 3.0).len(), 0);
        assert_eq!(r(3.0, -1.0, 0.0).len(), 4);
        assert_eq!(r(2.0, 1.0, 0.0).len(), 0);
        assert_eq!(r(0.0, 0.0, 1.0).len(), u32::MAX as u64);
        assert_eq!(r(1.0, 0.0, 1.0).len(), 1);
        assert_eq!(r(0.0, 1.0, 1e12).len(), u32::MAX as u64);
        assert_eq!(r(f64::NAN, 1.0, 1.0).len(), 0);
    }

    #[test]
    fn echo_and_str_forms() {
        let v = Value::vector(vec![
            Value::Number(1.0),
            Value::string("a"),
            Value::vector(vec![Value::Number(2.0), Value::Undef]),
        ]);
        assert_eq!(v.to_echo_string(), "[1, \"a\", [2, undef]]");
        assert_eq!(Value::string("s").to_echo_string(), "\"s\"");
        let r = Value::Range(Range {
            begin: 1.0,
            step: 2.0,
            end: 5.0,
        });
        assert_eq!(r.to_echo_string(), "[1 : 2 : 5]");
        assert!(values_equal(&Value::vector(vec![]), &Value::vector(vec![])));
        assert!(!values_equal(&Value::Number(1.0), &Value::Bool(true)));
        assert!(Value::Number(f64::NAN).truthy());
        assert!(!Value::string("").truthy());
    }
}
