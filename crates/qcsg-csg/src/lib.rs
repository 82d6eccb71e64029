//! The scene IR of qcsg: the transformed CSG DAG and its disjunctive normal form.
//!
//! The evaluator builds a [`Dag`] through its builder API: leaves are single quadrics in their
//! primitive's local frame, inner nodes are union / intersection / difference / complement plus
//! colour and highlight wrappers, and 4×4 transforms sit on the edges. Equal sub-solids are
//! hash-consed into one node. Boxes ([`Aabb`]) that may be infinite per axis bound nodes and
//! are propagated conservatively through transforms.
//!
//! This crate never depends on the front end: diagnostics point at sources through
//! [`qcsg_diag::FileId`] and [`qcsg_diag::Span`] only.

pub mod bounds;
pub mod codes;
pub mod dag;
pub mod quadric_box;

pub use bounds::Aabb;
pub use dag::{Dag, DagError, Edge, Node, NodeId, NodeKind, Rgba, Source, TransformId};
