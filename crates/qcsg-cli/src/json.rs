//! Diagnostics for tools: the `--format json` array (its shape is documented in README.md).
//!
//! Lines and characters are zero-based and characters count UTF-16 code units, as in LSP, so an
//! editor can use the positions without re-reading the file. Labels also carry their `file` and
//! `range` (additions to the contract), since a label may point into an included file.

use qcsg_diag::{Diagnostic, FileId, LineCol, SourceMap, Span};
use serde::Serialize;

/// One element of the output array; fields in the documented order.
#[derive(Debug, Serialize)]
pub struct JsonDiagnostic<'a> {
    severity: &'static str,
    code: &'a str,
    message: &'a str,
    file: &'a str,
    range: JsonRange,
    byte_range: [u32; 2],
    help: Option<&'a str>,
    labels: Vec<JsonLabel<'a>>,
}

/// A secondary label.
#[derive(Debug, Serialize)]
struct JsonLabel<'a> {
    message: &'a str,
    byte_range: [u32; 2],
    file: &'a str,
    range: JsonRange,
}

/// Start and end positions (zero-based line, UTF-16 character).
#[derive(Debug, Serialize)]
struct JsonRange {
    start: JsonPosition,
    end: JsonPosition,
}

#[derive(Debug, Serialize)]
struct JsonPosition {
    line: u32,
    character: u32,
}

impl<'a> JsonDiagnostic<'a> {
    /// The JSON view of `diagnostic`, whose files are in `sources`.
    pub fn new(sources: &'a SourceMap, diagnostic: &'a Diagnostic) -> Self {
        JsonDiagnostic {
            severity: diagnostic.severity.as_str(),
            code: diagnostic.code,
            message: &diagnostic.message,
            file: &sources.get(diagnostic.file).name,
            range: range(sources, diagnostic.file, diagnostic.span),
            byte_range: [diagnostic.span.start, diagnostic.span.end],
            help: diagnostic.help.as_deref(),
            labels: diagnostic
                .labels
                .iter()
                .map(|label| JsonLabel {
                    message: &label.message,
                    byte_range: [label.span.start, label.span.end],
                    file: &sources.get(label.file).name,
                    range: range(sources, label.file, label.span),
                })
                .collect(),
        }
    }
}

/// The output array: one diagnostic per line, so that the text is both valid JSON and easy to
/// read and grep.
pub fn array_text(elements: &[JsonDiagnostic<'_>]) -> String {
    if elements.is_empty() {
        return "[]\n".to_owned();
    }
    let lines: Vec<String> = elements
        .iter()
        .map(|element| {
            // Plain data of strings and numbers: serialising it cannot fail.
            serde_json::to_string(element).unwrap_or_default()
        })
        .collect();
    format!("[\n  {}\n]\n", lines.join(",\n  "))
}

fn range(sources: &SourceMap, file: FileId, span: Span) -> JsonRange {
    let file = sources.get(file);
    let position = |offset: u32| {
        let LineCol { line, character } = file.line_index.line_col(&file.text, offset as usize);
        JsonPosition { line, character }
    };
    JsonRange {
        start: position(span.start),
        end: position(span.end),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positions_are_zero_based_utf16() {
        let mut sources = SourceMap::new();
        let text = "a = 1;\ns = \"é😀\"; b = c;\n";
        let main = sources.add("main.qcsg", text);
        let lib = sources.add("lib.qcsg", "c = 2;\n");
        let at = text.rfind('c').unwrap();
        let diagnostic = Diagnostic::error(
            "E0101",
            "undefined variable `c`",
            main,
            Span::new(at, at + 1),
        )
        .with_label(
            lib,
            Span::new(0, 1),
            "a `c` exists here, but is not visible",
        );
        let value = serde_json::to_value(JsonDiagnostic::new(&sources, &diagnostic)).unwrap();
        // `s = "é😀"; b = ` is 15 UTF-16 units (é is one unit, 😀 two) but 18 bytes.
        assert_eq!(
            value,
            serde_json::json!({
                "severity": "error",
                "code": "E0101",
                "message": "undefined variable `c`",
                "file": "main.qcsg",
                "range": {"start": {"line": 1, "character": 15}, "end": {"line": 1, "character": 16}},
                "byte_range": [at, at + 1],
                "help": null,
                "labels": [{
                    "message": "a `c` exists here, but is not visible",
                    "byte_range": [0, 1],
                    "file": "lib.qcsg",
                    "range": {"start": {"line": 0, "character": 0}, "end": {"line": 0, "character": 1}},
                }],
            })
        );
        // The documented field order, for readers of the raw text.
        let compact = serde_json::to_string(&JsonDiagnostic::new(&sources, &diagnostic)).unwrap();
        let order = [
            "severity",
            "code",
            "message",
            "file",
            "range",
            "byte_range",
            "help",
            "labels",
        ]
        .map(|key| compact.find(&format!("\"{key}\":")).unwrap());
        assert!(order.is_sorted(), "{compact}");
    }
}
