//! The parser never panics, never hangs and keeps every span inside the text: random bytes,
//! token soups, mutations of real files, every prefix of every example, and deep nesting.

use std::path::{Path, PathBuf};

use proptest::prelude::*;
use qcsg_syntax::{FileId, Parse, parse};

/// Parses `text` and checks that every diagnostic span lies within it, on char boundaries.
fn check(text: &str) -> Parse {
    let parse = parse(text, FileId::default());
    for d in &parse.diagnostics {
        let range = d.span.range();
        assert!(
            range.start <= range.end && range.end <= text.len(),
            "{d:?} outside {text:?}"
        );
        assert!(
            text.is_char_boundary(range.start) && text.is_char_boundary(range.end),
            "{d:?} splits a character of {text:?}"
        );
        for label in &d.labels {
            assert!(
                label.span.end as usize <= text.len(),
                "{d:?} label outside {text:?}"
            );
        }
    }
    parse
}

/// Every `.qcsg` / `.scad` file under the workspace's `examples/` and `tests/`, plus this
/// crate's own corpus.
fn corpus() -> Vec<PathBuf> {
    let crate_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let workspace = crate_dir
        .parent()
        .and_then(Path::parent)
        .expect("crates/<name> layout");
    let mut files = Vec::new();
    let mut dirs = vec![
        workspace.join("examples"),
        workspace.join("tests"),
        crate_dir.join("tests"),
    ];
    while let Some(dir) = dirs.pop() {
        let Ok(entries) = std::fs::read_dir(&dir) else {
            continue;
        };
        for entry in entries.flatten() {
            let path = entry.path();
            if path.is_dir() {
                dirs.push(path);
            } else if matches!(
                path.extension().and_then(|e| e.to_str()),
                Some("qcsg" | "scad")
            ) {
                files.push(path);
            }
        }
    }
    files.sort();
    files
}

#[test]
fn corpus_parses_cleanly() {
    let crate_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(crate_dir.join("tests/data/all_syntax.scad")).unwrap();
    let parse = check(&text);
    assert!(parse.diagnostics.is_empty(), "{:#?}", parse.diagnostics);
}

#[test]
fn every_prefix_of_every_file() {
    let files = corpus();
    assert!(!files.is_empty());
    // Every byte position of files up to 1,500 bytes; longer files get 1,500 evenly spread cuts,
    // so that the test stays linear in the size of a growing corpus.
    for path in files {
        let text = std::fs::read_to_string(&path).unwrap_or_default();
        let stride = text.len().div_ceil(1_500).max(1);
        let cuts = (0..=text.len()).filter(|cut| cut % stride == 0 || *cut == text.len());
        for cut in cuts {
            if text.is_char_boundary(cut) {
                check(&text[..cut]);
            }
        }
    }
}

#[test]
fn deep_nesting_is_reported_not_overflowed() {
    for (open, close) in [("(", ")"), ("[", "]"), ("{", "}")] {
        let n = 100_000;
        let deep = format!("x = {}1{};", open.repeat(n), close.repeat(n));
        let parse = check(&deep);
        assert!(
            parse.diagnostics.iter().any(|d| d.code == "E0006"),
            "{open}"
        );
        let unclosed = format!("x = {}", open.repeat(n));
        check(&unclosed);
    }
    for prefix in ["-", "!", "+", "*", "#", "%"] {
        let text = format!(
            "x = {}1;\n{}cube();",
            prefix.repeat(100_000),
            prefix.repeat(100_000)
        );
        let parse = check(&text);
        assert!(
            parse.diagnostics.iter().any(|d| d.code == "E0006"),
            "{prefix}"
        );
    }
    let chains = [
        format!("x = 2{};", " ^ 2".repeat(20_000)),
        format!("x = 1{};", " + 1".repeat(20_000)),
        format!("x = {}c;", "a ? b : ".repeat(20_000)),
        format!("x = {}c;", "let (a = 1) ".repeat(20_000)),
        format!("x = {}c;", "function (a) ".repeat(20_000)),
        format!("x = {}c;", "echo(1) ".repeat(20_000)),
        format!("x = [{}c];", "for (i = a) ".repeat(20_000)),
        format!("x = [{}c];", "each ".repeat(20_000)),
        format!("x = f{};", "(1)".repeat(20_000)),
        format!("x = v{};", "[0]".repeat(20_000)),
        format!("x = v{};", ".x".repeat(20_000)),
        format!("x = {};", "(-".repeat(20_000)),
        format!("if (a) b();{}", " else if (a) b();".repeat(20_000)),
        format!("{}cube();", "translate([1, 0, 0]) ".repeat(20_000)),
        format!("{}cube();", "if (a) ".repeat(20_000)),
        format!("{}cube();", "for (i = a) ".repeat(20_000)),
        format!("{}cube();", "module m() ".repeat(20_000)),
    ];
    for text in &chains {
        let parse = check(text);
        assert!(
            parse.diagnostics.iter().any(|d| d.code == "E0006"),
            "{}",
            &text[..40]
        );
        assert!(
            parse.diagnostics.len() <= 3,
            "{}: {:#?}",
            &text[..40],
            parse.diagnostics
        );
    }
    // Many sibling statements are not nesting.
    let siblings = "module m() { cube(); }\nif (a) { b(); }\nx = 1;\n".repeat(2_000);
    assert!(check(&siblings).diagnostics.is_empty());
    // Nesting within the limit parses without diagnostics.
    let ok = format!("x = {}1{};", "(".repeat(200), ")".repeat(200));
    assert!(check(&ok).diagnostics.is_empty());
}

