//! Completion: names in scope, built-ins with their signatures, argument names inside a call
//! (ranked first there; the `arguments` module), and paths inside `include <…>` / `use <…>`.

use std::path::Path;

use qcsg_sema::builtins;
use qcsg_sema::{DefId, DefKind, LinkKind};
use qcsg_syntax::ast::{ExprKind, ListElemKind, StmtKind};

use crate::call_site::{Bracket, surroundings};
use crate::hover::builtin_markdown;
use crate::walk::{Node, walk};
use crate::{Analysis, LineCol, Span, TextRange};

/// What a completion inserts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CompletionKind {
    /// A module.
    Module,
    /// A function.
    Function,
    /// A variable.
    Variable,
    /// A named argument (`name = `).
    Parameter,
    /// A keyword.
    Keyword,
    /// A file for `include` / `use`.
    File,
    /// A directory on the way to one.
    Folder,
}

/// One completion.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CompletionItem {
    /// What the list shows (and inserts, unless `insert_text` says otherwise).
    pub label: String,
    /// What it is.
    pub kind: CompletionKind,
    /// A signature or type.
    pub detail: Option<String>,
    /// Markdown documentation.
    pub doc: Option<String>,
    /// The text to insert when it differs from the label.
    pub insert_text: Option<String>,
    /// The key that orders the list, best first; the label when absent.
    pub sort_text: Option<String>,
    /// What the completion replaces: the part of the name typed before the cursor. (Left to
    /// the editor, a `$` typed before `$fn` could stay, since not every editor counts it as part
    /// of a word.)
    pub replace: Option<TextRange>,
}

const KEYWORDS: &[&str] = &[
    "module", "function", "if", "else", "for", "let", "each", "true", "false", "undef", "include",
    "use",
];

