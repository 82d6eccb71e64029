//! A fuzzing run: inputs spread over worker processes, results gathered, failures minimised
//! and written down.
//!
//! One supervisor thread per worker ([`crate::process`]) takes the next input index, builds the
//! input ([`crate::input::make`]) and runs it; the run stops after `--inputs` inputs or
//! `--seconds` seconds. Failures are grouped by stage, kind and signature (one group is one
//! bug, however many inputs hit it); the first input of each group is minimised on a worker
//! ([`crate::minimise`]) and written with its report ([`crate::report`]).

use std::collections::BTreeMap;
use std::io;
use std::path::PathBuf;
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};
use std::thread;
use std::time::{Duration, Instant};

use crate::corpus::Corpus;
use crate::input::{self, Input};
use crate::minimise::minimise;
use crate::process::{Outcome, RunSpec, WorkerProcess};
use crate::protocol::{Failure, FailureKind, Stage};
use crate::report::{self, FailureGroup, StageStats, Summary};
use crate::worker::WorkerOptions;

/// What a run does.
#[derive(Clone, Debug)]
pub struct Config {
    /// The run's seed.
    pub seed: u64,
    /// Stop after this many inputs.
    pub inputs: Option<u64>,
    /// Stop after this much time.
    pub duration: Option<Duration>,
    /// Worker processes.
    pub workers: usize,
    /// The stages to run.
    pub stages: Vec<Stage>,
    /// How each worker runs.
    pub worker: WorkerOptions,
    /// The harness binary (started as workers).
    pub exe: PathBuf,
    /// The workspace whose `examples/` and `tests/` are the corpus.
    pub root: PathBuf,
    /// Where failures are written.
    pub out: PathBuf,
    /// Time to minimise each distinct failure.
    pub minimise_time: Duration,
    /// Print progress every so often.
    pub progress: bool,
}

/// What the workers gather during the run.
#[derive(Default)]
struct Gathered {
    inputs: u64,
    by_origin: BTreeMap<String, u64>,
    stages: BTreeMap<Stage, StageStats>,
    groups: BTreeMap<(Stage, FailureKind, String), FailureGroup>,
}

impl Gathered {
    fn record(&mut self, input: &Input, outcome: &Outcome) {
        self.inputs += 1;
        let origin = if input.origin == "generated" {
            "generated"
        } else if input.origin.starts_with("generated") {
            "generated, mutated"
        } else {
            "corpus, mutated"
        };
        *self.by_origin.entry(origin.to_owned()).or_default() += 1;
        for end in &outcome.ends {
            self.stages
                .entry(end.stage)
                .or_default()
                .add(end.micros, end.peak);
        }
        for failure in &outcome.failures {
            if !outcome.ends.iter().any(|e| e.stage == failure.stage) {
                // A stage that hung or died sent no end: count its run here.
                self.stages
                    .entry(failure.stage)
                    .or_default()
                    .add_unfinished();
            }
            self.groups
                .entry(failure.key())
                .or_insert_with(|| FailureGroup::new(input.clone(), failure.clone()))
                .count += 1;
        }
    }
}

/// The directory of library files that generated programs `include`, beside the failures
/// (`libs/`), where it stays so that reports can be replayed.
pub fn library_dir(out: &std::path::Path) -> io::Result<PathBuf> {
    let dir = out.join("libs");
    crate::libs::write(&dir)?;
    Ok(dir)
}

