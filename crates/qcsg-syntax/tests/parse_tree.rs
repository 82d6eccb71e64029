//! Tree shape of every construct, printed as S-expressions.

use qcsg_syntax::{FileId, parse, sexpr::file_to_sexpr};

/// Parses `text`, asserts it has no diagnostics and returns the printed tree (lines joined by
/// `\n`, no trailing newline).
fn tree(text: &str) -> String {
    let parse = parse(text, FileId::default());
    assert!(
        parse.diagnostics.is_empty(),
        "{text:?}: {:#?}",
        parse.diagnostics
    );
    file_to_sexpr(&parse.file).trim_end().to_owned()
}

#[test]
fn statements() {
    assert_eq!(tree(";"), "(empty)");
    assert_eq!(tree("x = 1;"), "(= x 1)");
    assert_eq!(tree("$fn = 32;"), "(= $fn 32)");
    assert_eq!(
        tree("module m(a, b = 2) cube(a);"),
        "(module m (a (= b 2)) (cube a))"
    );
    assert_eq!(tree("module m() { }"), "(module m () (block))");
    assert_eq!(tree("function f(x) = x * 2;"), "(function f (x) (* x 2))");
    assert_eq!(tree("{ a(); b(); }"), "(block (a) (b))");
    assert_eq!(tree("if (c) a(); else b();"), "(if c (a) (b))");
    assert_eq!(tree("if (c) a();"), "(if c (a))");
    assert_eq!(
        tree("for (i = [0:3], j = v) a(i);"),
        "(for ((= i (range 0 3)) (= j v)) (a i))"
    );
    assert_eq!(
        tree("let (a = 1, b = a) c(b);"),
        "(let ((= a 1) (= b a)) (c b))"
    );
    assert_eq!(tree("include <a/b.scad>"), "(include <a/b.scad>)");
    assert_eq!(tree("use <lib.scad>"), "(use <lib.scad>)");
}

#[test]
fn instantiations() {
    assert_eq!(tree("cube(1);"), "(cube 1)");
    assert_eq!(
        tree("cube(size = 2, center = true);"),
        "(cube (= size 2) (= center true))"
    );
    assert_eq!(
        tree("translate([1, 2, 3]) rotate(90) cube(1);"),
        "(translate [1 2 3] (rotate 90 (cube 1)))"
    );
    assert_eq!(tree("union() { a(); b(); }"), "(union (block (a) (b)))");
    assert_eq!(
        tree("intersection_for(i = [0:2]) a(i);"),
        "(intersection_for (= i (range 0 2)) (a i))"
    );
    assert_eq!(tree("echo(\"x\", y = 1);"), "(echo \"x\" (= y 1))");
    assert_eq!(tree("assert(x > 0, \"msg\");"), "(assert (> x 0) \"msg\")");
    assert_eq!(tree("children(0);"), "(children 0)");
    assert_eq!(tree("cube(1,);"), "(cube 1)");
}

#[test]
fn modifiers() {
    assert_eq!(tree("*cube(1);"), "(* (cube 1))");
    assert_eq!(tree("!#%cube(1);"), "(! (# (% (cube 1))))");
    assert_eq!(tree("#if (c) a();"), "(# (if c (a)))");
    assert_eq!(tree("%for (i = v) a();"), "(% (for ((= i v)) (a)))");
    assert_eq!(tree("*let (a = 1) b();"), "(* (let ((= a 1)) (b)))");
    assert_eq!(tree("!{ a(); }"), "(! (block (a)))");
    assert_eq!(tree("translate(v) #cube(1);"), "(translate v (# (cube 1)))");
}

fn expr(text: &str) -> String {
    let t = tree(&format!("x = {text};"));
    t.strip_prefix("(= x ")
        .and_then(|s| s.strip_suffix(')'))
        .unwrap()
        .to_owned()
}

