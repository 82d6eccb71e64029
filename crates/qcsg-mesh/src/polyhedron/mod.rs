//! OpenSCAD's `polyhedron(points, faces)` as a union of convex cells with disjoint interiors.
//!
//! OpenSCAD lists each face's points **clockwise seen from outside** (checked with OpenSCAD
//! 2021.01: a box given that way exports with outward normals and positive volume; the same box
//! with every face reversed exports inside out, silently). Here the mesh is first validated
//! ([`validate`]): indices in range, faces of at least three distinct points, every edge used
//! exactly twice in opposite directions. Faces are split into fans of triangles from their first
//! point (a non-planar face gets a warning, as OpenSCAD triangulates it too); the solid is the
//! set of points an odd number of triangles separates from infinity, which for a closed,
//! consistently oriented mesh is the enclosed solid whichever way the faces run. An inside-out
//! mesh (faces counter-clockwise seen from outside) gives the solid it encloses and a warning,
//! never its complement.
//!
//! The decomposition ([`bsp`]) partitions space by the triangles' own planes with axis-parallel
//! halving of regions of many faces ([`region`]), like the polygon's. **Exactness**: every cell
//! is bounded by planes through three input points (computed once per triangle, so neighbours
//! share the numbers) or axis-parallel walls shared by the regions on both sides.

pub(crate) mod boolean;
mod bsp;
mod region;
mod validate;

use std::fmt;

use glam::DVec3;

/// The half-space `normal · p ≤ offset` (the normal need not be unit length).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    /// The outward normal (not normalised).
    pub normal: DVec3,
    /// The offset: the half-space holds the points with `normal · p ≤ offset`.
    pub offset: f64,
}

impl Plane {
    /// The plane through `a`, `b`, `c`, the half-space on the side that `(b − a) × (c − a)`
    /// points away from: normal `(b − a) × (c − a)`, offset `normal · a`.
    pub fn through(a: DVec3, b: DVec3, c: DVec3) -> Self {
        let normal = (b - a).cross(c - a);
        Self {
            normal,
            offset: normal.dot(a),
        }
    }

    /// The closed complement across the same plane (the negation is exact).
    pub fn flipped(self) -> Self {
        Self {
            normal: -self.normal,
            offset: -self.offset,
        }
    }

    /// `normal · p − offset`: negative inside, positive outside, in units of `|normal|`.
    pub fn value(&self, p: DVec3) -> f64 {
        self.normal.dot(p) - self.offset
    }

    /// Whether `p` lies in the closed half-space.
    pub fn contains(&self, p: DVec3) -> bool {
        self.value(p) <= 0.0
    }
}

/// A convex cell: the intersection of its half-spaces; `min`/`max` is a box that contains it.
#[derive(Clone, Debug, PartialEq)]
pub struct Cell3 {
    /// The half-spaces whose intersection is the cell (at most about eight).
    pub planes: Vec<Plane>,
    /// The lower corner of a box containing the cell.
    pub min: DVec3,
    /// The upper corner of a box containing the cell.
    pub max: DVec3,
}

impl Cell3 {
    /// Whether `p` lies in the closed cell.
    pub fn contains(&self, p: DVec3) -> bool {
        self.planes.iter().all(|h| h.contains(p))
    }
}

/// A polygon mesh: points and faces listing point indices (OpenSCAD's order: clockwise seen from
/// outside).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// The vertices.
    pub points: Vec<DVec3>,
    /// The faces, each a cycle of indices into `points`.
    pub faces: Vec<Vec<usize>>,
}

/// Limits on a mesh's size, so that hostile input is refused instead of exhausting memory.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MeshLimits {
    /// The most points (default 10,000,000).
    pub max_points: usize,
    /// The most face entries (indices in all faces together), which bounds the triangles
    /// (default 30,000,000, ten million triangles).
    pub max_face_entries: usize,
}

impl Default for MeshLimits {
    fn default() -> Self {
        Self {
            max_points: 10_000_000,
            max_face_entries: 30_000_000,
        }
    }
}

/// A polyhedron's solid as a union of convex cells with disjoint interiors.
#[derive(Clone, Debug, PartialEq)]
pub struct Polyhedron {
    /// The cells; empty for an empty solid.
    pub cells: Vec<Cell3>,
    /// Things worth telling the user that do not stop the polyhedron (non-planar faces, an
    /// inside-out mesh).
    pub warnings: Vec<String>,
    /// The lower corner of a box containing every cell (zero for an empty solid).
    pub min: DVec3,
    /// The upper corner of a box containing every cell (zero for an empty solid).
    pub max: DVec3,
}

