//! Runs the static-checking cases of the language suite (`tests/check/sema/` and
//! `tests/check/ok/`) through `check_file` and compares the diagnostics with their inline
//! annotations (format: `tests/README.md`). The workspace harness in the CLI crate runs the whole
//! suite; this copy keeps the checker's own cases close to the checker.

use std::path::{Path, PathBuf};

use qcsg_sema::{CheckOptions, FsLoader, check_file};

/// One expected or reported diagnostic: line, start column, end (column on the same line, or
/// `None` for "a later line" / "unstated"), severity and code.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
struct Expect {
    line: usize,
    column: usize,
    end: Option<usize>,
    severity: String,
    code: String,
    fragment: String,
}

fn annotations(text: &str) -> Vec<(Expect, bool)> {
    let mut out = Vec::new();
    let mut target_line = 0;
    for (number, line) in text.lines().enumerate() {
        let trimmed = line.trim_start();
        let Some(rest) = trimmed.strip_prefix("//") else {
            target_line = number;
            continue;
        };
        let body = rest.trim_start();
        if let Some(at) = body.strip_prefix('@') {
            // `//@ L:C severity[CODE]`
            let mut words = at.split_whitespace();
            let (Some(position), Some(tag)) = (words.next(), words.next()) else {
                continue;
            };
            let Some((l, c)) = position.split_once(':') else {
                continue;
            };
            let (Ok(l), Ok(c)) = (l.parse::<usize>(), c.parse::<usize>()) else {
                continue;
            };
            let (severity, code) = split_tag(tag);
            out.push((
                Expect {
                    line: l - 1,
                    column: c - 1,
                    end: None,
                    severity,
                    code,
                    fragment: fragment_of(at),
                },
                true,
            ));
            continue;
        }
        if !(body.starts_with('^') || body.starts_with('|')) {
            target_line = number;
            continue;
        }
        let column = line.find(['^', '|']).unwrap_or(0);
        let marks: String = line[column..]
            .chars()
            .take_while(|&c| c == '^' || c == '|')
            .collect();
        let after = &line[column + marks.len()..];
        let (end, after) = if let Some(after) = after.strip_prefix("...") {
            (None, after)
        } else if marks == "|" {
            (Some(column), after)
        } else {
            (Some(column + marks.len()), after)
        };
        let tag = after.split_whitespace().next().unwrap_or("");
        let (severity, code) = split_tag(tag.trim_end_matches(':'));
        out.push((
            Expect {
                line: target_line,
                column,
                end,
                severity,
                code,
                fragment: fragment_of(after),
            },
            false,
        ));
    }
    out
}

/// The message fragment after `]:`, if any.
fn fragment_of(text: &str) -> String {
    text.split_once("]:")
        .map(|(_, f)| f.trim().to_string())
        .unwrap_or_default()
}

fn split_tag(tag: &str) -> (String, String) {
    let (severity, code) = tag.split_once('[').unwrap_or((tag, ""));
    (
        severity.to_string(),
        code.trim_end_matches(']')
            .trim_end_matches(':')
            .trim_end_matches(']')
            .to_string(),
    )
}

fn cases(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    let mut paths: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
    paths.sort();
    for path in paths {
        if path.is_dir() {
            if path.file_name().is_some_and(|n| n != "lib") {
                cases(&path, out);
            }
        } else if path.extension().is_some_and(|e| e == "scad" || e == "qcsg") {
            out.push(path);
        }
    }
}

fn check_case(path: &Path) -> Result<(), String> {
    let text = std::fs::read_to_string(path).map_err(|e| e.to_string())?;
    let analysis = check_file(
        &path.to_string_lossy(),
        text,
        &CheckOptions::default(),
        &FsLoader,
    );
    let mut report = String::new();
    for (file, source) in analysis.sources.iter() {
        let expected = annotations(&source.text);
        let mut reported: Vec<(Expect, String)> = analysis
            .diagnostics
            .iter()
            .filter(|d| d.file == file)
            .map(|d| {
                let start = source
                    .line_index
                    .line_col(&source.text, d.span.start as usize);
                let end = source
                    .line_index
                    .line_col(&source.text, d.span.end as usize);
                let line_start = source.line_index.line_start(start.line).unwrap_or(0);
                let column = d.span.start as usize - line_start;
                let end = (end.line == start.line).then(|| d.span.end as usize - line_start);
                let expect = Expect {
                    line: start.line as usize,
                    column,
                    end,
                    severity: d.severity.as_str().to_string(),
                    code: d.code.to_string(),
                    fragment: String::new(),
                };
                (expect, d.message.clone())
            })
            .collect();
        let mut missing = Vec::new();
        for (want, unstated_end) in &expected {
            let found = reported.iter().position(|(got, message)| {
                message.contains(&want.fragment)
                    && got.line == want.line
                    && got.column == want.column
                    && got.severity == want.severity
                    && got.code == want.code
                    && (*unstated_end
                        || (want.end.is_none() && got.end.is_none())
                        || want.end == got.end)
            });
            match found {
                Some(index) => {
                    reported.remove(index);
                }
                None => missing.push(want.clone()),
            }
        }
        for want in missing {
            report.push_str(&format!(
                "  {}: expected, not reported: {want:?}\n",
                source.name
            ));
        }
        for (got, message) in reported {
            report.push_str(&format!(
                "  {}: reported, not expected: {got:?} {message}\n",
                source.name
            ));
        }
    }
    if report.is_empty() {
        Ok(())
    } else {
        Err(report)
    }
}

#[test]
fn sema_and_ok_cases() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/check");
    let mut all = Vec::new();
    cases(&root.join("sema"), &mut all);
    cases(&root.join("ok"), &mut all);
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
    let mut all = Vec::new();
    cases(&root, &mut all);
    let mut failures = String::new();
    for path in &all {
        if let Err(report) = check_case(path) {
            failures.push_str(&format!("FAIL {}\n{report}", path.display()));
        }
    }
    assert!(failures.is_empty(), "{failures}");
}
