//! The transformed CSG DAG: an arena of hash-consed nodes with 4×4 transforms on the edges.
//!
//! Leaves hold one quadric each in the primitive's local frame; inner nodes are variadic union
//! and intersection, difference (first child minus the rest), complement, and the wrappers the
//! renderer needs (colour, highlight). Equal nodes (same kind, children, transforms, exact
//! coefficients, source and declared bounds) are stored once, so a module instantiated N times
//! with the same arguments is one node reached through N edges. Background parts (`%`) are kept
//! as separate roots, outside the solid.

use std::collections::HashMap;
use std::collections::hash_map::Entry;

use rustc_hash::FxHashMap;

use qcsg_diag::{FileId, Span};
use qcsg_quadric::{DMat4, DVec3, Quadric};

use crate::bounds::Aabb;
use crate::quadric_box::solid_bounds;

/// Handle of a node in a [`Dag`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct NodeId(pub u32);

/// Handle of an interned transform in a [`Dag`]; [`TransformId::IDENTITY`] is always present.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct TransformId(pub u32);

impl TransformId {
    /// The identity transform.
    pub const IDENTITY: TransformId = TransformId(0);
}

/// A child reference: the child node seen through a transform (points of the child map to
/// the parent's frame as `p_parent = M p_child`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Edge {
    /// The child node.
    pub child: NodeId,
    /// The transform from the child's frame to the parent's.
    pub transform: TransformId,
}

impl From<NodeId> for Edge {
    fn from(child: NodeId) -> Self {
        Edge {
            child,
            transform: TransformId::IDENTITY,
        }
    }
}

/// Where a node came from in the script: the file and byte range of the code that made it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Source {
    /// The file.
    pub file: FileId,
    /// The byte range in that file.
    pub span: Span,
}

impl Source {
    /// A source at `span` in `file`.
    pub fn new(file: FileId, span: Span) -> Self {
        Self { file, span }
    }
}

/// An RGBA colour with components in `[0, 1]`.
pub type Rgba = [f64; 4];

/// What a node is.
#[derive(Clone, Debug, PartialEq)]
pub enum NodeKind {
    /// The solid `q(p − origin) ≤ 0` of one quadric, in the node's local frame.
    Leaf(Quadric),
    /// The union of the children; no children is the empty solid.
    Union(Vec<Edge>),
    /// The intersection of the children (at least one: the builder turns an empty
    /// intersection into the empty solid, as OpenSCAD does).
    Intersection(Vec<Edge>),
    /// The first child minus all the others (at least one child).
    Difference(Vec<Edge>),
    /// Everything not in the child.
    Complement(Edge),
    /// The child painted with a colour (inherited by the leaves below unless they are
    /// painted again further down). No effect on geometry.
    Color(Rgba, Edge),
    /// The child, marked for highlighting (`#`). No effect on geometry.
    Highlight(Edge),
}

impl NodeKind {
    /// The short lower-case name used in text and JSON output.
    pub fn name(&self) -> &'static str {
        match self {
            NodeKind::Leaf(_) => "leaf",
            NodeKind::Union(_) => "union",
            NodeKind::Intersection(_) => "intersection",
            NodeKind::Difference(_) => "difference",
            NodeKind::Complement(_) => "complement",
            NodeKind::Color(..) => "color",
            NodeKind::Highlight(_) => "highlight",
        }
    }

    /// The child edges, in order.
    pub fn children(&self) -> &[Edge] {
        match self {
            NodeKind::Leaf(_) => &[],
            NodeKind::Union(c) | NodeKind::Intersection(c) | NodeKind::Difference(c) => c,
            NodeKind::Complement(e) | NodeKind::Color(_, e) | NodeKind::Highlight(e) => {
                std::slice::from_ref(e)
            }
        }
    }
}

