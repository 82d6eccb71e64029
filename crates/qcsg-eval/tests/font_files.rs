//! `use <file.ttf>`: as in OpenSCAD 2021.01, a font file named by `use` registers its faces for
//! `text(font = …)`; a missing, unreadable or non-TrueType file is an error at its `<path>`.

mod common;

use std::path::Path;

use common::{codes, eval_in, scratch};
use qcsg_csg::{DnfOptions, build_dnf};
use qcsg_eval::EvalOptions;
use qcsg_sema::{CheckOptions, FsLoader, check_file};

/// The bundled Liberation Sans with its family renamed (same length, in both encodings of its
/// name table), so that no installed font has the family.
fn renamed_font(dir: &Path, file: &str) {
    let mut data = std::fs::read(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("fonts/LiberationSans-Regular.ttf"),
    )
    .expect("the bundled font");
    let replace = |data: &mut Vec<u8>, from: &[u8], to: &[u8]| {
        let mut at = 0;
        while let Some(i) = data[at..].windows(from.len()).position(|w| w == from) {
            data[at + i..at + i + to.len()].copy_from_slice(to);
            at += i + to.len();
        }
    };
    let utf16 = |s: &str| -> Vec<u8> { s.encode_utf16().flat_map(u16::to_be_bytes).collect() };
    replace(&mut data, b"Liberation Sans", b"Qcsgtest Glyphs");
    replace(
        &mut data,
        &utf16("Liberation Sans"),
        &utf16("Qcsgtest Glyphs"),
    );
    std::fs::write(dir.join(file), data).expect("write the font");
}

/// The error and warning codes of checking and evaluating `main` in `dir`.
fn all_codes(dir: &Path, main: &str) -> (Vec<&'static str>, Vec<(u32, u32)>) {
    let path = dir.join("main.scad");
    std::fs::write(&path, main).expect("write main.scad");
    let analysis = check_file(
        &path.to_string_lossy(),
        main.to_string(),
        &CheckOptions::default(),
        &FsLoader,
    );
    let e = qcsg_eval::evaluate(&analysis, &EvalOptions::default());
    let diagnostics: Vec<_> = analysis.diagnostics.iter().chain(&e.diagnostics).collect();
    (
        diagnostics.iter().map(|d| d.code).collect(),
        diagnostics
            .iter()
            .map(|d| (d.span.start, d.span.end))
            .collect(),
    )
}

#[test]
fn a_used_font_file_is_found_by_its_family() {
    let dir = scratch("font_files", "registered");
    renamed_font(&dir, "Glyphs.ttf");
    let text = "linear_extrude(1) text(\"Hi\", size = 10, font = \"Qcsgtest Glyphs\");";
    // Without the `use`, no font has the family: the default is used, with a warning.
    let without = eval_in(&dir, text, &EvalOptions::default());
    assert_eq!(codes(&without), vec!["W0566"]);
    // With it, the family is the file's, and draws the same glyphs as Liberation Sans.
    let with = eval_in(
        &dir,
        &format!("use <Glyphs.ttf>\n{text}"),
        &EvalOptions::default(),
    );
    assert_eq!(codes(&with), Vec::<&str>::new(), "{:?}", with.diagnostics);
    let dnf = build_dnf(&with.dag, &DnfOptions::default()).expect("a solid");
    let reference = eval_in(
        &dir,
        "linear_extrude(1) text(\"Hi\", size = 10, font = \"Liberation Sans\");",
        &EvalOptions::default(),
    );
    let expected = build_dnf(&reference.dag, &DnfOptions::default()).expect("a solid");
    assert_eq!(dnf.bounds, expected.bounds);
    // The extension is told in any case, and the file may sit in a folder beside the program.
    std::fs::create_dir_all(dir.join("fonts")).unwrap();
    renamed_font(&dir.join("fonts"), "GLYPHS.TTF");
    let nested = eval_in(
        &dir,
        &format!("use <fonts/GLYPHS.TTF>\n{text}"),
        &EvalOptions::default(),
    );
    assert_eq!(codes(&nested), Vec::<&str>::new());
}

#[test]
fn missing_unreadable_and_non_truetype_files_are_errors_at_the_path() {
    let dir = scratch("font_files", "errors");
    let at = |main: &str, path: &str| {
        let start = main.find(path).expect("the path") as u32 - 1;
        (start, start + path.len() as u32 + 2)
    };
    // Missing.
    let main = "use <Nowhere.ttf>\nlinear_extrude(1) text(\"A\");";
    let (found, spans) = all_codes(&dir, main);
    assert_eq!(found, vec!["E0401"]);
    assert_eq!(spans[0], at(main, "Nowhere.ttf"));
    // Not a font at all.
    std::fs::write(dir.join("notes.ttf"), "these are notes, not a font").unwrap();
    let main = "use <notes.ttf>\nlinear_extrude(1) text(\"A\");";
    let (found, spans) = all_codes(&dir, main);
    assert_eq!(found, vec!["E0569"]);
    assert_eq!(spans[0], at(main, "notes.ttf"));
    // A folder.
    std::fs::create_dir_all(dir.join("folder.otf")).unwrap();
    let main = "use <folder.otf>\nlinear_extrude(1) text(\"A\");";
    let (found, _) = all_codes(&dir, main);
    assert_eq!(found, vec!["E0403"]);
    // A truncated font.
    let whole = std::fs::read(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("fonts/LiberationSans-Regular.ttf"),
    )
    .unwrap();
    std::fs::write(dir.join("cut.ttf"), &whole[..200]).unwrap();
    let (found, _) = all_codes(&dir, "use <cut.ttf>\nlinear_extrude(1) text(\"A\");");
    assert_eq!(found, vec!["E0569"]);
}
