//! DAG → DNF (paper 000 §5): a union of intersections of world-space quadrics.
//!
//! Complements are pushed to the leaves by De Morgan and folded into the quadric by negation;
//! transforms are composed along each path and folded into the quadric (eq. 17,
//! [`Quadric::transformed`]). Every term carries a box in world space that contains it: the
//! intersection of its literals' own boxes and of the boxes of the nodes it came through, which
//! keeps a rotated cube's term bounded although each of its slabs is unbounded.
//!
//! The expansion is driven by an accumulator: `and_into(terms, X)` returns the DNF of
//! `terms ∩ X`. Conjunctions fold their operands into the accumulator one by one; disjunctions
//! run each operand against a copy and concatenate. Because the accumulator's terms already know
//! their boxes, a subtracted operand that misses a term's box is skipped for that term, and a
//! literal that is provably false (or true) over a term's box ends (or skips) that term before
//! anything multiplies. The term limit is checked before terms are added, so a blow-up becomes a
//! diagnostic at the node that caused it.
//!
//! A region restricts the whole computation: the result then satisfies
//! `(⋃ terms) ∩ region = solid ∩ region`, which is what a later spatially local DNF needs.

mod plane_cells;

use std::collections::{HashMap, HashSet};

use rustc_hash::FxHashMap;

use qcsg_diag::{Diagnostic, Span};
use qcsg_quadric::{DMat4, Quadric};

use crate::bounds::Aabb;
use crate::codes;
use crate::coincident::{Rounding, Surfaces, find_surfaces};
use crate::dag::{Dag, Edge, NodeId, NodeKind, Rgba, Source};
use crate::polyhedron::{HalfSpace, half_spaces, polyhedron_bounds};
use crate::prune;
pub use crate::prune::Pruning;
use crate::quadric_box::{
    BoxClass, classify, clip_outside_interval, excluded_interval, solid_bounds,
};
use crate::stats::DnfStats;

/// OpenSCAD's default preview limit on CSG terms.
pub const DEFAULT_TERM_LIMIT: usize = 100_000;

/// Tolerance (relative to the largest coefficient) under which two quadrics count as equal.
pub const DUPLICATE_TOLERANCE: f64 = 1e-12;

/// How to build a DNF.
#[derive(Clone, Debug, PartialEq)]
pub struct DnfOptions {
    /// Only the part of the solid inside this box is wanted; `None` for all of it.
    pub region: Option<Aabb>,
    /// The most terms the DNF (or any intermediate stage of it) may have.
    pub term_limit: usize,
    /// Run the pruning passes over the finished DNF (those `pruning` leaves on); false turns
    /// all of them off at once.
    pub prune: bool,
    /// Which pruning rules run, during construction and in the final passes (all by default).
    pub pruning: Pruning,
}

impl Default for DnfOptions {
    fn default() -> Self {
        Self {
            region: None,
            term_limit: DEFAULT_TERM_LIMIT,
            prune: true,
            pruning: Pruning::all(),
        }
    }
}

/// One quadric of the DNF, in world space, with what the renderer needs to draw it.
#[derive(Clone, Debug, PartialEq)]
pub struct DnfQuadric {
    /// The world-space quadric; the literal is `quadric ≤ 0`.
    pub quadric: Quadric,
    /// The leaf it came from.
    pub source: Source,
    /// The innermost colour above the leaf, if any.
    pub color: Option<Rgba>,
    /// Whether the leaf lies below a highlight (`#`).
    pub highlight: bool,
    /// The rounding its coefficients and origin carry from the transform that placed it, which
    /// bounds how far it may be from the surface it stands for ([`crate::coincident`]).
    pub rounding: Rounding,
}

/// One term: the intersection of its literals, contained in its box.
#[derive(Clone, Debug, PartialEq)]
pub struct Term {
    /// Indices into [`Dnf::quadrics`], ascending and distinct.
    pub literals: Vec<u32>,
    /// A world-space box containing the term (within the region, if there is one).
    pub bounds: Aabb,
}