#[test]
fn literals() {
    assert_eq!(expr("1"), "1");
    assert_eq!(expr("1.5"), "1.5");
    assert_eq!(expr(".5"), "0.5");
    assert_eq!(expr("1e-3"), "0.001");
    assert_eq!(expr("2.5E+4"), "25000");
    assert_eq!(
        expr(r#""a\"\\\n\t\r\x41\u263A""#),
        "\"a\\\"\\\\\\n\\t\\rA\u{263A}\""
    );
    assert_eq!(expr("true"), "true");
    assert_eq!(expr("false"), "false");
    assert_eq!(expr("undef"), "undef");
    assert_eq!(expr("$fn"), "$fn");
    assert_eq!(expr("1."), "1");
    assert_eq!(expr("1e999"), "inf");
}

#[test]
fn precedence() {
    assert_eq!(expr("1 + 2 * 3"), "(+ 1 (* 2 3))");
    assert_eq!(expr("1 - 2 - 3"), "(- (- 1 2) 3)");
    assert_eq!(expr("2 ^ 3 ^ 2"), "(^ 2 (^ 3 2))");
    assert_eq!(expr("-2 ^ 2"), "(neg (^ 2 2))");
    assert_eq!(expr("2 ^ -1"), "(^ 2 (neg 1))");
    assert_eq!(expr("-a * b"), "(* (neg a) b)");
    assert_eq!(expr("!a && b || c"), "(|| (&& (! a) b) c)");
    assert_eq!(expr("a == b < c + 1"), "(== a (< b (+ c 1)))");
    assert_eq!(expr("a != b"), "(!= a b)");
    assert_eq!(expr("a <= b >= c > d"), "(> (>= (<= a b) c) d)");
    assert_eq!(expr("a % b / c"), "(/ (% a b) c)");
    assert_eq!(expr("+a"), "(pos a)");
    assert_eq!(expr("a ? b : c ? d : e"), "(? a b (? c d e))");
    assert_eq!(expr("a || b ? c + 1 : d"), "(? (|| a b) (+ c 1) d)");
    assert_eq!(expr("(1 + 2) * 3"), "(* (paren (+ 1 2)) 3)");
    assert_eq!(expr("-v[0]"), "(neg (index v 0))");
    assert_eq!(expr("2 ^ f(x)"), "(^ 2 (call f x))");
}

#[test]
fn postfix() {
    assert_eq!(expr("f(1, b = 2)"), "(call f 1 (= b 2))");
    assert_eq!(expr("v[0][1]"), "(index (index v 0) 1)");
    assert_eq!(expr("p.x + p.y"), "(+ (. p x) (. p y))");
    assert_eq!(expr("f(1)(2)"), "(call (call f 1) 2)");
    assert_eq!(expr("m[0].z"), "(. (index m 0) z)");
    assert_eq!(expr("a.b.c"), "(. (. a b) c)");
    assert_eq!(expr("echo"), "echo");
    assert_eq!(expr("assert"), "assert");
}

#[test]
fn vectors_and_ranges() {
    assert_eq!(expr("[]"), "[]");
    assert_eq!(expr("[1, 2, 3,]"), "[1 2 3]");
    assert_eq!(expr("[[1, 2], [3]]"), "[[1 2] [3]]");
    assert_eq!(expr("[0 : 10]"), "(range 0 10)");
    assert_eq!(expr("[0 : 2 : 10]"), "(range 0 2 10)");
    assert_eq!(expr("[a - 1 : -1 : 0]"), "(range (- a 1) (neg 1) 0)");
}

#[test]
fn comprehensions() {
    assert_eq!(
        expr("[for (i = [0:3]) i * i]"),
        "[(for ((= i (range 0 3))) (* i i))]"
    );
    assert_eq!(
        expr("[for (i = v) if (i > 0) i]"),
        "[(for ((= i v)) (if (> i 0) i))]"
    );
    assert_eq!(
        expr("[for (i = v) if (i > 0) i else -i]"),
        "[(for ((= i v)) (if (> i 0) i (neg i)))]"
    );
    assert_eq!(
        expr("[for (i = 0; i < n; i = i + 1) i]"),
        "[(cfor ((= i 0)) (< i n) ((= i (+ i 1))) i)]"
    );
    assert_eq!(
        expr("[for (i = 0, j = 1; i < n; i = i + 1, j = j * 2) j]"),
        "[(cfor ((= i 0) (= j 1)) (< i n) ((= i (+ i 1)) (= j (* j 2))) j)]"
    );
    assert_eq!(expr("[each v]"), "[(each v)]");
    assert_eq!(expr("[let (x = 1) x]"), "[(let ((= x 1)) x)]");
    assert_eq!(
        expr("[1, for (i = x) i, each v]"),
        "[1 (for ((= i x)) i) (each v)]"
    );
    assert_eq!(
        expr("[for (i = a) for (j = b) [i, j]]"),
        "[(for ((= i a)) (for ((= j b)) [i j]))]"
    );
    assert_eq!(
        expr("[for (i = a) each [i, i]]"),
        "[(for ((= i a)) (each [i i]))]"
    );
    assert_eq!(
        expr("[for (i = a) let (j = i) (if (j) j)]"),
        "[(for ((= i a)) (let ((= j i)) (paren (if j j))))]"
    );
    assert_eq!(
        expr("[each [for (i = a) i]]"),
        "[(each [(for ((= i a)) i)])]"
    );
}

#[test]
fn special_expressions() {
    assert_eq!(
        expr("let (a = 1, b = 2) a + b"),
        "(let ((= a 1) (= b 2)) (+ a b))"
    );
    assert_eq!(expr("function (x) x + 1"), "(fn (x) (+ x 1))");
    assert_eq!(
        expr("function (x, y = 2) function (z) x * z"),
        "(fn (x (= y 2)) (fn (z) (* x z)))"
    );
    assert_eq!(
        expr("assert(x > 0, \"m\") x"),
        "(assert (args (> x 0) \"m\") x)"
    );
    assert_eq!(expr("assert(true)"), "(assert (args true))");
    assert_eq!(
        expr("echo(\"v\", v) v + 1"),
        "(echo (args \"v\" v) (+ v 1))"
    );
    assert_eq!(expr("echo(1)"), "(echo (args 1))");
    assert_eq!(expr("f(echo(1) 2)"), "(call f (echo (args 1) 2))");
    assert_eq!(expr("c ? let (a = 1) a : 2"), "(? c (let ((= a 1)) a) 2)");
}

#[test]
fn docs_and_comments() {
    let text = "/// The size.\n/// In mm.\nsize = 1;\n/** A module.\n * Draws.\n */\nmodule m() cube();\n// plain\nfunction f() = 1;\n";
    let parse = parse(text, FileId::default());
    assert!(parse.diagnostics.is_empty(), "{:?}", parse.diagnostics);
    let docs: Vec<_> = parse
        .file
        .stmts
        .iter()
        .map(|s| s.doc.as_ref().map(|d| d.text.as_str()))
        .collect();
    assert_eq!(
        docs,
        vec![Some("The size.\nIn mm."), Some("A module.\nDraws."), None]
    );
    assert_eq!(parse.file.comments.len(), 4);
}

#[test]
fn spans() {
    let text = "x = 1 + 2;\ncube(1) sphere(2);";
    let parse = parse(text, FileId::default());
    let s = &parse.file.stmts;
    assert_eq!(&text[s[0].span.range()], "x = 1 + 2;");
    assert_eq!(&text[s[1].span.range()], "cube(1) sphere(2);");
    let qcsg_syntax::ast::StmtKind::Instantiate { args_span, .. } = &s[1].kind else {
        panic!()
    };
    assert_eq!(&text[args_span.range()], "(1)");
}
