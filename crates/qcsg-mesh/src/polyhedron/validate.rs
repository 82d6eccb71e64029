//! Validation of a polyhedron's mesh and its split into triangles.
//!
//! Checks, in order: sizes against the limits, finite and bounded coordinates, indices in range,
//! faces of at least three distinct points (consecutive repeats are dropped), then every edge
//! used exactly twice in opposite directions. The first problem is the error, naming the point,
//! face or edge. Faces become fans of triangles from their first point; exactly degenerate
//! triangles are dropped (they bound nothing), a visibly non-planar face gets a warning, and so
//! does a mesh whose faces run counter-clockwise seen from outside.

use std::collections::HashMap;

use glam::DVec3;

use super::{MAX_MESH_COORDINATE, Mesh, MeshError, MeshLimits, Plane, Triangle};
use crate::exact::normal_signs;

/// A validated mesh as triangles, and its warnings.
pub(super) struct Checked {
    pub(super) triangles: Vec<Triangle>,
    pub(super) warnings: Vec<String>,
}

/// Validates `mesh` and splits its faces into triangles.
pub(super) fn validate(mesh: &Mesh, limits: &MeshLimits) -> Result<Checked, MeshError> {
    if mesh.points.len() > limits.max_points {
        return Err(MeshError::TooLarge {
            what: "points",
            count: mesh.points.len(),
            limit: limits.max_points,
        });
    }
    let entries: usize = mesh.faces.iter().map(Vec::len).sum();
    if entries > limits.max_face_entries {
        return Err(MeshError::TooLarge {
            what: "face entries",
            count: entries,
            limit: limits.max_face_entries,
        });
    }
    for (index, p) in mesh.points.iter().enumerate() {
        if !p.is_finite() {
            return Err(MeshError::NonFinitePoint { index });
        }
        if let Some(&value) = p.to_array().iter().find(|v| v.abs() > MAX_MESH_COORDINATE) {
            return Err(MeshError::HugeCoordinate { index, value });
        }
    }
    let mut faces: Vec<Vec<usize>> = Vec::with_capacity(mesh.faces.len());
    for (face, indices) in mesh.faces.iter().enumerate() {
        for (position, &index) in indices.iter().enumerate() {
            if index >= mesh.points.len() {
                return Err(MeshError::IndexOutOfRange {
                    face,
                    position,
                    index,
                    points: mesh.points.len(),
                });
            }
        }
        let mut cycle: Vec<usize> = Vec::with_capacity(indices.len());
        for &i in indices {
            if cycle.last() != Some(&i) {
                cycle.push(i);
            }
        }
        while cycle.len() > 1 && cycle.first() == cycle.last() {
            cycle.pop();
        }
        let mut distinct = cycle.clone();
        distinct.sort_unstable();
        distinct.dedup();
        if distinct.len() < 3 {
            return Err(MeshError::DegenerateFace { face });
        }
        faces.push(cycle);
    }
    check_edges(&faces)?;

    let mut warnings = Vec::new();
    let mut triangles = Vec::with_capacity(entries);
    let mut non_planar = Vec::new();
    let mut volume6 = 0.0;
    let origin = mesh.points.first().copied().unwrap_or(DVec3::ZERO);
    for (face, cycle) in faces.iter().enumerate() {
        let corner = |k: usize| mesh.points[cycle[k]];
        if !is_planar(cycle.iter().map(|&i| mesh.points[i])) {
            non_planar.push(face);
        }
        for k in 1..cycle.len() - 1 {
            let (a, b, c) = (corner(0), corner(k), corner(k + 1));
            volume6 += (a - origin).dot((b - origin).cross(c - origin));
            if normal_signs(a, b, c) == [0, 0, 0] {
                continue;
            }
            triangles.push(Triangle {
                corners: [a, b, c],
                plane: Plane::through(a, b, c),
            });
        }
    }
    if !non_planar.is_empty() {
        let listed: Vec<String> = non_planar.iter().take(10).map(usize::to_string).collect();
        warnings.push(format!(
            "{} face(s) are not planar ({}{}); each is split into triangles fanning from its first point",
            non_planar.len(),
            listed.join(", "),
            if non_planar.len() > 10 { ", …" } else { "" }
        ));
    }
    // Clockwise seen from outside gives a negative signed volume.
    if volume6 > 0.0 {
        warnings.push(
            "the faces run counter-clockwise seen from outside (the mesh is inside out; OpenSCAD lists them clockwise); it is read as the solid it encloses".to_string(),
        );
    }
    Ok(Checked {
        triangles,
        warnings,
    })
}

/// Every edge used exactly twice, in opposite directions.
fn check_edges(faces: &[Vec<usize>]) -> Result<(), MeshError> {
    // (low, high) → the uses: (face, whether it runs low → high).
    let mut uses: HashMap<(usize, usize), Vec<(usize, bool)>> = HashMap::new();
    for (face, cycle) in faces.iter().enumerate() {
        for k in 0..cycle.len() {
            let (from, to) = (cycle[k], cycle[(k + 1) % cycle.len()]);
            uses.entry((from.min(to), from.max(to)))
                .or_default()
                .push((face, from < to));
        }
    }
    // Report the problem at the lowest edge, so the message does not depend on hashing.
    let mut keys: Vec<&(usize, usize)> = uses.keys().collect();
    keys.sort_unstable();
    for &(a, b) in keys {
        let list = &uses[&(a, b)];
        match list.as_slice() {
            [(face, forward)] => {
                let (from, to) = if *forward { (a, b) } else { (b, a) };
                return Err(MeshError::OpenEdge {
                    from,
                    to,
                    face: *face,
                });
            }
            [(first, f1), (second, f2)] => {
                if f1 == f2 {
                    let (from, to) = if *f1 { (a, b) } else { (b, a) };
                    return Err(MeshError::InconsistentOrientation {
                        from,
                        to,
                        first: *first,
                        second: *second,
                    });
                }
            }
            _ => {
                return Err(MeshError::NonManifoldEdge {
                    a,
                    b,
                    faces: list.iter().map(|&(f, _)| f).collect(),
                });
            }
        }
    }
    Ok(())
}

/// Whether the points lie on one plane within a relative 1e-9 of the face's size (input written
/// with a few digits is rarely exactly coplanar).
fn is_planar(points: impl Iterator<Item = DVec3> + Clone) -> bool {
    let all: Vec<DVec3> = points.collect();
    if all.len() <= 3 {
        return true;
    }
    // Newell's normal is robust for any simple polygon.
    let mut normal = DVec3::ZERO;
    for k in 0..all.len() {
        let (p, q) = (all[k], all[(k + 1) % all.len()]);
        normal += DVec3::new(
            (p.y - q.y) * (p.z + q.z),
            (p.z - q.z) * (p.x + q.x),
            (p.x - q.x) * (p.y + q.y),
        );
    }
    let Some(unit) = normal.try_normalize() else {
        return true;
    };
    let centre = all.iter().sum::<DVec3>() / all.len() as f64;
    let size = all
        .iter()
        .map(|p| (*p - centre).length())
        .fold(0.0, f64::max);
    all.iter()
        .all(|p| (*p - centre).dot(unit).abs() <= 1e-9 * size)
}
