//! The scene IR of qcsg: the transformed CSG DAG and its disjunctive normal form.
//!
//! The evaluator builds a [`Dag`] through its builder API: leaves are single quadrics in their
//! primitive's local frame, inner nodes are union / intersection / difference / complement plus
//! colour and highlight wrappers, and 4×4 transforms sit on the edges. Equal sub-solids are
//! hash-consed into one node. Boxes ([`Aabb`]) that may be infinite per axis bound nodes and
//! are propagated conservatively through transforms.
//!
//! [`build_dnf`] turns the DAG into a [`Dnf`] (a union of intersections of world-space
//! quadrics) with per-term boxes, pruning as it goes and in passes afterwards ([`prune`]);
//! [`json`] and [`text`] write both forms.
//!
//! This crate never depends on the front end: diagnostics point at sources through
//! [`qcsg_diag::FileId`] and [`qcsg_diag::Span`] only.

pub mod bounds;
pub mod codes;
pub mod dag;
pub mod dnf;
pub mod json;
pub mod polyhedron;
pub mod prune;
pub mod quadric_box;
pub mod stats;
pub mod text;

pub use bounds::Aabb;
pub use dag::{Dag, DagError, Edge, Node, NodeId, NodeKind, Rgba, Source, TransformId};
pub use dnf::{DEFAULT_TERM_LIMIT, Dnf, DnfOptions, DnfQuadric, Term, build_dnf, build_dnf_of};
pub use json::{dag_to_json, dnf_to_json, names_from_list};
pub use stats::DnfStats;
pub use text::{byte_locator, dag_to_text, dnf_to_text, line_locator};
