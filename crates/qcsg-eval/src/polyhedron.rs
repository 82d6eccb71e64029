//! OpenSCAD's `polyhedron(points, faces)` (and imported meshes) as a solid: the convex cells that
//! [`qcsg_mesh::polyhedron_cells`] cuts the mesh's solid into become the union of those cells,
//! each the intersection of its half-spaces.
//!
//! Every cell declares its box, so the union of many cells stays cheap to bound and its DNF has
//! one short term per cell. A plane is computed once per triangle in `qcsg-mesh` and normalised
//! here the same way wherever it occurs, so cells sharing a plane share its quadric exactly.
//!
//! A built mesh also keeps its triangles ([`MeshShape::faces`]): `projection` casts a mesh's
//! shadow from them ([`crate::mesh_shadow`]), which the cells' half-spaces do not give exactly.

use std::rc::Rc;

use glam::DVec3;
use qcsg_csg::{Aabb, Dag, Edge, NodeId, Source};
use qcsg_mesh::{Mesh, MeshError, MeshLimits, Polyhedron, polyhedron_cells};
use qcsg_quadric::Quadric;

use crate::mesh_shadow::MeshFaces;
use crate::polygon::point_index;
use crate::value::Value;

/// Which argument of `polyhedron` a failure is about, for its span.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeshPart {
    /// The points (a point that is not 3 finite numbers, too many points).
    Points,
    /// The faces (an index naming no point, an open edge, too many entries, …).
    Faces,
}

/// Why a mesh was refused.
#[derive(Debug)]
pub enum MeshFailure {
    /// An argument of the wrong shape (a point that is not 3 numbers, a face entry that is not
    /// an index).
    Argument(MeshPart, String),
    /// The faces bound no solid (see [`qcsg_mesh::MeshError`]).
    Invalid(MeshPart, String),
    /// More points or face entries than the limit (the evaluator's vector-length limit).
    TooLarge(MeshPart, String),
}

/// A built mesh: its node (`None` when the solid is empty) and the warnings to report.
pub struct BuiltMesh {
    /// The union of the cells, or `None` for an empty solid.
    pub node: Option<NodeId>,
    /// Non-planar faces and inside-out meshes, as the cell decomposition found them.
    pub warnings: Vec<String>,
    /// The mesh's triangles, for the shadow of `node`.
    pub faces: Rc<MeshFaces>,
}

/// A mesh's solid as convex cells, with the triangles that bound it (what `import` and
/// `surface` keep per file).
pub struct MeshShape {
    /// The convex cells.
    pub cells: Polyhedron,
    /// The mesh's triangles, as the cells were cut from them.
    pub faces: Rc<MeshFaces>,
}

/// The half-space `normal · p ≤ offset`, normalised so that its numbers depend only on the
/// plane (cells sharing a face's plane share the same quadric exactly).
pub(crate) fn normalised_half_space(normal: DVec3, offset: f64) -> Option<Quadric> {
    let scale = 1.0 / normal.length();
    let n = normal * scale;
    Quadric::new(
        DVec3::ZERO,
        [
            0.0,
            0.0,
            0.0,
            0.0,
            0.0,
            0.0,
            0.5 * n.x,
            0.5 * n.y,
            0.5 * n.z,
            -offset * scale,
        ],
    )
}

/// The points of `polyhedron(points)`: each a vector of 3 numbers.
fn points_of(value: &Value<'_>) -> Result<Vec<DVec3>, MeshFailure> {
    let bad = |m: String| MeshFailure::Argument(MeshPart::Points, m);
    if matches!(value, Value::Undef) {
        return Ok(Vec::new());
    }
    let Some(items) = value.as_vector() else {
        return Err(bad(format!(
            "polyhedron(points) needs a vector of points, got {}",
            value.type_name()
        )));
    };
    items
        .iter()
        .enumerate()
        .map(|(i, p)| {
            p.as_numbers(3)
                .map(|v| DVec3::new(v[0], v[1], v[2]))
                .ok_or_else(|| {
                    bad(format!(
                        "point {i} of the polyhedron is not a vector of 3 numbers"
                    ))
                })
        })
        .collect()
}

