//! Doc comments: the `///` run or `/** … */` block directly before a definition or assignment.

use crate::ast::{Comment, CommentKind, Doc, Span};

/// The doc comment that ends right before byte `start` (only whitespace between), with its
/// markers stripped. A `///` run is a sequence of `///` comments on consecutive lines.
pub(crate) fn doc_before(text: &str, comments: &[Comment], start: usize) -> Option<Doc> {
    let index = comments.partition_point(|c| (c.span.end as usize) <= start);
    let last = comments.get(index.checked_sub(1)?)?;
    let gap = text.get(last.span.end as usize..start)?;
    if !gap.trim().is_empty() {
        return None;
    }
    match last.kind {
        CommentKind::DocBlock => {
            let raw = &text[last.span.range()];
            let inner = raw.strip_prefix("/**").unwrap_or(raw);
            let inner = inner.strip_suffix("*/").unwrap_or(inner);
            let lines: Vec<&str> = inner
                .lines()
                .map(|line| {
                    let line = line.trim();
                    let line = line.strip_prefix('*').unwrap_or(line);
                    line.strip_prefix(' ').unwrap_or(line)
                })
                .collect();
            let text = lines.join("\n").trim().to_owned();
            Some(Doc {
                text,
                span: last.span,
            })
        }
        CommentKind::DocLine => {
            let mut first = index - 1;
            while first > 0 {
                let prev = &comments[first - 1];
                let between =
                    text.get(prev.span.end as usize..comments[first].span.start as usize)?;
                let newlines = between.bytes().filter(|&b| b == b'\n').count();
                if prev.kind != CommentKind::DocLine || !between.trim().is_empty() || newlines != 1
                {
                    break;
                }
                first -= 1;
            }
            let lines: Vec<&str> = comments[first..index]
                .iter()
                .map(|c| {
                    let raw = &text[c.span.range()];
                    let line = raw.strip_prefix("///").unwrap_or(raw);
                    line.strip_prefix(' ').unwrap_or(line).trim_end()
                })
                .collect();
            let span = Span {
                start: comments[first].span.start,
                end: last.span.end,
            };
            Some(Doc {
                text: lines.join("\n"),
                span,
            })
        }
        CommentKind::Line | CommentKind::Block => None,
    }
}
