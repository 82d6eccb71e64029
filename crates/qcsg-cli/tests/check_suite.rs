//! The language suite: every `*.qcsg` / `*.scad` file under `<workspace>/tests/check/` (skipping
//! `lib/` directories) is checked with `qcsg_sema::check_file` and its diagnostics compared with
//! the inline annotations described in `tests/README.md`.
//!
//! Every case runs; all mismatches are reported, per file, before the test fails. A case that
//! panics or hangs fails on its own without stopping the others.
//! `QCSG_SUITE_FILTER=text` runs only the cases whose path contains `text`.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::Duration;

use qcsg_sema::{CheckOptions, FsLoader};
use qcsg_testkit::annotations::{mismatch_report, suite_cases};

/// How long one case may take before it counts as hanging (debug builds are slow; cases are small).
const CASE_TIME_LIMIT: Duration = Duration::from_secs(20);

/// `<workspace>/tests/check`.
fn suite_root() -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/check");
    root.canonicalize().unwrap_or(root)
}

/// Checks one case; returns its failure report, or `None` when it passes.
fn run_case(root: &Path, path: &Path) -> Option<String> {
    let shown = |p: &Path| p.strip_prefix(root).unwrap_or(p).display().to_string();
    let text = match std::fs::read_to_string(path) {
        Ok(text) => text,
        Err(err) => return Some(format!("cannot read: {err}\n")),
    };
    let name = path.to_string_lossy().into_owned();
    // A case runs on its own thread so that a hang fails that case (after a generous time)
    // instead of stalling the whole suite; a panic fails it too, with the panic's message.
    let (send, receive) = mpsc::channel();
    std::thread::spawn(move || {
        let checked = catch_unwind(AssertUnwindSafe(|| {
            qcsg_sema::check_file(&name, text, &CheckOptions::default(), &FsLoader)
        }));
        let _ = send.send(checked.map_err(|panic| {
            panic
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| panic.downcast_ref::<&str>().map(|s| (*s).to_owned()))
                .unwrap_or_else(|| "(no message)".to_owned())
        }));
    });
    let analysis = match receive.recv_timeout(CASE_TIME_LIMIT) {
        Ok(Ok(analysis)) => analysis,
        Ok(Err(message)) => return Some(format!("  check_file panicked: {message}\n")),
        Err(_) => {
            return Some(format!(
                "  check_file did not finish within {CASE_TIME_LIMIT:?}\n"
            ));
        }
    };

    mismatch_report(&analysis, &|name| shown(Path::new(name)))
}

#[test]
fn language_suite() {
    let root = suite_root();
    let mut cases = suite_cases(&root);
    assert!(!cases.is_empty(), "no cases found under {}", root.display());
    if let Ok(filter) = std::env::var("QCSG_SUITE_FILTER") {
        cases.retain(|path| path.to_string_lossy().contains(&filter));
    }

    // Pass/fail counts per top-level directory of the suite.
    let mut per_directory: BTreeMap<String, (usize, usize)> = BTreeMap::new();
    let mut failures = String::new();
    for path in &cases {
        let relative = path.strip_prefix(&root).unwrap_or(path);
        let directory = match relative.components().count() {
            1 => ".".to_owned(),
            _ => relative
                .components()
                .next()
                .map(|c| c.as_os_str().to_string_lossy().into_owned())
                .unwrap_or_default(),
        };
        let counts = per_directory.entry(directory).or_default();
        match run_case(&root, path) {
            None => counts.0 += 1,
            Some(report) => {
                counts.1 += 1;
                let _ = writeln!(
                    failures,
                    "FAIL tests/check/{}\n{report}",
                    relative.display()
                );
            }
        }
    }

    let mut summary = String::from("language suite, per directory (passed / failed):\n");
    for (directory, (passed, failed)) in &per_directory {
        let _ = writeln!(
            summary,
            "  {directory:<24} {passed:>4} passed {failed:>4} failed"
        );
    }
    let failed: usize = per_directory.values().map(|c| c.1).sum();
    let _ = writeln!(summary, "{} passed, {failed} failed", cases.len() - failed);
    // Shown with `--nocapture`; on failure the counts end the failure message instead.
    assert!(failed == 0, "{failures}{summary}");
    eprintln!("{summary}");
}

/// The runner end to end on real `check_file` output: a right annotation passes, a wrong one
/// fails with both sides of the mismatch in the report.
#[test]
fn runner_detects_a_wrong_expectation() {
    let dir = std::env::temp_dir().join(format!("qcsg-check-suite-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let case = |name: &str, text: &str| {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        run_case(&dir, &path)
    };

    let right = case("right.qcsg", "x = ;\n//  ^ error[E0002]\n");
    assert_eq!(right, None);

    let wrong_column = case("column.qcsg", "x = ;\n//   ^ error[E0002]\n").expect("fails");
    assert!(
        wrong_column.contains("expected, not reported:\n    1:6-1:7"),
        "{wrong_column}"
    );
    assert!(
        wrong_column.contains("reported, not expected:\n    1:5-1:6"),
        "{wrong_column}"
    );

    let unannotated = case("bare.qcsg", "x = ;\n").expect("fails");
    assert!(
        unannotated.contains("reported, not expected"),
        "{unannotated}"
    );

    let missing = case("missing.qcsg", "x = 1;\n//  ^ error[E0002]\n").expect("fails");
    assert!(missing.contains("expected, not reported"), "{missing}");

    let malformed = case("malformed.qcsg", "x = ;\n//  ^ error(E0002)\n").expect("fails");
    assert!(malformed.contains("malformed annotation"), "{malformed}");

    std::fs::remove_dir_all(&dir).unwrap();
}
