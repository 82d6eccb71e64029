//! Lexer, recovering parser and span-carrying AST of the qcsg language (docs/language.md).
//!
//! [`parse`] never fails: it returns a tree for everything it could read plus a diagnostic for
//! every error it recovered from. This crate knows nothing of evaluation or of editors.
//!
//! Stages: [`lexer::lex`] (logos) turns the text into tokens, keeps comments aside and bounds the
//! nesting depth; the parser (chumsky, grammar in `grammar/qcsg.ebnf`) builds the [`ast`]. A
//! valid file is parsed once with a zero-cost error type; only a file with errors is parsed a
//! second time to explain them. Diagnostic codes are in [`codes`]; [`sexpr`] prints trees;
//! [`walk`] visits every node of one.
//! A file is read in a [`Dialect`]: `.scad` files take OpenSCAD's reading of string escapes
//! (module [`escape`]), `.qcsg` files are strict.

pub mod ast;
pub mod codes;
mod doc;
pub mod escape;
pub mod lexer;
mod parser;
pub mod sexpr;
pub mod walk;

pub use ast::SourceFile;
pub use escape::Dialect;
pub use qcsg_diag::{Diagnostic, FileId, Span};

/// The result of parsing one file: a tree (with error nodes where the text is broken) and the
/// syntax diagnostics.
#[derive(Clone, Debug)]
pub struct Parse {
    /// The tree; always present.
    pub file: SourceFile,
    /// Lexical and syntax errors, in source order.
    pub diagnostics: Vec<Diagnostic>,
}

/// Parses one `.qcsg` file. Never fails and never panics: syntax errors become diagnostics
/// (attributed to `file`) and error nodes in the tree.
pub fn parse(text: &str, file: FileId) -> Parse {
    parse_as(text, file, Dialect::Qcsg)
}

/// Parses one file in the given dialect ([`Dialect::of_file`] tells it by the file's name), as
/// [`parse`] does.
pub fn parse_as(text: &str, file: FileId, dialect: Dialect) -> Parse {
    let lexed = lexer::lex(text, file);
    let mut diagnostics = lexed.diagnostics;
    // Escapes are checked once here; the parser decodes strings without reporting.
    for &(tok, span) in &lexed.tokens {
        if let lexer::Tok::Str(terminated) = tok {
            let end = if terminated {
                span.end as usize - 1
            } else {
                span.end as usize
            };
            let body = &text[span.start as usize + 1..end];
            let mut found = Vec::new();
            escape::unescape(body, span.start as usize + 1, file, dialect, &mut found);
            // An unterminated literal runs to the end of the file: its error says it all, so
            // OpenSCAD's readings of what it swallowed are not worth a warning each.
            found.retain(|d| terminated || d.is_error());
            diagnostics.append(&mut found);
        }
    }
    let tokens: Vec<(lexer::Tok, chumsky::span::SimpleSpan)> = lexed
        .tokens
        .iter()
        .map(|&(tok, span)| (tok, chumsky::span::SimpleSpan::from(span.range())))
        .collect();
    let eof_reported = diagnostics.iter().any(|d| {
        d.code == codes::UNTERMINATED_STRING || d.code == codes::UNTERMINATED_BLOCK_COMMENT
    });
    let eof_reported = eof_reported || tokens.last().is_some_and(|t| t.0 == lexer::Tok::TooDeep);
    let (stmts, syntax) =
        parser::parse_tokens(text, &lexed.comments, &tokens, file, dialect, eof_reported);
    // What follows a too-deep region is not worth reporting: the region itself was.
    let too_deep_at = diagnostics
        .iter()
        .filter(|d| d.code == codes::NESTING_TOO_DEEP)
        .map(|d| d.span.start)
        .min()
        .unwrap_or(u32::MAX);
    diagnostics.extend(syntax.into_iter().filter(|d| d.span.start < too_deep_at));
    qcsg_diag::sort_diagnostics(&mut diagnostics);
    Parse {
        file: SourceFile {
            stmts,
            comments: lexed.comments,
        },
        diagnostics,
    }
}
