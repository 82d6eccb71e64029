//! The recovering parser (docs/language.md, "Statements", "Expressions"): tokens to
//! [`SourceFile`] statements, built on chumsky.
//!
//! The grammar follows `grammar/qcsg.ebnf`. Expressions use chumsky's Pratt parser for the binary
//! and prefix operators; everything else is recursive descent written so that no alternative
//! re-parses a long prefix (vectors decide between list and range after their first element,
//! statements starting with a name decide after the name), which keeps parsing linear.
//!
//! Recovery: a missing `;` is reported and assumed; a statement that cannot be parsed is skipped up
//! to the next `;` or `}` (balanced groups skipped whole) and becomes [`StmtKind::Error`]; a
//! parenthesised or bracketed expression that cannot be parsed becomes [`ExprKind::Error`].
//! The errors themselves, and how they become diagnostics, are in [`errors`].

mod errors;

use chumsky::input::{Input as _, MappedInput};
use chumsky::pratt::{infix, left, prefix, right};
use chumsky::prelude::*;
use qcsg_diag::{Diagnostic, FileId, Span};

use crate::ast::*;
use crate::doc::doc_before;
use crate::escape::{Dialect, unescape};
use crate::lexer::Tok;

use errors::{SynErr, SyntaxError, to_diagnostic};

/// The parser's input: a slice of spanned tokens.
type In<'t> = MappedInput<'t, Tok, SimpleSpan, &'t [(Tok, SimpleSpan)]>;
/// What the parsers need besides the tokens: the text (to read names, numbers and strings) and
/// the comments (for doc comments).
#[derive(Clone, Copy)]
struct Ctx<'t> {
    text: &'t str,
    comments: &'t [Comment],
    /// How string escapes read.
    dialect: Dialect,
}

impl<'t> Ctx<'t> {
    fn ident(self, span: SimpleSpan) -> Ident {
        Ident {
            name: self.text[span.start..span.end].to_owned(),
            span: sp(span),
        }
    }
    fn number(self, span: SimpleSpan) -> f64 {
        // The lexer only produces digit strings that Rust's float parser accepts.
        self.text[span.start..span.end].parse().unwrap_or(f64::NAN)
    }
    fn string(self, span: SimpleSpan) -> String {
        let end = if span.end - span.start >= 2 && self.text[span.start..span.end].ends_with('"') {
            span.end - 1
        } else {
            span.end
        };
        let body = self.text.get(span.start + 1..end).unwrap_or("");
        // Escape errors were reported once by `lex`; here only the value matters.
        unescape(
            body,
            span.start + 1,
            FileId::default(),
            self.dialect,
            &mut Vec::new(),
        )
    }
    /// Whether a line break separates `offset` from the token before it.
    fn newline_before(self, offset: usize) -> bool {
        let before = &self.text.as_bytes()[..offset.min(self.text.len())];
        before
            .iter()
            .rev()
            .find(|b| !matches!(b, b' ' | b'\t' | b'\r'))
            == Some(&b'\n')
    }
    fn doc(self, start: usize) -> Option<Doc> {
        doc_before(self.text, self.comments, start)
    }
}

fn sp(span: SimpleSpan) -> Span {
    Span::new(span.start, span.end)
}

fn boxed_expr(kind: ExprKind, span: SimpleSpan) -> Box<Expr> {
    Box::new(Expr {
        kind,
        span: sp(span),
    })
}

