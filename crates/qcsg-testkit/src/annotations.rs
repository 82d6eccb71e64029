//! Inline expectations of the language suite (`tests/README.md`): parsing them out of a case's
//! comments, matching them against the diagnostics a check produced, and the report of what did
//! not match. The CLI's runner of the whole suite and the checker's own cases both use it.
//!
//! Its own tests feed it hand-made diagnostics: a harness that silently accepted anything would
//! make the whole suite worthless.

use std::fmt;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Severity as written in annotations (`error`, `warning`, `info`, `hint`).
pub type SeverityName = &'static str;

const SEVERITIES: [SeverityName; 4] = ["error", "warning", "info", "hint"];

/// Where an expected span ends.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpanEnd {
    /// On the start line, at this zero-based byte column (exclusive): `^^^`, or `|` when equal
    /// to the start.
    Column(usize),
    /// On some later line: `^^^...`.
    LaterLine,
    /// Not stated: `//@ L:C`.
    Any,
}

/// One diagnostic a case expects.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Expectation {
    /// Zero-based line the annotation itself is written on (for reports).
    pub written_on: usize,
    /// Zero-based line of the span's start.
    pub line: usize,
    /// Zero-based byte column of the span's start.
    pub column: usize,
    /// Where the span ends.
    pub end: SpanEnd,
    /// `error`, `warning`, `info` or `hint`.
    pub severity: SeverityName,
    /// The diagnostic code, e.g. `E0101`.
    pub code: String,
    /// A fragment the message must contain.
    pub fragment: Option<String>,
}

/// One diagnostic a check reported, with positions in zero-based lines and byte columns.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Reported {
    /// Start line.
    pub line: usize,
    /// Start byte column.
    pub column: usize,
    /// End line.
    pub end_line: usize,
    /// End byte column (exclusive).
    pub end_column: usize,
    /// `error`, `warning`, `info` or `hint`.
    pub severity: SeverityName,
    /// The code.
    pub code: String,
    /// The message.
    pub message: String,
    /// The help text, shown in reports (annotations match the message only).
    pub help: Option<String>,
}

impl Reported {
    /// Converts a diagnostic's primary span in `text` to lines and byte columns.
    pub fn new(text: &str, diagnostic: &qcsg_diag::Diagnostic) -> Self {
        let (line, column) = line_and_byte_column(text, diagnostic.span.start as usize);
        let (end_line, end_column) = line_and_byte_column(text, diagnostic.span.end as usize);
        Reported {
            line,
            column,
            end_line,
            end_column,
            severity: diagnostic.severity.as_str(),
            code: diagnostic.code.to_owned(),
            message: diagnostic.message.clone(),
            help: diagnostic.help.clone(),
        }
    }
}

fn line_and_byte_column(text: &str, offset: usize) -> (usize, usize) {
    let offset = offset.min(text.len());
    let before = &text.as_bytes()[..offset];
    let line = before.iter().filter(|&&b| b == b'\n').count();
    let line_start = before
        .iter()
        .rposition(|&b| b == b'\n')
        .map_or(0, |i| i + 1);
    (line, offset - line_start)
}

/// An annotation that does not follow the format; reported as a failure of the case.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MalformedAnnotation {
    /// Zero-based line of the annotation.
    pub line: usize,
    /// What is wrong.
    pub reason: String,
}

impl fmt::Display for MalformedAnnotation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "line {}: malformed annotation: {}",
            self.line + 1,
            self.reason
        )
    }
}

