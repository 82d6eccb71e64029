//! Parts made of planes only, as convex cells instead of multiplied-out complements.
//!
//! A polygon, a mesh or a stack of cubes is a union of convex cells, and its DNF is one short term
//! per cell; but its complement, by De Morgan, is the product of the cells' complements, and an
//! intersection of two such unions the product of their cells: `A − P` with P a polygon of k cells
//! would multiply k factors. When the builder meets a subtree whose leaves are all planes (half-
//! spaces and slabs, under any transform that keeps them planes) and whose plain expansion would
//! have many more terms than it has planes, it cuts the subtree, complemented or not, into convex
//! cells instead ([`qcsg_mesh::boolean_cells`]): a partition of the box where the accumulated terms
//! lie by the subtree's own planes, simplified region by region, whose constant leaves are the
//! cells of the solid or of its complement. Each term is then intersected with the cells whose
//! boxes it meets. The result is exact (every face of a cell is one of the subtree's planes, an
//! axis-parallel wall or a halving plane), and its size follows the cells near the terms, so a
//! square minus a polygon of n points has O(n) terms, not a product of n factors.
//!
//! The box is the hull of the terms' boxes within what encloses them; along an axis where it is
//! unbounded (a 2-D shape's z), the subtree's planes must not depend on that axis. Where neither
//! holds, or the subtree has a leaf that is not a plane, the ordinary expansion runs.

use std::collections::HashMap;

use qcsg_mesh::{
    BooleanError, BooleanLimits, Bounds, ExprKind, ExprNode, HalfSpaceExpr, Plane, boolean_cells,
};
use qcsg_quadric::{DMat4, DVec3, Quadric};

use super::{Abort, Builder, Context, Term};
use crate::bounds::Aabb;
use crate::box_index::BoxIndex;
use crate::coincident::Rounding;
use crate::dag::{Dag, NodeId, NodeKind, Rgba, Source};
use crate::polyhedron::half_spaces;

/// A plane-only part is cut into cells only when its plain expansion would have more terms than
/// this (and many more than it has planes): smaller products multiply out cheaply.
const EXPANSION_THRESHOLD: u64 = 1024;

/// How many regions the partition may examine per term allowed.
const REGIONS_PER_TERM: usize = 64;

/// For a node whose solid is a boolean of planes: how many terms its plain DNF would have, as
/// is and complemented (saturating), and how many planes its leaves hold along all paths.
#[derive(Clone, Copy, Debug)]
pub(super) struct PlaneSize {
    positive: u64,
    negative: u64,
    planes: u64,
}

/// [`PlaneSize`] of every node (`None` where a leaf below is not a plane or a slab), children
/// first over the arena.
pub(super) fn plane_sizes(dag: &Dag) -> Vec<Option<PlaneSize>> {
    let mut sizes: Vec<Option<PlaneSize>> = Vec::with_capacity(dag.len());
    for node in dag.nodes() {
        let child = |e: &crate::dag::Edge| sizes.get(e.child.0 as usize).copied().flatten();
        let size = match &node.kind {
            NodeKind::Leaf(q) => match plane_count(q) {
                1 => Some(PlaneSize {
                    positive: 1,
                    negative: 1,
                    planes: 1,
                }),
                2 => Some(PlaneSize {
                    positive: 1,
                    negative: 2,
                    planes: 2,
                }),
                _ => None,
            },
            NodeKind::Union(c) | NodeKind::Intersection(c) | NodeKind::Difference(c) => {
                let parts: Option<Vec<PlaneSize>> = c.iter().map(child).collect();
                parts.map(|parts| {
                    let sum = |f: fn(&PlaneSize) -> u64, parts: &[PlaneSize]| {
                        parts.iter().fold(0u64, |a, p| a.saturating_add(f(p)))
                    };
                    let product = |f: fn(&PlaneSize) -> u64, parts: &[PlaneSize]| {
                        parts.iter().fold(1u64, |a, p| a.saturating_mul(f(p)))
                    };
                    let planes = sum(|p| p.planes, &parts);
                    let pos: fn(&PlaneSize) -> u64 = |p| p.positive;
                    let neg: fn(&PlaneSize) -> u64 = |p| p.negative;
                    let (positive, negative) = match &node.kind {
                        NodeKind::Union(_) => (sum(pos, &parts), product(neg, &parts)),
                        NodeKind::Intersection(_) => (product(pos, &parts), sum(neg, &parts)),
                        _ => match parts.split_first() {
                            Some((first, rest)) => (
                                first.positive.saturating_mul(product(neg, rest)),
                                first.negative.saturating_add(sum(pos, rest)),
                            ),
                            None => (0, 1),
                        },
                    };
                    PlaneSize {
                        positive,
                        negative,
                        planes,
                    }
                })
            }
            NodeKind::Complement(e) => child(e).map(|s| PlaneSize {
                positive: s.negative,
                negative: s.positive,
                planes: s.planes,
            }),
            NodeKind::Color(_, e) | NodeKind::Highlight(e) => child(e),
        };
        sizes.push(size);
    }
    sizes
}

