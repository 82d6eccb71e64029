//! The geometry of a document: the stages after the static check (evaluation and the DNF, run by
//! `qcsg-driver` as every command runs them) under the editor's limits, their diagnostics, and
//! hover on a module instantiation listing the world-space quadrics it becomes.
//!
//! [`Geometry::evaluate`] runs those stages under [`editor_limits`], so the editor reports what
//! `qcsg check` would (an unbounded solid, the term limit), and indexes the resulting DAG once: how many root-to-node paths reach every node (its instances in the solid), the
//! world transforms of the first few of them, and the DAG nodes each instantiation statement
//! produced (from [`qcsg_eval::Evaluation::instantiations`]). A hover then only walks the leaves
//! below the hovered call's nodes.
//!
//! Nodes are hash-consed, so two call sites that build exactly the same solid share a node, and
//! both sites' instances are counted on either call.

use std::collections::HashMap;
use std::fmt::Write as _;

use qcsg_csg::{Dag, Edge, NodeId, NodeKind, Source};
use qcsg_diag::{Diagnostic, Span};
use qcsg_driver::{Options, Stage};
use qcsg_eval::{EvalOptions, Evaluation};
use qcsg_ide::{Analysis, FileId, HoverExtension, IdeDiagnostic};
use qcsg_quadric::{DMat4, DVec3, Quadric, QuadricKind};

use crate::preview::Preview;

/// How many instances a hover lists in full.
const SHOWN_INSTANCES: usize = 3;
/// How many quadrics of one instance a hover lists.
const SHOWN_QUADRICS: usize = 6;

/// Evaluation limits for the editor: small enough that a runaway loop or recursion ends in well
/// under a second instead of blocking the analysis thread for as long as `qcsg check` may take.
pub fn editor_limits() -> EvalOptions {
    EvalOptions {
        defines: Vec::new(),
        max_recursion: 1_000,
        max_iterations: 1_000_000,
        max_vector_len: 1_000_000,
        max_instances: 100_000,
        ..EvalOptions::default()
    }
}

/// The evaluated solid of one analysis, indexed for hover.
#[derive(Debug)]
pub struct Geometry {
    evaluation: Evaluation,
    /// The DNF stage's errors and warnings (empty when evaluation failed).
    dnf_diagnostics: Vec<Diagnostic>,
    /// The evaluator's limits, to tell the editor's limits from the program's own errors.
    limits: EvalOptions,
    /// Number of root-to-node paths per node (f64: it can overflow any integer).
    paths: Vec<f64>,
    /// World transforms of the first [`SHOWN_INSTANCES`] paths to each node.
    placements: Vec<Vec<DMat4>>,
    /// Number of leaf paths below each node.
    leaves_below: Vec<f64>,
    /// The nodes each instantiation statement produced.
    by_statement: HashMap<Source, Vec<NodeId>>,
    /// The statement span of each instantiation of the main file, by the start of its name.
    statements: HashMap<u32, Span>,
    /// Frames and picks for the preview panel, when the solid was built without error.
    preview: Option<Preview>,
}

impl Geometry {
    /// Evaluates the program under `limits` and builds its DNF; `None` when it has static
    /// errors (the evaluator needs a correct program).
    pub fn evaluate(analysis: &Analysis, limits: &EvalOptions) -> Option<Geometry> {
        let options = Options {
            eval: limits.clone(),
            ..Options::default()
        };
        let built = qcsg_driver::build(analysis.sema(), &options, Stage::Dnf);
        let evaluation = built.evaluation?;
        // The preview panel's scene, when the layers were built without error.
        let preview = built
            .layers
            .filter(|_| !evaluation.has_errors())
            .map(|layers| Preview::new(analysis.sema(), layers, &evaluation.instantiations));
        let mut geometry = Geometry::new(analysis, evaluation, built.diagnostics, limits.clone());
        geometry.preview = preview;
        Some(geometry)
    }