/// A solid in disjunctive normal form: `⋃_terms ⋂_literals {p : q(p) ≤ 0}`.
#[derive(Clone, Debug, PartialEq)]
pub struct Dnf {
    /// The quadric table; terms refer to it by index.
    pub quadrics: Vec<DnfQuadric>,
    /// The terms.
    pub terms: Vec<Term>,
    /// The union of the term boxes.
    pub bounds: Aabb,
    /// The region it was restricted to, if any.
    pub region: Option<Aabb>,
    /// What construction and pruning did.
    pub stats: DnfStats,
    /// Warnings met on the way (e.g. parts dropped under singular transforms).
    pub warnings: Vec<Diagnostic>,
    /// Which quadrics are the same surface: each quadric's sheets, with a surface id and
    /// orientation ([`crate::coincident`]).
    pub surfaces: Surfaces,
}

impl Dnf {
    /// Whether the world point `p` lies in the solid (closed). With a region, only points in
    /// the region are answered faithfully; points outside it are reported outside.
    pub fn contains(&self, p: qcsg_quadric::DVec3) -> bool {
        if let Some(region) = &self.region
            && !region.contains(p)
        {
            return false;
        }
        self.terms.iter().any(|term| {
            term.literals.iter().all(|&id| {
                self.quadrics
                    .get(id as usize)
                    .is_some_and(|q| q.quadric.value(p) <= 0.0)
            })
        })
    }

    /// Number of literal occurrences over all terms.
    pub fn literal_count(&self) -> usize {
        self.terms.iter().map(|t| t.literals.len()).sum()
    }
}

/// Builds the DNF of the DAG's root.
///
/// Errors: no root ([`codes::NO_ROOT`]), the term limit crossed ([`codes::TERM_LIMIT`], at the
/// node whose expansion crossed it), an unbounded result without a region
/// ([`codes::UNBOUNDED`], at the unbounded part).
pub fn build_dnf(dag: &Dag, options: &DnfOptions) -> Result<Dnf, Vec<Diagnostic>> {
    let Some(root) = dag.root() else {
        return Err(vec![Diagnostic::error(
            codes::NO_ROOT,
            "the scene has no root solid",
            Default::default(),
            Span::default(),
        )]);
    };
    build_dnf_of(dag, root, options)
}

/// Builds the DNF of the solid behind `root` (e.g. one of [`Dag::backgrounds`]).
pub fn build_dnf_of(dag: &Dag, root: Edge, options: &DnfOptions) -> Result<Dnf, Vec<Diagnostic>> {
    let region = options.region.unwrap_or(Aabb::EVERYTHING);
    let mut builder = Builder::new(dag, options);
    let start = vec![Term {
        literals: Vec::new(),
        bounds: region,
    }];
    let ctx = Context {
        matrix: DMat4::IDENTITY,
        negated: false,
        color: None,
        highlight: false,
        enclosing: region,
    };
    let mut terms = match builder.and_into(start, root, &ctx) {
        Ok(terms) => terms,
        Err(abort) => {
            // A budget is only set inside an attempt, which never lets it escape.
            let source = match abort {
                Abort::TermLimit(source) => source,
                Abort::OverBudget => dag.node(root.child).map(|n| n.source).unwrap_or_default(),
            };
            return Err(vec![
                Diagnostic::error(
                    codes::TERM_LIMIT,
                    format!(
                        "the solid's normal form needs more than {} terms",
                        options.term_limit
                    ),
                    source.file,
                    source.span,
                )
                .with_help(
                    "raise the limit with `--max-terms N` on the command line, or split the \
                     operation so that fewer parts overlap",
                ),
            ]);
        }
    };
    bound_by_planes(&mut terms, &builder.literals);
    let mut stats = DnfStats {
        dag_nodes: dag.len(),
        background_parts: dag.backgrounds().len(),
        construction: builder.stats.clone(),
        ..DnfStats::default()
    };
    let literals: Vec<DnfQuadric> = builder
        .literals
        .iter()
        .map(|l| DnfQuadric {
            quadric: l.quadric,
            source: l.source,
            color: l.color,
            highlight: l.highlight,
            rounding: l.rounding,
        })
        .collect();
    let own_boxes: Vec<Aabb> = builder.literals.iter().map(|l| l.own_box).collect();
    let mut dnf = Dnf {
        quadrics: literals,
        terms,
        bounds: Aabb::EMPTY,
        region: options.region,
        stats: DnfStats::default(),
        warnings: builder.warnings,
        surfaces: Surfaces::default(),
    };
    prune::finish(
        &mut dnf,
        &own_boxes,
        region,
        options.prune,
        &options.pruning,
        &mut stats,
    );
    if options.region.is_none() {
        let errors = unbounded_diagnostics(&dnf, &own_boxes_after(&dnf), dag, root);
        if !errors.is_empty() {
            return Err(errors);
        }
    }
    dnf.surfaces = surfaces_of(&dnf);
    dnf.bounds = dnf
        .terms
        .iter()
        .fold(Aabb::EMPTY, |acc, t| acc.union(&t.bounds));
    stats.terms = dnf.terms.len();
    stats.literals = dnf.literal_count();
    stats.quadrics = dnf.quadrics.len();
    dnf.stats = stats;
    Ok(dnf)
}

