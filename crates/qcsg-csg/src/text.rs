//! Text forms of the DAG and the DNF, for people: one node or term per line.
//!
//! Sources are written by a caller-supplied locator: [`line_locator`] gives `file:line:col`
//! (1-based) from a [`SourceMap`], [`byte_locator`] gives `file@start..end` from file names.

use std::fmt::Write;

use qcsg_diag::SourceMap;

use crate::dag::{Dag, Edge, NodeKind, Source, TransformId};
use crate::dnf::Dnf;
use crate::json::reachable_nodes;

/// `file:line:col` (1-based line, 1-based UTF-16 column) of a source's start.
pub fn line_locator(map: &SourceMap) -> impl Fn(Source) -> String + '_ {
    move |source: Source| match map.iter().find(|(id, _)| *id == source.file) {
        Some((_, file)) => {
            let at = file
                .line_index
                .line_col(&file.text, source.span.start as usize);
            format!("{}:{}:{}", file.name, at.line + 1, at.character + 1)
        }
        None => format!("<unknown>@{}..{}", source.span.start, source.span.end),
    }
}

/// `file@start..end` with file names from a list indexed by `FileId`.
pub fn byte_locator(names: &[String]) -> impl Fn(Source) -> String + '_ {
    move |source: Source| {
        let name = names
            .get(source.file.0 as usize)
            .map_or("<unknown>", String::as_str);
        format!("{name}@{}..{}", source.span.start, source.span.end)
    }
}

fn vector(values: &[f64]) -> String {
    // Debug formatting is shortest-round-trip and switches to exponents for tiny and huge values.
    let parts: Vec<String> = values
        .iter()
        .map(|&v| format!("{:?}", crate::json::positive_zero(v)))
        .collect();
    format!("[{}]", parts.join(", "))
}

fn edge_text(edge: &Edge) -> String {
    if edge.transform == TransformId::IDENTITY {
        format!("n{}", edge.child.0)
    } else {
        format!("t{}·n{}", edge.transform.0, edge.child.0)
    }
}

/// The DAG, one reachable node per line (children first), then the transforms used, the root
/// and the background parts.
pub fn dag_to_text(dag: &Dag, locate: &dyn Fn(Source) -> String) -> String {
    let mut out = String::new();
    let reachable = reachable_nodes(dag);
    let mut used_transforms = std::collections::BTreeSet::new();
    for (id, node) in dag.nodes().iter().enumerate() {
        if !reachable[id] {
            continue;
        }
        let children: Vec<String> = node
            .kind
            .children()
            .iter()
            .map(|e| {
                if e.transform != TransformId::IDENTITY {
                    used_transforms.insert(e.transform);
                }
                edge_text(e)
            })
            .collect();
        let what = match &node.kind {
            NodeKind::Leaf(q) => format!(
                "leaf {} origin {} coefficients {}",
                q.kind().name(),
                vector(&q.origin().to_array()),
                vector(&q.coefficients())
            ),
            NodeKind::Color(rgba, _) => format!("color {} ({})", vector(rgba), children.join(", ")),
            kind => format!("{} ({})", kind.name(), children.join(", ")),
        };
        let bounds = node.bounds.map_or(String::new(), |b| {
            format!(
                " bounds {}..{}",
                vector(&b.min.to_array()),
                vector(&b.max.to_array())
            )
        });
        let _ = writeln!(out, "n{id} = {what}{bounds}  # {}", locate(node.source));
    }
    used_transforms.extend(
        dag.root()
            .iter()
            .chain(dag.backgrounds())
            .map(|e| e.transform)
            .filter(|&t| t != TransformId::IDENTITY),
    );
    for t in used_transforms {
        let _ = writeln!(
            out,
            "t{} = {}",
            t.0,
            vector(&crate::json::row_major(&dag.matrix(t)))
        );
    }
    match dag.root() {
        Some(root) => {
            let _ = writeln!(out, "root = {}", edge_text(&root));
        }
        None => out.push_str("root = none\n"),
    }
    for background in dag.backgrounds() {
        let _ = writeln!(out, "background = {}", edge_text(background));
    }
    out
}

/// The DNF: its bounds, the quadric table (kind, origin, coefficients, source, colour) and
/// one term per line, then the stats.
pub fn dnf_to_text(dnf: &Dnf, locate: &dyn Fn(Source) -> String) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "bounds {}..{}",
        vector(&dnf.bounds.min.to_array()),
        vector(&dnf.bounds.max.to_array())
    );
    if let Some(region) = &dnf.region {
        let _ = writeln!(
            out,
            "region {}..{}",
            vector(&region.min.to_array()),
            vector(&region.max.to_array())
        );
    }
    let _ = writeln!(out, "quadrics ({}):", dnf.quadrics.len());
    for (id, q) in dnf.quadrics.iter().enumerate() {
        let color = q
            .color
            .map_or(String::new(), |c| format!(" color {}", vector(&c)));
        let highlight = if q.highlight { " highlight" } else { "" };
        let _ = writeln!(
            out,
            "  q{id} {} origin {} coefficients {}  # {}{color}{highlight}",
            q.quadric.kind().name(),
            vector(&q.quadric.origin().to_array()),
            vector(&q.quadric.coefficients()),
            locate(q.source)
        );
    }
    let _ = writeln!(out, "terms ({}):", dnf.terms.len());
    for (index, term) in dnf.terms.iter().enumerate() {
        let literals: Vec<String> = term
            .literals
            .iter()
            .map(|&id| {
                let kind = dnf
                    .quadrics
                    .get(id as usize)
                    .map_or("?", |q| q.quadric.kind().name());
                format!("q{id} {kind}")
            })
            .collect();
        let body = if literals.is_empty() {
            "everything".to_string()
        } else {
            literals.join(" ∩ ")
        };
        let _ = writeln!(out, "  t{index}: {body}");
    }
    let _ = writeln!(out, "{}", dnf.stats);
    out
}
