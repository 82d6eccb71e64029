//! `echo` and `assert`, as statements and in expressions: echo lines within the echo-output limit,
//! and failed assertions quoted as OpenSCAD quotes them.

use qcsg_diag::{Diagnostic, FileId, Span};
use qcsg_syntax::ast::Arg;

use crate::text::BoundedText;
use crate::{codes, printer};

use super::{ArgValue, Evaluator, R};

/// What an `echo` line costs beside its text, in bytes of the echo-output limit: the diagnostic
/// that carries it and its printed form take about this much more, so that ten million empty
/// lines count as the burden they are.
pub(crate) const ECHO_LINE_COST: u64 = 64;

impl<'a> Evaluator<'a> {
    /// Reports an `echo` line, within what is left of the echo-output limit: the line that
    /// crosses it is cut, with a warning, and later lines are left out.
    pub(super) fn echo(&mut self, values: &[ArgValue<'a>], file: FileId, span: Span) {
        let Some(left) = self.echo_left else {
            return;
        };
        let mut text = BoundedText::new(left.saturating_sub(ECHO_LINE_COST));
        let written = text.push_echo_line(values.iter().map(|a| (a.name, &a.value)));
        self.echo_left = Some(left.saturating_sub(text.len() as u64 + ECHO_LINE_COST));
        let mut line = text.into_string();
        if written.is_err() {
            line.push('…');
            self.echo_left = None;
        }
        self.diagnostics.push(Diagnostic::new(
            qcsg_diag::Severity::Info,
            codes::ECHO,
            line,
            file,
            span,
        ));
        if written.is_err() {
            self.diagnostics.push(
                Diagnostic::warning(
                    codes::ECHO_LIMIT,
                    format!(
                        "echo output passed the limit of {} bytes: this line is cut and later echo output is left out",
                        self.options.max_echo_len
                    ),
                    file,
                    span,
                )
                .with_help(
                    "if you need all of it, raise the limit with `--max-echo-len N` on the command line",
                ),
            );
        }
    }

    pub(super) fn assert(
        &mut self,
        values: &[ArgValue<'a>],
        args: &'a [Arg],
        file: FileId,
        span: Span,
    ) -> R<()> {
        let pick = |name: &str, position: usize| {
            values
                .iter()
                .zip(args)
                .find(|(a, _)| a.name == Some(name))
                .or_else(|| {
                    values
                        .iter()
                        .zip(args)
                        .filter(|(a, _)| a.name.is_none())
                        .nth(position)
                })
        };
        let Some((cond, cond_arg)) = pick("condition", 0) else {
            return Err(self.error(
                codes::ASSERTION_FAILED,
                "assert() needs a condition",
                file,
                span,
            ));
        };
        if cond.value.truthy() {
            return Ok(());
        }
        let mut condition_text = String::new();
        printer::write_expr(&mut condition_text, &cond_arg.value);
        let mut message = format!("assertion `{condition_text}` failed");
        if let Some((m, _)) = pick("message", 1) {
            message.push_str(": ");
            // The message is quoted as echo prints it, as long as a string may be at most.
            let mut text = BoundedText::new(self.options.max_string_len);
            let cut = text.push_echo(&m.value).is_err();
            message.push_str(text.as_str());
            if cut {
                message.push('…');
            }
        }
        Err(self.error(codes::ASSERTION_FAILED, message, file, span))
    }
}
