//! The lexer (docs/language.md, "Lexical structure"): source text to a vector of spanned tokens plus the comments.
//!
//! Built on logos. Comments are not tokens for the parser: they are collected into
//! [`Lexed::comments`] so that the tree keeps them (formatting, folding, doc comments). Bad input
//! never stops the lexer: a run of invalid characters becomes one [`Tok::Error`] token and one
//! diagnostic, and unterminated strings, comments and paths are reported with their spans.

use std::fmt;

use logos::Logos;
use qcsg_diag::{Diagnostic, FileId, Span};

use crate::ast::{Comment, CommentKind};
use crate::codes;

/// A token kind. Tokens carry no text: the parser slices the source with the token's span, which
/// keeps tokens `Copy` and the token vector compact.
#[derive(Logos, Clone, Copy, Debug, PartialEq, Eq, Hash)]
// A byte-order mark (U+FEFF) counts as whitespace: editors on Windows write one.
#[logos(skip r"[ \t\r\n\x0C\u{FEFF}]+")]
pub enum Tok {
    /// A plain identifier: letters, digits and `_`, not all digits. As in OpenSCAD's lexer an
    /// identifier may start with digits (`8bit_font`); the longest match wins and a number wins
    /// a tie, so `1e5` and `2.5` are numbers while `1e5x` and `0x10` are identifiers.
    #[regex(r"[0-9]*[A-Za-z_][A-Za-z0-9_]*")]
    Ident,
    /// A special variable such as `$fn`.
    #[regex(r"\$[A-Za-z0-9_]*")]
    SpecialIdent,
    /// A number literal such as `1`, `1.5`, `.5`, `1.`, `1e-3`.
    #[regex(r"[0-9]+(\.[0-9]*)?([eE][+-]?[0-9]+)?", priority = 10)]
    #[regex(r"\.[0-9]+([eE][+-]?[0-9]+)?")]
    Number,
    /// A string literal; `false` when it runs to the end of the file without its closing quote.
    #[token("\"", lex_string)]
    Str(bool),
    /// `<path>` after `include` or `use` (produced by [`lex`], never by logos itself).
    Path,

    /// `module`
    #[token("module")]
    Module,
    /// `function`
    #[token("function")]
    Function,
    /// `if`
    #[token("if")]
    If,
    /// `else`
    #[token("else")]
    Else,
    /// `for`
    #[token("for")]
    For,
    /// `let`
    #[token("let")]
    Let,
    /// `each`
    #[token("each")]
    Each,
    /// `true`
    #[token("true")]
    True,
    /// `false`
    #[token("false")]
    False,
    /// `undef`
    #[token("undef")]
    Undef,
    /// `assert` (a name that also has a special expression form)
    #[token("assert")]
    Assert,
    /// `echo` (a name that also has a special expression form)
    #[token("echo")]
    Echo,
    /// `include`
    #[token("include")]
    Include,
    /// `use`
    #[token("use")]
    Use,

    /// `(`
    #[token("(")]
    LParen,
    /// `)`
    #[token(")")]
    RParen,
    /// `[`
    #[token("[")]
    LBracket,
    /// `]`
    #[token("]")]
    RBracket,
    /// `{`
    #[token("{")]
    LBrace,
    /// `}`
    #[token("}")]
    RBrace,
    /// `,`
    #[token(",")]
    Comma,
    /// `;`
    #[token(";")]
    Semi,
    /// `=`
    #[token("=")]
    Assign,
    /// `:`
    #[token(":")]
    Colon,
    /// `?`
    #[token("?")]
    Question,
    /// `.`
    #[token(".")]
    Dot,
    /// `+`
    #[token("+")]
    Plus,
    /// `-`
    #[token("-")]
    Minus,
    /// `*`
    #[token("*")]
    Star,
    /// `/`
    #[token("/")]
    Slash,
    /// `%`
    #[token("%")]
    Percent,
    /// `^`
    #[token("^")]
    Caret,
    /// `!`
    #[token("!")]
    Bang,
    /// `#`
    #[token("#")]
    Hash,
    /// `<`
    #[token("<")]
    Lt,
    /// `<=`
    #[token("<=")]
    Le,
    /// `>`
    #[token(">")]
    Gt,
    /// `>=`
    #[token(">=")]
    Ge,
    /// `==`
    #[token("==")]
    EqEq,
    /// `!=`
    #[token("!=")]
    Ne,
    /// `&&`
    #[token("&&")]
    AndAnd,
    /// `||`
    #[token("||")]
    OrOr,