/// Gives terms that their literals' boxes leave unbounded the box of the polyhedron formed by
/// their planar literals, when that is bounded.
fn bound_by_planes(terms: &mut [Term], literals: &[Literal]) {
    let mut planes_of: HashMap<u32, Vec<HalfSpace>> = HashMap::new();
    for term in terms.iter_mut().filter(|t| !t.bounds.is_bounded()) {
        let mut planes = Vec::new();
        for &id in &term.literals {
            let entry = planes_of
                .entry(id)
                .or_insert_with(|| half_spaces(&literals[id as usize].quadric));
            planes.extend_from_slice(entry);
        }
        if let Some(bounds) = polyhedron_bounds(&planes) {
            term.bounds = term.bounds.intersection(&bounds);
        }
    }
}

/// The surfaces of a DNF's quadric table ([`crate::coincident`]).
pub fn surfaces_of(dnf: &Dnf) -> Surfaces {
    find_surfaces(dnf.quadrics.iter().map(|q| (&q.quadric, q.rounding)))
}

fn own_boxes_after(dnf: &Dnf) -> Vec<Aabb> {
    dnf.quadrics
        .iter()
        .map(|q| solid_bounds(&q.quadric))
        .collect()
}

/// One error per unbounded part (at most a few), pointing at a literal of an unbounded term
/// that is unbounded on its own.
fn unbounded_diagnostics(dnf: &Dnf, own_boxes: &[Aabb], dag: &Dag, root: Edge) -> Vec<Diagnostic> {
    const MAX_REPORTS: usize = 4;
    let mut seen = HashSet::new();
    let mut errors = Vec::new();
    for term in &dnf.terms {
        if term.bounds.is_bounded() {
            continue;
        }
        let unbounded: Vec<u32> = term
            .literals
            .iter()
            .copied()
            .filter(|&id| !own_boxes[id as usize].is_bounded())
            .collect();
        let primary = unbounded
            .first()
            .map(|&id| dnf.quadrics[id as usize].source)
            .or_else(|| dag.node(root.child).map(|n| n.source))
            .unwrap_or_default();
        if !seen.insert(primary) {
            continue;
        }
        let mut diagnostic = Diagnostic::error(
            codes::UNBOUNDED,
            if term.literals.is_empty() {
                "the solid is unbounded: it is all of space".to_string()
            } else {
                "the solid is unbounded: this part extends to infinity".to_string()
            },
            primary.file,
            primary.span,
        )
        .with_help("intersect it with a bounded solid");
        for &id in unbounded.iter().skip(1).take(3) {
            let s = dnf.quadrics[id as usize].source;
            if s != primary {
                diagnostic =
                    diagnostic.with_label(s.file, s.span, "also unbounded in the same part");
            }
        }
        errors.push(diagnostic);
        if errors.len() == MAX_REPORTS {
            break;
        }
    }
    errors
}

