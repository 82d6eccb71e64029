//! The brackets and the call around the cursor, read from the tokens so that unfinished text
//! works.
//!
//! Completion runs on text being typed, and the recovering parser turns an unclosed call
//! (`sphere(r` at the end of the file, `translate([1, 2, 3], ` before its `)`) into one error
//! node: the tree no longer says that the cursor is inside an argument list. The tokens still do.
//! A statement never nests inside `(` or `[`, and `;`, `{` and `}` never appear inside them, so
//! the innermost unmatched opener before the cursor, looked for back to the nearest of those
//! three, is the bracket the cursor is in, and the same three end an argument list that was
//! never closed. For the same reason only the text between the top-level statements that end
//! with `;` or `}` around the cursor is lexed, so that the cost follows the statement being
//! edited rather than the file.

use qcsg_syntax::SourceFile;
use qcsg_syntax::lexer::{Tok, lex};

use crate::{FileId, Span};

/// The bracket the cursor is directly inside.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Bracket {
    /// `(`: an argument list, a parameter list, or the head of `if`, `for` or `let`.
    Paren,
    /// `[`: a vector, a range or a list comprehension.
    Square,
}

/// What surrounds the cursor.
#[derive(Clone, Debug, Default)]
pub(crate) struct Surroundings {
    /// The innermost unmatched bracket before the cursor, if any: inside one, only expressions
    /// (and the names of parameters, bindings and arguments) are written, never statements.
    pub bracket: Option<Bracket>,
    /// The call whose argument list that bracket opens, if it is one.
    pub call: Option<CallSite>,
}

/// A call whose argument list holds the cursor (at its top level, not nested in a bracket).
#[derive(Clone, Debug)]
pub(crate) struct CallSite {
    /// The called name.
    pub name: String,
    /// Where that name starts.
    pub name_start: usize,
    /// Where its `(` is.
    pub open: usize,
    /// Whether the call stands where a statement starts (a module instantiation); otherwise it is
    /// inside an expression (a function call). A guess from the tokens before the name, for calls
    /// the tree does not hold.
    pub statement: bool,
    /// Whether an argument's name may be written at the cursor: the cursor starts an argument or
    /// ends the name being typed at its start, and no `=` follows that name already.
    pub at_name: bool,
    /// The names of the call's other named arguments.
    pub named: Vec<String>,
    /// How many of its other arguments are positional.
    pub positional: usize,
}

/// What surrounds byte `offset` of `text` (whose tree is `tree`); nothing inside a comment or a
/// string.
pub(crate) fn surroundings(
    text: &str,
    tree: &SourceFile,
    file: FileId,
    offset: usize,
) -> Surroundings {
    let (start, end) = window(text, tree, offset);
    let mut found = surroundings_in(&text[start..end], file, offset - start);
    if let Some(call) = &mut found.call {
        call.name_start += start;
        call.open += start;
    }
    found
}

/// The part of `text` that decides what surrounds `offset`: from the end of the last top-level
/// statement before it that ends with `;` or `}` to the end of the first one after it that
/// does. Both scans of [`surroundings_in`] stop at those tokens anyway.
fn window(text: &str, tree: &SourceFile, offset: usize) -> (usize, usize) {
    let closes = |span: Span| text[..span.end as usize].ends_with([';', '}']);
    let first_after = tree
        .stmts
        .partition_point(|stmt| stmt.span.end as usize <= offset);
    let start = tree.stmts[..first_after]
        .iter()
        .rev()
        .find(|stmt| closes(stmt.span))
        .map_or(0, |stmt| stmt.span.end as usize);
    let end = tree.stmts[first_after..]
        .iter()
        .find(|stmt| closes(stmt.span))
        .map_or(text.len(), |stmt| stmt.span.end as usize);
    (start.min(offset), end.max(offset))
}

/// What surrounds byte `offset` of `text`, a window of the document.
fn surroundings_in(text: &str, file: FileId, offset: usize) -> Surroundings {
    let lexed = lex(text, file);
    let inside = |span: Span| (span.start as usize) < offset && offset < span.end as usize;
    let in_comment = lexed.comments.iter().any(|comment| {
        // A line comment runs to its end: a cursor there is still typing in it.
        inside(comment.span)
            || comment.span.end as usize == offset && text[comment.span.range()].starts_with("//")
    });
    let in_string = lexed.tokens.iter().any(|&(tok, span)| {
        matches!(tok, Tok::Str(_))
            && (inside(span) || tok == Tok::Str(false) && offset == span.end as usize)
    });
    if in_comment || in_string {
        return Surroundings::default();
    }
    let tokens = &lexed.tokens;
    let before = tokens.partition_point(|&(_, span)| (span.start as usize) < offset);
    let Some(open) = unmatched_opener(&tokens[..before]) else {
        return Surroundings::default();
    };
    let bracket = match tokens[open].0 {
        Tok::LParen => Bracket::Paren,
        _ => Bracket::Square,
    };
    Surroundings {
        bracket: Some(bracket),
        call: (bracket == Bracket::Paren)
            .then(|| call_site(text, tokens, open, before, offset))
            .flatten(),
    }
}