    /// `// …` or `/// …` (never reaches the parser).
    #[regex(r"//[^\n]*", allow_greedy = true)]
    LineComment,
    /// `/* … */` or `/** … */`; `false` when unterminated (never reaches the parser).
    #[token("/*", lex_block_comment)]
    BlockComment(bool),

    /// A run of characters that start no token (reported once per run).
    Error,
    /// Stands for a region nested deeper than the parser accepts (reported once).
    TooDeep,
}

/// Scans a string body after its opening quote; `true` when the closing quote was found.
fn lex_string(lex: &mut logos::Lexer<'_, Tok>) -> bool {
    let rest = lex.remainder().as_bytes();
    let mut i = 0;
    while i < rest.len() {
        match rest[i] {
            b'"' => {
                lex.bump(i + 1);
                return true;
            }
            // Skip the escaped byte unless it would split a multi-byte character; escapes are
            // validated later.
            b'\\' if i + 1 < rest.len() && rest[i + 1].is_ascii() => i += 2,
            _ => i += 1,
        }
    }
    lex.bump(rest.len());
    false
}

/// Scans a block comment after `/*`; `true` when `*/` was found. Block comments do not nest.
fn lex_block_comment(lex: &mut logos::Lexer<'_, Tok>) -> bool {
    let rest = lex.remainder();
    match rest.find("*/") {
        Some(end) => {
            lex.bump(end + 2);
            true
        }
        None => {
            lex.bump(rest.len());
            false
        }
    }
}

impl Tok {
    /// How the token is shown in "expected …, found …" messages.
    pub fn describe(self) -> &'static str {
        use Tok::*;
        match self {
            Ident | SpecialIdent => "identifier",
            Number => "number",
            Str(_) => "string",
            Path => "`<path>`",
            Module => "`module`",
            Function => "`function`",
            If => "`if`",
            Else => "`else`",
            For => "`for`",
            Let => "`let`",
            Each => "`each`",
            True => "`true`",
            False => "`false`",
            Undef => "`undef`",
            Assert => "`assert`",
            Echo => "`echo`",
            Include => "`include`",
            Use => "`use`",
            LParen => "`(`",
            RParen => "`)`",
            LBracket => "`[`",
            RBracket => "`]`",
            LBrace => "`{`",
            RBrace => "`}`",
            Comma => "`,`",
            Semi => "`;`",
            Assign => "`=`",
            Colon => "`:`",
            Question => "`?`",
            Dot => "`.`",
            Plus => "`+`",
            Minus => "`-`",
            Star => "`*`",
            Slash => "`/`",
            Percent => "`%`",
            Caret => "`^`",
            Bang => "`!`",
            Hash => "`#`",
            Lt => "`<`",
            Le => "`<=`",
            Gt => "`>`",
            Ge => "`>=`",
            EqEq => "`==`",
            Ne => "`!=`",
            AndAnd => "`&&`",
            OrOr => "`||`",
            LineComment | BlockComment(_) => "comment",
            Error => "invalid character",
            TooDeep => "nested region",
        }
    }
}

impl fmt::Display for Tok {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.describe())
    }
}

/// The lexer's output.
#[derive(Clone, Debug, Default)]
pub struct Lexed {
    /// Tokens for the parser (no comments), with their byte spans.
    pub tokens: Vec<(Tok, Span)>,
    /// Every comment in source order.
    pub comments: Vec<Comment>,
    /// Lexical errors in source order.
    pub diagnostics: Vec<Diagnostic>,
}

/// Delimiters may nest this deep; deeper regions are replaced by one [`Tok::TooDeep`] token and
/// reported, which keeps the parser's recursion (and every later tree walk) bounded.
pub const MAX_NESTING: usize = 256;

