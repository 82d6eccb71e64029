//! `qcsg check` runs the pipeline as far as the normal form, so what only the DNF finds (an
//! unbounded solid, the term limit) is reported by `check` exactly as by `compile`, `render` and
//! `sample`; `--no-dnf` and `--no-eval` stop earlier.

use qcsg_testkit::cli::{Invocation, Run};

/// Runs `qcsg ARGS -` with `program` on standard input.
fn run(program: &str, args: &[&str]) -> Run {
    Invocation::new(env!("CARGO_BIN_EXE_qcsg"))
        .args(args)
        .arg("-")
        .stdin(program)
        .run()
}

/// The exit status and the diagnostics as (code, byte range) pairs from `--format json`.
fn diagnostics(program: &str, args: &[&str]) -> (i32, Vec<(String, Vec<u64>)>) {
    let args = [args, &["--format", "json"]].concat();
    let run = run(program, &args);
    // `check` prints the array on standard output; commands whose output goes there print it on
    // standard error.
    let text = if run.stdout.starts_with(b"[") {
        String::from_utf8_lossy(&run.stdout)
    } else {
        run.stderr.as_str().into()
    };
    let start = text
        .find('[')
        .unwrap_or_else(|| panic!("no JSON in {text}"));
    let end = text.rfind(']').expect("a JSON array");
    let array: serde_json::Value = serde_json::from_str(&text[start..=end]).expect("JSON");
    let found = array
        .as_array()
        .expect("an array")
        .iter()
        .map(|d| {
            let range = d["byte_range"]
                .as_array()
                .expect("a byte range")
                .iter()
                .map(|n| n.as_u64().expect("an offset"))
                .collect();
            (d["code"].as_str().expect("a code").to_owned(), range)
        })
        .collect();
    (run.status, found)
}

/// The codes and `line:column` positions of `compile`'s diagnostics (its `--format` is that of
/// the emitted stage; diagnostics are for people).
fn compile_reports(program: &str, args: &[&str], code: &str, at: &str) -> bool {
    let run = run(program, &[&["compile", "--emit", "dnf"], args].concat());
    run.status == 1 && run.stderr.contains(code) && run.stderr.contains(at)
}

const UNBOUNDED: &str = "union() { sphere(3); halfspace([0, 0, 1], 0); }\n";
/// A block minus 8 cubes that all overlap: the normal form multiplies out past 20 terms.
const MANY_TERMS: &str =
    "difference() {\n  cube(10);\n  for (i = [0 : 7]) translate([i / 2, i / 3, 1]) cube(3);\n}\n";

#[test]
fn check_reports_an_unbounded_solid_as_compile_sample_and_render_do() {
    let (status, found) = diagnostics(UNBOUNDED, &["check"]);
    assert_eq!(status, 1);
    let at_halfspace = vec![("E0600".to_owned(), vec![21, 45])];
    assert_eq!(found, at_halfspace);
    assert!(compile_reports(UNBOUNDED, &[], "E0600", ":1:22"));
    for command in [&["sample", "--radius", "1%"][..], &["render", "-o", "-"]] {
        let (status, others) = diagnostics(UNBOUNDED, command);
        assert_eq!((status, &others), (1, &at_halfspace), "{command:?}");
    }
}

#[test]
fn check_reports_the_term_limit_with_the_same_flag_as_compile() {
    let limit = ["--max-terms", "20"];
    let (status, found) = diagnostics(MANY_TERMS, &["check", limit[0], limit[1]]);
    assert_eq!(status, 1);
    assert_eq!(found.len(), 1, "{found:?}");
    assert_eq!(found[0].0, "E0601");
    assert!(compile_reports(MANY_TERMS, &limit, "E0601", ":3:50"));
    let (status, found) = diagnostics(MANY_TERMS, &["check"]);
    assert_eq!((status, found.len()), (0, 0));
}

#[test]
fn no_dnf_and_no_eval_stop_earlier() {
    assert_eq!(
        diagnostics(UNBOUNDED, &["check", "--no-dnf"]),
        (0, Vec::new())
    );
    let failing_assert = "assert(false);\nsphere(1);\n";
    let (status, found) = diagnostics(failing_assert, &["check", "--no-dnf"]);
    assert_eq!(status, 1);
    assert_eq!(found[0].0, "E0555");
    assert_eq!(
        diagnostics(failing_assert, &["check", "--no-eval"]),
        (0, Vec::new())
    );
}