/// Parses the token slice into top-level statements plus diagnostics. `eof_reported`: the lexer
/// already reported something that runs to the end of the file (an unterminated string or
/// comment), so "found end of file" errors would only repeat it.
pub(crate) fn parse_tokens(
    text: &str,
    comments: &[Comment],
    tokens: &[(Tok, SimpleSpan)],
    file: FileId,
    dialect: Dialect,
    eof_reported: bool,
) -> (Vec<Stmt>, Vec<Diagnostic>) {
    let ctx = Ctx {
        text,
        comments,
        dialect,
    };
    let eoi = SimpleSpan::from(text.len()..text.len());
    // Fast pass without error details: most files are valid, and building chumsky's rich errors
    // for every failed alternative costs more than the parse itself.
    let (stmts, errors) = file_parser::<EmptyErr>(ctx)
        .parse(tokens.split_token_span(eoi))
        .into_output_errors();
    if errors.is_empty()
        && let Some(stmts) = stmts
    {
        return (stmts, Vec::new());
    }
    let (stmts, errors) = file_parser::<SynErr>(ctx)
        .parse(tokens.split_token_span(eoi))
        .into_output_errors();
    let mut diagnostics: Vec<Diagnostic> = Vec::with_capacity(errors.len());
    let mut eof_done = eof_reported;
    let mut seen = std::collections::HashSet::new();
    for error in &errors {
        if error.custom.is_none() {
            match error.found {
                // The lexer reported these already.
                Some(Tok::Error | Tok::TooDeep) => continue,
                None if eof_done => continue,
                None => eof_done = true,
                Some(_) => {}
            }
        }
        let diagnostic = to_diagnostic(error, tokens, text, file);
        // A set, not a scan of the list: a broken file may have an error on every token.
        if seen.insert((diagnostic.span, diagnostic.message.clone())) {
            diagnostics.push(diagnostic);
        }
    }
    (stmts.unwrap_or_default(), diagnostics)
}

/// Builds the parser for a whole file.
fn file_parser<'t, E: SyntaxError<'t>>(
    ctx: Ctx<'t>,
) -> impl Parser<'t, In<'t>, Vec<Stmt>, extra::Err<E>> {
    let expr = expr_parser(ctx);
    let stmt = stmt_parser(ctx, expr);
    stmt.or(stray_closer([Tok::RParen, Tok::RBracket, Tok::RBrace]))
        .repeated()
        .collect::<Vec<_>>()
        .then_ignore(end())
}

/// A closing delimiter (one of `closers`) with nothing to close: reported, and read as an error
/// statement so that parsing moves on.
fn stray_closer<'t, E: SyntaxError<'t>>(
    closers: impl chumsky::container::Seq<'t, Tok> + Clone + 't,
) -> impl Parser<'t, In<'t>, Stmt, extra::Err<E>> + Clone {
    one_of(closers)
        .map_with(|_, e| Stmt {
            kind: StmtKind::Error,
            span: sp(e.span()),
            doc: None,
        })
        .validate(|stmt, e, emitter| {
            emitter.emit(E::custom(e.span(), "unexpected closing delimiter"));
            stmt
        })
}

/// Balanced `( … )` or `[ … ]` group, skipped whole during recovery. It does not cross a `;`:
/// a group still open there is left to the next statement (and a failed attempt does not look
/// ahead to the end of the file, which would misplace later errors).
fn balanced_groups<'t, E: SyntaxError<'t>>() -> impl Parser<'t, In<'t>, (), extra::Err<E>> + Clone {
    let mut stops = DELIMITERS.to_vec();
    stops.push(Tok::Semi);
    let inner = balanced().or(none_of(stops).ignored()).repeated();
    choice((
        inner
            .clone()
            .delimited_by(just(Tok::LParen), just(Tok::RParen)),
        inner.delimited_by(just(Tok::LBracket), just(Tok::RBracket)),
    ))
}

/// Balanced `{ … }` group, skipped whole during recovery.
fn balanced_braces<'t, E: SyntaxError<'t>>() -> impl Parser<'t, In<'t>, (), extra::Err<E>> + Clone {
    balanced()
        .or(none_of(DELIMITERS).ignored())
        .repeated()
        .delimited_by(just(Tok::LBrace), just(Tok::RBrace))
}

const DELIMITERS: [Tok; 6] = [
    Tok::LParen,
    Tok::RParen,
    Tok::LBracket,
    Tok::RBracket,
    Tok::LBrace,
    Tok::RBrace,
];

/// Balanced `( … )`, `[ … ]` or `{ … }` group, skipped whole during recovery.
fn balanced<'t, E: SyntaxError<'t>>() -> impl Parser<'t, In<'t>, (), extra::Err<E>> + Clone {
    recursive(|group| {
        let inner = group.or(none_of(DELIMITERS).ignored()).repeated();
        choice((
            inner
                .clone()
                .delimited_by(just(Tok::LParen), just(Tok::RParen)),
            inner
                .clone()
                .delimited_by(just(Tok::LBracket), just(Tok::RBracket)),
            inner.delimited_by(just(Tok::LBrace), just(Tok::RBrace)),
        ))
    })
}

