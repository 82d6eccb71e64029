//! The source text a diagnostic is drawn over: only the lines it points at, each long line cut to
//! windows around the points, so that drawing one diagnostic costs the same whatever the size of
//! its file and the length of its lines.
//!
//! miette reads a source through [`SourceCode::read_span`], and its `&str` implementation scans
//! from the start of the text for every label; it also cannot draw a marker past column 65,535
//! (its widths are formatting arguments). An [`Excerpt`] gives miette a small text of its own:
//! runs of consecutive lines ("chunks"), the lines that the spans cover with one line of context
//! either side, each line longer than [`WHOLE_LINE_CHARS`] cut to [`WINDOW_CHARS`] characters
//! either side of each span's start and end, with `…` where text was left out. It reports the
//! real line numbers and columns, so the output reads as if miette had seen the whole file.

use std::ops::Range;

use miette::{MietteError, MietteSpanContents, SourceCode, SourceSpan, SpanContents};
use qcsg_diag::{SourceFile, Span};

/// Lines up to this many characters are shown whole.
const WHOLE_LINE_CHARS: usize = 200;
/// Characters shown either side of a span's start or end on a longer line.
const WINDOW_CHARS: usize = 80;
/// A span over more lines than this is drawn as its first line only.
const MAX_SPAN_LINES: usize = 8;
/// Chunks this many lines apart or closer are drawn as one, with the lines between.
const MAX_GAP_LINES: usize = 2;
/// What stands for text left out of a line.
const ELLIPSIS: &str = "…";

/// A source file cut down to what some spans of it need; see the module documentation.
#[derive(Debug)]
pub(super) struct Excerpt {
    name: String,
    /// The chunks' lines, each ending in `\n`.
    text: String,
    chunks: Vec<Chunk>,
    /// Where each span passed to [`Excerpt::new`] starts in `text`, and its real zero-based line
    /// and character column there.
    starts: Vec<(usize, usize, usize)>,
}

/// A run of consecutive lines of the file in the excerpt's text.
#[derive(Debug)]
struct Chunk {
    /// Its bytes in the excerpt's text.
    range: Range<usize>,
    /// The zero-based line of the file it starts with.
    first_line: usize,
    line_count: usize,
}

/// A line of the file as the excerpt shows it: windows of its text.
struct LineCut {
    /// The line's text without its line ending.
    content: Range<usize>,
    /// The parts shown, in order, not overlapping.
    windows: Vec<Range<usize>>,
}

