//! `qcsg check FILE...`: run each file through the pipeline as far as its normal form and bounds
//! (everything short of sampling and rendering, so it reports every error `compile`, `render`
//! and `sample` would), print the diagnostics, pick the exit code. `--no-eval` stops after the
//! static checks, `--no-dnf` after evaluation.
//!
//! Files are checked independently (each is its own program) and possibly in parallel, but the
//! output is always in the order the files were given, so it never depends on `--threads`.

use std::io::{IsTerminal, Write};
use std::num::NonZeroUsize;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

use qcsg_diag::{Diagnostic, SourceMap};
use qcsg_driver::{Options, Stage};
use qcsg_sema::{Analysis, SourceText};

use crate::human::{HumanRenderer, report};
use crate::{CheckArgs, DiagnosticFormat, EXIT_INPUT_ERRORS, EXIT_OK, EXIT_USAGE};

/// The name standard input goes by in diagnostics.
pub const STDIN_NAME: &str = "<stdin>";

/// Runs `qcsg check` and returns the process exit status.
pub fn run(args: CheckArgs) -> u8 {
    let options = args.limits.options(&args.common.defines);
    let stage = if args.no_eval {
        Stage::Check
    } else if args.no_dnf {
        Stage::Evaluate
    } else {
        Stage::Dnf
    };
    // Each readable input's name and text; why each other one could not be read.
    let (inputs, unreadable): (Vec<_>, Vec<_>) = args
        .files
        .iter()
        .map(|file| crate::program::read(file))
        .partition(Result::is_ok);
    let inputs: Vec<(String, SourceText)> = inputs.into_iter().flatten().collect();
    let threads = args
        .common
        .threads
        .or_else(|| std::thread::available_parallelism().ok())
        .unwrap_or(NonZeroUsize::MIN);
    let analyses = check_all(inputs, &options, stage, threads);

    for message in unreadable.iter().filter_map(|r| r.as_ref().err()) {
        eprintln!("error: {message}");
    }

    let has_errors = analyses
        .iter()
        .flat_map(|a| &a.diagnostics)
        .any(Diagnostic::is_error);
    let shown = |d: &&Diagnostic| !args.common.quiet || d.is_error();
    match args.common.format {
        DiagnosticFormat::Json => {
            let elements: Vec<_> = analyses
                .iter()
                .flat_map(|a| a.diagnostics.iter().filter(shown).map(move |d| (a, d)))
                .map(|(a, d)| crate::json::JsonDiagnostic::new(&a.sources, d))
                .collect();
            let text = crate::json::array_text(&elements);
            if std::io::stdout().lock().write_all(text.as_bytes()).is_err() {
                return EXIT_USAGE;
            }
        }
        DiagnosticFormat::Human => {
            let stderr = std::io::stderr();
            let colour = wants_colour(stderr.is_terminal(), std::env::var_os("NO_COLOR"));
            let renderer = HumanRenderer::for_terminal(colour);
            let diagnostics: Vec<(&SourceMap, &Diagnostic)> = analyses
                .iter()
                .flat_map(|a| a.diagnostics.iter().filter(shown).map(|d| (&a.sources, d)))
                .collect();
            let out = report(&renderer, &diagnostics, !args.common.quiet);
            // A closed standard error is no reason to change the verdict on the input.
            let _ = stderr.lock().write_all(out.as_bytes());
        }
    }

    if !unreadable.is_empty() {
        EXIT_USAGE
    } else if has_errors {
        EXIT_INPUT_ERRORS
    } else {
        EXIT_OK
    }
}

/// Colour only on a terminal, and not when `NO_COLOR` is set to anything but the empty string
/// (<https://no-color.org>).
fn wants_colour(is_terminal: bool, no_color: Option<std::ffi::OsString>) -> bool {
    is_terminal && no_color.is_none_or(|value| value.is_empty())
}

/// Checks every readable input on up to `threads` threads; the result is in input order.
fn check_all(
    jobs: Vec<(String, SourceText)>,
    options: &Options,
    stage: Stage,
    threads: NonZeroUsize,
) -> Vec<Analysis> {
    let check = |(name, source): (String, SourceText)| {
        crate::program::compile(&name, source, options, stage).analysis
    };
    let workers = threads.get().min(jobs.len());
    if workers <= 1 {
        return jobs.into_iter().map(check).collect();
    }

    // Each worker takes the next job out of its slot.
    let jobs: Vec<Mutex<Option<(String, SourceText)>>> =
        jobs.into_iter().map(|job| Mutex::new(Some(job))).collect();
    let next = AtomicUsize::new(0);
    let results: Mutex<Vec<Option<Analysis>>> = Mutex::new(jobs.iter().map(|_| None).collect());
    std::thread::scope(|scope| {
        for _ in 0..workers {
            scope.spawn(|| {
                loop {
                    let i = next.fetch_add(1, Ordering::Relaxed);
                    let Some(slot) = jobs.get(i) else { break };
                    let job = slot.lock().unwrap_or_else(|e| e.into_inner()).take();
                    let Some(job) = job else { continue };
                    let analysis = check(job);
                    results.lock().unwrap_or_else(|e| e.into_inner())[i] = Some(analysis);
                }
            });
        }
    });
    results
        .into_inner()
        .unwrap_or_else(|e| e.into_inner())
        .into_iter()
        .map(|a| a.expect("every job ran to completion"))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every prefix of some broken and some valid programs: whatever the checker reports, both
    /// formats render it.
    #[test]
    fn every_truncation_renders_in_both_formats() {
        let programs = [
            include_str!("../tests/fixtures/syntax_errors.qcsg"),
            include_str!("../tests/fixtures/names.qcsg"),
            include_str!("../tests/fixtures/unicode.qcsg"),
            include_str!("../../../examples/machined_block.qcsg"),
        ];
        let renderer = HumanRenderer::plain();
        for program in programs {
            for end in (0..=program.len()).filter(|&end| program.is_char_boundary(end)) {
                let text = program[..end].to_owned();
                let analysis = qcsg_sema::check_file(
                    "t.qcsg",
                    text,
                    &qcsg_sema::CheckOptions::default(),
                    &qcsg_sema::FsLoader,
                );
                for diagnostic in &analysis.diagnostics {
                    let human = renderer.render(&analysis.sources, diagnostic);
                    assert!(human.contains(diagnostic.code), "{human}");
                    let json = crate::json::JsonDiagnostic::new(&analysis.sources, diagnostic);
                    assert!(serde_json::to_string(&json).is_ok());
                }
            }
        }
    }

    #[test]
    fn colour_needs_a_terminal_and_no_no_color() {
        assert!(wants_colour(true, None));
        assert!(wants_colour(true, Some("".into())));
        assert!(!wants_colour(true, Some("1".into())));
        assert!(!wants_colour(false, None));
    }
}
