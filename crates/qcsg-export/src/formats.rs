//! The mesh as a file: binary STL (`stl_io`), ASCII STL, OBJ, OFF and 3MF (a zip of XML, `zip`).
//!
//! Binary STL stores float32: a coordinate near `10⁶` is rounded to `2⁻⁴ = 0.0625` (its unit in
//! the last place), so a part placed far from the origin loses its detail there; the other
//! formats are text and write each f64 coordinate in the shortest form that reads back exactly.
//! Every writer produces bytes in memory; the caller writes them atomically.

use std::fmt::Write as _;
use std::io::{Cursor, Write as _};

use crate::TriangleMesh;

/// A mesh file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// STL, binary (float32) or ASCII.
    Stl {
        /// ASCII instead of binary.
        ascii: bool,
    },
    /// Wavefront OBJ (text, f64).
    Obj,
    /// Object File Format (text, f64).
    Off,
    /// 3D Manufacturing Format (zipped XML, f64 as text).
    ThreeMf,
}

impl Format {
    /// The format named by a file's extension (case-insensitive), if any.
    pub fn from_extension(path: &str, ascii: bool) -> Option<Self> {
        let ext = std::path::Path::new(path)
            .extension()?
            .to_str()?
            .to_ascii_lowercase();
        match ext.as_str() {
            "stl" => Some(Self::Stl { ascii }),
            "obj" => Some(Self::Obj),
            "off" => Some(Self::Off),
            "3mf" => Some(Self::ThreeMf),
            _ => None,
        }
    }

    /// The extensions [`Self::from_extension`] knows.
    pub const EXTENSIONS: &'static [&'static str] = &["stl", "obj", "off", "3mf"];
}

/// The bytes of the mesh in `format`.
pub fn write(mesh: &TriangleMesh, format: Format) -> std::io::Result<Vec<u8>> {
    match format {
        Format::Stl { ascii: false } => stl_binary(mesh),
        Format::Stl { ascii: true } => Ok(stl_ascii(mesh).into_bytes()),
        Format::Obj => Ok(obj(mesh).into_bytes()),
        Format::Off => Ok(off(mesh).into_bytes()),
        Format::ThreeMf => three_mf(mesh),
    }
}

fn normal(mesh: &TriangleMesh, t: &[u32; 3]) -> [f64; 3] {
    let [a, b, c] = mesh.corners(t);
    (b - a).cross(c - a).normalize_or_zero().to_array()
}

fn stl_binary(mesh: &TriangleMesh) -> std::io::Result<Vec<u8>> {
    let f32s = |v: [f64; 3]| stl_io::Vector::new(v.map(|x| x as f32));
    let triangles = mesh.triangles.iter().map(|t| stl_io::Triangle {
        normal: f32s(normal(mesh, t)),
        vertices: mesh.corners(t).map(|v| f32s(v.to_array())),
    });
    let mut bytes = Vec::with_capacity(84 + 50 * mesh.triangles.len());
    stl_io::write_stl(&mut bytes, triangles)?;
    Ok(bytes)
}

fn stl_ascii(mesh: &TriangleMesh) -> String {
    let mut s = String::from("solid qcsg\n");
    for t in &mesh.triangles {
        let [nx, ny, nz] = normal(mesh, t);
        let _ = writeln!(s, "  facet normal {nx:?} {ny:?} {nz:?}\n    outer loop");
        for v in mesh.corners(t) {
            let _ = writeln!(s, "      vertex {:?} {:?} {:?}", v.x, v.y, v.z);
        }
        s.push_str("    endloop\n  endfacet\n");
    }
    s.push_str("endsolid qcsg\n");
    s
}

