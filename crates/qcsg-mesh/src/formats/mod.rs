//! Readers of mesh files (STL, OFF, 3MF) into [`Mesh`](crate::Mesh)es in OpenSCAD's face
//! order, and of DXF drawings into a [`Drawing`].
//!
//! STL, OFF and 3MF list faces counter-clockwise seen from outside; the readers reverse them so
//! every [`Mesh`](crate::Mesh) is clockwise seen from outside, as `polyhedron` expects. Errors are
//! values with the line (text) or record (binary) where reading stopped; sizes are bounded by
//! [`ReadLimits`] so a hostile file cannot exhaust memory.

mod dxf;
mod off;
mod stl;
mod threemf;

use std::collections::HashMap;
use std::fmt;

use glam::DVec3;

pub use dxf::{
    Arc, Dimension, Drawing, DrawingCircle, DrawingCurve, DrawingEllipse, DrawingLimits,
    DrawingOptions, DrawingPath, DrawingWarning, Edge, EllipticArc, read_dxf,
};
pub use off::read_off;
pub use stl::read_stl;
pub use threemf::read_3mf;

/// Limits on what a file may hold.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ReadLimits {
    /// The most triangles (or faces) read (default 10,000,000).
    pub max_triangles: usize,
    /// The most vertices read (default 10,000,000).
    pub max_vertices: usize,
}

impl Default for ReadLimits {
    fn default() -> Self {
        Self {
            max_triangles: 10_000_000,
            max_vertices: 10_000_000,
        }
    }
}

/// Why a file could not be read.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ReadError {
    /// The format being read ("STL", "OFF").
    pub format: &'static str,
    /// Where reading stopped: "line 12", "triangle 3", "the header".
    pub location: String,
    /// What was wrong there.
    pub message: String,
}

impl ReadError {
    pub(crate) fn new(
        format: &'static str,
        location: impl Into<String>,
        message: impl Into<String>,
    ) -> Self {
        Self {
            format,
            location: location.into(),
            message: message.into(),
        }
    }
}

impl fmt::Display for ReadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} file, {}: {}",
            self.format, self.location, self.message
        )
    }
}

impl std::error::Error for ReadError {}

/// Merges exactly equal vertices (−0 and 0 are one) into indices.
#[derive(Default)]
pub(crate) struct VertexMerger {
    points: Vec<DVec3>,
    index: HashMap<[u64; 3], usize>,
}

impl VertexMerger {
    pub(crate) fn index_of(&mut self, p: DVec3) -> usize {
        let key = [p.x, p.y, p.z].map(|v| if v == 0.0 { 0u64 } else { v.to_bits() });
        let next = self.points.len();
        *self.index.entry(key).or_insert_with(|| {
            self.points.push(p);
            next
        })
    }

    pub(crate) fn into_points(self) -> Vec<DVec3> {
        self.points
    }
}
