//! The formatter shared by `qcsg fmt` and the language server.
//!
//! It works on the token stream, not the tree, so that it cannot lose or reorder anything: every
//! token and comment is written back verbatim, in order; only the whitespace between them
//! changes. Line breaks are the author's (runs of blank lines shrink to one), indentation follows
//! the nesting of brackets plus one level for a statement continued on the next line, and spaces
//! within a line follow one fixed style (`x = a + f(b, -c)[0];`, `for (i = [0 : 3])`). Formatting
//! is idempotent, and a file with syntax errors is refused rather than guessed at.

use std::fmt;

use qcsg_diag::{Diagnostic, FileId, Span};
use qcsg_syntax::Dialect;
use qcsg_syntax::lexer::{self, Tok};

/// The indentation of one level.
pub const INDENT: &str = "    ";

/// Why a text was not formatted.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FormatError {
    /// The syntax errors of the text.
    pub errors: Vec<Diagnostic>,
}

impl fmt::Display for FormatError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "the file has {} syntax error(s); fix them before formatting",
            self.errors.len()
        )
    }
}

impl std::error::Error for FormatError {}

/// A token or a comment, in source order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Item {
    Token(Tok),
    LineComment,
    BlockComment,
}

/// An open bracket.
#[derive(Clone, Copy, Debug)]
struct Open {
    tok: Tok,
    /// Indentation of the line it was opened on.
    line_indent: usize,
    /// Whether it is the parenthesised head of `for`, `if` or `let` (followed by a body).
    head: bool,
}

/// Formats `text` as a `.qcsg` file, or refuses if it has syntax errors.
pub fn format(text: &str) -> Result<String, FormatError> {
    format_as(text, Dialect::Qcsg)
}

/// Formats the text of the file called `name`, read in that file's dialect (a `.scad` file's
/// escapes that OpenSCAD accepts are warnings, not errors, so they do not stop formatting).
pub fn format_file(name: &str, text: &str) -> Result<String, FormatError> {
    format_as(text, Dialect::of_file(name))
}

/// Formats `text` read in `dialect`, or refuses if it has syntax errors. String literals are
/// kept as written, so formatting never changes what they mean.
pub fn format_as(text: &str, dialect: Dialect) -> Result<String, FormatError> {
    let parse = qcsg_syntax::parse_as(text, FileId(0), dialect);
    let errors: Vec<Diagnostic> = parse
        .diagnostics
        .into_iter()
        .filter(Diagnostic::is_error)
        .collect();
    if !errors.is_empty() {
        return Err(FormatError { errors });
    }
    let lexed = lexer::lex(text, FileId(0));
    let mut items: Vec<(Item, Span)> = lexed
        .tokens
        .iter()
        .map(|&(tok, span)| (Item::Token(tok), span))
        .collect();
    items.extend(lexed.comments.iter().map(|c| {
        let line = text[c.span.range()].starts_with("//");
        (
            if line {
                Item::LineComment
            } else {
                Item::BlockComment
            },
            c.span,
        )
    }));
    items.sort_by_key(|(_, span)| span.start);
    Ok(Formatter::default().run(text, &items))
}

#[derive(Default)]
struct Formatter {
    out: String,
    stack: Vec<Open>,
    line_indent: usize,
    /// Indentation of the line the current statement started on.
    statement_indent: usize,
    /// The last item written, and the last token (comments skipped).
    prev: Option<Item>,
    prev_token: Option<Tok>,
    /// The previous token was a prefix operator or a modifier: nothing separates it from what
    /// follows.
    prev_prefix: bool,
    /// The last `)` closed the head of a `for`, `if` or `let`.
    closed_head: bool,
    /// Inside the value of a statement-level `=` (so `*` and `%` are operators, not modifiers).
    in_value: bool,
}

impl Formatter {
    fn run(mut self, text: &str, items: &[(Item, Span)]) -> String {
        let mut prev_end = None;
        for &(item, span) in items {
            if let Some(end) = prev_end {
                let gap = &text[end..span.start as usize];
                let newlines = gap.matches('\n').count();
                if newlines > 0 {
                    self.out.push_str(&"\n".repeat(newlines.min(2)));
                    self.start_line(item);
                } else if matches!(item, Item::LineComment | Item::BlockComment) && !gap.is_empty()
                {
                    // A trailing comment keeps its distance: authors align them in columns.
                    self.out.push_str(&" ".repeat(gap.chars().count()));
                } else if self.space_before(item) {
                    self.out.push(' ');
                }
            }
            self.out.push_str(&text[span.range()]);
            self.after(item);
            prev_end = Some(span.end as usize);
        }
        if !self.out.is_empty() {
            self.out.push('\n');
        }
        self.out
    }

