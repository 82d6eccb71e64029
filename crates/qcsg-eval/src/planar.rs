//! 2-D shapes as plane figures: a 2-D subtree of the DAG as an expression of conics in the
//! xy-plane, and back.
//!
//! In qcsg a 2-D shape is a **z-invariant solid**: its leaves are quadrics without `z` (edges
//! are half-spaces and slabs with normals ⟂ z, circles and ellipses are cylinders along z) and
//! the transforms above them act in the xy-plane only ([`planar_matrix`]). Operations on 2-D
//! shapes (`linear_extrude` with `scale`, and later `rotate_extrude`, `offset`, `projection`)
//! need the plane figure itself: [`planar_expression`] walks the subtree behind an edge and
//! returns a flat arena of [`Conic`] leaves, each with every transform above it folded in, and
//! the booleans between them; [`rebuild`] turns such an arena back into DAG nodes, the caller
//! mapping each conic to a 3-D solid. Shared sub-shapes seen through the same transform stay
//! shared; a limit on the arena's size bounds the work on a DAG with many paths.
//!
//! ```
//! use qcsg_csg::{Aabb, Dag, Source};
//! use qcsg_eval::planar::{Conic, planar_expression, rebuild};
//! use glam::{DVec2, DVec3};
//! use qcsg_quadric::Quadric;
//!
//! let mut dag = Dag::new();
//! let at = Source::default();
//! // circle(2) as a z-invariant solid, moved by [5, 0].
//! let disc = dag.leaf(Quadric::cylinder(DVec3::ZERO, DVec3::Z, 2.0).unwrap(), at);
//! let moved = dag.translated(disc.into(), DVec3::new(5.0, 0.0, 0.0)).unwrap();
//! let expr = planar_expression(&dag, moved, 1000).unwrap();
//! let conic: &Conic = expr.leaves().next().unwrap();
//! assert!(conic.value(DVec2::new(6.5, 0.0)) < 0.0 && conic.value(DVec2::ZERO) > 0.0);
//! // Back to 3-D: each conic becomes the z-invariant quadric it describes.
//! let solid = rebuild(
//!     &mut dag,
//!     &expr,
//!     |dag: &mut Dag, conic: &Conic, source| -> Result<_, ()> {
//!         Ok(dag.leaf(conic.to_cylinder().ok_or(())?, source).into())
//!     },
//!     |min, max| Aabb::new(min.extend(f64::NEG_INFINITY), max.extend(f64::INFINITY)),
//! )
//! .unwrap();
//! assert!(dag.edge_contains(solid, DVec3::new(6.5, 0.0, 100.0)));
//! ```

use std::collections::HashMap;

use glam::{DMat3, DMat4, DVec2, DVec3, DVec4};
use qcsg_csg::{Aabb, Dag, Edge, NodeId, NodeKind, Source};
use qcsg_quadric::Quadric;

/// The xy part of a 3-D transform, as OpenSCAD 2021.01 applies a transform to a 2-D shape: rows
/// and columns x, y and w of the 4×4 matrix, with z left alone. The result maps z-invariant
/// solids to z-invariant solids (a projective row maps `z` to `z / w`, which keeps every line
/// along z a line along z).
pub fn planar_matrix(m: &DMat4) -> DMat4 {
    let r = |i: usize| m.row(i);
    let (x, y, w) = (r(0), r(1), r(3));
    DMat4::from_cols(
        DVec4::new(x.x, y.x, 0.0, w.x),
        DVec4::new(x.y, y.y, 0.0, w.y),
        DVec4::new(0.0, 0.0, 1.0, 0.0),
        DVec4::new(x.w, y.w, 0.0, w.w),
    )
}

/// The plane homography (3×3, on `(x, y, 1)`) of a matrix made by [`planar_matrix`].
fn homography(m: &DMat4) -> DMat3 {
    let r = |i: usize| m.row(i);
    let (x, y, w) = (r(0), r(1), r(3));
    DMat3::from_cols(
        DVec3::new(x.x, y.x, w.x),
        DVec3::new(x.y, y.y, w.y),
        DVec3::new(x.w, y.w, w.w),
    )
}