impl Analysis {
    /// Completions at `position` of the main document. Inside an argument list the argument
    /// names the call still accepts come first, in the list and by their sort keys, before the
    /// expressions an argument may be.
    pub fn completions(&self, position: LineCol) -> Vec<CompletionItem> {
        let offset = self.offset(position);
        let text = self.text();
        let line_start = text[..offset].rfind('\n').map_or(0, |i| i + 1);
        if let Some(partial) = include_path_prefix(&text[line_start..offset]) {
            return self.path_completions(partial);
        }
        // The name being typed: ASCII only, so the byte after the character found is a
        // boundary whatever that character's width.
        let prefix_start = text[..offset]
            .rfind(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == '$'))
            .map_or(0, |i| {
                i + text[i..].chars().next().map_or(1, char::len_utf8)
            });
        let prefix = &text[prefix_start..offset];
        let around = surroundings(text, self.tree(), self.main(), offset);
        let visible = self.visible_definitions(offset);
        let mut items = Vec::new();
        if let Some(site) = around.call.as_ref().filter(|site| site.at_name) {
            items.extend(self.argument_completions(site, offset, &visible));
        }
        let arguments = items.len();
        self.scope_completions(&visible, &mut items);
        builtin_completions(&mut items);
        items.extend(KEYWORDS.iter().map(|k| CompletionItem {
            label: (*k).to_owned(),
            kind: CompletionKind::Keyword,
            detail: None,
            doc: None,
            insert_text: None,
            sort_text: None,
            replace: None,
        }));
        if let Some(bracket) = around.bracket {
            // Inside brackets only expressions are written: no module instantiation, no
            // statement keyword.
            let mut index = 0;
            items.retain(|item| {
                index += 1;
                index <= arguments || fits_expression(item, bracket)
            });
        }
        let lower = prefix.to_lowercase();
        let replace = self.range(self.sema.main, Span::new(prefix_start, offset));
        let mut seen = std::collections::HashSet::new();
        let mut rank = 0;
        let mut ranked = Vec::with_capacity(items.len());
        for (index, mut item) in items.into_iter().enumerate() {
            if !item.label.to_lowercase().starts_with(&lower)
                || !seen.insert((item.label.clone(), item.kind))
            {
                continue;
            }
            item.sort_text = Some(if index < arguments {
                rank += 1;
                format!("0{rank:04}")
            } else {
                // Without `format!`: this runs for every one of thousands of items per request.
                let mut key = String::with_capacity(item.label.len() + 1);
                key.push('1');
                key.push_str(&item.label);
                key
            });
            item.replace = Some(replace);
            ranked.push(item);
        }
        // Argument names lead the list already; the rest is left for the editor to order by the
        // keys (sorting thousands of names here would cost more than the rest of the request).
        ranked
    }

    /// User definitions visible at `offset`: top-level ones of every file (only modules and
    /// functions of `use`d files), and the parameters, variables, loop and `let` variables of the
    /// scopes around it.
    pub(crate) fn visible_definitions(&self, offset: usize) -> Vec<DefId> {
        let main = self.sema.main;
        let inside = |span: Span| span.start as usize <= offset && offset <= span.end as usize;
        let mut local_names: Vec<Span> = Vec::new();
        walk(self.tree(), &mut |node| match node {
            Node::Stmt(stmt) => {
                if let StmtKind::For { bindings, .. } | StmtKind::Let { bindings, .. } = &stmt.kind
                    && inside(stmt.span)
                {
                    local_names.extend(bindings.iter().map(|b| b.name.span));
                }
                // `assign(a = 1) child` and `intersection_for(i = r) child` bind their named
                // arguments for the child only.
                if let StmtKind::Instantiate {
                    name,
                    args,
                    child: Some(child),
                    ..
                } = &stmt.kind
                    && matches!(name.name.as_str(), "assign" | "intersection_for")
                    && inside(child.span)
                {
                    local_names.extend(args.iter().filter_map(|a| a.name.as_ref().map(|n| n.span)));
                }
            }
            Node::Expr(expr) => match &expr.kind {
                ExprKind::Let { bindings, .. } if inside(expr.span) => {
                    local_names.extend(bindings.iter().map(|b| b.name.span));
                }
                ExprKind::Vector(elems) => {
                    for elem in elems.iter().filter(|e| inside(e.span)) {
                        if let ListElemKind::For { bindings, .. }
                        | ListElemKind::Let { bindings, .. } = &elem.kind
                        {
                            local_names.extend(bindings.iter().map(|b| b.name.span));
                        }
                    }
                }
                _ => {}
            },
            Node::Elem(_) => {}
        });
        // `use`d files lend their modules and functions only.
        let used: Vec<_> = self
            .sema
            .links
            .iter()
            .filter(|l| l.kind == LinkKind::Use)
            .filter_map(|l| l.target)
            .collect();
        let mut visible = Vec::new();
        for (i, definition) in self.sema.definitions.iter().enumerate() {
            let enclosing = definition
                .parent
                .and_then(|p| self.sema.definition(p))
                .is_some_and(|p| p.file == main && inside(p.span));
            let shown = match definition.kind {
                DefKind::Module | DefKind::Function => definition.parent.is_none() || enclosing,
                DefKind::Variable => {
                    (definition.parent.is_none() && !used.contains(&definition.file)) || enclosing
                }
                DefKind::Parameter => enclosing,
                DefKind::LoopVariable | DefKind::LetVariable => {
                    definition.file == main && local_names.contains(&definition.name_span)
                }
            };
            if shown {
                visible.push(DefId(i as u32));
            }
        }
        visible
    }

    /// The `visible` user definitions as completions.
    fn scope_completions(&self, visible: &[DefId], items: &mut Vec<CompletionItem>) {
        for &id in visible {
            let Some(definition) = self.sema.definition(id) else {
                continue;
            };
            let kind = match definition.kind {
                DefKind::Module => CompletionKind::Module,
                DefKind::Function => CompletionKind::Function,
                _ => CompletionKind::Variable,
            };
            let detail = match kind {
                CompletionKind::Variable => Some(definition.ty.to_string()),
                _ => self.definition_signature(id).map(|s| s.label().0),
            };
            items.push(CompletionItem {
                label: definition.name.clone(),
                kind,
                detail,
                doc: definition.doc.clone(),
                insert_text: None,
                sort_text: None,
                replace: None,
            });
        }
    }

    /// Files and directories matching the partial path of an `include <…>` / `use <…>`.
    fn path_completions(&self, partial: &str) -> Vec<CompletionItem> {
        let main_name = &self.sema.sources.get(self.sema.main).name;
        let base = Path::new(main_name).parent().unwrap_or(Path::new(""));
        let (dir, _) = partial.rsplit_once('/').unwrap_or(("", partial));
        let directory = if base.as_os_str().is_empty() {
            Path::new(".").join(dir)
        } else {
            base.join(dir)
        };
        let Ok(entries) = std::fs::read_dir(&directory) else {
            return Vec::new();
        };
        let mut items: Vec<CompletionItem> = entries
            .filter_map(Result::ok)
            .filter_map(|entry| {
                let name = entry.file_name().into_string().ok()?;
                let is_dir = entry.file_type().ok()?.is_dir();
                let wanted = is_dir && !name.starts_with('.')
                    || name.ends_with(".scad")
                    || name.ends_with(".qcsg");
                // A file does not include itself.
                let own = dir.is_empty()
                    && Path::new(main_name)
                        .file_name()
                        .is_some_and(|f| f == name.as_str());
                let wanted = wanted && !own;
                wanted.then(|| CompletionItem {
                    label: if is_dir { format!("{name}/") } else { name },
                    kind: if is_dir {
                        CompletionKind::Folder
                    } else {
                        CompletionKind::File
                    },
                    detail: None,
                    doc: None,
                    insert_text: None,
                    sort_text: None,
                    replace: None,
                })
            })
            .collect();
        items.sort_by(|a, b| a.label.cmp(&b.label));
        items
    }
}

