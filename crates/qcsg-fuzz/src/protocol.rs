//! What the supervisor and a worker process say to each other, and the vocabulary of results:
//! [`Stage`]s, [`FailureKind`]s and [`Failure`]s.
//!
//! A request is one JSON line ([`Request`]) followed by exactly `len` raw bytes of input (any
//! bytes, not necessarily UTF-8). The worker answers with JSON lines ([`Event`]): the start of
//! each stage before it runs (so a worker that dies or hangs is known to have died in that
//! stage), its end with time, memory and any failure, and [`Event::Done`] after the last stage.
//! Lines that are not events (a library printing to standard output) are ignored.

use std::fmt;
use std::io::{self, BufRead, Write};

use serde::{Deserialize, Serialize};

/// A stage of the pipeline, in the order a worker runs them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Stage {
    /// `qcsg_syntax::parse`, with its span invariants.
    Parse,
    /// The formatter of `qcsg fmt` and the language server, with its stated properties.
    Format,
    /// `qcsg_sema::check_file` through the file system loader, with its span invariants.
    Check,
    /// `qcsg_eval::evaluate` of a program without static errors.
    Eval,
    /// `qcsg_csg::build_dnf` of an evaluated solid.
    Dnf,
    /// The printers of `qcsg compile --emit ast|dag|dnf` (text and JSON).
    Emit,
    /// The sampler at a coarse radius with small limits.
    Sample,
    /// The CPU ray tracer, a small image, encoded as PNG.
    Render,
    /// A random edit session with the language server, in process.
    Lsp,
    /// `qcsg check` (the binary): human-readable diagnostics.
    Cli,
}

impl Stage {
    /// Every stage, in pipeline order.
    pub const ALL: [Stage; 10] = [
        Stage::Parse,
        Stage::Format,
        Stage::Check,
        Stage::Eval,
        Stage::Dnf,
        Stage::Emit,
        Stage::Sample,
        Stage::Render,
        Stage::Lsp,
        Stage::Cli,
    ];

    /// The stage's name, as on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Stage::Parse => "parse",
            Stage::Format => "format",
            Stage::Check => "check",
            Stage::Eval => "eval",
            Stage::Dnf => "dnf",
            Stage::Emit => "emit",
            Stage::Sample => "sample",
            Stage::Render => "render",
            Stage::Lsp => "lsp",
            Stage::Cli => "cli",
        }
    }

    /// The stage called `name`.
    pub fn from_name(name: &str) -> Option<Stage> {
        Stage::ALL.into_iter().find(|s| s.name() == name)
    }

    /// The stages that must run for this one to run: itself and what feeds it.
    pub fn with_prerequisites(self) -> Vec<Stage> {
        match self {
            Stage::Eval => vec![Stage::Check, Stage::Eval],
            Stage::Dnf => vec![Stage::Check, Stage::Eval, Stage::Dnf],
            Stage::Emit => vec![Stage::Check, Stage::Eval, Stage::Dnf, Stage::Emit],
            Stage::Sample => vec![Stage::Check, Stage::Eval, Stage::Dnf, Stage::Sample],
            Stage::Render => vec![Stage::Check, Stage::Eval, Stage::Render],
            other => vec![other],
        }
    }
}

impl fmt::Display for Stage {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// How a stage failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FailureKind {
    /// A panic (caught, or a panic exit of the `qcsg` binary).
    Panic,
    /// The stage ran past its time budget.
    Hang,
    /// The stage allocated past its memory budget, or an allocation failed.
    Memory,
    /// The stack overflowed.
    StackOverflow,
    /// The process died otherwise (a signal, an abort).
    Crash,
    /// A stated property did not hold (a span outside its file, formatting that is not
    /// idempotent, a semantic token past the end of its line, …).
    Invariant,
    /// The language server answered with an internal error, logged an error, or stopped
    /// answering.
    Server,
    /// The `qcsg` binary refused a readable program as unreadable input (exit status 2)
    /// instead of reporting diagnostics at spans.
    Refused,
}

impl FailureKind {
    /// The kind's name in reports.
    pub fn name(self) -> &'static str {
        match self {
            FailureKind::Panic => "panic",
            FailureKind::Hang => "hang",
            FailureKind::Memory => "memory",
            FailureKind::StackOverflow => "stack-overflow",
            FailureKind::Crash => "crash",
            FailureKind::Invariant => "invariant",
            FailureKind::Server => "server",
            FailureKind::Refused => "refused",
        }
    }
}