    fn new(
        analysis: &Analysis,
        evaluation: Evaluation,
        dnf_diagnostics: Vec<Diagnostic>,
        limits: EvalOptions,
    ) -> Self {
        let dag = &evaluation.dag;
        let count = dag.len();
        let mut paths = vec![0.0; count];
        let mut placements: Vec<Vec<DMat4>> = vec![Vec::new(); count];
        let seeds = dag
            .root()
            .into_iter()
            .chain(dag.backgrounds().iter().copied());
        for edge in seeds {
            if let Some(slot) = paths.get_mut(edge.child.0 as usize) {
                *slot += 1.0;
                let shown = &mut placements[edge.child.0 as usize];
                if shown.len() < SHOWN_INSTANCES {
                    shown.push(dag.matrix(edge.transform));
                }
            }
        }
        // Children precede their parents, so a reverse sweep sees every parent first.
        for index in (0..count).rev() {
            if paths[index] == 0.0 {
                continue;
            }
            let Some(node) = dag.node(NodeId(index as u32)) else {
                continue;
            };
            for edge in node.kind.children() {
                let child = edge.child.0 as usize;
                if child >= count {
                    continue;
                }
                paths[child] += paths[index];
                let matrix = dag.matrix(edge.transform);
                for parent in placements[index].clone() {
                    if placements[child].len() >= SHOWN_INSTANCES {
                        break;
                    }
                    placements[child].push(parent * matrix);
                }
            }
        }
        let mut leaves_below = vec![0.0; count];
        for (index, node) in dag.nodes().iter().enumerate() {
            leaves_below[index] = match &node.kind {
                NodeKind::Leaf(_) => 1.0,
                kind => kind
                    .children()
                    .iter()
                    .filter_map(|e| leaves_below.get(e.child.0 as usize))
                    .sum(),
            };
        }
        let mut by_statement: HashMap<Source, Vec<NodeId>> = HashMap::new();
        for (source, node) in &evaluation.instantiations {
            by_statement.entry(*source).or_default().push(*node);
        }
        Self {
            statements: analysis.instantiation_statements(),
            evaluation,
            dnf_diagnostics,
            limits,
            paths,
            placements,
            leaves_below,
            by_statement,
            preview: None,
        }
    }

    /// The preview panel's scene, when the solid was built without error.
    pub fn preview(&self) -> Option<&Preview> {
        self.preview.as_ref()
    }

    /// The evaluation itself.
    pub fn evaluation(&self) -> &Evaluation {
        &self.evaluation
    }

    /// The diagnostics of evaluation and the DNF for the main document (runtime errors,
    /// warnings, `echo` output, an unbounded solid), with those located in included or used files shown at the `include`/`use`
    /// line. A limit reached under the editor's limits is information, not an error: the
    /// program may well be correct under `qcsg check`'s larger ones.
    pub fn diagnostics(&self, analysis: &Analysis) -> Vec<IdeDiagnostic> {
        analysis.present(self.softened().iter())
    }

    /// The diagnostics of evaluation and the DNF located in the file `path` (an included or used file).
    pub fn diagnostics_in(&self, analysis: &Analysis, path: &str) -> Vec<IdeDiagnostic> {
        analysis.diagnostics_located_in(self.softened().iter(), path)
    }

    fn softened(&self) -> Vec<Diagnostic> {
        let defaults = EvalOptions::default();
        let lowered = [
            (
                qcsg_eval::codes::RECURSION_LIMIT,
                self.limits.max_recursion < defaults.max_recursion,
            ),
            (
                qcsg_eval::codes::ITERATION_LIMIT,
                self.limits.max_iterations < defaults.max_iterations,
            ),
            (
                qcsg_eval::codes::VECTOR_LIMIT,
                self.limits.max_vector_len < defaults.max_vector_len,
            ),
            (
                qcsg_eval::codes::INSTANCE_LIMIT,
                self.limits.max_instances < defaults.max_instances,
            ),
        ];
        self.evaluation
            .diagnostics
            .iter()
            .chain(&self.dnf_diagnostics)
            .map(|d| {
                let mut d = d.clone();
                if lowered.iter().any(|(code, lower)| *lower && d.code == *code) {
                    d.severity = qcsg_diag::Severity::Info;
                    d.message = format!(
                        "evaluation stopped in the editor: {} (the editor's limit; `qcsg check` allows more)",
                        d.message
                    );
                }
                d
            })
            .collect()
    }

