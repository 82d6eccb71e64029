//! Syntax errors: the error type the explaining pass collects (lighter than chumsky's `Rich`),
//! and how each becomes a diagnostic with a readable message and a precise span.

use chumsky::DefaultExpected;
use chumsky::label::LabelError;
use chumsky::prelude::*;
use chumsky::util::MaybeRef;
use qcsg_diag::{Diagnostic, FileId, Span};

use super::{In, sp};
use crate::codes;
use crate::lexer::Tok;

/// The error type the parsers are generic over: [`EmptyErr`] for the fast first pass, [`SynErr`]
/// for the pass that explains errors.
pub(crate) trait SyntaxError<'t>:
    chumsky::error::Error<'t, In<'t>> + LabelError<'t, In<'t>, &'static str> + Clone + 't
{
    /// An error with a message of its own.
    fn custom(span: SimpleSpan, message: &str) -> Self;
}

impl<'t> SyntaxError<'t> for EmptyErr {
    fn custom(_: SimpleSpan, _: &str) -> Self {
        EmptyErr::default()
    }
}

/// A syntax error as the explaining pass collects it: what was found, and which tokens and
/// labelled constructs were expected there. Lighter than chumsky's `Rich` (no per-pattern
/// allocation, cheap merging), which matters because editors parse broken text all the time.
#[derive(Clone, Debug)]
pub(crate) struct SynErr {
    span: SimpleSpan,
    /// The token found; `None` at the end of the file (or for a custom error).
    pub(super) found: Option<Tok>,
    /// Tokens that would have been accepted.
    tokens: Vec<Tok>,
    /// Labelled constructs that would have been accepted ("expression", "`;` after assignment").
    labels: Vec<&'static str>,
    /// A message of its own instead of "expected …, found …".
    pub(super) custom: Option<String>,
}

impl SynErr {
    fn add_tokens<'t>(&mut self, expected: impl IntoIterator<Item = DefaultExpected<'t, Tok>>) {
        for pattern in expected {
            if let DefaultExpected::Token(tok) = pattern
                && !self.tokens.contains(&*tok)
            {
                self.tokens.push(*tok);
            }
        }
    }
    fn add_labels(&mut self, expected: impl IntoIterator<Item = &'static str>) {
        for label in expected {
            if !self.labels.contains(&label) {
                self.labels.push(label);
            }
        }
    }
    fn reset(&mut self, found: Option<MaybeRef<'_, Tok>>, span: SimpleSpan) {
        self.span = span;
        self.found = found.map(|t| *t);
        self.tokens.clear();
        self.labels.clear();
        self.custom = None;
    }
    fn new(found: Option<MaybeRef<'_, Tok>>, span: SimpleSpan) -> Self {
        Self {
            span,
            found: found.map(|t| *t),
            tokens: Vec::new(),
            labels: Vec::new(),
            custom: None,
        }
    }
}

impl<'t> chumsky::error::Error<'t, In<'t>> for SynErr {
    fn merge(mut self, other: Self) -> Self {
        if self.custom.is_none() {
            if other.custom.is_some() {
                return other;
            }
            for tok in other.tokens {
                if !self.tokens.contains(&tok) {
                    self.tokens.push(tok);
                }
            }
            self.add_labels(other.labels);
        }
        self
    }
}

impl<'t> LabelError<'t, In<'t>, DefaultExpected<'t, Tok>> for SynErr {
    fn expected_found<E: IntoIterator<Item = DefaultExpected<'t, Tok>>>(
        expected: E,
        found: Option<MaybeRef<'t, Tok>>,
        span: SimpleSpan,
    ) -> Self {
        let mut error = SynErr::new(found, span);
        error.add_tokens(expected);
        error
    }
    fn merge_expected_found<E: IntoIterator<Item = DefaultExpected<'t, Tok>>>(
        mut self,
        expected: E,
        _found: Option<MaybeRef<'t, Tok>>,
        _span: SimpleSpan,
    ) -> Self {
        if self.custom.is_none() {
            self.add_tokens(expected);
        }
        self
    }
    fn replace_expected_found<E: IntoIterator<Item = DefaultExpected<'t, Tok>>>(
        mut self,
        expected: E,
        found: Option<MaybeRef<'t, Tok>>,
        span: SimpleSpan,
    ) -> Self {
        self.reset(found, span);
        self.add_tokens(expected);
        self
    }
}

impl<'t> LabelError<'t, In<'t>, &'static str> for SynErr {
    fn expected_found<E: IntoIterator<Item = &'static str>>(
        expected: E,
        found: Option<MaybeRef<'t, Tok>>,
        span: SimpleSpan,
    ) -> Self {
        let mut error = SynErr::new(found, span);
        error.add_labels(expected);
        error
    }
    fn merge_expected_found<E: IntoIterator<Item = &'static str>>(
        mut self,
        expected: E,
        _found: Option<MaybeRef<'t, Tok>>,
        _span: SimpleSpan,
    ) -> Self {
        if self.custom.is_none() {
            self.add_labels(expected);
        }
        self
    }
    fn replace_expected_found<E: IntoIterator<Item = &'static str>>(
        mut self,
        expected: E,
        found: Option<MaybeRef<'t, Tok>>,
        span: SimpleSpan,
    ) -> Self {
        self.reset(found, span);
        self.add_labels(expected);
        self
    }
    fn label_with(&mut self, label: &'static str) {
        // As chumsky's `Rich`: a label stands for everything expected inside it.
        if self.custom.is_none() {
            self.tokens.clear();
            self.labels.clear();
            self.labels.push(label);
        }
    }
}