/// The estimated depth of the tree (see `limit_nesting`) may reach this much.
pub const MAX_DEPTH: usize = 1024;

/// Splits `text` into tokens and comments. Never fails: problems become diagnostics and
/// [`Tok::Error`] tokens.
pub fn lex(text: &str, file: FileId) -> Lexed {
    let mut out = Lexed {
        tokens: Vec::with_capacity(text.len() / 3),
        ..Lexed::default()
    };
    let mut lexer = Tok::lexer(text);
    while let Some(result) = lexer.next() {
        let range = lexer.span();
        let span = Span::new(range.start, range.end);
        let tok = match result {
            Ok(tok) => tok,
            Err(()) => {
                // Merge a run of bad characters into one token and one diagnostic.
                if let Some((Tok::Error, last)) = out.tokens.last_mut()
                    && last.end == span.start
                {
                    last.end = span.end;
                    if let Some(diag) = out.diagnostics.last_mut() {
                        diag.span.end = span.end;
                    }
                    continue;
                }
                out.diagnostics.push(Diagnostic::error(
                    codes::INVALID_CHARACTER,
                    "invalid character",
                    file,
                    span,
                ));
                out.tokens.push((Tok::Error, span));
                continue;
            }
        };
        match tok {
            Tok::LineComment => {
                let slice = &text[span.range()];
                let kind = if slice.starts_with("///") && !slice.starts_with("////") {
                    CommentKind::DocLine
                } else {
                    CommentKind::Line
                };
                out.comments.push(Comment { kind, span });
            }
            Tok::BlockComment(terminated) => {
                let slice = &text[span.range()];
                let kind =
                    if slice.starts_with("/**") && !slice.starts_with("/***") && slice.len() > 4 {
                        CommentKind::DocBlock
                    } else {
                        CommentKind::Block
                    };
                if !terminated {
                    out.diagnostics.push(
                        Diagnostic::error(
                            codes::UNTERMINATED_BLOCK_COMMENT,
                            "unterminated block comment",
                            file,
                            Span {
                                start: span.start,
                                end: span.start + 2,
                            },
                        )
                        .with_help("close it with `*/`; block comments do not nest"),
                    );
                }
                out.comments.push(Comment { kind, span });
            }
            Tok::Str(terminated) => {
                if !terminated {
                    out.diagnostics.push(
                        Diagnostic::error(
                            codes::UNTERMINATED_STRING,
                            "unterminated string",
                            file,
                            Span {
                                start: span.start,
                                end: span.start + 1,
                            },
                        )
                        .with_help("add the closing `\"`"),
                    );
                }
                out.tokens.push((tok, span));
            }
            Tok::Include | Tok::Use => {
                out.tokens.push((tok, span));
                lex_path(&mut lexer, &mut out, file);
            }
            _ => out.tokens.push((tok, span)),
        }
    }
    limit_nesting(&mut out, file);
    out
}

/// After `include` / `use`: reads `<path>` if the next non-blank character is `<`.
fn lex_path(lexer: &mut logos::Lexer<'_, Tok>, out: &mut Lexed, file: FileId) {
    let rest = lexer.remainder();
    let blank = rest.len() - rest.trim_start_matches([' ', '\t']).len();
    if !rest[blank..].starts_with('<') {
        return;
    }
    let start = lexer.span().end + blank;
    let body = &rest[blank..];
    let line_end = body.find(['\n', '\r']).unwrap_or(body.len());
    match body[..line_end].find('>') {
        Some(close) => {
            out.tokens
                .push((Tok::Path, Span::new(start, start + close + 1)));
            lexer.bump(blank + close + 1);
        }
        None => {
            out.diagnostics.push(
                Diagnostic::error(
                    codes::UNTERMINATED_PATH,
                    "unterminated path: expected `>`",
                    file,
                    Span::new(start, start + line_end),
                )
                .with_help("write the path as `<file.scad>` on one line"),
            );
            out.tokens
                .push((Tok::Path, Span::new(start, start + line_end)));
            lexer.bump(blank + line_end);
        }
    }
}

