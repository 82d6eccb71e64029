//! Signatures of callables (user definitions and built-ins) and signature help inside a call.

use qcsg_sema::builtins::{self, BuiltinParam};
use qcsg_sema::{DefId, DefKind, Namespace, Reference, Target};

use crate::walk::call_at;
use crate::{Analysis, LineCol};

/// The signature of the call around the cursor.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SignatureHelp {
    /// The whole signature, such as `cylinder(h, r1, r2, center, r, d, d1, d2)`.
    pub label: String,
    /// Its documentation, when there is any.
    pub doc: Option<String>,
    /// The parameters, as byte ranges of `label`.
    pub params: Vec<SignatureParam>,
    /// The parameter the cursor's argument sets, if any.
    pub active_param: Option<usize>,
}

/// One parameter of a [`SignatureHelp`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SignatureParam {
    /// The parameter's name.
    pub name: String,
    /// Where its text lies in the signature label (byte offsets).
    pub label_range: (u32, u32),
    /// What it accepts, for built-ins.
    pub doc: Option<String>,
}

/// A callable's name, parameters and documentation.
#[derive(Clone, Debug)]
pub(crate) struct Signature {
    pub name: String,
    /// Parameter texts as written (`r = 1`) or as built-ins describe them.
    pub params: Vec<(String, Option<String>)>,
    /// Which parameters may be given by position.
    pub positional: Vec<bool>,
    pub doc: Option<String>,
    pub is_module: bool,
}

impl Signature {
    /// `name(a, b = 1)`, and the byte range of each parameter in it.
    pub(crate) fn label(&self) -> (String, Vec<(u32, u32)>) {
        let mut label = format!("{}(", self.name);
        let mut ranges = Vec::new();
        for (i, (param, _)) in self.params.iter().enumerate() {
            if i > 0 {
                label.push_str(", ");
            }
            let start = label.len() as u32;
            label.push_str(param);
            ranges.push((start, label.len() as u32));
        }
        label.push(')');
        (label, ranges)
    }

    /// The name of each parameter (the text before any `=`).
    pub(crate) fn param_names(&self) -> impl Iterator<Item = &str> {
        self.params
            .iter()
            .map(|(text, _)| text.split('=').next().unwrap_or(text).trim())
    }

    /// The definition line shown on hover: `module name(…)` or `function name(…)`.
    pub(crate) fn declaration(&self) -> String {
        let keyword = if self.is_module { "module" } else { "function" };
        format!("{keyword} {}", self.label().0)
    }
}

fn builtin_params(params: &[BuiltinParam]) -> (Vec<(String, Option<String>)>, Vec<bool>) {
    params
        .iter()
        .map(|p| {
            (
                (p.name.to_owned(), Some(p.ty.expected().to_owned())),
                p.positional,
            )
        })
        .unzip()
}

impl Analysis {
    /// The signature of a built-in module (`is_module`) or function called `name`.
    pub(crate) fn builtin_signature(name: &str, is_module: bool) -> Option<Signature> {
        if is_module {
            let module = builtins::module(name)?;
            let (params, positional) = builtin_params(module.params);
            Some(Signature {
                name: name.to_owned(),
                params,
                positional,
                doc: Some(module.doc.to_owned()),
                is_module,
            })
        } else {
            let function = builtins::function(name)?;
            let (params, positional) = builtin_params(function.params);
            Some(Signature {
                name: name.to_owned(),
                params,
                positional,
                doc: Some(function.doc.to_owned()),
                is_module,
            })
        }
    }

    /// The signature of a module, function or function-valued variable defined in the source.
    pub(crate) fn definition_signature(&self, id: DefId) -> Option<Signature> {
        let definition = self.sema.definition(id)?;
        let params = definition.params.as_ref()?;
        let text = &self.sema.sources.get(definition.file).text;
        Some(Signature {
            name: definition.name.clone(),
            params: params
                .iter()
                .map(|p| (text.get(p.span.range()).unwrap_or(&p.name).to_owned(), None))
                .collect(),
            positional: vec![true; params.len()],
            doc: definition.doc.clone(),
            is_module: definition.kind == DefKind::Module,
        })
    }

    /// The signature a call's name resolves to.
    pub(crate) fn call_signature(&self, name_start: usize, is_module: bool) -> Option<Signature> {
        let reference = self.sema.reference_at(self.sema.main, name_start)?;
        self.reference_signature(reference, is_module)
    }

    /// The signature of what `reference` (in the main document) resolves to.
    pub(crate) fn reference_signature(
        &self,
        reference: &Reference,
        is_module: bool,
    ) -> Option<Signature> {
        let name = self.text().get(reference.span.range())?;
        match reference.target {
            Target::Definition(id) => self.definition_signature(id),
            Target::Builtin => {
                Self::builtin_signature(name, reference.namespace == Namespace::Module || is_module)
            }
            Target::CommandLine => None,
        }
    }

    /// Signature help for the innermost call around `position`.
    pub fn signature_help(&self, position: LineCol) -> Option<SignatureHelp> {
        let offset = self.offset(position);
        let call = call_at(self.tree(), offset)?;
        let signature = self.call_signature(call.name.span.start as usize, call.is_module)?;
        let (label, ranges) = signature.label();
        // The argument under the cursor is the one after as many top-level commas.
        let before_cursor = self
            .text()
            .get(call.args_span.start as usize..offset)
            .unwrap_or("");
        let index = count_top_level_commas(before_cursor);
        let active_param = match call.args.get(index).and_then(|arg| arg.name.as_ref()) {
            Some(name) => signature.param_names().position(|p| p == name.name),
            None => (0..signature.params.len())
                .filter(|&i| signature.positional[i])
                .nth(index),
        };
        Some(SignatureHelp {
            label,
            doc: signature.doc.clone(),
            params: signature
                .params
                .iter()
                .zip(ranges)
                .zip(signature.param_names())
                .map(|(((_, doc), range), name)| SignatureParam {
                    name: name.to_owned(),
                    label_range: range,
                    doc: doc.clone(),
                })
                .collect(),
            active_param,
        })
    }
}

/// Commas of `text` (which starts at a call's `(`) outside nested brackets and strings.
fn count_top_level_commas(text: &str) -> usize {
    let mut depth = 0i32;
    let mut in_string = false;
    let mut escaped = false;
    let mut commas = 0;
    for c in text.chars() {
        if in_string {
            match c {
                _ if escaped => escaped = false,
                '\\' => escaped = true,
                '"' => in_string = false,
                _ => {}
            }
            continue;
        }
        match c {
            '"' => in_string = true,
            '(' | '[' | '{' => depth += 1,
            ')' | ']' | '}' => depth -= 1,
            ',' if depth == 1 => commas += 1,
            _ => {}
        }
    }
    commas
}