/// Name of a variable, function or module: an identifier or a `$`-variable. `assert` and `echo`
/// are ordinary names where they are not the special expression forms.
fn name<'t, E: SyntaxError<'t>>(
    ctx: Ctx<'t>,
) -> impl Parser<'t, In<'t>, Ident, extra::Err<E>> + Clone {
    select! {
        Tok::Ident | Tok::SpecialIdent | Tok::Assert | Tok::Echo = e => ctx.ident(e.span()),
    }
    .labelled("identifier")
}

/// `name = value` (a `for`/`let` binding).
fn binding<'t, E: SyntaxError<'t>>(
    ctx: Ctx<'t>,
    expr: impl Parser<'t, In<'t>, Expr, extra::Err<E>> + Clone + 't,
) -> impl Parser<'t, In<'t>, Binding, extra::Err<E>> + Clone {
    name(ctx)
        .then_ignore(just(Tok::Assign).labelled("`=`"))
        .then(expr)
        .map_with(|(name, value), e| Binding {
            name,
            value,
            span: sp(e.span()),
        })
}

/// `( binding, … )`.
fn bindings<'t, E: SyntaxError<'t>>(
    ctx: Ctx<'t>,
    expr: impl Parser<'t, In<'t>, Expr, extra::Err<E>> + Clone + 't,
) -> impl Parser<'t, In<'t>, Vec<Binding>, extra::Err<E>> + Clone {
    binding(ctx, expr)
        .separated_by(just(Tok::Comma))
        .allow_trailing()
        .collect::<Vec<_>>()
        .delimited_by(just(Tok::LParen), just(Tok::RParen).labelled("`)`"))
}

/// `( param, … )` where a parameter is `name` or `name = default`.
fn params<'t, E: SyntaxError<'t>>(
    ctx: Ctx<'t>,
    expr: impl Parser<'t, In<'t>, Expr, extra::Err<E>> + Clone + 't,
) -> impl Parser<'t, In<'t>, Vec<Param>, extra::Err<E>> + Clone {
    name(ctx)
        .then(just(Tok::Assign).ignore_then(expr).or_not())
        .map_with(|(name, default), e| Param {
            name,
            default,
            span: sp(e.span()),
        })
        .separated_by(just(Tok::Comma))
        .allow_trailing()
        .collect::<Vec<_>>()
        .delimited_by(
            just(Tok::LParen).labelled("`(`"),
            just(Tok::RParen).labelled("`)`"),
        )
}

/// `( arg, … )` with its span; an argument is `value` or `name = value`.
fn args<'t, E: SyntaxError<'t>>(
    ctx: Ctx<'t>,
    expr: impl Parser<'t, In<'t>, Expr, extra::Err<E>> + Clone + 't,
) -> impl Parser<'t, In<'t>, (Vec<Arg>, Span), extra::Err<E>> + Clone {
    let named = name(ctx).then_ignore(just(Tok::Assign)).then(expr.clone());
    named
        .map(|(name, value)| (Some(name), value))
        .or(expr.map(|value| (None, value)))
        .map_with(|(name, value), e| Arg {
            name,
            value,
            span: sp(e.span()),
        })
        .separated_by(just(Tok::Comma))
        .allow_trailing()
        .collect::<Vec<_>>()
        .delimited_by(just(Tok::LParen), just(Tok::RParen).labelled("`)`"))
        .map_with(|args, e| (args, sp(e.span())))
        .boxed()
}

