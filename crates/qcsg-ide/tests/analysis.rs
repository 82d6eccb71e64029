//! The analyses over in-memory programs, as the language server calls them.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use qcsg_diag::LineIndex;
use qcsg_ide::*;

#[derive(Default)]
struct Files(HashMap<PathBuf, String>);

impl FileLoader for Files {
    fn load(&self, path: &Path) -> std::io::Result<String> {
        self.0
            .get(path)
            .cloned()
            .ok_or_else(|| std::io::ErrorKind::NotFound.into())
    }
}

fn analyze(text: &str) -> Analysis {
    let files = Files(
        [(
            PathBuf::from("dir/lib.scad"),
            "/// A library part.\nmodule part(size = 2) cube(size);\nlib_width = 3;\n".to_owned(),
        )]
        .into_iter()
        .collect(),
    );
    Analysis::new(
        "dir/main.qcsg",
        text.to_owned(),
        &CheckOptions::default(),
        &files,
    )
}

/// The position of the `nth` occurrence of `needle`, plus `shift` bytes.
fn at(text: &str, needle: &str, nth: usize, shift: usize) -> LineCol {
    let offset = text.match_indices(needle).nth(nth).expect("needle").0 + shift;
    LineIndex::new(text).line_col(text, offset)
}

const PROGRAM: &str = "include <lib.scad>
/// Width of the plate.
width = 10 * 2;
module plate(w, thickness = 1) {
    cube([w, w, thickness]);
}
function twice(x) = 2 * x;
plate(width, 3);
part(lib_width);
echo(twice(width));
";

#[test]
fn diagnostics_carry_codes_help_and_related_locations() {
    let text = "width = 1;\ncube(widht);\nunused = 2;\n";
    let analysis = analyze(text);
    let diagnostics = analysis.diagnostics();
    let undefined = diagnostics
        .iter()
        .find(|d| d.code == "E0101")
        .expect("undefined");
    assert_eq!(undefined.range.start, at(text, "widht", 0, 0));
    assert!(
        undefined.message.contains("help: ") && undefined.message.contains("`width`"),
        "{}",
        undefined.message
    );
    let unused = diagnostics
        .iter()
        .find(|d| d.code == "W0101")
        .expect("unused");
    assert!(unused.unnecessary);
    let twice = analyze("x = 1;\nx = 2;\necho(x);\n").diagnostics();
    let reassigned = twice
        .iter()
        .find(|d| d.code == "W0105")
        .expect("reassignment");
    assert!(!reassigned.related.is_empty());
}

#[test]
fn hover_shows_values_docs_signatures_and_builtins() {
    let analysis = analyze(PROGRAM);
    let width = analysis
        .hover(at(PROGRAM, "width));", 0, 1))
        .expect("hover")
        .markdown;
    assert!(
        width.contains("width = 20") && width.contains("Width of the plate."),
        "{width}"
    );
    let plate = analysis
        .hover(at(PROGRAM, "plate(width", 0, 0))
        .expect("hover")
        .markdown;
    assert!(plate.contains("module plate(w, thickness = 1)"), "{plate}");
    let part = analysis
        .hover(at(PROGRAM, "part(lib", 0, 0))
        .expect("hover")
        .markdown;
    assert!(
        part.contains("A library part.") && part.contains("lib.scad"),
        "{part}"
    );
    let cube = analysis
        .hover(at(PROGRAM, "cube", 0, 1))
        .expect("hover")
        .markdown;
    assert!(
        cube.contains("module cube(size, center)") && cube.contains("built-in primitive"),
        "{cube}"
    );
    let param = analysis
        .hover(at(PROGRAM, "thickness]", 0, 0))
        .expect("hover")
        .markdown;
    assert!(param.contains("parameter of `plate`"), "{param}");
}

#[test]
fn definitions_references_and_rename() {
    let analysis = analyze(PROGRAM);
    let definition = analysis
        .goto_definition(at(PROGRAM, "width, 3", 0, 0))
        .expect("definition");
    assert_eq!(definition.range.start, at(PROGRAM, "width =", 0, 0));
    let into_library = analysis
        .goto_definition(at(PROGRAM, "part(", 0, 0))
        .expect("definition");
    assert_eq!(into_library.file, "dir/lib.scad");
    assert_eq!(
        into_library.range.start,
        LineCol {
            line: 1,
            character: 7
        }
    );
    let include = analysis
        .goto_definition(at(PROGRAM, "lib.scad", 0, 0))
        .expect("include");
    assert_eq!(include.file, "dir/lib.scad");

    let uses = analysis.references(at(PROGRAM, "width =", 0, 0), false);
    assert_eq!(uses.len(), 2);
    assert_eq!(
        analysis
            .references(at(PROGRAM, "width =", 0, 0), true)
            .len(),
        3
    );

    let edits = analysis
        .rename(at(PROGRAM, "twice(w", 0, 0), "double")
        .expect("rename");
    assert_eq!(edits.len(), 2);
    assert!(matches!(
        analysis.prepare_rename(at(PROGRAM, "cube", 0, 0)),
        Err(RenameError::Builtin(_))
    ));
    assert!(matches!(
        analysis.rename(at(PROGRAM, "width", 0, 0), "for"),
        Err(RenameError::InvalidName(_))
    ));
}