/// Reads every annotation of a file.
pub fn parse_annotations(text: &str) -> (Vec<Expectation>, Vec<MalformedAnnotation>) {
    let lines: Vec<&str> = text
        .split('\n')
        .map(|l| l.strip_suffix('\r').unwrap_or(l))
        .collect();
    let mut expectations = Vec::new();
    let mut malformed = Vec::new();
    // The nearest line above that is not an annotation: what caret columns refer to.
    let mut target: Option<usize> = None;
    for (number, line) in lines.iter().enumerate() {
        let result = match classify(line) {
            LineKind::Code => {
                target = Some(number);
                continue;
            }
            LineKind::Caret { column, rest } => match target {
                Some(target) => parse_caret(number, target, column, rest),
                None => Err("no line above to point at".to_owned()),
            },
            LineKind::Positioned(rest) => parse_positioned(number, rest),
        };
        match result {
            Ok(expectation) => expectations.push(expectation),
            Err(reason) => malformed.push(MalformedAnnotation {
                line: number,
                reason,
            }),
        }
    }
    (expectations, malformed)
}

enum LineKind<'a> {
    Code,
    /// `// ^…` or `// |…`: the byte column of the first marker and the text from it on.
    Caret {
        column: usize,
        rest: &'a str,
    },
    /// `//@ …`: the text after `@`.
    Positioned(&'a str),
}

fn classify(line: &str) -> LineKind<'_> {
    let Some(comment) = line.trim_start().strip_prefix("//") else {
        return LineKind::Code;
    };
    if let Some(rest) = comment.strip_prefix('@') {
        return LineKind::Positioned(rest);
    }
    let body = comment.trim_start();
    if body.starts_with('^') || body.starts_with('|') {
        LineKind::Caret {
            column: line.len() - body.len(),
            rest: body,
        }
    } else {
        LineKind::Code
    }
}

fn parse_caret(
    written_on: usize,
    line: usize,
    column: usize,
    rest: &str,
) -> Result<Expectation, String> {
    let (end, after) = if let Some(after) = rest.strip_prefix('|') {
        (SpanEnd::Column(column), after)
    } else {
        let carets = rest.len() - rest.trim_start_matches('^').len();
        let after = &rest[carets..];
        match after.strip_prefix("...") {
            Some(after) => (SpanEnd::LaterLine, after),
            None => (SpanEnd::Column(column + carets), after),
        }
    };
    if !after.starts_with(char::is_whitespace) {
        return Err(format!(
            "expected a space and `severity[CODE]` after the markers, found `{after}`"
        ));
    }
    let (severity, code, fragment) = parse_tail(after)?;
    Ok(Expectation {
        written_on,
        line,
        column,
        end,
        severity,
        code,
        fragment,
    })
}

/// `//@ L:C severity[CODE]…` with one-based L and C (byte columns).
fn parse_positioned(written_on: usize, rest: &str) -> Result<Expectation, String> {
    let rest = rest.trim_start();
    let (position, tail) = rest.split_once(char::is_whitespace).unwrap_or((rest, ""));
    let parsed = position.split_once(':').and_then(|(l, c)| {
        let (l, c) = (l.parse::<usize>().ok()?, c.parse::<usize>().ok()?);
        (l >= 1 && c >= 1).then(|| (l - 1, c - 1))
    });
    let Some((line, column)) = parsed else {
        return Err(format!(
            "expected `//@ LINE:COLUMN severity[CODE]` (one-based), found `//@{rest}`"
        ));
    };
    let (severity, code, fragment) = parse_tail(tail)?;
    Ok(Expectation {
        written_on,
        line,
        column,
        end: SpanEnd::Any,
        severity,
        code,
        fragment,
    })
}

/// ` severity[CODE]` optionally followed by `: fragment`.
fn parse_tail(text: &str) -> Result<(SeverityName, String, Option<String>), String> {
    let text = text.trim();
    let bad =
        || format!("expected `severity[CODE]` (severity one of {SEVERITIES:?}), found `{text}`");
    let (severity, after) = text.split_once('[').ok_or_else(bad)?;
    let severity = SEVERITIES
        .iter()
        .copied()
        .find(|s| *s == severity)
        .ok_or_else(bad)?;
    let (code, after) = after.split_once(']').ok_or_else(bad)?;
    if code.is_empty() || !code.chars().all(|c| c.is_ascii_alphanumeric()) {
        return Err(bad());
    }
    let fragment = if after.is_empty() {
        None
    } else if let Some(fragment) = after.strip_prefix(':') {
        let fragment = fragment.trim();
        if fragment.is_empty() {
            return Err("empty message fragment after `:`".to_owned());
        }
        Some(fragment.to_owned())
    } else {
        return Err(format!(
            "expected `: message fragment` or nothing after `]`, found `{after}`"
        ));
    };
    Ok((severity, code.to_owned(), fragment))
}

