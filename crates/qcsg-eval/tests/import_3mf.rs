//! `import(file)` of 3MF packages with OpenSCAD 2021.01's meaning: every mesh object, united,
//! build items and their transforms ignored; the model part found through the package
//! relationships; and every bad package a diagnostic at the `file` argument.

use std::io::{Cursor, Write};
use std::path::PathBuf;

use glam::DVec3;
use qcsg_csg::{DnfOptions, build_dnf};
use qcsg_eval::EvalOptions;

mod common;

use common::{eval_in, first_error};

fn scratch(name: &str) -> PathBuf {
    common::scratch("import-3mf-tests", name)
}

const RELS: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">
<Relationship Target="/3D/3dmodel.model" Id="rel0" Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"/>
</Relationships>"#;

/// A zip package of the given parts.
fn package(parts: &[(&str, &str)]) -> Vec<u8> {
    let mut zip = zip::ZipWriter::new(Cursor::new(Vec::new()));
    let options = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated);
    for (name, text) in parts {
        zip.start_file(*name, options).unwrap();
        zip.write_all(text.as_bytes()).unwrap();
    }
    zip.finish().unwrap().into_inner()
}

/// A mesh object: vertices and triangles (counter-clockwise seen from outside, 3MF's order).
fn object(id: u32, vertices: &[[f64; 3]], triangles: &[[usize; 3]]) -> String {
    let mut s = format!("<object id=\"{id}\" type=\"model\"><mesh><vertices>");
    for v in vertices {
        s.push_str(&format!(
            "<vertex x=\"{}\" y=\"{}\" z=\"{}\"/>",
            v[0], v[1], v[2]
        ));
    }
    s.push_str("</vertices><triangles>");
    for t in triangles {
        s.push_str(&format!(
            "<triangle v1=\"{}\" v2=\"{}\" v3=\"{}\"/>",
            t[0], t[1], t[2]
        ));
    }
    s.push_str("</triangles></mesh></object>");
    s
}

fn model(objects: &str, build: &str) -> String {
    format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<model unit=\"millimeter\" \
         xmlns=\"http://schemas.microsoft.com/3dmanufacturing/core/2015/02\">\n\
         <resources>{objects}</resources>\n<build>{build}</build>\n</model>\n"
    )
}