/// One node of the DAG.
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    /// What it is.
    pub kind: NodeKind,
    /// The code that made it (for diagnostics and the DNF's quadric sources).
    pub source: Source,
    /// A box in the node's local frame known to contain its solid (a cube's `[0, s]³`), if the
    /// code that built it knew one.
    pub bounds: Option<Aabb>,
}

/// Errors of the builder API.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DagError {
    /// A transform matrix has a NaN or infinite entry.
    NonFiniteTransform,
    /// A colour has a NaN or infinite component.
    NonFiniteColor,
}

impl std::fmt::Display for DagError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            DagError::NonFiniteTransform => f.write_str("transform matrix is not finite"),
            DagError::NonFiniteColor => f.write_str("colour is not finite"),
        }
    }
}

impl std::error::Error for DagError {}

/// The exact identity of a node, for hash-consing: floats by bit pattern. It borrows the node's
/// children, so that the index holds no copy of them: a copy made each key several times the
/// size of its entry, and a long text's DAG interns a million nodes.
#[derive(PartialEq, Eq, Hash)]
struct NodeKey<'n> {
    tag: u8,
    edges: &'n [Edge],
    /// A leaf's origin and coefficients, a colour's channels; zeros beyond them.
    bits: [u64; 13],
    source: Source,
    bounds: Option<[u64; 6]>,
}

impl<'n> NodeKey<'n> {
    fn of(node: &'n Node) -> Self {
        let mut bits = [0u64; 13];
        let (tag, edges): (u8, &[Edge]) = match &node.kind {
            NodeKind::Leaf(q) => {
                let numbers = q.origin().to_array().into_iter().chain(q.coefficients());
                for (bit, number) in bits.iter_mut().zip(numbers) {
                    *bit = number.to_bits();
                }
                (0, &[])
            }
            NodeKind::Union(c) => (1, c),
            NodeKind::Intersection(c) => (2, c),
            NodeKind::Difference(c) => (3, c),
            NodeKind::Complement(e) => (4, std::slice::from_ref(e)),
            NodeKind::Color(rgba, e) => {
                for (bit, channel) in bits.iter_mut().zip(rgba) {
                    *bit = channel.to_bits();
                }
                (5, std::slice::from_ref(e))
            }
            NodeKind::Highlight(e) => (6, std::slice::from_ref(e)),
        };
        NodeKey {
            tag,
            edges,
            bits,
            source: node.source,
            bounds: node.bounds.map(|b| b.bits()),
        }
    }

    fn hash(&self) -> u64 {
        let mut hasher = rustc_hash::FxHasher::default();
        std::hash::Hash::hash(self, &mut hasher);
        std::hash::Hasher::finish(&hasher)
    }
}

/// The nodes interned under one hash of their [`NodeKey`]: nearly always one.
#[derive(Clone, Debug)]
enum Interned {
    One(NodeId),
    Many(Vec<NodeId>),
}

impl Interned {
    fn ids(&self) -> &[NodeId] {
        match self {
            Interned::One(id) => std::slice::from_ref(id),
            Interned::Many(ids) => ids,
        }
    }

    /// These and `id`, a node whose key hashes alike.
    fn with(&self, id: NodeId) -> Self {
        Interned::Many(self.ids().iter().copied().chain([id]).collect())
    }
}

/// The scene DAG: nodes, interned transforms, the root and the background roots.
///
/// Build it bottom-up with the builder methods; every method returns a handle into this DAG
/// and never panics. Children always precede their parents, so the DAG is acyclic by
/// construction: an edge to a handle this DAG does not hold (a logic error) is stored as an edge
/// to the empty solid, and queries given such a handle answer `None` / `false`.
#[derive(Clone, Debug)]
pub struct Dag {
    nodes: Vec<Node>,
    /// The nodes by the hash of their [`NodeKey`] (a fast hash: building a mesh's cells interns
    /// hundreds of thousands of nodes).
    node_index: FxHashMap<u64, Interned>,
    transforms: Vec<DMat4>,
    /// Inverses of `transforms` (`None` where singular), for membership queries.
    inverses: Vec<Option<DMat4>>,
    transform_index: FxHashMap<[u64; 16], TransformId>,
    root: Option<Edge>,
    backgrounds: Vec<Edge>,
    /// For some nodes, another node that is exactly their complement in the same frame, built
    /// to expand into few terms where the node is subtracted ([`Dag::set_complement`]).
    complements: HashMap<NodeId, NodeId>,
}

