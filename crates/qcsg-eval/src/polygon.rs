//! OpenSCAD's `polygon(points, paths)` as a z-invariant solid: the even–odd region that
//! [`qcsg_mesh::polygon_cells`] cuts into convex cells becomes the union of those cells, each the
//! intersection of its half-planes' z-invariant half-spaces (see [`crate::planar`]).
//!
//! Every cell declares its box (bounded in x and y, unbounded in z, as `square`'s), so the union
//! of thousands of cells stays cheap to bound and its DNF has one short term per cell.

use glam::DVec2;
use qcsg_csg::{Dag, Edge, NodeId, Source};
use qcsg_mesh::{HalfPlane, PolygonError, PolygonLimits, polygon_cells};
use qcsg_quadric::Quadric;

use crate::polyhedron::normalised_half_space;
use crate::primitives::ArgLookup;
use crate::primitives_2d::column;
use crate::value::Value;

/// Why a `polygon` call was refused.
#[derive(Debug)]
pub enum PolygonFailure {
    /// An argument of the wrong shape, a point out of range, a path entry naming no point.
    Argument(String),
    /// More points or path entries than the limit (the evaluator's vector-length limit).
    TooLarge(String),
}

/// A built polygon: its node (`None` when the region is empty) and the warnings to report.
pub struct BuiltPolygon {
    /// The union of the cells, or `None` for an empty region.
    pub node: Option<NodeId>,
    /// Self-crossing outlines and paths that enclose nothing, as the cell decomposition found them.
    pub warnings: Vec<String>,
}

/// The z-invariant half-space `normal · p ≤ offset` (cells sharing an edge's line share the same
/// quadric exactly; see [`crate::polyhedron::normalised_half_space`]).
pub(crate) fn half_space(h: &HalfPlane) -> Option<Quadric> {
    normalised_half_space(h.normal.extend(0.0), h.offset)
}

/// An entry of a list of point indices (`paths`, `faces`): a whole number from 0.
pub(crate) fn point_index(e: &Value<'_>) -> Option<usize> {
    e.as_number()
        .filter(|&i| i >= 0.0 && i.fract() == 0.0 && i < usize::MAX as f64)
        .map(|i| i as usize)
}

fn points_of(value: &Value<'_>) -> Result<Vec<DVec2>, PolygonFailure> {
    let Some(items) = value.as_vector() else {
        return Err(PolygonFailure::Argument(format!(
            "polygon(points) needs a vector of points, got {}",
            value.type_name()
        )));
    };
    items
        .iter()
        .enumerate()
        .map(|(i, p)| {
            // OpenSCAD reads x and y of each point (a z, if given, is ignored).
            match p.as_vector() {
                Some(v) if v.len() == 2 || v.len() == 3 => {
                    match (v[0].as_number(), v[1].as_number()) {
                        (Some(x), Some(y)) => Ok(DVec2::new(x, y)),
                        _ => Err(()),
                    }
                }
                _ => Err(()),
            }
            .map_err(|()| {
                PolygonFailure::Argument(format!(
                    "point {i} of the polygon is not a vector of 2 numbers"
                ))
            })
        })
        .collect()
}

fn paths_of(value: &Value<'_>) -> Result<Option<Vec<Vec<usize>>>, PolygonFailure> {
    if matches!(value, Value::Undef) {
        return Ok(None);
    }
    let bad = |what: String| PolygonFailure::Argument(what);
    let Some(paths) = value.as_vector() else {
        return Err(bad(format!(
            "polygon(paths) needs a vector of paths, got {}",
            value.type_name()
        )));
    };
    let mut out = Vec::with_capacity(paths.len());
    for (p, path) in paths.iter().enumerate() {
        let Some(entries) = path.as_vector() else {
            return Err(bad(format!(
                "path {p} of the polygon is not a vector of point indices"
            )));
        };
        let mut indices = Vec::with_capacity(entries.len());
        for (k, e) in entries.iter().enumerate() {
            let Some(i) = point_index(e) else {
                return Err(bad(format!(
                    "entry {k} of path {p} is not a point index (a whole number from 0)"
                )));
            };
            indices.push(i);
        }
        out.push(indices);
    }
    Ok(Some(out))
}

/// The union of a polygon's cells, each the intersection of its half-planes' z-invariant
/// half-spaces within its box; `None` for an empty region.
pub(crate) fn cells_node(
    dag: &mut Dag,
    shape: &qcsg_mesh::Polygon,
    source: Source,
) -> Result<Option<NodeId>, String> {
    let mut cells: Vec<Edge> = Vec::with_capacity(shape.cells.len());
    for cell in &shape.cells {
        let mut sides: Vec<Edge> = Vec::with_capacity(cell.half_planes.len());
        for h in &cell.half_planes {
            let q = half_space(h).ok_or("an edge of the polygon is not representable")?;
            sides.push(dag.leaf(q, source).into());
        }
        let node = dag.intersection(sides, source);
        cells.push(dag.bounded(node, column(cell.min, cell.max)).into());
    }
    Ok(match cells.len() {
        0 => None,
        1 => Some(cells[0].child),
        _ => {
            let node = dag.union(cells, source);
            Some(dag.bounded(node, column(shape.min, shape.max)))
        }
    })
}

/// `polygon(points, paths)`: the even–odd region of the paths (one outline through all points
/// when `paths` is undefined), with at most `max_points` points and path entries.
pub fn polygon(
    dag: &mut Dag,
    args: &dyn ArgLookup<'_>,
    max_points: usize,
    source: Source,
) -> Result<BuiltPolygon, PolygonFailure> {
    let points = match args.get("points") {
        Value::Undef => Vec::new(),
        v => points_of(&v)?,
    };
    let paths = paths_of(&args.get("paths"))?;
    let limits = PolygonLimits { max_points };
    let shape = polygon_cells(&points, paths.as_deref(), &limits).map_err(|e| match e {
        PolygonError::TooManyPoints { .. } => PolygonFailure::TooLarge(e.to_string()),
        other => PolygonFailure::Argument(other.to_string()),
    })?;
    let node = cells_node(dag, &shape, source).map_err(PolygonFailure::Argument)?;
    Ok(BuiltPolygon {
        node,
        warnings: shape.warnings,
    })
}
