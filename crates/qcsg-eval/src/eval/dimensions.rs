//! The dimension of every evaluated object (2-D shape or 3-D solid) and its box, and OpenSCAD's
//! rules for objects of the other dimension.
//!
//! A 2-D shape is a z-invariant solid (see [`crate::planar`]); its leaves are marked when a 2-D
//! primitive builds them, and a node's dimension is that of its first non-empty child. Both are
//! kept in tables beside the DAG's arena and brought up to date, in arena order (children come
//! first), whenever they are asked for, so each node is looked at once.
//!
//! OpenSCAD 2021.01 decides the dimension of a group or boolean by its first non-empty child and
//! ignores children of the other dimension with a warning ("Mixing 2D and 3D objects is not
//! supported"); [`Evaluator::same_dimension`] does the same, warning at each ignored child. A
//! 2-D shape at the top level is no solid: OpenSCAD's preview draws it as a plate 1 unit thick
//! centred on z = 0 and its STL export refuses it; qcsg makes it that plate, with a warning
//! ([`Evaluator::top_level_plate`]).

use glam::DVec3;
use qcsg_csg::{Aabb, Edge, NodeId, NodeKind, Source};
use qcsg_quadric::Quadric;

use crate::codes;

use super::Evaluator;

/// What kind of object a DAG node is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Dim {
    /// The empty object, which mixes with either kind.
    Empty,
    /// A 2-D shape (a z-invariant solid).
    Two,
    /// A 3-D solid.
    Three,
}

/// Half the thickness of the plate a top-level 2-D shape becomes.
const PLATE_HALF_THICKNESS: f64 = 0.5;

impl<'a> Evaluator<'a> {
    /// Marks the leaves created since the arena had `from` nodes, and `node`, as parts of a 2-D
    /// shape. Call it right after building a 2-D primitive.
    pub(super) fn mark_planar(&mut self, from: usize, node: NodeId) {
        for (i, n) in self.dag.nodes().iter().enumerate().skip(from) {
            if matches!(n.kind, NodeKind::Leaf(_)) {
                self.planar_leaves.insert(NodeId(i as u32));
            } else {
                // A leaf the shape shares with an earlier solid (hash-consed: a mesh's vertical
                // wall is a half-plane) keeps that solid's dimension, so the new inner nodes
                // are marked themselves.
                self.planar_nodes.insert(NodeId(i as u32));
            }
        }
        if matches!(
            self.dag.node(node).map(|n| &n.kind),
            Some(NodeKind::Leaf(_))
        ) {
            self.planar_leaves.insert(node);
        }
    }

    /// Brings the dimension and box tables up to the arena's length.
    fn sync_nodes(&mut self) {
        for i in self.node_dims.len()..self.dag.len() {
            let node = &self.dag.nodes()[i];
            let child_dim = |e: &Edge, dims: &[Dim]| {
                dims.get(e.child.0 as usize).copied().unwrap_or(Dim::Empty)
            };
            let child_box = |e: &Edge, boxes: &[Aabb]| {
                boxes
                    .get(e.child.0 as usize)
                    .copied()
                    .unwrap_or(Aabb::EVERYTHING)
                    .transformed(&self.dag.matrix(e.transform))
            };
            let (dim, computed) = match &node.kind {
                NodeKind::Leaf(q) => {
                    let dim = if self.planar_leaves.contains(&NodeId(i as u32)) {
                        Dim::Two
                    } else {
                        Dim::Three
                    };
                    (dim, qcsg_csg::quadric_box::solid_bounds(q))
                }
                NodeKind::Union(c) => (
                    first_dim(c.iter().map(|e| child_dim(e, &self.node_dims))),
                    c.iter().fold(Aabb::EMPTY, |acc, e| {
                        acc.union(&child_box(e, &self.node_boxes))
                    }),
                ),
                NodeKind::Intersection(c) => (
                    first_dim(c.iter().map(|e| child_dim(e, &self.node_dims))),
                    c.iter().fold(Aabb::EVERYTHING, |acc, e| {
                        acc.intersection(&child_box(e, &self.node_boxes))
                    }),
                ),
                NodeKind::Difference(c) => (
                    first_dim(c.iter().map(|e| child_dim(e, &self.node_dims))),
                    c.first()
                        .map_or(Aabb::EMPTY, |e| child_box(e, &self.node_boxes)),
                ),
                NodeKind::Complement(e) => (child_dim(e, &self.node_dims), Aabb::EVERYTHING),
                NodeKind::Color(_, e) | NodeKind::Highlight(e) => (
                    child_dim(e, &self.node_dims),
                    child_box(e, &self.node_boxes),
                ),
            };
            let dim = if self.extruded.contains(&NodeId(i as u32)) {
                Dim::Three
            } else if self.planar_nodes.contains(&NodeId(i as u32)) {
                Dim::Two
            } else {
                dim
            };
            let declared = node.bounds.unwrap_or(Aabb::EVERYTHING);
            self.node_dims.push(dim);
            self.node_boxes.push(computed.intersection(&declared));
        }
    }

