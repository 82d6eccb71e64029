//! Conversions from `qcsg-ide`'s plain data to LSP types. Positions need no arithmetic: both
//! count lines from zero and columns in UTF-16 code units.

use qcsg_ide::{self as ide, LineCol, Severity, TextRange};
use tower_lsp_server::ls_types::{
    self as lsp, DiagnosticRelatedInformation, DiagnosticSeverity, DiagnosticTag, Location,
    NumberOrString, Position, Range, SemanticTokenModifier, SemanticTokenType,
    SemanticTokensLegend, Uri,
};

/// An LSP position as a [`LineCol`].
pub fn line_col(position: Position) -> LineCol {
    LineCol {
        line: position.line,
        character: position.character,
    }
}

/// A [`LineCol`] as an LSP position.
pub fn position(line_col: LineCol) -> Position {
    Position::new(line_col.line, line_col.character)
}

/// A [`TextRange`] as an LSP range.
pub fn range(range: TextRange) -> Range {
    Range::new(position(range.start), position(range.end))
}

/// An LSP range as a [`TextRange`].
pub fn text_range(range: Range) -> TextRange {
    TextRange {
        start: line_col(range.start),
        end: line_col(range.end),
    }
}

/// The URI of a file the analysis names: the document's own URI for the main file, a `file:`
/// URI for the others.
pub fn uri_of(file: &str, main_path: &str, main_uri: &Uri) -> Option<Uri> {
    if file == main_path {
        Some(main_uri.clone())
    } else {
        Uri::from_file_path(file)
    }
}

/// A [`ide::FileRange`] as an LSP location.
pub fn location(file_range: &ide::FileRange, main_path: &str, main_uri: &Uri) -> Option<Location> {
    Some(Location::new(
        uri_of(&file_range.file, main_path, main_uri)?,
        range(file_range.range),
    ))
}

/// An [`ide::IdeDiagnostic`] as an LSP diagnostic.
pub fn diagnostic(d: &ide::IdeDiagnostic, main_path: &str, main_uri: &Uri) -> lsp::Diagnostic {
    let severity = match d.severity {
        Severity::Error => DiagnosticSeverity::ERROR,
        Severity::Warning => DiagnosticSeverity::WARNING,
        Severity::Info => DiagnosticSeverity::INFORMATION,
        Severity::Hint => DiagnosticSeverity::HINT,
    };
    let related: Vec<_> = d
        .related
        .iter()
        .filter_map(|r| {
            Some(DiagnosticRelatedInformation {
                location: location(&r.location, main_path, main_uri)?,
                message: r.message.clone(),
            })
        })
        .collect();
    lsp::Diagnostic {
        range: range(d.range),
        severity: Some(severity),
        code: Some(NumberOrString::String(d.code.to_owned())),
        source: Some("qcsg".to_owned()),
        message: d.message.clone(),
        related_information: (!related.is_empty()).then_some(related),
        tags: d.unnecessary.then(|| vec![DiagnosticTag::UNNECESSARY]),
        ..lsp::Diagnostic::default()
    }
}

/// The most diagnostics published for one file. An editor lists no more usefully, and each one
/// is held, copied and serialised again on every change: a file of 280,000 stray `)` took the
/// server past 1 GB and 24 s to publish them.
pub const MAX_PUBLISHED: usize = 1_000;

/// At most [`MAX_PUBLISHED`] of `diagnostics`, errors first (each severity in the order given),
/// then, where some were left out, one more saying how many and where the first of them is.
pub fn capped(mut diagnostics: Vec<lsp::Diagnostic>) -> Vec<lsp::Diagnostic> {
    if diagnostics.len() <= MAX_PUBLISHED {
        return diagnostics;
    }
    diagnostics.sort_by_key(|d| d.severity != Some(DiagnosticSeverity::ERROR));
    let left_out = diagnostics.len() - MAX_PUBLISHED;
    let first_left_out = diagnostics[MAX_PUBLISHED].range;
    diagnostics.truncate(MAX_PUBLISHED);
    diagnostics.push(lsp::Diagnostic {
        range: first_left_out,
        severity: Some(DiagnosticSeverity::INFORMATION),
        source: Some("qcsg".to_owned()),
        message: format!(
            "{left_out} more diagnostics in this file are not shown, the first of them here; \
             `qcsg check` lists them all"
        ),
        ..lsp::Diagnostic::default()
    });
    diagnostics
}

