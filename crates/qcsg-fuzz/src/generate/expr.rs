//! Expressions of generated programs: literals with ordinary and extreme values, operators,
//! calls of built-in and generated functions, indexing, `let`, function literals, `assert` and
//! `echo` expressions, ranges and list comprehensions.
//!
//! Most expressions are made for a wanted [`Kind`] (a number where a radius goes, a 3-vector
//! where a translation goes), so that most generated programs pass the checker and reach the
//! evaluator, the sampler and the ray tracer; a few are deliberately of the wrong kind.

use qcsg_sema::builtins::{self, BuiltinFunction, Returns};
use qcsg_sema::ty::ParamTy;

use super::Generator;

/// What an expression is meant to evaluate to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A number.
    Num,
    /// A vector of three numbers.
    Vec3,
    /// A vector of numbers of some length.
    NumList,
    /// A boolean.
    Bool,
    /// A string.
    Str,
    /// Anything.
    Any,
}

/// Numbers at the edges of f64 and of the language's arithmetic.
const EXTREME_NUMBERS: &[&str] = &[
    "0",
    "-0",
    "1e308",
    "-1e308",
    "1e309",
    "1e-308",
    "5e-324",
    "1e-320",
    "4.9406564584124654e-324",
    "1.7976931348623157e308",
    "9007199254740993",
    "18446744073709551616",
    "1e100",
    "1e-100",
    "1e-9",
    "1e9",
    "1e15",
    "0.1",
    "123456789012345678901234567890",
    "0.000000000000000000000000000001",
    "1e-15",
    "2147483648",
    "4294967296",
];

/// Expressions that evaluate to NaN or infinity.
const NON_FINITE: &[&str] = &[
    "0/0",
    "1/0",
    "-1/0",
    "sqrt(-1)",
    "acos(2)",
    "asin(-3)",
    "ln(0)",
    "log(-1)",
    "1e308*10",
    "(1e308*10)-(1e308*10)",
    "pow(-8, 1/3)",
    "exp(1000)",
    "tan(90)",
    "0*(1/0)",
];

/// Strings with escapes, non-ASCII text and characters editors and terminals find hard.
const STRINGS: &[&str] = &[
    "\"\"",
    "\"a\"",
    "\"red\"",
    "\"blue\"",
    "\"#ff000080\"",
    "\"hello, world\"",
    "\"tab\\there\"",
    "\"quote \\\" and backslash \\\\\"",
    "\"\\x41\\x7f\"",
    "\"\\u263A \\u00e9\"",
    "\"ünïcödé ✓ 😀 𝔘\"",
    "\"line\\nbreak\\r\"",
    "\"\u{202e}rtl\u{202c}\"",
    "\"\u{feff}bom\"",
    "\"%s {} $fn\"",
];

/// Strings the lexer must reject (invalid escapes), drawn rarely.
const BAD_STRINGS: &[&str] = &[
    "\"\\u10FFFF\"",
    "\"\\u0000\"",
    "\"\\x00\"",
    "\"\\q unknown escape\"",
];

