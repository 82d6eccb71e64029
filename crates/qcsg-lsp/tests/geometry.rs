//! Evaluation in the editor: runtime diagnostics, included files' errors at the include line,
//! and hover listing the world-space quadrics of a call.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use qcsg_diag::LineIndex;
use qcsg_ide::*;
use qcsg_lsp::geometry::{Geometry, editor_limits};

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

fn analyze_with(text: &str, files: &[(&str, &str)]) -> Analysis {
    let files = Files(
        files
            .iter()
            .map(|(path, text)| (PathBuf::from(path), (*text).to_owned()))
            .collect(),
    );
    Analysis::new(
        "dir/main.qcsg",
        text.to_owned(),
        &CheckOptions::default(),
        &files,
    )
}

fn analyze(text: &str) -> Analysis {
    analyze_with(text, &[])
}

/// The position of the `nth` occurrence of `needle`.
fn at(text: &str, needle: &str, nth: usize) -> LineCol {
    let offset = text.match_indices(needle).nth(nth).expect("needle").0;
    LineIndex::new(text).line_col(text, offset)
}

/// The hover at the `nth` occurrence of `needle`, with the geometry.
fn geometry_hover(text: &str, needle: &str, nth: usize) -> String {
    let analysis = analyze(text);
    let geometry = Geometry::evaluate(&analysis, &editor_limits()).expect("no static errors");
    analysis
        .hover_with(at(text, needle, nth), Some(&geometry))
        .expect("hover")
        .markdown
}

/// The geometry section of a hover (after the last rule).
fn geometry_part(markdown: &str) -> &str {
    markdown
        .rsplit("\n---\n")
        .next()
        .filter(|part| part.contains("**geometry**"))
        .unwrap_or_else(|| panic!("no geometry in {markdown}"))
}

#[test]
fn a_translated_sphere_shows_its_world_centre_and_radius() {
    let text = "translate([1, 2, 3]) sphere(r = 5);\n";
    let geometry = geometry_hover(text, "sphere", 0).to_owned();
    let part = geometry_part(&geometry);
    assert!(part.contains("1 instance · 1 quadric"), "{part}");
    assert!(part.contains("**sphere**"), "{part}");
    assert!(part.contains("centre (1, 2, 3)"), "{part}");
    assert!(part.contains("radius 5"), "{part}");
    // The world matrix about the origin, as the primitive scales it (by 1/r²): the constant is
    // (1 + 4 + 9 − 25) / 25.
    assert!(part.contains("-0.44]`"), "{part}");
    // The transform above it becomes the same quadric.
    let outer = geometry_hover(text, "translate", 0);
    assert!(
        geometry_part(&outer).contains("centre (1, 2, 3)"),
        "{outer}"
    );
}

#[test]
fn loops_and_modules_count_their_instances() {
    let text = "module post(h) cylinder(h = h, r = 1);\n\
                for (i = [0 : 4]) translate([10 * i, 0, 0]) post(3);\n\
                post(7);\n";
    let in_loop = geometry_hover(text, "post", 1);
    let part = geometry_part(&in_loop);
    // Five posts of height 3, each a cylinder between two planes (or a slab).
    assert!(part.contains("5 instances"), "{part}");
    assert!(
        part.contains("instance 1:") && part.contains("instance 3:"),
        "{part}"
    );
    assert!(!part.contains("instance 4:"), "{part}");
    assert!(part.contains("… and 2 more instances"), "{part}");
    assert!(part.contains("elliptic cylinder"), "{part}");
    // The call outside the loop has different arguments: one instance.
    let single = geometry_hover(text, "post", 2);
    assert!(geometry_part(&single).contains("1 instance ·"), "{single}");
    // The primitive inside the module is instantiated six times in all.
    let cylinder = geometry_hover(text, "cylinder", 0);
    assert!(
        geometry_part(&cylinder).contains("6 instances"),
        "{cylinder}"
    );
}

#[test]
fn subtracted_parts_are_marked() {
    let text = "difference() {\n    cube(10, center = true);\n    sphere(6);\n}\n";
    let hover = geometry_hover(text, "difference", 0);
    let part = geometry_part(&hover);
    assert!(part.contains("**sphere** (subtracted)"), "{part}");
    assert!(!part.contains("slab** (subtracted)"), "{part}");
}

#[test]
fn a_discarded_subtree_is_not_part_of_the_solid() {
    let text = "sphere(1);\n!cube(2);\n";
    let hover = geometry_hover(text, "sphere", 0);
    assert!(
        geometry_part(&hover).contains("not part of the solid"),
        "{hover}"
    );
}

#[test]
fn runtime_diagnostics_and_echo_are_reported() {
    let text = "echo(\"hello\", 1 + 2);\nassert(1 > 2, \"too small\");\n";
    let analysis = analyze(text);
    assert!(analysis.diagnostics().is_empty());
    let geometry = Geometry::evaluate(&analysis, &editor_limits()).expect("evaluates");
    let diagnostics = geometry.diagnostics(&analysis);
    let echo = diagnostics
        .iter()
        .find(|d| d.severity == Severity::Info)
        .expect("echo");
    assert!(echo.message.contains("hello"), "{}", echo.message);
    assert_eq!(echo.range.start, at(text, "echo", 0));
    let failed = diagnostics
        .iter()
        .find(|d| d.severity == Severity::Error)
        .expect("assertion");
    assert_eq!(failed.range.start.line, 1);
    assert!(failed.message.contains("too small"), "{}", failed.message);
}

