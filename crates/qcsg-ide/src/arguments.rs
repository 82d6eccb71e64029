//! Argument-name completion: inside a call's argument list, the callee's parameters that the call
//! does not give yet (`r = `, `outer = `), each with its default and documentation, and the `$`
//! special variables a call may set for its callee.
//!
//! What is called comes from the tree where the tree holds the call (its name's resolved
//! reference); in unfinished text, which the parser could not make a call of, the name is looked
//! up among the definitions visible at the cursor and the built-ins, in the namespace the tokens
//! before it suggest (see [`CallSite::statement`]) and then in the other.

use qcsg_sema::builtins::{self, BuiltinParam};
use qcsg_sema::{DefId, DefKind, Namespace, Target};

use crate::Analysis;
use crate::call_site::CallSite;
use crate::completion::{CompletionItem, CompletionKind};
use crate::walk::call_at;

/// What a call calls.
#[derive(Clone, Copy, Debug)]
enum Callee {
    /// A built-in module (`is_module`) or function of this name.
    Builtin { name: &'static str, is_module: bool },
    /// A module, function or function-valued variable of the source.
    Definition(DefId),
}

/// Special variables that a call does not set: the module instance keeps them itself.
const MAINTAINED: &[&str] = &["$children", "$parent_modules"];

/// Longer default values are cut to this many characters in an item's detail.
const DEFAULT_SHOWN: usize = 40;

impl Analysis {
    /// The argument names the call at `site` still accepts (the cursor at `offset`, `visible`
    /// the definitions visible there): its own parameters first in their order, then the `$`
    /// special variables; none for built-in functions, which OpenSCAD binds by position only (the
    /// checker rejects their names, and they read no special variable).
    pub(crate) fn argument_completions(
        &self,
        site: &CallSite,
        offset: usize,
        visible: &[DefId],
    ) -> Vec<CompletionItem> {
        let Some(callee) = self.callee(site, offset, visible) else {
            return Vec::new();
        };
        let mut items = match callee {
            Callee::Builtin {
                is_module: false, ..
            } => return Vec::new(),
            Callee::Builtin { name, .. } => self.builtin_arguments(name, site),
            Callee::Definition(id) => self.definition_arguments(id, site),
        };
        self.special_arguments(site, visible, &mut items);
        items
    }

    /// What the call at `site` calls.
    fn callee(&self, site: &CallSite, offset: usize, visible: &[DefId]) -> Option<Callee> {
        if let Some(call) = call_at(self.tree(), offset)
            && call.args_span.start as usize == site.open
        {
            let Some(reference) = self.sema.reference_at(self.sema.main, site.name_start) else {
                return self.callee_named(&site.name, call.is_module, visible);
            };
            return match reference.target {
                Target::Definition(id) => Some(Callee::Definition(id)),
                Target::Builtin => builtin_callee(
                    &site.name,
                    reference.namespace == Namespace::Module || call.is_module,
                ),
                Target::CommandLine => None,
            };
        }
        self.callee_named(&site.name, site.statement, visible)
            .or_else(|| self.callee_named(&site.name, !site.statement, visible))
    }

    /// The module (`is_module`) or function called `name` that a call at `offset` reaches: a
    /// local definition before a top-level one, the main file's before another file's, the later
    /// of two (as the evaluator keeps the last), then a built-in.
    fn callee_named(&self, name: &str, is_module: bool, visible: &[DefId]) -> Option<Callee> {
        let main = self.sema.main;
        visible
            .iter()
            .copied()
            .filter(|&id| {
                self.sema.definition(id).is_some_and(|d| {
                    d.name == name
                        && match d.kind {
                            DefKind::Module => is_module,
                            DefKind::Function => !is_module,
                            _ => !is_module && d.params.is_some(),
                        }
                })
            })
            .max_by_key(|&id| {
                let d = self.sema.definition(id);
                (
                    d.is_some_and(|d| d.parent.is_some()),
                    d.is_some_and(|d| d.file == main),
                    id.0,
                )
            })
            .map(Callee::Definition)
            .or_else(|| builtin_callee(name, is_module))
    }