/// How many planes bound the quadric's solid: 1 for a half-space, 2 for a slab, 0 otherwise.
fn plane_count(q: &Quadric) -> usize {
    let k = q.coefficients();
    if k[..6].iter().all(|&v| v == 0.0) {
        return usize::from(q.linear() != DVec3::ZERO);
    }
    if half_spaces(q).len() == 2 { 2 } else { 0 }
}

/// One half-space of the flattened part, with what its DNF literal carries.
struct PlaneLiteral {
    quadric: Quadric,
    source: Source,
    color: Option<Rgba>,
    highlight: bool,
    rounding: Rounding,
}

/// A plane-only subtree in world space, complements pushed to its half-spaces.
#[derive(Default)]
struct Flat {
    planes: Vec<Plane>,
    literals: Vec<PlaneLiteral>,
    nodes: Vec<ExprNode>,
}

/// Exact bits of a plane, to find a cell's face among the input planes.
fn plane_bits(p: &Plane) -> [u64; 4] {
    let z = |v: f64| if v == 0.0 { 0 } else { v.to_bits() };
    [z(p.normal.x), z(p.normal.y), z(p.normal.z), z(p.offset)]
}

/// The budget of a plain expansion tried first (see [`Builder::expand_or_cells`]).
pub(super) struct Attempt {
    /// Terms formed so far, summed over the nodes visited.
    pub(super) work: usize,
    /// The most `work` allowed.
    pub(super) budget: usize,
}

/// Terms a plain expansion may form per plane of the part before cells take over, summed over
/// the nodes it visits.
const WORK_PER_PLANE: usize = 16;

/// Terms a plain expansion may hold at once per plane of the part before cells take over.
const TERMS_PER_PLANE: usize = 2;

