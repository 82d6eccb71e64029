//! `polygon(points, paths)`: the even–odd region as a union of convex cells of z-invariant
//! half-spaces, its warnings and errors, and its cost on large outlines.

mod common;

use common::{eval, eval_with, membership, p};
use qcsg_csg::{DnfOptions, build_dnf};
use qcsg_eval::EvalOptions;

/// The first error of `text`, with the source text it points at.
fn first_error(text: &str, options: &EvalOptions) -> (&'static str, String, String) {
    let e = eval_with(text, options);
    let d = e
        .diagnostics
        .iter()
        .find(|d| d.is_error())
        .unwrap_or_else(|| panic!("{text}: no error in {:?}", e.diagnostics));
    (
        d.code,
        text[d.span.start as usize..d.span.end as usize].to_owned(),
        d.message.clone(),
    )
}

#[test]
fn a_non_convex_outline_with_a_hole() {
    // An L with a square hole in its foot, the hole given as a second path.
    let found = membership(
        "linear_extrude(2) polygon([[0, 0], [10, 0], [10, 4], [4, 4], [4, 10], [0, 10],
                                    [6, 1], [8, 1], [8, 3], [6, 3]],
                                   [[0, 1, 2, 3, 4, 5], [6, 7, 8, 9]]);",
        &[
            (p(2.0, 8.0, 1.0), true),
            (p(9.0, 2.0, 1.0), true),
            (p(5.0, 2.0, 1.0), true),
            (p(7.0, 2.0, 1.0), false), // the hole
            (p(7.0, 7.0, 1.0), false), // the reflex corner's outside
            (p(2.0, 8.0, 2.5), false),
            (p(-0.5, 5.0, 1.0), false),
        ],
    );
    assert!(found.is_empty(), "{found:?}");
}

#[test]
fn a_self_crossing_outline_is_filled_even_odd_with_a_warning() {
    // The bow-tie: two triangles meeting at (1, 1).
    let found = membership(
        "linear_extrude(1) polygon([[0, 0], [2, 2], [2, 0], [0, 2]]);",
        &[
            (p(0.3, 1.0, 0.5), true),
            (p(1.7, 1.0, 0.5), true),
            (p(1.0, 0.3, 0.5), false),
            (p(1.0, 1.7, 0.5), false),
        ],
    );
    assert_eq!(found, ["W0561"]);
}

#[test]
fn bad_points_and_paths_are_errors_at_the_call() {
    let options = EvalOptions::default();
    let text = "linear_extrude(1) polygon([[0, 0], [1, 0], [0, 1]], [[0, 1, 3]]);";
    let (code, at, message) = first_error(text, &options);
    assert_eq!(code, "E0552");
    assert_eq!(at, "polygon([[0, 0], [1, 0], [0, 1]], [[0, 1, 3]]);");
    assert!(message.contains("refers to point 3"), "{message}");
    let text = "linear_extrude(1) polygon([[0, 0], [1 / 0, 0], [0, 1]]);";
    let (code, _, message) = first_error(text, &options);
    assert_eq!(code, "E0552");
    assert!(message.contains("point 1"), "{message}");
    let text = "linear_extrude(1) polygon([[0, 0], [1, 0], \"x\"]);";
    let (code, _, message) = first_error(text, &options);
    assert_eq!(code, "E0552");
    assert!(message.contains("point 2"), "{message}");
    // Path entries count against the vector-length limit, all paths together.
    let options = EvalOptions {
        max_vector_len: 100,
        ..EvalOptions::default()
    };
    let text = "n = 60; linear_extrude(1) polygon([for (i = [0 : n - 1]) [cos(6 * i), sin(6 * i)]],
                                                [[for (i = [0 : n - 1]) i], [for (i = [0 : n - 1]) i]]);";
    let (code, _, message) = first_error(text, &options);
    assert_eq!(code, "E0558");
    assert!(message.contains("120"), "{message}");
}

#[test]
fn an_empty_polygon_is_empty() {
    let e = eval("linear_extrude(1) polygon([]); cube(1);");
    assert!(!e.has_errors(), "{:?}", e.diagnostics);
    assert!(e.dag.contains(p(0.5, 0.5, 0.5)));
}

/// A 5,000-point star compiles to about one short DNF term per point: the cells have a handful of
/// half-planes each, so the work stays linear in the outline (an expansion of the even–odd rule
/// as a boolean formula over the edges would have thousands of literals per term).
#[test]
fn a_large_outline_gives_few_short_terms() {
    let n = 5000;
    let text = format!(
        "n = {n}; linear_extrude(1) polygon([for (i = [0 : n - 1]) (i % 2 == 0 ? 10 : 9) * [cos(360 * i / n), sin(360 * i / n)]]);"
    );
    let start = std::time::Instant::now();
    let e = eval(&text);
    assert!(!e.has_errors(), "{:?}", e.diagnostics);
    let dnf = build_dnf(&e.dag, &DnfOptions::default()).expect("a bounded solid");
    let elapsed = start.elapsed();
    assert!(
        dnf.terms.len() <= 4 * n,
        "{} terms for {n} points",
        dnf.terms.len()
    );
    let longest = dnf
        .terms
        .iter()
        .map(|t| t.literals.len())
        .max()
        .unwrap_or(0);
    assert!(longest <= 12, "a term of {longest} literals");
    assert!(dnf.contains(p(0.0, 0.0, 0.5)));
    assert!(!dnf.contains(p(10.5, 0.0, 0.5)));
    assert!(elapsed.as_secs() < 20, "{elapsed:?}");
}
