//! Diagnostics for people: qcsg's plain [`Diagnostic`] rendered by miette's graphical handler.
//!
//! miette draws one source per report, so a label that points into another file (say, "defined
//! here" in an included library) becomes a note of its own, with its own excerpt, drawn under the
//! main report. miette sees only an [`Excerpt`] of each file: the lines the diagnostic points at,
//! long lines cut to windows around the spans, so a diagnostic costs the same to draw however
//! large its file; and [`report`] prints at most [`limits::MAX_SHOWN`] diagnostics of a run, so a file
//! that breaks everywhere gives a page of errors, not megabytes.
//! Without a terminal the output is fixed-width and colourless, so it can be snapshot-tested.

mod excerpt;
mod limits;

use std::fmt;

use miette::{GraphicalReportHandler, GraphicalTheme, LabeledSpan, SourceCode};
use qcsg_diag::{Diagnostic, Severity, SourceMap, Span};

use excerpt::Excerpt;

/// Width of the output when it is not a terminal (or the terminal's width is unknown).
const FIXED_WIDTH: usize = 80;

/// Renders diagnostics as text with source excerpts.
pub struct HumanRenderer {
    handler: GraphicalReportHandler,
}

impl HumanRenderer {
    /// Unicode box drawing without colour, [`FIXED_WIDTH`] columns: deterministic output.
    pub fn plain() -> Self {
        Self::with_theme(GraphicalTheme::unicode_nocolor(), FIXED_WIDTH)
    }

    /// What a terminal gets: colour when asked for, and the terminal's width when `COLUMNS`
    /// says it.
    pub fn for_terminal(colour: bool) -> Self {
        if !colour {
            return Self::plain();
        }
        let width = std::env::var("COLUMNS")
            .ok()
            .and_then(|c| c.parse().ok())
            .filter(|&w: &usize| w >= 40)
            .unwrap_or(FIXED_WIDTH);
        Self::with_theme(GraphicalTheme::unicode(), width)
    }

    fn with_theme(theme: GraphicalTheme, width: usize) -> Self {
        let handler = GraphicalReportHandler::new_themed(theme)
            .with_width(width)
            .with_links(false);
        Self { handler }
    }

    /// One diagnostic, its source excerpts and help, ending with a blank line. Labels in other
    /// files follow as notes with excerpts of their own.
    pub fn render(&self, sources: &SourceMap, diagnostic: &Diagnostic) -> String {
        let report = Report::new(sources, diagnostic);
        let mut out = String::new();
        for part in std::iter::once(&report).chain(&report.notes) {
            let mut text = String::new();
            // Writing into a String cannot fail; should the handler fail, keep the message.
            if self.handler.render_report(&mut text, part).is_err() {
                text = format!("{part}\n");
            }
            out.push_str(text.trim_end());
            out.push_str("\n\n");
        }
        out
    }
}

/// What is printed for a run's diagnostics (those `-q` leaves): the ones [`limits::select`]
/// picks, in order, a line for those left out, and the summary line (counting every one) when
/// `summary` is set.
pub fn report(
    renderer: &HumanRenderer,
    diagnostics: &[(&SourceMap, &Diagnostic)],
    summary: bool,
) -> String {
    let selection = limits::select(diagnostics);
    let mut out = String::new();
    let mut counts = [0usize; 4];
    for (&(sources, diagnostic), &shown) in diagnostics.iter().zip(&selection.shown) {
        counts[diagnostic.severity as usize] += 1;
        if shown {
            out.push_str(&renderer.render(sources, diagnostic));
        }
    }
    if let Some(line) = limits::omitted_line(selection.omitted) {
        out.push_str(&line);
        out.push('\n');
    }
    if summary {
        out.push_str(&summary_line(counts));
        out.push('\n');
    }
    out
}

/// `"2 errors, 1 warning"`; infos and hints are mentioned only when there are some.
/// `counts` is indexed by [`Severity`] (error, warning, info, hint).
pub fn summary_line(counts: [usize; 4]) -> String {
    let plural = |n: usize, word: &str| format!("{n} {word}{}", if n == 1 { "" } else { "s" });
    let mut parts = vec![plural(counts[0], "error"), plural(counts[1], "warning")];
    if counts[2] > 0 {
        parts.push(plural(counts[2], "info"));
    }
    if counts[3] > 0 {
        parts.push(plural(counts[3], "hint"));
    }
    parts.join(", ")
}