impl Generator<'_> {
    /// An expression of `kind`, with the nesting budget left at this depth.
    pub(super) fn expr(&mut self, kind: Kind) -> String {
        self.depth += 1;
        let text = if self.depth > self.max_depth || self.dice.chance(0.35) {
            self.leaf(kind)
        } else {
            self.compound(kind)
        };
        self.depth -= 1;
        text
    }

    /// A literal or a name.
    fn leaf(&mut self, kind: Kind) -> String {
        match kind {
            Kind::Num => {
                if let Some(name) = self.scope_var(Kind::Num)
                    && self.dice.chance(0.4)
                {
                    return name;
                }
                self.number()
            }
            Kind::Vec3 => {
                if let Some(name) = self.scope_var(Kind::Vec3)
                    && self.dice.chance(0.4)
                {
                    return name;
                }
                format!("[{}, {}, {}]", self.number(), self.number(), self.number())
            }
            Kind::NumList => {
                let n = self.dice.between(0, 5);
                let items: Vec<String> = (0..n).map(|_| self.number()).collect();
                format!("[{}]", items.join(", "))
            }
            Kind::Bool => (*self.dice.pick(&["true", "false"])).to_owned(),
            Kind::Str if self.dice.chance(0.01) => (*self.dice.pick(BAD_STRINGS)).to_owned(),
            Kind::Str => (*self.dice.pick(STRINGS)).to_owned(),
            Kind::Any => match self.dice.below(9) {
                0 => "undef".to_owned(),
                1 => self.leaf(Kind::Str),
                2 => self.leaf(Kind::Bool),
                3 => self.leaf(Kind::Vec3),
                4 => (*self
                    .dice
                    .pick(&["$fn", "$fa", "$fs", "$t", "$children", "$preview"]))
                .to_owned(),
                5 => "PI".to_owned(),
                6 => self
                    .scope_var(Kind::Any)
                    .unwrap_or_else(|| "undef".to_owned()),
                _ => self.number(),
            },
        }
    }

    /// A number literal: mostly a size a scene would use, sometimes an extreme one.
    pub(super) fn number(&mut self) -> String {
        match self.dice.below(80) {
            0 => (*self.dice.pick(EXTREME_NUMBERS)).to_owned(),
            1 => format!("({})", self.dice.pick(NON_FINITE)),
            2..=4 => format!("-{}", self.dice.between(0, 20)),
            5..=8 => format!("{:.3}", self.dice.unit() * 2.0),
            9..=20 => format!("{}", self.dice.between(1, 20)),
            _ => format!("{:.2}", 0.5 + self.dice.unit() * 15.0),
        }
    }

    /// An operator, call or other composite expression.
    fn compound(&mut self, kind: Kind) -> String {
        match kind {
            Kind::Num => match self.dice.below(14) {
                0..=2 => {
                    let op = *self.dice.pick(&["+", "-", "*", "/", "%", "^"]);
                    format!("({} {op} {})", self.expr(Kind::Num), self.expr(Kind::Num))
                }
                3 => format!("-({})", self.expr(Kind::Num)),
                4 => format!("({})", self.expr(Kind::Num)),
                5 => format!(
                    "({} ? {} : {})",
                    self.expr(Kind::Bool),
                    self.expr(Kind::Num),
                    self.expr(Kind::Num)
                ),
                6 | 7 => self.builtin_call(Returns::Number),
                8 => self.user_call(),
                9 => {
                    let index = if self.dice.chance(0.97) {
                        *self.dice.pick(&["0", "1", "2"])
                    } else {
                        *self.dice.pick(&["3", "-1", "0.5", "1e9", "\"x\""])
                    };
                    format!("{}[{index}]", self.expr(Kind::Vec3))
                }
                10 => {
                    let member = if self.dice.chance(0.98) {
                        *self.dice.pick(&["x", "y", "z"])
                    } else {
                        *self.dice.pick(&["w", "a"])
                    };
                    format!("{}.{member}", self.expr(Kind::Vec3))
                }
                11 => format!("({})", self.let_expr(Kind::Num)),
                12 => format!(
                    "(function ({p}) {p} * {}) ({})",
                    self.expr(Kind::Num),
                    self.expr(Kind::Num),
                    p = self.fresh_name("p")
                ),
                _ => format!("({})", self.assert_or_echo(Kind::Num)),
            },
            Kind::Vec3 => match self.dice.below(8) {
                0 | 1 => format!(
                    "[{}, {}, {}]",
                    self.expr(Kind::Num),
                    self.expr(Kind::Num),
                    self.expr(Kind::Num)
                ),
                2 => {
                    let op = *self.dice.pick(&["+", "-"]);
                    format!("({} {op} {})", self.expr(Kind::Vec3), self.expr(Kind::Vec3))
                }
                3 => format!("({} * {})", self.expr(Kind::Num), self.expr(Kind::Vec3)),
                4 => format!(
                    "cross({}, {})",
                    self.expr(Kind::Vec3),
                    self.expr(Kind::Vec3)
                ),
                5 => format!(
                    "[for ({v} = [0 : 2]) {}]",
                    self.expr(Kind::Num),
                    v = self.fresh_name("i")
                ),
                6 => format!("({})", self.let_expr(Kind::Vec3)),
                _ => format!(
                    "({} ? {} : {})",
                    self.expr(Kind::Bool),
                    self.expr(Kind::Vec3),
                    self.expr(Kind::Vec3)
                ),
            },
            Kind::NumList => match self.dice.below(6) {
                0 => self.comprehension(),
                1 => self.range(),
                2 => format!(
                    "concat({}, {})",
                    self.expr(Kind::NumList),
                    self.expr(Kind::NumList)
                ),
                3 => format!("rands(0, 10, {})", self.dice.between(0, 20)),
                4 => self.expr(Kind::Vec3),
                _ => self.leaf(Kind::NumList),
            },
            Kind::Bool => match self.dice.below(6) {
                0 | 1 => {
                    let op = *self.dice.pick(&["<", "<=", ">", ">=", "==", "!="]);
                    format!("({} {op} {})", self.expr(Kind::Num), self.expr(Kind::Num))
                }
                2 => {
                    let op = *self.dice.pick(&["&&", "||"]);
                    format!("({} {op} {})", self.expr(Kind::Bool), self.expr(Kind::Bool))
                }
                3 => format!("!({})", self.expr(Kind::Bool)),
                4 => format!(
                    "{}({})",
                    self.dice.pick(&[
                        "is_undef",
                        "is_num",
                        "is_bool",
                        "is_string",
                        "is_list",
                        "is_function"
                    ]),
                    self.expr(Kind::Any)
                ),
                _ => self.leaf(Kind::Bool),
            },
            Kind::Str => match self.dice.below(4) {
                0 => format!("str({}, {})", self.expr(Kind::Any), self.expr(Kind::Num)),
                1 => format!("chr({})", self.expr(Kind::Num)),
                2 => self.builtin_call(Returns::String),
                _ => self.leaf(Kind::Str),
            },
            Kind::Any => match self.dice.below(10) {
                0 => self.comprehension(),
                1 => self.range(),
                2 => {
                    let returns = *self.dice.pick(&[
                        Returns::Any,
                        Returns::Number,
                        Returns::String,
                        Returns::Bool,
                    ]);
                    self.builtin_call(returns)
                }
                3 => format!("[{}, {}]", self.expr(Kind::Any), self.expr(Kind::Any)),
                4 => format!(
                    "function ({}) {}",
                    self.fresh_name("q"),
                    self.expr(Kind::Any)
                ),
                5 => self.let_expr(Kind::Any),
                6 => self.assert_or_echo(Kind::Any),
                _ => {
                    let kind = *self
                        .dice
                        .pick(&[Kind::Num, Kind::Vec3, Kind::Bool, Kind::Str]);
                    self.compound(kind)
                }
            },
        }
    }

    /// `[a : b]` or `[a : step : b]`, sometimes empty, huge or with a zero step.
    fn range(&mut self) -> String {
        match self.dice.below(6) {
            0 => format!(
                "[0 : {}]",
                self.dice.pick(&["1e9", "1e15", "-5", "0", "1/0", "0/0"])
            ),
            1 => format!(
                "[0 : {} : 10]",
                self.dice.pick(&["0", "-1", "1e-9", "0/0", "1e300"])
            ),
            2 => format!(
                "[{} : {} : {}]",
                self.number(),
                self.number(),
                self.number()
            ),
            _ => format!(
                "[{} : {}]",
                self.dice.between(0, 3),
                self.dice.between(0, 12)
            ),
        }
    }

    /// A list comprehension with `for` (both forms), `if`/`else`, `let` and `each`.
    fn comprehension(&mut self) -> String {
        let v = self.fresh_name("i");
        let body = match self.dice.below(7) {
            0 => format!("if ({v} % 2 == 0) {v} else -{v}"),
            1 => format!("let (w = {v} * 2) w"),
            2 => format!("each [{v}, {v}]"),
            3 => format!("for (j = [0 : {v}]) j"),
            4 => format!("({})", "each [1, 2]"),
            5 => format!("{v} * {}", self.expr(Kind::Num)),
            _ => v.clone(),
        };
        match self.dice.below(4) {
            0 => format!(
                "[for ({v} = 0; {v} < {}; {v} = {v} + 1) {body}]",
                self.dice.between(0, 12)
            ),
            1 => format!("[for ({v} = {}) {body}]", self.expr(Kind::NumList)),
            _ => format!("[for ({v} = {}) {body}]", self.range()),
        }
    }

    /// `let (x = …) body`.
    fn let_expr(&mut self, kind: Kind) -> String {
        let name = self.fresh_name("l");
        let value = self.expr(Kind::Num);
        self.push_var(&name, Kind::Num);
        let body = self.expr(kind);
        self.pop_var();
        format!("let ({name} = {value}) {body}")
    }

    /// `assert(…) body` or `echo(…) body`.
    fn assert_or_echo(&mut self, kind: Kind) -> String {
        let body = self.expr(kind);
        if self.dice.chance(0.5) {
            format!(
                "echo({}, {}) {body}",
                self.expr(Kind::Any),
                self.expr(Kind::Any)
            )
        } else {
            let condition = if self.dice.chance(0.9) {
                format!("true || {}", self.expr(Kind::Bool))
            } else {
                self.expr(Kind::Bool)
            };
            format!("assert({condition}, {}) {body}", self.leaf(Kind::Str))
        }
    }

    /// A call of a built-in function returning roughly `returns`, its arguments of the
    /// parameters' types (a wrong one now and then).
    fn builtin_call(&mut self, returns: Returns) -> String {
        if returns == Returns::Number && self.dice.chance(0.7) {
            // Mostly functions defined everywhere, so that the program evaluates.
            let name = *self
                .dice
                .pick(&["abs", "sin", "cos", "floor", "ceil", "round", "atan"]);
            return format!("{name}({})", self.expr(Kind::Num));
        }
        let candidates: Vec<&BuiltinFunction> = builtins::FUNCTIONS
            .iter()
            .filter(|f| f.returns == returns || returns == Returns::Any)
            .collect();
        let Some(function) = candidates.get(self.dice.below(candidates.len())).copied() else {
            return self.number();
        };
        let mut args: Vec<String> = Vec::new();
        for (i, param) in function.params.iter().enumerate() {
            if i >= function.min_args && self.dice.chance(0.5) {
                break;
            }
            args.push(self.argument_of(param.ty));
        }
        if let Some(rest) = function.rest {
            for _ in 0..self.dice.between(function.min_args.max(1), 4) {
                args.push(self.argument_of(rest));
            }
        }
        if self.dice.chance(0.005) {
            args.push(self.expr(Kind::Any));
        }
        format!("{}({})", function.name, args.join(", "))
    }

    /// A value for a parameter of type `ty`.
    pub(super) fn argument_of(&mut self, ty: ParamTy) -> String {
        if self.dice.chance(0.005) {
            return self.expr(Kind::Any);
        }
        // Mostly literals: arbitrary arithmetic overflows or divides by zero often enough to
        // keep most programs from evaluating.
        let literal = self.dice.chance(0.7);
        match ty {
            ParamTy::Number if literal => self.number(),
            ParamTy::Number => self.expr(Kind::Num),
            ParamTy::Bool | ParamTy::BoolOrVector => self.expr(Kind::Bool),
            ParamTy::String => self.expr(Kind::Str),
            ParamTy::NumberVector(lengths)
            | ParamTy::NumberOrVector(lengths)
            | ParamTy::List(lengths) => {
                if matches!(ty, ParamTy::NumberOrVector(_)) && self.dice.chance(0.4) {
                    return self.expr(Kind::Num);
                }
                match lengths.get(self.dice.below(lengths.len())) {
                    Some(3) if literal => {
                        format!("[{}, {}, {}]", self.number(), self.number(), self.number())
                    }
                    Some(3) => self.expr(Kind::Vec3),
                    Some(&n) if matches!(ty, ParamTy::List(_)) && n <= 4 => {
                        // A matrix given by its rows.
                        let rows: Vec<String> = (0..n)
                            .map(|_| {
                                let row: Vec<String> = (0..n).map(|_| self.number()).collect();
                                format!("[{}]", row.join(", "))
                            })
                            .collect();
                        format!("[{}]", rows.join(", "))
                    }
                    Some(&n) => {
                        let items: Vec<String> = (0..n.min(16))
                            .map(|_| {
                                if literal {
                                    self.number()
                                } else {
                                    self.expr(Kind::Num)
                                }
                            })
                            .collect();
                        format!("[{}]", items.join(", "))
                    }
                    None => self.expr(Kind::NumList),
                }
            }
            ParamTy::StringOrVector(_) => {
                if self.dice.chance(0.5) {
                    self.expr(Kind::Str)
                } else {
                    format!(
                        "[{:.2}, {:.2}, {:.2}, 1]",
                        self.dice.unit(),
                        self.dice.unit(),
                        self.dice.unit()
                    )
                }
            }
            ParamTy::StringOrList => {
                if self.dice.chance(0.5) {
                    self.expr(Kind::Str)
                } else {
                    self.expr(Kind::NumList)
                }
            }
            ParamTy::Selection => self
                .dice
                .pick(&["0", "[0, 1]", "[0 : 1]", "-1", "99"])
                .to_string(),
            ParamTy::Any => self.expr(Kind::Any),
        }
    }

    /// A call of a function generated earlier in the program, with its arity (or not).
    fn user_call(&mut self) -> String {
        if self.scope.functions.is_empty() {
            return self.builtin_call(Returns::Number);
        }
        let (name, arity) =
            self.scope.functions[self.dice.below(self.scope.functions.len())].clone();
        let n = if self.dice.chance(0.9) {
            arity
        } else {
            self.dice.between(0, arity + 2)
        };
        let args: Vec<String> = (0..n).map(|_| self.expr(Kind::Num)).collect();
        format!("{name}({})", args.join(", "))
    }
}