/// A plane figure bounded by a conic: the points where `[X, Y, 1] · matrix · [X, Y, 1]ᵀ ≤ 0`,
/// with `(X, Y) = (x, y) − origin` (about an origin, as quadrics are, so coefficients stay
/// well-conditioned far from the world's origin). `matrix` is symmetric. A half-plane has a
/// zero upper-left 2×2 block, a strip between parallel lines a rank-one block.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Conic {
    /// The point the coefficients are written about.
    pub origin: DVec2,
    /// The symmetric 3×3 matrix of the form.
    pub matrix: DMat3,
}

impl Conic {
    /// The conic's value at the world point `p`: negative inside, positive outside.
    pub fn value(&self, p: DVec2) -> f64 {
        let v = (p - self.origin).extend(1.0);
        v.dot(self.matrix * v)
    }

    /// `[a, b, d, g, h, j]` of `a X² + b Y² + 2d XY + 2g X + 2h Y + j` about [`Conic::origin`].
    pub fn coefficients(&self) -> [f64; 6] {
        let m = &self.matrix;
        [
            m.x_axis.x, m.y_axis.y, m.y_axis.x, m.z_axis.x, m.z_axis.y, m.z_axis.z,
        ]
    }

    /// Whether the form is linear (a half-plane): no quadratic term.
    pub fn is_linear(&self) -> bool {
        let [a, b, d, ..] = self.coefficients();
        a == 0.0 && b == 0.0 && d == 0.0
    }

    /// The z-invariant quadric (a cylinder along z over the conic) this conic describes.
    pub fn to_cylinder(&self) -> Option<Quadric> {
        let [a, b, d, g, h, j] = self.coefficients();
        Quadric::new(
            self.origin.extend(0.0),
            [a, b, 0.0, d, 0.0, 0.0, g, h, 0.0, j],
        )
    }

    /// The conic of a z-invariant quadric (no `z` in its form), or `None` if it depends on z.
    pub fn from_quadric(q: &Quadric) -> Option<Conic> {
        let k = q.coefficients();
        if k[2] != 0.0 || k[4] != 0.0 || k[5] != 0.0 || k[8] != 0.0 {
            return None;
        }
        let matrix = DMat3::from_cols(
            DVec3::new(k[0], k[3], k[6]),
            DVec3::new(k[3], k[1], k[7]),
            DVec3::new(k[6], k[7], k[9]),
        );
        Some(Conic {
            origin: q.origin().truncate(),
            matrix,
        })
    }

    /// The image of the figure under the plane homography `h` (points map as `p' ~ h p`);
    /// `None` if `h` is singular or the result is not finite.
    pub fn transformed(&self, h: &DMat3) -> Option<Conic> {
        let det = h.determinant();
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        let affine = h.x_axis.z == 0.0 && h.y_axis.z == 0.0 && h.z_axis.z != 0.0;
        let out = if affine {
            // Move the origin with the figure: X' = L X, so M' = Nᵀ M N with N = diag(L⁻¹, 1).
            let h = *h * (1.0 / h.z_axis.z);
            let origin = (h * self.origin.extend(1.0)).truncate();
            let linear = glam::DMat2::from_cols(h.x_axis.truncate(), h.y_axis.truncate());
            let inverse = linear.inverse();
            let n = DMat3::from_cols(
                inverse.x_axis.extend(0.0),
                inverse.y_axis.extend(0.0),
                DVec3::Z,
            );
            Conic {
                origin,
                matrix: n.transpose() * self.matrix * n,
            }
        } else {
            // Projective: write the form about the world origin, then M' = H⁻ᵀ M H⁻¹.
            let o = self.origin;
            let shift = DMat3::from_cols(DVec3::X, DVec3::Y, DVec3::new(-o.x, -o.y, 1.0));
            let absolute = shift.transpose() * self.matrix * shift;
            let inverse = h.inverse();
            Conic {
                origin: DVec2::ZERO,
                matrix: inverse.transpose() * absolute * inverse,
            }
        };
        let symmetric = 0.5 * (out.matrix + out.matrix.transpose());
        let out = Conic {
            matrix: symmetric,
            ..out
        };
        (out.origin.is_finite() && out.matrix.is_finite()).then_some(out)
    }

