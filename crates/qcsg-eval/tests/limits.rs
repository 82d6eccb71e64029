//! Limits: runaway programs end quickly with a diagnostic at the span that caused it.

mod common;

use std::time::{Duration, Instant};

use common::{codes, eval, eval_with};
use qcsg_eval::{EvalOptions, codes as c};

fn quick<T>(f: impl FnOnce() -> T) -> T {
    let start = Instant::now();
    let out = f();
    assert!(
        start.elapsed() < Duration::from_secs(20),
        "took {:?}",
        start.elapsed()
    );
    out
}

fn small() -> EvalOptions {
    EvalOptions {
        max_recursion: 500,
        max_iterations: 100_000,
        max_vector_len: 100_000,
        max_instances: 50,
        ..EvalOptions::default()
    }
}

#[test]
fn infinite_recursion_stops_at_the_depth_limit() {
    let e = quick(|| eval("function f(n) = 1 + f(n + 1);\necho(f(0));\n"));
    assert!(
        codes(&e).contains(&c::RECURSION_LIMIT),
        "{:?}",
        e.diagnostics
    );
    let e = quick(|| eval("module m(n) { m(n + 1); }\nm(0);\n"));
    assert!(
        codes(&e).contains(&c::RECURSION_LIMIT),
        "{:?}",
        e.diagnostics
    );
}

#[test]
fn deep_recursion_within_the_limit_works() {
    let e = quick(|| eval("function s(n) = n == 0 ? 0 : 1 + s(n - 1);\necho(s(5000));\n"));
    assert_eq!(e.echo_lines(), ["ECHO: 5000"], "{:?}", e.diagnostics);
}

#[test]
fn infinite_tail_recursion_stops_at_the_iteration_limit() {
    let e = quick(|| eval_with("function g(n) = g(n + 1);\necho(g(0));\n", &small()));
    assert!(
        codes(&e).contains(&c::ITERATION_LIMIT),
        "{:?}",
        e.diagnostics
    );
}

#[test]
fn huge_ranges_are_refused_before_iterating() {
    let text = "for (i = [0 : 1e12]) cube(1);\n";
    let e = quick(|| eval(text));
    let d = e
        .diagnostics
        .iter()
        .find(|d| d.code == c::ITERATION_LIMIT)
        .expect("limit");
    assert_eq!(&text[d.span.range()], "[0 : 1e12]");
    let e = quick(|| eval("x = [for (i = [0 : 1e12]) i];\necho(len(x));\n"));
    assert!(
        codes(&e).contains(&c::ITERATION_LIMIT),
        "{:?}",
        e.diagnostics
    );
    let e = quick(|| eval("echo(len([each [0 : 1e12]]));\n"));
    assert!(codes(&e).contains(&c::VECTOR_LIMIT), "{:?}", e.diagnostics);
    let e = quick(|| eval("echo(len(rands(0, 1, 1e12, 1)));\n"));
    assert!(codes(&e).contains(&c::VECTOR_LIMIT), "{:?}", e.diagnostics);
    let e = quick(|| eval("for (i = [0 : 0 : 1]) cube(1);\n"));
    assert!(
        codes(&e).contains(&c::ITERATION_LIMIT),
        "{:?}",
        e.diagnostics
    );
}

#[test]
fn c_style_loops_that_never_end_stop() {
    let e = quick(|| eval_with("x = [for (i = 0; true; i = i + 1) i];\n", &small()));
    assert!(
        codes(&e).contains(&c::ITERATION_LIMIT) || codes(&e).contains(&c::VECTOR_LIMIT),
        "{:?}",
        e.diagnostics
    );
}

#[test]
fn too_many_instances() {
    let e = quick(|| {
        eval_with(
            "for (i = [0 : 99]) translate([i, 0, 0]) cube(1);\n",
            &small(),
        )
    });
    assert!(
        codes(&e).contains(&c::INSTANCE_LIMIT),
        "{:?}",
        e.diagnostics
    );
    let e = quick(|| {
        eval_with(
            "for (i = [0 : 9]) translate([i, 0, 0]) cube(1);\n",
            &small(),
        )
    });
    assert!(!e.has_errors(), "{:?}", e.diagnostics);
}

#[test]
fn runtime_errors_are_reported_at_their_span() {
    let text = "x = [1, 2];\ny = x[5] + 1;\n";
    let e = eval(text);
    let d = e.diagnostics.iter().find(|d| d.is_error()).expect("error");
    assert_eq!(d.code, c::OPERATOR_TYPE);
    assert_eq!(&text[d.span.range()], "x[5] + 1");
    let text = "n = -1;\nassert(n > 0, \"n must be positive\");\n";
    let e = eval(text);
    let d = e.diagnostics.iter().find(|d| d.is_error()).expect("error");
    assert_eq!(d.code, c::ASSERTION_FAILED);
    assert!(d.message.contains("n must be positive"), "{}", d.message);
    assert!(d.message.contains("(n > 0)"), "{}", d.message);
}