impl Expectation {
    /// Whether `reported` is the diagnostic this expects.
    pub fn matches(&self, reported: &Reported) -> bool {
        let end_matches = match self.end {
            SpanEnd::Column(column) => {
                reported.end_line == self.line && reported.end_column == column
            }
            SpanEnd::LaterLine => reported.end_line > self.line,
            SpanEnd::Any => true,
        };
        reported.line == self.line
            && reported.column == self.column
            && end_matches
            && reported.severity == self.severity
            && reported.code == self.code
            && self
                .fragment
                .as_ref()
                .is_none_or(|f| reported.message.contains(f.as_str()))
    }
}

impl fmt::Display for Expectation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let start = format!("{}:{}", self.line + 1, self.column + 1);
        let span = match self.end {
            SpanEnd::Column(end) if end == self.column => format!("{start} (empty)"),
            SpanEnd::Column(end) => format!("{start}-{}:{}", self.line + 1, end + 1),
            SpanEnd::LaterLine => format!("{start}-(a later line)"),
            SpanEnd::Any => start,
        };
        write!(f, "{span:<18} {}[{}]", self.severity, self.code)?;
        if let Some(fragment) = &self.fragment {
            write!(f, ": …{fragment}…")?;
        }
        write!(f, "   (annotation on line {})", self.written_on + 1)
    }
}

impl fmt::Display for Reported {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let start = format!("{}:{}", self.line + 1, self.column + 1);
        let span = if (self.line, self.column) == (self.end_line, self.end_column) {
            format!("{start} (empty)")
        } else {
            format!("{start}-{}:{}", self.end_line + 1, self.end_column + 1)
        };
        write!(
            f,
            "{span:<18} {}[{}]: {}",
            self.severity, self.code, self.message
        )
    }
}

/// What did not match in one file.
#[derive(Debug, Default)]
pub struct Mismatches {
    /// Expected but not reported.
    pub missing: Vec<Expectation>,
    /// Reported but not expected.
    pub unexpected: Vec<Reported>,
}

impl Mismatches {
    /// Whether everything matched.
    pub fn is_empty(&self) -> bool {
        self.missing.is_empty() && self.unexpected.is_empty()
    }
}

/// Pairs each reported diagnostic with a distinct expectation; the rest are mismatches.
pub fn compare(expected: &[Expectation], reported: &[Reported]) -> Mismatches {
    let mut used = vec![false; expected.len()];
    let mut unexpected = Vec::new();
    // Exact matches first (fragment-less expectations are the most permissive, so try them last)
    // so that two diagnostics at one span are paired with the annotations that name them.
    let mut order: Vec<usize> = (0..expected.len()).collect();
    order.sort_by_key(|&i| expected[i].fragment.is_none());
    for diagnostic in reported {
        match order
            .iter()
            .copied()
            .find(|&i| !used[i] && expected[i].matches(diagnostic))
        {
            Some(i) => used[i] = true,
            None => unexpected.push(diagnostic.clone()),
        }
    }
    let missing = expected
        .iter()
        .zip(&used)
        .filter(|(_, used)| !**used)
        .map(|(e, _)| e.clone())
        .collect();
    Mismatches {
        missing,
        unexpected,
    }
}

