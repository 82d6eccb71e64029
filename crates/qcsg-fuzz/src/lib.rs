//! A stable fuzzing harness for qcsg: random programs through every stage, in process, with
//! budgets on time and memory, and minimised reproducers for what fails.
//!
//! `cargo fuzz` needs a nightly compiler; this harness runs on stable. Inputs are generated
//! programs ([`generate`], grammar-aware) and byte-level mutations of the corpus of
//! `examples/` and `tests/` ([`mutate`], [`corpus`]), each built from the run's seed and its
//! index alone ([`input`]). A supervisor ([`supervisor`]) spreads them over worker processes
//! ([`process`], [`worker`]), one per core; a worker runs each input through the pipeline
//! ([`stages`]): parse, format, check, evaluate, DNF, the `compile --emit` printers, sample,
//! ray trace, a language server edit session ([`lsp_session`]) and `qcsg check` through the
//! binary ([`cli_stage`]). Panics are recorded ([`panics`]); a stage over its time budget (the
//! wall time of its work on an idle machine, with a cap on wall time: [`cpu_clock`]) is a hang
//! and its worker is killed; the heap's peak per stage is measured by a counting allocator
//! and the worker's address space is limited, so a runaway allocation fails inside the worker.
//! Each distinct failure is minimised ([`minimise`]) and written with a report ([`report`]).
//!
//! The protocol between the supervisor and the workers is in [`protocol`]; docs/fuzzing.md
//! says how to run the harness and why it is built this way.

pub mod cli_stage;
pub mod corpus;
pub mod cpu_clock;
pub mod dice;
pub mod generate;
pub mod input;
pub mod libs;
pub mod lsp_session;
pub mod minimise;
pub mod mutate;
pub mod panics;
pub mod process;
pub mod protocol;
pub mod report;
pub mod stages;
pub mod supervisor;
pub mod worker;