/// Broken text nested 200 deep. Recovery that re-parsed a failed construct from its parent took
/// twice as long per level (20 levels of `union(){` took 8.5 s), so each of these would run for
/// longer than the universe has existed; parsing them now takes milliseconds. A worker thread and
/// a deadline turn a regression into a failure instead of a hung test run.
#[test]
fn broken_nesting_recovers_in_linear_time() {
    let n = 200;
    let cases = [
        "union(){".repeat(n),
        format!("{} ) {}", "union(){".repeat(n), "}".repeat(n)),
        format!("{} ]; {}", "union(){".repeat(n), "}".repeat(n)),
        "module m(){".repeat(n),
        format!("{} ( {}", "{".repeat(n), "}".repeat(n)),
        format!("x = {};", "f(1, ".repeat(n)),
        format!("x = {}", "[for (i = ".repeat(n)),
        format!("x = {}", "let (a = ".repeat(n)),
        format!("x = {} ) {};", "[".repeat(n), "]".repeat(n)),
        format!("{} )", "if (1) ".repeat(n)),
        format!("{}{}", "union(){ cube() ) ".repeat(n), "}".repeat(n)),
        "echo(\n".repeat(n),
        format!("x = {}", "assert(1, ".repeat(n)),
        // An operand left open after an operator: the operator must not give it up and have
        // the enclosing expression parse it again (found by fuzzing, doubling per level).
        format!("x = {}2;", "2 * (1 + ".repeat(n)),
        format!("x = {}2 x;", "2 * [1 + ".repeat(n)),
        format!(
            "halfspace([0, 0, 1], 0.5 + {}i);",
            "1e-3 * (-1 + 2 * ".repeat(n)
        ),
        // A stray token among groups never closed, under `^` and a prefix `-`: the power's
        // operand failed at it, and `-19 ^ …` tried that operand twice (once inside the `-`,
        // once after it), doubling per level (found by fuzzing: 20 levels took 27 s).
        format!(
            "x = (10.40 < {}&{} 8.75));",
            "(-19 ^ ".repeat(n),
            "(-19 ^ ".repeat(n)
        ),
        format!("x = ({}`{} 1)", "-2 ^ (".repeat(n), "(-2 ^ ".repeat(n)),
        format!("x = {}\u{202e}1;", "(!1 ^ ".repeat(n)),
        // Many broken siblings: the work per error must not grow with the number of errors.
        "a = (1 ];\n".repeat(20 * n),
        ")".repeat(20 * n),
    ];
    let (done, finished) = std::sync::mpsc::channel();
    std::thread::Builder::new()
        .stack_size(64 * 1024 * 1024)
        .spawn(move || {
            for text in &cases {
                let parse = check(text);
                assert!(!parse.diagnostics.is_empty(), "{}", &text[..40]);
            }
            done.send(()).unwrap();
        })
        .unwrap();
    finished
        .recv_timeout(std::time::Duration::from_secs(60))
        .expect("parsing broken nested text did not finish in 60 s (or panicked)");
}

/// A stray `)` or `]` inside a block closes nothing (the parser skips it), so it must not count
/// as closing the block either: blocks left open, each holding one, nested as deep as the file
/// was long (found by fuzzing: 64,000 levels overflowed the stack, and 16,000 took seconds to
/// check).
#[test]
fn stray_closers_in_blocks_do_not_hide_their_nesting() {
    for line in ["module m() {\nchil);\n", "union() {\nx];\n", "{ a) }) {\n"] {
        let text = line.repeat(2_000);
        let parse = check(&text);
        assert!(
            parse.diagnostics.iter().any(|d| d.code == "E0006"),
            "{line:?} nested 2,000 deep without `nesting too deep`"
        );
    }
}