impl Excerpt {
    /// The excerpt of `file` that draws `spans`, and the spans as offsets into it (in the same
    /// order). Spans past the end of the file, or starting or ending inside a character, are
    /// moved to the nearest place that exists.
    pub(super) fn new(file: &SourceFile, spans: &[Span]) -> (Self, Vec<SourceSpan>) {
        let text = file.text.as_str();
        let index = &file.line_index;
        let spans: Vec<Range<usize>> = spans.iter().map(|&span| clamp(file, span)).collect();

        // The last line is an empty one after a final newline: it is shown only when a span is
        // on it ("unexpected end of file").
        let mut last_line = index.line_count() - 1;
        let ends_empty = index
            .line_range(last_line as u32)
            .is_some_and(|r| r.is_empty());
        if ends_empty && last_line > 0 && spans.iter().all(|s| s.start < text.len()) {
            last_line -= 1;
        }

        // The lines each span needs, merged into chunks.
        let mut needed: Vec<Range<usize>> = spans
            .iter()
            .map(|span| {
                let first = index.line_of(span.start) as usize;
                let last = index.line_of(span.end) as usize;
                first.saturating_sub(1)..(last + 1).min(last_line.max(last)) + 1
            })
            .collect();
        needed.sort_by_key(|lines| lines.start);
        let mut chunk_lines: Vec<Range<usize>> = Vec::new();
        for lines in needed {
            match chunk_lines.last_mut() {
                Some(last) if lines.start <= last.end + MAX_GAP_LINES => {
                    last.end = last.end.max(lines.end);
                }
                _ => chunk_lines.push(lines),
            }
        }

        // Every span start and end is a point its line must show.
        let mut points: Vec<usize> = spans.iter().flat_map(|s| [s.start, s.end]).collect();
        points.sort_unstable();
        points.dedup();

        let mut excerpt = Excerpt {
            name: file.name.clone(),
            text: String::new(),
            chunks: Vec::with_capacity(chunk_lines.len()),
            starts: Vec::with_capacity(spans.len()),
        };
        // Where each point went in the excerpt's text.
        let mut mapped: Vec<(usize, usize)> = Vec::with_capacity(points.len());
        for lines in chunk_lines {
            let start = excerpt.text.len();
            // Lines without a point of their own are cut where the chunk's first point is.
            let anchor = points
                .iter()
                .find(|&&p| index.line_of(p) as usize >= lines.start)
                .map(|&p| p - line_start(file, index.line_of(p) as usize));
            for line in lines.clone() {
                let line_points = points_on_line(file, &points, line);
                let cut = cut_line(file, line, line_points, anchor.unwrap_or(0));
                excerpt.push_line(text, &cut, line_points, &mut mapped);
            }
            excerpt.chunks.push(Chunk {
                range: start..excerpt.text.len(),
                first_line: lines.start,
                line_count: lines.len(),
            });
        }

        let at = |offset: usize| {
            let i = mapped.partition_point(|&(p, _)| p < offset);
            mapped.get(i).map_or(excerpt.text.len(), |&(_, at)| at)
        };
        let mut out = Vec::with_capacity(spans.len());
        for span in &spans {
            let (start, end) = (at(span.start), at(span.end).max(at(span.start)));
            let line = index.line_of(span.start) as usize;
            let column = index.char_column(text, span.start) as usize;
            excerpt.starts.push((start, line, column));
            out.push(SourceSpan::from(start..end));
        }
        (excerpt, out)
    }

    /// Appends one line cut to its windows, recording where its points went.
    fn push_line(
        &mut self,
        text: &str,
        cut: &LineCut,
        points: &[usize],
        mapped: &mut Vec<(usize, usize)>,
    ) {
        let mut points = points.iter().copied().peekable();
        for (i, window) in cut.windows.iter().enumerate() {
            let left_out = if i == 0 {
                window.start > cut.content.start
            } else {
                window.start > cut.windows[i - 1].end
            };
            if left_out {
                self.text.push_str(ELLIPSIS);
            }
            let at = self.text.len();
            while let Some(p) = points.next_if(|&p| p <= window.end) {
                mapped.push((p, at + p.saturating_sub(window.start)));
            }
            push_visible(&mut self.text, &text[window.clone()]);
        }
        let cut_at_end = cut.windows.last().is_some_and(|w| w.end < cut.content.end);
        if cut_at_end {
            self.text.push_str(ELLIPSIS);
        }
        // Points past the text of the line (at its line ending) are drawn at its end.
        for p in points {
            mapped.push((p, self.text.len()));
        }
        self.text.push('\n');
    }

    /// The chunk that holds the excerpt's bytes `span`.
    fn chunk_of(&self, span: &SourceSpan) -> Option<&Chunk> {
        let (start, end) = (span.offset(), span.offset() + span.len());
        // The chunk that starts at `start` rather than the one that ends there.
        let i = self.chunks.partition_point(|c| c.range.end <= start);
        self.chunks
            .get(i)
            .or(self.chunks.last())
            .filter(|c| c.range.start <= start && end <= c.range.end)
    }
}

impl SourceCode for Excerpt {
    /// With context: the whole chunk the span is in (the lines chosen for it). Without: the span
    /// itself, with the real line and column of its start, which miette prints in the header.
    fn read_span<'a>(
        &'a self,
        span: &SourceSpan,
        context_lines_before: usize,
        context_lines_after: usize,
    ) -> Result<Box<dyn SpanContents<'a> + 'a>, MietteError> {
        let chunk = self.chunk_of(span).ok_or(MietteError::OutOfBounds)?;
        if context_lines_before == 0 && context_lines_after == 0 {
            let (line, column) = self
                .starts
                .iter()
                .find(|&&(at, _, _)| at == span.offset())
                .map_or((chunk.first_line, 0), |&(_, line, column)| (line, column));
            let range = span.offset()..span.offset() + span.len();
            return Ok(Box::new(MietteSpanContents::new_named(
                self.name.clone(),
                &self.text.as_bytes()[range],
                *span,
                line,
                column,
                1,
            )));
        }
        Ok(Box::new(MietteSpanContents::new_named(
            self.name.clone(),
            &self.text.as_bytes()[chunk.range.clone()],
            SourceSpan::from(chunk.range.clone()),
            chunk.first_line,
            0,
            chunk.line_count,
        )))
    }
}

