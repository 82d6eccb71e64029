//! The qcsg language server: the only crate that knows LSP and JSON-RPC.
//!
//! Built on `tower-lsp-server` 0.23.0, the maintained continuation of `tower-lsp` (whose last
//! release, 0.20, is from 2023 and unmaintained), with `tokio` as its runtime. Both are pinned
//! exactly in the workspace because a language server's behaviour under concurrency depends on
//! them, and pre-releases of the next `tower-lsp-server` change its API.
//!
//! Every analysis comes from `qcsg-ide` as plain data; this crate keeps the open documents
//! ([`documents`]), converts positions and results to LSP types ([`convert`]) and answers
//! requests ([`server`]). [`run_stdio`] is what `qcsg lsp` runs.

pub mod convert;
pub mod documents;
pub mod server;

use tower_lsp_server::{LspService, Server};

/// Serves LSP on standard input and output until the client exits.
///
/// # Errors
/// If the tokio runtime cannot be created.
pub fn run_stdio() -> std::io::Result<()> {
    let runtime = tokio::runtime::Builder::new_multi_thread()
        // Analyses walk trees recursively; deep (but accepted) nesting needs more than the 2 MiB
        // default of tokio's threads.
        .thread_stack_size(32 * 1024 * 1024)
        .enable_all()
        .build()?;
    runtime.block_on(async {
        let (service, socket) = LspService::new(server::Backend::new);
        Server::new(tokio::io::stdin(), tokio::io::stdout(), socket)
            .serve(service)
            .await;
    });
    Ok(())
}