/// A diagnostic (or one of its labels in another file) in the shape miette draws.
#[derive(Debug)]
struct Report {
    /// `error[E0101]`: what miette prints as the header.
    header: String,
    message: String,
    severity: miette::Severity,
    help: Option<String>,
    source: Excerpt,
    labels: Vec<LabeledSpan>,
    /// Labels in other files, as reports of their own. (miette's "related" reports would do, but
    /// it heads each with a bare "Advice:".)
    notes: Vec<Report>,
}

impl Report {
    fn new(sources: &SourceMap, diagnostic: &Diagnostic) -> Self {
        let local = || {
            diagnostic
                .labels
                .iter()
                .filter(|label| label.file == diagnostic.file)
        };
        let local_spans: Vec<Span> = std::iter::once(diagnostic.span)
            .chain(local().map(|label| label.span))
            .collect();
        let (source, spans) = Excerpt::new(sources.get(diagnostic.file), &local_spans);
        let mut labels = vec![LabeledSpan::new_primary_with_span(None, spans[0])];
        labels.extend(
            local().zip(&spans[1..]).map(|(label, &span)| {
                LabeledSpan::new_with_span(Some(label.message.clone()), span)
            }),
        );
        let notes = diagnostic
            .labels
            .iter()
            .filter(|label| label.file != diagnostic.file)
            .map(|label| {
                let (source, spans) = Excerpt::new(sources.get(label.file), &[label.span]);
                Report {
                    header: String::new(),
                    message: format!("note: {}", label.message),
                    severity: miette::Severity::Advice,
                    help: None,
                    source,
                    labels: vec![LabeledSpan::new_primary_with_span(None, spans[0])],
                    notes: Vec::new(),
                }
            })
            .collect();
        Report {
            header: format!("{}[{}]", diagnostic.severity.as_str(), diagnostic.code),
            message: diagnostic.message.clone(),
            severity: match diagnostic.severity {
                Severity::Error => miette::Severity::Error,
                Severity::Warning => miette::Severity::Warning,
                Severity::Info | Severity::Hint => miette::Severity::Advice,
            },
            help: diagnostic.help.clone(),
            source,
            labels,
            notes,
        }
    }
}

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for Report {}

impl miette::Diagnostic for Report {
    fn code<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        (!self.header.is_empty()).then(|| Box::new(&self.header) as Box<dyn fmt::Display + 'a>)
    }

    fn severity(&self) -> Option<miette::Severity> {
        Some(self.severity)
    }

    fn help<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        self.help
            .as_ref()
            .map(|h| Box::new(h) as Box<dyn fmt::Display + 'a>)
    }

    fn source_code(&self) -> Option<&dyn SourceCode> {
        Some(&self.source)
    }

