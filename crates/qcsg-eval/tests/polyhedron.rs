//! `polyhedron(points, faces)`: the solid a closed mesh bounds as a union of convex cells of
//! half-spaces, its warnings, and every error at the argument it is about.

mod common;

use common::{codes, eval, eval_with, membership, p};
use glam::DVec3;
use qcsg_eval::EvalOptions;

/// The first error of `text`: its code, the source text it points at and its message.
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

/// A box `[0, 2] × [0, 3] × [0, 4]` as OpenSCAD's manual writes a cube: faces clockwise seen
/// from outside, scaled by `s` and moved by `o`.
fn cube_text(s: f64, o: [f64; 3], faces: &str) -> String {
    let corners = [
        [0, 0, 0],
        [2, 0, 0],
        [2, 3, 0],
        [0, 3, 0],
        [0, 0, 4],
        [2, 0, 4],
        [2, 3, 4],
        [0, 3, 4],
    ];
    let points: Vec<String> = corners
        .iter()
        .map(|c| {
            format!(
                "[{:?}, {:?}, {:?}]",
                f64::from(c[0]) * s + o[0],
                f64::from(c[1]) * s + o[1],
                f64::from(c[2]) * s + o[2]
            )
        })
        .collect();
    format!("polyhedron(points = [{}], {faces});", points.join(", "))
}

const CUBE_FACES: &str =
    "faces = [[0, 1, 2, 3], [4, 5, 1, 0], [7, 6, 5, 4], [5, 6, 2, 1], [6, 7, 3, 2], [7, 4, 0, 3]]";

fn box_cases(s: f64, o: [f64; 3]) -> Vec<(DVec3, bool)> {
    let at = |x: f64, y: f64, z: f64| p(x * s + o[0], y * s + o[1], z * s + o[2]);
    vec![
        (at(1.0, 1.5, 2.0), true),
        (at(0.01, 0.01, 0.01), true),
        (at(1.99, 2.99, 3.99), true),
        (at(2.01, 1.5, 2.0), false),
        (at(1.0, -0.01, 2.0), false),
        (at(1.0, 1.5, 4.01), false),
    ]
}

#[test]
fn a_box_in_openscad_order() {
    let found = membership(
        &cube_text(1.0, [0.0; 3], CUBE_FACES),
        &box_cases(1.0, [0.0; 3]),
    );
    assert!(found.is_empty(), "{found:?}");
}

#[test]
fn far_and_tiny_boxes_are_exact() {
    for (s, o) in [
        (1.0, [1e6, -1e6, 1e6]),
        (1e-3, [0.0; 3]),
        (1e-6, [5.0, 5.0, 5.0]),
        (1e6, [0.0; 3]),
    ] {
        let found = membership(&cube_text(s, o, CUBE_FACES), &box_cases(s, o));
        assert!(found.is_empty(), "{s} {o:?}: {found:?}");
    }
}

#[test]
fn a_non_convex_solid() {
    // An L-shaped prism: the L of (0,0)-(4,0)-(4,1)-(1,1)-(1,4)-(0,4), z in [0, 1].
    let text = "pts = [[0,0],[4,0],[4,1],[1,1],[1,4],[0,4]];
        polyhedron(points = concat([for (q = pts) [q[0], q[1], 0]], [for (q = pts) [q[0], q[1], 1]]),
                   faces = [[0, 1, 2, 3, 4, 5], [11, 10, 9, 8, 7, 6],
                            for (i = [0 : 5]) [i, i + 6, (i + 1) % 6 + 6, (i + 1) % 6]]);";
    let found = membership(
        text,
        &[
            (p(3.0, 0.5, 0.5), true),
            (p(0.5, 3.0, 0.5), true),
            (p(2.0, 2.0, 0.5), false),
            (p(3.0, 0.5, 1.5), false),
        ],
    );
    assert!(found.is_empty(), "{found:?}");
}

#[test]
fn the_deprecated_triangles_argument_is_read_with_a_warning() {
    let text = "polyhedron(points = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]],
                          triangles = [[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]]);";
    let found = membership(text, &[(p(0.1, 0.1, 0.1), true), (p(0.5, 0.5, 0.5), false)]);
    assert_eq!(found, ["W0563"]);
}