/// Runs the fuzzer; the summary says what it found.
///
/// # Errors
/// If the library directory, a worker or a report cannot be made.
pub fn run(config: &Config) -> io::Result<Summary> {
    let libs = library_dir(&config.out)?;
    let corpus = Corpus::load(&config.root);
    let started = Instant::now();
    let next = AtomicU64::new(0);
    let gathered = Mutex::new(Gathered::default());
    let stop_at = config.duration.map(|d| started + d);
    let last_progress = Mutex::new(Instant::now());

    thread::scope(|scope| -> io::Result<()> {
        let mut handles = Vec::new();
        for _ in 0..config.workers.max(1) {
            handles.push(scope.spawn(|| -> io::Result<()> {
                let mut worker = WorkerProcess::spawn(config.exe.clone(), config.worker.clone())?;
                loop {
                    if stop_at.is_some_and(|t| Instant::now() >= t) {
                        break;
                    }
                    let index = next.fetch_add(1, Ordering::Relaxed);
                    if config.inputs.is_some_and(|n| index >= n) {
                        break;
                    }
                    let input = input::make(config.seed, index, &corpus, &libs);
                    let outcome = worker.run(&spec_of(&input, &config.stages), &input.bytes)?;
                    let mut gathered = gathered.lock().unwrap_or_else(|p| p.into_inner());
                    gathered.record(&input, &outcome);
                    let mut last = last_progress.lock().unwrap_or_else(|p| p.into_inner());
                    if config.progress && last.elapsed() > Duration::from_secs(15) {
                        *last = Instant::now();
                        eprintln!(
                            "[{:.0} s] {} inputs, {} failures in {} groups",
                            started.elapsed().as_secs_f64(),
                            gathered.inputs,
                            gathered.groups.values().map(|g| g.count).sum::<u64>(),
                            gathered.groups.len()
                        );
                    }
                }
                Ok(())
            }));
        }
        for handle in handles {
            handle
                .join()
                .map_err(|_| io::Error::other("a supervisor thread panicked"))??;
        }
        Ok(())
    })?;
    let elapsed = started.elapsed();
    let gathered = gathered.into_inner().unwrap_or_else(|p| p.into_inner());

    let mut groups: Vec<FailureGroup> = gathered.groups.into_values().collect();
    if !groups.is_empty() {
        minimise_groups(config, &mut groups)?;
        for group in &groups {
            report::write_group(&config.out, config.seed, group)?;
        }
    }
    Ok(Summary {
        seed: config.seed,
        workers: config.workers,
        inputs: gathered.inputs,
        elapsed,
        by_origin: gathered.by_origin,
        stages: gathered.stages,
        groups,
        out: config.out.clone(),
    })
}

/// How an input is run.
fn spec_of(input: &Input, stages: &[Stage]) -> RunSpec {
    RunSpec {
        name: input.name.clone(),
        stages: stages.to_vec(),
        radius: input.radius,
        session_seed: input.session_seed,
        fault: None,
    }
}

/// Minimises the first input of each group, the groups spread over the workers.
fn minimise_groups(config: &Config, groups: &mut [FailureGroup]) -> io::Result<()> {
    let chunk = groups.len().div_ceil(config.workers.max(1));
    thread::scope(|scope| -> io::Result<()> {
        let mut handles = Vec::new();
        for part in groups.chunks_mut(chunk.max(1)) {
            handles.push(scope.spawn(|| -> io::Result<()> {
                let mut worker = WorkerProcess::spawn(config.exe.clone(), config.worker.clone())?;
                for group in part {
                    group.minimised = Some(minimise_one(
                        &mut worker,
                        config,
                        &group.input,
                        &group.failure,
                    )?);
                }
                Ok(())
            }));
        }
        for handle in handles {
            handle
                .join()
                .map_err(|_| io::Error::other("a minimising thread panicked"))??;
        }
        Ok(())
    })
}

/// The smallest input found in the time budget that fails like `failure` does, running only
/// the failing stage and what it needs.
pub fn minimise_one(
    worker: &mut WorkerProcess,
    config: &Config,
    input: &Input,
    failure: &Failure,
) -> io::Result<Vec<u8>> {
    let spec = RunSpec {
        stages: vec![failure.stage],
        ..spec_of(input, &config.stages)
    };
    let deadline = Instant::now() + config.minimise_time;
    let mut error = None;
    let mut still_fails = |bytes: &[u8]| match worker.run(&spec, bytes) {
        Ok(outcome) => outcome.failures.iter().any(|f| f.key() == failure.key()),
        Err(e) => {
            error.get_or_insert(e);
            false
        }
    };
    // An input that does not fail alone (it needed a stage before it) is kept as it is.
    if !still_fails(&input.bytes) {
        return Ok(input.bytes.clone());
    }
    let minimised = minimise(&input.bytes, &mut still_fails, deadline);
    match error {
        Some(e) => Err(e),
        None => Ok(minimised),
    }
}

/// Runs one file through the stages once (the `--replay` mode), returning what happened.
///
/// # Errors
/// If the worker cannot be started.
pub fn replay(config: &Config, spec: &RunSpec, bytes: &[u8]) -> io::Result<Outcome> {
    let mut worker = WorkerProcess::spawn(config.exe.clone(), config.worker.clone())?;
    worker.run(spec, bytes)
}
