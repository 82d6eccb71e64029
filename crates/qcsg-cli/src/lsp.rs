//! `qcsg lsp`: the language server on standard input and output (see `docs/lsp.md`).

use clap::Args;

use crate::EXIT_USAGE;

/// Arguments of `qcsg lsp`.
#[derive(Debug, Args)]
pub struct LspArgs {
    /// The largest message accepted, in bytes; a longer one is answered with an error and
    /// skipped unread.
    #[arg(long, value_name = "BYTES", default_value_t = qcsg_lsp::transport::DEFAULT_MAX_MESSAGE_BYTES)]
    max_message_bytes: usize,
}

/// Runs the language server until the client exits; returns the process exit status: 0, or 1
/// for `exit` without `shutdown` (LSP).
pub fn run(args: LspArgs) -> u8 {
    let options = qcsg_lsp::transport::Options {
        max_message_bytes: args.max_message_bytes,
    };
    match qcsg_lsp::run_stdio(options) {
        Ok(ending) => ending.exit_code(),
        Err(error) => {
            eprintln!("error: cannot start the language server: {error}");
            EXIT_USAGE
        }
    }
}
