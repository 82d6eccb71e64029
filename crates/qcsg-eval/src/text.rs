//! The text forms of values (what `echo` prints and `str` makes), written under a length limit.
//!
//! Values share their parts: `[v, v]` holds `v` once, so a value built in 40 steps can print as
//! 2⁴⁰ numbers. Text is therefore never built without a limit: a [`BoundedText`] refuses to grow
//! past its limit, and printing a value stops at the first refusal. Every part of a value that
//! is printed adds at least one byte, so the work of printing is bounded by the limit, not by
//! the size the value would have without sharing. Printing keeps its own stack of the vectors it
//! is inside, so a deeply nested value does not overflow the thread's stack either.

use std::fmt::Write as _;

use crate::printer;
use crate::value::{Value, format_number};

/// The text would pass its limit: what fits has been written, the rest has not.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Overflow;

/// A string that grows up to a limit in bytes and no further.
#[derive(Clone, Debug)]
pub struct BoundedText {
    text: String,
    limit: usize,
}

impl BoundedText {
    /// An empty text that may grow to `limit` bytes.
    pub fn new(limit: u64) -> Self {
        Self {
            text: String::new(),
            limit: usize::try_from(limit).unwrap_or(usize::MAX),
        }
    }

    /// Appends `s`, or as much of it as fits (whole characters) and then reports the overflow.
    pub fn push_str(&mut self, s: &str) -> Result<(), Overflow> {
        let room = self.limit - self.text.len();
        if s.len() <= room {
            self.text.push_str(s);
            return Ok(());
        }
        let mut end = room;
        while !s.is_char_boundary(end) {
            end -= 1;
        }
        self.text.push_str(&s[..end]);
        Err(Overflow)
    }

    /// The text so far.
    pub fn as_str(&self) -> &str {
        &self.text
    }

    /// The length of the text so far, in bytes.
    pub fn len(&self) -> usize {
        self.text.len()
    }

    /// Whether nothing has been written.
    pub fn is_empty(&self) -> bool {
        self.text.is_empty()
    }

    /// The text.
    pub fn into_string(self) -> String {
        self.text
    }

    /// Appends the text `echo` prints for `value` (strings in quotes).
    pub fn push_echo(&mut self, value: &Value<'_>) -> Result<(), Overflow> {
        write_value(self, value)
    }

    /// Appends an `echo` line: `ECHO: ` and the arguments, named ones as `name = value`.
    pub fn push_echo_line<'v, 'a: 'v>(
        &mut self,
        args: impl IntoIterator<Item = (Option<&'v str>, &'v Value<'a>)>,
    ) -> Result<(), Overflow> {
        self.push_str("ECHO: ")?;
        for (i, (name, value)) in args.into_iter().enumerate() {
            if i > 0 {
                self.push_str(", ")?;
            }
            if let Some(name) = name {
                self.push_str(name)?;
                self.push_str(" = ")?;
            }
            self.push_echo(value)?;
        }
        Ok(())
    }

    /// Appends the text `str` makes of `value` (a string itself without quotes).
    pub fn push_str_form(&mut self, value: &Value<'_>) -> Result<(), Overflow> {
        match value {
            Value::String(s) => self.push_str(s),
            other => write_value(self, other),
        }
    }
}

/// The text `echo` prints for `value`, cut after about `max` bytes with `…` when longer: for
/// values quoted in messages.
pub fn echo_text_cut(value: &Value<'_>, max: usize) -> String {
    let mut text = BoundedText::new(max as u64);
    match text.push_echo(value) {
        Ok(()) => text.into_string(),
        Err(Overflow) => text.into_string() + "…",
    }
}

/// Writes `value` in its `echo` form. Vectors are walked with an explicit stack of the ones
/// still open; each value visited writes at least one byte, so an overflow ends the walk after
/// at most `limit` visits.
fn write_value(out: &mut BoundedText, value: &Value<'_>) -> Result<(), Overflow> {
    // The vectors being printed: the elements still to print and whether one has been.
    let mut open: Vec<(std::slice::Iter<'_, Value<'_>>, bool)> = Vec::new();
    let mut next = value;
    loop {
        match next {
            Value::Vector(items) => {
                out.push_str("[")?;
                open.push((items.iter(), false));
            }
            scalar => write_scalar(out, scalar)?,
        }
        // The next value to print, closing the vectors that have none left.
        loop {
            let Some((items, started)) = open.last_mut() else {
                return Ok(());
            };
            match items.next() {
                Some(item) => {
                    if *started {
                        out.push_str(", ")?;
                    }
                    *started = true;
                    next = item;
                    break;
                }
                None => {
                    out.push_str("]")?;
                    open.pop();
                }
            }
        }
    }
}