    /// A strip between two parallel lines (a rank-one quadratic part `λ (u·X)²` with the
    /// linear part along `u`) as its two half-planes; `None` for any other conic.
    pub fn split_strip(&self) -> Option<[Conic; 2]> {
        let [a, b, d, g, h, j] = self.coefficients();
        let trace = a + b;
        if trace <= 0.0 || !trace.is_finite() {
            return None;
        }
        let det = a * b - d * d;
        if det.abs() > 1e-12 * trace * trace {
            return None;
        }
        // u: the eigenvector of the non-zero eigenvalue λ = trace.
        let u = if a >= b {
            DVec2::new(a, d)
        } else {
            DVec2::new(d, b)
        }
        .normalize_or_zero();
        if u == DVec2::ZERO {
            return None;
        }
        let lambda = trace;
        let linear = DVec2::new(g, h);
        let mu = linear.dot(u);
        if (linear - mu * u).length() > 1e-12 * (linear.length() + lambda) {
            return None;
        }
        // λ s² + 2μ s + j ≤ 0 for s = u·X: s between the roots.
        let disc = mu * mu - lambda * j;
        if disc.is_nan() || disc <= 0.0 {
            return None;
        }
        let root = disc.sqrt();
        let (s1, s2) = ((-mu - root) / lambda, (-mu + root) / lambda);
        let half = |n: DVec2, c: f64| Conic {
            origin: self.origin,
            // 2 (n/2)·X − c ≤ 0  ⟺  n·X ≤ c.
            matrix: DMat3::from_cols(
                DVec3::new(0.0, 0.0, 0.5 * n.x),
                DVec3::new(0.0, 0.0, 0.5 * n.y),
                DVec3::new(0.5 * n.x, 0.5 * n.y, -c),
            ),
        };
        Some([half(u, s2), half(-u, -s1)])
    }
}

/// Handle of a node of a [`PlanarExpr`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct PlanarId(pub u32);

/// What a node of a [`PlanarExpr`] is.
#[derive(Clone, Debug, PartialEq)]
pub enum PlanarKind {
    /// The figure of one conic, in world coordinates of the plane.
    Leaf(Conic),
    /// The union of the children (none: empty).
    Union(Vec<PlanarId>),
    /// The intersection of the children (at least one).
    Intersection(Vec<PlanarId>),
    /// The first child minus the others (at least one).
    Difference(Vec<PlanarId>),
    /// Everything outside the child.
    Complement(PlanarId),
}

/// One node of a [`PlanarExpr`].
#[derive(Clone, Debug, PartialEq)]
pub struct PlanarNode {
    /// What it is.
    pub kind: PlanarKind,
    /// The code that made the DAG node it comes from.
    pub source: Source,
    /// A box `[min, max]` of the plane known to contain the figure, where the DAG declared one.
    pub bounds: Option<(DVec2, DVec2)>,
}

/// A 2-D shape as booleans of conic figures: an arena in which children precede their parents.
#[derive(Clone, Debug, PartialEq)]
pub struct PlanarExpr {
    /// The nodes.
    pub nodes: Vec<PlanarNode>,
    /// The node of the whole shape.
    pub root: PlanarId,
}

impl PlanarExpr {
    /// The node behind `id`.
    pub fn node(&self, id: PlanarId) -> &PlanarNode {
        &self.nodes[id.0 as usize]
    }

    /// Every conic leaf, in arena order.
    pub fn leaves(&self) -> impl Iterator<Item = &Conic> {
        self.nodes.iter().filter_map(|n| match &n.kind {
            PlanarKind::Leaf(c) => Some(c),
            _ => None,
        })
    }

