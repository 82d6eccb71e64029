//! Hover, signature help and completion know the 2-D shapes, `linear_extrude` and the version
//! functions, from the built-in tables of qcsg-sema.

use std::path::Path;

use qcsg_diag::LineIndex;
use qcsg_ide::*;

struct NoFiles;

impl FileLoader for NoFiles {
    fn load(&self, _: &Path) -> std::io::Result<String> {
        Err(std::io::ErrorKind::NotFound.into())
    }
}

fn analyze(text: &str) -> Analysis {
    Analysis::new(
        "main.scad",
        text.to_owned(),
        &CheckOptions::default(),
        &NoFiles,
    )
}

fn at(text: &str, needle: &str, shift: usize) -> LineCol {
    let offset = text.find(needle).expect("needle") + shift;
    LineIndex::new(text).line_col(text, offset)
}

const PROGRAM: &str = "linear_extrude(height = 2, scale = 0.5) square(3);
linear_extrude(4) circle(d = 2);
echo(version(), version_num());
module m() echo(parent_module(0));
m();
";

#[test]
fn hover_shows_the_new_builtins() {
    let analysis = analyze(PROGRAM);
    for (needle, expected) in [
        ("linear_extrude", "linear_extrude(height"),
        ("square", "module square(size, center)"),
        ("circle", "module circle(r"),
        ("version()", "[2021, 1, 0]"),
        ("version_num", "20210100"),
        ("parent_module", "parent_module(n"),
    ] {
        let hover = analysis
            .hover(at(PROGRAM, needle, 1))
            .unwrap_or_else(|| panic!("no hover on {needle}"))
            .markdown;
        assert!(hover.contains(expected), "{needle}: {hover}");
    }
}

#[test]
fn signature_help_and_completion_know_linear_extrude() {
    let text = "linear_extrude(3, );\n";
    let analysis = analyze(text);
    let help = analysis
        .signature_help(at(text, ", )", 2))
        .expect("signature help");
    assert!(
        help.label.starts_with("linear_extrude(height"),
        "{}",
        help.label
    );
    let named: Vec<_> = analysis
        .completions(at(text, ", )", 2))
        .into_iter()
        .filter(|c| c.kind == CompletionKind::Parameter)
        .map(|c| c.label)
        .collect();
    for name in ["center =", "scale =", "twist =", "convexity ="] {
        assert!(named.iter().any(|l| l == name), "{name} in {named:?}");
    }
    for name in [
        "square",
        "circle",
        "linear_extrude",
        "version",
        "parent_module",
    ] {
        let text = format!("{}\n", &name[..3]);
        let labels: Vec<_> = analyze(&text)
            .completions(at(&text, "\n", 0))
            .into_iter()
            .map(|c| c.label)
            .collect();
        assert!(labels.iter().any(|l| l == name), "{name} in {labels:?}");
    }
}