fn obj(mesh: &TriangleMesh) -> String {
    let mut s = String::from("# qcsg export\n");
    for v in &mesh.vertices {
        let _ = writeln!(s, "v {:?} {:?} {:?}", v.x, v.y, v.z);
    }
    for t in &mesh.triangles {
        let _ = writeln!(s, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    s
}

fn off(mesh: &TriangleMesh) -> String {
    let mut s = format!("OFF\n{} {} 0\n", mesh.vertices.len(), mesh.triangles.len());
    for v in &mesh.vertices {
        let _ = writeln!(s, "{:?} {:?} {:?}", v.x, v.y, v.z);
    }
    for t in &mesh.triangles {
        let _ = writeln!(s, "3 {} {} {}", t[0], t[1], t[2]);
    }
    s
}

const CONTENT_TYPES: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types">
  <Default Extension="rels" ContentType="application/vnd.openxmlformats-package.relationships+xml"/>
  <Default Extension="model" ContentType="application/vnd.ms-package.3dmanufacturing-3dmodel+xml"/>
</Types>
"#;

const RELS: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">
  <Relationship Target="/3D/3dmodel.model" Id="rel0" Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"/>
</Relationships>
"#;

/// The 3MF model part: one object, one mesh, millimetres (OpenSCAD's unit convention).
pub fn three_mf_model(mesh: &TriangleMesh) -> String {
    let mut s = String::from(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<model unit=\"millimeter\" xml:lang=\"en-US\" \
         xmlns=\"http://schemas.microsoft.com/3dmanufacturing/core/2015/02\">\n  <resources>\n    \
         <object id=\"1\" type=\"model\">\n      <mesh>\n        <vertices>\n",
    );
    for v in &mesh.vertices {
        let _ = writeln!(
            s,
            "          <vertex x=\"{:?}\" y=\"{:?}\" z=\"{:?}\"/>",
            v.x, v.y, v.z
        );
    }
    s.push_str("        </vertices>\n        <triangles>\n");
    for t in &mesh.triangles {
        let _ = writeln!(
            s,
            "          <triangle v1=\"{}\" v2=\"{}\" v3=\"{}\"/>",
            t[0], t[1], t[2]
        );
    }
    s.push_str(
        "        </triangles>\n      </mesh>\n    </object>\n  </resources>\n  <build>\n    \
         <item objectid=\"1\"/>\n  </build>\n</model>\n",
    );
    s
}

fn three_mf(mesh: &TriangleMesh) -> std::io::Result<Vec<u8>> {
    let mut zip = zip::ZipWriter::new(Cursor::new(Vec::new()));
    let options = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated);
    let parts = [
        ("[Content_Types].xml", CONTENT_TYPES.to_owned()),
        ("_rels/.rels", RELS.to_owned()),
        ("3D/3dmodel.model", three_mf_model(mesh)),
    ];
    for (name, text) in parts {
        zip.start_file(name, options)
            .map_err(std::io::Error::other)?;
        zip.write_all(text.as_bytes())?;
    }
    Ok(zip.finish().map_err(std::io::Error::other)?.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;
    use qcsg_quadric::DVec3;

    fn triangle() -> TriangleMesh {
        TriangleMesh {
            vertices: vec![DVec3::ZERO, DVec3::X, DVec3::new(0.1, 1e6 + 0.03, 0.0)],
            triangles: vec![[0, 1, 2]],
        }
    }

    #[test]
    fn binary_stl_has_its_size_and_rounds_to_float32() {
        let bytes = write(&triangle(), Format::Stl { ascii: false }).expect("writes");
        assert_eq!(bytes.len(), 84 + 50);
        let mesh = stl_io::read_stl(&mut Cursor::new(bytes)).expect("reads");
        // 1e6 + 0.03 is not a float32: it rounds to a multiple of 1/16.
        let y = mesh.vertices[2][1];
        assert_eq!(y, 1_000_000.0);
    }

    #[test]
    fn text_formats_keep_f64() {
        let obj = write(&triangle(), Format::Obj).expect("writes");
        let text = String::from_utf8(obj).expect("utf-8");
        assert!(text.contains("v 0.1 1000000.03 0.0"), "{text}");
        assert!(text.contains("f 1 2 3"));
        let off =
            String::from_utf8(write(&triangle(), Format::Off).expect("writes")).expect("utf-8");
        assert!(off.starts_with("OFF\n3 1 0\n") && off.contains("3 0 1 2"));
        let stl = String::from_utf8(write(&triangle(), Format::Stl { ascii: true }).expect("w"))
            .expect("utf-8");
        assert!(stl.contains("vertex 0.1 1000000.03 0.0"));
    }

    #[test]
    fn three_mf_is_a_zip_with_the_model() {
        let bytes = write(&triangle(), Format::ThreeMf).expect("writes");
        let mut archive = zip::ZipArchive::new(Cursor::new(bytes)).expect("zip");
        let mut model = String::new();
        std::io::Read::read_to_string(
            &mut archive.by_name("3D/3dmodel.model").expect("model part"),
            &mut model,
        )
        .expect("reads");
        assert!(model.contains("<vertex x=\"0.1\" y=\"1000000.03\" z=\"0.0\"/>"));
        assert!(model.contains("<triangle v1=\"0\" v2=\"1\" v3=\"2\"/>"));
        assert!(archive.by_name("[Content_Types].xml").is_ok());
    }

    #[test]
    fn extensions() {
        assert_eq!(
            Format::from_extension("a.STL", true),
            Some(Format::Stl { ascii: true })
        );
        assert_eq!(
            Format::from_extension("a.3mf", false),
            Some(Format::ThreeMf)
        );
        assert_eq!(Format::from_extension("a.ply", false), None);
    }
}