impl Default for Dag {
    fn default() -> Self {
        Self::new()
    }
}

impl Dag {
    /// An empty DAG with no root.
    pub fn new() -> Self {
        let mut transform_index = FxHashMap::default();
        transform_index.insert(matrix_bits(&DMat4::IDENTITY), TransformId::IDENTITY);
        Self {
            nodes: Vec::new(),
            node_index: FxHashMap::default(),
            transforms: vec![DMat4::IDENTITY],
            inverses: vec![Some(DMat4::IDENTITY)],
            transform_index,
            root: None,
            backgrounds: Vec::new(),
            complements: HashMap::new(),
        }
    }

    // ----- builder -------------------------------------------------------------------------

    /// A leaf: the solid `quadric ≤ 0` in its own local frame, made by the code at `source`.
    pub fn leaf(&mut self, quadric: Quadric, source: Source) -> NodeId {
        self.intern(NodeKind::Leaf(quadric), source, None)
    }

    /// A leaf that also knows a box containing its solid (e.g. a sphere's).
    pub fn bounded_leaf(&mut self, quadric: Quadric, source: Source, bounds: Aabb) -> NodeId {
        self.intern(NodeKind::Leaf(quadric), source, Some(bounds))
    }

    /// The empty solid.
    pub fn empty(&mut self, source: Source) -> NodeId {
        self.intern(NodeKind::Union(Vec::new()), source, None)
    }

    /// The union of `children` (none: the empty solid).
    pub fn union(&mut self, children: impl IntoIterator<Item = Edge>, source: Source) -> NodeId {
        let children: Vec<Edge> = children.into_iter().collect();
        self.intern(NodeKind::Union(children), source, None)
    }

    /// The intersection of `children` (none: the empty solid, as in OpenSCAD).
    pub fn intersection(
        &mut self,
        children: impl IntoIterator<Item = Edge>,
        source: Source,
    ) -> NodeId {
        let children: Vec<Edge> = children.into_iter().collect();
        if children.is_empty() {
            return self.empty(source);
        }
        self.intern(NodeKind::Intersection(children), source, None)
    }

    /// The first child minus all the others (none: the empty solid).
    pub fn difference(
        &mut self,
        children: impl IntoIterator<Item = Edge>,
        source: Source,
    ) -> NodeId {
        let children: Vec<Edge> = children.into_iter().collect();
        if children.is_empty() {
            return self.empty(source);
        }
        self.intern(NodeKind::Difference(children), source, None)
    }

    /// Everything outside `child`.
    pub fn complement(&mut self, child: Edge, source: Source) -> NodeId {
        self.intern(NodeKind::Complement(child), source, None)
    }

    /// `child` painted `rgba` (components clamped to `[0, 1]`); an error if not finite.
    pub fn color(&mut self, child: Edge, rgba: Rgba, source: Source) -> Result<NodeId, DagError> {
        if rgba.iter().any(|c| !c.is_finite()) {
            return Err(DagError::NonFiniteColor);
        }
        let rgba = rgba.map(|c| c.clamp(0.0, 1.0));
        Ok(self.intern(NodeKind::Color(rgba, child), source, None))
    }

    /// `child` marked for highlighting (`#`); still part of the solid.
    pub fn highlight(&mut self, child: Edge, source: Source) -> NodeId {
        self.intern(NodeKind::Highlight(child), source, None)
    }