/// The faces of `polyhedron(faces)`: each a vector of point indices.
fn faces_of(value: &Value<'_>, max_entries: usize) -> Result<Vec<Vec<usize>>, MeshFailure> {
    let bad = |m: String| MeshFailure::Argument(MeshPart::Faces, m);
    if matches!(value, Value::Undef) {
        return Ok(Vec::new());
    }
    let Some(faces) = value.as_vector() else {
        return Err(bad(format!(
            "polyhedron(faces) needs a vector of faces, got {}",
            value.type_name()
        )));
    };
    let mut out = Vec::with_capacity(faces.len());
    let mut entries = 0usize;
    for (f, face) in faces.iter().enumerate() {
        let Some(items) = face.as_vector() else {
            return Err(bad(format!(
                "face {f} of the polyhedron is not a vector of point indices"
            )));
        };
        entries = entries.saturating_add(items.len());
        if entries > max_entries {
            return Err(MeshFailure::TooLarge(
                MeshPart::Faces,
                format!("the polyhedron has more than {max_entries} face entries"),
            ));
        }
        let mut indices = Vec::with_capacity(items.len());
        for (k, e) in items.iter().enumerate() {
            let Some(i) = point_index(e) else {
                return Err(bad(format!(
                    "entry {k} of face {f} is not a point index (a whole number from 0)"
                )));
            };
            indices.push(i);
        }
        out.push(indices);
    }
    Ok(out)
}

/// The mesh of `polyhedron(points, faces)` from its argument values, with at most `max_entries`
/// face entries.
pub fn mesh_of(
    points: &Value<'_>,
    faces: &Value<'_>,
    max_entries: usize,
) -> Result<Mesh, MeshFailure> {
    Ok(Mesh {
        points: points_of(points)?,
        faces: faces_of(faces, max_entries)?,
    })
}

/// Which argument a [`MeshError`] is about.
fn part_of(e: &MeshError) -> MeshPart {
    match e {
        MeshError::NonFinitePoint { .. } | MeshError::HugeCoordinate { .. } => MeshPart::Points,
        MeshError::TooLarge { what, .. } if *what == "points" => MeshPart::Points,
        _ => MeshPart::Faces,
    }
}

/// The solid `mesh` bounds, as the union of its convex cells, with at most `max_len` points and
/// face entries.
pub fn build(
    dag: &mut Dag,
    mesh: &Mesh,
    max_len: usize,
    source: Source,
) -> Result<BuiltMesh, MeshFailure> {
    solid(dag, &shape(mesh, max_len)?, source)
}

/// The cells of the solid `mesh` bounds, with its triangles.
pub fn shape(mesh: &Mesh, max_len: usize) -> Result<MeshShape, MeshFailure> {
    Ok(MeshShape {
        cells: cells(mesh, max_len)?,
        faces: Rc::new(MeshFaces::of(mesh)),
    })
}

/// The convex cells of the solid `mesh` bounds (the costly part, which `import` keeps per file).
pub fn cells(mesh: &Mesh, max_len: usize) -> Result<Polyhedron, MeshFailure> {
    let limits = MeshLimits {
        max_points: max_len,
        max_face_entries: max_len,
    };
    polyhedron_cells(mesh, &limits).map_err(|e| {
        let part = part_of(&e);
        match e {
            MeshError::TooLarge { .. } => MeshFailure::TooLarge(part, e.to_string()),
            other => MeshFailure::Invalid(part, other.to_string()),
        }
    })
}

/// The union of `shape`'s cells, each the intersection of its half-spaces with its box.
pub fn solid(dag: &mut Dag, mesh: &MeshShape, source: Source) -> Result<BuiltMesh, MeshFailure> {
    let shape = &mesh.cells;
    let mut cells: Vec<Edge> = Vec::with_capacity(shape.cells.len());
    for cell in &shape.cells {
        let mut sides: Vec<Edge> = Vec::with_capacity(cell.planes.len());
        for h in &cell.planes {
            let q = normalised_half_space(h.normal, h.offset).ok_or_else(|| {
                MeshFailure::Invalid(
                    MeshPart::Faces,
                    "a face of the mesh is not representable".into(),
                )
            })?;
            sides.push(dag.leaf(q, source).into());
        }
        let node = dag.intersection(sides, source);
        cells.push(dag.bounded(node, Aabb::new(cell.min, cell.max)).into());
    }
    let node = match cells.len() {
        0 => None,
        1 => Some(cells[0].child),
        _ => {
            let node = dag.union(cells, source);
            Some(dag.bounded(node, Aabb::new(shape.min, shape.max)))
        }
    };
    Ok(BuiltMesh {
        node,
        warnings: shape.warnings.clone(),
        faces: mesh.faces.clone(),
    })
}