#[test]
fn the_editors_limits_stop_runaway_programs_with_information() {
    let text = "module r(n) r(n + 1);\nr(0);\n";
    let analysis = analyze(text);
    let geometry = Geometry::evaluate(&analysis, &editor_limits()).expect("evaluates");
    let diagnostics = geometry.diagnostics(&analysis);
    let stopped = diagnostics
        .iter()
        .find(|d| d.message.contains("evaluation stopped in the editor"))
        .unwrap_or_else(|| panic!("{diagnostics:?}"));
    assert_eq!(stopped.severity, Severity::Info);
}

#[test]
fn errors_of_included_files_show_at_the_include_line() {
    let library = "module part() cube(1);\nx = ;\n";
    let text = "// parts\ninclude <lib.scad>\npart();\n";
    let analysis = analyze_with(text, &[("dir/lib.scad", library)]);
    let diagnostics = analysis.diagnostics();
    let shown = diagnostics
        .iter()
        .find(|d| d.severity == Severity::Error)
        .unwrap_or_else(|| panic!("{diagnostics:?}"));
    assert_eq!(shown.range.start, at(text, "<lib.scad>", 0));
    assert!(
        shown.message.starts_with("in included file `lib.scad`"),
        "{}",
        shown.message
    );
    let inside = &shown.related[0];
    assert_eq!(inside.location.file, "dir/lib.scad");
    assert_eq!(inside.location.range.start.line, 1);
    // And in the library's own coordinates, for publishing to it.
    let own = analysis.diagnostics_in("dir/lib.scad");
    assert_eq!(own.len(), 1);
    assert_eq!(own[0].range.start.line, 1);
    assert_eq!(analysis.dependencies(), vec!["dir/lib.scad".to_owned()]);
}

#[test]
fn errors_two_includes_deep_show_at_the_first_one() {
    let text = "use <a.scad>\n";
    let analysis = analyze_with(
        text,
        &[
            ("dir/a.scad", "include <b.scad>\n"),
            ("dir/b.scad", "module m() cube(;\n"),
        ],
    );
    let diagnostics = analysis.diagnostics();
    let shown = diagnostics
        .iter()
        .find(|d| d.severity == Severity::Error)
        .unwrap_or_else(|| panic!("{diagnostics:?}"));
    assert_eq!(shown.range.start, at(text, "<a.scad>", 0));
    assert!(
        shown.message.starts_with("in used file `b.scad`"),
        "{}",
        shown.message
    );
}

#[test]
fn a_runtime_error_in_a_used_file_shows_at_the_use_line() {
    let library = "module check(n) assert(n < 3, \"n too big\");\n";
    let text = "use <lib.scad>\ncheck(5);\n";
    let analysis = analyze_with(text, &[("dir/lib.scad", library)]);
    let geometry = Geometry::evaluate(&analysis, &editor_limits()).expect("evaluates");
    let diagnostics = geometry.diagnostics(&analysis);
    let shown = diagnostics
        .iter()
        .find(|d| d.severity == Severity::Error)
        .unwrap_or_else(|| panic!("{diagnostics:?}"));
    assert_eq!(shown.range.start, at(text, "<lib.scad>", 0));
    assert!(shown.message.contains("n too big"), "{}", shown.message);
    assert_eq!(geometry.diagnostics_in(&analysis, "dir/lib.scad").len(), 1);
}

#[test]
fn hover_on_a_scene_snapshot() {
    let text = "module wheel(r) rotate([90, 0, 0]) cylinder(h = 2, r = r, center = true);\n\
                for (x = [-10, 10]) translate([x, 0, 0]) wheel(4);\n\
                scale([2, 1, 1]) sphere(3);\n";
    let wheel = geometry_hover(text, "wheel", 1);
    let scaled = geometry_hover(text, "scale", 0);
    insta::assert_snapshot!(format!(
        "{}\n\n=====\n\n{}",
        geometry_part(&wheel),
        geometry_part(&scaled)
    ));
}

/// What only the DNF finds (here an unbounded solid) reaches the editor as `qcsg check` reports
/// it, at the unbounded part.
#[test]
fn the_dnf_stage_reports_an_unbounded_solid() {
    let text = "union() { sphere(3); halfspace([0, 0, 1], 0); }\n";
    let analysis = analyze(text);
    let geometry = Geometry::evaluate(&analysis, &editor_limits()).expect("evaluates");
    let diagnostics = geometry.diagnostics(&analysis);
    let unbounded = diagnostics
        .iter()
        .find(|d| d.code == "E0600")
        .unwrap_or_else(|| panic!("{diagnostics:?}"));
    assert_eq!(unbounded.severity, Severity::Error);
    assert_eq!(unbounded.range.start, at(text, "halfspace", 0));
}