/// Whether `item` may be written inside `bracket`: not a module (but for `assert` and `echo`,
/// which have expression forms too), and of the keywords only those that start expressions, with
/// list comprehensions' inside `[ ]`.
fn fits_expression(item: &CompletionItem, bracket: Bracket) -> bool {
    match item.kind {
        CompletionKind::Module => matches!(item.label.as_str(), "assert" | "echo"),
        CompletionKind::Keyword => match item.label.as_str() {
            "true" | "false" | "undef" | "let" | "function" => true,
            "for" | "if" | "else" | "each" => bracket == Bracket::Square,
            _ => false,
        },
        _ => true,
    }
}

/// The partial path when `line` (up to the cursor) ends inside `include <…` or `use <…`.
fn include_path_prefix(line: &str) -> Option<&str> {
    let open = line.rfind('<')?;
    let before = line[..open].trim_end();
    let partial = &line[open + 1..];
    ((before.ends_with("include") || before.ends_with("use")) && !partial.contains('>'))
        .then_some(partial)
}

fn builtin_completions(items: &mut Vec<CompletionItem>) {
    for module in builtins::MODULES {
        let signature = Analysis::builtin_signature(module.name, true).map(|s| s.label().0);
        items.push(CompletionItem {
            label: module.name.to_owned(),
            kind: CompletionKind::Module,
            detail: signature,
            doc: builtin_markdown(module.name, qcsg_sema::Namespace::Module),
            insert_text: None,
            sort_text: None,
            replace: None,
        });
    }
    for function in builtins::FUNCTIONS {
        let signature = Analysis::builtin_signature(function.name, false).map(|s| s.label().0);
        items.push(CompletionItem {
            label: function.name.to_owned(),
            kind: CompletionKind::Function,
            detail: signature,
            doc: builtin_markdown(function.name, qcsg_sema::Namespace::Function),
            insert_text: None,
            sort_text: None,
            replace: None,
        });
    }
    for (name, doc) in builtins::SPECIAL_VARIABLES {
        items.push(CompletionItem {
            label: (*name).to_owned(),
            kind: CompletionKind::Variable,
            detail: Some("special variable".to_owned()),
            doc: Some((*doc).to_owned()),
            insert_text: None,
            sort_text: None,
            replace: None,
        });
    }
    for (name, doc, ty) in builtins::VARIABLES {
        items.push(CompletionItem {
            label: (*name).to_owned(),
            kind: CompletionKind::Variable,
            detail: Some(ty.to_string()),
            doc: Some((*doc).to_owned()),
            insert_text: None,
            sort_text: None,
            replace: None,
        });
    }
}