/// Why construction stopped.
enum Abort {
    /// The term limit was crossed while expanding the node made at this source.
    TermLimit(Source),
    /// A budgeted expansion ([`Builder::expand_or_cells`]) did more work than allowed.
    OverBudget,
}

/// What holds on the way down from the root to a node.
#[derive(Clone)]
struct Context {
    /// World from the node's parent frame.
    matrix: DMat4,
    /// Whether the node is seen through an odd number of complements.
    negated: bool,
    /// The innermost colour above.
    color: Option<Rgba>,
    /// Whether a highlight is above.
    highlight: bool,
    /// The intersection of the world boxes of the non-negated nodes being expanded above:
    /// every term formed below ends up inside it (used to prove literals false, never true).
    enclosing: Aabb,
}

/// A world-space literal.
struct Literal {
    quadric: Quadric,
    source: Source,
    color: Option<Rgba>,
    highlight: bool,
    /// A box containing the literal's solid.
    own_box: Aabb,
    /// For the complement of an axis-aligned slab: the axis and the interval it excludes.
    excluded: Option<(usize, f64, f64)>,
    /// What the transform that placed it may have rounded.
    rounding: Rounding,
}

/// The exact identity of a literal before it is looked up among equal quadrics.
#[derive(Clone, PartialEq, Eq, Hash)]
struct LiteralKey {
    leaf: NodeId,
    matrix: [u64; 16],
    negated: bool,
    color: Option<[u64; 4]>,
    highlight: bool,
}

/// Literals that may be merged: same shape key, same appearance.
#[derive(Clone, PartialEq, Eq, Hash)]
struct ShapeGroup {
    shape: [u64; 9],
    color: Option<[u64; 4]>,
    highlight: bool,
}

struct Builder<'a> {
    dag: &'a Dag,
    term_limit: usize,
    pruning: Pruning,
    literals: Vec<Literal>,
    literal_index: FxHashMap<LiteralKey, Option<u32>>,
    /// Literal ids grouped by [`shape_key`], to find equal quadrics.
    /// Colour and highlight are part of the key: merging a red face into a blue one would
    /// repaint it.
    shape_groups: FxHashMap<ShapeGroup, Vec<u32>>,
    /// Each node's box in its own frame.
    local_boxes: Vec<Aabb>,
    /// Which nodes are made of planes only, and how large their plain expansion would be.
    plane_sizes: Vec<Option<plane_cells::PlaneSize>>,
    /// The budget of the plain expansion being tried on a part made of planes, if any.
    attempt: Option<plane_cells::Attempt>,
    singular_reported: HashSet<NodeId>,
    warnings: Vec<Diagnostic>,
    stats: crate::stats::ConstructionStats,
}

/// Whether a node combines its operands by intersection or by union (after De Morgan).
#[derive(Clone, Copy, PartialEq, Eq)]
enum Combine {
    All,
    Any,
}

impl<'a> Builder<'a> {
    fn new(dag: &'a Dag, options: &DnfOptions) -> Self {
        Self {
            dag,
            term_limit: options.term_limit,
            pruning: options.pruning,
            literals: Vec::new(),
            literal_index: FxHashMap::default(),
            shape_groups: FxHashMap::default(),
            local_boxes: dag.local_bounds(),
            plane_sizes: plane_cells::plane_sizes(dag),
            attempt: None,
            singular_reported: HashSet::new(),
            warnings: Vec::new(),
            stats: Default::default(),
        }
    }

    /// The DNF of `acc ∩ X` where X is the solid behind `edge` (complemented if
    /// `ctx.negated`), each term of `acc` already inside its box.
    fn and_into(&mut self, acc: Vec<Term>, edge: Edge, ctx: &Context) -> Result<Vec<Term>, Abort> {
        stacker_guard(|| self.and_into_inner(acc, edge, ctx))
    }

