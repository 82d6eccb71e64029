//! Shared helpers: check and evaluate a program given as text.

use qcsg_eval::{EvalOptions, Evaluation, evaluate};
use qcsg_sema::{CheckOptions, FsLoader, check_file};

/// Checks `text` (which must have no static errors) and evaluates it with `options`.
pub fn eval_with(text: &str, options: &EvalOptions) -> Evaluation {
    let analysis = check_file(
        "test.scad",
        text.to_string(),
        &CheckOptions::default(),
        &FsLoader,
    );
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