/// The expression parser.
fn expr_parser<'t, E: SyntaxError<'t>>(
    ctx: Ctx<'t>,
) -> impl Parser<'t, In<'t>, Expr, extra::Err<E>> + Clone {
    recursive(move |expr| {
        let expr = expr.boxed();
        // One token decides a literal or a name: a single `select` instead of a `choice`.
        let literal = select! {
            Tok::Number = e => ExprKind::Number(ctx.number(e.span())),
            Tok::Str(_) = e => ExprKind::String(ctx.string(e.span())),
            Tok::True => ExprKind::Bool(true),
            Tok::False => ExprKind::Bool(false),
            Tok::Undef => ExprKind::Undef,
            Tok::TooDeep => ExprKind::Error,
            Tok::Ident | Tok::SpecialIdent = e => ExprKind::Ident(ctx.ident(e.span())),
        }
        // `assert` and `echo` are names only where no `(` follows: `echo(` always starts the
        // special form, and a broken one must not be parsed again as a call, which doubled
        // the work at every level of `echo(echo(…`.
        .or(one_of([Tok::Assert, Tok::Echo])
            .then_ignore(just(Tok::LParen).not())
            .map_with(move |_, e| ExprKind::Ident(ctx.ident(e.span()))))
        .map_with(|kind, e| Expr {
            kind,
            span: sp(e.span()),
        });

        // A parenthesised expression left open does not fail once what it holds is read: its
        // `)` is reported and assumed. Failing would make the operator before it give up its
        // right operand and the enclosing expression parse it all again, which doubles the work
        // at every level of `2 * (1 + 2 * (1 + …` left open.
        let paren = expr
            .clone()
            .delimited_by(just(Tok::LParen), closer(Tok::RParen, "`)`"))
            .map_with(|inner, e| Expr {
                kind: ExprKind::Paren(Box::new(inner)),
                span: sp(e.span()),
            })
            .recover_with(via_parser(nested_delimiters(
                Tok::LParen,
                Tok::RParen,
                [(Tok::LBracket, Tok::RBracket), (Tok::LBrace, Tok::RBrace)],
                |span| Expr {
                    kind: ExprKind::Error,
                    span: sp(span),
                },
            )));

        let vector = bracket_parser(ctx, expr.clone()).recover_with(via_parser(nested_delimiters(
            Tok::LBracket,
            Tok::RBracket,
            [(Tok::LParen, Tok::RParen), (Tok::LBrace, Tok::RBrace)],
            |span| Expr {
                kind: ExprKind::Error,
                span: sp(span),
            },
        )));

        // A group that failed at a position fails there again: remember that. `-1 ^ (…` tries
        // the power's operand twice (once inside the `-`, once after it), so a failing group
        // under `-… ^` at every level was parsed twice as often per level.
        let atom = choice((literal, paren.memoized(), vector.memoized()))
            .labelled("expression")
            .boxed();

        enum Postfix {
            Call(Vec<Arg>, Span),
            Index(Expr),
            Member(Ident),
        }
        let postfix_op = choice((
            args(ctx, expr.clone()).map(|(a, s)| Postfix::Call(a, s)),
            expr.clone()
                .delimited_by(just(Tok::LBracket), just(Tok::RBracket).labelled("`]`"))
                .map(Postfix::Index),
            just(Tok::Dot).ignore_then(name(ctx)).map(Postfix::Member),
        ));
        let postfix = atom.foldl_with(postfix_op.repeated(), |base, op, e| {
            let base = Box::new(base);
            let kind = match op {
                Postfix::Call(args, args_span) => ExprKind::Call {
                    callee: base,
                    args,
                    args_span,
                },
                Postfix::Index(index) => ExprKind::Index {
                    base,
                    index: Box::new(index),
                },
                Postfix::Member(member) => ExprKind::Member { base, member },
            };
            Expr {
                kind,
                span: sp(e.span()),
            }
        });

        use BinaryOp as B;
        type Extra<'t, 'b, E> = chumsky::input::MapExtra<'t, 'b, In<'t>, extra::Err<E>>;
        let binary = |lhs: Expr,
                      (op, op_span): (BinaryOp, SimpleSpan),
                      rhs: Expr,
                      e: &mut Extra<'t, '_, E>| Expr {
            kind: ExprKind::Binary {
                op,
                op_span: sp(op_span),
                lhs: Box::new(lhs),
                rhs: Box::new(rhs),
            },
            span: sp(e.span()),
        };
        let unary =
            |(op, op_span): (UnaryOp, SimpleSpan), operand: Expr, e: &mut Extra<'t, '_, E>| Expr {
                kind: ExprKind::Unary {
                    op,
                    op_span: sp(op_span),
                    operand: Box::new(operand),
                },
                span: sp(e.span()),
            };
        // One operator parser per precedence level: fewer failed alternatives per token.
        let operators = postfix
            .pratt((
                infix(right(8), select! { Tok::Caret => B::Pow }.map_with(|op, e| (op, e.span())), binary),
                prefix(
                    7,
                    select! { Tok::Minus => UnaryOp::Neg, Tok::Plus => UnaryOp::Plus, Tok::Bang => UnaryOp::Not }
                        .map_with(|op, e| (op, e.span())),
                    unary,
                ),
                infix(
                    left(6),
                    select! { Tok::Star => B::Mul, Tok::Slash => B::Div, Tok::Percent => B::Rem }
                        .map_with(|op, e| (op, e.span())),
                    binary,
                ),
                infix(
                    left(5),
                    select! { Tok::Plus => B::Add, Tok::Minus => B::Sub }.map_with(|op, e| (op, e.span())),
                    binary,
                ),
                infix(
                    left(4),
                    select! { Tok::Lt => B::Lt, Tok::Le => B::Le, Tok::Gt => B::Gt, Tok::Ge => B::Ge }
                        .map_with(|op, e| (op, e.span())),
                    binary,
                ),
                infix(
                    left(3),
                    select! { Tok::EqEq => B::Eq, Tok::Ne => B::Ne }.map_with(|op, e| (op, e.span())),
                    binary,
                ),
                infix(left(2), select! { Tok::AndAnd => B::And }.map_with(|op, e| (op, e.span())), binary),
                infix(left(1), select! { Tok::OrOr => B::Or }.map_with(|op, e| (op, e.span())), binary),
            ))
            .boxed();

        let ternary = operators
            .then(
                just(Tok::Question)
                    .ignore_then(expr.clone())
                    .then_ignore(just(Tok::Colon).labelled("`:`"))
                    .then(expr.clone())
                    .or_not(),
            )
            .map_with(|(cond, branches), e| match branches {
                None => cond,
                Some((then, els)) => Expr {
                    kind: ExprKind::Ternary {
                        cond: Box::new(cond),
                        then: Box::new(then),
                        els: Box::new(els),
                    },
                    span: sp(e.span()),
                },
            });

        let let_expr = just(Tok::Let)
            .ignore_then(bindings(ctx, expr.clone()))
            .then(expr.clone())
            .map_with(|(bindings, body), e| {
                boxed_expr(
                    ExprKind::Let {
                        bindings,
                        body: Box::new(body),
                    },
                    e.span(),
                )
            })
            .map(|b| *b);
        let function_lit = just(Tok::Function)
            .ignore_then(params(ctx, expr.clone()))
            .then(expr.clone())
            .map_with(|(params, body), e| Expr {
                kind: ExprKind::FunctionLit {
                    params,
                    body: Box::new(body),
                },
                span: sp(e.span()),
            });
        // `assert(…) body` / `echo(…) body`: the body is optional, as in OpenSCAD.
        let special = one_of([Tok::Assert, Tok::Echo])
            .then(args(ctx, expr.clone()))
            .then(expr.clone().or_not())
            .map_with(|((tok, (args, args_span)), body), e| {
                let body = body.map(Box::new);
                let kind = if tok == Tok::Assert {
                    ExprKind::Assert {
                        args,
                        args_span,
                        body,
                    }
                } else {
                    ExprKind::Echo {
                        args,
                        args_span,
                        body,
                    }
                };
                Expr {
                    kind,
                    span: sp(e.span()),
                }
            });

        choice((let_expr, function_lit, special, ternary)).labelled("expression")
    })
}