    /// The parameters of a built-in module that `site` does not give yet.
    fn builtin_arguments(&self, name: &str, site: &CallSite) -> Vec<CompletionItem> {
        let Some(module) = builtins::module(name) else {
            return Vec::new();
        };
        let declaration = Analysis::builtin_signature(name, true).map(|s| s.declaration());
        let positional: Vec<bool> = module.params.iter().map(|p| p.positional).collect();
        let given = given(&positional, site);
        module
            .params
            .iter()
            .zip(given)
            .filter(|(param, given)| !given && !site.named.iter().any(|n| n == param.name))
            .map(|(param, _)| {
                let default = leading_form_default(module.doc, name, param.name);
                let detail = builtin_detail(param, default.as_deref());
                let mut doc = String::new();
                if let Some(declaration) = &declaration {
                    doc.push_str(&format!("```qcsg\n{declaration}\n```\n"));
                }
                doc.push_str(&format!(
                    "parameter `{}` of the built-in `{name}` · {detail}\n\n---\n\n{}",
                    param.name, module.doc
                ));
                argument_item(param.name, Some(detail), Some(doc))
            })
            .collect()
    }

    /// The parameters of a user definition that `site` does not give yet.
    fn definition_arguments(&self, id: DefId, site: &CallSite) -> Vec<CompletionItem> {
        let Some(definition) = self.sema.definition(id) else {
            return Vec::new();
        };
        let Some(params) = &definition.params else {
            return Vec::new();
        };
        let text = &self.sema.sources.get(definition.file).text;
        let declaration = self.definition_signature(id).map(|s| s.declaration());
        let given = given(&vec![true; params.len()], site);
        params
            .iter()
            .zip(given)
            .filter(|(param, given)| !given && !site.named.contains(&param.name))
            .map(|(param, _)| {
                let written = text.get(param.span.range()).unwrap_or(&param.name);
                let default = param
                    .has_default
                    .then(|| written.split_once('=').map(|(_, value)| value.trim()))
                    .flatten();
                let ty = self
                    .sema
                    .definition(param.def)
                    .map(|d| &d.ty)
                    .filter(|ty| ty.is_known());
                let mut parts: Vec<String> = ty.map(ToString::to_string).into_iter().collect();
                parts.push(match default {
                    Some(value) => format!("default {}", shorten(value)),
                    None if param.tested_for_undef => "optional".to_owned(),
                    None => "required".to_owned(),
                });
                let detail = parts.join(" · ");
                let mut doc = String::new();
                if let Some(declaration) = &declaration {
                    doc.push_str(&format!("```qcsg\n{declaration}\n```\n"));
                }
                doc.push_str(&format!(
                    "parameter `{}` of `{}` · {detail}",
                    param.name, definition.name
                ));
                let own_doc = self
                    .sema
                    .definition(param.def)
                    .and_then(|d| d.doc.as_deref());
                let callee_doc = definition.doc.as_deref();
                let lines = callee_doc
                    .map(|d| lines_about(d, &param.name))
                    .unwrap_or_default();
                if let Some(text) = own_doc {
                    doc.push_str(&format!("\n\n---\n\n{text}"));
                } else if !lines.is_empty() {
                    doc.push_str(&format!("\n\n---\n\n{}", lines.join("\n")));
                } else if let Some(text) = callee_doc {
                    doc.push_str(&format!("\n\n---\n\n{text}"));
                }
                argument_item(&param.name, Some(detail), Some(doc))
            })
            .collect()
    }

