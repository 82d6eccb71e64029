//! The worker process: runs inputs through the stages, in process, one at a time, and reports
//! on standard output ([`crate::protocol`]).
//!
//! A worker is the harness binary started with `--worker` by the supervisor
//! ([`crate::supervisor`]). It first limits its own address space (`RLIMIT_AS`), so that a
//! runaway allocation fails inside it (Rust then aborts with "memory allocation of N bytes
//! failed", which the supervisor reads) instead of taking the machine's memory; the `qcsg`
//! binary it starts inherits the limit. It silences and records panics ([`crate::panics`]),
//! then serves requests until its input ends. A hang or a crash ends the worker; the supervisor
//! notices, kills it if need be and starts another.

use std::io;
use std::path::PathBuf;
use std::time::Duration;

use crate::protocol::{read_request, write_event};
use crate::stages::{self, Context};
use crate::{lsp_session, panics};

/// How a worker runs.
#[derive(Clone, Debug)]
pub struct WorkerOptions {
    /// The `qcsg` binary for the CLI stage, if any.
    pub qcsg: Option<PathBuf>,
    /// The most heap one stage may hold, in bytes.
    pub memory_budget: u64,
    /// The limit on the worker's address space, in bytes.
    pub address_space: Option<u64>,
    /// How long one stage may take.
    pub stage_timeout: Duration,
}

/// Serves requests from standard input until it ends.
///
/// # Errors
/// If the address-space limit cannot be set, a thread pool or runtime cannot be started, or
/// the supervisor's stream is broken.
pub fn run(options: &WorkerOptions) -> io::Result<()> {
    if let Some(limit) = options.address_space {
        rlimit::setrlimit(rlimit::Resource::AS, limit, limit)?;
    }
    panics::install();
    let context = Context {
        pool: rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .thread_name(|i| format!("sample-{i}"))
            .build()
            .map_err(io::Error::other)?,
        lsp: lsp_session::Runtime::new()?,
        qcsg: options.qcsg.clone(),
        memory_budget: options.memory_budget,
        stage_timeout: options.stage_timeout,
    };
    let mut input = io::stdin().lock();
    let stdout = io::stdout();
    while let Some((request, bytes)) = read_request(&mut input)? {
        stages::run(&context, &request, &bytes, &mut |event| {
            // A supervisor that went away ends the worker at its next read.
            let _ = write_event(&mut stdout.lock(), &event);
        });
    }
    Ok(())
}
