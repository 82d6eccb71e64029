//! What qcsg's tests share, so that each exists once:
//!
//! - [`Rng`]: a small deterministic generator (SplitMix64) with the draws tests need (points in
//!   a box, directions, rotations, similarities);
//! - [`FLUSH_PAIRS`]: solids written with surfaces shared by their parts and without, which
//!   every consumer of the DNF must show alike;
//! - [`annotations`]: the language suite's inline expectations, parsed and matched against a
//!   check's diagnostics;
//! - [`dxf`]: DXF drawings of lines, arcs, circles and ellipses, written for the readers' tests;
//! - [`MemoryFiles`]: files from memory for `include` / `use`, as an editor's unsaved buffers;
//! - [`TriangleMesh`]: a triangle mesh read from STL with an exact-enough membership oracle
//!   (the generalised winding number) and distances to it;
//! - [`openscad`]: OpenSCAD 2021.01 as the oracle of meaning — its STL export of a scene, cached
//!   by content;
//! - [`cpu`]: a process's CPU time, which benchmarks on a shared machine compare;
//! - [`cli`]: the end-to-end tests' runner of a binary (input, captured output, a deadline, a
//!   capped address space);
//! - [`reference`]: points on a DNF's surface and on its feature curves, found by exact
//!   line-quadric intersections and membership alone: the oracle of coverage and distance that
//!   the sampler's tests and the benchmarks measure against.
//!
//! It is a dependency of tests and benchmarks only; nothing in the product depends on it.

pub mod annotations;
pub mod cli;
pub mod cpu;
pub mod dxf;
mod files;
mod flush;
mod mesh;
pub mod openscad;
pub mod reference;
mod rng;

pub use files::MemoryFiles;
pub use flush::{FLUSH_PAIRS, FlushPair};
pub use mesh::TriangleMesh;
pub use rng::Rng;
