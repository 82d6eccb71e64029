//! OpenSCAD's `polygon(points, paths)` as a union of convex cells with disjoint interiors.
//!
//! OpenSCAD 2021.01 fills every polygon with the **even–odd rule** over all of its paths
//! together, whatever their orientation (checked with its SVG export): a path inside another is a
//! hole, two overlapping squares keep only what one of them covers, the same square given twice is
//! empty, a bow-tie is its two triangles and a pentagram loses its central pentagon.
//!
//! The decomposition ([`bsp`]) partitions the plane by the edges' own lines, in a pseudo-random
//! order, halving any region of more than a few sides by an axis-parallel line, until no edge
//! passes through a region ([`region`]); each region is then wholly inside or outside, by the
//! even–odd parity of its reference point. Parities travel down the partition along segments
//! between reference points, so each crossing test looks only at the edges of one region. On
//! ordinary outlines (circles, stars with long thin spikes, combs, many holes) this gives O(n)
//! cells of at most about six half-planes in O(n log n) time.
//!
//! **Exactness.** Every cell is an intersection of half-planes, each either the line through the
//! two input points of an edge ([`HalfPlane::left_of`], computed once per edge so every cell that
//! uses it holds the same numbers) or an axis-parallel wall of the partition, shared
//! bit-for-bit by the regions on both sides. So the boundary of the union lies on the input edges' lines, never on
//! a rounded intersection point; the pieces' vertices are rounded only to decide which side of a
//! line a piece lies on and where to put its bounding box. A piece thinner than the rounding of
//! that decision (about 1e-14 of the coordinates' magnitude) is not cut and is classified with
//! its neighbour.

mod bsp;
mod region;

pub mod curved;

use std::fmt;

use glam::DVec2;

/// The half-plane `normal · p ≤ offset`.
///
/// The normal need not be unit length: for an edge it is computed from the exact input points
/// (see [`HalfPlane::left_of`]), so neighbouring cells that share the edge's line share the same
/// numbers exactly.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HalfPlane {
    /// The outward normal (not normalised).
    pub normal: DVec2,
    /// The offset: the half-plane holds the points with `normal · p ≤ offset`.
    pub offset: f64,
}

impl HalfPlane {
    /// The closed half-plane to the left of the directed line from `a` through `b` (the inside of
    /// a counter-clockwise outline): normal `(b.y − a.y, a.x − b.x)`, offset `normal · a`.
    pub fn left_of(a: DVec2, b: DVec2) -> Self {
        let normal = DVec2::new(b.y - a.y, a.x - b.x);
        Self {
            normal,
            offset: normal.dot(a),
        }
    }

    /// The closed complement across the same line (the negation is exact).
    pub fn flipped(self) -> Self {
        Self {
            normal: -self.normal,
            offset: -self.offset,
        }
    }

    /// `normal · p − offset`: negative inside, positive outside, in units of `|normal|`.
    pub fn value(&self, p: DVec2) -> f64 {
        self.normal.dot(p) - self.offset
    }

    /// Whether `p` lies in the closed half-plane.
    pub fn contains(&self, p: DVec2) -> bool {
        self.value(p) <= 0.0
    }
}

/// A convex cell: the intersection of its half-planes. `min`/`max` is a box that contains it
/// (slightly enlarged beyond the rounded corners, never smaller than the cell).
#[derive(Clone, Debug, PartialEq)]
pub struct Cell2 {
    /// The half-planes whose intersection is the cell (a handful: the decomposition keeps only
    /// those that bound it).
    pub half_planes: Vec<HalfPlane>,
    /// The lower corner of a box containing the cell.
    pub min: DVec2,
    /// The upper corner of a box containing the cell.
    pub max: DVec2,
}

impl Cell2 {
    /// Whether `p` lies in the closed cell.
    pub fn contains(&self, p: DVec2) -> bool {
        self.half_planes.iter().all(|h| h.contains(p))
    }
}

/// Limits on a polygon's size, so that hostile input is refused instead of exhausting memory.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PolygonLimits {
    /// The most points, and the most path entries in all paths together (default 1,000,000).
    pub max_points: usize,
}

impl Default for PolygonLimits {
    fn default() -> Self {
        Self {
            max_points: 1_000_000,
        }
    }
}

/// A polygon's region as a union of convex cells with disjoint interiors.
#[derive(Clone, Debug, PartialEq)]
pub struct Polygon {
    /// The cells; empty for an empty region.
    pub cells: Vec<Cell2>,
    /// Things worth telling the user that do not stop the polygon (a self-crossing outline, a
    /// path too short to enclose anything).
    pub warnings: Vec<String>,
    /// The lower corner of a box containing every cell (zero for an empty region).
    pub min: DVec2,
    /// The upper corner of a box containing every cell (zero for an empty region).
    pub max: DVec2,
}

impl Polygon {
    /// Whether `p` lies in some cell (a linear scan: for tests and small polygons).
    pub fn contains(&self, p: DVec2) -> bool {
        self.cells.iter().any(|c| c.contains(p))
    }
}

/// Why a polygon was refused.
#[derive(Clone, Debug, PartialEq)]
pub enum PolygonError {
    /// A point has a NaN or infinite coordinate.
    NonFinitePoint {
        /// The point's index in `points`.
        index: usize,
    },
    /// A point's coordinate exceeds [`MAX_COORDINATE`] in magnitude.
    HugeCoordinate {
        /// The point's index in `points`.
        index: usize,
        /// The offending coordinate.
        value: f64,
    },
    /// A path refers to a point that does not exist.
    IndexOutOfRange {
        /// The path's index in `paths`.
        path: usize,
        /// The entry's position in that path.
        position: usize,
        /// The index given.
        index: usize,
        /// How many points there are.
        points: usize,
    },
    /// More points or path entries than [`PolygonLimits::max_points`].
    TooManyPoints {
        /// How many were given.
        count: usize,
        /// The limit.
        limit: usize,
    },
}