    /// Whether the plane point `p` lies in the shape (closed), by direct evaluation.
    pub fn contains(&self, p: DVec2) -> bool {
        let mut inside = Vec::with_capacity(self.nodes.len());
        for node in &self.nodes {
            let at = |id: &PlanarId, inside: &[bool]| inside[id.0 as usize];
            let value = match &node.kind {
                PlanarKind::Leaf(c) => c.value(p) <= 0.0,
                PlanarKind::Union(c) => c.iter().any(|id| at(id, &inside)),
                PlanarKind::Intersection(c) => c.iter().all(|id| at(id, &inside)),
                PlanarKind::Difference(c) => {
                    c.first().is_some_and(|id| at(id, &inside))
                        && !c[1..].iter().any(|id| at(id, &inside))
                }
                PlanarKind::Complement(id) => !at(id, &inside),
            };
            inside.push(value);
        }
        inside[self.root.0 as usize]
    }
}

/// Why a subtree is no plane figure.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlanarError {
    /// A leaf whose quadric depends on z, or a transform that mixes z into x and y: the subtree
    /// is not a 2-D shape. The source of the offending node.
    NotPlanar(Source),
    /// The expression would have more nodes than the limit (a DAG whose shared parts are seen
    /// through many different transforms).
    TooLarge(usize),
}

impl std::fmt::Display for PlanarError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            PlanarError::NotPlanar(_) => f.write_str("the shape is not a 2-D shape"),
            PlanarError::TooLarge(limit) => write!(
                f,
                "the 2-D shape has more than {limit} parts once its transforms are applied"
            ),
        }
    }
}

/// The 2-D shape behind `edge` (seen in the frame of the edge's parent) as conic leaves with
/// every transform folded in, at most `max_nodes` nodes. Colours and highlights are passed
/// through; shared nodes reached through the same transform become one node.
pub fn planar_expression(
    dag: &Dag,
    edge: Edge,
    max_nodes: usize,
) -> Result<PlanarExpr, PlanarError> {
    let mut builder = Builder {
        dag,
        nodes: Vec::new(),
        memo: HashMap::new(),
        max_nodes,
    };
    let matrix = dag.matrix(edge.transform);
    let root = builder.edge(edge.child, &matrix)?;
    Ok(PlanarExpr {
        nodes: builder.nodes,
        root,
    })
}

struct Builder<'d> {
    dag: &'d Dag,
    nodes: Vec<PlanarNode>,
    memo: HashMap<(NodeId, [u64; 16]), PlanarId>,
    max_nodes: usize,
}

impl Builder<'_> {
    fn push(&mut self, node: PlanarNode) -> Result<PlanarId, PlanarError> {
        if self.nodes.len() >= self.max_nodes {
            return Err(PlanarError::TooLarge(self.max_nodes));
        }
        self.nodes.push(node);
        Ok(PlanarId(self.nodes.len() as u32 - 1))
    }

    /// The node `id` seen through `world` (its frame to the plane's).
    fn edge(&mut self, id: NodeId, world: &DMat4) -> Result<PlanarId, PlanarError> {
        stacker::maybe_grow(128 * 1024, 4 * 1024 * 1024, || self.edge_inner(id, world))
    }

    fn edge_inner(&mut self, id: NodeId, world: &DMat4) -> Result<PlanarId, PlanarError> {
        let key = (id, world.to_cols_array().map(f64::to_bits));
        if let Some(&done) = self.memo.get(&key) {
            return Ok(done);
        }
        let Some(node) = self.dag.node(id) else {
            return self.push(PlanarNode {
                kind: PlanarKind::Union(Vec::new()),
                source: Source::default(),
                bounds: None,
            });
        };
        let source = node.source;
        if *world != planar_matrix(world) {
            return Err(PlanarError::NotPlanar(source));
        }
        let children = |this: &mut Self, edges: &[Edge]| -> Result<Vec<PlanarId>, PlanarError> {
            edges
                .iter()
                .map(|e| {
                    let m = *world * this.dag.matrix(e.transform);
                    this.edge(e.child, &m)
                })
                .collect()
        };
        let kind = match &node.kind {
            NodeKind::Leaf(q) => {
                let conic = Conic::from_quadric(q)
                    .and_then(|c| c.transformed(&homography(world)))
                    .ok_or(PlanarError::NotPlanar(source))?;
                PlanarKind::Leaf(conic)
            }
            NodeKind::Union(c) => PlanarKind::Union(children(self, c)?),
            NodeKind::Intersection(c) => PlanarKind::Intersection(children(self, c)?),
            NodeKind::Difference(c) => PlanarKind::Difference(children(self, c)?),
            NodeKind::Complement(e) => {
                PlanarKind::Complement(children(self, std::slice::from_ref(e))?[0])
            }
            NodeKind::Color(_, e) | NodeKind::Highlight(e) => {
                let m = *world * self.dag.matrix(e.transform);
                let inner = self.edge(e.child, &m)?;
                self.memo.insert(key, inner);
                return Ok(inner);
            }
        };
        let bounds = node.bounds.and_then(|b| {
            let b = b.transformed(world);
            let (min, max) = (b.min.truncate(), b.max.truncate());
            (min.is_finite() && max.is_finite()).then_some((min, max))
        });
        let made = self.push(PlanarNode {
            kind,
            source,
            bounds,
        })?;
        self.memo.insert(key, made);
        Ok(made)
    }
}

