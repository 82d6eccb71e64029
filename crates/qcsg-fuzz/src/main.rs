//! `qcsg-fuzz`: the fuzzing harness's command line (docs/fuzzing.md).
//!
//! `qcsg-fuzz --seconds 120` (or `--inputs N`) runs the fuzzer and exits with status 1 when
//! anything failed; `--replay FILE` runs one file through the stages; `--worker` is how the
//! harness starts its own worker processes.

use std::num::NonZeroUsize;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use clap::Parser;
use peak_alloc::PeakAlloc;
use qcsg_fuzz::corpus;
use qcsg_fuzz::process::RunSpec;
use qcsg_fuzz::protocol::{Fault, Radius, Stage};
use qcsg_fuzz::supervisor::{self, Config};
use qcsg_fuzz::worker::{self, WorkerOptions};

/// Counts the heap, so that each stage's peak can be measured in the worker.
#[global_allocator]
static ALLOCATOR: PeakAlloc = PeakAlloc;

/// Fuzzes every stage of qcsg with generated and mutated programs.
#[derive(Debug, Parser)]
#[command(name = "qcsg-fuzz", version)]
struct Args {
    /// Run for this many seconds (default: 60, unless --inputs is given).
    #[arg(long, value_name = "S")]
    seconds: Option<f64>,

    /// Run this many inputs.
    #[arg(long, value_name = "N")]
    inputs: Option<u64>,

    /// The run's seed (default: from the clock, printed so the run can be repeated).
    #[arg(long, value_name = "N")]
    seed: Option<u64>,

    /// Worker processes (default: one per core).
    #[arg(long, value_name = "N")]
    workers: Option<NonZeroUsize>,

    /// Time budget of one stage, in seconds (a language server session gets three times as
    /// much): a stage whose work would take longer on an idle machine is a hang.
    #[arg(long, value_name = "S", default_value_t = 5.0)]
    timeout: f64,

    /// Heap budget of one stage, in MiB.
    #[arg(long, value_name = "MIB", default_value_t = 1024)]
    memory_mb: u64,

    /// Limit of a worker's address space, in MiB (default: the heap budget plus 2048, room for
    /// thread stacks and allocator arenas); an allocation past it fails.
    #[arg(long, value_name = "MIB")]
    address_space_mb: Option<u64>,

    /// Time to minimise each distinct failure, in seconds.
    #[arg(long, value_name = "S", default_value_t = 30.0)]
    minimise_seconds: f64,

    /// The stages to run, comma-separated (default: all): parse, format, check, eval, dnf,
    /// emit, sample, render, lsp, cli.
    #[arg(long, value_name = "LIST", value_delimiter = ',', value_parser = parse_stage)]
    stages: Vec<Stage>,

    /// Where failures are written (default: target/fuzz-failures).
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,

    /// The workspace whose examples/ and tests/ are the corpus (default: the one the harness
    /// was built in).
    #[arg(long, value_name = "DIR")]
    root: Option<PathBuf>,

    /// The `qcsg` binary for the cli stage (default: the one beside this binary, when built).
    #[arg(long, value_name = "PATH")]
    qcsg: Option<PathBuf>,

    /// Leave out the cli stage.
    #[arg(long)]
    no_cli: bool,

    /// Run one file through the stages once and print what happened.
    #[arg(long, value_name = "FILE")]
    replay: Option<PathBuf>,

    /// With --replay: the path the file is checked under (default: the file's own).
    #[arg(long, value_name = "PATH", requires = "replay")]
    name: Option<PathBuf>,

    /// With --replay: the language server session's seed.
    #[arg(long, value_name = "N", default_value_t = 0)]
    session_seed: u64,

    /// With --replay: the sampler's radius as a length.
    #[arg(long, value_name = "R", conflicts_with = "radius_fraction")]
    radius: Option<f64>,

    /// With --replay: the sampler's radius as a fraction of the diagonal (default 0.05).
    #[arg(long, value_name = "F")]
    radius_fraction: Option<f64>,

    /// With --replay: inject a fault instead of running the stages (tests of the harness).
    #[arg(long, value_name = "FAULT", hide = true, value_parser = parse_fault)]
    fault: Option<Fault>,

    /// Print no progress while running.
    #[arg(short, long)]
    quiet: bool,

    /// Serve as a worker process (the harness starts these itself).
    #[arg(long, hide = true)]
    worker: bool,
}

fn parse_stage(text: &str) -> Result<Stage, String> {
    Stage::from_name(text).ok_or_else(|| format!("no stage `{text}`"))
}

fn parse_fault(text: &str) -> Result<Fault, String> {
    serde_json::from_value(serde_json::Value::String(text.to_owned()))
        .map_err(|_| format!("no fault `{text}`"))
}

/// The `qcsg` binary beside this one (both are built into the same target directory).
fn sibling_qcsg() -> Option<PathBuf> {
    let exe = std::env::current_exe().ok()?;
    let qcsg = exe.with_file_name("qcsg");
    qcsg.is_file().then_some(qcsg)
}