/// The legend of [`semantic_tokens`], in [`ide::TokenKind::ALL`] order.
pub fn semantic_legend() -> SemanticTokensLegend {
    let token_types = ide::TokenKind::ALL
        .iter()
        .map(|kind| match kind {
            ide::TokenKind::Keyword => SemanticTokenType::KEYWORD,
            ide::TokenKind::Number => SemanticTokenType::NUMBER,
            ide::TokenKind::String => SemanticTokenType::STRING,
            ide::TokenKind::Comment => SemanticTokenType::COMMENT,
            ide::TokenKind::Function => SemanticTokenType::FUNCTION,
            // Modules are procedures that make solids; `macro` keeps them apart from functions.
            ide::TokenKind::Module => SemanticTokenType::MACRO,
            ide::TokenKind::Variable => SemanticTokenType::VARIABLE,
            ide::TokenKind::Parameter => SemanticTokenType::PARAMETER,
            ide::TokenKind::SpecialVariable => SemanticTokenType::new("specialVariable"),
        })
        .collect();
    let token_modifiers = ide::TokenModifiers::NAMES
        .iter()
        .map(|name| SemanticTokenModifier::new(name))
        .collect();
    SemanticTokensLegend {
        token_types,
        token_modifiers,
    }
}

/// Absolute tokens as LSP's relative encoding.
pub fn semantic_tokens(tokens: &[ide::SemanticToken]) -> Vec<lsp::SemanticToken> {
    let mut previous = (0, 0);
    tokens
        .iter()
        .map(|token| {
            let delta_line = token.line - previous.0;
            let delta_start = if delta_line == 0 {
                token.start - previous.1
            } else {
                token.start
            };
            previous = (token.line, token.start);
            lsp::SemanticToken {
                delta_line,
                delta_start,
                length: token.length,
                token_type: ide::TokenKind::ALL
                    .iter()
                    .position(|k| *k == token.kind)
                    .unwrap_or(0) as u32,
                token_modifiers_bitset: token.modifiers.0,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at_line(line: u32, severity: DiagnosticSeverity) -> lsp::Diagnostic {
        lsp::Diagnostic {
            range: Range::new(Position::new(line, 0), Position::new(line, 1)),
            severity: Some(severity),
            ..lsp::Diagnostic::default()
        }
    }

    #[test]
    fn a_flood_of_diagnostics_is_capped_errors_first_with_a_count() {
        let few: Vec<_> = (0..10)
            .map(|l| at_line(l, DiagnosticSeverity::WARNING))
            .collect();
        assert_eq!(capped(few.clone()), few);
        // 700 warnings, then 800 errors.
        let flood: Vec<_> = (0..1_500)
            .map(|l| {
                let severity = if l < 700 {
                    DiagnosticSeverity::WARNING
                } else {
                    DiagnosticSeverity::ERROR
                };
                at_line(l, severity)
            })
            .collect();
        let published = capped(flood);
        assert_eq!(published.len(), MAX_PUBLISHED + 1);
        // Every error, in order, then the first 200 warnings.
        assert!(published[..800].iter().enumerate().all(|(i, d)| {
            d.severity == Some(DiagnosticSeverity::ERROR) && d.range.start.line == 700 + i as u32
        }));
        assert_eq!(published[999].range.start.line, 199);
        let summary = &published[MAX_PUBLISHED];
        assert_eq!(summary.range.start.line, 200);
        assert!(
            summary.message.starts_with("500 more diagnostics"),
            "{}",
            summary.message
        );
    }
}