/// `[ … ]`: a vector (with comprehension elements) or a range. The first element is parsed once
/// and what follows it (`:` or `,`/`]`) decides which.
fn bracket_parser<'t, E: SyntaxError<'t>>(
    ctx: Ctx<'t>,
    expr: impl Parser<'t, In<'t>, Expr, extra::Err<E>> + Clone + 't,
) -> impl Parser<'t, In<'t>, Expr, extra::Err<E>> + Clone {
    let elem = list_elem_parser(ctx, expr.clone());
    enum Tail {
        Range(Expr, Option<Expr>),
        List(Vec<ListElem>),
    }
    let range_tail = just(Tok::Colon)
        .ignore_then(expr.clone())
        .then(just(Tok::Colon).ignore_then(expr).or_not())
        .map(|(a, b)| Tail::Range(a, b));
    let list_tail = just(Tok::Comma)
        .ignore_then(elem.clone())
        .repeated()
        .collect::<Vec<_>>()
        .then_ignore(just(Tok::Comma).or_not())
        .map(Tail::List);
    elem.then(range_tail.or(list_tail))
        .or_not()
        // A `]` missing is reported and assumed, as a `)` is (see `expr_parser`).
        .delimited_by(just(Tok::LBracket), closer(Tok::RBracket, "`]`"))
        .validate(|body, e, emitter| {
            let kind = match body {
                None => ExprKind::Vector(Vec::new()),
                Some((first, Tail::List(rest))) => {
                    let mut elems = Vec::with_capacity(rest.len() + 1);
                    elems.push(first);
                    elems.extend(rest);
                    ExprKind::Vector(elems)
                }
                Some((first, Tail::Range(second, third))) => match first.kind {
                    ListElemKind::Expr(start) => {
                        let (step, end) = match third {
                            Some(end) => (Some(Box::new(second)), end),
                            None => (None, second),
                        };
                        ExprKind::Range {
                            start: Box::new(start),
                            step,
                            end: Box::new(end),
                        }
                    }
                    _ => {
                        emitter.emit(E::custom(
                            SimpleSpan::from(first.span.range()),
                            "a range starts with a plain expression, not a comprehension",
                        ));
                        ExprKind::Error
                    }
                },
            };
            Expr {
                kind,
                span: sp(e.span()),
            }
        })
        .boxed()
}

