//! `qcsg lsp`: the language server on standard input and output (see `docs/lsp.md`).

use crate::{EXIT_OK, EXIT_USAGE};

/// Runs the language server until the client exits; returns the process exit status.
pub fn run() -> u8 {
    match qcsg_lsp::run_stdio() {
        Ok(()) => EXIT_OK,
        Err(error) => {
            eprintln!("error: cannot start the language server: {error}");
            EXIT_USAGE
        }
    }
}
