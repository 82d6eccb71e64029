//! Error recovery: every independent error is reported once, at its exact span, and the tree
//! keeps everything around it.
//!
//! Cases use the inline annotation format of the workspace's language suite (`tests/README.md`):
//! a `//` line whose first non-blank character after `//` is `^` or `|` annotates the nearest
//! line above it that is not an annotation; `//@ L:C severity[CODE]` annotates by position.

use std::path::Path;

use qcsg_syntax::{Dialect, FileId, parse, parse_as, sexpr::file_to_sexpr};

/// An expected diagnostic: code, start, end (`None`: any end), message fragment.
type Expected = (String, usize, Option<usize>, String);

fn annotations(text: &str) -> Vec<Expected> {
    let mut line_starts = vec![0];
    line_starts.extend(text.match_indices('\n').map(|(i, _)| i + 1));
    let mut expected = Vec::new();
    let mut target: Option<usize> = None;
    for (index, line) in text.split('\n').enumerate() {
        let trimmed = line.trim_start();
        let body = trimmed.strip_prefix("//").map(str::trim_start);
        if let Some(body) = body.filter(|b| b.starts_with('^') || b.starts_with('|'))
            && let Some(target) = target
        {
            let marks: String = body.chars().take_while(|&c| c == '^' || c == '|').collect();
            let column = line.find(&marks).expect("marks are in the line");
            let start = line_starts[target] + column;
            let end = if marks == "|" {
                start
            } else {
                start + marks.len()
            };
            let rest = &body[marks.len()..];
            let (code, fragment) = parse_severity(rest);
            expected.push((code, start, Some(end), fragment));
            continue;
        }
        if let Some(at) = line.find("//@ ") {
            let rest = &line[at + 4..];
            let (position, rest) = rest.split_once(' ').expect("L:C then severity");
            let (l, c) = position.split_once(':').expect("L:C");
            let start =
                line_starts[l.parse::<usize>().unwrap() - 1] + c.parse::<usize>().unwrap() - 1;
            let (code, fragment) = parse_severity(rest);
            expected.push((code, start, None, fragment));
            continue;
        }
        target = Some(index);
    }
    expected
}

/// `error[E0002]: fragment` to (code, fragment).
fn parse_severity(text: &str) -> (String, String) {
    let open = text.find('[').expect("severity[CODE]");
    let close = text.find(']').expect("severity[CODE]");
    let code = text[open + 1..close].to_owned();
    let fragment = text[close + 1..].trim_start_matches(':').trim().to_owned();
    (code, fragment)
}

/// Parses `text` in the dialect of `name` and checks its diagnostics against its annotations
/// exactly.
fn check_annotated(name: &str, text: &str) {
    let parse = parse_as(text, FileId::default(), Dialect::of_file(name));
    // The cases also carry the checker's diagnostics (the language suite runs them through
    // `qcsg check`); the parser answers for its own codes.
    let expected: Vec<_> = annotations(text)
        .into_iter()
        .filter(|(code, ..)| qcsg_syntax::codes::ALL.iter().any(|(c, _)| c == code))
        .collect();
    let found: Vec<_> = parse
        .diagnostics
        .iter()
        .map(|d| {
            (
                d.code.to_owned(),
                d.span.start as usize,
                d.span.end as usize,
                d.message.clone(),
            )
        })
        .collect();
    for (code, start, end, fragment) in &expected {
        assert!(
            found.iter().any(|(c, s, e, m)| c == code
                && s == start
                && end.is_none_or(|end| end == *e)
                && m.contains(fragment.as_str())),
            "{name}: expected {code} at {start}..{end:?} ({fragment:?}); found {found:#?}"
        );
    }
    for (code, start, end, message) in &found {
        assert!(
            expected
                .iter()
                .any(|(c, s, e, _)| c == code && s == start && e.is_none_or(|e| e == *end)),
            "{name}: unexpected {code} at {start}..{end}: {message}"
        );
    }
}

#[test]
fn suite_syntax_cases() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/check/syntax");
    let mut count = 0;
    for entry in std::fs::read_dir(&dir).expect("tests/check/syntax exists") {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "scad" || e == "qcsg") {
            let text = std::fs::read_to_string(&path).unwrap();
            check_annotated(&path.display().to_string(), &text);
            count += 1;
        }
    }
    assert!(count > 0);
}

#[test]
fn independent_errors_each_reported() {
    check_annotated(
        "inline",
        "a = 1\n\
         //   | error[E0002]: expected `;` after assignment\n\
         b = [1, 2;\n\
         //       | error[E0002]: expected `]`\n\
         c = (1 + ) * 2;\n\
         //       ^ error[E0002]: expected expression, found `)`\n\
         module m( { cube(); }\n\
         //        ^ error[E0002]\n\
         d = 4;\n",
    );
}

#[test]
fn tree_survives_errors() {
    let text = "a = 1\ncube(a);\nb = (1 + ) * 2;\nmodule m(x) { sphere(x) }\nc = ;\nm(2);\n";
    let parse = parse(text, FileId::default());
    assert_eq!(
        file_to_sexpr(&parse.file),
        "(= a 1)\n(cube a)\n(= b (* (error) 2))\n(module m (x) (block (sphere x)))\n(error)\n(m 2)\n"
    );
    assert_eq!(parse.diagnostics.len(), 4, "{:#?}", parse.diagnostics);
}

#[test]
fn missing_semicolon_before_closing_brace_points_after_the_statement() {
    check_annotated(
        "inline",
        "union() { cube(1); sphere(1) }\n\
         //                          | error[E0002]: expected `;`\n",
    );
}

#[test]
fn lexical_errors_are_not_repeated_by_the_parser() {
    check_annotated(
        "inline",
        "x = 1 § 2;\n\
         //    ^^ error[E0001]\n\
         y = \"open\n\
         //  ^ error[E0003]\n",
    );
}
