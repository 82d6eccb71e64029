//! End-to-end tests of the `qcsg` binary: exit codes, standard input, the human rendering and the
//! JSON format (snapshots), and UTF-16 columns. The binary runs in `tests/fixtures/` so that file
//! names in the output are short and stable; its standard error is a pipe, so it is colourless.

use std::path::{Path, PathBuf};

use qcsg_testkit::cli::{Invocation, Run};

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures")
}

/// Runs `qcsg args…` in `tests/fixtures/` with `stdin` as standard input.
fn qcsg(args: &[&str], stdin: &str) -> Run {
    qcsg_with_path(args, stdin, None)
}

/// Runs `qcsg args…` with `QCSG_PATH` set to `search_path`, or unset.
fn qcsg_with_path(args: &[&str], stdin: &str, search_path: Option<&str>) -> Run {
    let mut run = Invocation::new(env!("CARGO_BIN_EXE_qcsg"))
        .args(args)
        .current_dir(fixtures())
        .stdin(stdin);
    if let Some(search_path) = search_path {
        run = run.env("QCSG_PATH", search_path);
    }
    run.run()
}

fn json(run: &Run) -> Vec<serde_json::Value> {
    serde_json::from_str(run.stdout_text())
        .unwrap_or_else(|e| panic!("stdout is not a JSON array ({e}):\n{}", run.stdout_text()))
}

#[test]
fn clean_file_exits_0_with_a_summary() {
    let run = qcsg(&["check", "clean.qcsg"], "");
    assert_eq!((run.status, run.stdout_text()), (0, ""), "{}", run.stderr);
    assert_eq!(run.stderr, "0 errors, 0 warnings\n");

    let run = qcsg(&["check", "--format", "json", "clean.qcsg"], "");
    assert_eq!(
        (run.status, run.stdout_text(), run.stderr.as_str()),
        (0, "[]\n", "")
    );

    let run = qcsg(&["check", "-q", "clean.qcsg"], "");
    assert_eq!(
        (run.status, run.stdout_text(), run.stderr.as_str()),
        (0, "", "")
    );
}

#[test]
fn errors_exit_1_rendered_for_people() {
    let run = qcsg(&["check", "syntax_errors.qcsg"], "");
    assert_eq!(run.status, 1);
    assert_eq!(run.stdout_text(), "");
    assert!(
        !run.stderr.contains('\u{1b}'),
        "no colour without a terminal"
    );
    insta::assert_snapshot!(run.stderr);
}

#[test]
fn errors_exit_1_as_json() {
    let run = qcsg(&["check", "--format", "json", "syntax_errors.qcsg"], "");
    assert_eq!((run.status, run.stderr.as_str()), (1, ""));
    for diagnostic in json(&run) {
        let keys: Vec<&str> = diagnostic
            .as_object()
            .unwrap()
            .keys()
            .map(String::as_str)
            .collect();
        let mut expected = [
            "byte_range",
            "code",
            "file",
            "help",
            "labels",
            "message",
            "range",
            "severity",
        ];
        expected.sort_unstable();
        assert_eq!(keys, expected);
    }
    insta::assert_snapshot!(run.stdout_text());
}

#[test]
fn help_and_labels_in_included_files_are_rendered() {
    let run = qcsg(&["check", "names.qcsg"], "");
    assert_eq!(run.status, 1);
    insta::assert_snapshot!("names_human", run.stderr);

    let run = qcsg(&["check", "--format", "json", "names.qcsg"], "");
    assert_eq!(run.status, 1);
    let diagnostics = json(&run);
    let in_library = diagnostics
        .iter()
        .flat_map(|d| d["labels"].as_array().unwrap())
        .find(|label| label["file"] == "lib/parts.qcsg")
        .unwrap_or_else(|| panic!("a label in lib/parts.qcsg:\n{}", run.stdout_text()));
    assert_eq!(in_library["range"]["start"]["line"], 1);
    insta::assert_snapshot!("names_json", run.stdout_text());
}

#[test]
fn qcsg_path_is_searched_for_use_and_include() {
    let without = qcsg(&["check", "--format", "json", "uses_search_path.qcsg"], "");
    assert_eq!(without.status, 1);
    assert!(
        json(&without).iter().any(|d| d["code"] == "E0401"),
        "{}",
        without.stdout_text()
    );

    let library = fixtures().join("search_path");
    let search_path = format!("/no/such/directory::{}", library.display());
    let with = qcsg_with_path(&["check", "uses_search_path.qcsg"], "", Some(&search_path));
    assert_eq!(
        (with.status, with.stderr.as_str()),
        (0, "0 errors, 0 warnings\n")
    );
}