/// A variable reassigned many times is one variable: its references and a rename reach every
/// assignment and use, in time linear in them (found by fuzzing: 12,000 reassignments on one
/// line took the language server minutes, a fixed point over the reassignment links that was
/// cubic in their number).
#[test]
fn references_to_a_much_reassigned_variable_are_found_in_linear_time() {
    let n = 20_000;
    let text = format!("{}cube(ht);\n", "ht = 4;".repeat(n));
    let (done, finished) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let analysis = analyze(&text);
        let middle = LineCol {
            line: 0,
            character: (7 * (n / 2)) as u32,
        };
        let all = analysis.references(middle, true);
        let uses = analysis.references(middle, false);
        let renamed = analysis.rename(middle, "height").expect("rename").len();
        done.send((all.len(), uses.len(), renamed)).unwrap();
    });
    let (all, uses, renamed) = finished
        .recv_timeout(std::time::Duration::from_secs(60))
        .expect("references did not finish in 60 s (or panicked)");
    assert_eq!((all, uses, renamed), (n + 1, 1, n + 1));
}

#[test]
fn symbols_outline_the_file() {
    let analysis = analyze(PROGRAM);
    let names: Vec<_> = analysis
        .document_symbols()
        .iter()
        .map(|s| (s.name.clone(), s.kind))
        .collect();
    assert_eq!(
        names,
        [
            ("width".to_owned(), SymbolKind::Variable),
            ("plate".to_owned(), SymbolKind::Module),
            ("twice".to_owned(), SymbolKind::Function)
        ]
    );
    let found = analysis.workspace_symbols("PAR");
    assert_eq!(found.len(), 1);
    assert_eq!(found[0].location.file, "dir/lib.scad");
}

#[test]
fn completion_knows_scopes_builtins_and_named_arguments() {
    let text =
        "module m(size, height = 2) {\n    cube(size);\n    \n}\nm(size = 1, );\nlength = 3;\nl\n";
    let analysis = analyze(text);
    let inside = analysis.completions(at(text, "    \n", 0, 4));
    let labels: Vec<_> = inside.iter().map(|c| c.label.as_str()).collect();
    assert!(
        labels.contains(&"size") && labels.contains(&"height") && labels.contains(&"cylinder"),
        "{labels:?}"
    );
    let outside = analysis.completions(at(text, "l\n", 0, 1));
    let labels: Vec<_> = outside.iter().map(|c| c.label.as_str()).collect();
    assert!(
        labels.contains(&"length") && labels.contains(&"len") && !labels.contains(&"size"),
        "{labels:?}"
    );
    let named = analysis.completions(at(text, ", )", 0, 2));
    let labels: Vec<_> = named
        .iter()
        .filter(|c| c.kind == CompletionKind::Parameter)
        .map(|c| c.label.as_str())
        .collect();
    assert_eq!(labels[0], "height =");
    assert!(
        labels.contains(&"$fn =") && !labels.contains(&"size ="),
        "{labels:?}"
    );
}

#[test]
fn signature_help_tracks_the_argument() {
    let text = "cylinder(10, 2, );\n";
    let help = analyze(text)
        .signature_help(at(text, ", )", 0, 2))
        .expect("help");
    assert!(
        help.label.starts_with("cylinder(h, r1, r2"),
        "{}",
        help.label
    );
    assert_eq!(help.active_param, Some(2));
}

#[test]
fn semantic_tokens_classify_names() {
    let text = "module m(p) cube(p); // c\n$fn = 8;\nm(1);\n";
    let tokens = analyze(text).semantic_tokens();
    let kind_at = |needle: &str, nth: usize| {
        let position = at(text, needle, nth, 0);
        tokens
            .iter()
            .find(|t| t.line == position.line && t.start == position.character)
            .map(|t| (t.kind, t.modifiers))
    };
    assert_eq!(kind_at("module", 0).map(|k| k.0), Some(TokenKind::Keyword));
    assert_eq!(
        kind_at("m(", 0),
        Some((
            TokenKind::Module,
            TokenModifiers(TokenModifiers::DECLARATION)
        ))
    );
    assert_eq!(kind_at("p)", 0).map(|k| k.0), Some(TokenKind::Parameter));
    assert_eq!(
        kind_at("cube", 0),
        Some((
            TokenKind::Module,
            TokenModifiers(TokenModifiers::DEFAULT_LIBRARY)
        ))
    );
    assert_eq!(kind_at("// c", 0).map(|k| k.0), Some(TokenKind::Comment));
    assert_eq!(
        kind_at("$fn", 0).map(|k| k.0),
        Some(TokenKind::SpecialVariable)
    );
    assert_eq!(kind_at("8", 0).map(|k| k.0), Some(TokenKind::Number));
}

