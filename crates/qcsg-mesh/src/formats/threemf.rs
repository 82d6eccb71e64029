//! 3MF (3D Manufacturing Format): a zip package whose model part is XML, read with OpenSCAD
//! 2021.01's meaning. OpenSCAD (through lib3mf) takes every `<object>` that holds a `<mesh>`,
//! ignores components, build items and their transforms, materials and units, and unites the
//! objects; [`read_3mf`] returns the objects' meshes in file order for the caller to unite.
//!
//! The model part is the one `_rels/.rels` names as the start part (type `…/3dmodel`), or
//! `3D/3dmodel.model` when the package has no such relationship. Its unpacked size is bounded by
//! the caller's byte limit before it is read, so a small archive cannot unpack into gigabytes;
//! XML with a DTD is refused (no entity expansion). Triangles list their vertices
//! counter-clockwise seen from outside, as STL does, and are reversed into OpenSCAD's order.

use std::io::{Cursor, Read};

use glam::DVec3;

use super::{ReadError, ReadLimits};
use crate::Mesh;

const FORMAT: &str = "3MF";

/// The relationship type of a package's 3-D model part.
const MODEL_RELATIONSHIP: &str = "http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel";
/// Where the model part usually is, for packages without that relationship.
const DEFAULT_MODEL: &str = "3D/3dmodel.model";

/// Reads a 3MF package: one mesh for each mesh object, in file order. The model part may unpack
/// to at most `max_unpacked_bytes`.
pub fn read_3mf(
    bytes: &[u8],
    limits: &ReadLimits,
    max_unpacked_bytes: u64,
) -> Result<Vec<Mesh>, ReadError> {
    let mut archive = zip::ZipArchive::new(Cursor::new(bytes)).map_err(|e| {
        ReadError::new(
            FORMAT,
            "the package",
            format!("not a zip archive, as a 3MF file is ({e})"),
        )
    })?;
    let model_name = match read_part(&mut archive, "_rels/.rels", max_unpacked_bytes)? {
        Some(rels) => start_part(&rels)?.unwrap_or_else(|| DEFAULT_MODEL.to_owned()),
        None => DEFAULT_MODEL.to_owned(),
    };
    let model = read_part(&mut archive, &model_name, max_unpacked_bytes)?.ok_or_else(|| {
        ReadError::new(
            FORMAT,
            "the package",
            format!("it has no model part `{model_name}`"),
        )
    })?;
    read_model(&model, &model_name, limits)
}

/// The text of the part `name` (without a leading `/`), or `None` when the package lacks it.
fn read_part(
    archive: &mut zip::ZipArchive<Cursor<&[u8]>>,
    name: &str,
    max_bytes: u64,
) -> Result<Option<String>, ReadError> {
    let at = |message: String| ReadError::new(FORMAT, format!("part `{name}`"), message);
    let mut file = match archive.by_name(name) {
        Ok(file) => file,
        Err(zip::result::ZipError::FileNotFound) => return Ok(None),
        Err(e) => return Err(at(format!("cannot be read: {e}"))),
    };
    if file.size() > max_bytes {
        return Err(at(format!(
            "it unpacks to {} bytes, more than the limit of {max_bytes}",
            file.size()
        )));
    }
    // The declared size can lie; the reader stops one byte past the limit either way.
    let mut data = Vec::new();
    (&mut file)
        .take(max_bytes.saturating_add(1))
        .read_to_end(&mut data)
        .map_err(|e| at(format!("cannot be unpacked: {e}")))?;
    if data.len() as u64 > max_bytes {
        return Err(at(format!(
            "it unpacks to more than the limit of {max_bytes} bytes"
        )));
    }
    String::from_utf8(data).map(Some).map_err(|e| {
        at(format!(
            "byte {}: not UTF-8 text",
            e.utf8_error().valid_up_to()
        ))
    })
}

/// Parses XML text, refusing DTDs.
fn parse_xml<'t>(text: &'t str, part: &str) -> Result<roxmltree::Document<'t>, ReadError> {
    roxmltree::Document::parse(text).map_err(|e| {
        let pos = e.pos();
        ReadError::new(
            FORMAT,
            format!("part `{part}`, line {}, column {}", pos.row, pos.col),
            format!("not well-formed XML: {e}"),
        )
    })
}