/// DAG nodes for `expr`: `leaf` makes the solid of each conic leaf (with its source), inner
/// nodes become unions, intersections, differences and complements with their sources, and
/// every node whose figure has a known box declares `boxed(min, max)`, the caller's 3-D box of
/// the plane box. Returns the edge of the root; the first error of `leaf` stops it.
pub fn rebuild<E>(
    dag: &mut Dag,
    expr: &PlanarExpr,
    mut leaf: impl FnMut(&mut Dag, &Conic, Source) -> Result<Edge, E>,
    boxed: impl Fn(DVec2, DVec2) -> Aabb,
) -> Result<Edge, E> {
    let mut made: Vec<Edge> = Vec::with_capacity(expr.nodes.len());
    for node in &expr.nodes {
        let ids = |c: &[PlanarId], made: &[Edge]| -> Vec<Edge> {
            c.iter().map(|id| made[id.0 as usize]).collect()
        };
        let id = match &node.kind {
            PlanarKind::Leaf(conic) => {
                made.push(leaf(dag, conic, node.source)?);
                continue;
            }
            PlanarKind::Union(c) => dag.union(ids(c, &made), node.source),
            PlanarKind::Intersection(c) => dag.intersection(ids(c, &made), node.source),
            PlanarKind::Difference(c) => dag.difference(ids(c, &made), node.source),
            PlanarKind::Complement(c) => dag.complement(made[c.0 as usize], node.source),
        };
        let id = match node.bounds {
            Some((min, max)) => dag.bounded(id, boxed(min, max)),
            None => id,
        };
        made.push(id.into());
    }
    Ok(made[expr.root.0 as usize])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square_dag(dag: &mut Dag) -> NodeId {
        let at = Source::default();
        let centre = DVec3::new(1.0, 1.0, 0.0);
        let x = dag.leaf(Quadric::slab(centre, DVec3::X, 1.0).unwrap(), at);
        let y = dag.leaf(Quadric::slab(centre, DVec3::Y, 1.0).unwrap(), at);
        dag.intersection([x.into(), y.into()], at)
    }

    #[test]
    fn transforms_fold_into_the_leaves() {
        let mut dag = Dag::new();
        let square = square_dag(&mut dag);
        let m = crate::transforms::rotate_xyz(0.0, 0.0, 90.0)
            * DMat4::from_translation(DVec3::new(3.0, 0.0, 0.0));
        let edge = dag.edge(square, &m).unwrap();
        let expr = planar_expression(&dag, edge, 100).unwrap();
        assert_eq!(expr.leaves().count(), 2);
        // [3, 5] × [0, 2] turned by 90°: [-2, 0] × [3, 5].
        assert!(expr.contains(DVec2::new(-1.0, 4.0)));
        assert!(!expr.contains(DVec2::new(1.0, 4.0)));
        assert!(!expr.contains(DVec2::new(4.0, 1.0)));
    }

    #[test]
    fn three_d_transforms_are_refused() {
        let mut dag = Dag::new();
        let square = square_dag(&mut dag);
        let m = crate::transforms::rotate_xyz(90.0, 0.0, 0.0);
        let edge = dag.edge(square, &m).unwrap();
        assert!(matches!(
            planar_expression(&dag, edge, 100),
            Err(PlanarError::NotPlanar(_))
        ));
        let ball = dag.leaf(
            Quadric::sphere(DVec3::ZERO, 1.0).unwrap(),
            Source::default(),
        );
        assert!(planar_expression(&dag, ball.into(), 100).is_err());
    }

    #[test]
    fn sharing_is_kept_and_limited() {
        let mut dag = Dag::new();
        let square = square_dag(&mut dag);
        let mut node = square;
        for _ in 0..60 {
            let moved = dag
                .translated(node.into(), DVec3::new(0.5, 0.0, 0.0))
                .unwrap();
            node = dag.union([node.into(), moved], Source::default());
        }
        // 2^60 paths, but translations add up: level k is reached through k + 1 distinct
        // offsets, so the arena grows with the square of the depth, not with the paths.
        let expr = planar_expression(&dag, node.into(), 10_000).unwrap();
        assert!(expr.nodes.len() < 6_000, "{}", expr.nodes.len());
        assert!(expr.contains(DVec2::new(31.5, 1.0)) && !expr.contains(DVec2::new(33.0, 1.0)));
        assert!(matches!(
            planar_expression(&dag, node.into(), 100),
            Err(PlanarError::TooLarge(100))
        ));
        let small = planar_expression(&dag, square.into(), 10).unwrap();
        assert_eq!(small.nodes.len(), 3);
    }

    #[test]
    fn strips_split_into_half_planes() {
        let q = Quadric::slab(DVec3::new(2.0, 0.0, 0.0), DVec3::new(1.0, 1.0, 0.0), 1.0).unwrap();
        let conic = Conic::from_quadric(&q).unwrap();
        let [a, b] = conic.split_strip().unwrap();
        assert!(a.is_linear() && b.is_linear());
        for p in [
            DVec2::new(2.0, 0.0),
            DVec2::new(2.6, 0.6),
            DVec2::new(3.0, 0.5),
            DVec2::new(0.0, 0.0),
        ] {
            let inside = conic.value(p) <= 0.0;
            assert_eq!(inside, a.value(p) <= 0.0 && b.value(p) <= 0.0, "{p}");
        }
        let disc = Conic::from_quadric(&Quadric::cylinder(DVec3::ZERO, DVec3::Z, 1.0).unwrap());
        assert!(disc.unwrap().split_strip().is_none());
    }

    #[test]
    fn projective_transforms_keep_the_figure() {
        let disc =
            Conic::from_quadric(&Quadric::cylinder(DVec3::ZERO, DVec3::Z, 1.0).unwrap()).unwrap();
        let h = DMat3::from_cols(DVec3::X, DVec3::Y, DVec3::new(0.0, 0.0, 1.0))
            * DMat3::from_cols(
                DVec3::new(1.0, 0.0, 0.1),
                DVec3::new(0.0, 1.0, 0.0),
                DVec3::new(0.0, 0.0, 1.0),
            );
        let image = disc.transformed(&h).unwrap();
        for p in [
            DVec2::new(0.9, 0.0),
            DVec2::new(-0.9, 0.2),
            DVec2::new(1.1, 0.0),
        ] {
            let q = h * p.extend(1.0);
            let q = q.truncate() / q.z;
            assert_eq!(disc.value(p) <= 0.0, image.value(q) <= 0.0, "{p}");
        }
    }
}