impl fmt::Display for FailureKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// One failure of one stage on one input.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Failure {
    /// The stage.
    pub stage: Stage,
    /// How it failed.
    pub kind: FailureKind,
    /// What happened, for people.
    pub message: String,
    /// What tells this failure from others of the same stage and kind: a panic's location, the
    /// property that failed. Inputs with the same stage, kind and signature are one bug.
    pub signature: String,
}

impl Failure {
    /// The key failures are grouped by.
    pub fn key(&self) -> (Stage, FailureKind, String) {
        (self.stage, self.kind, self.signature.clone())
    }
}

/// How the sampler's radius is chosen for an input.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum Radius {
    /// A fraction of the diagonal of the solid's bounding box.
    OfDiagonal(f64),
    /// A length.
    Absolute(f64),
}

/// A fault a worker injects instead of running the stages, on inputs that contain
/// [`crate::stages::FAULT_MARKER`]: the harness's own tests use it to check that each kind of
/// failure is caught, classified and minimised.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Fault {
    /// Panic.
    Panic,
    /// Compute forever (a hang that uses a core).
    Hang,
    /// Wait forever without computing (a deadlock).
    Stall,
    /// Allocate (and touch) memory until stopped.
    Memory,
    /// Recurse until the stack overflows.
    StackOverflow,
    /// Abort the process.
    Abort,
}

/// One input for a worker to run.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Request {
    /// The path the main file is checked under (includes resolve from its directory).
    pub name: String,
    /// The stages to run (with what they need).
    pub stages: Vec<Stage>,
    /// The sampler's radius.
    pub radius: Radius,
    /// Seeds the language server session's edits and requests.
    pub session_seed: u64,
    /// A fault to inject (tests of the harness only).
    #[serde(default)]
    pub fault: Option<Fault>,
    /// The number of input bytes after the line.
    pub len: usize,
}

/// What a worker reports.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub enum Event {
    /// A stage starts.
    Start {
        /// The stage.
        stage: Stage,
    },
    /// A stage ended.
    End {
        /// The stage.
        stage: Stage,
        /// Its time, in microseconds.
        micros: u64,
        /// The most heap it held beyond what was held before it, in bytes.
        peak: u64,
        /// What went wrong, if anything.
        failure: Option<Failure>,
    },
    /// Every stage of the request has run.
    Done,
}

/// Writes a request and its input.
pub fn write_request(out: &mut impl Write, request: &Request, bytes: &[u8]) -> io::Result<()> {
    let line = serde_json::to_string(request).map_err(io::Error::other)?;
    out.write_all(line.as_bytes())?;
    out.write_all(b"\n")?;
    out.write_all(bytes)?;
    out.flush()
}

/// Reads a request and its input; `None` at the end of the stream.
pub fn read_request(input: &mut impl BufRead) -> io::Result<Option<(Request, Vec<u8>)>> {
    let mut line = String::new();
    if input.read_line(&mut line)? == 0 {
        return Ok(None);
    }
    let request: Request = serde_json::from_str(line.trim_end()).map_err(io::Error::other)?;
    let mut bytes = vec![0; request.len];
    input.read_exact(&mut bytes)?;
    Ok(Some((request, bytes)))
}

/// Writes one event line and flushes it, so the supervisor sees it at once.
pub fn write_event(out: &mut impl Write, event: &Event) -> io::Result<()> {
    let line = serde_json::to_string(event).map_err(io::Error::other)?;
    out.write_all(line.as_bytes())?;
    out.write_all(b"\n")?;
    out.flush()
}

/// The event on a line, if it is one.
pub fn parse_event(line: &str) -> Option<Event> {
    serde_json::from_str(line).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn requests_round_trip_with_any_bytes() {
        let bytes = b"cube(1);\n\xff\x00 {".to_vec();
        let request = Request {
            name: "/tmp/x.qcsg".into(),
            stages: Stage::ALL.to_vec(),
            radius: Radius::OfDiagonal(0.05),
            session_seed: 9,
            fault: None,
            len: bytes.len(),
        };
        let mut wire = Vec::new();
        write_request(&mut wire, &request, &bytes).unwrap();
        write_request(&mut wire, &request, &bytes).unwrap();
        let mut reader = io::BufReader::new(&wire[..]);
        for _ in 0..2 {
            let (read, read_bytes) = read_request(&mut reader).unwrap().unwrap();
            assert_eq!(read_bytes, bytes);
            assert_eq!(read.stages, request.stages);
        }
        assert!(read_request(&mut reader).unwrap().is_none());
    }

    #[test]
    fn stage_names_round_trip() {
        for stage in Stage::ALL {
            assert_eq!(Stage::from_name(stage.name()), Some(stage));
        }
    }
}
