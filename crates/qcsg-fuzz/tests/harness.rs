//! The harness catches what it is for: each kind of failure, injected into a real worker
//! process, is detected and classified, and a failing input is minimised through the workers;
//! and the generator writes programs that get through the checker to the deeper stages.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

use qcsg_diag::FileId;
use qcsg_fuzz::dice::Dice;
use qcsg_fuzz::generate;
use qcsg_fuzz::input::Input;
use qcsg_fuzz::process::{RunSpec, WorkerProcess};
use qcsg_fuzz::protocol::{Failure, FailureKind, Fault, Radius, Stage};
use qcsg_fuzz::supervisor::{self, Config};
use qcsg_fuzz::worker::WorkerOptions;

const EXE: &str = env!("CARGO_BIN_EXE_qcsg-fuzz");

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("qcsg-fuzz-test-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn options() -> WorkerOptions {
    WorkerOptions {
        qcsg: None,
        memory_budget: 256 << 20,
        address_space: Some(2048 << 20),
        stage_timeout: Duration::from_secs(2),
    }
}

/// `qcsg-fuzz --replay` of a file with the fault marker and `--fault`: the line it prints.
fn replay_with_fault(fault: &str) -> String {
    let dir = scratch(fault);
    let file = dir.join("input.qcsg");
    std::fs::write(&file, "cube(1); // qcsg-fuzz-fault\n").unwrap();
    let output = Command::new(EXE)
        .arg("--replay")
        .arg(&file)
        .args([
            "--fault",
            fault,
            "--timeout",
            "2",
            "--memory-mb",
            "256",
            "--no-cli",
        ])
        .args(["--address-space-mb", "2048"])
        .arg("--out")
        .arg(&dir)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    assert_eq!(output.status.code(), Some(1), "{stdout}");
    stdout
}

#[test]
fn each_kind_of_failure_is_caught_and_classified() {
    for (fault, expected) in [
        (
            "panic",
            "FAILED parse panic [crates/qcsg-fuzz/src/stages.rs:",
        ),
        ("hang", "FAILED parse hang"),
        // Found by the cap on wall time (4× the budget), as it uses no CPU time.
        ("stall", "FAILED parse hang"),
        ("memory", "FAILED parse memory"),
        ("stack-overflow", "FAILED parse stack-overflow"),
        ("abort", "FAILED parse crash [signal 6]"),
    ] {
        let out = replay_with_fault(fault);
        assert!(out.contains(expected), "{fault}: {out}");
    }
}

#[test]
fn a_failing_input_is_minimised_through_the_workers() {
    let dir = scratch("minimise");
    let mut worker = WorkerProcess::spawn(PathBuf::from(EXE), options()).unwrap();
    let mut bytes = Vec::new();
    for i in 0..40 {
        bytes.extend_from_slice(format!("cube({i});\n").as_bytes());
        if i == 27 {
            bytes.extend_from_slice(b"x = 1; // qcsg-fuzz-fault\n");
        }
    }
    let input = Input {
        index: 0,
        bytes,
        name: dir.join("main.qcsg"),
        radius: Radius::OfDiagonal(0.05),
        session_seed: 0,
        origin: "test".into(),
    };
    let spec = RunSpec {
        name: input.name.clone(),
        stages: Stage::ALL.to_vec(),
        radius: input.radius,
        session_seed: 0,
        fault: Some(Fault::Panic),
    };
    let outcome = worker.run(&spec, &input.bytes).unwrap();
    let failure: Failure = outcome.failures[0].clone();
    assert_eq!(
        (failure.stage, failure.kind),
        (Stage::Parse, FailureKind::Panic)
    );

    let config = Config {
        seed: 0,
        inputs: None,
        duration: None,
        workers: 1,
        stages: Stage::ALL.to_vec(),
        worker: options(),
        exe: PathBuf::from(EXE),
        root: dir.clone(),
        out: dir.clone(),
        minimise_time: Duration::from_secs(60),
        progress: false,
    };
    // The fault is injected by requests that ask for it: minimise with the same request.
    let minimised = {
        let mut still_fails = |b: &[u8]| {
            worker
                .run(&spec, b)
                .unwrap()
                .failures
                .iter()
                .any(|f| f.key() == failure.key())
        };
        qcsg_fuzz::minimise::minimise(
            &input.bytes,
            &mut still_fails,
            std::time::Instant::now() + Duration::from_secs(60),
        )
    };
    assert_eq!(String::from_utf8_lossy(&minimised), "qcsg-fuzz-fault");
    // Without the fault, the same worker runs the input clean through every stage it has.
    let clean = supervisor::replay(
        &config,
        &RunSpec {
            fault: None,
            ..spec.clone()
        },
        &input.bytes,
    )
    .unwrap();
    let stages: BTreeSet<Stage> = clean.ends.iter().map(|e| e.stage).collect();
    assert!(
        stages.contains(&Stage::Sample) && stages.contains(&Stage::Render),
        "{clean:?}"
    );
}

#[test]
fn generated_programs_reach_the_deep_stages() {
    // Through a worker, under its memory limit: a generated program may be one of the
    // explosive ones (echo of a value shared 2^40 times), which in this process would take
    // the machine's memory.
    let libs = scratch("libs");
    qcsg_fuzz::libs::write(&libs).unwrap();
    let mut worker = WorkerProcess::spawn(PathBuf::from(EXE), options()).unwrap();
    let spec = RunSpec {
        name: libs.join("main.qcsg"),
        stages: vec![Stage::Parse, Stage::Sample, Stage::Render],
        radius: Radius::OfDiagonal(0.05),
        session_seed: 0,
        fault: None,
    };
    let programs = 200;
    let mut reached: BTreeMap<Stage, usize> = BTreeMap::new();
    let mut clean_parses = 0;
    let mut modules = BTreeSet::new();
    for seed in 0..programs {
        let text = generate::program(&mut Dice::new(seed));
        let parse = qcsg_syntax::parse(&text, FileId(0));
        clean_parses += usize::from(!parse.diagnostics.iter().any(|d| d.is_error()));
        for module in qcsg_sema::builtins::MODULES {
            if text.contains(&format!("{}(", module.name)) {
                modules.insert(module.name);
            }
        }
        let outcome = worker.run(&spec, text.as_bytes()).unwrap();
        for end in &outcome.ends {
            *reached.entry(end.stage).or_default() += 1;
        }
    }
    let share = |stage| reached.get(&stage).copied().unwrap_or(0) * 100 / programs as usize;
    assert!(
        clean_parses * 100 >= programs as usize * 85,
        "{clean_parses} parse clean"
    );
    // A stage runs only when the one before it succeeded: checked without errors, evaluated
    // without errors, a DNF built.
    assert!(share(Stage::Eval) >= 25, "{reached:?}");
    assert!(share(Stage::Sample) >= 10, "{reached:?}");
    assert!(share(Stage::Render) >= 10, "{reached:?}");
    let missing: Vec<&str> = qcsg_sema::builtins::MODULES
        .iter()
        .map(|m| m.name)
        .filter(|name| !modules.contains(name))
        .collect();
    assert!(missing.is_empty(), "never generated: {missing:?}");
}

#[test]
fn the_library_files_exist_for_every_include_path_that_should() {
    let libs = scratch("include-paths");
    qcsg_fuzz::libs::write(&libs).unwrap();
    for path in generate::INCLUDE_PATHS {
        if path.ends_with(".qcsg") || path.ends_with(".scad") {
            let exists = Path::new(&libs).join(path).is_file();
            assert_eq!(exists, !path.starts_with("missing"), "{path}");
        }
    }
}