/// A block whose `}` is missing at the end of the file keeps its statements: the tree is what an
/// editor shows while the user is typing.
#[test]
fn unclosed_blocks_keep_their_statements() {
    let parse = check("union() {\n    cube(1);\n    translate([1, 0, 0]) {\n        sphere(2);\n");
    assert_eq!(parse.diagnostics.len(), 1, "{:#?}", parse.diagnostics);
    assert_eq!(
        parse.diagnostics[0].code, "E0008",
        "{:#?}",
        parse.diagnostics
    );
    let tree = qcsg_syntax::sexpr::file_to_sexpr(&parse.file);
    assert!(tree.contains("sphere"), "{tree}");
    let parse = check("union() { cube(1); ) sphere(2); }");
    assert_eq!(parse.diagnostics.len(), 1, "{:#?}", parse.diagnostics);
    let tree = qcsg_syntax::sexpr::file_to_sexpr(&parse.file);
    assert!(tree.contains("cube") && tree.contains("sphere"), "{tree}");
}

/// A `(` or `[` never closed in its statement is reported once and assumed closed there, and
/// what it holds stays in the tree; one closed further on is still a group skipped whole.
#[test]
fn groups_left_open_keep_their_contents() {
    let parse = check("x = 2 * (1 + 3;\ny = [1, 2 * (4;\n");
    assert_eq!(parse.diagnostics.len(), 3, "{:#?}", parse.diagnostics);
    let tree = qcsg_syntax::sexpr::file_to_sexpr(&parse.file);
    assert!(tree.contains("(+ 1 3)") && tree.contains("4"), "{tree}");
    let parse = check("b = (1 + ) * 2;");
    let tree = qcsg_syntax::sexpr::file_to_sexpr(&parse.file);
    assert_eq!(tree, "(= b (* (error) 2))\n", "{:#?}", parse.diagnostics);
}

#[test]
fn long_chains_parse() {
    let sum = format!("x = 1{};", " + 1".repeat(1_000));
    assert!(check(&sum).diagnostics.is_empty());
    let pow = format!("x = 2{};", " ^ 2".repeat(1_000));
    assert!(check(&pow).diagnostics.is_empty());
    let chain = format!("{}cube();", "translate([1, 0, 0]) ".repeat(500));
    assert!(check(&chain).diagnostics.is_empty());
    let elses = format!("if (a) b();{}", " else if (a) b();".repeat(400));
    assert!(check(&elses).diagnostics.is_empty());
}

const SOUP: &[&str] = &[
    "x", "$fn", "1", ".5", "\"s\"", "\"", "\\", "(", ")", "[", "]", "{", "}", ",", ";", "=", ":",
    "?", ".", "+", "-", "*", "/", "%", "^", "!", "#", "<", ">", "<=", "==", "!=", "&&", "||",
    "module", "function", "if", "else", "for", "let", "each", "true", "undef", "include", "use",
    "<a.scad>", "assert", "echo", "//", "/*", "*/", "\n", " ", "é", "@", "\0",
];

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn random_bytes(bytes in proptest::collection::vec(any::<u8>(), 0..200)) {
        check(&String::from_utf8_lossy(&bytes));
    }

    #[test]
    fn token_soup(picks in proptest::collection::vec(0..SOUP.len(), 0..120)) {
        let text: String = picks.iter().map(|&i| SOUP[i]).collect::<Vec<_>>().join(" ");
        check(&text);
        let tight: String = picks.iter().map(|&i| SOUP[i]).collect();
        check(&tight);
    }

    #[test]
    fn mutated_corpus(
        edits in proptest::collection::vec((any::<prop::sample::Index>(), 0..SOUP.len(), 0..3u8), 1..8)
    ) {
        let crate_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
        let mut text = std::fs::read_to_string(crate_dir.join("tests/data/all_syntax.scad")).unwrap();
        for (at, pick, how) in edits {
            let mut i = at.index(text.len() + 1);
            while !text.is_char_boundary(i) {
                i -= 1;
            }
            match how {
                0 => text.insert_str(i, SOUP[pick]),
                1 => {
                    let mut j = (i + 1 + pick).min(text.len());
                    while !text.is_char_boundary(j) {
                        j -= 1;
                    }
                    text.replace_range(i..j, "");
                }
                _ => {
                    let mut j = (i + 1).min(text.len());
                    while !text.is_char_boundary(j) {
                        j += 1;
                    }
                    text.replace_range(i..j, SOUP[pick]);
                }
            }
        }
        check(&text);
    }
}
