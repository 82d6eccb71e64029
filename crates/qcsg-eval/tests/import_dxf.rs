//! `import` of DXF drawings: the even–odd region of a layer as an exact 2-D shape (lines, arcs,
//! circles, ellipses, bulged polylines), `origin` and `scale`, OpenSCAD's bundled example drawings, and every failure a
//! diagnostic at the `file` argument.

use std::path::{Path, PathBuf};

use glam::DVec3;
use qcsg_csg::{DnfOptions, build_dnf};
use qcsg_eval::{EvalOptions, Evaluation};
use qcsg_testkit::dxf::{arc, circle, dxf, ellipse, line};

mod common;

use common::{eval_in, first_diagnostic, p};

/// A fresh directory for one test.
fn scratch(name: &str) -> PathBuf {
    common::scratch("import-dxf-tests", name)
}

/// A plate: a 20 × 10 rectangle with its right end rounded (a half circle about (20, 5)), a hole
/// of radius 2 at (5, 5) and, on layer `b`, a square elsewhere.
fn plate() -> String {
    dxf(&[
        line([0.0, 0.0], [20.0, 0.0]).on("a"),
        arc([20.0, 5.0], 5.0, 270.0, 90.0).on("a"),
        line([20.0, 10.0], [0.0, 10.0]).on("a"),
        line([0.0, 10.0], [0.0, 0.0]).on("a"),
        circle([5.0, 5.0], 2.0).on("a"),
        line([40.0, 0.0], [41.0, 0.0]).on("b"),
        line([41.0, 0.0], [41.0, 1.0]).on("b"),
        line([41.0, 1.0], [40.0, 1.0]).on("b"),
        line([40.0, 1.0], [40.0, 0.0]).on("b"),
    ])
}

fn check(e: &Evaluation, cases: &[(DVec3, bool)]) {
    assert!(!e.has_errors(), "{:?}", e.diagnostics);
    let dnf = build_dnf(&e.dag, &DnfOptions::default()).expect("a bounded solid");
    for &(p, inside) in cases {
        assert_eq!(e.dag.contains(p), inside, "DAG at {p}");
        assert_eq!(dnf.contains(p), inside, "DNF at {p}");
    }
}

#[test]
fn a_layer_with_an_arc_and_a_hole_is_exact() {
    let dir = scratch("plate");
    std::fs::write(dir.join("plate.dxf"), plate()).unwrap();
    let e = eval_in(
        &dir,
        "linear_extrude(height = 2) import(file = \"plate.dxf\", layer = \"a\");",
        &EvalOptions::default(),
    );
    assert!(e.diagnostics.is_empty(), "{:?}", e.diagnostics);
    check(
        &e,
        &[
            (p(1.0, 1.0, 1.0), true),
            (p(5.0, 5.0, 1.0), false),
            (p(6.9, 5.0, 1.0), false),
            (p(7.1, 5.0, 1.0), true),
            // On the arc's bulge, just inside and just outside radius 5.
            (p(24.99, 5.0, 1.0), true),
            (p(25.01, 5.0, 1.0), false),
            (p(23.5, 8.5, 1.0), true),
            (p(23.6, 8.6, 1.0), false),
            (p(40.5, 0.5, 1.0), false),
            (p(1.0, 1.0, 2.5), false),
        ],
    );
    assert_eq!(e.imports.len(), 1);
}

#[test]
fn all_layers_origin_and_scale() {
    let dir = scratch("options");
    std::fs::write(dir.join("plate.dxf"), plate()).unwrap();
    let e = eval_in(
        &dir,
        "linear_extrude(1) import(\"plate.dxf\", origin = [40, 0], scale = 2);",
        &EvalOptions::default(),
    );
    check(
        &e,
        &[
            // The square of layer b, moved to the origin and doubled.
            (p(1.9, 1.9, 0.5), true),
            (p(2.1, 1.0, 0.5), false),
            // The plate, at (0 − 40) · 2.
            (p(-79.0, 1.0, 0.5), true),
            (p(-70.0, 10.0, 0.5), false),
        ],
    );
}

