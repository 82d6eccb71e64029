//! A grammar-aware generator of random qcsg programs (grammar/qcsg.ebnf).
//!
//! [`program`] writes a program statement by statement: assignments, module and function
//! definitions (recursive ones too), instantiations of every built-in module from the sema's own
//! tables ([`qcsg_sema::builtins::MODULES`], so the generator follows the language as it grows),
//! transforms and booleans with children, `if`/`else`, `for`, `let`, `intersection_for`,
//! modifiers, `echo` and `assert`, `include` and `use` of the library files in the run's
//! directory (and of paths that are not files), and comments. Expressions are in [`expr`].
//!
//! Values are mostly those a scene uses, so that most programs pass the checker and reach the
//! sampler and the ray tracer; now and then they are extreme (huge, tiny, NaN-producing), and a
//! few programs carry one deliberately extreme construct ([`Generator::extreme`]): deep nesting
//! of calls, brackets, operators or `if`s, long identifiers, strings, lines and statement
//! lists, repetition that grows values exponentially.

mod expr;

use qcsg_sema::builtins::{self, ModuleKind};

use crate::dice::Dice;
pub use expr::Kind;

/// Paths an `include <…>` / `use <…>` of a generated program may name: the library files
/// [`crate::libs`] writes into the run's directory, and paths that are no source file.
pub const INCLUDE_PATHS: &[&str] = &[
    "lib.qcsg",
    "lib.qcsg",
    "lib.qcsg",
    "shapes.scad",
    "loop_a.qcsg",
    "self.qcsg",
    "broken.qcsg",
    "empty.qcsg",
    "binary.qcsg",
    "missing.qcsg",
    "subdir",
    "subdir/../lib.qcsg",
    "/dev/null",
    "/dev/zero",
    "",
    "lib.qcsg\u{0}",
];

/// What the program has defined so far, for references that resolve.
#[derive(Default)]
struct Scope {
    /// Variables and their kinds, innermost last.
    vars: Vec<(String, Kind)>,
    /// Functions and their arities.
    functions: Vec<(String, usize)>,
    /// Modules and their arities.
    modules: Vec<(String, usize)>,
    /// Whether statements are inside a module body (`children()` is meaningful).
    in_module: bool,
}

/// The state of one program being written.
pub struct Generator<'a> {
    dice: &'a mut Dice,
    scope: Scope,
    /// Current expression or statement nesting.
    depth: usize,
    /// Nesting beyond which only leaves are written.
    max_depth: usize,
    /// Statements still allowed (bounds the size of a program).
    budget: usize,
    /// Counter for fresh names.
    names: usize,
}

/// A random program.
pub fn program(dice: &mut Dice) -> String {
    let max_depth = dice.between(2, 5);
    let budget = dice.skewed(120).max(3);
    let mut generator = Generator {
        dice,
        scope: Scope::default(),
        depth: 0,
        max_depth,
        budget,
        names: 0,
    };
    let mut out = String::new();
    if generator.dice.chance(0.2) {
        out.push_str("// generated\n/// doc comment\n");
    }
    let statements = generator.dice.between(1, 12);
    for _ in 0..statements {
        let stmt = generator.statement();
        out.push_str(&stmt);
        out.push('\n');
    }
    // Most programs end with a solid to sample and render.
    if generator.dice.chance(0.8) {
        let solid = generator.solid();
        out.push_str(&solid);
        out.push('\n');
    }
    if generator.dice.chance(0.06) {
        let extreme = generator.extreme();
        out.push_str(&extreme);
        out.push('\n');
    }
    out
}