#[test]
fn inlay_hints_name_parameters_and_show_values() {
    let text = "a = 2;\nb = a * 3 + 1;\ncylinder(b, 1);\n";
    let analysis = analyze(text);
    let whole = TextRange {
        start: LineCol {
            line: 0,
            character: 0,
        },
        end: LineCol {
            line: 9,
            character: 0,
        },
    };
    let labels: Vec<_> = analysis
        .inlay_hints(whole)
        .into_iter()
        .map(|h| h.label)
        .collect();
    assert_eq!(labels, ["= 7", "h =", "r1 ="]);
}

#[test]
fn folding_covers_blocks_and_comment_runs() {
    let text = "// one\n// two\nmodule m() {\n    cube(1);\n}\n";
    let ranges = analyze(text).folding_ranges();
    assert!(ranges.contains(&FoldingRange {
        start_line: 0,
        end_line: 1,
        kind: FoldKind::Comment
    }));
    assert!(ranges.contains(&FoldingRange {
        start_line: 2,
        end_line: 3,
        kind: FoldKind::Region
    }));
}

#[test]
fn code_actions_fix_the_obvious() {
    let text = "width = 1;\ncube(widht);\nspare = 2;\ncube(depth);\n";
    let analysis = analyze(text);
    let everything = TextRange {
        start: LineCol {
            line: 0,
            character: 0,
        },
        end: LineCol {
            line: 4,
            character: 0,
        },
    };
    let actions = analysis.code_actions(everything);
    let titles: Vec<_> = actions.iter().map(|a| a.title.as_str()).collect();
    assert!(titles.contains(&"Change `widht` to `width`"), "{titles:?}");
    assert!(titles.contains(&"Declare `depth`"), "{titles:?}");
    let remove = actions
        .iter()
        .find(|a| a.title == "Remove unused `spare`")
        .expect("remove");
    assert_eq!(
        remove.edits[0].range.start,
        LineCol {
            line: 2,
            character: 0
        }
    );
    assert_eq!(
        remove.edits[0].range.end,
        LineCol {
            line: 3,
            character: 0
        }
    );
}

#[test]
fn broken_text_still_answers() {
    for text in [
        "module m( {",
        "x = ;\ncube(",
        "include <",
        "for (i = [0:",
        "\u{1F600} = 1;",
    ] {
        let analysis = analyze(text);
        let end = analysis.position(analysis.main(), text.len());
        let _ = analysis.hover(end);
        let _ = analysis.completions(end);
        let _ = analysis.signature_help(end);
        let _ = analysis.semantic_tokens();
        let _ = analysis.folding_ranges();
        let _ = analysis.inlay_hints(TextRange {
            start: LineCol {
                line: 0,
                character: 0,
            },
            end,
        });
    }
}

/// OpenSCAD's deprecated `assign` binds its named arguments for its child as `let` does: hover,
/// go to definition and completion treat them alike; `child` hovers as a built-in.
#[test]
fn assign_bindings_are_let_bindings() {
    let text = "module m() child(0);\nassign(depth = 2, wide = 3) {\n    m() cube([wide, depth, 1]);\n    \n}\nd\n";
    let analysis = Analysis::new(
        "dir/old.scad",
        text.to_owned(),
        &CheckOptions::default(),
        &Files::default(),
    );
    let codes: Vec<_> = analysis.sema().diagnostics.iter().map(|d| d.code).collect();
    assert!(!codes.iter().any(|c| c.starts_with("E01")), "{codes:?}");
    let hover = analysis
        .hover(at(text, "wide, depth", 0, 0))
        .expect("hover")
        .markdown;
    assert!(
        hover.contains("wide") && hover.contains("`let` variable"),
        "{hover}"
    );
    let definition = analysis
        .goto_definition(at(text, "depth, 1", 0, 0))
        .expect("definition");
    assert_eq!(definition.range.start, at(text, "depth = 2", 0, 0));
    let inside = analysis.completions(at(text, "    \n", 0, 4));
    let labels: Vec<_> = inside.iter().map(|c| c.label.as_str()).collect();
    assert!(
        labels.contains(&"depth") && labels.contains(&"wide"),
        "{labels:?}"
    );
    let outside = analysis.completions(at(text, "d\n", 0, 1));
    let labels: Vec<_> = outside.iter().map(|c| c.label.as_str()).collect();
    assert!(!labels.contains(&"depth"), "{labels:?}");
    let child = analysis
        .hover(at(text, "child(0)", 0, 0))
        .expect("hover")
        .markdown;
    assert!(child.contains("children(i)"), "{child}");
}