    fn and_into_inner(
        &mut self,
        mut acc: Vec<Term>,
        edge: Edge,
        ctx: &Context,
    ) -> Result<Vec<Term>, Abort> {
        if acc.is_empty() {
            return Ok(acc);
        }
        let Some(node) = self.dag.node(edge.child) else {
            // A handle from another DAG: nothing.
            return Ok(if ctx.negated { acc } else { Vec::new() });
        };
        let matrix = self.world_matrix(edge, &ctx.matrix);
        let world_box = self.local_boxes[edge.child.0 as usize].transformed(&matrix);

        // Region of interest: X only matters where it meets a term's box.
        let mut untouched = Vec::new();
        if !self.pruning.operand_bounds {
            // Every term meets X.
        } else if ctx.negated {
            // ¬X holds on every term that misses X's box: those pass through unchanged. They
            // stay where they are (a small cutter among thousands of terms moves only the few
            // it meets).
            let hit: Vec<Term> = acc
                .extract_if(.., |t| t.bounds.intersects(&world_box))
                .collect();
            self.stats.operands_skipped += acc.len();
            untouched = std::mem::replace(&mut acc, hit);
            if acc.is_empty() {
                return Ok(untouched);
            }
        } else {
            let before = acc.len();
            acc.retain(|t| t.bounds.intersects(&world_box));
            self.stats.terms_outside_operand_bounds += before - acc.len();
            if acc.is_empty() {
                return Ok(acc);
            }
        }

        let mut child_ctx = Context {
            matrix,
            ..ctx.clone()
        };
        if !ctx.negated {
            child_ctx.enclosing = ctx.enclosing.intersection(&world_box);
        }
        let negated = ctx.negated;
        let result = if self.wants_cells(edge.child, negated) {
            // A part made of planes whose expansion may multiply out: cells where it does.
            let enclosing = if negated {
                ctx.enclosing
            } else {
                child_ctx.enclosing
            };
            self.expand_or_cells(acc, edge.child, &child_ctx, enclosing)?
        } else {
            self.expand(acc, edge.child, &child_ctx)?
        };
        self.finish_node(result, untouched, negated, world_box, node.source)
    }

    /// `acc ∩ X` for the node `id` (in `ctx`'s frame and sign), by the node's kind.
    fn expand(&mut self, acc: Vec<Term>, id: NodeId, ctx: &Context) -> Result<Vec<Term>, Abort> {
        let Some(node) = self.dag.node(id) else {
            return Ok(if ctx.negated { acc } else { Vec::new() });
        };
        let negated = ctx.negated;
        if negated
            && self.pruning.plane_cells
            && let Some(complement) = self.dag.complement_of(id)
        {
            // A part that knows its complement as cells (a glyph's unfilled cells): those,
            // instead of the product of its own cells' complements.
            let positive = Context {
                negated: false,
                ..ctx.clone()
            };
            return self.expand(acc, complement, &positive);
        }
        let mut child_ctx = ctx.clone();
        Ok(match &node.kind {
            NodeKind::Leaf(q) => self.add_leaf(acc, id, q, node.source, &child_ctx),
            NodeKind::Complement(e) => {
                child_ctx.negated = !negated;
                self.and_into(acc, *e, &child_ctx)?
            }
            NodeKind::Color(rgba, e) => {
                child_ctx.color = Some(*rgba);
                self.and_into(acc, *e, &child_ctx)?
            }
            NodeKind::Highlight(e) => {
                child_ctx.highlight = true;
                self.and_into(acc, *e, &child_ctx)?
            }
            NodeKind::Union(children) => {
                let combine = if negated { Combine::All } else { Combine::Any };
                let operands: Vec<(Edge, bool)> = children.iter().map(|&c| (c, negated)).collect();
                self.combine(acc, &operands, combine, node.source, &child_ctx)?
            }
            NodeKind::Intersection(children) => {
                let combine = if negated { Combine::Any } else { Combine::All };
                let operands: Vec<(Edge, bool)> = children.iter().map(|&c| (c, negated)).collect();
                self.combine(acc, &operands, combine, node.source, &child_ctx)?
            }
            NodeKind::Difference(children) => {
                // A − B − C = A ∩ ¬B ∩ ¬C; its complement is ¬A ∪ B ∪ C.
                let combine = if negated { Combine::Any } else { Combine::All };
                let operands: Vec<(Edge, bool)> = children
                    .iter()
                    .enumerate()
                    .map(|(i, &c)| (c, if i == 0 { negated } else { !negated }))
                    .collect();
                self.combine(acc, &operands, combine, node.source, &child_ctx)?
            }
        })
    }