/// A closing delimiter that is reported and assumed where the group it closes is never closed:
/// where no unmatched closer follows before the end of the statement (a `;`, a brace or the end
/// of the file, balanced groups skipped). Where one does follow, the closer fails as before, and
/// the group's own recovery skips it whole (`(1 + ) * 2`).
fn closer<'t, E: SyntaxError<'t>>(
    token: Tok,
    label: &'static str,
) -> impl Parser<'t, In<'t>, (), extra::Err<E>> + Clone {
    let mut plain = DELIMITERS.to_vec();
    plain.push(Tok::Semi);
    let never_closed = balanced()
        .or(none_of(plain).ignored())
        .repeated()
        .then(
            one_of([Tok::Semi, Tok::LBrace, Tok::RBrace])
                .ignored()
                .or(end()),
        )
        .rewind()
        .ignored();
    just(token)
        .labelled(label)
        .ignored()
        .recover_with(via_parser(never_closed))
}

/// An element of a vector: an expression or a comprehension (`for`, `if`, `let`, `each`).
fn list_elem_parser<'t, E: SyntaxError<'t>>(
    ctx: Ctx<'t>,
    expr: impl Parser<'t, In<'t>, Expr, extra::Err<E>> + Clone + 't,
) -> impl Parser<'t, In<'t>, ListElem, extra::Err<E>> + Clone {
    recursive(move |elem| {
        let elem = elem.boxed();
        let each = just(Tok::Each)
            .ignore_then(elem.clone())
            .map(|e| ListElemKind::Each(Box::new(e)));
        // `for (i = 0; i < n; i = i + 1)`: told apart from `for (i = r)` by the `;` after the
        // first bindings.
        let binding_list = binding(ctx, expr.clone())
            .separated_by(just(Tok::Comma))
            .allow_trailing()
            .collect::<Vec<_>>();
        let c_for_tail = just(Tok::Semi)
            .ignore_then(expr.clone())
            .then_ignore(just(Tok::Semi).labelled("`;`"))
            .then(binding_list.clone());
        let for_ = just(Tok::For)
            .ignore_then(
                binding_list
                    .then(c_for_tail.or_not())
                    .delimited_by(just(Tok::LParen), just(Tok::RParen).labelled("`)`")),
            )
            .then(elem.clone())
            .map(|((init, c_style), body)| match c_style {
                Some((cond, update)) => ListElemKind::CFor {
                    init,
                    cond,
                    update,
                    body: Box::new(body),
                },
                None => ListElemKind::For {
                    bindings: init,
                    body: Box::new(body),
                },
            });
        let if_ = just(Tok::If)
            .ignore_then(
                expr.clone()
                    .delimited_by(just(Tok::LParen), just(Tok::RParen).labelled("`)`")),
            )
            .then(elem.clone())
            .then(just(Tok::Else).ignore_then(elem.clone()).or_not())
            .map(|((cond, then), els)| ListElemKind::If {
                cond,
                then: Box::new(then),
                els: els.map(Box::new),
            });
        let let_ = just(Tok::Let)
            .ignore_then(bindings(ctx, expr.clone()))
            .then(elem.clone())
            .map(|(bindings, body)| ListElemKind::Let {
                bindings,
                body: Box::new(body),
            });
        let comprehension = choice((each, for_, if_, let_)).map_with(|kind, e| ListElem {
            kind,
            span: sp(e.span()),
        });
        // `( for … )`: parenthesised comprehension elements. A parenthesised plain expression is
        // left to the expression parser.
        let paren = comprehension
            .clone()
            .delimited_by(just(Tok::LParen), just(Tok::RParen))
            .map_with(|inner, e| ListElem {
                kind: ListElemKind::Paren(Box::new(inner)),
                span: sp(e.span()),
            });
        let plain = expr.map(|e| {
            let span = e.span;
            ListElem {
                kind: ListElemKind::Expr(e),
                span,
            }
        });
        choice((comprehension, paren, plain))
    })
}