/// The unit tetrahedron, moved by `d`.
fn tetra(id: u32, d: f64) -> String {
    object(
        id,
        &[[d, d, d], [1.0 + d, d, d], [d, 1.0 + d, d], [d, d, 1.0 + d]],
        &[[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
    )
}

#[test]
fn every_mesh_object_is_united_and_build_transforms_are_ignored() {
    let dir = scratch("objects");
    // Two tetrahedra overlapping, the second moved by 0.2 in its own coordinates; the build
    // items move them far away, which OpenSCAD 2021.01 ignores.
    let text = model(
        &(tetra(1, 0.0) + &tetra(2, 0.2)),
        "<item objectid=\"1\" transform=\"1 0 0 0 1 0 0 0 1 100 0 0\"/><item objectid=\"2\"/>",
    );
    std::fs::write(
        dir.join("two.3mf"),
        package(&[("_rels/.rels", RELS), ("3D/3dmodel.model", &text)]),
    )
    .unwrap();
    let e = eval_in(&dir, "import(\"two.3mf\");", &EvalOptions::default());
    assert!(!e.has_errors(), "{:?}", e.diagnostics);
    let dnf = build_dnf(&e.dag, &DnfOptions::default()).expect("a bounded solid");
    for (p, inside) in [
        (DVec3::splat(0.1), true),  // the first only
        (DVec3::splat(0.5), true),  // the second only
        (DVec3::splat(0.25), true), // both
        (DVec3::splat(0.6), false), // beyond the second's slanted face
        (DVec3::new(0.85, 0.05, 0.05), true),
        (DVec3::new(100.1, 0.1, 0.1), false),
    ] {
        assert_eq!(e.dag.contains(p), inside, "DAG at {p}");
        assert_eq!(dnf.contains(p), inside, "DNF at {p}");
    }
}

#[test]
fn the_model_part_is_found_through_the_relationships() {
    let dir = scratch("relationships");
    let rels = RELS.replace("/3D/3dmodel.model", "/parts/other.model");
    let text = model(&tetra(7, 0.0), "<item objectid=\"7\"/>");
    // The default name holds something else, which must not be read.
    std::fs::write(
        dir.join("named.3mf"),
        package(&[
            ("_rels/.rels", &rels),
            ("3D/3dmodel.model", "not xml"),
            ("parts/other.model", &text),
        ]),
    )
    .unwrap();
    // Without relationships, the default name.
    std::fs::write(
        dir.join("plain.3mf"),
        package(&[("3D/3dmodel.model", &text)]),
    )
    .unwrap();
    for file in ["named.3mf", "plain.3mf"] {
        let e = eval_in(
            &dir,
            &format!("import(\"{file}\");"),
            &EvalOptions::default(),
        );
        assert!(!e.has_errors(), "{file}: {:?}", e.diagnostics);
        assert!(e.dag.contains(DVec3::splat(0.2)), "{file}");
        assert!(!e.dag.contains(DVec3::splat(0.4)), "{file}");
    }
}

#[test]
fn bad_packages_are_errors_at_the_file_argument() {
    let dir = scratch("bad");
    let good = model(&tetra(1, 0.0), "");
    let cases: Vec<(&str, Vec<u8>, &str, &str)> = vec![
        (
            "notzip",
            b"solid x\n".to_vec(),
            "E0567",
            "not a zip archive",
        ),
        (
            "nomodel",
            package(&[("_rels/.rels", RELS)]),
            "E0567",
            "no model part `3D/3dmodel.model`",
        ),
        (
            "badxml",
            package(&[("3D/3dmodel.model", "<model>\n<resources>\n</model>")]),
            "E0567",
            "line 3",
        ),
        (
            "dtd",
            package(&[(
                "3D/3dmodel.model",
                "<?xml version=\"1.0\"?><!DOCTYPE model [<!ENTITY a \"aaaa\">]><model>&a;</model>",
            )]),
            "E0567",
            "not well-formed XML",
        ),
        (
            "index",
            package(&[(
                "3D/3dmodel.model",
                &model(&object(1, &[[0.0; 3]; 3], &[[0, 1, 3]]), ""),
            )]),
            "E0567",
            "v3=\"3\" is past the object's 3 vertices",
        ),
        (
            "number",
            package(&[("3D/3dmodel.model", &good.replace("x=\"1\"", "x=\"1e999\""))]),
            "E0567",
            "x=\"1e999\" is not a finite number",
        ),
        (
            "empty",
            package(&[("3D/3dmodel.model", &model("", ""))]),
            "E0567",
            "no mesh object",
        ),
        (
            "open",
            package(&[(
                "3D/3dmodel.model",
                &model(
                    &object(
                        1,
                        &[
                            [0.0, 0.0, 0.0],
                            [1.0, 0.0, 0.0],
                            [0.0, 1.0, 0.0],
                            [0.0, 0.0, 1.0],
                        ],
                        &[[0, 2, 1], [0, 1, 3], [0, 3, 2]],
                    ),
                    "",
                ),
            )]),
            "E0565",
            "open mesh",
        ),
    ];
    for (name, bytes, code, fragment) in cases {
        std::fs::write(dir.join(format!("{name}.3mf")), bytes).unwrap();
        let text = format!("translate([1, 0, 0]) import(\"{name}.3mf\");");
        let (got, at, message) = first_error(&dir, &text, &EvalOptions::default());
        assert_eq!(
            (got, at.as_str()),
            (code, format!("\"{name}.3mf\"").as_str()),
            "{name}: {message}"
        );
        assert!(message.contains(fragment), "{name}: {message}");
    }
}

/// A small package whose model unpacks past the byte limit is refused before it is unpacked.
#[test]
fn a_model_that_unpacks_past_the_byte_limit_is_refused() {
    let dir = scratch("bomb");
    let padded = model(&tetra(1, 0.0), "") + &" ".repeat(200_000);
    let bytes = package(&[("3D/3dmodel.model", &padded)]);
    assert!(bytes.len() < 5_000, "{} bytes", bytes.len());
    std::fs::write(dir.join("bomb.3mf"), bytes).unwrap();
    let options = EvalOptions {
        max_import_bytes: 10_000,
        ..EvalOptions::default()
    };
    let (code, at, message) = first_error(&dir, "import(\"bomb.3mf\");", &options);
    assert_eq!((code, at.as_str()), ("E0568", "\"bomb.3mf\""), "{message}");
    assert!(message.contains("unpacks to"), "{message}");
    // Within the default limit it reads.
    let e = eval_in(&dir, "import(\"bomb.3mf\");", &EvalOptions::default());
    assert!(!e.has_errors(), "{:?}", e.diagnostics);
}
