//! Runs the static-checking cases of the language suite (`tests/check/sema/` and
//! `tests/check/ok/`) through `check_file` and compares the diagnostics with their inline
//! annotations (format: `tests/README.md`; parsed and matched by `qcsg_testkit::annotations`).
//! The workspace harness in the CLI crate runs the whole suite; this test keeps the checker's
//! own cases close to the checker.

use std::path::Path;

use qcsg_sema::{CheckOptions, FsLoader, check_file};
use qcsg_testkit::annotations::{mismatch_report, suite_cases};

fn check_case(path: &Path) -> Result<(), String> {
    let text = std::fs::read_to_string(path).map_err(|e| e.to_string())?;
    let analysis = check_file(
        &path.to_string_lossy(),
        text,
        &CheckOptions::default(),
        &FsLoader,
    );
    match mismatch_report(&analysis, &|name| name.to_owned()) {
        None => Ok(()),
        Some(report) => Err(report),
    }
}

#[test]
fn sema_and_ok_cases() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/check");
    let mut all = suite_cases(&root.join("sema"));
    all.extend(suite_cases(&root.join("ok")));
    let mut failures = String::new();
    for path in &all {
        if let Err(report) = check_case(path) {
            failures.push_str(&format!("FAIL {}\n{report}", path.display()));
        }
    }
    assert!(failures.is_empty(), "{failures}");
}

/// The whole suite, other directories included: `cargo test -p qcsg-sema --test cases -- --ignored`.
#[test]
#[ignore = "the workspace harness in qcsg-cli owns the whole suite"]
fn whole_suite() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/check");
    let all = suite_cases(&root);
    let mut failures = String::new();
    for path in &all {
        if let Err(report) = check_case(path) {
            failures.push_str(&format!("FAIL {}\n{report}", path.display()));
        }
    }
    assert!(failures.is_empty(), "{failures}");
}
