//! The STL and OFF readers on small files written here and on OpenSCAD's bundled examples.

use glam::DVec3;
use qcsg_mesh::{MeshLimits, ReadLimits, polyhedron_cells, read_off, read_stl};

/// A tetrahedron's four triangles, counter-clockwise seen from outside (STL's order).
fn tetrahedron() -> Vec<[[f32; 3]; 3]> {
    let (o, x, y, z) = (
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    );
    vec![[o, y, x], [o, x, z], [o, z, y], [x, y, z]]
}

fn ascii_stl(triangles: &[[[f32; 3]; 3]]) -> String {
    let mut text = String::from("solid t\n");
    for t in triangles {
        text.push_str("  facet normal 0 0 0\n    outer loop\n");
        for v in t {
            text.push_str(&format!("      vertex {} {} {}\n", v[0], v[1], v[2]));
        }
        text.push_str("    endloop\n  endfacet\n");
    }
    text.push_str("endsolid t\n");
    text
}

fn binary_stl(triangles: &[[[f32; 3]; 3]]) -> Vec<u8> {
    let mut bytes = b"solid but binary".to_vec();
    bytes.resize(80, 0);
    bytes.extend((triangles.len() as u32).to_le_bytes());
    for t in triangles {
        bytes.extend([0u8; 12]);
        for v in t {
            for c in v {
                bytes.extend(c.to_le_bytes());
            }
        }
        bytes.extend([0u8; 2]);
    }
    bytes
}

#[test]
fn stl_ascii_and_binary_give_the_same_closed_mesh() {
    let limits = ReadLimits::default();
    let ascii = read_stl(ascii_stl(&tetrahedron()).as_bytes(), &limits).unwrap();
    let binary = read_stl(&binary_stl(&tetrahedron()), &limits).unwrap();
    assert_eq!(ascii, binary);
    assert_eq!(ascii.points.len(), 4, "equal vertices are merged");
    let solid = polyhedron_cells(&ascii, &MeshLimits::default()).unwrap();
    assert!(solid.warnings.is_empty(), "{:?}", solid.warnings);
    assert!(solid.contains(DVec3::splat(0.2)) && !solid.contains(DVec3::splat(0.5)));
}

#[test]
fn stl_errors_name_the_line_or_record() {
    let limits = ReadLimits::default();
    let bad = "solid t\n facet normal 0 0 0\n  outer loop\n   vertex 0 0 zero\n";
    let error = read_stl(bad.as_bytes(), &limits).unwrap_err();
    assert_eq!(error.location, "line 4", "{error}");
    assert!(
        error.to_string().contains("`zero` is not a finite number"),
        "{error}"
    );
    let short = "solid t\n outer loop\n vertex 0 0 0\n vertex 1 0 0\n endloop\n";
    assert!(
        read_stl(short.as_bytes(), &limits)
            .unwrap_err()
            .message
            .contains("three vertices")
    );
    assert!(read_stl(b"\xff\xfe garbage", &limits).is_err());
    let few = ReadLimits {
        max_triangles: 2,
        ..limits
    };
    assert!(
        read_stl(&binary_stl(&tetrahedron()), &few)
            .unwrap_err()
            .message
            .contains("limit")
    );
    assert!(
        read_stl(ascii_stl(&tetrahedron()).as_bytes(), &few)
            .unwrap_err()
            .message
            .contains("limit")
    );
    let mut nan = tetrahedron();
    nan[2][1][0] = f32::NAN;
    assert_eq!(
        read_stl(&binary_stl(&nan), &limits).unwrap_err().location,
        "triangle 2"
    );
}

#[test]
fn off_cube_reads_as_a_closed_solid() {
    let cube = "OFF\n# a unit cube\n8 6 12\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n\
                4 3 2 1 0\n4 0 1 5 4\n4 4 5 6 7 255 0 0\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n";
    let mesh = read_off(cube, &ReadLimits::default()).unwrap();
    assert_eq!((mesh.points.len(), mesh.faces.len()), (8, 6));
    let solid = polyhedron_cells(&mesh, &MeshLimits::default()).unwrap();
    assert!(solid.warnings.is_empty(), "{:?}", solid.warnings);
    assert!(solid.contains(DVec3::splat(0.5)) && !solid.contains(DVec3::splat(1.5)));
    let error = read_off("OFF\n1 0 0\n0 0 x\n", &ReadLimits::default()).unwrap_err();
    assert_eq!(error.location, "line 3");
    let error = read_off("OFF\n2 0 0\n0 0 0\n", &ReadLimits::default()).unwrap_err();
    assert!(error.message.contains("ends where"), "{error}");
    assert!(
        read_off("PLY\n", &ReadLimits::default())
            .unwrap_err()
            .message
            .contains("expected `OFF`")
    );
}

#[test]
fn openscad_example_stl_files_read_as_closed_solids() {
    for path in [
        "/usr/share/openscad/examples/Basics/projection.stl",
        "/usr/share/openscad/examples/Old/example012.stl",
    ] {
        let Ok(bytes) = std::fs::read(path) else {
            // OpenSCAD's examples are not installed on every machine.
            continue;
        };
        let mesh =
            read_stl(&bytes, &ReadLimits::default()).unwrap_or_else(|e| panic!("{path}: {e}"));
        let solid = polyhedron_cells(&mesh, &MeshLimits::default())
            .unwrap_or_else(|e| panic!("{path}: {e}"));
        assert!(!solid.cells.is_empty(), "{path}");
        assert!(
            !solid.warnings.iter().any(|w| w.contains("inside out")),
            "{path}: {:?}",
            solid.warnings
        );
    }
}