/// The index of the innermost `(` or `[` of `tokens` that no later token closes, looking back no
/// further than the nearest `;`, `{` or `}`.
fn unmatched_opener(tokens: &[(Tok, Span)]) -> Option<usize> {
    let mut depth = 0usize;
    for (i, &(tok, _)) in tokens.iter().enumerate().rev() {
        match tok {
            Tok::RParen | Tok::RBracket => depth += 1,
            Tok::LParen | Tok::LBracket if depth == 0 => return Some(i),
            Tok::LParen | Tok::LBracket => depth -= 1,
            Tok::Semi | Tok::LBrace | Tok::RBrace | Tok::TooDeep => return None,
            _ => {}
        }
    }
    None
}

/// The call whose `(` is `tokens[open]`, if a name precedes it; `before` tokens start before the
/// cursor at `offset`.
fn call_site(
    text: &str,
    tokens: &[(Tok, Span)],
    open: usize,
    before: usize,
    offset: usize,
) -> Option<CallSite> {
    let callee = open.checked_sub(1)?;
    let (callee_tok, callee_span) = tokens[callee];
    if !matches!(callee_tok, Tok::Ident | Tok::Assert | Tok::Echo) {
        return None;
    }
    // `module m(`, `function f(` open parameter lists; `v.x(` calls no name.
    if callee > 0 && matches!(tokens[callee - 1].0, Tok::Module | Tok::Function | Tok::Dot) {
        return None;
    }
    let arguments = argument_ranges(tokens, open);
    // The cursor's argument is the last one starting at or before it.
    let current = arguments
        .iter()
        .rposition(|&(start, _)| start <= before)
        .unwrap_or(0);
    let mut named = Vec::new();
    let mut positional = 0;
    for (i, &(start, end)) in arguments.iter().enumerate() {
        let argument = &tokens[start..end];
        if i == current || argument.is_empty() {
            continue;
        }
        match argument {
            [(Tok::Ident | Tok::SpecialIdent, name), (Tok::Assign, _), ..] => {
                named.push(text[name.range()].to_owned());
            }
            _ => positional += 1,
        }
    }
    let word = |&(_, span): &(Tok, Span)| {
        text[span.range()].starts_with(|c: char| c.is_ascii_alphabetic() || c == '_' || c == '$')
    };
    let typed = arguments.get(current).map_or(&tokens[..0], |&(start, _)| {
        &tokens[start..before.max(start)]
    });
    let mut next = before;
    // A name that starts right at the cursor is the one being written.
    if tokens
        .get(next)
        .is_some_and(|t| word(t) && t.1.start as usize == offset)
    {
        next += 1;
    }
    let at_name = match typed {
        [] => true,
        [token] => word(token) && token.1.end as usize >= offset,
        _ => false,
    } && tokens.get(next).is_none_or(|&(tok, _)| tok != Tok::Assign);
    Some(CallSite {
        name: text[callee_span.range()].to_owned(),
        name_start: callee_span.start as usize,
        open: tokens[open].1.start as usize,
        statement: starts_statement(tokens, callee),
        at_name,
        named,
        positional,
    })
}

/// The token ranges of the arguments of the list opened by `tokens[open]`, split at its top-level
/// commas; the list ends at its `)` or, unclosed, where a statement would go on.
fn argument_ranges(tokens: &[(Tok, Span)], open: usize) -> Vec<(usize, usize)> {
    let mut ranges = Vec::new();
    let mut start = open + 1;
    let mut depth = 0usize;
    let mut end = tokens.len();
    for (i, &(tok, _)) in tokens.iter().enumerate().skip(open + 1) {
        match tok {
            Tok::LParen | Tok::LBracket => depth += 1,
            Tok::RParen | Tok::RBracket if depth == 0 => {
                end = i;
                break;
            }
            Tok::RParen | Tok::RBracket => depth -= 1,
            Tok::Comma if depth == 0 => {
                ranges.push((start, i));
                start = i + 1;
            }
            Tok::Semi | Tok::LBrace | Tok::RBrace | Tok::TooDeep => {
                end = i;
                break;
            }
            _ => {}
        }
    }
    ranges.push((start, end.max(start)));
    ranges
}

/// Whether the name at `tokens[name]` stands where a statement starts: after nothing, `;`, a
/// block's brace, the `)` of a parent's arguments or of an `if`/`for` head, or `else`, with any
/// modifier characters (`!`, `#`, `%`, `*`) between.
fn starts_statement(tokens: &[(Tok, Span)], name: usize) -> bool {
    let mut first = name;
    while first > 0
        && matches!(
            tokens[first - 1].0,
            Tok::Bang | Tok::Hash | Tok::Percent | Tok::Star
        )
    {
        first -= 1;
    }
    match first.checked_sub(1) {
        None => true,
        Some(previous) => matches!(
            tokens[previous].0,
            Tok::Semi | Tok::LBrace | Tok::RBrace | Tok::RParen | Tok::Else
        ),
    }
}
