//! `import(file)` of STL and OFF meshes (3MF in `import_3mf.rs`): paths relative to the
//! calling file, formats told by the extension in any case, and every failure (missing, a
//! directory, a device, too large, malformed, an open mesh, another format) a diagnostic at the
//! `file` argument.

use std::path::PathBuf;

use glam::DVec3;
use qcsg_csg::{DnfOptions, build_dnf};
use qcsg_eval::{EvalOptions, Evaluation};

mod common;

use common::{eval_in, first_error};

/// A fresh directory for one test.
fn scratch(name: &str) -> PathBuf {
    common::scratch("import-tests", name)
}

/// The unit tetrahedron's triangles, counter-clockwise seen from outside (STL's and OFF's order).
const TETRA: [[[f32; 3]; 3]; 4] = [
    [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]],
    [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]],
    [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]],
    [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
];

fn ascii_stl(triangles: &[[[f32; 3]; 3]]) -> String {
    let mut s = String::from("solid t\n");
    for t in triangles {
        s.push_str("facet normal 0 0 0\nouter loop\n");
        for v in t {
            s.push_str(&format!("vertex {} {} {}\n", v[0], v[1], v[2]));
        }
        s.push_str("endloop\nendfacet\n");
    }
    s.push_str("endsolid t\n");
    s
}

fn binary_stl(triangles: &[[[f32; 3]; 3]]) -> Vec<u8> {
    let mut b = vec![0u8; 80];
    b.extend_from_slice(&(triangles.len() as u32).to_le_bytes());
    for t in triangles {
        b.extend_from_slice(&[0u8; 12]);
        for v in t {
            for c in v {
                b.extend_from_slice(&c.to_le_bytes());
            }
        }
        b.extend_from_slice(&[0u8; 2]);
    }
    b
}

const TETRA_OFF: &str =
    "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";

fn assert_tetra(e: &Evaluation, offset: DVec3) {
    assert!(!e.has_errors(), "{:?}", e.diagnostics);
    let dnf = build_dnf(&e.dag, &DnfOptions::default()).expect("a bounded solid");
    for (p, inside) in [
        (DVec3::new(0.1, 0.1, 0.1), true),
        (DVec3::new(0.3, 0.3, 0.3), true),
        (DVec3::new(0.4, 0.4, 0.4), false),
        (DVec3::new(-0.1, 0.1, 0.1), false),
    ] {
        assert_eq!(e.dag.contains(p + offset), inside, "DAG at {p}");
        assert_eq!(dnf.contains(p + offset), inside, "DNF at {p}");
    }
}

#[test]
fn stl_ascii_binary_and_off_in_any_case() {
    let dir = scratch("formats");
    std::fs::write(dir.join("a.stl"), ascii_stl(&TETRA)).unwrap();
    std::fs::write(dir.join("b.STL"), binary_stl(&TETRA)).unwrap();
    std::fs::write(dir.join("c.Off"), TETRA_OFF).unwrap();
    let options = EvalOptions::default();
    for (call, offset) in [
        ("import(\"a.stl\");", DVec3::ZERO),
        ("translate([5, 0, 0]) import(\"b.STL\");", DVec3::X * 5.0),
        (
            "translate([0, 5, 0]) import(file = \"c.Off\", convexity = 3);",
            DVec3::Y * 5.0,
        ),
    ] {
        let e = eval_in(&dir, call, &options);
        assert!(e.diagnostics.is_empty(), "{call}: {:?}", e.diagnostics);
        assert_tetra(&e, offset);
        assert_eq!(e.imports.len(), 1, "{call}");
        assert!(e.imports[0].starts_with(&dir), "{:?}", e.imports);
    }
}

#[test]
fn paths_are_relative_to_the_calling_file() {
    let dir = scratch("relative");
    std::fs::create_dir_all(dir.join("parts")).unwrap();
    std::fs::write(dir.join("parts/t.stl"), ascii_stl(&TETRA)).unwrap();
    std::fs::write(
        dir.join("parts/lib.scad"),
        "module part() import(\"t.stl\");\n",
    )
    .unwrap();
    // The module is defined in parts/, so its `import` looks there, wherever it is called from.
    let e = eval_in(
        &dir,
        "use <parts/lib.scad>\npart();",
        &EvalOptions::default(),
    );
    assert_tetra(&e, DVec3::ZERO);
    // An absolute path is used as given.
    let absolute = dir.join("parts/t.stl");
    let text = format!("import(\"{}\");", absolute.display());
    assert_tetra(&eval_in(&dir, &text, &EvalOptions::default()), DVec3::ZERO);
}

