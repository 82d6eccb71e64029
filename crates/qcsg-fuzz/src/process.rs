//! One worker process as the supervisor sees it: started, fed one input at a time, watched.
//!
//! [`WorkerProcess::run`] sends a request and reads the worker's events on a reader thread. The
//! watchdog is the wait for the next event: a stage that has not ended within its time budget
//! (the wall time its work would take on an idle machine, from the worker's CPU times, with a cap
//! on wall time: [`crate::cpu_clock`]) is a hang, and the worker is killed. A worker whose
//! output ends before [`Event::Done`] died in the stage it had started; its exit status and the
//! end of its standard error (kept by a second thread) tell an allocation failure, a stack
//! overflow or another crash apart. Either way a fresh worker is started for the next input.

use std::collections::VecDeque;
use std::io::{self, BufRead, BufReader, Read};
use std::os::unix::process::ExitStatusExt;
use std::path::PathBuf;
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError};
use std::sync::{Arc, Mutex};
use std::thread;
use std::time::{Duration, Instant};

use crate::cpu_clock::{Verdict, Watch};
use crate::protocol::{
    Event, Failure, FailureKind, Fault, Radius, Request, Stage, parse_event, write_request,
};
use crate::worker::WorkerOptions;

/// Bytes of a worker's standard error kept (its end, where an abort message is).
const KEPT_STDERR: usize = 8192;

/// How much longer than the stage budget the supervisor waits for a stage that does many
/// analyses (a language server session) or waits on a process it stops itself (the CLI).
fn budget_factor(stage: Stage) -> u32 {
    match stage {
        Stage::Lsp => 3,
        Stage::Cli => 2,
        _ => 1,
    }
}

/// One stage that ended, with its measurements.
#[derive(Clone, Copy, Debug)]
pub struct StageEnd {
    /// The stage.
    pub stage: Stage,
    /// Its time, in microseconds.
    pub micros: u64,
    /// Its peak heap beyond what was held before, in bytes.
    pub peak: u64,
}

/// What running one input gave.
#[derive(Clone, Debug, Default)]
pub struct Outcome {
    /// The stages that ended, in order.
    pub ends: Vec<StageEnd>,
    /// The failures, in order (a hang or crash is the last).
    pub failures: Vec<Failure>,
}

/// What an input is run with, besides its bytes.
#[derive(Clone, Debug)]
pub struct RunSpec {
    /// The path it is checked under.
    pub name: PathBuf,
    /// The stages to run.
    pub stages: Vec<Stage>,
    /// The sampler's radius.
    pub radius: Radius,
    /// The language server session's seed.
    pub session_seed: u64,
    /// A fault to inject (tests only).
    pub fault: Option<Fault>,
}

/// A running worker.
pub struct WorkerProcess {
    exe: PathBuf,
    options: WorkerOptions,
    child: Child,
    stdin: ChildStdin,
    events: Receiver<Event>,
    stderr: Arc<Mutex<VecDeque<u8>>>,
}

impl WorkerProcess {
    /// Starts the harness binary `exe` as a worker.
    ///
    /// # Errors
    /// If the process cannot be started.
    pub fn spawn(exe: PathBuf, options: WorkerOptions) -> io::Result<Self> {
        let mut command = Command::new(&exe);
        command
            .arg("--worker")
            .arg("--memory-mb")
            .arg((options.memory_budget >> 20).to_string())
            .arg("--timeout")
            .arg(options.stage_timeout.as_secs_f64().to_string());
        if let Some(limit) = options.address_space {
            command
                .arg("--address-space-mb")
                .arg((limit >> 20).to_string());
        }
        match &options.qcsg {
            Some(qcsg) => command.arg("--qcsg").arg(qcsg),
            None => command.arg("--no-cli"),
        };
        // No backtraces: a long one would push an abort's message out of the kept tail.
        let mut child = command
            .env("RUST_BACKTRACE", "0")
            .env("RUST_LIB_BACKTRACE", "0")
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()?;
        let stdin = child
            .stdin
            .take()
            .ok_or_else(|| io::Error::other("no stdin"))?;
        let stdout = child
            .stdout
            .take()
            .ok_or_else(|| io::Error::other("no stdout"))?;
        let stderr = child
            .stderr
            .take()
            .ok_or_else(|| io::Error::other("no stderr"))?;
        let (sender, events) = mpsc::channel();
        thread::spawn(move || {
            for line in BufReader::new(stdout).lines() {
                let Ok(line) = line else { break };
                if let Some(event) = parse_event(&line)
                    && sender.send(event).is_err()
                {
                    break;
                }
            }
        });
        let kept = Arc::new(Mutex::new(VecDeque::with_capacity(KEPT_STDERR)));
        let sink = Arc::clone(&kept);
        thread::spawn(move || keep_tail(stderr, &sink));
        Ok(Self {
            exe,
            options,
            child,
            stdin,
            events,
            stderr: kept,
        })
    }

    /// Replaces this worker by a fresh one, after killing it.
    fn restart(&mut self) -> io::Result<()> {
        let _ = self.child.kill();
        let _ = self.child.wait();
        *self = Self::spawn(self.exe.clone(), self.options.clone())?;
        Ok(())
    }