#[test]
fn defines_override_top_level_variables() {
    let options = EvalOptions {
        defines: vec![("a".into(), "5".into()), ("s".into(), "\"x\"".into())],
        ..EvalOptions::default()
    };
    let e = eval_with("a = 1;\nb = a + 1;\necho(a, b);\n", &options);
    assert_eq!(e.echo_lines(), ["ECHO: 5, 6"]);
    let options = EvalOptions {
        defines: vec![("a".into(), "1 +".into())],
        ..EvalOptions::default()
    };
    let e = eval_with("a = 1;\n", &options);
    assert!(codes(&e).contains(&c::BAD_DEFINE));
}

/// The spans of the errors of an evaluation, as source text.
fn error_texts<'t>(text: &'t str, e: &qcsg_eval::Evaluation) -> Vec<(&'static str, &'t str)> {
    e.diagnostics
        .iter()
        .filter(|d| d.is_error())
        .map(|d| (d.code, &text[d.span.range()]))
        .collect()
}

#[test]
fn errors_where_openscad_warns_do_not_stop_the_evaluation() {
    // OpenSCAD warns about each of these and goes on with `undef`: so does the evaluation here,
    // reporting every one (a loop's error once) and still running what comes after.
    let text = "x = [1, 2];\ny = x[5] + 1;\nz = x[6] - 1;\n\
                for (i = [0 : 3]) echo(i * x[7]);\necho(\"after\", y);\ncube(1);\n";
    let e = eval(text);
    assert_eq!(
        error_texts(text, &e),
        [
            (c::OPERATOR_TYPE, "x[5] + 1"),
            (c::OPERATOR_TYPE, "x[6] - 1"),
            (c::OPERATOR_TYPE, "i * x[7]"),
        ],
        "{:?}",
        e.diagnostics
    );
    assert_eq!(e.echo_lines(), ["ECHO: \"after\", undef"]);
}

#[test]
fn failed_assertions_and_limits_stop_the_evaluation() {
    let text = "x = [1, 2];\ny = x[5] + 1;\nassert(y == 3);\necho(\"never\");\n";
    let e = eval(text);
    assert_eq!(
        codes(&e)
            .into_iter()
            .filter(|code| code.starts_with('E'))
            .collect::<Vec<_>>(),
        [c::OPERATOR_TYPE, c::ASSERTION_FAILED]
    );
    assert!(e.echo_lines().is_empty());
    let e = quick(|| {
        eval_with(
            "function f(n) = f(n + 1) + 1;\na = f(0);\necho(\"never\");\n",
            &small(),
        )
    });
    assert_eq!(
        codes(&e)
            .into_iter()
            .filter(|code| code.starts_with('E'))
            .collect::<Vec<_>>(),
        [c::RECURSION_LIMIT]
    );
    assert!(e.echo_lines().is_empty());
}

#[test]
fn a_flood_of_errors_stops_after_the_cap() {
    let mut text = String::from("x = [1, 2];\n");
    for i in 0..80 {
        text.push_str(&format!("echo(x[5] + {i});\n"));
    }
    let e = eval(&text);
    let errors: Vec<_> = e.diagnostics.iter().filter(|d| d.is_error()).collect();
    assert_eq!(errors.len(), 50);
    assert!(errors[49].help.is_some(), "{:?}", errors[49]);
    assert!(e.echo_lines().is_empty());
}

/// The first diagnostic of `code`, with the source text of its span.
fn first_of<'t>(text: &'t str, e: &qcsg_eval::Evaluation, code: &str) -> Option<(&'t str, String)> {
    e.diagnostics
        .iter()
        .find(|d| d.code == code)
        .map(|d| (&text[d.span.range()], d.message.clone()))
}

/// `d(v, n)` is `[v, v]` n times over: 2ⁿ copies of `v` in n + 1 shared vectors.
const DOUBLED: &str = "function d(v, n) = n == 0 ? v : d([v, v], n - 1);\n";

