//! `projection` as plane figures: a 3-D subtree turned into a [`PlanarExpr`] whose leaves are
//! conics, either its section by the plane z = 0 (`cut = true`) or its shadow on that plane
//! (`cut = false`).
//!
//! **Section.** Restricting to z = 0 commutes with every boolean, so the section is the subtree
//! itself with each quadric restricted to z = 0 (a conic): exact, leaf by leaf.
//!
//! **Shadow.** The projection along z commutes with union only. It is exact here where each
//! intersection has at most one part that is not z-invariant (`Z ∩ B` projects to `Z ∩ proj B`
//! when Z is z-invariant), each difference subtracts z-invariant parts only and each complement
//! is of a z-invariant part. A leaf's shadow is itself when it is z-invariant, the ellipse
//! `min_z q ≤ 0` (a Schur complement) when q is convex in z, and the whole plane otherwise (a
//! slab or half-space in z, a tilted plane, a hyperboloid). So boxes, balls, ellipsoids and
//! vertical cylinders, their unions and their cuts by z-invariant parts project exactly; a cone
//! cut by a slab does not, and [`ShadowError`] names it.
//!
//! **Meshes.** A mesh's cells are intersections of several tilted half-spaces, which the rule
//! above refuses; the walker is given each mesh node's triangles instead and casts the shadow
//! from them ([`crate::mesh_shadow`]): a union of convex polygons, each an intersection of
//! half-planes, not z-invariant as a part (so it may be cut by z-invariant parts).

use std::collections::HashMap;
use std::rc::Rc;

use glam::{DMat3, DMat4, DVec2, DVec3};
use qcsg_csg::{Dag, Edge, NodeId, NodeKind, Source};
use qcsg_quadric::Quadric;

use crate::mesh_shadow::{MeshFaces, shadow_polygons};
use crate::planar::{Conic, PlanarError, PlanarExpr, PlanarId, PlanarKind, PlanarNode};

/// Why a subtree has no shadow computed here: the part whose projection is not exact this way.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShadowError {
    /// The node at this source combines parts that depend on z in a way projection does not
    /// commute with.
    Inexact(Source),
    /// More nodes than the limit.
    TooLarge(usize),
}

/// The constant conic `j ≤ 0`: the whole plane for a negative `j`, nothing for a positive one.
fn constant(j: f64) -> Conic {
    Conic {
        origin: DVec2::ZERO,
        matrix: DMat3::from_cols(DVec3::ZERO, DVec3::ZERO, DVec3::new(0.0, 0.0, j)),
    }
}

/// Whether `conic` has no term in X or Y: it is the whole plane or nothing.
pub fn constant_value(conic: &Conic) -> Option<f64> {
    let [a, b, d, g, h, j] = conic.coefficients();
    (a == 0.0 && b == 0.0 && d == 0.0 && g == 0.0 && h == 0.0).then_some(j)
}

/// The box of the figure of `conic` when it is a bounded ellipse (slightly padded for rounding).
pub fn ellipse_box(conic: &Conic) -> Option<(DVec2, DVec2)> {
    let [a, b, d, g, h, j] = conic.coefficients();
    let det = a * b - d * d;
    if !(a > 0.0 && b > 0.0 && det > 0.0) {
        return None;
    }
    // Centre c = −A⁻¹ (g, h); inside: (X − c)ᵀ A (X − c) ≤ −k with k = j + (g, h) · c.
    let centre = DVec2::new(-(b * g - d * h) / det, -(a * h - d * g) / det);
    let k = j + g * centre.x + h * centre.y;
    if k >= 0.0 {
        return None;
    }
    // The half-extents sqrt(−k (A⁻¹)_ii).
    let half = DVec2::new((-k * b / det).sqrt(), (-k * a / det).sqrt()) * (1.0 + 1e-9);
    let centre = conic.origin + centre;
    (centre.is_finite() && half.is_finite()).then_some((centre - half, centre + half))
}

/// `q` restricted to the plane z = 0, as a conic in (x, y).
pub fn restrict_to_ground(q: &Quadric) -> Conic {
    let [a, b, c, d, e, f, g, h, i, j] = q.coefficients();
    let o = q.origin();
    // Z = z − oz = −oz on the plane.
    let z = -o.z;
    let (g, h, j) = (g + e * z, h + f * z, j + c * z * z + 2.0 * i * z);
    Conic {
        origin: o.truncate(),
        matrix: DMat3::from_cols(
            DVec3::new(a, d, g),
            DVec3::new(d, b, h),
            DVec3::new(g, h, j),
        ),
    }
}