/// Every case file (`.qcsg`, `.scad`) below `dir`, sorted, `lib/` directories skipped.
pub fn suite_cases(dir: &Path) -> Vec<PathBuf> {
    fn collect(dir: &Path, cases: &mut Vec<PathBuf>) {
        let Ok(entries) = std::fs::read_dir(dir) else {
            panic!("cannot read the suite directory {}", dir.display());
        };
        let mut paths: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
        paths.sort();
        for path in paths {
            if path.is_dir() {
                if path.file_name().is_some_and(|name| name != "lib") {
                    collect(&path, cases);
                }
            } else if path
                .extension()
                .is_some_and(|ext| ext == "qcsg" || ext == "scad")
            {
                cases.push(path);
            }
        }
    }
    let mut cases = Vec::new();
    collect(dir, &mut cases);
    cases
}

/// What did not match between the annotations of every file `analysis` read and the
/// diagnostics reported in it, or `None` when all matched. A library's annotations are expected
/// whenever a case loads it; files other than the main one are named by `shown`.
pub fn mismatch_report(
    analysis: &qcsg_sema::Analysis,
    shown: &dyn Fn(&str) -> String,
) -> Option<String> {
    let mut report = String::new();
    for (file, source) in analysis.sources.iter() {
        let (expected, malformed) = parse_annotations(&source.text);
        let reported: Vec<Reported> = analysis
            .diagnostics
            .iter()
            .filter(|d| d.file == file)
            .map(|d| Reported::new(&source.text, d))
            .collect();
        let mismatches = compare(&expected, &reported);
        if malformed.is_empty() && mismatches.is_empty() {
            continue;
        }
        if file != analysis.main {
            let _ = writeln!(report, "  in {}:", shown(&source.name));
        }
        for annotation in &malformed {
            let _ = writeln!(report, "  {annotation}");
        }
        if !mismatches.missing.is_empty() {
            let _ = writeln!(report, "  expected, not reported:");
            for expectation in &mismatches.missing {
                let _ = writeln!(report, "    {expectation}");
            }
        }
        if !mismatches.unexpected.is_empty() {
            let _ = writeln!(report, "  reported, not expected:");
            for diagnostic in &mismatches.unexpected {
                let _ = writeln!(report, "    {diagnostic}");
            }
        }
    }
    (!report.is_empty()).then_some(report)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reported(
        line: usize,
        column: usize,
        end: (usize, usize),
        code: &str,
        message: &str,
    ) -> Reported {
        Reported {
            line,
            column,
            end_line: end.0,
            end_column: end.1,
            severity: if code.starts_with('W') {
                "warning"
            } else {
                "error"
            },
            code: code.to_owned(),
            message: message.to_owned(),
            help: None,
        }
    }

    const CASE: &str = "\
x = y + 1;
//  ^ error[E0101]: undefined variable
cube(size = \"a\");
//          ^^^ error[E0201]
//  ^^^^ warning[W0001]: unused
echo(\"missing semicolon\")
//                       | error[E0002]
module m() {
//^^^... error[E0003]: unclosed
//@ 11:1 error[E0004]: end of file
}";

    #[test]
    fn reads_carets_pipes_ellipses_and_positions() {
        let (expected, malformed) = parse_annotations(CASE);
        assert_eq!(malformed, []);
        let summary: Vec<_> = expected
            .iter()
            .map(|e| {
                (
                    e.written_on,
                    e.line,
                    e.column,
                    e.end,
                    e.severity,
                    e.code.as_str(),
                    e.fragment.as_deref(),
                )
            })
            .collect();
        assert_eq!(
            summary,
            [
                (
                    1,
                    0,
                    4,
                    SpanEnd::Column(5),
                    "error",
                    "E0101",
                    Some("undefined variable")
                ),
                (3, 2, 12, SpanEnd::Column(15), "error", "E0201", None),
                // A second annotation refers to the same code line, not to the annotation above.
                (
                    4,
                    2,
                    4,
                    SpanEnd::Column(8),
                    "warning",
                    "W0001",
                    Some("unused")
                ),
                (6, 5, 25, SpanEnd::Column(25), "error", "E0002", None),
                (
                    8,
                    7,
                    2,
                    SpanEnd::LaterLine,
                    "error",
                    "E0003",
                    Some("unclosed")
                ),
                (
                    9,
                    10,
                    0,
                    SpanEnd::Any,
                    "error",
                    "E0004",
                    Some("end of file")
                ),
            ]
        );
    }

    #[test]
    fn accepts_exactly_the_annotated_diagnostics() {
        let (expected, _) = parse_annotations(CASE);
        let all = vec![
            reported(0, 4, (0, 5), "E0101", "undefined variable `y`"),
            reported(2, 12, (2, 15), "E0201", "expected a number"),
            reported(2, 4, (2, 8), "W0001", "unused argument"),
            reported(5, 25, (5, 25), "E0002", "expected `;`"),
            reported(7, 2, (10, 1), "E0003", "unclosed block"),
            reported(10, 0, (10, 1), "E0004", "unexpected end of file"),
        ];
        assert!(compare(&expected, &all).is_empty());

        // Each deliberate mistake is caught: as a missing expectation and an unexpected diagnostic.
        let wrong: [(usize, Reported); 8] = [
            (0, reported(0, 5, (0, 6), "E0101", "undefined variable `y`")), // column
            (0, reported(0, 4, (0, 6), "E0101", "undefined variable `y`")), // end column
            (0, reported(0, 4, (0, 5), "E0102", "undefined variable `y`")), // code
            (0, reported(0, 4, (0, 5), "E0101", "undefined function `y`")), // message fragment
            (2, reported(2, 4, (2, 8), "E0001", "unused argument")),        // severity
            (3, reported(5, 25, (5, 26), "E0002", "expected `;`")),         // `|` is an empty span
            (4, reported(7, 2, (7, 9), "E0003", "unclosed block")),         // `...` ends later
            (5, reported(9, 0, (9, 1), "E0004", "unexpected end of file")), // line
        ];
        for (index, replacement) in wrong {
            let mut diagnostics = all.clone();
            diagnostics[index] = replacement.clone();
            let mismatches = compare(&expected, &diagnostics);
            assert_eq!(mismatches.unexpected, [replacement], "{index}");
            assert_eq!(mismatches.missing.len(), 1, "{index}");
        }

        // An unannotated diagnostic, a missing one, and a duplicate of an annotated one.
        let mut extra = all.clone();
        extra.push(reported(3, 0, (3, 1), "W0002", "unused module"));
        assert_eq!(compare(&expected, &extra).unexpected.len(), 1);
        assert_eq!(compare(&expected, &all[1..]).missing.len(), 1);
        let mut twice = all.clone();
        twice.push(all[0].clone());
        assert_eq!(compare(&expected, &twice).unexpected.len(), 1);
        // No diagnostics at all fails every expectation.
        assert_eq!(compare(&expected, &[]).missing.len(), expected.len());
    }

    #[test]
    fn rejects_malformed_annotations() {
        for bad in [
            "// ^ error",
            "// ^ eror[E0101]",
            "// ^ error[E0101] message without colon",
            "// ^ error[]",
            "// ^ error[E0101]:",
            "// ^error[E0101]",
            "//@ 0:1 error[E0101]",
            "//@ 3 error[E0101]",
            "//@ 1:1",
        ] {
            let text = format!("x = 1;\n{bad}\n");
            let (expected, malformed) = parse_annotations(&text);
            assert_eq!((expected.len(), malformed.len()), (0, 1), "{bad}");
        }
        // An annotation needs a line above it.
        assert_eq!(parse_annotations("// ^ error[E0001]\n").1.len(), 1);
        // Ordinary comments, including ones that mention carets later on, are not annotations.
        assert_eq!(
            parse_annotations("x = 1; // ^ error[E1]\n// x ^ y\n/// doc\n"),
            (vec![], vec![])
        );
    }

    #[test]
    fn byte_columns_of_reported_spans() {
        assert_eq!(line_and_byte_column("ab\ncé d", 7), (1, 4));
        assert_eq!(line_and_byte_column("ab\n", 3), (1, 0));
        assert_eq!(line_and_byte_column("ab", 99), (0, 2));
    }
}
