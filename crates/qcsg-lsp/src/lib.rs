//! The qcsg language server: the only crate that knows LSP and JSON-RPC.
//!
//! Built on `tower-lsp-server` 0.23.0, the maintained continuation of `tower-lsp` (whose last
//! release, 0.20, is from 2023 and unmaintained), with `tokio` as its runtime. Both are pinned
//! exactly in the workspace because a language server's behaviour under concurrency depends on
//! them, and pre-releases of the next `tower-lsp-server` change its API.
//!
//! Every analysis comes from `qcsg-ide` as plain data, and the stages after the check (evaluation
//! and the DNF, through `qcsg-driver`) from [`geometry`]; this crate keeps the open documents
//! ([`documents`]), converts positions and results to LSP types ([`convert`]) and answers
//! requests ([`server`]). [`preview`] renders frames of the scene and says what a pixel shows,
//! for the editor's preview panel and `qcsg view`; [`custom`] answers the panel's requests.
//! The client's bytes reach the server only through [`transport`], which frames and checks them
//! and answers what is malformed. [`run_stdio`] is what `qcsg lsp`
//! runs.

pub mod convert;
pub mod custom;
pub mod documents;
pub mod geometry;
pub mod preview;
pub mod server;
pub mod transport;

use transport::{Ending, Options};

/// Serves LSP on standard input and output until the client exits or the input ends.
///
/// # Errors
/// If the tokio runtime cannot be created.
pub fn run_stdio(options: Options) -> std::io::Result<Ending> {
    let runtime = tokio::runtime::Builder::new_multi_thread()
        // Analyses walk trees recursively; deep (but accepted) nesting needs more than the 2 MiB
        // default of tokio's threads.
        .thread_stack_size(32 * 1024 * 1024)
        .enable_all()
        .build()?;
    let ending = runtime.block_on(transport::serve(
        tokio::io::stdin(),
        tokio::io::stdout(),
        options,
    ));
    // Standard input is read by a blocking thread that cannot be interrupted: after `exit`,
    // waiting for it would wait for the client to close its end.
    runtime.shutdown_background();
    Ok(ending)
}