/// The largest coordinate magnitude accepted: beyond it the exact predicates' products could
/// overflow.
pub const MAX_COORDINATE: f64 = 1e100;

impl fmt::Display for PolygonError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NonFinitePoint { index } => {
                write!(
                    f,
                    "point {index} of the polygon has a coordinate that is not a finite number"
                )
            }
            Self::HugeCoordinate { index, value } => write!(
                f,
                "point {index} of the polygon has the coordinate {value:e}, beyond the supported magnitude {MAX_COORDINATE:e}"
            ),
            Self::IndexOutOfRange {
                path,
                position,
                index,
                points,
            } => write!(
                f,
                "entry {position} of path {path} refers to point {index}, but the polygon has {points} points (indices 0 to {})",
                points.saturating_sub(1)
            ),
            Self::TooManyPoints { count, limit } => write!(
                f,
                "the polygon has {count} points or path entries, more than the limit of {limit}"
            ),
        }
    }
}

impl std::error::Error for PolygonError {}

/// One edge of an outline, with the line it lies on.
#[derive(Clone, Copy, Debug)]
struct Edge {
    a: DVec2,
    b: DVec2,
    /// The half-plane left of `a → b`, computed once so every cell using it shares it exactly.
    line: HalfPlane,
    /// The path and the entry where the edge starts (for warnings).
    path: usize,
    position: usize,
}

/// OpenSCAD's `polygon(points, paths)`: the region its paths enclose under the even–odd rule, as
/// a union of convex cells with disjoint interiors.
///
/// Without `paths` the points form one outline in order. Each path is closed (its last point
/// joins its first). Repeated points and zero-length edges are harmless; a path with fewer than
/// three distinct points encloses nothing (a warning says so); a zero-area polygon gives no cells.
/// Errors name the offending point or path entry.
pub fn polygon_cells(
    points: &[DVec2],
    paths: Option<&[Vec<usize>]>,
    limits: &PolygonLimits,
) -> Result<Polygon, PolygonError> {
    if points.len() > limits.max_points {
        return Err(PolygonError::TooManyPoints {
            count: points.len(),
            limit: limits.max_points,
        });
    }
    for (index, p) in points.iter().enumerate() {
        if !p.is_finite() {
            return Err(PolygonError::NonFinitePoint { index });
        }
        for value in [p.x, p.y] {
            if value.abs() > MAX_COORDINATE {
                return Err(PolygonError::HugeCoordinate { index, value });
            }
        }
    }
    let mut warnings = Vec::new();
    let edges = match paths {
        None => {
            let all: Vec<usize> = (0..points.len()).collect();
            path_edges(points, &[all], &mut warnings)
        }
        Some(paths) => {
            let entries: usize = paths.iter().map(Vec::len).sum();
            if entries > limits.max_points {
                return Err(PolygonError::TooManyPoints {
                    count: entries,
                    limit: limits.max_points,
                });
            }
            for (path, indices) in paths.iter().enumerate() {
                for (position, &index) in indices.iter().enumerate() {
                    if index >= points.len() {
                        return Err(PolygonError::IndexOutOfRange {
                            path,
                            position,
                            index,
                            points: points.len(),
                        });
                    }
                }
            }
            path_edges(points, paths, &mut warnings)
        }
    };
    let (cells, crossing) = bsp::decompose(&edges);
    if let Some((first, second)) = crossing {
        let (e, f) = (edges[first], edges[second]);
        warnings.push(format!(
            "the outline crosses itself: the edge from entry {} of path {} and the edge from entry {} of path {} cross; the region is filled with the even–odd rule, as OpenSCAD does",
            e.position, e.path, f.position, f.path
        ));
    }
    let (min, max) = bounds(&cells);
    Ok(Polygon {
        cells,
        warnings,
        min,
        max,
    })
}

/// The non-degenerate edges of closed paths over validated indices.
fn path_edges(points: &[DVec2], paths: &[Vec<usize>], warnings: &mut Vec<String>) -> Vec<Edge> {
    let mut edges = Vec::new();
    for (path, indices) in paths.iter().enumerate() {
        let start = edges.len();
        for (position, &i) in indices.iter().enumerate() {
            let j = indices[(position + 1) % indices.len()];
            let (a, b) = (points[i], points[j]);
            if a != b {
                edges.push(Edge {
                    a,
                    b,
                    line: HalfPlane::left_of(a, b),
                    path,
                    position,
                });
            }
        }
        // Fewer than three distinct points: at most a segment travelled there and back.
        let distinct = {
            let mut seen: Vec<DVec2> = Vec::new();
            for &i in indices {
                if seen.len() < 3 && !seen.contains(&points[i]) {
                    seen.push(points[i]);
                }
            }
            seen.len()
        };
        if distinct < 3 {
            edges.truncate(start);
            warnings.push(format!(
                "path {path} has fewer than three distinct points and encloses nothing"
            ));
        }
    }
    edges
}

/// The box containing every cell's box.
fn bounds(cells: &[Cell2]) -> (DVec2, DVec2) {
    if cells.is_empty() {
        return (DVec2::ZERO, DVec2::ZERO);
    }
    cells.iter().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(min, max), c| (min.min(c.min), max.max(c.max)),
    )
}
