//! Signatures and argument checking: built-in and user callees are described alike, and a
//! call's arguments are matched to their parameters (by position, or by name where the callee
//! allows it) and checked for count, duplicates, unknown names and known types.

use qcsg_diag::{Diagnostic, FileId, Span};
use qcsg_syntax::ast::{Arg, ExprKind, Ident};

use crate::builtins::{BuiltinFunction, BuiltinModule, BuiltinParam};
use crate::ty::{Mismatch, ParamTy, Ty, format_lengths};
use crate::{DefId, Namespace, Target, codes};

use super::Resolver;
use super::names::VarLookup;

/// A parameter as argument checking sees it, for built-in and user callees alike.
struct SigParam {
    name: String,
    positional: bool,
    required: bool,
    ty: ParamTy,
    def: Option<DefId>,
}

/// A callee's signature.
pub(super) struct Signature {
    /// "module `cube`", "function `f`".
    title: String,
    params: Vec<SigParam>,
    /// Type of further positional arguments, for variadic built-ins.
    rest: Option<ParamTy>,
    /// Whether any named argument is accepted (`echo`).
    any_named: bool,
    min_args: usize,
    defined_at: Option<(FileId, Span)>,
    /// Built-in functions match arguments by position only: OpenSCAD ignores their names.
    positional_only: bool,
}

impl<'a> Resolver<'a> {
    pub(super) fn args(&mut self, file: FileId, args: &[Arg]) -> Vec<Ty> {
        args.iter()
            .map(|arg| {
                if let Some(name) = &arg.name {
                    self.tessellation_hint(file, name);
                }
                self.expr(file, &arg.value)
            })
            .collect()
    }

    pub(super) fn user_signature(&self, def: DefId, what: &str) -> Option<Signature> {
        let definition = self.definition(def)?;
        let params = definition.params.as_ref()?;
        Some(Signature {
            title: format!("{what} `{}`", definition.name),
            params: params
                .iter()
                .map(|p| SigParam {
                    name: p.name.clone(),
                    positional: true,
                    required: !p.has_default && !p.tested_for_undef && !p.name.starts_with('$'),
                    ty: ParamTy::Any,
                    def: Some(p.def),
                })
                .collect(),
            rest: None,
            any_named: false,
            min_args: 0,
            defined_at: Some((definition.file, definition.name_span)),
            positional_only: false,
        })
    }

    /// Checks a call's arguments against a signature. `$`-arguments are always accepted: they set
    /// special variables for the callee.
    pub(super) fn check_args(
        &mut self,
        file: FileId,
        callee: &Ident,
        args_span: Span,
        args: &[Arg],
        tys: &[Ty],
        signature: &Signature,
    ) {
        let positional: Vec<usize> = (0..signature.params.len())
            .filter(|&i| signature.params[i].positional)
            .collect();
        let mut supplied: Vec<Option<Span>> = vec![None; signature.params.len()];
        let mut positional_count = 0usize;
        let mut extra: Option<Span> = None;
        for (arg, ty) in args.iter().zip(tys) {
            let name = match &arg.name {
                Some(name) if signature.positional_only && !name.is_special() => {
                    self.diagnostics.push(
                        Diagnostic::error(
                            codes::UNKNOWN_ARGUMENT,
                            format!(
                                "{} takes positional arguments only: the name `{}` would be ignored",
                                signature.title, name.name
                            ),
                            file,
                            name.span,
                        )
                        .with_help("OpenSCAD matches a built-in function's arguments by position whatever their names; remove the name"),
                    );
                    None
                }
                other => other.as_ref(),
            };
            match name {
                None => {
                    if let Some(&index) = positional.get(positional_count) {
                        supplied[index] = Some(arg.span);
                        self.check_arg_type(
                            file,
                            signature,
                            &signature.params[index].name,
                            signature.params[index].ty,
                            arg,
                            ty,
                        );
                    } else if let Some(rest) = signature.rest {
                        self.check_arg_type(file, signature, "", rest, arg, ty);
                    } else {
                        extra = Some(extra.map_or(arg.span, |s| s.cover(arg.span)));
                    }
                    positional_count += 1;
                }
                Some(name) if name.is_special() || signature.any_named => {}
                Some(name) => match signature.params.iter().position(|p| p.name == name.name) {
                    Some(index) => {
                        if let Some(param_def) = signature.params[index].def {
                            self.reference(
                                file,
                                name.span,
                                Namespace::Variable,
                                Target::Definition(param_def),
                            );
                        }
                        if let Some(previous) = supplied[index] {
                            self.diagnostics.push(
                                Diagnostic::error(
                                    codes::DUPLICATE_ARGUMENT,
                                    format!(
                                        "argument `{}` of {} is given more than once",
                                        name.name, signature.title
                                    ),
                                    file,
                                    name.span,
                                )
                                .with_label(
                                    file,
                                    previous,
                                    "first given here",
                                ),
                            );
                        } else {
                            supplied[index] = Some(name.span);
                            self.check_arg_type(
                                file,
                                signature,
                                &name.name,
                                signature.params[index].ty,
                                arg,
                                ty,
                            );
                        }
                    }
                    None => {
                        let mut diagnostic = Diagnostic::error(
                            codes::UNKNOWN_ARGUMENT,
                            format!("{} has no parameter `{}`", signature.title, name.name),
                            file,
                            name.span,
                        );
                        let names: Vec<&str> =
                            signature.params.iter().map(|p| p.name.as_str()).collect();
                        diagnostic = match self.suggester.closest(&name.name, names.iter().copied())
                        {
                            Some(similar) => {
                                diagnostic.with_help(format!("did you mean `{similar}`?"))
                            }
                            None if names.is_empty() => diagnostic
                                .with_help(format!("{} takes no arguments", signature.title)),
                            None => diagnostic
                                .with_help(format!("its parameters are {}", quoted_list(&names))),
                        };
                        if let Some((def_file, def_span)) = signature.defined_at {
                            diagnostic = diagnostic.with_label(def_file, def_span, "defined here");
                        }
                        self.diagnostics.push(diagnostic);
                    }
                },
            }
        }
        if let Some(extra_span) = extra {
            let count = positional.len();
            let mut diagnostic = Diagnostic::error(
                codes::TOO_MANY_ARGUMENTS,
                format!(
                    "{} takes {} positional argument{} but {} were given",
                    signature.title,
                    count,
                    if count == 1 { "" } else { "s" },
                    positional_count
                ),
                file,
                extra_span,
            )
            .with_help("remove the extra arguments (OpenSCAD would ignore them)");
            if let Some((def_file, def_span)) = signature.defined_at {
                diagnostic = diagnostic.with_label(def_file, def_span, "defined here");
            }
            self.diagnostics.push(diagnostic);
        }
        let missing: Vec<&str> = signature
            .params
            .iter()
            .zip(&supplied)
            .filter(|(p, s)| p.required && s.is_none())
            .map(|(p, _)| p.name.as_str())
            .collect();
        if !missing.is_empty() {
            let mut diagnostic = Diagnostic::error(
                codes::MISSING_ARGUMENT,
                format!(
                    "{} is missing argument{} {}",
                    signature.title,
                    if missing.len() == 1 { "" } else { "s" },
                    quoted_list(&missing)
                ),
                file,
                callee.span,
            )
            .with_label(file, args_span, "arguments given here")
            .with_help("give the parameter a default value in the definition (`name = undef`) if it is optional");
            if let Some((def_file, def_span)) = signature.defined_at {
                diagnostic = diagnostic.with_label(def_file, def_span, "defined here");
            }
            self.diagnostics.push(diagnostic);
        } else if signature.rest.is_some() && positional_count < signature.min_args {
            self.diagnostics.push(
                Diagnostic::error(
                    codes::MISSING_ARGUMENT,
                    format!(
                        "{} needs at least {} argument{}",
                        signature.title,
                        signature.min_args,
                        if signature.min_args == 1 { "" } else { "s" }
                    ),
                    file,
                    callee.span,
                )
                .with_label(file, args_span, "arguments given here"),
            );
        }
    }