/// `span` within `file`, on character boundaries, and not over more than [`MAX_SPAN_LINES`]
/// lines (a longer one is cut at the end of its first line).
fn clamp(file: &SourceFile, span: Span) -> Range<usize> {
    let text = file.text.as_str();
    let mut start = (span.start as usize).min(text.len());
    while !text.is_char_boundary(start) {
        start -= 1;
    }
    let mut end = (span.end as usize).clamp(start, text.len());
    while !text.is_char_boundary(end) {
        end += 1;
    }
    // A span that takes in the final newline ends at the end of the last line, not on the empty
    // line after it, which is not drawn.
    if end == text.len() && start < end && text.ends_with('\n') {
        end -= 1;
    }
    let index = &file.line_index;
    let first = index.line_of(start);
    if (index.line_of(end) - first) as usize >= MAX_SPAN_LINES {
        end = index.line_range(first).map_or(end, |r| r.end.max(start));
    }
    start..end
}

fn line_start(file: &SourceFile, line: usize) -> usize {
    file.line_index
        .line_start(line as u32)
        .unwrap_or(file.text.len())
}

/// The points (sorted) that lie on `line`, its line ending included.
fn points_on_line<'p>(file: &SourceFile, points: &'p [usize], line: usize) -> &'p [usize] {
    let start = line_start(file, line);
    let end = file
        .line_index
        .line_start(line as u32 + 1)
        .unwrap_or(file.text.len() + 1);
    let from = points.partition_point(|&p| p < start);
    let to = points.partition_point(|&p| p < end);
    &points[from..to]
}

/// How `line` is shown: whole when short, else windows around its points (or, without points,
/// around byte column `anchor`).
fn cut_line(file: &SourceFile, line: usize, points: &[usize], anchor: usize) -> LineCut {
    let text = file.text.as_str();
    let range = file
        .line_index
        .line_range(line as u32)
        .unwrap_or(text.len()..text.len());
    let content = if text[range.clone()].ends_with('\r') {
        range.start..range.end - 1
    } else {
        range
    };
    let line_text = &text[content.clone()];
    let short = line_text.len() <= WHOLE_LINE_CHARS
        || line_text.chars().take(WHOLE_LINE_CHARS + 1).count() <= WHOLE_LINE_CHARS;
    if short {
        return LineCut {
            windows: vec![content.clone()],
            content,
        };
    }
    let around = |p: usize| {
        let p = p.clamp(content.start, content.end);
        let p = floor_boundary(text, p);
        let before = text[content.start..p]
            .char_indices()
            .rev()
            .take(WINDOW_CHARS)
            .last()
            .map_or(p, |(i, _)| content.start + i);
        let after = text[p..content.end]
            .char_indices()
            .nth(WINDOW_CHARS)
            .map_or(content.end, |(i, _)| p + i);
        before..after
    };
    let mut windows: Vec<Range<usize>> = Vec::new();
    let centres: Vec<usize> = if points.is_empty() {
        vec![content.start + anchor.min(content.len())]
    } else {
        points.to_vec()
    };
    for centre in centres {
        let window = around(centre);
        match windows.last_mut() {
            // Windows that meet or nearly meet are one: an ellipsis would hide almost nothing.
            Some(last) if window.start <= last.end + ELLIPSIS.len() * 4 => {
                last.end = last.end.max(window.end);
            }
            _ => windows.push(window),
        }
    }
    LineCut { content, windows }
}

fn floor_boundary(text: &str, mut offset: usize) -> usize {
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    offset
}

