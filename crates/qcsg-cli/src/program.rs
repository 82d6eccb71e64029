//! What the commands share: reading a program, checking and evaluating it, and printing its
//! diagnostics.

use std::io::{IsTerminal, Write};
use std::path::Path;

use qcsg_csg::Dag;
use qcsg_diag::{Diagnostic, SourceMap};
use qcsg_eval::{EvalOptions, evaluate};
use qcsg_sema::{Analysis, CheckOptions, FsLoader, MAX_SOURCE_BYTES, SourceText};

use crate::human::{HumanRenderer, report};

/// The name and text of FILE (`-`: standard input, named `<stdin>`), read as every source file is
/// ([`qcsg_sema::read_source`]): a regular file of at most [`MAX_SOURCE_BYTES`]. Text that is not
/// valid UTF-8 is read, and the check reports it.
pub fn read(file: &str) -> Result<(String, SourceText), String> {
    if file == "-" {
        let source = qcsg_sema::read_source_from(std::io::stdin().lock(), MAX_SOURCE_BYTES)
            .map_err(|err| format!("cannot read standard input: {err}"))?;
        return Ok((crate::check::STDIN_NAME.to_owned(), source));
    }
    qcsg_sema::read_source(Path::new(file))
        .map(|source| (file.to_owned(), source))
        .map_err(|err| format!("cannot read `{file}`: {err}"))
}

/// Statically checks a program, with `-D` overrides and `QCSG_PATH`.
pub fn check(name: &str, source: SourceText, defines: &[(String, String)]) -> Analysis {
    let options = CheckOptions {
        search_path: crate::search_path_from_env(),
        defines: defines.to_vec(),
    };
    qcsg_sema::check_source(name, source, &options, &FsLoader)
}

/// Evaluates a program whose static check found no errors, appending the evaluation's
/// diagnostics (echo output, warnings, runtime errors) to the analysis. The DAG comes back only
/// when neither step found an error.
pub fn evaluate_checked(analysis: &mut Analysis, options: &EvalOptions) -> Option<Dag> {
    if analysis.has_errors() {
        return None;
    }
    let evaluation = evaluate(analysis, options);
    let failed = evaluation.has_errors();
    analysis.diagnostics.extend(evaluation.diagnostics);
    (!failed).then_some(evaluation.dag)
}

/// Prints the diagnostics on standard error with source excerpts (colour on a terminal unless
/// `NO_COLOR` is set), then a summary line when anything was shown; `quiet` shows errors only.
/// A flood is cut short ([`crate::human::report`]).
pub fn print_human(analysis: &Analysis, quiet: bool) {
    let stderr = std::io::stderr();
    let colour = stderr.is_terminal() && std::env::var_os("NO_COLOR").is_none_or(|v| v.is_empty());
    let renderer = HumanRenderer::for_terminal(colour);
    let diagnostics: Vec<(&SourceMap, &Diagnostic)> = analysis
        .diagnostics
        .iter()
        .filter(|d| !quiet || d.is_error())
        .map(|d| (&analysis.sources, d))
        .collect();
    let out = report(&renderer, &diagnostics, !quiet && !diagnostics.is_empty());
    let _ = stderr.lock().write_all(out.as_bytes());
}

/// Prints the diagnostics (errors only when `quiet`): as JSON on standard output when that is
/// free (standard error when it carries the command's output), or for people on standard error.
pub fn print_diagnostics(
    analysis: &Analysis,
    quiet: bool,
    format: crate::DiagnosticFormat,
    stdout_free: bool,
) {
    if format == crate::DiagnosticFormat::Human {
        print_human(analysis, quiet);
        return;
    }
    let elements: Vec<_> = analysis
        .diagnostics
        .iter()
        .filter(|d| !quiet || d.is_error())
        .map(|d| crate::json::JsonDiagnostic::new(&analysis.sources, d))
        .collect();
    let text = crate::json::array_text(&elements);
    if stdout_free {
        print!("{text}");
    } else {
        eprint!("{text}");
    }
}

/// The worker threads of `--threads` (default: one per core, each kept to its core:
/// [`qcsg_sample::threads`]).
pub fn thread_pool(threads: Option<std::num::NonZeroUsize>) -> Result<rayon::ThreadPool, String> {
    qcsg_sample::threads::pool_builder(threads.map_or(0, |n| n.get()))
        .build()
        .map_err(|error| format!("cannot start worker threads: {error}"))
}