    /// Markdown describing the quadrics the instantiation statement at `statement` of `file`
    /// becomes, or `None` when the evaluator recorded nothing for it.
    pub fn describe_statement(&self, file: FileId, statement: Span) -> Option<String> {
        let nodes = self.by_statement.get(&Source::new(file, statement))?;
        let dag = &self.evaluation.dag;
        let instances: f64 = nodes.iter().map(|n| self.paths[n.0 as usize]).sum();
        let mut out = String::new();
        if instances == 0.0 {
            out.push_str("**geometry**: not part of the solid (discarded by `!` or evaluation)");
            return Some(out);
        }
        let leaves: f64 = nodes
            .iter()
            .map(|n| self.paths[n.0 as usize] * self.leaves_below[n.0 as usize])
            .sum();
        let _ = write!(
            out,
            "**geometry**: {} · {}",
            plural(instances, "instance"),
            plural(leaves, "quadric")
        );
        if self.evaluation.has_errors() {
            out.push_str(" (evaluation stopped at an error: partial)");
        }
        out.push('\n');
        let mut shown = 0;
        for node in nodes {
            for world in &self.placements[node.0 as usize] {
                if shown == SHOWN_INSTANCES {
                    break;
                }
                shown += 1;
                if instances > 1.0 {
                    let _ = writeln!(out, "\ninstance {shown}:");
                }
                out.push('\n');
                self.describe_leaves(dag, *node, world, &mut out);
            }
        }
        if instances > shown as f64 {
            let _ = writeln!(
                out,
                "\n… and {}",
                more(instances - shown as f64, "instance")
            );
        }
        Some(out)
    }

    /// Lists the first quadrics below `node` placed by `world`, each as one bullet.
    fn describe_leaves(&self, dag: &Dag, node: NodeId, world: &DMat4, out: &mut String) {
        let mut found = Vec::new();
        collect_leaves(dag, node, *world, false, &mut found);
        for (quadric, subtracted) in &found {
            describe_quadric(quadric, *subtracted, out);
        }
        let total = self.leaves_below[node.0 as usize];
        if total > found.len() as f64 {
            let _ = writeln!(
                out,
                "- … and {}",
                more(total - found.len() as f64, "quadric")
            );
        }
    }
}

impl HoverExtension for Geometry {
    fn instantiation(&self, _: &Analysis, file: FileId, name_span: Span) -> Option<String> {
        let statement = self.statements.get(&name_span.start)?;
        self.describe_statement(file, *statement)
    }
}

/// Collects up to [`SHOWN_QUADRICS`] leaves below `node` in world space, in DAG order, with
/// whether each bounds a subtracted or complemented part.
fn collect_leaves(
    dag: &Dag,
    node: NodeId,
    world: DMat4,
    subtracted: bool,
    found: &mut Vec<(Quadric, bool)>,
) {
    if found.len() >= SHOWN_QUADRICS {
        return;
    }
    let Some(n) = dag.node(node) else { return };
    let visit = |edge: &Edge, flip: bool, found: &mut Vec<(Quadric, bool)>| {
        let matrix = world * dag.matrix(edge.transform);
        collect_leaves(dag, edge.child, matrix, subtracted ^ flip, found);
    };
    match &n.kind {
        NodeKind::Leaf(quadric) => {
            if let Some(placed) = quadric.transformed(&world) {
                found.push((placed, subtracted));
            }
        }
        NodeKind::Difference(children) => {
            for (i, edge) in children.iter().enumerate() {
                visit(edge, i > 0, found);
            }
        }
        NodeKind::Complement(edge) => visit(edge, true, found),
        kind => {
            for edge in kind.children() {
                visit(edge, false, found);
            }
        }
    }
}