#[test]
fn json_columns_count_utf16_code_units() {
    let run = qcsg(&["check", "--format", "json", "unicode.qcsg"], "");
    assert_eq!(run.status, 1);
    let text = std::fs::read_to_string(fixtures().join("unicode.qcsg")).unwrap();
    let at = text.find('@').unwrap();
    let line_start = text[..at].rfind('\n').unwrap() + 1;
    let diagnostics = json(&run);
    let diagnostic = diagnostics
        .iter()
        .find(|d| d["byte_range"][0] == at)
        .unwrap_or_else(|| {
            panic!(
                "a diagnostic at the `@` (byte {at}):\n{}",
                run.stdout_text()
            )
        });
    let utf16: usize = text[line_start..at].encode_utf16().count();
    assert_ne!(
        utf16,
        at - line_start,
        "the line must have multi-byte text before the error"
    );
    assert_eq!(
        diagnostic["range"]["start"],
        serde_json::json!({"line": 1, "character": utf16})
    );
    assert_eq!(diagnostic["file"], "unicode.qcsg");
}

#[test]
fn quiet_keeps_errors_only() {
    let run = qcsg(&["check", "-q", "syntax_errors.qcsg"], "");
    assert_eq!(run.status, 1);
    assert!(run.stderr.contains("error["), "{}", run.stderr);
    assert!(
        !run.stderr.contains("errors,"),
        "no summary line:\n{}",
        run.stderr
    );
}

#[test]
fn dash_reads_standard_input_as_stdin() {
    let source = std::fs::read_to_string(fixtures().join("syntax_errors.qcsg")).unwrap();
    let run = qcsg(&["check", "--format", "json", "-"], &source);
    assert_eq!(run.status, 1);
    let diagnostics = json(&run);
    assert!(!diagnostics.is_empty());
    assert!(
        diagnostics.iter().all(|d| d["file"] == "<stdin>"),
        "{}",
        run.stdout_text()
    );

    let run = qcsg(&["check", "-"], "cube(1);\n");
    assert_eq!(run.status, 0, "{}", run.stderr);
}

#[test]
fn unreadable_input_exits_2() {
    let run = qcsg(&["check", "no-such-file.qcsg"], "");
    assert_eq!(run.status, 2);
    assert!(
        run.stderr.contains("cannot read `no-such-file.qcsg`"),
        "{}",
        run.stderr
    );

    // A directory is not a readable file either; the readable file is still checked.
    let run = qcsg(
        &["check", "--format", "json", ".", "syntax_errors.qcsg"],
        "",
    );
    assert_eq!(run.status, 2);
    assert!(run.stderr.contains("cannot read `.`"), "{}", run.stderr);
    assert!(!json(&run).is_empty());
}

#[test]
fn usage_errors_exit_2() {
    for args in [
        &["check"][..],
        &["check", "--format", "xml", "clean.qcsg"],
        &["check", "-D", "novalue", "clean.qcsg"],
        &["check", "--threads", "0", "clean.qcsg"],
        &["check", "--no-such-flag", "clean.qcsg"],
        &["no-such-command"],
        &[],
    ] {
        let run = qcsg(args, "");
        assert_eq!(run.status, 2, "qcsg {args:?}:\n{}", run.stderr);
    }
    assert_eq!(qcsg(&["--help"], "").status, 0);
    assert_eq!(qcsg(&["--version"], "").status, 0);
}

#[test]
fn common_flags_are_accepted() {
    let run = qcsg(
        &[
            "check",
            "-D",
            "w=3",
            "-D",
            "$fn=12",
            "--threads",
            "2",
            "clean.qcsg",
        ],
        "",
    );
    assert_eq!(run.status, 0, "{}", run.stderr);
}

#[test]
fn several_files_report_in_argument_order_for_any_thread_count() {
    let files = [
        "syntax_errors.qcsg",
        "clean.qcsg",
        "unicode.qcsg",
        "syntax_errors.qcsg",
    ];
    let run_with = |threads: &str| {
        let mut args = vec!["check", "--format", "json", "--threads", threads];
        args.extend(files);
        qcsg(&args, "")
    };
    let one = run_with("1");
    assert_eq!(one.status, 1);
    let names: Vec<String> = json(&one)
        .iter()
        .map(|d| d["file"].as_str().unwrap().to_owned())
        .collect();
    let mut order = names.clone();
    order.dedup();
    assert_eq!(
        order,
        ["syntax_errors.qcsg", "unicode.qcsg", "syntax_errors.qcsg"]
    );
    assert_eq!(run_with("3").stdout, one.stdout);
}

#[test]
fn check_takes_the_evaluation_limit_flags() {
    let program = "for (i = [0 : 99]) translate([i, 0, 0]) cube(1);\n";
    let default = qcsg(&["check", "--format", "json", "-"], program);
    assert_eq!(default.status, 0, "{}", default.stderr);

    let limited = qcsg(
        &["check", "--format", "json", "--max-instances", "10", "-"],
        program,
    );
    assert_eq!(limited.status, 1, "{}", limited.stderr);
    let diagnostics = json(&limited);
    let limit = diagnostics
        .iter()
        .find(|d| d["code"] == "E0559")
        .unwrap_or_else(|| panic!("no instance limit diagnostic: {diagnostics:?}"));
    // At the primitive that crossed the limit, on the program's only line.
    assert_eq!(limit["range"]["start"]["line"], 0);
    assert!(
        limit["help"]
            .as_str()
            .is_some_and(|h| h.contains("--max-instances"))
    );
}