    /// The dimension of the object behind `edge`.
    pub(crate) fn dim(&mut self, edge: Edge) -> Dim {
        self.sync_nodes();
        self.node_dims
            .get(edge.child.0 as usize)
            .copied()
            .unwrap_or(Dim::Empty)
    }

    /// A box, in the frame of the edge's parent, containing the object behind `edge` (infinite
    /// along z for a 2-D shape).
    pub(crate) fn edge_box(&mut self, edge: Edge) -> Aabb {
        self.sync_nodes();
        self.node_boxes
            .get(edge.child.0 as usize)
            .copied()
            .unwrap_or(Aabb::EVERYTHING)
            .transformed(&self.dag.matrix(edge.transform))
    }

    /// The objects of `edges` of the dimension of the first non-empty one, with a warning at
    /// each object of the other dimension, which is left out (as OpenSCAD does); and that
    /// dimension.
    pub(crate) fn same_dimension(&mut self, edges: Vec<Edge>) -> (Vec<Edge>, Dim) {
        let dims: Vec<Dim> = edges.iter().map(|e| self.dim(*e)).collect();
        let dim = first_dim(dims.iter().copied());
        self.keep(edges, dims, dim)
    }

    /// The objects of `edges` of dimension `dim` (an operation on 2-D shapes, say), with a
    /// warning at each of the other dimension, which is left out.
    pub(crate) fn keep_dimension(&mut self, edges: Vec<Edge>, dim: Dim) -> (Vec<Edge>, Dim) {
        let dims: Vec<Dim> = edges.iter().map(|e| self.dim(*e)).collect();
        self.keep(edges, dims, dim)
    }

    fn keep(&mut self, edges: Vec<Edge>, dims: Vec<Dim>, dim: Dim) -> (Vec<Edge>, Dim) {
        if dims.iter().all(|d| *d == dim || *d == Dim::Empty) {
            return (edges, dim);
        }
        let mut kept = Vec::with_capacity(edges.len());
        for (edge, d) in edges.into_iter().zip(dims) {
            if d == dim || d == Dim::Empty {
                kept.push(edge);
                continue;
            }
            let source = self
                .dag
                .node(edge.child)
                .map_or(Source::default(), |n| n.source);
            let (this, here) = match dim {
                Dim::Two => ("3-D object", "2-D shapes"),
                _ => ("2-D shape", "3-D objects"),
            };
            self.warn_once(
                codes::MIXED_DIMENSIONS,
                format!(
                    "this {this} is ignored: the operation here takes {here} (OpenSCAD does not \
                     mix 2-D and 3-D objects, and the first object decides)"
                ),
                source,
            );
        }
        (kept, dim)
    }

    /// A top-level 2-D shape as the plate OpenSCAD's preview shows, 1 unit thick and centred on
    /// z = 0, with a warning at `at`; any other object unchanged.
    pub(super) fn top_level_plate(&mut self, edge: Edge, at: Source) -> Edge {
        if self.dim(edge) != Dim::Two {
            return edge;
        }
        self.warn_once(
            codes::TOP_LEVEL_2D,
            "a 2-D shape at the top level is not a solid: it is shown as a plate 1 unit thick \
             (-0.5 <= z <= 0.5), as OpenSCAD's preview shows it",
            at,
        );
        self.z_slab_cut(edge, -PLATE_HALF_THICKNESS, PLATE_HALF_THICKNESS, at)
    }

    /// The 2-D shape behind `edge` cut to `bottom <= z <= top`, with the box of the result.
    pub(crate) fn z_slab_cut(&mut self, edge: Edge, bottom: f64, top: f64, at: Source) -> Edge {
        let half = 0.5 * (top - bottom);
        let centre = DVec3::new(0.0, 0.0, 0.5 * (top + bottom));
        let slab_box = Aabb::new(
            DVec3::new(f64::NEG_INFINITY, f64::NEG_INFINITY, bottom),
            DVec3::new(f64::INFINITY, f64::INFINITY, top),
        );
        let shape_box = self.edge_box(edge);
        let Some(slab) = Quadric::slab(centre, DVec3::Z, half) else {
            return self.dag.empty(at).into();
        };
        let slab = self.dag.bounded_leaf(slab, at, slab_box);
        let cut = self.dag.intersection([edge, slab.into()], at);
        let cut = self.dag.bounded(cut, shape_box.intersection(&slab_box));
        self.mark_extruded(cut);
        cut.into()
    }

    /// Marks `node`, made from a 2-D shape, as a 3-D solid.
    pub(crate) fn mark_extruded(&mut self, node: NodeId) {
        self.extruded.insert(node);
    }

    /// A warning reported once per code and place.
    pub(super) fn warn_once(&mut self, code: &'static str, message: impl Into<String>, at: Source) {
        if self.reported.insert((code, at.file, at.span)) {
            self.warn(code, message, at.file, at.span);
        }
    }
}

/// The dimension of the first non-empty object.
fn first_dim(dims: impl Iterator<Item = Dim>) -> Dim {
    dims.into_iter()
        .find(|d| *d != Dim::Empty)
        .unwrap_or(Dim::Empty)
}
