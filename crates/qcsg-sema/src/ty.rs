//! The static types (docs/language.md, "Static checking") and the small inference rules checking relies on.
//!
//! Inference is deliberately partial: whatever is not certain is [`Ty::Any`], and checks only
//! report a mismatch between two *known* types, so a correct program never gets a type error.

use std::fmt;

/// A statically known type of a value.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Ty {
    /// Unknown: could be anything. Never reported.
    Any,
    /// A number.
    Number,
    /// `true` or `false`.
    Bool,
    /// A string.
    String,
    /// `undef`.
    Undef,
    /// A vector, with its length and element type where they are known.
    Vector {
        /// Number of elements, if known.
        len: Option<u32>,
        /// The type every element has ([`Ty::Any`] when mixed or unknown).
        elem: Box<Ty>,
    },
    /// A range `[a : b]` or `[a : s : b]`.
    Range,
    /// A function value (a function literal).
    Function,
    /// A solid (the result of a module instantiation; never a value of an expression).
    Solid,
}

impl Ty {
    /// A vector of unknown length and element type.
    pub fn any_vector() -> Ty {
        Ty::Vector {
            len: None,
            elem: Box::new(Ty::Any),
        }
    }

    /// A vector of `len` numbers.
    pub fn number_vector(len: Option<u32>) -> Ty {
        Ty::Vector {
            len,
            elem: Box::new(Ty::Number),
        }
    }

    /// The type of a value that is one of `self` or `other`: the common type, or [`Ty::Any`].
    pub fn join(&self, other: &Ty) -> Ty {
        match (self, other) {
            (a, b) if a == b => a.clone(),
            (Ty::Vector { len: la, elem: ea }, Ty::Vector { len: lb, elem: eb }) => Ty::Vector {
                len: if la == lb { *la } else { None },
                elem: Box::new(ea.join(eb)),
            },
            _ => Ty::Any,
        }
    }

    /// Whether the type is known (not [`Ty::Any`]).
    pub fn is_known(&self) -> bool {
        !matches!(self, Ty::Any)
    }

    /// Whether no arithmetic operator is defined for a value of this type, whatever the other
    /// operand (OpenSCAD yields `undef` for them).
    pub fn never_arithmetic(&self) -> bool {
        matches!(
            self,
            Ty::String | Ty::Bool | Ty::Undef | Ty::Function | Ty::Range | Ty::Solid
        )
    }

    /// The type with an article, for messages: "a number", "a vector of 4 numbers".
    pub fn describe(&self) -> String {
        match self {
            Ty::Any => "a value".into(),
            Ty::Number => "a number".into(),
            Ty::Bool => "a boolean".into(),
            Ty::String => "a string".into(),
            Ty::Undef => "`undef`".into(),
            Ty::Range => "a range".into(),
            Ty::Function => "a function".into(),
            Ty::Solid => "a solid".into(),
            Ty::Vector { len, elem } => {
                let elems = match elem.as_ref() {
                    Ty::Number => "numbers",
                    Ty::Bool => "booleans",
                    Ty::String => "strings",
                    Ty::Vector { .. } => "vectors",
                    _ => "elements",
                };
                match len {
                    Some(1) if elems == "elements" => "a vector of 1 element".into(),
                    Some(1) => format!("a vector of 1 {}", elems.trim_end_matches('s')),
                    Some(n) => format!("a vector of {n} {elems}"),
                    None if elems == "elements" => "a vector".into(),
                    None => format!("a vector of {elems}"),
                }
            }
        }
    }
}

impl fmt::Display for Ty {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Ty::Any => f.write_str("any"),
            Ty::Number => f.write_str("number"),
            Ty::Bool => f.write_str("bool"),
            Ty::String => f.write_str("string"),
            Ty::Undef => f.write_str("undef"),
            Ty::Range => f.write_str("range"),
            Ty::Function => f.write_str("function"),
            Ty::Solid => f.write_str("solid"),
            Ty::Vector { len, elem } => {
                write!(f, "vector")?;
                match len {
                    Some(n) => write!(f, "[{n}]")?,
                    None => write!(f, "[]")?,
                }
                if elem.is_known() {
                    write!(f, "<{elem}>")?;
                }
                Ok(())
            }
        }
    }
}