#[test]
fn an_inside_out_mesh_gives_its_solid_with_a_warning() {
    let text = "polyhedron(points = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]],
                          faces = [[2, 1, 0], [1, 3, 0], [3, 2, 0], [2, 3, 1]]);";
    let found = membership(text, &[(p(0.1, 0.1, 0.1), true), (p(0.5, 0.5, 0.5), false)]);
    assert_eq!(found, ["W0562"]);
}

#[test]
fn errors_point_at_the_argument() {
    let options = EvalOptions::default();
    let tet = "[[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]";
    let cases = [
        // An index naming no point.
        (
            format!("polyhedron({tet}, [[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 7]]);"),
            "E0565",
            "[[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 7]]",
            "point 7",
        ),
        // An open mesh: a face left out.
        (
            format!("polyhedron(points = {tet}, faces = [[0, 1, 2], [0, 3, 1], [0, 2, 3]]);"),
            "E0565",
            "[[0, 1, 2], [0, 3, 1], [0, 2, 3]]",
            "open mesh",
        ),
        // Two faces along an edge in the same direction.
        (
            format!("polyhedron({tet}, [[0, 1, 2], [0, 3, 1], [0, 2, 3], [2, 3, 1]]);"),
            "E0565",
            "[[0, 1, 2], [0, 3, 1], [0, 2, 3], [2, 3, 1]]",
            "oriented inconsistently",
        ),
        // A face of two points.
        (
            format!("polyhedron({tet}, [[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2], [1, 1, 2]]);"),
            "E0565",
            "[[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2], [1, 1, 2]]",
            "",
        ),
        // A point that is not 3 numbers.
        (
            "polyhedron(points = [[0, 0, 0], [1, 0], [0, 1, 0], [0, 0, 1]], faces = []);"
                .to_owned(),
            "E0552",
            "[[0, 0, 0], [1, 0], [0, 1, 0], [0, 0, 1]]",
            "point 1",
        ),
        // A coordinate that is not finite.
        (
            "polyhedron([[0, 0, 0], [1 / 0, 0, 0], [0, 1, 0], [0, 0, 1]], [[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]]);"
                .to_owned(),
            "E0565",
            "[[0, 0, 0], [1 / 0, 0, 0], [0, 1, 0], [0, 0, 1]]",
            "point 1",
        ),
        // A face entry that is not an index.
        (
            format!("polyhedron({tet}, faces = [[0, 1, 2], [0, 3, -1]]);"),
            "E0552",
            "[[0, 1, 2], [0, 3, -1]]",
            "entry 2 of face 1",
        ),
        // The deprecated spelling's errors point at it.
        (
            format!("polyhedron({tet}, triangles = [[0, 1, 2]]);"),
            "E0565",
            "[[0, 1, 2]]",
            "open mesh",
        ),
    ];
    for (text, code, at, fragment) in cases {
        let (got_code, got_at, message) = first_error(&text, &options);
        assert_eq!((got_code, got_at.as_str()), (code, at), "{text}: {message}");
        assert!(message.contains(fragment), "{text}: {message}");
    }
}

#[test]
fn the_vector_length_limit_bounds_points_and_face_entries() {
    let options = EvalOptions {
        max_vector_len: 10,
        ..EvalOptions::default()
    };
    let text = cube_text(1.0, [0.0; 3], CUBE_FACES);
    let (code, at, message) = first_error(&text, &options);
    assert_eq!(code, "E0558", "{message}");
    assert!(at.starts_with("[[0, 1, 2, 3]"), "{at}");
    let e = eval_with(&text, &options);
    let help = e.diagnostics[0].help.clone().unwrap_or_default();
    assert!(help.contains("--max-vector-len"), "{help}");
}

#[test]
fn an_empty_polyhedron_is_empty() {
    let e = eval("polyhedron([], []); cube(1);");
    assert!(!e.has_errors(), "{:?}", e.diagnostics);
    assert!(e.dag.contains(p(0.5, 0.5, 0.5)));
}

/// The conformance scene lists its faces as OpenSCAD asks (clockwise seen from outside), so the
/// only warning is the deprecated `triangles`.
#[test]
fn the_conformance_scene_is_oriented_as_openscad_asks() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/openscad/polyhedron_csg.scad"
    );
    let text = std::fs::read_to_string(path).expect("the scene");
    let e = eval(&text);
    assert_eq!(codes(&e), ["W0563"], "{:?}", e.diagnostics);
}