    fn labels(&self) -> Option<Box<dyn Iterator<Item = LabeledSpan> + '_>> {
        Some(Box::new(self.labels.iter().cloned()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use qcsg_diag::FileId;

    /// A map with a main file and a library, and the main file's id.
    fn sources() -> (SourceMap, FileId, FileId) {
        let mut sources = SourceMap::new();
        let main = sources.add(
            "scene.qcsg",
            "include <lib/parts.qcsg>\nwidth = 10;\ncube(size = \"wide\");\nbolt(d = width)\n",
        );
        let lib = sources.add(
            "lib/parts.qcsg",
            "module bolt(r = 1) {\n    cylinder(h = 3, r = r);\n}\n",
        );
        (sources, main, lib)
    }

    fn span_of(sources: &SourceMap, file: FileId, needle: &str) -> Span {
        let start = sources.get(file).text.find(needle).expect("needle in text");
        Span::new(start, start + needle.len())
    }

    #[test]
    fn error_with_help_and_a_label_in_the_same_file() {
        let (sources, main, _) = sources();
        let diagnostic = Diagnostic::error(
            "E0201",
            "expected a number or a vector of 3 numbers, found a string",
            main,
            span_of(&sources, main, "\"wide\""),
        )
        .with_help("write `cube(size = 10)` or `cube([10, 20, 5])`")
        .with_label(main, span_of(&sources, main, "size"), "this parameter");
        insta::assert_snapshot!(HumanRenderer::plain().render(&sources, &diagnostic));
    }

    #[test]
    fn label_in_another_file_is_drawn_as_a_related_note() {
        let (sources, main, lib) = sources();
        let argument = span_of(&sources, main, "d = width");
        let diagnostic = Diagnostic::error(
            "E0103",
            "unknown named argument `d`",
            main,
            Span::new(argument.start as usize, argument.start as usize + 1),
        )
        .with_label(lib, span_of(&sources, lib, "r = 1"), "`bolt` takes `r`");
        insta::assert_snapshot!(HumanRenderer::plain().render(&sources, &diagnostic));
    }

    #[test]
    fn empty_span_at_end_of_line_and_other_severities() {
        let (sources, main, _) = sources();
        let end_of_bolt = sources.get(main).text.rfind(')').unwrap() + 1;
        let missing = Diagnostic::error("E0002", "expected `;`", main, Span::empty(end_of_bolt));
        let unused = Diagnostic::warning(
            "W0101",
            "unused variable `width`",
            main,
            span_of(&sources, main, "width"),
        );
        let mut hint = Diagnostic::new(
            Severity::Hint,
            "H0001",
            "`$fn` has no effect",
            main,
            span_of(&sources, main, "cube"),
        );
        hint.help = Some("surfaces are exact".into());
        let renderer = HumanRenderer::plain();
        let out = [missing, unused, hint]
            .iter()
            .map(|d| renderer.render(&sources, d))
            .collect::<String>();
        insta::assert_snapshot!(out);
    }

    #[test]
    fn spans_at_end_of_file_and_after_non_ascii_text() {
        let mut sources = SourceMap::new();
        let text = "label = \"größe 😀\"; x = ;";
        let file = sources.add("unicode.qcsg", text);
        let at = text.find("= ;").unwrap() + 2;
        let diagnostic = Diagnostic::error(
            "E0001",
            "expected an expression",
            file,
            Span::new(at, at + 1),
        );
        let eof = Diagnostic::error(
            "E0003",
            "unexpected end of file",
            file,
            Span::empty(text.len()),
        );
        let renderer = HumanRenderer::plain();
        insta::assert_snapshot!(
            renderer.render(&sources, &diagnostic) + &renderer.render(&sources, &eof)
        );
    }

    #[test]
    fn label_at_the_end_of_a_file_with_a_final_newline() {
        let mut sources = SourceMap::new();
        let text = "translate([1, 0, 0)\ncube(1);\n";
        let file = sources.add("open.qcsg", text);
        let diagnostic = Diagnostic::error("E0008", "unclosed `[`", file, Span::new(10, 11))
            .with_label(
                file,
                Span::empty(text.len()),
                "expected `]` before the end of the file",
            );
        insta::assert_snapshot!(HumanRenderer::plain().render(&sources, &diagnostic));
    }

    /// Spans and labels starting and ending everywhere in a text of long lines of tabs, wide and
    /// astral characters, CRLF endings and control characters: each renders, in short lines.
    #[test]
    fn any_span_over_long_lines_renders_in_short_lines() {
        let long = "\tab 日本 😀 x = 1; \u{1b}[31m ".repeat(20);
        let text = format!("{long}\r\nshort\n\n{long}\n{}\nend", "y".repeat(70_000));
        let mut sources = SourceMap::new();
        let file = sources.add("long.qcsg", text.as_str());
        let renderer = HumanRenderer::plain();
        let step = 53;
        for start in (0..=text.len() + 1).step_by(step) {
            for end in (start..=text.len() + 1).step_by(step * 61) {
                let diagnostic =
                    Diagnostic::error("E0001", "somewhere", file, Span::new(start, end))
                        .with_label(file, Span::new(end / 2, end), "half")
                        .with_label(
                            file,
                            Span::empty(text.len() - start.min(text.len())),
                            "mirror",
                        );
                let out = renderer.render(&sources, &diagnostic);
                assert!(out.contains("somewhere"), "{out}");
                assert!(!out.contains('\u{1b}'), "{out}");
                let longest = out.lines().map(|l| l.chars().count()).max().unwrap_or(0);
                assert!(longest < 800, "{start}..{end}: a line of {longest}");
            }
        }
    }

    #[test]
    fn odd_spans_render_without_panicking() {
        let mut sources = SourceMap::new();
        let file = sources.add("odd.qcsg", "é = 1;\n");
        let renderer = HumanRenderer::plain();
        for span in [
            Span::new(1, 2),
            Span::new(0, 100),
            Span::new(50, 60),
            Span::empty(0),
        ] {
            let diagnostic = Diagnostic::error("E0001", "odd span", file, span);
            assert!(renderer.render(&sources, &diagnostic).contains("odd span"));
        }
        let empty = sources.add("empty.qcsg", "");
        let diagnostic = Diagnostic::error("E0002", "empty file", empty, Span::empty(0));
        assert!(
            renderer
                .render(&sources, &diagnostic)
                .contains("empty file")
        );
    }

    #[test]
    fn summary_counts() {
        assert_eq!(summary_line([2, 1, 0, 0]), "2 errors, 1 warning");
        assert_eq!(summary_line([0, 0, 0, 0]), "0 errors, 0 warnings");
        assert_eq!(
            summary_line([1, 0, 3, 1]),
            "1 error, 0 warnings, 3 infos, 1 hint"
        );
    }
}