#[test]
fn openscad_examples_import() {
    let examples = Path::new("/usr/share/openscad/examples/Old");
    if !examples.exists() {
        eprintln!("OpenSCAD's examples are not installed; skipped");
        return;
    }
    let dir = scratch("examples");
    for name in ["example007", "example008", "example009", "example013"] {
        std::fs::copy(
            examples.join(format!("{name}.dxf")),
            dir.join(format!("{name}.dxf")),
        )
        .unwrap();
    }
    for (call, inside, outside) in [
        (
            "import(\"example013.dxf\");",
            p(0.0, 0.0, 0.0),
            p(100.0, 0.0, 0.0),
        ),
        (
            "import(\"example008.dxf\", layer = \"B\");",
            p(105.0, 125.0, 0.0),
            p(120.0, 115.0, 0.0),
        ),
        (
            "import(\"example009.dxf\", layer = \"body\");",
            p(19.0, 0.0, 0.0),
            p(0.0, 0.0, 0.0),
        ),
        (
            "import(\"example009.dxf\", layer = \"plate\");",
            p(0.0, 10.0, 0.0),
            p(10.0, 10.0, 0.0),
        ),
        (
            "import(\"example009.dxf\", layer = \"fan_top\");",
            p(0.0, 10.0, 0.0),
            p(10.0, 10.0, 0.0),
        ),
    ] {
        let text = format!("linear_extrude(height = 1, center = true) {call}");
        let e = eval_in(&dir, &text, &EvalOptions::default());
        assert!(!e.has_errors(), "{call}: {:?}", e.diagnostics);
        check(&e, &[(inside, true), (outside, false)]);
    }
}

#[test]
fn failures_are_diagnostics_at_the_file_argument() {
    let dir = scratch("failures");
    let options = EvalOptions::default();
    // Two circles that cross: no exact composition, E0301 naming both DXF lines.
    std::fs::write(
        dir.join("cross.dxf"),
        dxf(&[circle([0.0, 0.0], 1.0), circle([1.5, 0.0], 1.0)]),
    )
    .unwrap();
    let (code, at, message) =
        first_diagnostic(&dir, "import(file = \"cross.dxf\");", &options, true);
    assert_eq!((code, at.as_str()), ("E0301", "\"cross.dxf\""), "{message}");
    assert!(
        message.contains("DXF line 5") && message.contains("DXF line 15"),
        "{message}"
    );
    // A malformed file: E0567 with the line.
    std::fs::write(
        dir.join("bad.dxf"),
        "  0\nSECTION\n  2\nENTITIES\n  0\nLINE\n 10\nx\n",
    )
    .unwrap();
    let (code, at, message) = first_diagnostic(&dir, "import(\"bad.dxf\");", &options, true);
    assert_eq!((code, at.as_str()), ("E0567", "\"bad.dxf\""), "{message}");
    assert!(message.contains("line 8"), "{message}");
    // A missing file: E0566.
    let (code, _, _) = first_diagnostic(&dir, "import(\"none.dxf\");", &options, true);
    assert_eq!(code, "E0566");
    // The vector-length limit bounds entities: E0558.
    std::fs::write(dir.join("plate.dxf"), plate()).unwrap();
    let few = EvalOptions {
        max_vector_len: 3,
        ..EvalOptions::default()
    };
    let (code, at, message) = first_diagnostic(&dir, "import(\"plate.dxf\");", &few, true);
    assert_eq!((code, at.as_str()), ("E0558", "\"plate.dxf\""), "{message}");
    // An open path is closed, with warning W0564.
    std::fs::write(
        dir.join("open.dxf"),
        dxf(&[line([0.0, 0.0], [1.0, 0.0]), line([1.0, 0.0], [1.0, 1.0])]),
    )
    .unwrap();
    let (code, at, _) = first_diagnostic(&dir, "import(\"open.dxf\");", &options, false);
    assert_eq!((code, at.as_str()), ("W0564", "\"open.dxf\""));
}

