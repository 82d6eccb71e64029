//! The driver runs each stage only after the ones before it succeeded, and reports what each
//! stage finds, up to the stage asked for.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use qcsg_driver::{Options, Stage, compile};
use qcsg_sema::{FileLoader, FsLoader};

fn run(text: &str, stage: Stage) -> qcsg_driver::Compilation {
    compile(
        "main.qcsg",
        text.to_owned(),
        &Options::default(),
        &FsLoader,
        stage,
    )
}

fn codes(compilation: &qcsg_driver::Compilation) -> Vec<&str> {
    compilation
        .analysis
        .diagnostics
        .iter()
        .map(|d| d.code)
        .collect()
}

/// The text under a diagnostic's primary span.
fn spanned<'a>(text: &'a str, compilation: &qcsg_driver::Compilation, code: &str) -> &'a str {
    let d = compilation
        .analysis
        .diagnostics
        .iter()
        .find(|d| d.code == code)
        .unwrap_or_else(|| panic!("no {code}: {:#?}", compilation.analysis.diagnostics));
    &text[d.span.range()]
}

#[test]
fn each_stage_runs_only_as_far_as_asked() {
    let text = "sphere(3);";
    let checked = run(text, Stage::Check);
    assert!(checked.dag.is_none() && checked.layers.is_none());
    let evaluated = run(text, Stage::Evaluate);
    assert!(evaluated.dag.is_some() && evaluated.layers.is_none());
    let built = run(text, Stage::Dnf);
    assert!(
        codes(&built).is_empty(),
        "{:#?}",
        built.analysis.diagnostics
    );
    assert_eq!(built.solid().expect("a solid").quadrics.len(), 1);
}

#[test]
fn an_unbounded_scene_is_an_error_of_the_dnf_stage_at_the_unbounded_part() {
    let text = "union() { sphere(3); halfspace([0, 0, 1], 0); }";
    assert!(codes(&run(text, Stage::Evaluate)).is_empty());
    let built = run(text, Stage::Dnf);
    assert!(built.has_errors());
    assert!(built.layers.is_none());
    assert!(
        spanned(text, &built, "E0600").starts_with("halfspace"),
        "{:#?}",
        built.analysis.diagnostics
    );
}

#[test]
fn the_term_limit_is_an_option() {
    // A block minus 8 cubes that all overlap: the normal form multiplies out.
    let text = "difference() { cube(10); for (i = [0 : 7]) translate([i / 2, i / 3, 1]) cube(3); }";
    let mut options = Options::default();
    options.dnf.term_limit = 20;
    let built = compile("t.qcsg", text.to_owned(), &options, &FsLoader, Stage::Dnf);
    assert!(
        codes(&built).contains(&"E0601"),
        "{:#?}",
        built.analysis.diagnostics
    );
    options.dnf.term_limit = 1_000;
    let built = compile("t.qcsg", text.to_owned(), &options, &FsLoader, Stage::Dnf);
    assert!(!built.has_errors(), "{:#?}", built.analysis.diagnostics);
}

#[test]
fn an_evaluation_error_stops_before_the_dnf() {
    let built = run("assert(false, \"no\"); sphere(1);", Stage::Dnf);
    assert!(built.has_errors());
    assert!(built.dag.is_none() && built.layers.is_none());
}

#[test]
fn background_parts_are_layers_and_an_empty_scene_has_no_solid() {
    let built = run("%sphere(2);", Stage::Dnf);
    assert!(!built.has_errors(), "{:#?}", built.analysis.diagnostics);
    assert_eq!(built.layers.as_ref().expect("layers").backgrounds.len(), 1);
    // A scene with no solid statement is empty, not an error.
    let built = run("x = 1;", Stage::Dnf);
    assert!(!built.has_errors(), "{:#?}", built.analysis.diagnostics);
    assert!(built.solid().expect("a solid").terms.is_empty());
}

#[test]
fn highlighted_parts_are_layers_of_their_own() {
    let built = run("difference() { cube(4); #sphere(2); }", Stage::Dnf);
    let layers = built.layers.as_ref().expect("layers");
    assert_eq!(layers.highlights.len(), 1);
    assert!(layers.solid.is_some());
}

#[test]
fn overrides_reach_the_checker_and_the_evaluator() {
    let options = Options {
        defines: vec![("r".to_owned(), "5".to_owned())],
        ..Options::default()
    };
    let built = compile(
        "t.qcsg",
        "r = 1; sphere(r);".to_owned(),
        &options,
        &FsLoader,
        Stage::Dnf,
    );
    let solid = built.solid().expect("a solid");
    let size = solid.bounds.max - solid.bounds.min;
    assert!((size.x - 10.0).abs() < 1e-9, "{size}");
}

/// Files from memory, as an editor's unsaved buffers.
struct Buffers(HashMap<PathBuf, String>);

impl FileLoader for Buffers {
    fn load(&self, path: &Path) -> std::io::Result<String> {
        self.0
            .get(path)
            .cloned()
            .ok_or_else(|| std::io::Error::from(std::io::ErrorKind::NotFound))
    }
}

#[test]
fn included_files_come_through_the_loader_and_their_errors_stop_the_dnf() {
    let buffers = Buffers(HashMap::from([(
        PathBuf::from("lib/part.qcsg"),
        "module part() { halfspace([0, 0, 1], 0); }".to_owned(),
    )]));
    let built = compile(
        "main.qcsg",
        "use <lib/part.qcsg>\npart();".to_owned(),
        &Options::default(),
        &buffers,
        Stage::Dnf,
    );
    let unbounded = built
        .analysis
        .diagnostics
        .iter()
        .find(|d| d.code == "E0600")
        .unwrap_or_else(|| panic!("{:#?}", built.analysis.diagnostics));
    assert_ne!(
        unbounded.file,
        qcsg_diag::FileId::default(),
        "at the included file"
    );
}
