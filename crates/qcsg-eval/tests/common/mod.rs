//! Shared helpers: check and evaluate a program given as text, and check points against it.

// Each test file uses the helpers it needs.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

use glam::DVec3;
use qcsg_csg::{DnfOptions, build_dnf};
use qcsg_eval::{EvalOptions, Evaluation, evaluate};
use qcsg_sema::{CheckOptions, FsLoader, check_file};

/// Checks `text` (which must have no static errors) and evaluates it with `options`.
pub fn eval_with(text: &str, options: &EvalOptions) -> Evaluation {
    eval_named("test.scad", text, options)
}

/// Writes `main.scad` with `text` into `dir`, checks it (no static errors allowed) and evaluates
/// it, so that the files it reads are found beside it.
pub fn eval_in(dir: &Path, text: &str, options: &EvalOptions) -> Evaluation {
    let main = dir.join("main.scad");
    std::fs::write(&main, text).expect("write main.scad");
    eval_named(&main.to_string_lossy(), text, options)
}

/// The first error of evaluating `text` in `dir` (with `error` false, the first warning or
/// note): its code, the text it points at, and its message and help joined by ` / `.
pub fn first_diagnostic(
    dir: &Path,
    text: &str,
    options: &EvalOptions,
    error: bool,
) -> (&'static str, String, String) {
    let e = eval_in(dir, text, options);
    let d = e
        .diagnostics
        .iter()
        .find(|d| d.is_error() == error)
        .unwrap_or_else(|| panic!("{text}: nothing of its kind in {:?}", e.diagnostics));
    let message = format!("{} / {}", d.message, d.help.clone().unwrap_or_default());
    (
        d.code,
        text[d.span.start as usize..d.span.end as usize].to_owned(),
        message,
    )
}

/// [`first_diagnostic`]'s first error.
pub fn first_error(
    dir: &Path,
    text: &str,
    options: &EvalOptions,
) -> (&'static str, String, String) {
    first_diagnostic(dir, text, options, true)
}

/// A fresh directory `name` of the test group `group`.
pub fn scratch(group: &str, name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(group)
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch directory");
    dir
}

fn eval_named(name: &str, text: &str, options: &EvalOptions) -> Evaluation {
    let analysis = check_file(name, text.to_string(), &CheckOptions::default(), &FsLoader);
    let errors: Vec<_> = analysis
        .diagnostics
        .iter()
        .filter(|d| d.is_error())
        .map(|d| format!("{} {}", d.code, d.message))
        .collect();
    assert!(errors.is_empty(), "static errors in {text:?}: {errors:?}");
    evaluate(&analysis, options)
}

/// Checks and evaluates `text` with the default options.
pub fn eval(text: &str) -> Evaluation {
    eval_with(text, &EvalOptions::default())
}

/// The codes of the diagnostics of an evaluation.
pub fn codes(e: &Evaluation) -> Vec<&'static str> {
    e.diagnostics.iter().map(|d| d.code).collect()
}

/// A point.
pub fn p(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

/// Evaluates `text` (no errors allowed) and checks each `(point, inside)` on the DAG and the DNF.
pub fn membership(text: &str, cases: &[(DVec3, bool)]) -> Vec<&'static str> {
    let e = eval(text);
    assert!(!e.has_errors(), "{text}: {:?}", e.diagnostics);
    let dnf = build_dnf(&e.dag, &DnfOptions::default()).expect("a bounded solid");
    for (point, inside) in cases {
        assert_eq!(e.dag.contains(*point), *inside, "{text}: DAG at {point}");
        assert_eq!(dnf.contains(*point), *inside, "{text}: DNF at {point}");
    }
    codes(&e)
}

/// Asserts that `text` is refused with E0301 alone, with help, and with one label at each part
/// that cannot be combined: the label's text starts with `parts[0]`, then `parts[1]`.
pub fn assert_refused_at_both_parts(text: &str, parts: [&str; 2]) {
    let e = eval(text);
    assert_eq!(codes(&e), vec!["E0301"], "{text}: {:?}", e.diagnostics);
    let d = &e.diagnostics[0];
    let labels: Vec<&str> = d
        .labels
        .iter()
        .map(|l| &text[l.span.start as usize..l.span.end as usize])
        .collect();
    assert_eq!(labels.len(), 2, "{text}: {labels:?}");
    assert!(labels[0].starts_with(parts[0]), "{text}: {labels:?}");
    assert!(labels[1].starts_with(parts[1]), "{text}: {labels:?}");
    assert!(d.help.is_some(), "{text}");
}