/// What a parameter of a built-in module or function accepts. `undef` is always accepted (it
/// means "not given").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParamTy {
    /// Anything.
    Any,
    /// A number.
    Number,
    /// A boolean.
    Bool,
    /// A string.
    String,
    /// A vector of numbers whose length is one of the list (any length when empty).
    NumberVector(&'static [u32]),
    /// A number or a vector of numbers whose length is one of the list (any when empty).
    NumberOrVector(&'static [u32]),
    /// A string or a vector of numbers whose length is one of the list.
    StringOrVector(&'static [u32]),
    /// A boolean or a vector (of booleans).
    BoolOrVector,
    /// A vector of any elements whose length is one of the list (a matrix given by its rows, the
    /// coefficients of a quadric).
    List(&'static [u32]),
    /// A string or a vector of anything.
    StringOrList,
    /// A number, a vector or a range (an index selection such as `children([0, 2])`).
    Selection,
}

/// Why an argument does not fit its parameter.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Mismatch {
    /// The type is wrong; the string says what is expected ("a number").
    Type(&'static str),
    /// A vector of the right kind but the wrong length.
    Length {
        /// The length given.
        given: u32,
        /// The accepted lengths.
        allowed: &'static [u32],
    },
}

impl ParamTy {
    /// What the parameter accepts, for messages.
    pub fn expected(self) -> &'static str {
        match self {
            ParamTy::Any => "any value",
            ParamTy::Number => "a number",
            ParamTy::Bool => "a boolean (`true` or `false`)",
            ParamTy::String => "a string",
            ParamTy::NumberVector(_) => "a vector of numbers",
            ParamTy::NumberOrVector(_) => "a number or a vector of numbers",
            ParamTy::StringOrVector(_) => "a color name or a vector of numbers",
            ParamTy::BoolOrVector => "a boolean or a vector of booleans",
            ParamTy::List(_) => "a vector",
            ParamTy::StringOrList => "a string or a vector",
            ParamTy::Selection => "a number, a vector or a range",
        }
    }

    /// Checks a statically inferred argument type; `Ok` unless it is definitely wrong.
    pub fn check(self, ty: &Ty) -> Result<(), Mismatch> {
        if matches!(ty, Ty::Any | Ty::Undef) {
            return Ok(());
        }
        let wrong = Err(Mismatch::Type(self.expected()));
        let vector = |ty: &Ty, lens: &'static [u32], numeric: bool| -> Result<(), Mismatch> {
            let Ty::Vector { len, elem } = ty else {
                return wrong.clone();
            };
            if numeric && elem.is_known() && **elem != Ty::Number {
                return wrong.clone();
            }
            match len {
                Some(n) if !lens.is_empty() && !lens.contains(n) => Err(Mismatch::Length {
                    given: *n,
                    allowed: lens,
                }),
                _ => Ok(()),
            }
        };
        match self {
            ParamTy::Any => Ok(()),
            ParamTy::Number => {
                if *ty == Ty::Number {
                    Ok(())
                } else {
                    wrong
                }
            }
            ParamTy::Bool => {
                if *ty == Ty::Bool {
                    Ok(())
                } else {
                    wrong
                }
            }
            ParamTy::String => {
                if *ty == Ty::String {
                    Ok(())
                } else {
                    wrong
                }
            }
            ParamTy::NumberVector(lens) => vector(ty, lens, true),
            ParamTy::NumberOrVector(lens) => {
                if *ty == Ty::Number {
                    Ok(())
                } else {
                    vector(ty, lens, true)
                }
            }
            ParamTy::StringOrVector(lens) => {
                if *ty == Ty::String {
                    Ok(())
                } else {
                    vector(ty, lens, true)
                }
            }
            ParamTy::BoolOrVector => {
                if *ty == Ty::Bool || matches!(ty, Ty::Vector { .. }) {
                    Ok(())
                } else {
                    wrong
                }
            }
            ParamTy::List(lens) => vector(ty, lens, false),
            ParamTy::StringOrList => {
                if matches!(ty, Ty::String | Ty::Vector { .. }) {
                    Ok(())
                } else {
                    wrong
                }
            }
            ParamTy::Selection => {
                if matches!(ty, Ty::Number | Ty::Vector { .. } | Ty::Range) {
                    Ok(())
                } else {
                    wrong
                }
            }
        }
    }
}

/// Formats accepted lengths as "2 or 3".
pub(crate) fn format_lengths(lens: &[u32]) -> String {
    match lens {
        [] => "any".into(),
        [one] => one.to_string(),
        [init @ .., last] => {
            let init: Vec<String> = init.iter().map(u32::to_string).collect();
            format!("{} or {last}", init.join(", "))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn join_keeps_what_both_share() {
        let v3 = Ty::number_vector(Some(3));
        assert_eq!(v3.join(&v3), v3);
        assert_eq!(
            v3.join(&Ty::number_vector(Some(2))),
            Ty::number_vector(None)
        );
        assert_eq!(Ty::Number.join(&Ty::String), Ty::Any);
    }

    #[test]
    fn checks_report_only_definite_mismatches() {
        let vec3 = ParamTy::NumberVector(&[2, 3]);
        assert!(vec3.check(&Ty::Any).is_ok());
        assert!(vec3.check(&Ty::Undef).is_ok());
        assert!(vec3.check(&Ty::number_vector(None)).is_ok());
        assert!(vec3.check(&Ty::any_vector()).is_ok());
        assert_eq!(
            vec3.check(&Ty::String),
            Err(Mismatch::Type("a vector of numbers"))
        );
        assert_eq!(
            vec3.check(&Ty::number_vector(Some(4))),
            Err(Mismatch::Length {
                given: 4,
                allowed: &[2, 3]
            })
        );
        assert!(ParamTy::Number.check(&Ty::number_vector(Some(2))).is_err());
        assert_eq!(format_lengths(&[2, 3]), "2 or 3");
        assert_eq!(
            Ty::number_vector(Some(4)).describe(),
            "a vector of 4 numbers"
        );
    }
}
