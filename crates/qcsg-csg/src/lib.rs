//! The scene IR of qcsg: the transformed CSG DAG and its disjunctive normal form.
//!
//! The evaluator builds a [`Dag`] through its builder API: leaves are single quadrics in their
//! primitive's local frame, inner nodes are union / intersection / difference / complement plus
//! colour and highlight wrappers, and 4×4 transforms sit on the edges. Equal sub-solids are
//! hash-consed into one node. Boxes ([`Aabb`]) that may be infinite per axis bound nodes and
//! are propagated conservatively through transforms.
//!
//! [`build_dnf`] turns the DAG into a [`Dnf`] (a union of intersections of world-space
//! quadrics) with per-term boxes, pruning as it goes and in passes afterwards ([`prune`]), and
//! decides which of its quadrics are the same surface ([`coincident`]);
//! [`json`] and [`text`] write both forms; [`unpruned_size`] counts what the DNF would be
//! without any pruning.
//!
//! ```
//! use qcsg_csg::{Aabb, Dag, DnfOptions, Source, build_dnf, dnf_to_json, names_from_list};
//! use qcsg_quadric::{DVec3, Quadric};
//!
//! let mut dag = Dag::new();
//! let at = Source::default(); // the script's FileId and byte Span in real use
//! // cube(2): three slabs, and the box the cube knows.
//! let slabs: Vec<_> = [DVec3::X, DVec3::Y, DVec3::Z]
//!     .into_iter()
//!     .map(|n| dag.leaf(Quadric::slab(DVec3::ONE, n, 1.0).unwrap(), at).into())
//!     .collect();
//! let cube = dag.intersection(slabs, at);
//! let cube = dag.bounded(cube, Aabb::new(DVec3::ZERO, DVec3::splat(2.0)));
//! // translate([2, 2, 2]) sphere(1.2), subtracted.
//! let ball = dag.leaf(Quadric::sphere(DVec3::ZERO, 1.2).unwrap(), at);
//! let ball = dag.translated(ball.into(), DVec3::splat(2.0)).unwrap();
//! let solid = dag.difference([cube.into(), ball], at);
//! dag.set_root(solid.into());
//!
//! let dnf = build_dnf(&dag, &DnfOptions::default()).unwrap();
//! assert_eq!(dnf.terms.len(), 1); // slabs ∩ ¬sphere
//! assert!(dnf.contains(DVec3::splat(0.5)) && !dnf.contains(DVec3::splat(1.9)));
//! let names = vec!["main.qcsg".to_string()];
//! let json = dnf_to_json(&dnf, &names_from_list(&names));
//! assert!(json.contains("\"terms\""));
//! ```
//!
//! This crate never depends on the front end: diagnostics point at sources through
//! [`qcsg_diag::FileId`] and [`qcsg_diag::Span`] only.

pub mod bounds;
pub mod box_index;
pub mod codes;
pub mod coincident;
pub mod dag;
pub mod dnf;
pub mod json;
pub mod layers;
pub mod polyhedron;
pub mod prune;
pub mod quadric_box;
pub mod stats;
pub mod text;
pub mod unpruned;

pub use bounds::Aabb;
pub use box_index::BoxIndex;
pub use coincident::{Rounding, Sheet, Surface, Surfaces, find_surfaces};
pub use dag::{Dag, DagError, Edge, Node, NodeId, NodeKind, Rgba, Source, TransformId};
pub use dnf::{DEFAULT_TERM_LIMIT, Dnf, DnfOptions, DnfQuadric, Term, build_dnf, build_dnf_of};
pub use json::{dag_to_json, dnf_to_json, names_from_list};
pub use layers::{Layers, build_layers};
pub use stats::DnfStats;
pub use text::{byte_locator, dag_to_text, dnf_to_text, line_locator};
pub use unpruned::{DnfSize, unpruned_size};
