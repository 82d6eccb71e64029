//! The checker never panics, whatever the input: random token soups and mutations of valid
//! programs all come back as an analysis.

use std::path::Path;

use proptest::prelude::*;
use qcsg_sema::{CheckOptions, FileLoader, check_file};

/// Every include resolves to a small fixed library that includes itself back.
struct Library;

impl FileLoader for Library {
    fn load(&self, path: &Path) -> std::io::Result<String> {
        if path.to_string_lossy().ends_with("lib.scad") {
            Ok("include <lib.scad>\nmodule lib(a) cube(a);\nfunction f(x) = x;\nv = 1;\n".into())
        } else {
            Err(std::io::ErrorKind::NotFound.into())
        }
    }
}

const TOKENS: &[&str] = &[
    "module",
    "function",
    "if",
    "else",
    "for",
    "let",
    "each",
    "include <lib.scad>",
    "use <lib.scad>",
    "x",
    "y",
    "f",
    "lib",
    "cube",
    "sphere",
    "translate",
    "children",
    "$fn",
    "$x",
    "intersection_for",
    "polyhedron",
    "echo",
    "assert",
    "1",
    "2.5",
    "\"s\"",
    "true",
    "undef",
    "(",
    ")",
    "[",
    "]",
    "{",
    "}",
    ",",
    ";",
    "=",
    "+",
    "-",
    "*",
    "/",
    "%",
    "^",
    "!",
    "#",
    "?",
    ":",
    ".",
    "<",
    "==",
    "&&",
    "function (a)",
    "\n",
];

fn soup() -> impl Strategy<Value = String> {
    prop::collection::vec(prop::sample::select(TOKENS), 0..120).prop_map(|tokens| tokens.join(" "))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]

    #[test]
    fn token_soup_never_panics(text in soup()) {
        let analysis = check_file("dir/main.scad", text, &CheckOptions::default(), &Library);
        for diagnostic in &analysis.diagnostics {
            let source = analysis.sources.get(diagnostic.file);
            prop_assert!(diagnostic.span.end as usize <= source.text.len());
        }
    }

    #[test]
    fn truncated_programs_never_panic(cut in 0usize..400) {
        let program = "include <lib.scad>\nmodule m(a = 1, b) { for (i = [0 : a], j = [i : 2]) translate([i, j, 0]) children(); }\nm(b = 2) lib(v);\nw = [for (k = 0; k < 3; k = k + 1) let (q = k) if (q > 1) q else each [q]];\necho(f(w), $x);\n";
        let end = program.char_indices().map(|(i, _)| i).take_while(|&i| i <= cut).last().unwrap_or(0);
        let _ = check_file("main.scad", program[..end].to_string(), &CheckOptions::default(), &Library);
    }
}