    /// The terms formed at a node, boxed by the node's box (when not complemented), with the
    /// terms that passed by untouched.
    fn finish_node(
        &mut self,
        mut result: Vec<Term>,
        mut untouched: Vec<Term>,
        negated: bool,
        world_box: Aabb,
        source: Source,
    ) -> Result<Vec<Term>, Abort> {
        if let Some(attempt) = &mut self.attempt {
            attempt.work += result.len();
            if attempt.work > attempt.budget {
                return Err(Abort::OverBudget);
            }
        }
        if !negated {
            // Every term formed here lies in X, hence in X's box.
            let before = result.len();
            for term in &mut result {
                term.bounds = term.bounds.intersection(&world_box);
            }
            if self.pruning.empty_bounds {
                result.retain(|t| !t.bounds.is_empty());
            }
            self.stats.terms_empty_bounds += before - result.len();
        }
        if !untouched.is_empty() {
            self.check_limit(untouched.len() + result.len(), source)?;
            untouched.append(&mut result);
            result = untouched;
        }
        self.stats.peak_terms = self.stats.peak_terms.max(result.len());
        Ok(result)
    }

    /// Intersects (`All`) or unites (`Any`) the operands `(edge, negated)` into `acc`.
    fn combine(
        &mut self,
        mut acc: Vec<Term>,
        operands: &[(Edge, bool)],
        combine: Combine,
        source: Source,
        ctx: &Context,
    ) -> Result<Vec<Term>, Abort> {
        match combine {
            Combine::All => {
                for &(edge, negated) in operands {
                    if acc.is_empty() {
                        break;
                    }
                    let child_ctx = Context {
                        negated,
                        ..ctx.clone()
                    };
                    acc = self.and_into(acc, edge, &child_ctx)?;
                }
                Ok(acc)
            }
            Combine::Any => {
                let mut result: Vec<Term> = Vec::new();
                for &(edge, negated) in operands {
                    let child_ctx = Context {
                        negated,
                        ..ctx.clone()
                    };
                    // Copy only the terms a non-negated operand can meet (the rest would be
                    // dropped on entry anyway): a wide union then costs no quadratic copying.
                    let input: Vec<Term> = if negated || !self.pruning.operand_bounds {
                        acc.clone()
                    } else {
                        let reach = self.world_bounds(edge, &ctx.matrix);
                        let input: Vec<Term> = acc
                            .iter()
                            .filter(|t| t.bounds.intersects(&reach))
                            .cloned()
                            .collect();
                        self.stats.terms_outside_operand_bounds += acc.len() - input.len();
                        input
                    };
                    let part = self.and_into(input, edge, &child_ctx)?;
                    self.check_limit(result.len() + part.len(), source)?;
                    result.extend(part);
                }
                self.stats.peak_terms = self.stats.peak_terms.max(result.len());
                prune::simplify_terms(
                    &mut result,
                    self.pruning.duplicate_terms,
                    self.pruning.subsumed_terms,
                    prune::INCREMENTAL_SUBSUMPTION_LIMIT,
                    &mut self.stats,
                );
                Ok(result)
            }
        }
    }

    /// The world matrix of the frame of `edge`'s child, under the parent's world matrix.
    fn world_matrix(&self, edge: Edge, parent: &DMat4) -> DMat4 {
        let edge_matrix = self.dag.matrix(edge.transform);
        if edge_matrix == DMat4::IDENTITY {
            *parent
        } else {
            *parent * edge_matrix
        }
    }