/// One bullet: kind, centre, axes with semi-axes, and the 4×4 coefficient matrix about the world
/// origin.
fn describe_quadric(quadric: &Quadric, subtracted: bool, out: &mut String) {
    let kind = quadric.kind();
    let frame = quadric.frame();
    let _ = write!(out, "- **{}**", kind.name().replace('_', " "));
    if subtracted {
        out.push_str(" (subtracted)");
    }
    let centre_name = match kind {
        QuadricKind::Cone => "apex",
        QuadricKind::EllipticParaboloid
        | QuadricKind::HyperbolicParaboloid
        | QuadricKind::ParabolicCylinder => "vertex",
        QuadricKind::Plane => "point",
        _ => "centre",
    };
    if frame.centre.is_finite() && !kind.has_no_surface() {
        let _ = write!(out, " · {centre_name} {}", vector(frame.centre));
    }
    let semi = frame.semi_axes();
    let mut axes = Vec::new();
    for (k, semi_axis) in semi.iter().enumerate() {
        let axis = vector(frame.axes[k]);
        if frame.linear[k] != 0.0 {
            axes.push(format!("{axis} (normal)"));
        } else if frame.eigenvalues[k] == 0.0 {
            axes.push(format!("{axis} (unbounded)"));
        } else if frame.constant != 0.0 && semi_axis.is_finite() {
            axes.push(format!("{axis} × {}", number(*semi_axis)));
        } else {
            axes.push(axis);
        }
    }
    if kind == QuadricKind::Sphere && frame.constant != 0.0 {
        let _ = write!(out, " · radius {}", number(semi[0]));
    } else if !kind.has_no_surface() {
        let _ = write!(out, " · axes {}", axes.join(", "));
    }
    let world = quadric.with_origin(DVec3::ZERO);
    let [a, b, c, d, e, f, g, h, i, j] = world.coefficients();
    let rows = [[a, d, e, g], [d, b, f, h], [e, f, c, i], [g, h, i, j]];
    let scale = rows.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
    let matrix: Vec<String> = rows
        .iter()
        .map(|row| {
            row.iter()
                .map(|x| number(if x.abs() <= 1e-12 * scale { 0.0 } else { *x }))
                .collect::<Vec<_>>()
                .join(" ")
        })
        .collect();
    let _ = writeln!(out, " · `[{}]`", matrix.join("; "));
}

/// `(x, y, z)` with short numbers.
fn vector(v: DVec3) -> String {
    format!("({}, {}, {})", number(v.x), number(v.y), number(v.z))
}

/// A number with at most six significant digits, no trailing zeros, no negative zero.
fn number(x: f64) -> String {
    if !x.is_finite() {
        return if x.is_nan() {
            "NaN".into()
        } else {
            "∞".into()
        };
    }
    let magnitude = x.abs();
    if magnitude < 1e-9 {
        return "0".into();
    }
    if !(1e-4..1e9).contains(&magnitude) {
        return format!("{x:.5e}");
    }
    let decimals = (5 - magnitude.log10().floor() as i32).max(0) as usize;
    let text = format!("{x:.decimals$}");
    let text = if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_owned()
    } else {
        text
    };
    if text == "-0" { "0".into() } else { text }
}

/// `1 more instance`, `3 more instances`.
fn more(count: f64, noun: &str) -> String {
    plural(count, noun).replacen(' ', " more ", 1)
}

/// `1 instance`, `3 instances`, `1.2e20 instances`.
fn plural(count: f64, noun: &str) -> String {
    let shown = if count < 1e15 {
        format!("{}", count as u64)
    } else {
        format!("{count:.2e}")
    };
    if count == 1.0 {
        format!("{shown} {noun}")
    } else {
        format!("{shown} {noun}s")
    }
}

#[cfg(test)]
mod tests {
    use super::number;

    #[test]
    fn numbers_are_short() {
        assert_eq!(number(10.0), "10");
        assert_eq!(number(-0.0), "0");
        assert_eq!(number(1.0 / 3.0), "0.333333");
        assert_eq!(number(-2.5), "-2.5");
        assert_eq!(number(1234567.0), "1234567");
        assert_eq!(number(1e-12), "0");
        assert_eq!(number(f64::INFINITY), "∞");
    }
}