/// The statement parser.
fn stmt_parser<'t, E: SyntaxError<'t>>(
    ctx: Ctx<'t>,
    expr: impl Parser<'t, In<'t>, Expr, extra::Err<E>> + Clone + 't,
) -> impl Parser<'t, In<'t>, Stmt, extra::Err<E>> + Clone {
    recursive(move |stmt| {
        let stmt = stmt.boxed();
        let semi = |what: &'static str| {
            just(Tok::Semi)
                .labelled(what)
                .ignored()
                // A `;` missing at the end of a line (or of the file) is reported and assumed;
                // anywhere else the statement is broken and skipped.
                .recover_with(via_parser(
                    end()
                        .or(any()
                            .try_map(move |_, span: SimpleSpan| {
                                if ctx.newline_before(span.start) {
                                    Ok(())
                                } else {
                                    Err(E::custom(span, "no line break"))
                                }
                            })
                            .ignored())
                        .rewind(),
                ))
        };
        let paren_expr = expr.clone().delimited_by(
            just(Tok::LParen).labelled("`(`"),
            just(Tok::RParen).labelled("`)`"),
        );
        let mk = |kind: StmtKind, span: SimpleSpan| Stmt {
            kind,
            span: sp(span),
            doc: None,
        };

        let empty_stmt = just(Tok::Semi).map_with(move |_, e| mk(StmtKind::Empty, e.span()));
        // Once its `{` is read, a block never fails: a stray `)` or `]` inside is reported and
        // skipped, and a `}` missing at the end of the file is reported and assumed. Recovery
        // from a failed block would re-parse everything inside it from the enclosing statement,
        // which doubles the work at every level of nesting.
        let block = stmt
            .clone()
            .or(stray_closer::<E>([Tok::RParen, Tok::RBracket]))
            .repeated()
            .collect::<Vec<_>>()
            .delimited_by(
                just(Tok::LBrace),
                just(Tok::RBrace)
                    .labelled("`}`")
                    .ignored()
                    .recover_with(via_parser(end().rewind())),
            )
            .map_with(move |stmts, e| mk(StmtKind::Block(stmts), e.span()));
        let module_def = just(Tok::Module)
            .ignore_then(name(ctx))
            .then(params(ctx, expr.clone()))
            .then(stmt.clone())
            .map_with(move |((name, params), body), e| Stmt {
                kind: StmtKind::ModuleDef {
                    name,
                    params,
                    body: Box::new(body),
                },
                span: sp(e.span()),
                doc: ctx.doc(e.span().start),
            });
        let function_def = just(Tok::Function)
            .ignore_then(name(ctx))
            .then(params(ctx, expr.clone()))
            .then_ignore(just(Tok::Assign).labelled("`=`"))
            .then(expr.clone())
            .then_ignore(semi("`;` after function definition"))
            .map_with(move |((name, params), body), e| Stmt {
                kind: StmtKind::FunctionDef { name, params, body },
                span: sp(e.span()),
                doc: ctx.doc(e.span().start),
            });
        let if_ = just(Tok::If)
            .ignore_then(paren_expr.clone())
            .then(stmt.clone())
            .then(just(Tok::Else).ignore_then(stmt.clone()).or_not())
            .map_with(move |((cond, then), els), e| {
                mk(
                    StmtKind::If {
                        cond,
                        then: Box::new(then),
                        els: els.map(Box::new),
                    },
                    e.span(),
                )
            });
        let for_ = just(Tok::For)
            .ignore_then(bindings(ctx, expr.clone()))
            .then(stmt.clone())
            .map_with(move |(bindings, body), e| {
                mk(
                    StmtKind::For {
                        bindings,
                        body: Box::new(body),
                    },
                    e.span(),
                )
            });
        let let_ = just(Tok::Let)
            .ignore_then(bindings(ctx, expr.clone()))
            .then(stmt.clone())
            .map_with(move |(bindings, body), e| {
                mk(
                    StmtKind::Let {
                        bindings,
                        body: Box::new(body),
                    },
                    e.span(),
                )
            });
        let path = just(Tok::Path).labelled("`<path>`").map_with(move |_, e| {
            let span: SimpleSpan = e.span();
            let raw = &ctx.text[span.start..span.end];
            let inner = raw.strip_prefix('<').unwrap_or(raw);
            let inner = inner.strip_suffix('>').unwrap_or(inner);
            PathLit {
                path: inner.to_owned(),
                span: sp(span),
            }
        });
        let include = just(Tok::Include)
            .ignore_then(path)
            .map_with(move |p, e| mk(StmtKind::Include(p), e.span()));
        let use_ = just(Tok::Use)
            .ignore_then(path)
            .map_with(move |p, e| mk(StmtKind::Use(p), e.span()));

        // A statement that starts with a name: an assignment or a module instantiation.
        enum Tail {
            Assign(Expr),
            Instantiate(Vec<Arg>, Span, Option<Stmt>),
        }
        // `cube(1) }` or `cube(1)` at the end of the file: the `;` is missing, not the child (a
        // child may well start on the next line, so a line break proves nothing here).
        let child = just(Tok::Semi)
            .labelled("`;`")
            .to(None)
            .or(stmt.clone().map(Some))
            .recover_with(via_parser(
                just(Tok::RBrace).ignored().or(end()).rewind().to(None),
            ));
        let named = name(ctx)
            .then(choice((
                just(Tok::Assign)
                    .ignore_then(expr.clone())
                    .then_ignore(semi("`;` after assignment"))
                    .map(Tail::Assign),
                args(ctx, expr.clone())
                    .then(child)
                    .map(|((args, args_span), child)| Tail::Instantiate(args, args_span, child)),
            )))
            .map_with(move |(name, tail), e| {
                let span = sp(e.span());
                match tail {
                    Tail::Assign(value) => Stmt {
                        kind: StmtKind::Assign { name, value },
                        span,
                        doc: ctx.doc(span.start as usize),
                    },
                    Tail::Instantiate(args, args_span, child) => Stmt {
                        kind: StmtKind::Instantiate {
                            name,
                            args,
                            args_span,
                            child: child.map(Box::new),
                        },
                        span,
                        doc: None,
                    },
                }
            });

        let modifier = choice((
            just(Tok::Star).to(Modifier::Disable),
            just(Tok::Bang).to(Modifier::ShowOnly),
            just(Tok::Hash).to(Modifier::Highlight),
            just(Tok::Percent).to(Modifier::Background),
        ))
        .map_with(|m, e| (m, sp(e.span())))
        .then(stmt.clone())
        .map_with(move |((modifier, modifier_span), body), e| {
            mk(
                StmtKind::Modified {
                    modifier,
                    modifier_span,
                    body: Box::new(body),
                },
                e.span(),
            )
        });

        let too_deep = just(Tok::TooDeep).map_with(move |_, e| mk(StmtKind::Error, e.span()));

        // Skips a broken statement: up to and including the next `;`, or up to a `}`, skipping
        // balanced groups whole.
        // A `{ … }` group ends the skipped statement, as it would end a module definition.
        let brace_group = balanced_braces();
        // A statement never starts with `)` or `]` (those are reported as stray), but a broken
        // one may contain unbalanced ones: `for (i = [0:3) a();` is one error, not three.
        let skip = balanced_groups()
            .or(none_of([
                Tok::Semi,
                Tok::LBrace,
                Tok::RBrace,
                Tok::RParen,
                Tok::RBracket,
            ])
            .ignored())
            .then(
                balanced_groups()
                    .or(none_of([Tok::Semi, Tok::LBrace, Tok::RBrace]).ignored())
                    .repeated(),
            )
            .then(just(Tok::Semi).ignored().or(brace_group.clone()).or_not())
            .ignored()
            .or(just(Tok::Semi).ignored())
            .or(brace_group)
            .map_with(move |_, e| mk(StmtKind::Error, e.span()));

        choice((
            named,
            block,
            module_def,
            function_def,
            if_,
            for_,
            let_,
            modifier,
            include,
            use_,
            empty_stmt,
            too_deep,
        ))
        .labelled("statement")
        .recover_with(via_parser(skip))
        .boxed()
    })
}
