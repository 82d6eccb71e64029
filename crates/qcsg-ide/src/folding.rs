//! Folding ranges: blocks, multi-line argument lists and vectors, comments.

use qcsg_syntax::ast::{CommentKind, ExprKind, StmtKind};

use crate::walk::{Node, walk};
use crate::{Analysis, Span};

/// What a folding range folds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum FoldKind {
    /// Code: a block, an argument list, a vector.
    Region,
    /// A comment or a run of line comments.
    Comment,
}

/// A foldable range of whole lines.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct FoldingRange {
    /// First line (stays visible).
    pub start_line: u32,
    /// Last line folded.
    pub end_line: u32,
    /// What it folds.
    pub kind: FoldKind,
}

impl Analysis {
    /// Every range of the main document worth folding, sorted, spanning at least two lines.
    pub fn folding_ranges(&self) -> Vec<FoldingRange> {
        let main = self.sema.main;
        let mut spans: Vec<(Span, FoldKind)> = Vec::new();
        walk(self.tree(), &mut |node| match node {
            Node::Stmt(stmt) => match &stmt.kind {
                StmtKind::Block(_) => spans.push((stmt.span, FoldKind::Region)),
                StmtKind::Instantiate { args_span, .. } => {
                    spans.push((*args_span, FoldKind::Region))
                }
                _ => {}
            },
            Node::Expr(expr) => match &expr.kind {
                ExprKind::Vector(_) => spans.push((expr.span, FoldKind::Region)),
                ExprKind::Call { args_span, .. } => spans.push((*args_span, FoldKind::Region)),
                _ => {}
            },
            Node::Elem(_) => {}
        });
        // Consecutive line comments fold as one.
        let mut run: Option<Span> = None;
        let text = self.text();
        for comment in &self.tree().comments {
            let line_like = matches!(comment.kind, CommentKind::Line | CommentKind::DocLine);
            match run {
                Some(span)
                    if line_like
                        && text
                            .get(span.end as usize..comment.span.start as usize)
                            .is_some_and(|gap| {
                                gap.trim().is_empty() && gap.matches('\n').count() == 1
                            }) =>
                {
                    run = Some(span.cover(comment.span));
                }
                _ => {
                    if let Some(span) = run.take() {
                        spans.push((span, FoldKind::Comment));
                    }
                    if line_like {
                        run = Some(comment.span);
                    } else {
                        spans.push((comment.span, FoldKind::Comment));
                    }
                }
            }
        }
        spans.extend(run.map(|span| (span, FoldKind::Comment)));
        let mut ranges: Vec<FoldingRange> = spans
            .into_iter()
            .filter_map(|(span, kind)| {
                let range = self.range(main, span);
                // Keep the closing line visible for code, as editors do.
                let end_line = match kind {
                    FoldKind::Region => range.end.line.checked_sub(1)?,
                    FoldKind::Comment => range.end.line,
                };
                (end_line > range.start.line).then_some(FoldingRange {
                    start_line: range.start.line,
                    end_line,
                    kind,
                })
            })
            .collect();
        ranges.sort();
        ranges.dedup();
        ranges
    }
}