/// `target/fuzz-failures` of the target directory this binary is in.
fn default_out() -> PathBuf {
    std::env::current_exe()
        .ok()
        .and_then(|exe| Some(exe.parent()?.parent()?.join("fuzz-failures")))
        .unwrap_or_else(|| PathBuf::from("fuzz-failures"))
}

fn main() -> ExitCode {
    let args = Args::parse();
    let qcsg = if args.no_cli {
        None
    } else {
        args.qcsg.clone().or_else(sibling_qcsg)
    };
    let memory_budget = args.memory_mb << 20;
    let worker_options = WorkerOptions {
        qcsg: qcsg.clone(),
        memory_budget,
        address_space: Some(args.address_space_mb.unwrap_or(args.memory_mb + 2048) << 20),
        stage_timeout: Duration::from_secs_f64(args.timeout.max(0.01)),
    };
    if args.worker {
        return match worker::run(&worker_options) {
            Ok(()) => ExitCode::SUCCESS,
            Err(error) => {
                eprintln!("qcsg-fuzz worker: {error}");
                ExitCode::from(2)
            }
        };
    }
    let Ok(exe) = std::env::current_exe() else {
        eprintln!("error: cannot find the harness's own binary");
        return ExitCode::from(2);
    };
    let mut stages = if args.stages.is_empty() {
        Stage::ALL.to_vec()
    } else {
        args.stages.clone()
    };
    if qcsg.is_none() {
        stages.retain(|&s| s != Stage::Cli);
    }
    let seed = args.seed.unwrap_or_else(|| {
        SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .map_or(0, |d| d.as_nanos() as u64)
    });
    let config = Config {
        seed,
        inputs: args.inputs,
        duration: match (args.seconds, args.inputs) {
            (Some(s), _) => Some(Duration::from_secs_f64(s.max(0.0))),
            (None, Some(_)) => None,
            (None, None) => Some(Duration::from_secs(60)),
        },
        workers: args
            .workers
            .or_else(|| std::thread::available_parallelism().ok())
            .map_or(1, NonZeroUsize::get),
        stages,
        worker: worker_options,
        exe,
        root: args.root.clone().unwrap_or_else(corpus::default_root),
        out: args.out.clone().unwrap_or_else(default_out),
        minimise_time: Duration::from_secs_f64(args.minimise_seconds.max(0.0)),
        progress: !args.quiet,
    };

    if let Some(file) = &args.replay {
        return replay(&config, &args, file);
    }

    eprintln!(
        "qcsg-fuzz: seed {seed} (repeat this run with --seed {seed}); stages {}",
        config
            .stages
            .iter()
            .map(|s| s.name())
            .collect::<Vec<_>>()
            .join(",")
    );
    if qcsg.is_none() && !args.no_cli {
        eprintln!(
            "qcsg-fuzz: the cli stage is off: no `qcsg` binary beside the harness (build it with \
             `cargo build [--release] -p qcsg-cli`, or pass --qcsg PATH)"
        );
    }
    match supervisor::run(&config) {
        Ok(summary) => {
            print!("{summary}");
            if summary.failed() {
                ExitCode::FAILURE
            } else {
                ExitCode::SUCCESS
            }
        }
        Err(error) => {
            eprintln!("error: {error}");
            ExitCode::from(2)
        }
    }
}

/// `--replay FILE`: one run, its stages and failures printed; exit status 1 on a failure.
fn replay(config: &Config, args: &Args, file: &PathBuf) -> ExitCode {
    let bytes = match std::fs::read(file) {
        Ok(bytes) => bytes,
        Err(error) => {
            eprintln!("error: cannot read `{}`: {error}", file.display());
            return ExitCode::from(2);
        }
    };
    let spec = RunSpec {
        name: args.name.clone().unwrap_or_else(|| file.clone()),
        stages: config.stages.clone(),
        radius: match (args.radius, args.radius_fraction) {
            (Some(r), _) => Radius::Absolute(r),
            (None, Some(f)) => Radius::OfDiagonal(f),
            (None, None) => Radius::OfDiagonal(0.05),
        },
        session_seed: args.session_seed,
        fault: args.fault,
    };
    match supervisor::replay(config, &spec, &bytes) {
        Ok(outcome) => {
            for end in &outcome.ends {
                println!(
                    "{:<8} {:>10.2} ms {:>10.1} MiB",
                    end.stage.name(),
                    end.micros as f64 / 1000.0,
                    end.peak as f64 / f64::from(1 << 20)
                );
            }
            for failure in &outcome.failures {
                println!(
                    "FAILED {} {} [{}]: {}",
                    failure.stage, failure.kind, failure.signature, failure.message
                );
            }
            if outcome.failures.is_empty() {
                ExitCode::SUCCESS
            } else {
                ExitCode::FAILURE
            }
        }
        Err(error) => {
            eprintln!("error: {error}");
            ExitCode::from(2)
        }
    }
}