impl Generator<'_> {
    /// A fresh name with a readable prefix.
    fn fresh_name(&mut self, prefix: &str) -> String {
        self.names += 1;
        format!("{prefix}{}", self.names)
    }

    /// A variable in scope of `kind` (any kind for [`Kind::Any`]).
    fn scope_var(&mut self, kind: Kind) -> Option<String> {
        let matching: Vec<&String> = self
            .scope
            .vars
            .iter()
            .filter(|(_, k)| kind == Kind::Any || *k == kind)
            .map(|(name, _)| name)
            .collect();
        if matching.is_empty() {
            return None;
        }
        Some(matching[self.dice.below(matching.len())].clone())
    }

    fn push_var(&mut self, name: &str, kind: Kind) {
        self.scope.vars.push((name.to_owned(), kind));
    }

    fn pop_var(&mut self) {
        self.scope.vars.pop();
    }

    /// One statement.
    fn statement(&mut self) -> String {
        if self.budget == 0 || self.depth > self.max_depth + 2 {
            return self.primitive();
        }
        self.budget -= 1;
        // What a nested statement defines is not visible after it (bodies are scopes).
        let nested = self.depth > 0;
        let marks = (
            self.scope.vars.len(),
            self.scope.functions.len(),
            self.scope.modules.len(),
        );
        self.depth += 1;
        let text = match self.dice.below(24) {
            0..=3 => self.assignment(),
            4 => self.function_definition(),
            5 => self.module_definition(),
            6..=9 => self.solid(),
            10 => self.if_statement(),
            11 => self.for_statement(),
            12 => format!(
                "let ({} = {}) {}",
                self.fresh_name("k"),
                self.expr(Kind::Num),
                self.statement()
            ),
            13 => format!("echo({}, {});", self.expr(Kind::Any), self.expr(Kind::Any)),
            14 => {
                let condition = if self.dice.chance(0.9) {
                    "true"
                } else {
                    "false"
                };
                format!(
                    "assert({condition} || {}, {});",
                    self.expr(Kind::Bool),
                    self.expr(Kind::Str)
                )
            }
            15 => {
                let keyword = *self.dice.pick(&["include", "use"]);
                let path = if self.dice.chance(0.8) {
                    *self.dice.pick(&["lib.qcsg", "shapes.scad"])
                } else {
                    *self.dice.pick(INCLUDE_PATHS)
                };
                format!("{keyword} <{path}>")
            }
            16 => {
                let modifier = *self.dice.pick(&["*", "!", "#", "%"]);
                format!("{modifier}{}", self.statement())
            }
            17 => format!("{{ {} {} }}", self.statement(), self.statement()),
            18 => ";".to_owned(),
            19 if self.scope.in_module => (*self.dice.pick(&[
                "children();",
                "children(0);",
                "children([0 : $children - 1]);",
                "children(99);",
                "echo($children);",
            ]))
            .to_owned(),
            20 => self.user_module_call(),
            21 => format!("/* {} */ {}", "block comment", self.statement()),
            _ => self.solid(),
        };
        self.depth -= 1;
        if nested {
            self.scope.vars.truncate(marks.0);
            self.scope.functions.truncate(marks.1);
            self.scope.modules.truncate(marks.2);
        }
        text
    }

    /// `name = expr;`, sometimes reassigning a name or assigning a special variable.
    fn assignment(&mut self) -> String {
        let kind = *self.dice.pick(&[
            Kind::Num,
            Kind::Num,
            Kind::Vec3,
            Kind::Bool,
            Kind::Str,
            Kind::Any,
        ]);
        let value = self.expr(kind);
        let name = match self.dice.below(10) {
            0 => (*self.dice.pick(&["$fn", "$fa", "$fs", "$t", "$my_special"])).to_owned(),
            // A reassignment, of the same kind so that uses still check.
            1 => self.scope_var(kind).unwrap_or_else(|| self.fresh_name("v")),
            _ => self.fresh_name("v"),
        };
        self.push_var(&name, kind);
        format!("{name} = {value};")
    }

    /// `function f(a, b = …) = body;`, sometimes recursive (with or without an end).
    fn function_definition(&mut self) -> String {
        let name = self.fresh_name("f");
        let arity = self.dice.between(0, 3);
        let params: Vec<String> = (0..arity).map(|i| format!("a{i}")).collect();
        for p in &params {
            self.push_var(p, Kind::Num);
        }
        let body = match self.dice.below(6) {
            // Tail recursion with an end, which runs as a loop.
            0 if arity > 0 => format!("a0 <= 0 ? 0 : {name}(a0 - 1{})", ", a0".repeat(arity - 1)),
            // Recursion without an end: the recursion or iteration limit must stop it.
            1 if arity > 0 => format!("1 + {name}(a0{})", ", a0".repeat(arity - 1)),
            // Exponential recursion with an end.
            2 if arity > 0 => format!(
                "a0 <= 0 ? 1 : {name}(a0 - 1{rest}) + {name}(a0 - 1{rest})",
                rest = ", a0".repeat(arity - 1)
            ),
            _ => self.expr(Kind::Num),
        };
        for _ in &params {
            self.pop_var();
        }
        let params: Vec<String> = params
            .into_iter()
            .map(|p| {
                if self.dice.chance(0.3) {
                    format!("{p} = {}", self.number())
                } else {
                    p
                }
            })
            .collect();
        self.scope.functions.push((name.clone(), arity));
        format!("function {name}({}) = {body};", params.join(", "))
    }

    /// `module m(a, …) { … }`, its body using `children()` and sometimes itself.
    fn module_definition(&mut self) -> String {
        let name = self.fresh_name("m");
        let arity = self.dice.between(0, 3);
        let params: Vec<String> = (0..arity).map(|i| format!("b{i}")).collect();
        for p in &params {
            self.push_var(p, Kind::Num);
        }
        let was_in_module = std::mem::replace(&mut self.scope.in_module, true);
        let mut body = Vec::new();
        for _ in 0..self.dice.between(1, 4) {
            body.push(self.statement());
        }
        if arity > 0 && self.dice.chance(0.2) {
            // Recursion, ending (or not) on the first parameter.
            let rest = ", b0".repeat(arity - 1);
            body.push(if self.dice.chance(0.7) {
                format!("if (b0 > 0) translate([1, 0, 0]) {name}(b0 - 1{rest});")
            } else {
                format!("{name}(b0{rest});")
            });
        }
        self.scope.in_module = was_in_module;
        for _ in &params {
            self.pop_var();
        }
        self.scope.modules.push((name.clone(), arity));
        format!(
            "module {name}({}) {{\n{}\n}}",
            params.join(", "),
            body.join("\n")
        )
    }

    /// A call of a module defined earlier, possibly with children.
    fn user_module_call(&mut self) -> String {
        if self.scope.modules.is_empty() {
            return self.solid();
        }
        let (name, arity) = self.scope.modules[self.dice.below(self.scope.modules.len())].clone();
        let args: Vec<String> = (0..arity).map(|_| self.expr(Kind::Num)).collect();
        if self.dice.chance(0.4) {
            format!("{name}({}) {}", args.join(", "), self.statement())
        } else {
            format!("{name}({});", args.join(", "))
        }
    }

    /// `if (…) … else …`.
    fn if_statement(&mut self) -> String {
        let condition = self.expr(Kind::Bool);
        let then = self.statement();
        if self.dice.chance(0.5) {
            format!("if ({condition}) {then} else {}", self.statement())
        } else {
            format!("if ({condition}) {then}")
        }
    }

    /// `for (…) …` over a range or a list, sometimes with two loop variables.
    fn for_statement(&mut self) -> String {
        let v = self.fresh_name("i");
        let over = match self.dice.below(4) {
            0 => format!("[0 : {}]", self.dice.between(0, 6)),
            1 => format!(
                "[0 : {} : {}]",
                self.dice.between(1, 3),
                self.dice.between(0, 12)
            ),
            2 => self.expr(Kind::NumList),
            _ => format!("[{}, {}]", self.expr(Kind::Vec3), self.expr(Kind::Vec3)),
        };
        self.push_var(&v, Kind::Num);
        let body = self.statement();
        self.pop_var();
        let keyword = if self.dice.chance(0.15) {
            "intersection_for"
        } else {
            "for"
        };
        if self.dice.chance(0.15) {
            format!("{keyword} ({v} = {over}, w{v} = [0 : 1]) {body}")
        } else {
            format!("{keyword} ({v} = {over}) {body}")
        }
    }

    /// A solid: a primitive, or a transform or boolean of children.
    fn solid(&mut self) -> String {
        if self.depth > self.max_depth || self.dice.chance(0.4) {
            return self.primitive();
        }
        let module = self.pick_module(&[
            ModuleKind::Transform,
            ModuleKind::Boolean,
            ModuleKind::Other,
        ]);
        match module.name {
            "echo" | "assert" | "children" => return self.primitive(),
            _ => {}
        }
        let args = self.arguments(module);
        self.depth += 1;
        let children = match self.dice.below(4) {
            0 => format!(" {}", self.solid()),
            1 => " {}".to_owned(),
            _ => {
                let n = self.dice.between(1, 4);
                let parts: Vec<String> = (0..n).map(|_| self.solid()).collect();
                format!(" {{\n{}\n}}", parts.join("\n"))
            }
        };
        self.depth -= 1;
        format!("{}({args}){children}", module.name)
    }

    /// A built-in primitive with arguments of its parameters' types. Those that read a file
    /// or take a list of points or faces are errors with almost any generated arguments, so
    /// they are picked rarely: the programs should mostly reach the deep stages.
    fn primitive(&mut self) -> String {
        let module = loop {
            let module = self.pick_module(&[ModuleKind::Primitive]);
            if !RARELY_VALID_PRIMITIVES.contains(&module.name) || self.dice.chance(0.1) {
                break module;
            }
        };
        let args = self.arguments(module);
        format!("{}({args});", module.name)
    }

    /// A built-in module of one of `kinds`.
    fn pick_module(&mut self, kinds: &[ModuleKind]) -> &'static builtins::BuiltinModule {
        let candidates: Vec<&'static builtins::BuiltinModule> = builtins::MODULES
            .iter()
            .filter(|m| kinds.contains(&m.kind))
            .collect();
        candidates[self.dice.below(candidates.len())]
    }

    /// Arguments for a built-in module: positional then named, each parameter now and then
    /// left out, plus a `$`-argument or an unknown name once in a while.
    fn arguments(&mut self, module: &builtins::BuiltinModule) -> String {
        let mut args = Vec::new();
        let mut positional = true;
        for (i, param) in module.params.iter().enumerate() {
            // The first parameter is what most calls give (`translate(v)`); the others vary.
            let leave_out = if i == 0 { 0.05 } else { 0.45 };
            if !param.required && self.dice.chance(leave_out) {
                positional = false;
                continue;
            }
            let value = match param.name {
                // Values outside a parameter's domain are errors at run time: mostly valid ones.
                "sheets" if self.dice.chance(0.95) => self.dice.pick(&["1", "2"]).to_string(),
                _ => self.argument_of(param.ty),
            };
            if positional && param.positional && self.dice.chance(0.6) {
                args.push(value);
            } else {
                positional = false;
                args.push(format!("{} = {value}", param.name));
            }
        }
        if self.dice.chance(0.1) {
            args.push(format!("$fn = {}", self.dice.between(0, 64)));
        }
        if self.dice.chance(0.003) {
            args.push(format!("bogus = {}", self.number()));
        }
        args.join(", ")
    }

    /// One deliberately extreme construct.
    fn extreme(&mut self) -> String {
        let n = self.dice.skewed(400);
        match self.dice.below(14) {
            0 => format!("{}sphere(1);{}", "union() { ".repeat(n), " }".repeat(n)),
            1 => format!("x = {}1{};", "(".repeat(n), ")".repeat(n)),
            2 => format!("x = {}1{};", "[".repeat(n), "]".repeat(n)),
            3 => format!("x = {}1;", "-".repeat(n)),
            4 => format!("x = 1{};", " + 1".repeat(n * 50)),
            5 => format!("x = {};", "2 ^ ".repeat(n) + "2"),
            6 => format!("{}cube(1);", "if (true) ".repeat(n)),
            7 => {
                let name = format!("id_{}", "a".repeat(self.dice.skewed(200_000)));
                format!("{name} = 1;\necho({name}b);\ncube({name});")
            }
            8 => format!(
                "s = \"{}\";\necho(len(s));",
                "x".repeat(self.dice.skewed(1_000_000))
            ),
            9 => format!("{}\n", "cube(1); ".repeat(n * 20)),
            10 => format!(
                "function d(v, n) = n == 0 ? v : d([v, v], n - 1);\necho(len(d(1, {})));",
                self.dice.between(5, 40)
            ),
            11 => format!(
                "function s(t, n) = n == 0 ? t : s(str(t, t), n - 1);\necho(len(s(\"ab\", {})));",
                self.dice.between(5, 40)
            ),
            12 => format!("x = {}1{};", "let (a = 1) ".repeat(n), ""),
            _ => format!(
                "for (i = [0 : {}]) translate([i, 0, 0]) sphere(0.5);",
                self.dice.skewed(200_000)
            ),
        }
    }
}

/// Primitives whose generated arguments are almost never valid: files to read, lists of
/// points and faces.
const RARELY_VALID_PRIMITIVES: &[&str] = &[
    "polygon",
    "polyhedron",
    "import",
    "import_stl",
    "import_off",
    "import_dxf",
    "surface",
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn programs_are_deterministic_per_seed() {
        assert_eq!(program(&mut Dice::new(5)), program(&mut Dice::new(5)));
        assert_ne!(program(&mut Dice::new(5)), program(&mut Dice::new(6)));
    }
}