impl Polyhedron {
    /// Whether `p` lies in some cell (a linear scan: for tests and small meshes).
    pub fn contains(&self, p: DVec3) -> bool {
        self.cells.iter().any(|c| c.contains(p))
    }
}

/// The largest coordinate magnitude accepted in a mesh: beyond it the exact predicates' triple
/// products could overflow.
pub const MAX_MESH_COORDINATE: f64 = 1e60;

/// Why a mesh was refused.
#[derive(Clone, Debug, PartialEq)]
pub enum MeshError {
    /// A point has a NaN or infinite coordinate.
    NonFinitePoint {
        /// The point's index.
        index: usize,
    },
    /// A point's coordinate exceeds [`MAX_MESH_COORDINATE`] in magnitude.
    HugeCoordinate {
        /// The point's index.
        index: usize,
        /// The offending coordinate.
        value: f64,
    },
    /// A face refers to a point that does not exist.
    IndexOutOfRange {
        /// The face's index.
        face: usize,
        /// The entry's position in the face.
        position: usize,
        /// The index given.
        index: usize,
        /// How many points there are.
        points: usize,
    },
    /// A face has fewer than three distinct points.
    DegenerateFace {
        /// The face's index.
        face: usize,
    },
    /// An edge is used by one face only.
    OpenEdge {
        /// The edge's first point, as the face runs.
        from: usize,
        /// The edge's second point.
        to: usize,
        /// The face using it.
        face: usize,
    },
    /// An edge is used by more than two faces.
    NonManifoldEdge {
        /// The edge's lower point index.
        a: usize,
        /// The edge's higher point index.
        b: usize,
        /// The faces using it.
        faces: Vec<usize>,
    },
    /// Two faces run along a shared edge in the same direction.
    InconsistentOrientation {
        /// The edge's first point, as both faces run.
        from: usize,
        /// The edge's second point.
        to: usize,
        /// The first face.
        first: usize,
        /// The second face.
        second: usize,
    },
    /// More points or face entries than the [`MeshLimits`] allow.
    TooLarge {
        /// What was counted ("points", "face entries").
        what: &'static str,
        /// How many were given.
        count: usize,
        /// The limit.
        limit: usize,
    },
}

impl fmt::Display for MeshError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NonFinitePoint { index } => write!(
                f,
                "point {index} of the mesh has a coordinate that is not a finite number"
            ),
            Self::HugeCoordinate { index, value } => write!(
                f,
                "point {index} of the mesh has the coordinate {value:e}, beyond the supported magnitude {MAX_MESH_COORDINATE:e}"
            ),
            Self::IndexOutOfRange {
                face,
                position,
                index,
                points,
            } => write!(
                f,
                "entry {position} of face {face} refers to point {index}, but the mesh has {points} points"
            ),
            Self::DegenerateFace { face } => {
                write!(f, "face {face} has fewer than three distinct points")
            }
            Self::OpenEdge { from, to, face } => write!(
                f,
                "open mesh: edge ({from}, {to}) of face {face} has no neighbour (every edge must be shared by exactly two faces)"
            ),
            Self::NonManifoldEdge { a, b, faces } => write!(
                f,
                "non-manifold edge ({a}, {b}): it is shared by {} faces ({}), not two",
                faces.len(),
                faces
                    .iter()
                    .map(usize::to_string)
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
            Self::InconsistentOrientation {
                from,
                to,
                first,
                second,
            } => write!(
                f,
                "faces {first} and {second} are oriented inconsistently: both run along edge ({from}, {to}) in the same direction (list every face clockwise seen from outside)"
            ),
            Self::TooLarge { what, count, limit } => {
                write!(
                    f,
                    "the mesh has {count} {what}, more than the limit of {limit}"
                )
            }
        }
    }
}

impl std::error::Error for MeshError {}

/// One triangle of a face's fan, with its plane.
#[derive(Clone, Copy, Debug)]
struct Triangle {
    corners: [DVec3; 3],
    plane: Plane,
}

/// OpenSCAD's `polyhedron(points, faces)`: the closed solid the faces bound, validated, as convex
/// cells with disjoint interiors.
pub fn polyhedron_cells(mesh: &Mesh, limits: &MeshLimits) -> Result<Polyhedron, MeshError> {
    let checked = validate::validate(mesh, limits)?;
    let cells = bsp::decompose(&checked.triangles);
    let (min, max) = if cells.is_empty() {
        (DVec3::ZERO, DVec3::ZERO)
    } else {
        cells.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), c| (lo.min(c.min), hi.max(c.max)),
        )
    };
    Ok(Polyhedron {
        cells,
        warnings: checked.warnings,
        min,
        max,
    })
}