#[test]
fn doubling_a_string_stops_at_the_string_limit() {
    // Before the limit, the fortieth doubling asked for 2 GB and aborted the process.
    let text = "function d(s, n) = n == 0 ? s : d(str(s, s), n - 1);\necho(len(d(\"ab\", 40)));\n";
    let e = quick(|| eval(text));
    let (at, message) = first_of(text, &e, c::STRING_LIMIT).expect("string limit");
    assert_eq!(at, "str(s, s)");
    assert!(message.contains("16777216 bytes"), "{message}");
    assert!(e.echo_lines().is_empty(), "{:?}", e.echo_lines());
    let help = e.diagnostics.iter().find(|d| d.code == c::STRING_LIMIT);
    assert!(
        help.and_then(|d| d.help.as_deref())
            .is_some_and(|h| h.contains("--max-string-len")),
        "{help:?}"
    );
    // Up to the limit, strings are whole.
    let options = EvalOptions {
        max_string_len: 1024,
        ..EvalOptions::default()
    };
    let e = eval_with(
        "function d(s, n) = n == 0 ? s : d(str(s, s), n - 1);\necho(len(d(\"ab\", 9)));\n",
        &options,
    );
    assert_eq!(e.echo_lines(), ["ECHO: 1024"], "{:?}", e.diagnostics);
    let e = eval_with(
        "function d(s, n) = n == 0 ? s : d(str(s, s), n - 1);\necho(len(d(\"ab\", 10)));\n",
        &options,
    );
    assert_eq!(codes(&e), [c::STRING_LIMIT]);
}

#[test]
fn str_of_a_shared_list_stops_at_the_string_limit() {
    // 2⁴⁰ numbers in the text: before the limit, memory grew until the process was killed.
    let text = format!("{DOUBLED}s = str(d(1, 40));\necho(len(s));\n");
    let e = quick(|| eval(&text));
    let (at, _) = first_of(&text, &e, c::STRING_LIMIT).expect("string limit");
    assert_eq!(at, "str(d(1, 40))");
    assert!(e.echo_lines().is_empty());
}

#[test]
fn chr_stops_at_the_string_and_vector_limits() {
    let options = EvalOptions {
        max_string_len: 1000,
        ..EvalOptions::default()
    };
    let text =
        "echo(len(chr([for (i = [1 : 1000]) 65])));\necho(chr([for (i = [1 : 1001]) 65]));\n";
    let e = eval_with(text, &options);
    assert_eq!(e.echo_lines(), ["ECHO: 1000"]);
    let (at, _) = first_of(text, &e, c::STRING_LIMIT).expect("string limit");
    assert_eq!(at, "chr([for (i = [1 : 1001]) 65])");
    // Two-byte characters count twice.
    let e = eval_with("echo(chr([for (i = [1 : 501]) 233]));\n", &options);
    assert_eq!(codes(&e), [c::STRING_LIMIT]);
    // A shared list is walked no further than the vector limit allows, whether its leaves make
    // characters or not (the walk used to visit all 2⁴⁰ of them).
    for leaf in ["65", "undef"] {
        let text = format!("{DOUBLED}echo(len(chr(d({leaf}, 40))));\n");
        let e = quick(|| eval(&text));
        assert_eq!(codes(&e), [c::VECTOR_LIMIT], "{:?}", e.diagnostics);
    }
}

#[test]
fn echo_of_a_shared_list_is_cut_at_the_echo_limit() {
    // Before the limit, printing 2⁴⁰ numbers grew memory until the process was killed.
    let text = format!("{DOUBLED}echo(d(1, 40));\necho(\"after\");\ncube(1);\n");
    let options = EvalOptions {
        max_echo_len: 10_000,
        ..EvalOptions::default()
    };
    let e = quick(|| eval_with(&text, &options));
    assert!(!e.has_errors(), "{:?}", e.diagnostics);
    let lines = e.echo_lines();
    assert_eq!(lines.len(), 1, "later echo output is left out");
    assert!(lines[0].starts_with("ECHO: [[[[["), "{}", &lines[0][..40]);
    assert!(lines[0].ends_with('…'));
    assert!(lines[0].len() <= 10_000, "{}", lines[0].len());
    let (at, message) = first_of(&text, &e, c::ECHO_LIMIT).expect("echo limit");
    assert_eq!(at, "echo(d(1, 40));");
    assert!(message.contains("10000 bytes"), "{message}");
    assert_eq!(
        codes(&e)
            .iter()
            .filter(|&&code| code == c::ECHO_LIMIT)
            .count(),
        1
    );
    // The solid is still built: echo output does not change it.
    assert!(e.dag.root().is_some());
    // With the default limit too.
    let text = format!("{DOUBLED}echo(d(1, 40));\n");
    let e = quick(|| eval(&text));
    assert!(codes(&e).contains(&c::ECHO_LIMIT), "{:?}", codes(&e));
}

