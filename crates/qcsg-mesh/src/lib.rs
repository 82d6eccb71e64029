//! Exact polygons and polyhedra as unions of convex cells, for qcsg's 2-D shapes and meshes.
//!
//! qcsg's solids are booleans of quadric half-spaces, so OpenSCAD's `polygon` becomes a union of
//! convex cells, each an intersection of a few half-planes whose lines pass through input points
//! ([`polygon_cells`]), and `polyhedron` a union of convex cells of half-spaces whose planes pass
//! through three input points ([`polyhedron_cells`]). The crate knows nothing of the rest of qcsg: the evaluator turns cells into
//! solids.
//! It also reads STL, OFF and 3MF meshes ([`read_stl`], [`read_off`], [`read_3mf`]) into
//! [`Mesh`]es, and DXF drawings ([`read_dxf`]) into a [`Drawing`] of exact paths, arcs and circles, whose even–odd
//! region [`drawing_region`] builds from cells, discs and circular segments, and computes exact
//! convex hulls of point sets ([`convex_hull`], [`convex_hull_2d`]). [`boolean_cells`] cuts any
//! boolean of half-spaces, or its complement, within a box into convex cells.
//! [`closest_point_on_triangle`] is the distance query that checks of meshes are built on.

mod closest;
mod drawing;
mod exact;
mod formats;
mod hull;
mod polygon;
mod polyhedron;

pub use closest::closest_point_on_triangle;
pub use drawing::{CurvedPiece, DrawingRegion, Op, RegionError, Step, drawing_region};
pub use formats::{
    Arc, Dimension, Drawing, DrawingCircle, DrawingCurve, DrawingEllipse, DrawingLimits,
    DrawingOptions, DrawingPath, DrawingWarning, Edge, EllipticArc, ReadError, ReadLimits,
    read_3mf, read_dxf, read_off, read_stl,
};
pub use hull::{ConvexHull, HullError, HullFace, convex_hull, convex_hull_2d};
pub use polygon::curved;
pub use polygon::{
    Cell2, HalfPlane, MAX_COORDINATE, Polygon, PolygonError, PolygonLimits, polygon_cells,
};
pub use polyhedron::boolean::{
    BooleanError, BooleanLimits, Bounds, ExprKind, ExprNode, HalfSpaceExpr, boolean_cells,
};
pub use polyhedron::{
    Cell3, MAX_MESH_COORDINATE, Mesh, MeshError, MeshLimits, Plane, Polyhedron, polyhedron_cells,
};