/// The model part named by the package relationships, if any.
fn start_part(rels: &str) -> Result<Option<String>, ReadError> {
    let doc = parse_xml(rels, "_rels/.rels")?;
    Ok(doc
        .descendants()
        .filter(|n| n.has_tag_name("Relationship"))
        .find(|n| n.attribute("Type") == Some(MODEL_RELATIONSHIP))
        .and_then(|n| n.attribute("Target"))
        .map(|target| target.trim_start_matches('/').to_owned()))
}

/// The meshes of the model part's mesh objects.
fn read_model(text: &str, part: &str, limits: &ReadLimits) -> Result<Vec<Mesh>, ReadError> {
    let doc = parse_xml(text, part)?;
    let at = |node: roxmltree::Node<'_, '_>, message: String| {
        let pos = doc.text_pos_at(node.range().start);
        ReadError::new(FORMAT, format!("part `{part}`, line {}", pos.row), message)
    };
    let mut meshes = Vec::new();
    let (mut vertices, mut triangles) = (0usize, 0usize);
    let objects = doc
        .descendants()
        .filter(|n| n.tag_name().name() == "object");
    for object in objects {
        let Some(mesh) = object.children().find(|n| n.tag_name().name() == "mesh") else {
            continue;
        };
        let mut points = Vec::new();
        for vertex in list(mesh, "vertices", "vertex") {
            vertices += 1;
            if vertices > limits.max_vertices {
                return Err(at(
                    vertex,
                    format!("more vertices than the limit of {}", limits.max_vertices),
                ));
            }
            let mut p = [0.0; 3];
            for (c, name) in p.iter_mut().zip(["x", "y", "z"]) {
                *c = number(vertex, name).map_err(|m| at(vertex, m))?;
            }
            points.push(DVec3::from_array(p));
        }
        let mut faces = Vec::new();
        for triangle in list(mesh, "triangles", "triangle") {
            triangles += 1;
            if triangles > limits.max_triangles {
                return Err(at(
                    triangle,
                    format!("more triangles than the limit of {}", limits.max_triangles),
                ));
            }
            let mut face = Vec::with_capacity(3);
            for name in ["v3", "v2", "v1"] {
                let index = index(triangle, name).map_err(|m| at(triangle, m))?;
                if index >= points.len() {
                    return Err(at(
                        triangle,
                        format!(
                            "vertex index {name}=\"{index}\" is past the object's {} vertices",
                            points.len()
                        ),
                    ));
                }
                face.push(index);
            }
            faces.push(face);
        }
        if faces.is_empty() {
            return Err(at(object, "a mesh object without triangles".to_owned()));
        }
        meshes.push(Mesh { points, faces });
    }
    if meshes.is_empty() {
        return Err(ReadError::new(
            FORMAT,
            format!("part `{part}`"),
            "the model has no mesh object",
        ));
    }
    Ok(meshes)
}

/// The `<item>` elements inside the `<tag>` children of `mesh`.
fn list<'a, 'input>(
    mesh: roxmltree::Node<'a, 'input>,
    tag: &'static str,
    item: &'static str,
) -> impl Iterator<Item = roxmltree::Node<'a, 'input>> {
    mesh.children()
        .filter(move |n| n.tag_name().name() == tag)
        .flat_map(|n| n.children())
        .filter(move |n| n.tag_name().name() == item)
}

/// The finite number in attribute `name`.
fn number(node: roxmltree::Node<'_, '_>, name: &str) -> Result<f64, String> {
    let text = node
        .attribute(name)
        .ok_or_else(|| format!("<{}> without `{name}`", node.tag_name().name()))?;
    text.trim()
        .parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| format!("{name}=\"{text}\" is not a finite number"))
}

/// The vertex index in attribute `name`.
fn index(node: roxmltree::Node<'_, '_>, name: &str) -> Result<usize, String> {
    let text = node
        .attribute(name)
        .ok_or_else(|| format!("<triangle> without `{name}`"))?;
    text.trim()
        .parse::<usize>()
        .map_err(|_| format!("{name}=\"{text}\" is not a vertex index"))
}