/// Whether `tok` adds a level to the tree when it appears in a chain: operators and modifiers,
/// and keywords that take a nested body.
fn nests(tok: Tok) -> bool {
    use Tok::*;
    matches!(
        tok,
        Plus | Minus
            | Star
            | Slash
            | Percent
            | Caret
            | Bang
            | Hash
            | Lt
            | Le
            | Gt
            | Ge
            | EqEq
            | Ne
            | AndAnd
            | OrOr
            | Question
            | Dot
            | If
            | For
            | Let
            | Each
            | Function
            | Module
            | Assert
            | Echo
    )
}

/// Bounds how deep the tree can get, so that the parser and every recursive walk over the tree
/// stay within the stack.
///
/// The depth of the tree is estimated from the tokens: one level per open delimiter, plus one per
/// nesting token ([`nests`], a name or call right after `)` / `]`) since the last `,` or `;` (or
/// closed `{ … }` block) of each open delimiter level. Where the estimate passes
/// [`MAX_DEPTH`] (or the delimiters alone pass [`MAX_NESTING`]), the rest of that construct is
/// replaced by one [`Tok::TooDeep`] token and reported once.
fn limit_nesting(out: &mut Lexed, file: FileId) {
    if out.tokens.len() <= MAX_NESTING {
        return;
    }
    let tokens = std::mem::take(&mut out.tokens);
    let mut kept: Vec<(Tok, Span)> = Vec::with_capacity(tokens.len());
    // Nesting tokens counted per open delimiter level (index 0: the file itself), and the
    // delimiter that opened each level after the first.
    let mut counts: Vec<usize> = vec![0];
    let mut openers: Vec<Tok> = Vec::new();
    let mut total = 0usize;
    // Whether the construct being swallowed has been reported (cleared at the next statement).
    let mut reported = false;
    let mut i = 0;
    while i < tokens.len() {
        let (tok, span) = tokens[i];
        let prev = i.checked_sub(1).map(|p| tokens[p].0);
        let next = tokens.get(i + 1).map(|t| t.0);
        let after_group = matches!(prev, Some(Tok::RParen | Tok::RBracket));
        let weight = usize::from(
            nests(tok)
                || (after_group
                    && matches!(tok, Tok::Ident | Tok::LParen | Tok::LBracket | Tok::LBrace)),
        );
        let opens = matches!(tok, Tok::LParen | Tok::LBracket | Tok::LBrace);
        let too_deep = (opens && (counts.len() > MAX_NESTING || total + weight >= MAX_DEPTH))
            || (weight > 0 && total + weight > MAX_DEPTH);
        if too_deep {
            // Swallow the rest of the construct: to the matching closer of an opening delimiter,
            // otherwise to the next separator or closer of the current level.
            let mut inner = 0usize;
            let mut j = i;
            let mut end = span.end;
            while j < tokens.len() {
                let (t, s) = tokens[j];
                match t {
                    Tok::LParen | Tok::LBracket | Tok::LBrace => inner += 1,
                    Tok::RParen | Tok::RBracket | Tok::RBrace => {
                        if inner == 0 {
                            break;
                        }
                        inner -= 1;
                    }
                    Tok::Comma | Tok::Semi if inner == 0 => break,
                    _ => {}
                }
                end = s.end;
                j += 1;
                if opens && inner == 0 {
                    break;
                }
            }
            let region = Span {
                start: span.start,
                end,
            };
            // One report per deep construct: later regions of the same construct only extend it.
            if let Some((Tok::TooDeep, last)) = kept.last_mut() {
                last.end = end;
                i = j.max(i + 1);
                continue;
            }
            kept.push((Tok::TooDeep, region));
            i = j.max(i + 1);
            if reported {
                continue;
            }
            reported = true;
            out.diagnostics.push(
                Diagnostic::error(
                    codes::NESTING_TOO_DEEP,
                    "nesting too deep",
                    file,
                    Span {
                        start: span.start,
                        end: span.end,
                    },
                )
                .with_help(format!(
                    "at most {MAX_NESTING} nested brackets and about {MAX_DEPTH} nested operations \
                     are supported; split the construct into named parts"
                )),
            );
            continue;
        }
        kept.push((tok, span));
        i += 1;
        let level = counts.last_mut().expect("the file level is never popped");
        *level += weight;
        total += weight;
        match tok {
            Tok::LParen | Tok::LBracket | Tok::LBrace => {
                counts.push(0);
                openers.push(tok);
                total += 1;
            }
            // The parser skips a `)` or `]` inside a block as stray: it closes nothing, and
            // counted as closing the block it would let blocks nest without bound.
            Tok::RParen | Tok::RBracket if openers.last() == Some(&Tok::LBrace) => {}
            Tok::RParen | Tok::RBracket | Tok::RBrace if counts.len() > 1 => {
                openers.pop();
                total -= counts.pop().unwrap_or(0) + 1;
                // A closed block ends its statement unless an `else` continues it.
                if tok == Tok::RBrace && next != Some(Tok::Else) {
                    let level = counts.last_mut().expect("the file level is never popped");
                    total -= *level;
                    *level = 0;
                }
            }
            Tok::Comma | Tok::Semi if next != Some(Tok::Else) => {
                let level = counts.last_mut().expect("the file level is never popped");
                total -= *level;
                *level = 0;
                if counts.len() == 1 {
                    reported = false;
                }
            }
            _ => {}
        }
    }
    out.tokens = kept;
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kinds(text: &str) -> Vec<Tok> {
        lex(text, FileId::default())
            .tokens
            .into_iter()
            .map(|(t, _)| t)
            .collect()
    }

    #[test]
    fn numbers() {
        use Tok::*;
        assert_eq!(kinds("1 1.5 .5 1e-3 2.5E+4 1."), vec![Number; 6]);
        assert_eq!(kinds("v.x"), vec![Ident, Dot, Ident]);
    }

    /// OpenSCAD's flex lexer: identifiers may start with digits, the longest match wins, and a
    /// number wins a tie (`1e5` matches both rules).
    #[test]
    fn identifiers_may_start_with_digits() {
        use Tok::*;
        assert_eq!(kinds("8bit_polyfont"), vec![Ident]);
        assert_eq!(kinds("1e"), vec![Ident]);
        assert_eq!(kinds("1e5 1E+5 12 0.5 1.e5"), vec![Number; 5]);
        assert_eq!(kinds("1e5x 0x10 3d 12abc"), vec![Ident; 4]);
        assert_eq!(kinds("2.5abc"), vec![Number, Ident]);
        assert_eq!(kinds("1e-3x"), vec![Number, Ident]);
        assert_eq!(kinds("1.x"), vec![Number, Ident]);
        assert_eq!(kinds("a-1e"), vec![Ident, Minus, Ident]);
        assert_eq!(kinds("x=2d+1"), vec![Ident, Assign, Ident, Plus, Number]);
    }

    #[test]
    fn keywords_and_paths() {
        use Tok::*;
        assert_eq!(kinds("include <a/b.scad>"), vec![Include, Path]);
        assert_eq!(kinds("use<x>"), vec![Use, Path]);
        assert_eq!(kinds("a < b"), vec![Ident, Lt, Ident]);
        assert_eq!(kinds("$fn intersection_for"), vec![SpecialIdent, Ident]);
    }

    #[test]
    fn comments_are_kept_aside() {
        let lexed = lex("/// doc\n// c\n/** d */ /* e */ /**/ x", FileId::default());
        let kinds: Vec<_> = lexed.comments.iter().map(|c| c.kind).collect();
        use CommentKind::*;
        assert_eq!(kinds, vec![DocLine, Line, DocBlock, Block, Block]);
        assert_eq!(lexed.tokens.len(), 1);
    }

    #[test]
    fn byte_order_mark_is_whitespace() {
        let lexed = lex("\u{FEFF}x = 1;", FileId::default());
        assert!(lexed.diagnostics.is_empty());
        assert_eq!(lexed.tokens.len(), 4);
    }

    #[test]
    fn error_runs_are_merged() {
        let lexed = lex("a @@@ b", FileId::default());
        assert_eq!(lexed.diagnostics.len(), 1);
        assert_eq!(lexed.diagnostics[0].span, Span::new(2, 5));
    }
}