    /// A world box containing the solid behind `edge` (uncomplemented).
    fn world_bounds(&self, edge: Edge, parent: &DMat4) -> Aabb {
        let local = self
            .local_boxes
            .get(edge.child.0 as usize)
            .copied()
            .unwrap_or(Aabb::EVERYTHING);
        local.transformed(&self.world_matrix(edge, parent))
    }

    fn check_limit(&self, count: usize, source: Source) -> Result<(), Abort> {
        if count > self.term_limit {
            Err(Abort::TermLimit(source))
        } else {
            Ok(())
        }
    }

    /// `acc ∩ leaf` (or `acc ∩ ¬leaf`).
    fn add_leaf(
        &mut self,
        mut acc: Vec<Term>,
        leaf: NodeId,
        q: &Quadric,
        source: Source,
        ctx: &Context,
    ) -> Vec<Term> {
        self.stats.leaves_visited += 1;
        let Some(id) = self.literal(leaf, q, source, ctx) else {
            // A flattened leaf has no volume; its complement is everything.
            return if ctx.negated { acc } else { Vec::new() };
        };
        acc.retain_mut(|term| self.add_literal(term, id, &ctx.enclosing));
        acc
    }

    /// Adds literal `id` to `term` with the construction's pruning (`enclosing` holds the
    /// finished term); false when the term is provably empty and must be dropped.
    fn add_literal(&mut self, term: &mut Term, id: u32, enclosing: &Aabb) -> bool {
        let literal = &self.literals[id as usize];
        let (quadric, own_box, excluded) = (literal.quadric, literal.own_box, literal.excluded);
        let pruning = self.pruning;
        let position = match term.literals.binary_search(&id) {
            Ok(_) => {
                self.stats.literals_duplicate += 1;
                return true;
            }
            Err(position) => position,
        };
        let mut bounds = term.bounds.intersection(&own_box);
        if let Some((axis, low, high)) = excluded {
            bounds = clip_outside_interval(&bounds, axis, low, high);
        }
        if pruning.empty_bounds && bounds.is_empty() {
            self.stats.terms_empty_bounds += 1;
            return false;
        }
        // The term will lie in `bounds ∩ enclosing`: a literal false there ends it.
        let outer = bounds.intersection(enclosing);
        if pruning.empty_bounds && outer.is_empty() {
            self.stats.terms_empty_bounds += 1;
            return false;
        }
        if pruning.outside_literal
            && !outer.is_empty()
            && classify(&quadric, &outer) == BoxClass::Outside
        {
            self.stats.terms_outside_literal += 1;
            return false;
        }
        // The term so far lies in its own box: a literal true there adds nothing.
        if pruning.inside_literal
            && !term.bounds.is_empty()
            && classify(&quadric, &term.bounds) == BoxClass::Inside
        {
            self.stats.literals_inside += 1;
            return true;
        }
        term.literals.insert(position, id);
        term.bounds = bounds;
        true
    }

    /// The literal for `leaf` under the context's transform, sign and colour; `None` when
    /// the transform is singular (a warning is recorded once per leaf).
    fn literal(&mut self, leaf: NodeId, q: &Quadric, source: Source, ctx: &Context) -> Option<u32> {
        let key = LiteralKey {
            leaf,
            matrix: ctx.matrix.to_cols_array().map(f64::to_bits),
            negated: ctx.negated,
            color: ctx.color.map(|c| c.map(f64::to_bits)),
            highlight: ctx.highlight,
        };
        if let Some(&id) = self.literal_index.get(&key) {
            return id;
        }
        let world = if ctx.matrix == DMat4::IDENTITY {
            Some(q.normalized())
        } else {
            q.transformed(&ctx.matrix)
        };
        let Some(world) = world else {
            if self.singular_reported.insert(leaf) {
                self.warnings.push(Diagnostic::warning(
                    codes::SINGULAR_TRANSFORM,
                    "this part is flattened to zero volume by a singular transform and was left out",
                    source.file,
                    source.span,
                ));
            }
            self.literal_index.insert(key, None);
            return None;
        };
        let world = if ctx.negated { world.negated() } else { world };
        let rounding = Rounding::of_placement(&ctx.matrix, q.origin());
        let id = self.intern(world, source, ctx.color, ctx.highlight, rounding);
        self.literal_index.insert(key, Some(id));
        Some(id)
    }