/// Writes a value that is not a vector in its `echo` form.
fn write_scalar(out: &mut BoundedText, value: &Value<'_>) -> Result<(), Overflow> {
    match value {
        Value::Undef => out.push_str("undef"),
        Value::Bool(b) => out.push_str(if *b { "true" } else { "false" }),
        Value::Number(x) => out.push_str(&format_number(*x)),
        Value::String(s) => {
            out.push_str("\"")?;
            out.push_str(s)?;
            out.push_str("\"")
        }
        Value::Range(r) => {
            let mut text = String::new();
            let _ = write!(
                text,
                "[{} : {} : {}]",
                format_number(r.begin),
                format_number(r.step),
                format_number(r.end)
            );
            out.push_str(&text)
        }
        // The literal's text is as long as its source at most: printing it whole is linear.
        Value::Function(c) => out.push_str(&printer::function_literal(c.params, c.body)),
        Value::Vector(_) => write_value(out, value),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::value::Range;

    fn echo(value: &Value<'_>, limit: u64) -> (String, bool) {
        let mut text = BoundedText::new(limit);
        let overflow = text.push_echo(value).is_err();
        (text.into_string(), overflow)
    }

    #[test]
    fn echo_and_str_forms() {
        let v = Value::vector(vec![
            Value::Number(1.0),
            Value::string("a"),
            Value::vector(vec![Value::Number(2.0), Value::Undef]),
            Value::vector(vec![]),
            Value::Bool(true),
        ]);
        assert_eq!(
            echo(&v, 100),
            ("[1, \"a\", [2, undef], [], true]".into(), false)
        );
        let mut text = BoundedText::new(100);
        text.push_str_form(&Value::string("s")).unwrap();
        text.push_str_form(&v).unwrap();
        assert_eq!(text.as_str(), "s[1, \"a\", [2, undef], [], true]");
        let r = Value::Range(Range {
            begin: 1.0,
            step: 2.0,
            end: 5.0,
        });
        assert_eq!(echo(&r, 100), ("[1 : 2 : 5]".into(), false));
        assert_eq!(echo(&Value::vector(vec![]), 100), ("[]".into(), false));
    }

    #[test]
    fn the_limit_cuts_at_a_character_boundary() {
        let v = Value::vector(vec![Value::string("aé")]);
        assert_eq!(echo(&v, 7), ("[\"aé\"]".into(), false));
        assert_eq!(echo(&v, 6), ("[\"aé\"".into(), true));
        assert_eq!(echo(&v, 5), ("[\"aé".into(), true));
        assert_eq!(echo(&v, 4), ("[\"a".into(), true));
        assert_eq!(echo(&v, 3), ("[\"a".into(), true));
        assert_eq!(echo(&v, 0), (String::new(), true));
        assert_eq!(echo_text_cut(&v, 4), "[\"a…");
        assert_eq!(echo_text_cut(&v, 40), "[\"aé\"]");
    }

    /// `[v, v]` forty times over: 2⁴⁰ numbers in 41 vectors.
    fn doubled<'a>(times: usize) -> Value<'a> {
        let mut v = Value::Number(1.0);
        for _ in 0..times {
            v = Value::vector(vec![v.clone(), v]);
        }
        v
    }

    #[test]
    fn a_shared_value_prints_no_further_than_the_limit() {
        let (text, overflow) = echo(&doubled(40), 1000);
        assert!(overflow);
        assert_eq!(text.len(), 1000);
        assert!(text.starts_with("[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[1, 1], [1, 1]]"));
        let (text, overflow) = echo(&doubled(2), 1000);
        assert_eq!(text, "[[1, 1], [1, 1]]");
        assert!(!overflow);
    }

    #[test]
    fn deep_nesting_does_not_overflow_the_stack() {
        let mut v = Value::Number(1.0);
        let depth = 1_000_000;
        // (Dropping it at the end must not overflow the stack either: see `value`.)
        for _ in 0..depth {
            v = Value::vector(vec![v]);
        }
        let (text, overflow) = echo(&v, 10_000_000);
        assert!(!overflow);
        assert_eq!(text.len(), 2 * depth + 1);
    }
}
