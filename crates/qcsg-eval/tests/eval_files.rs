//! Evaluation tests as data: every `tests/eval/NAME.scad` of the repository is checked and
//! evaluated, and its `echo` output must equal `tests/eval/NAME.echo`, which holds the `ECHO:`
//! lines OpenSCAD 2021.01 prints for the same file (`openscad -o NAME.echo NAME.scad`).

use std::path::{Path, PathBuf};

use qcsg_eval::{EvalOptions, evaluate};
use qcsg_sema::{CheckOptions, FsLoader, check_file};

fn cases_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/eval")
}

#[test]
fn echo_output_matches_openscad() {
    let mut cases: Vec<PathBuf> = std::fs::read_dir(cases_dir())
        .expect("tests/eval exists")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "scad"))
        .collect();
    cases.sort();
    assert!(!cases.is_empty());
    let mut failures = Vec::new();
    for scad in &cases {
        let text = std::fs::read_to_string(scad).expect("readable case");
        let name = scad.to_string_lossy().into_owned();
        let analysis = check_file(&name, text, &CheckOptions::default(), &FsLoader);
        let static_errors: Vec<_> = analysis
            .diagnostics
            .iter()
            .filter(|d| d.is_error())
            .map(|d| format!("{} {}", d.code, d.message))
            .collect();
        if !static_errors.is_empty() {
            failures.push(format!("{name}: static errors {static_errors:?}"));
            continue;
        }
        let evaluation = evaluate(&analysis, &EvalOptions::default());
        let errors: Vec<_> = evaluation
            .diagnostics
            .iter()
            .filter(|d| d.is_error())
            .map(|d| format!("{} {}", d.code, d.message))
            .collect();
        let got = evaluation.echo_lines().join("\n");
        let expected_path = scad.with_extension("echo");
        let expected = std::fs::read_to_string(&expected_path).unwrap_or_default();
        if !errors.is_empty() || got.trim_end() != expected.trim_end() {
            failures.push(format!(
                "{name}\nerrors: {errors:?}\n--- expected\n{}\n--- got\n{got}",
                expected.trim_end()
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}