/// The shadow of `{q ≤ 0}` on the plane z = 0, and whether q is z-invariant.
fn leaf_shadow(q: &Quadric) -> (Conic, bool) {
    let [a, b, c, d, e, f, g, h, i, j] = q.coefficients();
    if c == 0.0 && e == 0.0 && f == 0.0 && i == 0.0 {
        return (restrict_to_ground(q), true);
    }
    if c <= 0.0 {
        // For each (x, y) some z makes q ≤ 0 (but for a line, at most): the whole plane.
        return (constant(-1.0), false);
    }
    // min over Z of c Z² + 2 Z (e X + f Y + i) + rest(X, Y) = rest − (e X + f Y + i)² / c.
    let v = DVec3::new(e, f, i);
    let rest = DMat3::from_cols(
        DVec3::new(a, d, g),
        DVec3::new(d, b, h),
        DVec3::new(g, h, j),
    );
    let outer = DMat3::from_cols(v * v.x, v * v.y, v * v.z) * (1.0 / c);
    (
        Conic {
            origin: q.origin().truncate(),
            matrix: rest - outer,
        },
        false,
    )
}

/// Which projection to take.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Mode {
    Section,
    Shadow,
}

/// The section by z = 0 of the 3-D subtree behind `edge` (seen in its parent's frame).
pub fn section_expression(
    dag: &Dag,
    edge: Edge,
    max_nodes: usize,
) -> Result<PlanarExpr, PlanarError> {
    walk(dag, edge, max_nodes, Mode::Section, &HashMap::new()).map_err(|e| match e {
        ShadowError::Inexact(source) => PlanarError::NotPlanar(source),
        ShadowError::TooLarge(n) => PlanarError::TooLarge(n),
    })
}

/// The shadow on z = 0 of the 3-D subtree behind `edge`, where it is exact (see the module's
/// documentation); `meshes` holds the triangles of the mesh nodes.
pub fn shadow_expression(
    dag: &Dag,
    edge: Edge,
    max_nodes: usize,
    meshes: &HashMap<NodeId, Rc<MeshFaces>>,
) -> Result<PlanarExpr, ShadowError> {
    walk(dag, edge, max_nodes, Mode::Shadow, meshes)
}

fn walk(
    dag: &Dag,
    edge: Edge,
    max_nodes: usize,
    mode: Mode,
    meshes: &HashMap<NodeId, Rc<MeshFaces>>,
) -> Result<PlanarExpr, ShadowError> {
    let mut walker = Walker {
        dag,
        mode,
        meshes,
        nodes: Vec::new(),
        memo: HashMap::new(),
        max_nodes,
    };
    let (root, _) = walker.edge(edge.child, &dag.matrix(edge.transform))?;
    Ok(PlanarExpr {
        nodes: walker.nodes,
        root,
    })
}

struct Walker<'d> {
    dag: &'d Dag,
    mode: Mode,
    meshes: &'d HashMap<NodeId, Rc<MeshFaces>>,
    nodes: Vec<PlanarNode>,
    /// (node, transform) → the figure and whether the node is z-invariant.
    memo: HashMap<(NodeId, [u64; 16]), (PlanarId, bool)>,
    max_nodes: usize,
}