    /// The id of the world-space literal `world` with its appearance: an equal literal already
    /// interned (same appearance, equal up to a positive factor), or a new one.
    fn intern(
        &mut self,
        world: Quadric,
        source: Source,
        color: Option<Rgba>,
        highlight: bool,
        rounding: Rounding,
    ) -> u32 {
        let group_key = ShapeGroup {
            shape: shape_key(&world),
            color: color.map(|c| c.map(f64::to_bits)),
            highlight,
        };
        let group = self.shape_groups.entry(group_key).or_default();
        let candidates: &[u32] = if self.pruning.merged_literals {
            group
        } else {
            &[]
        };
        for &candidate in candidates {
            if self.literals[candidate as usize]
                .quadric
                .approx_eq_up_to_scale(&world, DUPLICATE_TOLERANCE)
            {
                self.stats.literals_merged += 1;
                return candidate;
            }
        }
        let id = self.literals.len() as u32;
        group.push(id);
        self.literals.push(Literal {
            quadric: world,
            source,
            color,
            highlight,
            own_box: solid_bounds(&world),
            excluded: excluded_interval(&world),
            rounding,
        });
        self.stats.literals_interned += 1;
        id
    }
}

/// A key under which quadrics equal up to a positive factor and a change of origin collide:
/// the quadratic part scaled to unit largest entry (the linear part when there is none) and the
/// point of the quadric's centre set nearest the world origin, both with the low 32 bits of
/// their mantissas cleared. Values straddling a rounding boundary only cost a missed merge:
/// equality is always confirmed by [`Quadric::approx_eq_up_to_scale`].
pub(crate) fn shape_key(q: &Quadric) -> [u64; 9] {
    fn coarse(x: f64) -> u64 {
        if x == 0.0 {
            0
        } else {
            x.to_bits() & !0xffff_ffffu64
        }
    }
    let k = q.coefficients();
    let origin = q.origin();
    let l = q.linear();
    let largest = k[..6].iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut key = [0u64; 9];
    let centre = if largest > 0.0 {
        for (slot, v) in key.iter_mut().zip(&k[..6]) {
            *slot = coarse(v / largest);
        }
        // Centre set {p : A (p − origin) + l = 0}; its point nearest the world origin is
        // Σ over non-null eigenvectors v of v (v·origin − v·l / λ).
        let eigen = q.eigen();
        let tolerance = 1e-12 * largest;
        let mut centre = qcsg_quadric::DVec3::ZERO;
        for (value, vector) in eigen.values.iter().zip(eigen.vectors.iter()) {
            if value.abs() > tolerance {
                centre += *vector * (vector.dot(origin) - vector.dot(l) / value);
            }
        }
        centre
    } else {
        let largest_linear = l.abs().max_element();
        if largest_linear == 0.0 {
            return key;
        }
        let direction = l / largest_linear;
        key[0] = coarse(direction.x);
        key[1] = coarse(direction.y);
        key[2] = coarse(direction.z);
        // The plane 2 l·(p − origin) + j = 0 meets the line t·l at its point nearest 0.
        let t = (2.0 * l.dot(origin) - q.constant()) / (2.0 * l.length_squared());
        l * t
    };
    key[6] = coarse(centre.x);
    key[7] = coarse(centre.y);
    key[8] = coarse(centre.z);
    key
}

/// Runs `f` with enough stack for deep DAGs.
fn stacker_guard<R>(f: impl FnOnce() -> R) -> R {
    const RED_ZONE: usize = 128 * 1024;
    const GROWTH: usize = 4 * 1024 * 1024;
    stacker::maybe_grow(RED_ZONE, GROWTH, f)
}