impl<'t> SyntaxError<'t> for SynErr {
    fn custom(span: SimpleSpan, message: &str) -> Self {
        SynErr {
            span,
            found: None,
            tokens: Vec::new(),
            labels: Vec::new(),
            custom: Some(message.to_owned()),
        }
    }
}

/// The innermost opening delimiter left unclosed at the end of the tokens, if any.
fn unclosed_delimiter(tokens: &[(Tok, SimpleSpan)]) -> Option<(Tok, SimpleSpan)> {
    let mut stack: Vec<(Tok, SimpleSpan)> = Vec::new();
    for &(tok, span) in tokens {
        let opener = match tok {
            Tok::LParen | Tok::LBracket | Tok::LBrace => {
                stack.push((tok, span));
                continue;
            }
            Tok::RParen => Tok::LParen,
            Tok::RBracket => Tok::LBracket,
            Tok::RBrace => Tok::LBrace,
            _ => continue,
        };
        if stack.last().is_some_and(|(t, _)| *t == opener) {
            stack.pop();
        }
    }
    stack.pop()
}

/// Turns a chumsky error into a diagnostic with a readable message and a precise span.
pub(super) fn to_diagnostic(
    error: &SynErr,
    tokens: &[(Tok, SimpleSpan)],
    text: &str,
    file: FileId,
) -> Diagnostic {
    let span = error.span;
    let found = error.found;
    match &error.custom {
        Some(message) => {
            let code = if message.starts_with("unexpected closing") {
                codes::UNEXPECTED_CLOSING_DELIMITER
            } else {
                codes::EXPECTED
            };
            Diagnostic::error(code, message.clone(), file, sp(span))
        }
        None => {
            let labels: Vec<String> = error.labels.iter().map(|l| (*l).to_owned()).collect();
            let toks: Vec<String> = error
                .tokens
                .iter()
                .map(|t| t.describe().to_owned())
                .collect();
            // Labels say what was wanted in words; fall back to tokens only without them.
            let mut wanted = if labels.is_empty() { toks } else { labels };
            wanted.sort();
            wanted.dedup();
            // A named argument starts with an identifier, which is an expression too.
            if wanted.iter().any(|w| w == "expression") {
                wanted.retain(|w| w != "identifier");
            }
            // A specific "`;` after …" beats a plain "`;`".
            let specific: Vec<String> = wanted
                .iter()
                .filter(|w| w.contains(" after "))
                .cloned()
                .collect();
            if !specific.is_empty() {
                wanted.retain(|w| {
                    !specific.iter().any(|s| s.starts_with(w.as_str())) || w.contains(" after ")
                });
            }
            let wanted_text = match wanted.len() {
                0 => "something else".to_owned(),
                1 => wanted[0].clone(),
                n => format!("{} or {}", wanted[..n - 1].join(", "), wanted[n - 1]),
            };
            let found_text = match found {
                Some(t) => t.describe().to_owned(),
                None => "end of file".to_owned(),
            };
            if found.is_none()
                && let Some((open, open_span)) = unclosed_delimiter(tokens)
            {
                let close = match open {
                    Tok::LParen => "`)`",
                    Tok::LBracket => "`]`",
                    _ => "`}`",
                };
                return Diagnostic::error(
                    codes::UNCLOSED_DELIMITER,
                    format!("unclosed {open}"),
                    file,
                    sp(open_span),
                )
                .with_label(
                    file,
                    Span::empty(text.len()),
                    format!("expected {close} before the end of the file"),
                );
            }
            let code = if wanted.len() == 1 && wanted[0] == "`<path>`" {
                codes::MISSING_PATH
            } else {
                codes::EXPECTED
            };
            let message = format!("expected {wanted_text}, found {found_text}");
            // "Expected `;`" and friends point just after the previous token, where the missing
            // token belongs, rather than at whatever follows on the next line.
            let only_closers = !wanted.is_empty()
                && (wanted.iter().any(|w| w.starts_with("`;`"))
                    || wanted
                        .iter()
                        .all(|w| w == "`)`" || w == "`]`" || w == "`}`" || w == "`,`"));
            let primary = if only_closers || found.is_none() {
                let index = tokens.partition_point(|(_, s)| s.start < span.start);
                match index.checked_sub(1).and_then(|i| tokens.get(i)) {
                    Some((_, prev)) => Span::empty(prev.end),
                    None => Span::empty(span.start.min(text.len())),
                }
            } else {
                sp(span)
            };
            Diagnostic::error(code, message, file, primary)
        }
    }
}
