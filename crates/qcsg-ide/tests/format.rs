//! Formatter properties over every program of the repository (`examples/`, `tests/`) and every
//! line-prefix of them that parses: formatting is idempotent, and it changes whitespace only.

use std::path::{Path, PathBuf};

use qcsg_diag::FileId;
use qcsg_ide::format::format;
use qcsg_syntax::lexer::lex;

fn programs(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() {
            programs(&path, out);
        } else if path.extension().is_some_and(|e| e == "scad" || e == "qcsg") {
            out.push(path);
        }
    }
}

/// Tokens and comments as text, in order: what formatting must not change.
fn words(text: &str) -> Vec<String> {
    let lexed = lex(text, FileId(0));
    let mut spans: Vec<_> = lexed.tokens.iter().map(|(_, span)| *span).collect();
    spans.extend(lexed.comments.iter().map(|c| c.span));
    spans.sort_by_key(|s| s.start);
    spans.iter().map(|s| text[s.range()].to_owned()).collect()
}

fn check(name: &str, text: &str) -> bool {
    let Ok(once) = format(text) else { return false };
    let twice = format(&once)
        .unwrap_or_else(|e| panic!("{name}: formatted text does not parse: {e}\n{once}"));
    assert_eq!(once, twice, "{name}: formatting is not idempotent");
    assert_eq!(
        words(text),
        words(&once),
        "{name}: formatting changed more than whitespace"
    );
    true
}

#[test]
fn formatting_is_idempotent_and_changes_only_whitespace() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut files = Vec::new();
    programs(&root.join("examples"), &mut files);
    programs(&root.join("tests"), &mut files);
    files.sort();
    assert!(!files.is_empty(), "no programs found");
    let mut formatted = 0;
    for file in &files {
        let text = std::fs::read_to_string(file).expect("readable");
        let name = file.display().to_string();
        formatted += usize::from(check(&name, &text));
        // Every prefix of whole lines that parses, and the whole text squeezed onto few lines.
        let lines: Vec<&str> = text.split_inclusive('\n').collect();
        for end in 0..lines.len() {
            check(
                &format!("{name} (first {end} lines)"),
                &lines[..end].concat(),
            );
        }
        check(
            &format!("{name} (no indentation)"),
            &lines.iter().map(|l| l.trim_start()).collect::<String>(),
        );
    }
    assert!(
        formatted * 2 >= files.len(),
        "most programs must be formattable ({formatted} of {})",
        files.len()
    );
}

#[test]
fn style_examples() {
    let cases = [
        ("x=1;", "x = 1;\n"),
        ("x = -a+b*-c;", "x = -a + b * -c;\n"),
        (
            "translate([1,0,0])cube(1);",
            "translate([1, 0, 0]) cube(1);\n",
        ),
        (
            "v=[for(i=[0:3])[i,i*2]];",
            "v = [for (i = [0 : 3]) [i, i * 2]];\n",
        ),
        (
            "module m(a=1){\ncube(a);\n}",
            "module m(a = 1) {\n    cube(a);\n}\n",
        ),
        (
            "*cube(1);\n%sphere(2);\n#cube(3);",
            "*cube(1);\n%sphere(2);\n#cube(3);\n",
        ),
        ("y = f(1)%2;", "y = f(1) % 2;\n"),
        (
            "if(a)\ncube(1);\nelse\nsphere(1);",
            "if (a)\n    cube(1);\nelse\n    sphere(1);\n",
        ),
        ("x = 1;\n\n\n\ny = 2;  \n", "x = 1;\n\ny = 2;\n"),
        (
            "include<lib.scad>\nx = v.x;",
            "include <lib.scad>\nx = v.x;\n",
        ),
        ("x = 1;   // note\n", "x = 1;   // note\n"),
        // A member of a number keeps its space: `2.t` would lex as `2.` and `t`.
        ("x=[2 .t];", "x = [2 .t];\n"),
        ("a = [\n1,\n2\n];", "a = [\n    1,\n    2\n];\n"),
    ];
    for (input, expected) in cases {
        assert_eq!(
            format(input).as_deref(),
            Ok(expected),
            "formatting {input:?}"
        );
    }
}

#[test]
fn syntax_errors_are_refused() {
    assert!(format("x = ;").is_err());
    assert!(format("module m( {").is_err());
}

/// A `.scad` file's escapes that OpenSCAD accepts (`\q`, `\0`) are warnings there, so the file
/// formats, with its strings kept as written; the same text as `.qcsg` has errors and is refused.
#[test]
fn scad_escapes_do_not_stop_formatting() {
    let text = "echo(  \"a\\0b\\qc\" );\n";
    assert_eq!(
        qcsg_ide::format::format_file("dir/old.scad", text).expect("formats"),
        "echo(\"a\\0b\\qc\");\n"
    );
    assert!(qcsg_ide::format::format_file("dir/new.qcsg", text).is_err());
    assert!(format(text).is_err());
}