#[test]
fn unreadable_files_are_errors_at_the_file_argument() {
    let dir = scratch("unreadable");
    std::fs::create_dir_all(dir.join("folder.stl")).unwrap();
    std::fs::write(dir.join("big.stl"), ascii_stl(&TETRA)).unwrap();
    std::fs::write(
        dir.join("bad.stl"),
        "solid x\nfacet normal 0 0 0\nouter loop\nvertex 0 0\n",
    )
    .unwrap();
    std::fs::write(dir.join("bad.off"), "OFF\n4 4 0\n0 0 0\n").unwrap();
    std::fs::write(dir.join("binary.off"), [0xffu8, 0xfe, 0x00]).unwrap();
    std::fs::write(
        dir.join("open.off"),
        "OFF\n4 3 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n",
    )
    .unwrap();
    let small = EvalOptions {
        max_import_bytes: 100,
        ..EvalOptions::default()
    };
    let options = EvalOptions::default();
    let cases: [(&str, &EvalOptions, &str, &str, &str); 7] = [
        (
            "import(\"missing.stl\");",
            &options,
            "E0566",
            "\"missing.stl\"",
            "no such file",
        ),
        (
            "import(\"folder.stl\");",
            &options,
            "E0566",
            "\"folder.stl\"",
            "a directory",
        ),
        (
            "import(\"big.stl\");",
            &small,
            "E0568",
            "\"big.stl\"",
            "--max-import-bytes",
        ),
        (
            "import(\"bad.stl\");",
            &options,
            "E0567",
            "\"bad.stl\"",
            "STL file, line 4",
        ),
        (
            "import(\"bad.off\");",
            &options,
            "E0567",
            "\"bad.off\"",
            "OFF file",
        ),
        (
            "import(\"binary.off\");",
            &options,
            "E0567",
            "\"binary.off\"",
            "UTF-8",
        ),
        (
            "import(\"open.off\");",
            &options,
            "E0565",
            "\"open.off\"",
            "open mesh",
        ),
    ];
    for (text, options, code, at, fragment) in cases {
        let (got, got_at, message) = first_error(&dir, text, options);
        assert_eq!((got, got_at.as_str()), (code, at), "{text}: {message}");
        assert!(message.contains(fragment), "{text}: {message}");
    }
}

/// A device is refused before it is read: `/dev/zero` never ends.
#[cfg(unix)]
#[test]
fn a_device_is_refused_without_reading_it() {
    let dir = scratch("device");
    let link = dir.join("zero.stl");
    std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
    let (code, at, message) = first_error(&dir, "import(\"zero.stl\");", &EvalOptions::default());
    assert_eq!((code, at.as_str()), ("E0566", "\"zero.stl\""), "{message}");
    assert!(message.contains("character device"), "{message}");
}

#[test]
fn other_formats_are_e0301_naming_the_format() {
    let dir = scratch("formats-other");
    for (text, fragment) in [
        ("import(\"part.amf\");", "`.amf`"),
        ("import(\"logo.svg\");", "`.svg`"),
        ("import(\"photo.PNG\");", "`.png`"),
        ("import(\"README\");", "without an extension"),
    ] {
        let (code, at, message) = first_error(&dir, text, &EvalOptions::default());
        assert_eq!(code, "E0301", "{text}: {message}");
        assert_eq!(&text[7..text.len() - 2], at, "{text}");
        assert!(message.contains(fragment), "{text}: {message}");
    }
}

#[test]
fn mesh_size_counts_against_the_vector_length_limit() {
    let dir = scratch("limits");
    std::fs::write(dir.join("t.stl"), binary_stl(&TETRA)).unwrap();
    let options = EvalOptions {
        max_vector_len: 3,
        ..EvalOptions::default()
    };
    let (code, at, message) = first_error(&dir, "import(\"t.stl\");", &options);
    assert_eq!((code, at.as_str()), ("E0558", "\"t.stl\""), "{message}");
    assert!(message.contains("--max-vector-len"), "{message}");
}

/// A far-off, tiny mesh stays exact: a tetrahedron of edge 1e-3 at 1e6.
#[test]
fn a_far_tiny_mesh_is_exact() {
    let dir = scratch("stiff");
    let off = "OFF\n4 4 0\n1000000 1000000 1000000\n1000000.001 1000000 1000000\n1000000 1000000.001 1000000\n1000000 1000000 1000000.001\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    std::fs::write(dir.join("t.off"), off).unwrap();
    let e = eval_in(&dir, "import(\"t.off\");", &EvalOptions::default());
    assert!(e.diagnostics.is_empty(), "{:?}", e.diagnostics);
    let dnf = build_dnf(&e.dag, &DnfOptions::default()).expect("a bounded solid");
    let base = DVec3::splat(1e6);
    for (p, inside) in [
        (DVec3::splat(1e-4), true),
        (DVec3::splat(3e-4), true),
        (DVec3::splat(4e-4), false),
        (DVec3::new(-1e-5, 1e-4, 1e-4), false),
    ] {
        assert_eq!(e.dag.contains(base + p), inside, "DAG at {p}");
        assert_eq!(dnf.contains(base + p), inside, "DNF at {p}");
    }
}