    fn block_level(&self) -> bool {
        self.stack.last().is_none_or(|open| open.tok == Tok::LBrace)
    }

    /// Indents a new line for `item`.
    fn start_line(&mut self, item: Item) {
        let indent = match (item, self.stack.last()) {
            (Item::Token(Tok::RParen | Tok::RBracket | Tok::RBrace), Some(open)) => {
                open.line_indent
            }
            (_, top) => {
                let base = top.map_or(0, |open| open.line_indent + 1);
                let continued = self.block_level()
                    && item != Item::Token(Tok::LBrace)
                    && self.prev_token.is_some_and(|t| {
                        !matches!(t, Tok::Semi | Tok::LBrace | Tok::RBrace | Tok::Path)
                    });
                match self.prev_token {
                    // A child statement on its own line goes one level deeper than its parent:
                    // `translate(v)` / `rotate(a)` / `cube();` steps in.
                    Some(Tok::RParen | Tok::Else) if continued => self.line_indent + 1,
                    _ if continued => self.statement_indent + 1,
                    _ => {
                        if self.block_level() {
                            self.statement_indent = base;
                        }
                        base
                    }
                }
            }
        };
        self.line_indent = indent;
        self.out.push_str(&INDENT.repeat(indent));
    }

    fn space_before(&self, item: Item) -> bool {
        let Item::Token(tok) = item else { return true };
        let Some(prev) = self.prev else { return false };
        let Item::Token(prev) = prev else { return true };
        // `2 .x` written `2.x` would lex as the number `2.` and then `x`.
        if tok == Tok::Dot && prev == Tok::Number {
            return true;
        }
        if matches!(
            tok,
            Tok::RParen | Tok::RBracket | Tok::Comma | Tok::Semi | Tok::Dot
        ) || matches!(prev, Tok::LParen | Tok::LBracket | Tok::Dot)
            || self.prev_prefix
        {
            return false;
        }
        let callee = matches!(
            prev,
            Tok::Ident | Tok::SpecialIdent | Tok::Assert | Tok::Echo | Tok::RBracket
        );
        match tok {
            Tok::LParen => !(callee || prev == Tok::RParen),
            Tok::LBracket => !(callee || prev == Tok::RParen && !self.closed_head),
            _ => true,
        }
    }

    /// Whether `tok`, coming now, is a prefix operator or a modifier.
    fn is_prefix(&self, tok: Tok) -> bool {
        let after_operand = match self.prev_token {
            None => false,
            Some(Tok::RParen) => !self.closed_head,
            Some(prev) => matches!(
                prev,
                Tok::Ident
                    | Tok::SpecialIdent
                    | Tok::Number
                    | Tok::Str(_)
                    | Tok::True
                    | Tok::False
                    | Tok::Undef
                    | Tok::RBracket
            ),
        };
        let statement_start = self.block_level()
            && !self.in_value
            && self.prev_token.is_none_or(|p| {
                matches!(
                    p,
                    Tok::Semi | Tok::LBrace | Tok::RBrace | Tok::RParen | Tok::Else
                )
            })
            || self.prev_prefix
                && matches!(
                    self.prev_token,
                    Some(Tok::Star | Tok::Percent | Tok::Hash | Tok::Bang)
                );
        match tok {
            Tok::Bang | Tok::Hash => true,
            Tok::Minus | Tok::Plus => !after_operand,
            Tok::Star | Tok::Percent => statement_start,
            _ => false,
        }
    }

    fn after(&mut self, item: Item) {
        self.prev = Some(item);
        let Item::Token(tok) = item else { return };
        let prefix = self.is_prefix(tok);
        match tok {
            Tok::LParen | Tok::LBracket | Tok::LBrace => {
                let head = tok == Tok::LParen
                    && matches!(self.prev_token, Some(Tok::For | Tok::If | Tok::Let));
                self.stack.push(Open {
                    tok,
                    line_indent: self.line_indent,
                    head,
                });
                if tok == Tok::LBrace {
                    self.in_value = false;
                }
            }
            Tok::RParen | Tok::RBracket | Tok::RBrace => {
                let open = self.stack.pop();
                self.closed_head = tok == Tok::RParen && open.is_some_and(|o| o.head);
                if tok == Tok::RBrace {
                    self.in_value = false;
                }
            }
            Tok::Assign if self.block_level() => self.in_value = true,
            Tok::Semi if self.block_level() => self.in_value = false,
            _ => {}
        }
        if tok != Tok::RParen {
            self.closed_head = false;
        }
        self.prev_prefix = prefix;
        self.prev_token = Some(tok);
    }
}