impl Builder<'_> {
    /// Whether the node `id`, complemented or not, is made of planes and its plain expansion
    /// could multiply out (and no budgeted expansion is running already).
    pub(super) fn wants_cells(&self, id: NodeId, negated: bool) -> bool {
        if self.attempt.is_some() || !self.pruning.plane_cells {
            return false;
        }
        let Some(Some(size)) = self.plane_sizes.get(id.0 as usize).copied() else {
            return false;
        };
        let expansion = if negated {
            size.negative
        } else {
            size.positive
        };
        expansion > EXPANSION_THRESHOLD && expansion / 4 > size.planes
    }

    /// `acc ∩ X` for a part X made of planes (in `ctx`'s frame and sign): the plain expansion
    /// while it stays within a budget near-linear in X's planes (pruning often keeps it small:
    /// holes in a row share their slabs), else X's cells. `enclosing` holds every term formed.
    pub(super) fn expand_or_cells(
        &mut self,
        acc: Vec<Term>,
        id: NodeId,
        ctx: &Context,
        enclosing: Aabb,
    ) -> Result<Vec<Term>, Abort> {
        let planes = self.plane_sizes[id.0 as usize].map_or(0, |s| s.planes) as usize;
        let limit = self.term_limit;
        self.term_limit = limit.min(
            planes
                .saturating_mul(TERMS_PER_PLANE)
                .saturating_add(acc.len())
                .max(256),
        );
        self.attempt = Some(Attempt {
            work: 0,
            budget: planes
                .saturating_mul(WORK_PER_PLANE)
                .saturating_add(acc.len().saturating_mul(8)),
        });
        let tried = self.expand(acc.clone(), id, ctx);
        self.term_limit = limit;
        self.attempt = None;
        // Where the plain expansion crossed the term limit, if it did: the part a diagnostic
        // points at when the cells cross it too.
        let crossed = match tried {
            Ok(terms) => return Ok(terms),
            Err(Abort::TermLimit(at)) => Some(at),
            Err(Abort::OverBudget) => None,
        };
        let source = self.dag.node(id).map(|n| n.source).unwrap_or_default();
        match self.plane_cells(acc, id, source, ctx, enclosing) {
            Ok(Cells::Done(terms)) => Ok(terms),
            Ok(Cells::Skip(acc)) => self.expand(acc, id, ctx),
            Err(Abort::TermLimit(at)) => Err(Abort::TermLimit(crossed.unwrap_or(at))),
            Err(other) => Err(other),
        }
    }
}

/// What happened to the accumulator.
pub(super) enum Cells {
    /// The part was cut into cells: the terms of `acc ∩ part`.
    Done(Vec<Term>),
    /// Not a case for cells: the accumulator, unchanged, for the ordinary expansion.
    Skip(Vec<Term>),
}

