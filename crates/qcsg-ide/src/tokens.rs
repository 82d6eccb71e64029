//! Semantic tokens: the lexer's view (keywords, numbers, strings, comments) refined by name
//! resolution (functions, modules, variables, parameters, `$`-variables, built-ins).

use std::collections::HashMap;

use qcsg_sema::{DefKind, Definition, Namespace, Reference, Target};
use qcsg_syntax::ast::CommentKind;
use qcsg_syntax::lexer::{self, Tok};

use crate::{Analysis, Span};

/// The kind of a semantic token.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TokenKind {
    /// A keyword, `true`, `false` or `undef`.
    Keyword,
    /// A number literal.
    Number,
    /// A string literal or an `include`/`use` path.
    String,
    /// A comment.
    Comment,
    /// A function name.
    Function,
    /// A module name.
    Module,
    /// A variable name.
    Variable,
    /// A parameter name (in its definition, in the body and in named arguments).
    Parameter,
    /// A `$`-variable such as `$fn`.
    SpecialVariable,
}

impl TokenKind {
    /// Every kind, in the order of their indices in an LSP legend.
    pub const ALL: [TokenKind; 9] = [
        TokenKind::Keyword,
        TokenKind::Number,
        TokenKind::String,
        TokenKind::Comment,
        TokenKind::Function,
        TokenKind::Module,
        TokenKind::Variable,
        TokenKind::Parameter,
        TokenKind::SpecialVariable,
    ];
}

/// Modifiers of a semantic token, as a bit set.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct TokenModifiers(pub u32);

impl TokenModifiers {
    /// The name is being defined here.
    pub const DECLARATION: u32 = 1;
    /// A built-in.
    pub const DEFAULT_LIBRARY: u32 = 2;
    /// A doc comment.
    pub const DOCUMENTATION: u32 = 4;
    /// Modifier names in bit order, for an LSP legend.
    pub const NAMES: [&'static str; 3] = ["declaration", "defaultLibrary", "documentation"];
}

/// One token on one line, positions in UTF-16 code units.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SemanticToken {
    /// Zero-based line.
    pub line: u32,
    /// Start column.
    pub start: u32,
    /// Length in UTF-16 code units (never crossing a line end).
    pub length: u32,
    /// What it is.
    pub kind: TokenKind,
    /// Its modifiers.
    pub modifiers: TokenModifiers,
}

impl Analysis {
    /// Semantic tokens of the main document in source order, one line each.
    pub fn semantic_tokens(&self) -> Vec<SemanticToken> {
        let text = self.text();
        let lexed = lexer::lex(text, self.sema.main);
        let main = self.sema.main;
        // Lookups by start offset: the analysis' own are linear scans, fine for one query only.
        let names = Names {
            references: self
                .sema
                .references
                .iter()
                .filter(|r| r.file == main)
                .map(|r| (r.span.start, r))
                .collect(),
            definitions: self
                .sema
                .definitions
                .iter()
                .filter(|d| d.file == main)
                .map(|d| (d.name_span.start, d))
                .collect(),
        };
        let mut spans: Vec<(Span, TokenKind, u32)> = Vec::with_capacity(lexed.tokens.len());
        for &(tok, span) in &lexed.tokens {
            if let Some((kind, modifiers)) = self.classify(&names, tok, span) {
                spans.push((span, kind, modifiers));
            }
        }
        for comment in &lexed.comments {
            let doc = matches!(comment.kind, CommentKind::DocLine | CommentKind::DocBlock);
            let modifiers = if doc {
                TokenModifiers::DOCUMENTATION
            } else {
                0
            };
            spans.push((comment.span, TokenKind::Comment, modifiers));
        }
        spans.sort_by_key(|(span, _, _)| span.start);
        let mut out = Vec::with_capacity(spans.len());
        for (span, kind, modifiers) in spans {
            self.push_lines(span, kind, TokenModifiers(modifiers), &mut out);
        }
        out
    }

    fn classify(&self, names: &Names<'_>, tok: Tok, span: Span) -> Option<(TokenKind, u32)> {
        use TokenKind as K;
        Some(match tok {
            Tok::Number => (K::Number, 0),
            Tok::Str(_) | Tok::Path => (K::String, 0),
            Tok::Ident | Tok::SpecialIdent | Tok::Assert | Tok::Echo => {
                self.classify_name(names, tok, span)?
            }
            Tok::Module
            | Tok::Function
            | Tok::If
            | Tok::Else
            | Tok::For
            | Tok::Let
            | Tok::Each
            | Tok::True
            | Tok::False
            | Tok::Undef
            | Tok::Include
            | Tok::Use => (K::Keyword, 0),
            _ => return None,
        })
    }

    fn classify_name(&self, names: &Names<'_>, tok: Tok, span: Span) -> Option<(TokenKind, u32)> {
        use TokenKind as K;
        let special = tok == Tok::SpecialIdent;
        if let Some(reference) = names.references.get(&span.start) {
            let (kind, builtin) = match reference.target {
                Target::Definition(id) => {
                    let kind = self.sema.definition(id).map(|d| d.kind);
                    (def_token(kind, reference.namespace, special), false)
                }
                Target::Builtin => (def_token(None, reference.namespace, special), true),
                Target::CommandLine => (K::Variable, false),
            };
            let modifiers = if builtin {
                TokenModifiers::DEFAULT_LIBRARY
            } else {
                0
            };
            return Some((kind, modifiers));
        }
        if let Some(definition) = names.definitions.get(&span.start) {
            let kind = def_token(Some(definition.kind), Namespace::Variable, special);
            return Some((kind, TokenModifiers::DECLARATION));
        }
        match tok {
            Tok::Assert | Tok::Echo => Some((K::Keyword, 0)),
            Tok::SpecialIdent => Some((K::SpecialVariable, 0)),
            _ => None,
        }
    }

    /// Splits a span at line ends into tokens.
    fn push_lines(
        &self,
        span: Span,
        kind: TokenKind,
        modifiers: TokenModifiers,
        out: &mut Vec<SemanticToken>,
    ) {
        let text = self.text();
        let main = self.sema.main;
        let mut start = span.start as usize;
        let end = span.end as usize;
        while start < end {
            let line_end = text[start..end].find('\n').map_or(end, |i| start + i);
            let piece = text[start..line_end].trim_end_matches('\r');
            if !piece.is_empty() {
                let position = self.position(main, start);
                out.push(SemanticToken {
                    line: position.line,
                    start: position.character,
                    length: piece.encode_utf16().count() as u32,
                    kind,
                    modifiers,
                });
            }
            start = line_end + 1;
        }
    }
}

/// The main document's references and definitions by the start of their name.
struct Names<'a> {
    references: HashMap<u32, &'a Reference>,
    definitions: HashMap<u32, &'a Definition>,
}

fn def_token(kind: Option<DefKind>, namespace: Namespace, special: bool) -> TokenKind {
    use TokenKind as K;
    if special {
        return K::SpecialVariable;
    }
    match (kind, namespace) {
        (Some(DefKind::Module), _) | (None, Namespace::Module) => K::Module,
        (Some(DefKind::Function), _) | (None, Namespace::Function) => K::Function,
        (Some(DefKind::Parameter), _) => K::Parameter,
        _ => K::Variable,
    }
}
