//! `qcsg fmt FILE... [--check]`: format files in place, or report which would change.
//!
//! `-` formats standard input to standard output. A file with syntax errors, or that is not valid
//! UTF-8, is left untouched and reported; the run then exits 1, as does `--check` when any file
//! would change. Files are read as every source is ([`crate::program::read`]).

use std::io::Write;

use clap::Args;

use crate::{EXIT_INPUT_ERRORS, EXIT_OK, EXIT_USAGE};

/// Arguments of `qcsg fmt`.
#[derive(Debug, Args)]
pub struct FmtArgs {
    /// Files to format in place (`.qcsg` or `.scad`); `-` formats standard input to standard
    /// output.
    #[arg(value_name = "FILE", required = true)]
    files: Vec<String>,

    /// Change nothing; exit 1 if any file is not formatted.
    #[arg(long)]
    check: bool,
}

/// Runs `qcsg fmt` and returns the process exit status.
pub fn run(args: FmtArgs) -> u8 {
    let mut status = EXIT_OK;
    for file in &args.files {
        let (_, source) = match crate::program::read(file) {
            Ok(input) => input,
            Err(message) => {
                eprintln!("error: {message}");
                return EXIT_USAGE;
            }
        };
        // Formatting would write the replacement characters back in place of the bytes.
        if let Some(invalid) = &source.invalid_utf8 {
            let line = qcsg_diag::LineIndex::new(&source.text).line_of(invalid.span.start as usize);
            eprintln!(
                "error: {file}:{}: not valid UTF-8; the file is left as it is",
                line + 1
            );
            status = status.max(EXIT_INPUT_ERRORS);
            continue;
        }
        let text = source.text;
        let formatted = match qcsg_ide::format::format_file(file, &text) {
            Ok(formatted) => formatted,
            Err(error) => {
                eprintln!("error: {file}: {error}");
                status = status.max(EXIT_INPUT_ERRORS);
                continue;
            }
        };
        if args.check {
            if formatted != text {
                eprintln!("{file}: would be reformatted");
                status = status.max(EXIT_INPUT_ERRORS);
            }
        } else if file == "-" {
            if std::io::stdout().write_all(formatted.as_bytes()).is_err() {
                return EXIT_USAGE;
            }
        } else if formatted != text
            && let Err(error) = std::fs::write(file, formatted)
        {
            eprintln!("error: cannot write {file}: {error}");
            return EXIT_USAGE;
        }
    }
    status
}