    fn check_arg_type(
        &mut self,
        file: FileId,
        signature: &Signature,
        param: &str,
        expected: ParamTy,
        arg: &Arg,
        ty: &Ty,
    ) {
        let what = if param.is_empty() {
            "an argument".to_string()
        } else {
            format!("`{param}`")
        };
        let mismatch = match expected.check(ty) {
            Ok(()) => return,
            Err(mismatch) => mismatch,
        };
        // When the value comes from a variable, point at where its type comes from.
        let origin = match &arg.value.kind {
            ExprKind::Ident(ident) => match self.lookup_var(&ident.name) {
                VarLookup::Found(binding) => {
                    binding.def.and_then(|def| self.definition(def)).map(|d| {
                        (
                            d.file,
                            d.name_span,
                            format!("`{}` is assigned here", d.name),
                        )
                    })
                }
                _ => None,
            },
            _ => None,
        };
        let diagnostic = match mismatch {
            Mismatch::Type(expected) => {
                let mut diagnostic = Diagnostic::error(
                    codes::ARGUMENT_TYPE,
                    format!(
                        "{} expects {expected} for {what}, found {}",
                        signature.title,
                        ty.describe()
                    ),
                    file,
                    arg.value.span,
                );
                if expected.starts_with("a boolean") && *ty == Ty::Number {
                    diagnostic = diagnostic
                        .with_help("OpenSCAD ignores a number here; write `true` or `false`");
                }
                diagnostic
            }
            Mismatch::Length { given, allowed } => Diagnostic::error(
                codes::ARGUMENT_LENGTH,
                format!(
                    "{} expects {what} to have {} elements, found {given}",
                    signature.title,
                    format_lengths(allowed)
                ),
                file,
                arg.value.span,
            ),
        };
        let diagnostic = match origin {
            Some((def_file, def_span, message)) => {
                diagnostic.with_label(def_file, def_span, message)
            }
            None => diagnostic,
        };
        self.diagnostics.push(diagnostic);
    }
}

/// The parameters of a built-in module or function as a signature lists them.
fn builtin_params(params: &[BuiltinParam]) -> Vec<SigParam> {
    params
        .iter()
        .map(|p| SigParam {
            name: p.name.to_string(),
            positional: p.positional,
            required: p.required,
            ty: p.ty,
            def: None,
        })
        .collect()
}

pub(super) fn builtin_module_signature(module: &BuiltinModule) -> Signature {
    Signature {
        title: format!("`{}`", module.name),
        params: builtin_params(module.params),
        rest: module.variadic.then_some(ParamTy::Any),
        any_named: module.variadic,
        min_args: 0,
        defined_at: None,
        positional_only: false,
    }
}

pub(super) fn builtin_function_signature(function: &BuiltinFunction) -> Signature {
    Signature {
        title: format!("`{}`", function.name),
        params: builtin_params(function.params),
        rest: function.rest,
        any_named: false,
        min_args: function.min_args,
        defined_at: None,
        // OpenSCAD reads `dxf_dim` and `dxf_cross` by argument name, every other built-in
        // function by position.
        positional_only: !matches!(function.name, "dxf_dim" | "dxf_cross"),
    }
}

fn quoted_list(names: &[&str]) -> String {
    names
        .iter()
        .map(|n| format!("`{n}`"))
        .collect::<Vec<_>>()
        .join(", ")
}
