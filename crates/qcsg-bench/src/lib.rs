//! Measurements of qcsg, shared by the stability suite (`tests/stability.rs` over
//! `tests/stability/*.qcsg` at the repository root) and the report binary (`qcsg-bench`, which
//! writes `docs/report.md`).
//!
//! - [`pipeline`]: source text to the DNF, as `qcsg` does it, keeping every diagnostic;
//! - [`reference`](mod@reference): reference points on the exact CSG surface by ray casting the DNF,
//!   independently of the sampler;
//! - [`metrics`]: coverage error (k-d trees of samples per quadric), on-surface error, samples
//!   off the CSG surface, non-finite output;
//! - [`measure`]: one timed sampling with all its errors;
//! - [`image`]: the ray tracer's frame and a CPU model of splat rendering to compare with it;
//! - [`bumpy`]: closed non-convex test meshes of a chosen triangle count, as binary STL;
//! - [`crease`]: the point of a feature curve nearest to a point, for meshes' distances;
//! - [`mesh`]: STL meshes of a mesh-based peer and their Hausdorff distance to the exact surface;
//! - [`openscad`]: OpenSCAD's CGAL export, the mesh-based peer, run when installed;
//! - [`python_peer`]: the Python peers, Manifold and build123d (OpenCascade), run when installed;
//! - [`shape`]: one CSG tree as OpenSCAD text and as the Python peers' JSON; the scaling families;
//! - [`plot`]: log-log SVG plots and power-law fits for the report;
//! - [`stability`]: the stability cases' header format (`// expect: …`) and running one case.

pub mod bumpy;
pub mod crease;
pub mod image;
pub mod measure;
pub mod mesh;
pub mod metrics;
pub mod openscad;
pub mod pipeline;
pub mod plot;
pub mod python_peer;
pub mod reference;
pub mod shape;
pub mod stability;