#[test]
fn a_far_drawing_and_a_tiny_one() {
    let dir = scratch("stiff");
    let far = dxf(&[
        line([1e6, 1e6], [1e6 + 2.0, 1e6]),
        arc([1e6 + 2.0, 1e6 + 1.0], 1.0, 270.0, 90.0),
        line([1e6 + 2.0, 1e6 + 2.0], [1e6, 1e6 + 2.0]),
        line([1e6, 1e6 + 2.0], [1e6, 1e6]),
        circle([1e6 + 1.0, 1e6 + 1.0], 0.5),
    ]);
    std::fs::write(dir.join("far.dxf"), far).unwrap();
    let e = eval_in(
        &dir,
        "linear_extrude(1) import(\"far.dxf\");",
        &EvalOptions::default(),
    );
    let o = p(1e6, 1e6, 0.5);
    check(
        &e,
        &[
            (o + p(0.2, 0.2, 0.0), true),
            (o + p(1.0, 1.0, 0.0), false),
            (o + p(2.9, 1.0, 0.0), true),
            (o + p(3.1, 1.0, 0.0), false),
        ],
    );
    let tiny = dxf(&[
        line([0.0, 0.0], [2e-6, 0.0]),
        arc([2e-6, 1e-6], 1e-6, 270.0, 90.0),
        line([2e-6, 2e-6], [0.0, 2e-6]),
        line([0.0, 2e-6], [0.0, 0.0]),
        circle([1e-6, 1e-6], 0.5e-6),
    ]);
    std::fs::write(dir.join("tiny.dxf"), tiny).unwrap();
    let e = eval_in(
        &dir,
        "linear_extrude(1) import(\"tiny.dxf\");",
        &EvalOptions::default(),
    );
    check(
        &e,
        &[
            (p(0.2e-6, 0.2e-6, 0.5), true),
            (p(1e-6, 1e-6, 0.5), false),
            (p(2.9e-6, 1e-6, 0.5), true),
            (p(3.1e-6, 1e-6, 0.5), false),
        ],
    );
}

#[test]
fn dxf_dim_and_dxf_cross_read_example009() {
    let examples = Path::new("/usr/share/openscad/examples/Old");
    if !examples.exists() {
        eprintln!("OpenSCAD's examples are not installed; skipped");
        return;
    }
    let dir = scratch("functions");
    std::fs::copy(examples.join("example009.dxf"), dir.join("example009.dxf")).unwrap();
    let text = "f = \"example009.dxf\";\n\
                echo(dxf_dim(file = f, name = \"bodywidth\"), dxf_dim(file = f, name = \"fanrot\"), \
                dxf_cross(file = f, layer = \"fan_side_center\"), \
                dxf_cross(file = f, layer = \"fan_side_center\", origin = [0, -40], scale = 2), \
                dxf_dim(file = f, name = \"none\"));";
    let e = eval_in(&dir, text, &EvalOptions::default());
    assert!(!e.has_errors(), "{:?}", e.diagnostics);
    let echo: Vec<_> = e
        .diagnostics
        .iter()
        .filter(|d| d.code == "I0550")
        .map(|d| d.message.clone())
        .collect();
    // As OpenSCAD 2021.01 echoes it.
    assert_eq!(echo, ["ECHO: 22, 57.5288, [0, -40], [0, 0], undef"]);
    assert!(e.diagnostics.iter().any(|d| d.code == "W0565"));
    let (code, _, _) = first_diagnostic(
        &dir,
        "echo(dxf_dim(file = \"none.dxf\"));",
        &EvalOptions::default(),
        true,
    );
    assert_eq!(code, "E0566");
}