impl Builder<'_> {
    /// `acc ∩ X` (or `acc ∩ ¬X` if `ctx.negated`) for the node `id` seen through `ctx.matrix`,
    /// by cells. `enclosing` holds every term formed here.
    fn plane_cells(
        &mut self,
        acc: Vec<Term>,
        id: NodeId,
        source: Source,
        ctx: &Context,
        enclosing: Aabb,
    ) -> Result<Cells, Abort> {
        let node_limit = self.term_limit.saturating_mul(8);
        let mut flat = Flat::default();
        let Some(root) = self.flatten(id, ctx, &mut flat, node_limit) else {
            return Ok(Cells::Skip(acc));
        };
        let region = acc.iter().fold(Aabb::EMPTY, |r, t| {
            r.union(&t.bounds.intersection(&enclosing))
        });
        if region.is_empty() {
            return Ok(Cells::Skip(acc));
        }
        // Walls strictly outside every term, so that they are never a term's literal.
        let region = region.widened_by(1e-3);
        let expr = HalfSpaceExpr {
            nodes: std::mem::take(&mut flat.nodes),
            root,
        };
        let limits = BooleanLimits {
            max_cells: self.term_limit,
            max_regions: self.term_limit.saturating_mul(REGIONS_PER_TERM),
        };
        let cells = match boolean_cells(&flat.planes, &expr, region.min, region.max, true, limits) {
            Ok(cells) => cells,
            Err(BooleanError::TooManyCells | BooleanError::TooManyRegions) => {
                return Err(Abort::TermLimit(source));
            }
            Err(BooleanError::BadBox | BooleanError::BadExpression) => {
                return Ok(Cells::Skip(acc));
            }
        };
        self.stats.plane_parts += 1;
        self.stats.plane_cells += cells.len();
        let index_of: HashMap<[u64; 4], usize> = flat
            .planes
            .iter()
            .enumerate()
            .rev()
            .map(|(i, p)| (plane_bits(p), i))
            .collect();
        let boxes: Vec<Aabb> = cells.iter().map(|c| Aabb::new(c.min, c.max)).collect();
        let index = BoxIndex::new(boxes);
        let mut literal_of: HashMap<[u64; 4], u32> = HashMap::new();
        let mut result: Vec<Term> = Vec::new();
        for term in acc {
            for c in index.near(&term.bounds, 0.0) {
                let cell = &cells[c as usize];
                let mut next = Term {
                    literals: term.literals.clone(),
                    bounds: term.bounds.intersection(&index.boxes()[c as usize]),
                };
                if next.bounds.is_empty() {
                    continue;
                }
                let mut keep = true;
                for plane in &cell.planes {
                    let key = plane_bits(plane);
                    let literal = match literal_of.get(&key) {
                        Some(&l) => l,
                        None => {
                            let l = self.face_literal(plane, &index_of, &flat, source, ctx);
                            literal_of.insert(key, l);
                            l
                        }
                    };
                    if !self.add_literal(&mut next, literal, &enclosing) {
                        keep = false;
                        break;
                    }
                }
                if keep {
                    self.check_limit(result.len() + 1, source)?;
                    result.push(next);
                }
            }
        }
        Ok(Cells::Done(result))
    }

    /// The literal of a cell's face: an input plane (or its complement) with its leaf's source
    /// and colour, or a wall or halving plane of the partition, attributed to the part.
    fn face_literal(
        &mut self,
        plane: &Plane,
        index_of: &HashMap<[u64; 4], usize>,
        flat: &Flat,
        source: Source,
        ctx: &Context,
    ) -> u32 {
        if let Some(&i) = index_of.get(&plane_bits(plane)) {
            let l = &flat.literals[i];
            return self.intern(l.quadric, l.source, l.color, l.highlight, l.rounding);
        }
        if let Some(&i) = index_of.get(&plane_bits(&plane.flipped())) {
            let l = &flat.literals[i];
            return self.intern(
                l.quadric.negated(),
                l.source,
                l.color,
                l.highlight,
                l.rounding,
            );
        }
        // An axis-parallel wall or halving plane: `normal · p ≤ offset` with a unit normal.
        let quadric = Quadric::half_space(plane.normal * plane.offset, plane.normal)
            .or_else(|| Quadric::new(DVec3::ZERO, [0.0; 10]))
            .expect("a finite plane");
        self.intern(
            quadric,
            source,
            ctx.color,
            ctx.highlight,
            Rounding::default(),
        )
    }

    /// The node `id` under `ctx` (its matrix, sign, colour) as half-space expression nodes;
    /// `None` where a leaf is not a plane in world space or the expression grows past `limit`.
    fn flatten(&self, id: NodeId, ctx: &Context, flat: &mut Flat, limit: usize) -> Option<u32> {
        stacker::maybe_grow(128 * 1024, 4 * 1024 * 1024, || {
            self.flatten_inner(id, ctx, flat, limit)
        })
    }

    fn flatten_inner(
        &self,
        id: NodeId,
        ctx: &Context,
        flat: &mut Flat,
        limit: usize,
    ) -> Option<u32> {
        if flat.nodes.len() >= limit {
            return None;
        }
        let node = self.dag.node(id)?;
        let world_box = self.local_boxes[id.0 as usize].transformed(&ctx.matrix);
        let known = world_box.min.is_finite() || world_box.max.is_finite();
        let bounds: Option<Bounds> = known.then_some((world_box.min, world_box.max));
        let (inside, outside) = if ctx.negated {
            (None, bounds)
        } else {
            (bounds, None)
        };
        let children = |this: &Self,
                        flat: &mut Flat,
                        edges: &[(crate::dag::Edge, bool)]|
         -> Option<Vec<u32>> {
            edges
                .iter()
                .map(|&(e, negated)| {
                    let child = Context {
                        matrix: this.world_matrix(e, &ctx.matrix),
                        negated,
                        ..ctx.clone()
                    };
                    this.flatten(e.child, &child, flat, limit)
                })
                .collect()
        };
        let negated = ctx.negated;
        let (kind, list) = match &node.kind {
            NodeKind::Leaf(q) => return self.flatten_leaf(q, node.source, ctx, flat),
            NodeKind::Union(c) | NodeKind::Intersection(c) => {
                let union = matches!(node.kind, NodeKind::Union(_));
                let any = union != negated;
                let list: Vec<_> = c.iter().map(|&e| (e, negated)).collect();
                (any, children(self, flat, &list)?)
            }
            NodeKind::Difference(c) => {
                let list: Vec<_> = c
                    .iter()
                    .enumerate()
                    .map(|(i, &e)| (e, if i == 0 { negated } else { !negated }))
                    .collect();
                (negated, children(self, flat, &list)?)
            }
            NodeKind::Complement(e) => {
                let child = Context {
                    matrix: self.world_matrix(*e, &ctx.matrix),
                    negated: !negated,
                    ..ctx.clone()
                };
                return self.flatten(e.child, &child, flat, limit);
            }
            NodeKind::Color(rgba, e) => {
                let child = Context {
                    matrix: self.world_matrix(*e, &ctx.matrix),
                    color: Some(*rgba),
                    ..ctx.clone()
                };
                return self.flatten(e.child, &child, flat, limit);
            }
            NodeKind::Highlight(e) => {
                let child = Context {
                    matrix: self.world_matrix(*e, &ctx.matrix),
                    highlight: true,
                    ..ctx.clone()
                };
                return self.flatten(e.child, &child, flat, limit);
            }
        };
        flat.nodes.push(ExprNode {
            kind: if kind {
                ExprKind::Any(list)
            } else {
                ExprKind::All(list)
            },
            inside,
            outside,
        });
        Some(flat.nodes.len() as u32 - 1)
    }

    /// A leaf's half-spaces in world space: one for a plane, the two of a slab (both needed, or
    /// either one for its complement).
    fn flatten_leaf(
        &self,
        q: &Quadric,
        source: Source,
        ctx: &Context,
        flat: &mut Flat,
    ) -> Option<u32> {
        let world = if ctx.matrix == DMat4::IDENTITY {
            q.normalized()
        } else {
            q.transformed(&ctx.matrix)?
        };
        let rounding = Rounding::of_placement(&ctx.matrix, q.origin());
        let add = |flat: &mut Flat, quadric: Quadric, plane: Plane| -> u32 {
            flat.planes.push(plane);
            flat.literals.push(PlaneLiteral {
                quadric,
                source,
                color: ctx.color,
                highlight: ctx.highlight,
                rounding,
            });
            flat.nodes.push(ExprNode {
                kind: ExprKind::HalfSpace(flat.planes.len() as u32 - 1),
                inside: None,
                outside: None,
            });
            flat.nodes.len() as u32 - 1
        };
        let k = world.coefficients();
        if k[..6].iter().all(|&v| v == 0.0) {
            // 2 l·(p − o) + j ≤ 0  ⟺  l̂·p ≤ l̂·o − j / (2|l|).
            let l = world.linear();
            let length = l.length();
            if length == 0.0 || !length.is_finite() {
                return None;
            }
            let normal = l / length;
            let plane = Plane {
                normal,
                offset: normal.dot(world.origin()) - world.constant() / (2.0 * length),
            };
            if !plane.offset.is_finite() {
                return None;
            }
            return Some(if ctx.negated {
                add(flat, world.negated(), plane.flipped())
            } else {
                add(flat, world, plane)
            });
        }
        let halves = half_spaces(&world);
        if halves.len() != 2 {
            return None;
        }
        let mut ids = Vec::with_capacity(2);
        for h in halves {
            let (normal, offset) = if ctx.negated {
                (-h.normal, -h.offset)
            } else {
                (h.normal, h.offset)
            };
            let quadric = Quadric::half_space(normal * offset, normal)?;
            ids.push(add(flat, quadric, Plane { normal, offset }));
        }
        flat.nodes.push(ExprNode {
            kind: if ctx.negated {
                ExprKind::Any(ids)
            } else {
                ExprKind::All(ids)
            },
            inside: None,
            outside: None,
        });
        Some(flat.nodes.len() as u32 - 1)
    }
}