    /// The `$` special variables a call may set that `site` does not set yet: those the program
    /// assigns at its top level, then the built-in ones, the three that change nothing on exact
    /// surfaces (`$fn`, `$fa`, `$fs`) last.
    fn special_arguments(
        &self,
        site: &CallSite,
        visible: &[DefId],
        items: &mut Vec<CompletionItem>,
    ) {
        let free = |name: &str| !site.named.iter().any(|n| n == name);
        let mut user: Vec<&str> = Vec::new();
        for &id in visible {
            let Some(definition) = self.sema.definition(id) else {
                continue;
            };
            if definition.kind == DefKind::Variable
                && definition.parent.is_none()
                && definition.name.starts_with('$')
                && !builtins::is_special_variable(&definition.name)
                && free(&definition.name)
                && !user.contains(&definition.name.as_str())
            {
                user.push(&definition.name);
                let mut doc = format!(
                    "```qcsg\n{}\n```\nspecial variable, set for this call",
                    definition.name
                );
                if let Some(text) = &definition.doc {
                    doc.push_str(&format!("\n\n---\n\n{text}"));
                }
                items.push(argument_item(
                    &definition.name,
                    Some(format!("special variable · {}", definition.ty)),
                    Some(doc),
                ));
            }
        }
        let (tessellation, others): (Vec<_>, Vec<_>) = builtins::SPECIAL_VARIABLES
            .iter()
            .filter(|(name, _)| !MAINTAINED.contains(name) && free(name))
            .partition(|(name, _)| builtins::is_tessellation_variable(name));
        for (name, doc) in others.into_iter().chain(tessellation) {
            items.push(argument_item(
                name,
                Some("special variable".to_owned()),
                Some(format!(
                    "```qcsg\n{name}\n```\nspecial variable, set for this call\n\n---\n\n{doc}"
                )),
            ));
        }
    }
}

/// A built-in module or function called `name`.
fn builtin_callee(name: &str, is_module: bool) -> Option<Callee> {
    let name = if is_module {
        builtins::module(name)?.name
    } else {
        builtins::function(name)?.name
    };
    Some(Callee::Builtin { name, is_module })
}

/// Which parameters the call's positional arguments fill: the first of those that may be given
/// by position (`positional`), as many as it has.
fn given(positional: &[bool], site: &CallSite) -> Vec<bool> {
    let mut left = site.positional;
    positional
        .iter()
        .map(|&by_position| {
            let filled = by_position && left > 0;
            left -= usize::from(filled);
            filled
        })
        .collect()
}

/// The item that inserts `name = `.
fn argument_item(name: &str, detail: Option<String>, doc: Option<String>) -> CompletionItem {
    CompletionItem {
        label: format!("{name} ="),
        kind: CompletionKind::Parameter,
        detail,
        doc,
        insert_text: Some(format!("{name} = ")),
        sort_text: None,
        replace: None,
    }
}

/// What a built-in parameter accepts, and its default or that it is required.
fn builtin_detail(param: &BuiltinParam, default: Option<&str>) -> String {
    let mut detail = param.ty.expected().to_owned();
    match default {
        Some(value) => detail.push_str(&format!(" · default {value}")),
        None if param.required => detail.push_str(" · required"),
        None => {}
    }
    detail
}

/// The default of `param` that a built-in's documentation shows in its leading call form, as in
/// `cube(size = 1, center = false): …` (the signature tables hold no defaults; the evaluator
/// applies them). Only literal values count: `ellipsoid(r = [a, b, c])` names no default.
fn leading_form_default(doc: &str, name: &str, param: &str) -> Option<String> {
    let form = doc.strip_prefix(name)?.strip_prefix('(')?;
    let mut depth = 0usize;
    let mut argument_start = 0;
    for (i, c) in form.char_indices() {
        match c {
            '[' | '(' => depth += 1,
            ']' if depth > 0 => depth -= 1,
            ',' | ')' if depth == 0 => {
                let argument = form[argument_start..i].trim();
                if let Some((written, value)) = argument.split_once('=')
                    && written.trim() == param
                    && is_literal(value.trim())
                {
                    return Some(value.trim().to_owned());
                }
                if c == ')' {
                    return None;
                }
                argument_start = i + 1;
            }
            ')' => depth -= 1,
            _ => {}
        }
    }
    None
}

/// Whether `value` is a number, a boolean, `undef` or a vector of numbers.
fn is_literal(value: &str) -> bool {
    matches!(value, "true" | "false" | "undef")
        || !value.is_empty()
            && value.chars().any(|c| c.is_ascii_digit())
            && value
                .chars()
                .all(|c| c.is_ascii_digit() || "+-.[], eE".contains(c))
}

/// The lines of a doc comment about the parameter `name`: those naming it in backquotes, or
/// starting with it and a colon or dash (`outer: the outer radius`, `- inner — …`).
fn lines_about<'a>(doc: &'a str, name: &str) -> Vec<&'a str> {
    let quoted = format!("`{name}`");
    doc.lines()
        .filter(|line| {
            let bare = line
                .trim_start()
                .trim_start_matches(['-', '*', ' '])
                .trim_start_matches("@param ");
            line.contains(&quoted)
                || bare
                    .strip_prefix(name)
                    .is_some_and(|rest| rest.trim_start().starts_with([':', '-', '—']))
        })
        .collect()
}

/// `text` cut to [`DEFAULT_SHOWN`] characters.
fn shorten(text: &str) -> String {
    match text.char_indices().nth(DEFAULT_SHOWN) {
        Some((cut, _)) => format!("{}…", &text[..cut]),
        None => text.to_owned(),
    }
}