/// Appends `text`, with control characters other than tabs as spaces of the same length: a
/// source file must not move the cursor or recolour the terminal it is shown on, and the
/// offsets into the excerpt must stay as they are.
fn push_visible(out: &mut String, text: &str) {
    if !text.chars().any(|c| c.is_control() && c != '\t') {
        out.push_str(text);
        return;
    }
    for c in text.chars() {
        if c.is_control() && c != '\t' {
            out.extend(std::iter::repeat_n(' ', c.len_utf8()));
        } else {
            out.push(c);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use qcsg_diag::SourceMap;

    fn excerpt(text: &str, spans: &[Span]) -> (Excerpt, Vec<SourceSpan>) {
        let mut sources = SourceMap::new();
        let file = sources.add("t.qcsg", text);
        Excerpt::new(sources.get(file), spans)
    }

    fn spanned(excerpt: &Excerpt, span: SourceSpan) -> &str {
        &excerpt.text[span.offset()..span.offset() + span.len()]
    }

    #[test]
    fn short_lines_are_kept_whole_with_a_line_of_context() {
        let text = "a = 1;\nb = 2;\nc = 3;\nd = 4;\n";
        let (excerpt, spans) = excerpt(text, &[Span::new(11, 12)]);
        assert_eq!(excerpt.text, "a = 1;\nb = 2;\nc = 3;\n");
        assert_eq!(spanned(&excerpt, spans[0]), "2");
        assert_eq!(excerpt.starts, [(11, 1, 4)]);
    }

    #[test]
    fn long_lines_are_cut_around_both_ends_of_a_span() {
        let line = format!("{}x = {};", " ".repeat(100_000), "1 + ".repeat(10_000));
        let x = 100_000;
        let semicolon = line.len() - 1;
        let (excerpt, spans) = excerpt(
            &line,
            &[Span::new(x, x + 1), Span::new(x + 4, semicolon + 1)],
        );
        assert_eq!(spanned(&excerpt, spans[0]), "x");
        let long = spanned(&excerpt, spans[1]);
        assert!(long.starts_with("1 + ") && long.ends_with("+ ;"), "{long}");
        assert!(long.contains(ELLIPSIS));
        assert!(excerpt.text.starts_with(ELLIPSIS), "{}", excerpt.text);
        assert!(excerpt.text.chars().count() < 4 * (2 * WINDOW_CHARS + 10));
        assert_eq!(excerpt.starts[0], (ELLIPSIS.len() + WINDOW_CHARS, 0, x));
    }

    #[test]
    fn tall_spans_are_cut_to_their_first_line_and_far_lines_make_chunks() {
        let text: String = (0..1000).map(|i| format!("line {i}\n")).collect();
        let start = text.find("line 10\n").unwrap();
        let far = text.find("line 900\n").unwrap();
        let (excerpt, spans) = excerpt(&text, &[Span::new(start, far), Span::new(far, far + 4)]);
        assert_eq!(spanned(&excerpt, spans[0]), "line 10");
        assert_eq!(excerpt.chunks.len(), 2);
        assert_eq!(
            excerpt.text,
            "line 9\nline 10\nline 11\nline 899\nline 900\nline 901\n"
        );
        let contents = excerpt.read_span(&spans[1], 1, 1).expect("in a chunk");
        assert_eq!((contents.line(), contents.line_count()), (899, 3));
    }

    #[test]
    fn control_characters_are_shown_as_spaces() {
        let (excerpt, _) = excerpt("a\u{1b}[2J\r = 1;\u{85}\r\n", &[Span::new(0, 1)]);
        assert_eq!(excerpt.text, "a [2J  = 1;  \n");
    }

    #[test]
    fn the_final_empty_line_is_shown_only_for_a_span_on_it() {
        let text = "a = 1;\n";
        assert_eq!(excerpt(text, &[Span::new(0, 1)]).0.text, "a = 1;\n");
        let (at_end, spans) = excerpt(text, &[Span::empty(text.len())]);
        assert_eq!(at_end.text, "a = 1;\n\n");
        assert_eq!(spans[0], SourceSpan::from(7..7));
    }
}
