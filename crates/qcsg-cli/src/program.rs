//! What the commands share: reading a program, running the pipeline on it (`qcsg-driver`), and
//! printing its diagnostics.

use std::io::{IsTerminal, Write};
use std::path::Path;

use qcsg_diag::{Diagnostic, SourceMap};
use qcsg_driver::{Compilation, Stage};
use qcsg_sema::{Analysis, FsLoader, MAX_SOURCE_BYTES, SourceText};

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

/// Runs the pipeline on a program as far as `stage`, with `-D` overrides, `QCSG_PATH` and the
/// limits of the command line.
pub fn compile(
    name: &str,
    source: SourceText,
    options: &qcsg_driver::Options,
    stage: Stage,
) -> Compilation {
    qcsg_driver::compile_source(name, source, options, &FsLoader, stage)
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