impl Walker<'_> {
    /// The union of convex `polygons` (corners counter-clockwise), each the intersection of the
    /// half-planes left of its edges, written about the edge's first corner.
    fn mesh_shadow(
        &mut self,
        polygons: &[Vec<DVec2>],
        source: Source,
    ) -> Result<PlanarId, ShadowError> {
        let mut parts = Vec::with_capacity(polygons.len());
        let (mut lo, mut hi) = (DVec2::INFINITY, DVec2::NEG_INFINITY);
        for polygon in polygons {
            let mut sides = Vec::with_capacity(polygon.len());
            let (mut min, mut max) = (DVec2::INFINITY, DVec2::NEG_INFINITY);
            for (k, &a) in polygon.iter().enumerate() {
                let b = polygon[(k + 1) % polygon.len()];
                let d = b - a;
                // Inside: (p − a) × d ≤ 0, with the outward normal (d.y, −d.x) normalised so
                // that an edge's numbers depend on its line's direction only.
                let n = DVec2::new(d.y, -d.x) / d.length();
                let matrix = DMat3::from_cols(
                    DVec3::new(0.0, 0.0, 0.5 * n.x),
                    DVec3::new(0.0, 0.0, 0.5 * n.y),
                    DVec3::new(0.5 * n.x, 0.5 * n.y, 0.0),
                );
                let conic = Conic { origin: a, matrix };
                sides.push(self.push(PlanarNode {
                    kind: PlanarKind::Leaf(conic),
                    source,
                    bounds: None,
                })?);
                (min, max) = (min.min(a), max.max(a));
            }
            (lo, hi) = (lo.min(min), hi.max(max));
            parts.push(self.push(PlanarNode {
                kind: PlanarKind::Intersection(sides),
                source,
                bounds: Some((min, max)),
            })?);
        }
        let bounds = (lo.is_finite() && hi.is_finite()).then_some((lo, hi));
        self.push(PlanarNode {
            kind: PlanarKind::Union(parts),
            source,
            bounds,
        })
    }

    fn push(&mut self, node: PlanarNode) -> Result<PlanarId, ShadowError> {
        if self.nodes.len() >= self.max_nodes {
            return Err(ShadowError::TooLarge(self.max_nodes));
        }
        self.nodes.push(node);
        Ok(PlanarId(self.nodes.len() as u32 - 1))
    }

    fn edge(&mut self, id: NodeId, world: &DMat4) -> Result<(PlanarId, bool), ShadowError> {
        stacker::maybe_grow(128 * 1024, 4 * 1024 * 1024, || self.edge_inner(id, world))
    }

    fn edge_inner(&mut self, id: NodeId, world: &DMat4) -> Result<(PlanarId, bool), ShadowError> {
        let key = (id, world.to_cols_array().map(f64::to_bits));
        if let Some(&done) = self.memo.get(&key) {
            return Ok(done);
        }
        let Some(node) = self.dag.node(id) else {
            let empty = self.push(PlanarNode {
                kind: PlanarKind::Union(Vec::new()),
                source: Source::default(),
                bounds: None,
            })?;
            return Ok((empty, true));
        };
        let source = node.source;
        let world_box = node.bounds.map(|b| b.transformed(world));
        // A part wholly above or below the plane has an empty section.
        if self.mode == Mode::Section && world_box.is_some_and(|b| b.min.z > 0.0 || b.max.z < 0.0) {
            let empty = self.push(PlanarNode {
                kind: PlanarKind::Union(Vec::new()),
                source,
                bounds: None,
            })?;
            self.memo.insert(key, (empty, true));
            return Ok((empty, true));
        }
        if self.mode == Mode::Shadow
            && let Some(faces) = self.meshes.get(&id)
        {
            let polygons = shadow_polygons(faces, world).ok_or(ShadowError::Inexact(source))?;
            let made = self.mesh_shadow(&polygons, source)?;
            self.memo.insert(key, (made, false));
            return Ok((made, false));
        }
        let children = |this: &mut Self, edges: &[Edge]| {
            edges
                .iter()
                .map(|e| {
                    let m = *world * this.dag.matrix(e.transform);
                    this.edge(e.child, &m)
                })
                .collect::<Result<Vec<_>, _>>()
        };
        let shadow = self.mode == Mode::Shadow;
        let inexact = ShadowError::Inexact(source);
        let ids = |c: &[(PlanarId, bool)]| c.iter().map(|(id, _)| *id).collect::<Vec<_>>();
        let (kind, invariant) = match &node.kind {
            NodeKind::Leaf(q) => {
                let q = q.transformed(world).ok_or(inexact)?;
                match self.mode {
                    Mode::Section => (PlanarKind::Leaf(restrict_to_ground(&q)), false),
                    Mode::Shadow => {
                        let (conic, invariant) = leaf_shadow(&q);
                        (PlanarKind::Leaf(conic), invariant)
                    }
                }
            }
            NodeKind::Union(c) => {
                let c = children(self, c)?;
                let invariant = c.iter().all(|(_, z)| *z);
                (PlanarKind::Union(ids(&c)), invariant)
            }
            NodeKind::Intersection(c) => {
                let c = children(self, c)?;
                let varying = c.iter().filter(|(_, z)| !*z).count();
                if shadow && varying > 1 {
                    return Err(inexact);
                }
                (PlanarKind::Intersection(ids(&c)), varying == 0)
            }
            NodeKind::Difference(c) => {
                let c = children(self, c)?;
                if shadow && c.iter().skip(1).any(|(_, z)| !*z) {
                    return Err(inexact);
                }
                let invariant = c.iter().all(|(_, z)| *z);
                (PlanarKind::Difference(ids(&c)), invariant)
            }
            NodeKind::Complement(e) => {
                let (inner, invariant) = children(self, std::slice::from_ref(e))?[0];
                if shadow && !invariant {
                    return Err(inexact);
                }
                (PlanarKind::Complement(inner), invariant)
            }
            NodeKind::Color(_, e) | NodeKind::Highlight(e) => {
                let m = *world * self.dag.matrix(e.transform);
                let inner = self.edge(e.child, &m)?;
                self.memo.insert(key, inner);
                return Ok(inner);
            }
        };
        let bounds = world_box.and_then(|b| {
            let (min, max) = (b.min.truncate(), b.max.truncate());
            (min.is_finite() && max.is_finite()).then_some((min, max))
        });
        let made = self.push(PlanarNode {
            kind,
            source,
            bounds,
        })?;
        self.memo.insert(key, (made, invariant));
        Ok((made, invariant))
    }
}
