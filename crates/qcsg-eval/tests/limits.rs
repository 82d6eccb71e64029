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