    /// Runs one input, watching every stage's time, and restarts the worker if it hung or died.
    ///
    /// # Errors
    /// If a new worker cannot be started.
    pub fn run(&mut self, spec: &RunSpec, bytes: &[u8]) -> io::Result<Outcome> {
        let request = Request {
            name: spec.name.to_string_lossy().into_owned(),
            stages: spec.stages.clone(),
            radius: spec.radius,
            session_seed: spec.session_seed,
            fault: spec.fault,
            len: bytes.len(),
        };
        if write_request(&mut self.stdin, &request, bytes).is_err() {
            // The worker died between inputs (it should not): start another and try once more.
            self.restart()?;
            write_request(&mut self.stdin, &request, bytes)?;
        }
        let budget = self.options.stage_timeout;
        let pid = self.child.id();
        let mut outcome = Outcome::default();
        let mut current: Option<Stage> = None;
        let mut watch = Watch::start(pid, budget);
        loop {
            let wait = match watch.look() {
                Verdict::Running(wait) => wait,
                Verdict::Over => {
                    let stage = current.unwrap_or(Stage::Parse);
                    let seconds = (budget * budget_factor(stage)).as_secs_f64();
                    let used = watch.work().map_or_else(String::new, |work| {
                        format!(
                            " (work of at least {:.1} s of wall time on an idle machine: {:.1} s \
                             of the worker's CPU time, {:.1} s on its busiest thread; in {:.1} s \
                             of wall time)",
                            work.least_wall().as_secs_f64(),
                            work.total.as_secs_f64(),
                            work.busiest.as_secs_f64(),
                            watch.elapsed().as_secs_f64()
                        )
                    });
                    outcome.failures.push(Failure {
                        stage,
                        kind: FailureKind::Hang,
                        message: format!("the {stage} stage ran past its {seconds} s budget{used}"),
                        signature: String::new(),
                    });
                    self.restart()?;
                    return Ok(outcome);
                }
            };
            match self.events.recv_timeout(wait) {
                Ok(Event::Start { stage }) => {
                    current = Some(stage);
                    watch = Watch::start(pid, budget * budget_factor(stage));
                }
                Ok(Event::End {
                    stage,
                    micros,
                    peak,
                    failure,
                }) => {
                    outcome.ends.push(StageEnd {
                        stage,
                        micros,
                        peak,
                    });
                    outcome.failures.extend(failure);
                    current = None;
                    watch = Watch::start(pid, budget);
                }
                Ok(Event::Done) => return Ok(outcome),
                // Look at the watch again.
                Err(RecvTimeoutError::Timeout) => {}
                Err(RecvTimeoutError::Disconnected) => {
                    let stage = current.unwrap_or(Stage::Parse);
                    outcome.failures.push(self.death(stage));
                    self.restart()?;
                    return Ok(outcome);
                }
            }
        }
    }

    /// Why the worker died during `stage`, from its exit status and standard error.
    fn death(&mut self, stage: Stage) -> Failure {
        // The output ended; the process ends with it (or is made to).
        let deadline = Instant::now() + Duration::from_secs(2);
        let status = loop {
            match self.child.try_wait() {
                Ok(Some(status)) => break Some(status),
                Ok(None) if Instant::now() < deadline => thread::sleep(Duration::from_millis(5)),
                _ => {
                    let _ = self.child.kill();
                    break self.child.wait().ok();
                }
            }
        };
        // Let the standard-error thread read what is left.
        thread::sleep(Duration::from_millis(20));
        let tail = {
            let kept = self.stderr.lock().unwrap_or_else(|p| p.into_inner());
            let (a, b) = kept.as_slices();
            String::from_utf8_lossy(&[a, b].concat()).into_owned()
        };
        let last_lines: String = {
            let lines: Vec<&str> = tail.trim_end().lines().collect();
            lines[lines.len().saturating_sub(4)..].join(" | ")
        };
        let how = match status {
            Some(s) if s.signal().is_some() => format!("signal {}", s.signal().unwrap_or(0)),
            Some(s) => format!("exit status {}", s.code().unwrap_or(-1)),
            None => "unknown status".to_owned(),
        };
        let (kind, signature) = if tail.contains("memory allocation of") {
            (FailureKind::Memory, String::new())
        } else if tail.contains("has overflowed its stack") {
            (FailureKind::StackOverflow, String::new())
        } else {
            (FailureKind::Crash, how.clone())
        };
        Failure {
            stage,
            kind,
            message: format!("the worker died in the {stage} stage ({how}): {last_lines}"),
            signature,
        }
    }
}

impl Drop for WorkerProcess {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Reads `stream` to its end, keeping its last [`KEPT_STDERR`] bytes in `kept`.
fn keep_tail(mut stream: impl Read, kept: &Mutex<VecDeque<u8>>) {
    let mut buffer = [0u8; 4096];
    while let Ok(n) = stream.read(&mut buffer) {
        if n == 0 {
            break;
        }
        let mut kept = kept.lock().unwrap_or_else(|p| p.into_inner());
        kept.extend(&buffer[..n]);
        let excess = kept.len().saturating_sub(KEPT_STDERR);
        kept.drain(..excess);
    }
}