#[test]
fn ellipses_and_bulges_are_exact() {
    use std::f64::consts::{PI, TAU};
    let dir = scratch("ellipses-bulges");
    // A full ellipse rotated by 30° (semi-axes 10 and 5) and the upper half of another, closed
    // by its chord.
    let (s, c) = 30f64.to_radians().sin_cos();
    std::fs::write(
        dir.join("ellipses.dxf"),
        dxf(&[
            ellipse([0.0, 0.0], [10.0 * c, 10.0 * s], 0.5, 0.0, TAU),
            ellipse([30.0, 0.0], [8.0, 0.0], 0.5, 0.0, PI),
        ]),
    )
    .unwrap();
    let e = eval_in(
        &dir,
        "linear_extrude(1) import(\"ellipses.dxf\");",
        &EvalOptions::default(),
    );
    // Points a thousandth inside and outside the ellipses' boundaries.
    let on = |t: f64, k: f64| {
        let (st, ct) = t.sin_cos();
        let (x, y) = (10.0 * ct * k, 5.0 * st * k);
        p(x * c - y * s, x * s + y * c, 0.5)
    };
    let mut cases = Vec::new();
    for t in [0.0, 1.0, 2.5, 4.0] {
        cases.push((on(t, 0.999), true));
        cases.push((on(t, 1.001), false));
    }
    cases.extend([
        (p(30.0, 3.99, 0.5), true),
        (p(30.0, 4.01, 0.5), false),
        (p(30.0, -0.01, 0.5), false),
        (p(37.99, 0.01, 0.5), true),
    ]);
    check(&e, &cases);
    // A closed LWPOLYLINE: a half circle out of the bottom edge of a 10 × 10 square (bulge 1),
    // with warning W0564 that OpenSCAD 2021.01 draws the chord.
    let mut text =
        String::from("  0\nSECTION\n  2\nENTITIES\n  0\nLWPOLYLINE\n  8\n0\n 90\n4\n 70\n1\n");
    for (x, y, bulge) in [(0, 0, "1"), (10, 0, "0"), (10, 10, "0"), (0, 10, "0")] {
        text.push_str(&format!(" 10\n{x}\n 20\n{y}\n 42\n{bulge}\n"));
    }
    text.push_str("  0\nENDSEC\n  0\nEOF\n");
    std::fs::write(dir.join("bulge.dxf"), text).unwrap();
    let source = "linear_extrude(1) import(\"bulge.dxf\");";
    let e = eval_in(&dir, source, &EvalOptions::default());
    check(
        &e,
        &[
            (p(5.0, -4.99, 0.5), true),
            (p(5.0, -5.01, 0.5), false),
            (p(1.0, -2.0, 0.5), true),
            (p(0.5, -3.0, 0.5), false),
            (p(5.0, 9.99, 0.5), true),
        ],
    );
    let warning = e.diagnostics.iter().find(|d| d.code == "W0564").unwrap();
    assert!(warning.message.contains("bulge"), "{}", warning.message);
    let at = &source[warning.span.start as usize..warning.span.end as usize];
    assert_eq!(at, "\"bulge.dxf\"");
}

#[test]
fn malformed_and_crossing_ellipses_are_diagnostics_at_the_file_argument() {
    use std::f64::consts::TAU;
    let dir = scratch("bad-ellipses");
    let options = EvalOptions::default();
    for (name, entity, needle) in [
        (
            "ratio.dxf",
            ellipse([0.0, 0.0], [1.0, 0.0], 0.0, 0.0, TAU),
            "axis ratio 0",
        ),
        (
            "axis.dxf",
            ellipse([0.0, 0.0], [0.0, 0.0], 0.5, 0.0, TAU),
            "major axis",
        ),
    ] {
        std::fs::write(dir.join(name), dxf(&[entity])).unwrap();
        let text = format!("import(\"{name}\");");
        let e = eval_in(&dir, &text, &options);
        let d = e.diagnostics.iter().find(|d| d.is_error()).unwrap();
        let at = &text[d.span.start as usize..d.span.end as usize];
        assert_eq!((d.code, at), ("E0567", format!("\"{name}\"").as_str()));
        assert!(
            d.message.contains(needle) && d.message.contains("line 5"),
            "{}",
            d.message
        );
    }
    // Two ellipses that cross: no exact composition, E0301 naming both.
    std::fs::write(
        dir.join("cross.dxf"),
        dxf(&[
            ellipse([0.0, 0.0], [10.0, 0.0], 0.3, 0.0, TAU),
            ellipse([0.0, 0.0], [0.0, 10.0], 0.3, 0.0, TAU),
        ]),
    )
    .unwrap();
    let text = "import(\"cross.dxf\");";
    let e = eval_in(&dir, text, &options);
    let d = e.diagnostics.iter().find(|d| d.is_error()).unwrap();
    let at = &text[d.span.start as usize..d.span.end as usize];
    assert_eq!((d.code, at), ("E0301", "\"cross.dxf\""), "{}", d.message);
    assert!(d.message.contains("the ellipse"), "{}", d.message);
}
