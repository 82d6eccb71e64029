//! The pipeline, assembled in one place: source text (or a file, with include paths, `-D`
//! overrides and limits) to static analysis, the scene DAG, its DNF layers, and the diagnostics
//! of every stage.
//!
//! Every consumer calls this crate instead of chaining `check_file`, `evaluate` and
//! `build_dnf` itself: the CLI's commands, the language server, the benchmarks and the tests.
//! A new flag, limit or import path is threaded through [`Options`] once.
//!
//! - [`options`]: what a run is asked to do: the search path (`QCSG_PATH`), the `-D`
//!   overrides and every limit.
//! - [`pipeline`]: the stages, each appending its diagnostics to the analysis, and
//!   [`Compilation`], what a run produced.
//!
//! The DNF stage builds [`Layers`]: the solid, the `#` highlighted parts and the `%`
//! background parts, all that a preview draws.
//!
//! This crate knows nothing of terminals, editors or images: diagnostics stay plain data.

pub mod options;
pub mod pipeline;

pub use options::{Options, search_path_from_env};
pub use pipeline::{Built, Compilation, Stage, build, compile, compile_source};
pub use qcsg_csg::Layers;