    /// Records that `complement` is exactly the set of points outside `node`, in the same frame:
    /// the DNF expands it where `node` is subtracted, instead of multiplying out the complements
    /// of `node`'s parts (a glyph's unfilled cells instead of the product of its filled cells'
    /// complements). The caller guarantees the two are complements; membership queries and the
    /// emitted forms keep using `node` itself. Ignored for handles this DAG does not hold.
    pub fn set_complement(&mut self, node: NodeId, complement: NodeId) {
        if self.node(node).is_some() && self.node(complement).is_some() && node != complement {
            self.complements.insert(node, complement);
        }
    }

    /// The node recorded as `node`'s exact complement, if any ([`Dag::set_complement`]).
    pub fn complement_of(&self, node: NodeId) -> Option<NodeId> {
        self.complements.get(&node).copied()
    }

    /// The same node with a declared box (in its local frame) that contains its solid, e.g.
    /// a cube's `[0, s]³` on the intersection of its three slabs. A box already declared is
    /// intersected with the new one. The caller guarantees the box really contains the solid.
    pub fn bounded(&mut self, node: NodeId, bounds: Aabb) -> NodeId {
        let Some(existing) = self.node(node) else {
            return node;
        };
        let bounds = match existing.bounds {
            Some(b) => b.intersection(&bounds),
            None => bounds,
        };
        let (kind, source) = (existing.kind.clone(), existing.source);
        self.intern(kind, source, Some(bounds))
    }

    /// Interns a matrix (points map as `p' = M p`); equal matrices (bitwise, with `-0 == 0`)
    /// share one id. An error if an entry is not finite. Singular matrices are accepted; the
    /// DNF reports them.
    pub fn transform(&mut self, matrix: &DMat4) -> Result<TransformId, DagError> {
        if !matrix.is_finite() {
            return Err(DagError::NonFiniteTransform);
        }
        let key = matrix_bits(matrix);
        if let Some(&id) = self.transform_index.get(&key) {
            return Ok(id);
        }
        let id = TransformId(self.transforms.len() as u32);
        // Store the canonical matrix (negative zeros cleared) so output is stable.
        let canonical = DMat4::from_cols_array(&key.map(f64::from_bits));
        let det = canonical.determinant();
        let inverse = canonical.inverse();
        self.inverses
            .push((det != 0.0 && det.is_finite() && inverse.is_finite()).then_some(inverse));
        self.transforms.push(canonical);
        self.transform_index.insert(key, id);
        Ok(id)
    }

    /// An edge to `child` through `matrix`.
    pub fn edge(&mut self, child: NodeId, matrix: &DMat4) -> Result<Edge, DagError> {
        Ok(Edge {
            child,
            transform: self.transform(matrix)?,
        })
    }

    /// `edge` seen through one more transform applied after its own: `M · T_edge`. This is
    /// how `translate(…) rotate(…) child` becomes one edge.
    pub fn transformed(&mut self, edge: Edge, matrix: &DMat4) -> Result<Edge, DagError> {
        let inner = self.matrix(edge.transform);
        let composed = if inner == DMat4::IDENTITY {
            *matrix
        } else {
            *matrix * inner
        };
        self.edge(edge.child, &composed)
    }

    /// `edge` translated by `offset`.
    pub fn translated(&mut self, edge: Edge, offset: DVec3) -> Result<Edge, DagError> {
        self.transformed(edge, &DMat4::from_translation(offset))
    }

    /// Makes `root` the solid of the scene.
    pub fn set_root(&mut self, root: Edge) {
        self.root = Some(root);
    }

    /// Adds a background part (`%`): drawn by the renderer, not part of the solid.
    pub fn add_background(&mut self, part: Edge) {
        self.backgrounds.push(part);
    }

    // ----- queries -------------------------------------------------------------------------

    /// The root solid, if set.
    pub fn root(&self) -> Option<Edge> {
        self.root
    }

    /// The background parts, in the order they were added.
    pub fn backgrounds(&self) -> &[Edge] {
        &self.backgrounds
    }