#[test]
fn many_echo_lines_stop_at_the_echo_limit() {
    // Each line counts 64 bytes beside its text: a loop of empty echoes cannot pile up
    // millions of diagnostics.
    let options = EvalOptions {
        max_echo_len: 64 * 100,
        ..EvalOptions::default()
    };
    let e = quick(|| eval_with("for (i = [1 : 1000]) echo();\n", &options));
    let lines = e.echo_lines();
    assert!((50..100).contains(&lines.len()), "{}", lines.len());
    assert_eq!(
        codes(&e)
            .iter()
            .filter(|&&code| code == c::ECHO_LIMIT)
            .count(),
        1
    );
    let e = eval_with("for (i = [1 : 10]) echo(i);\n", &options);
    assert_eq!(e.echo_lines().len(), 10);
    assert!(!codes(&e).contains(&c::ECHO_LIMIT));
}

#[test]
fn values_quoted_in_messages_are_bounded() {
    let options = EvalOptions {
        max_string_len: 1000,
        ..EvalOptions::default()
    };
    // An assertion's message value: printed up to the string limit.
    let text = format!("{DOUBLED}assert(false, d(1, 40));\n");
    let e = quick(|| eval_with(&text, &options));
    let (_, message) = first_of(&text, &e, c::ASSERTION_FAILED).expect("assertion");
    assert!(message.len() < 1100 && message.ends_with('…'), "{message}");
    // A search table row that is quoted in a warning, and a cell whose first character is
    // all that search needs.
    let text = format!("{DOUBLED}echo(search(\"a\", [d(1, 40)], 1, 5));\n");
    let e = quick(|| eval(&text));
    let (_, message) = first_of(&text, &e, c::SEARCH_TABLE).expect("warning");
    assert!(message.len() < 400, "{message}");
    let text = format!("{DOUBLED}echo(search(\"[\", [[d(1, 40)]]));\n");
    let e = quick(|| eval(&text));
    assert_eq!(e.echo_lines(), ["ECHO: [0]"], "{:?}", e.diagnostics);
}

#[test]
fn search_of_long_strings_is_linear() {
    // 200,000 characters searched for in 200,000: 4·10¹⁰ comparisons one by one, and for
    // "all matches" 4·10¹⁰ indices, before each character's answer was built once and shared.
    let text = "a = chr([for (i = [1 : 200000]) 97]);\nb = chr([for (i = [1 : 200000]) 98]);\n\
                echo(len(search(b, a)));\nall = search(a, a, 0);\necho(len(all), len(all[0]), all[199999][5]);\n\
                echo(search(\"ab\", \"xbab\", 0), search(\"aa\", \"xa\"), search(\"ba\", \"aab\", 2));\n";
    let e = quick(|| eval(text));
    assert_eq!(
        e.echo_lines(),
        [
            "ECHO: 0",
            "ECHO: 200000, 200000, 5",
            "ECHO: [[2], [1, 3]], [1, 1], [[2], [0, 1]]"
        ],
        "{:?}",
        e.diagnostics
    );
    // One index per character of the needle: no more than the vector limit.
    let options = EvalOptions {
        max_vector_len: 1000,
        ..EvalOptions::default()
    };
    let e = eval_with(
        "a = chr([for (i = [1 : 999]) 97]);\necho(len(search(str(a, \"aa\"), \"a\")));\n",
        &options,
    );
    assert_eq!(codes(&e), [c::VECTOR_LIMIT], "{:?}", e.diagnostics);
}

#[test]
fn deeply_nested_values_print_and_drop_without_overflowing_the_stack() {
    // Tail recursion nests a vector 200,000 deep in a moment; printing it and dropping it
    // recursed once per level and overflowed the stack.
    let text = "function n(v, k) = k == 0 ? v : n([v], k - 1);\necho(len(n(1, 200000)));\n\
                echo(len(str(n(1, 200000))));\n";
    let e = quick(|| eval(text));
    assert_eq!(
        e.echo_lines(),
        ["ECHO: 1", "ECHO: 400001"],
        "{:?}",
        e.diagnostics
    );
}

#[test]
fn near_miss_names_of_any_length_are_checked_quickly() {
    // "Did you mean" compared a 32,000-character name with its near miss in 2.4 s (quadratic in
    // the length); names of 100,000 characters took minutes. Long names get no suggestion now.
    for length in [32_000, 100_000] {
        let name = format!("x_{}", "a".repeat(length));
        let text =
            format!("{name} = 1;\necho({name}b);\nfunction f_{name}() = 1;\necho(f_{name}c());\n");
        let analysis = quick(|| {
            qcsg_sema::check_file(
                "long.scad",
                text.clone(),
                &qcsg_sema::CheckOptions::default(),
                &qcsg_sema::FsLoader,
            )
        });
        let undefined: Vec<_> = analysis
            .diagnostics
            .iter()
            .filter(|d| d.is_error())
            .map(|d| (d.code, d.help.is_some()))
            .collect();
        assert_eq!(undefined, [("E0101", false), ("E0102", false)]);
    }
}