    /// The node behind a handle (`None` for a handle from another DAG).
    pub fn node(&self, id: NodeId) -> Option<&Node> {
        self.nodes.get(id.0 as usize)
    }

    /// All nodes, indexed by `NodeId.0`; children always come before their parents.
    pub fn nodes(&self) -> &[Node] {
        &self.nodes
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// Whether the DAG has no node.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// The matrix behind a transform id (the identity for an unknown id).
    pub fn matrix(&self, id: TransformId) -> DMat4 {
        self.transforms
            .get(id.0 as usize)
            .copied()
            .unwrap_or(DMat4::IDENTITY)
    }

    /// All interned transforms, indexed by `TransformId.0`.
    pub fn transforms(&self) -> &[DMat4] {
        &self.transforms
    }

    /// For every node (indexed by `NodeId.0`), a box in its own frame containing its solid:
    /// the declared box intersected with what its children give (a leaf: its quadric's own
    /// box; union: the join; intersection: the meet; difference: the first child's;
    /// complement: all of space). One pass over the arena, children first.
    pub fn local_bounds(&self) -> Vec<Aabb> {
        self.local_bounds_up_to(self.nodes.len())
    }

    /// A box, in the frame of the edge's parent, containing the solid behind `edge` (all of
    /// space for a foreign handle). Costs one pass over the nodes up to the edge's child.
    pub fn edge_bounds(&self, edge: Edge) -> Aabb {
        let index = edge.child.0 as usize;
        if index >= self.nodes.len() {
            return Aabb::EVERYTHING;
        }
        let boxes = self.local_bounds_up_to(index + 1);
        boxes[index].transformed(&self.matrix(edge.transform))
    }

    fn local_bounds_up_to(&self, count: usize) -> Vec<Aabb> {
        let mut boxes: Vec<Aabb> = Vec::with_capacity(count);
        for node in &self.nodes[..count] {
            let child_box = |edge: &Edge, boxes: &[Aabb]| {
                boxes
                    .get(edge.child.0 as usize)
                    .copied()
                    .unwrap_or(Aabb::EVERYTHING)
                    .transformed(&self.matrix(edge.transform))
            };
            let computed = match &node.kind {
                NodeKind::Leaf(q) => solid_bounds(q),
                NodeKind::Union(children) => children
                    .iter()
                    .fold(Aabb::EMPTY, |acc, e| acc.union(&child_box(e, &boxes))),
                NodeKind::Intersection(children) => {
                    children.iter().fold(Aabb::EVERYTHING, |acc, e| {
                        acc.intersection(&child_box(e, &boxes))
                    })
                }
                NodeKind::Difference(children) => children
                    .first()
                    .map_or(Aabb::EMPTY, |e| child_box(e, &boxes)),
                NodeKind::Complement(_) => Aabb::EVERYTHING,
                NodeKind::Color(_, e) | NodeKind::Highlight(e) => child_box(e, &boxes),
            };
            let declared = node.bounds.unwrap_or(Aabb::EVERYTHING);
            boxes.push(computed.intersection(&declared));
        }
        boxes
    }

    /// The highlighted parts (`#`) reachable from the root, each as an edge from the world
    /// frame to the highlighted node's child, in the order a depth-first walk meets them,
    /// without repeats. `build_dnf_of` on one gives the solid to draw translucent, as OpenSCAD
    /// does, also for parts that are subtracted. The walk follows at most `max_visits` edges
    /// (a DAG can have exponentially many paths); `None` if it needed more.
    pub fn highlighted_parts(&mut self, max_visits: usize) -> Option<Vec<Edge>> {
        let Some(root) = self.root else {
            return Some(Vec::new());
        };
        let mut found: Vec<(NodeId, DMat4)> = Vec::new();
        let mut stack = vec![(root, DMat4::IDENTITY)];
        let mut visits = 0usize;
        while let Some((edge, parent)) = stack.pop() {
            visits += 1;
            if visits > max_visits {
                return None;
            }
            let world = parent * self.matrix(edge.transform);
            let Some(node) = self.node(edge.child) else {
                continue;
            };
            if let NodeKind::Highlight(inner) = &node.kind {
                found.push((inner.child, world * self.matrix(inner.transform)));
                continue;
            }
            // Push in reverse so that children are visited in order.
            for child in node.kind.children().iter().rev() {
                stack.push((*child, world));
            }
        }
        let mut parts: Vec<Edge> = Vec::new();
        for (child, matrix) in found {
            let Ok(edge) = self.edge(child, &matrix) else {
                continue;
            };
            if !parts.contains(&edge) {
                parts.push(edge);
            }
        }
        Some(parts)
    }

    /// Whether the world point `p` lies in the root solid (closed: surface points count as
    /// inside), by direct evaluation of the DAG. `false` without a root.
    pub fn contains(&self, p: DVec3) -> bool {
        self.root.is_some_and(|root| self.edge_contains(root, p))
    }

    /// Whether the point `p`, given in the parent's frame of `edge`, lies in the solid behind
    /// `edge`.
    pub fn edge_contains(&self, edge: Edge, p: DVec3) -> bool {
        match self.to_child_frame(edge.transform, p) {
            Some(local) => self.node_contains(edge.child, local),
            // A point that maps to infinity (projective) or through a singular transform is
            // outside every bounded part; treat it as outside.
            None => false,
        }
    }

    /// Whether `p` (in the node's local frame) lies in the node's solid.
    pub fn node_contains(&self, id: NodeId, p: DVec3) -> bool {
        // Deep DAGs (a recursive module) must not overflow the stack.
        stacker::maybe_grow(128 * 1024, 4 * 1024 * 1024, || {
            self.node_contains_inner(id, p)
        })
    }

    fn node_contains_inner(&self, id: NodeId, p: DVec3) -> bool {
        let Some(node) = self.node(id) else {
            return false;
        };
        match &node.kind {
            NodeKind::Leaf(q) => q.value(p) <= 0.0,
            NodeKind::Union(c) => c.iter().any(|&e| self.edge_contains(e, p)),
            NodeKind::Intersection(c) => c.iter().all(|&e| self.edge_contains(e, p)),
            NodeKind::Difference(c) => {
                c.first().is_some_and(|&e| self.edge_contains(e, p))
                    && !c[1..].iter().any(|&e| self.edge_contains(e, p))
            }
            NodeKind::Complement(e) => !self.edge_contains(*e, p),
            NodeKind::Color(_, e) | NodeKind::Highlight(e) => self.edge_contains(*e, p),
        }
    }

    /// `M⁻¹ p` for the transform `id`, dehomogenised; `None` if singular or at infinity.
    fn to_child_frame(&self, id: TransformId, p: DVec3) -> Option<DVec3> {
        if id == TransformId::IDENTITY {
            return Some(p);
        }
        let inverse = self.inverses.get(id.0 as usize).copied().flatten()?;
        let local = inverse * p.extend(1.0);
        if local.w == 0.0 {
            return None;
        }
        let local = local.truncate() / local.w;
        local.is_finite().then_some(local)
    }

    /// An edge that refers into this DAG: a child handle from elsewhere (which could otherwise
    /// name a node created later, and so a cycle) becomes the empty solid, an unknown transform
    /// the identity.
    fn sanitize(&mut self, edge: Edge) -> Edge {
        let child = if (edge.child.0 as usize) < self.nodes.len() {
            edge.child
        } else {
            self.intern(NodeKind::Union(Vec::new()), Source::default(), None)
        };
        let transform = if (edge.transform.0 as usize) < self.transforms.len() {
            edge.transform
        } else {
            TransformId::IDENTITY
        };
        Edge { child, transform }
    }

    fn intern(&mut self, kind: NodeKind, source: Source, bounds: Option<Aabb>) -> NodeId {
        let kind = match kind {
            NodeKind::Leaf(_) => kind,
            NodeKind::Union(c) => {
                NodeKind::Union(c.into_iter().map(|e| self.sanitize(e)).collect())
            }
            NodeKind::Intersection(c) => {
                NodeKind::Intersection(c.into_iter().map(|e| self.sanitize(e)).collect())
            }
            NodeKind::Difference(c) => {
                NodeKind::Difference(c.into_iter().map(|e| self.sanitize(e)).collect())
            }
            NodeKind::Complement(e) => NodeKind::Complement(self.sanitize(e)),
            NodeKind::Color(rgba, e) => NodeKind::Color(rgba, self.sanitize(e)),
            NodeKind::Highlight(e) => NodeKind::Highlight(self.sanitize(e)),
        };
        let node = Node {
            kind,
            source,
            bounds,
        };
        let key = NodeKey::of(&node);
        let hash = key.hash();
        let nodes = &self.nodes;
        let same = |id: &&NodeId| NodeKey::of(&nodes[id.0 as usize]) == key;
        if let Some(&id) = (self.node_index.get(&hash)).and_then(|ids| ids.ids().iter().find(same))
        {
            return id;
        }
        // u32 ids: four billion nodes of at least 100 bytes each exhaust memory long before
        // the id space.
        let id = NodeId(self.nodes.len() as u32);
        self.nodes.push(node);
        match self.node_index.entry(hash) {
            Entry::Vacant(entry) => {
                entry.insert(Interned::One(id));
            }
            Entry::Occupied(mut entry) => {
                let ids = entry.get().with(id);
                entry.insert(ids);
            }
        }
        id
    }
}

/// Bit patterns of a matrix (column-major) with `-0.0` folded into `0.0`.
fn matrix_bits(m: &DMat4) -> [u64; 16] {
    m.to_cols_array()
        .map(|v| if v == 0.0 { 0u64 } else { v.to_bits() })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sphere() -> Quadric {
        Quadric::sphere(DVec3::ZERO, 1.0).unwrap()
    }

    #[test]
    fn equal_nodes_and_transforms_are_shared() {
        let mut dag = Dag::new();
        let a = dag.leaf(sphere(), Source::default());
        let b = dag.leaf(sphere(), Source::default());
        assert_eq!(a, b);
        let t1 = dag.translated(a.into(), DVec3::X).unwrap();
        let t2 = dag.translated(b.into(), DVec3::X).unwrap();
        assert_eq!(t1, t2);
        let u1 = dag.union([t1, a.into()], Source::default());
        let u2 = dag.union([t2, b.into()], Source::default());
        assert_eq!(u1, u2);
        assert_eq!(dag.len(), 2);
        assert_eq!(dag.transforms().len(), 2);
    }

    /// Nodes that differ in any part of their identity stay apart; each is found again.
    #[test]
    fn distinct_nodes_are_kept_apart_and_found_again() {
        let mut dag = Dag::new();
        let source = Source::default();
        let a = dag.leaf(sphere(), source);
        let b = dag.leaf(Quadric::sphere(DVec3::ZERO, 2.0).unwrap(), source);
        let union = dag.union([a.into(), b.into()], source);
        let intersection = dag.intersection([a.into(), b.into()], source);
        let swapped = dag.union([b.into(), a.into()], source);
        let coloured = dag.color(a.into(), [1.0, 0.0, 0.0, 1.0], source).unwrap();
        let other_colour = dag.color(a.into(), [0.0, 1.0, 0.0, 1.0], source).unwrap();
        let elsewhere = dag.leaf(sphere(), Source::new(FileId(1), Span::new(0, 1)));
        let made = [
            a,
            b,
            union,
            intersection,
            swapped,
            coloured,
            other_colour,
            elsewhere,
        ];
        let mut distinct = made.to_vec();
        distinct.sort();
        distinct.dedup();
        assert_eq!(distinct.len(), made.len());
        assert_eq!(dag.union([a.into(), b.into()], source), union);
        assert_eq!(
            dag.color(a.into(), [0.0, 1.0, 0.0, 1.0], source).unwrap(),
            other_colour
        );
        assert_eq!(dag.len(), made.len());
    }

    /// Nodes whose keys hash alike are all kept under the hash.
    #[test]
    fn nodes_hashed_alike_are_all_kept() {
        let (a, b, c) = (NodeId(3), NodeId(5), NodeId(8));
        let many = Interned::One(a).with(b).with(c);
        assert_eq!(many.ids(), [a, b, c]);
    }

    #[test]
    fn membership_through_transforms() {
        let mut dag = Dag::new();
        let s = dag.leaf(sphere(), Source::default());
        let e = dag.translated(s.into(), DVec3::new(5.0, 0.0, 0.0)).unwrap();
        let d = dag.difference([e, s.into()], Source::default());
        dag.set_root(d.into());
        assert!(dag.contains(DVec3::new(5.5, 0.0, 0.0)));
        assert!(!dag.contains(DVec3::ZERO));
        assert!(
            dag.transform(&DMat4::from_cols_array(&[f64::NAN; 16]))
                .is_err()
        );
    }

    #[test]
    fn foreign_handles_cannot_make_cycles() {
        let mut dag = Dag::new();
        let s = dag.leaf(sphere(), Source::default());
        let bogus = Edge {
            child: NodeId(7),
            transform: TransformId(9),
        };
        let u = dag.union([s.into(), bogus], Source::default());
        let children = dag.node(u).unwrap().kind.children().to_vec();
        assert!(children.iter().all(|e| e.child < u));
        assert_eq!(children[1].transform, TransformId::IDENTITY);
        dag.set_root(u.into());
        assert!(dag.contains(DVec3::ZERO));
    }

    #[test]
    fn highlighted_parts_in_world_space() {
        let mut dag = Dag::new();
        let s = dag.leaf(sphere(), Source::default());
        let h = dag.highlight(s.into(), Source::default());
        let moved = dag.translated(h.into(), DVec3::new(5.0, 0.0, 0.0)).unwrap();
        let d = dag.difference([s.into(), moved], Source::default());
        dag.set_root(d.into());
        let parts = dag.highlighted_parts(1000).unwrap();
        assert_eq!(parts.len(), 1);
        assert_eq!(parts[0].child, s);
        assert_eq!(
            dag.matrix(parts[0].transform),
            DMat4::from_translation(DVec3::new(5.0, 0.0, 0.0))
        );
        assert!(dag.highlighted_parts(1).is_none());
    }

    #[test]
    fn bounds_of_edges() {
        let mut dag = Dag::new();
        let s = dag.leaf(sphere(), Source::default());
        let moved = dag.translated(s.into(), DVec3::new(5.0, 0.0, 0.0)).unwrap();
        let u = dag.union([s.into(), moved], Source::default());
        let b = dag.edge_bounds(u.into());
        assert!(b.contains(DVec3::new(-1.0, 0.0, 0.0)) && b.contains(DVec3::new(6.0, 1.0, 1.0)));
        assert!(!b.contains(DVec3::new(6.1, 0.0, 0.0)));
        let c = dag.complement(u.into(), Source::default());
        assert!(!dag.edge_bounds(c.into()).is_bounded());
    }

    #[test]
    fn deep_dags_do_not_overflow_the_stack() {
        let mut dag = Dag::new();
        let mut node = dag.leaf(sphere(), Source::default());
        for i in 0..100_000u32 {
            let step = Source::new(FileId(0), Span::new(i as usize, i as usize + 1));
            node = dag.union([node.into()], step);
        }
        dag.set_root(node.into());
        assert!(dag.contains(DVec3::ZERO));
    }
}
