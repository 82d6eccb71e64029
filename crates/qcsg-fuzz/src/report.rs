//! What a run reports: the summary printed at its end (inputs, time, throughput per stage,
//! failures by kind) and, for each distinct failure, a directory with the minimised input, the
//! original input and a report to reproduce it from.
//!
//! A failure's directory is named by its stage, kind and a hash of its signature
//! (`parse-hang-0000000000000000`), so a later run that finds the same bug writes to the same
//! place instead of piling up copies.

use std::collections::BTreeMap;
use std::fmt::{self, Write as _};
use std::io;
use std::path::{Path, PathBuf};
use std::time::Duration;

use crate::input::Input;
use crate::protocol::{Failure, FailureKind, Radius, Stage};

/// Time and memory of one stage over a run.
#[derive(Clone, Copy, Debug, Default)]
pub struct StageStats {
    /// How often it ran.
    pub runs: u64,
    /// Runs that never ended (the worker hung or died in it).
    pub unfinished: u64,
    /// Its total time, in microseconds.
    pub micros: u64,
    /// Its longest run, in microseconds.
    pub max_micros: u64,
    /// Its highest peak heap, in bytes.
    pub max_peak: u64,
}

impl StageStats {
    /// Counts a run that ended.
    pub fn add(&mut self, micros: u64, peak: u64) {
        self.runs += 1;
        self.micros += micros;
        self.max_micros = self.max_micros.max(micros);
        self.max_peak = self.max_peak.max(peak);
    }

    /// Counts a run that never ended.
    pub fn add_unfinished(&mut self) {
        self.runs += 1;
        self.unfinished += 1;
    }

    /// Runs per second of a worker's time spent in this stage.
    pub fn per_second(&self) -> f64 {
        if self.micros == 0 {
            return 0.0;
        }
        (self.runs - self.unfinished) as f64 / (self.micros as f64 * 1e-6)
    }
}

/// The inputs that failed one way: one bug.
#[derive(Clone, Debug)]
pub struct FailureGroup {
    /// The first input that failed so.
    pub input: Input,
    /// Its failure.
    pub failure: Failure,
    /// How many inputs failed so.
    pub count: u64,
    /// The first input minimised, once done.
    pub minimised: Option<Vec<u8>>,
}

impl FailureGroup {
    /// A group of one.
    pub fn new(input: Input, failure: Failure) -> Self {
        Self {
            input,
            failure,
            count: 0,
            minimised: None,
        }
    }

    /// The directory name of the group.
    pub fn dir_name(&self) -> String {
        format!(
            "{}-{}-{:016x}",
            self.failure.stage,
            self.failure.kind,
            fnv1a(self.failure.signature.as_bytes())
        )
    }
}

/// A stable 64-bit hash (FNV-1a), for directory names that do not change between runs.
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |hash, &b| {
        (hash ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// The end of a run.
#[derive(Debug)]
pub struct Summary {
    /// The run's seed.
    pub seed: u64,
    /// Worker processes.
    pub workers: usize,
    /// Inputs run.
    pub inputs: u64,
    /// Time the inputs took (minimisation not included).
    pub elapsed: Duration,
    /// Inputs by where they came from.
    pub by_origin: BTreeMap<String, u64>,
    /// Each stage's numbers.
    pub stages: BTreeMap<Stage, StageStats>,
    /// The distinct failures.
    pub groups: Vec<FailureGroup>,
    /// Where failures were written.
    pub out: PathBuf,
}

impl Summary {
    /// Whether anything failed.
    pub fn failed(&self) -> bool {
        !self.groups.is_empty()
    }
}

impl fmt::Display for Summary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let seconds = self.elapsed.as_secs_f64();
        writeln!(
            f,
            "qcsg-fuzz: seed {}, {} inputs in {seconds:.1} s on {} workers ({:.1} inputs/s)",
            self.seed,
            self.inputs,
            self.workers,
            self.inputs as f64 / seconds.max(1e-9)
        )?;
        let origins: Vec<String> = self
            .by_origin
            .iter()
            .map(|(origin, n)| format!("{n} {origin}"))
            .collect();
        writeln!(f, "inputs: {}", origins.join(", "))?;
        writeln!(
            f,
            "{:<8} {:>8} {:>10} {:>10} {:>12} {:>12}",
            "stage", "runs", "mean ms", "max ms", "runs/s/core", "max heap MiB"
        )?;
        for (stage, stats) in &self.stages {
            let finished = (stats.runs - stats.unfinished).max(1);
            writeln!(
                f,
                "{:<8} {:>8} {:>10.2} {:>10.1} {:>12.1} {:>12.1}",
                stage.name(),
                stats.runs,
                stats.micros as f64 / finished as f64 / 1000.0,
                stats.max_micros as f64 / 1000.0,
                stats.per_second(),
                stats.max_peak as f64 / f64::from(1 << 20)
            )?;
        }
        let mut by_kind: BTreeMap<FailureKind, (u64, usize)> = BTreeMap::new();
        for group in &self.groups {
            let entry = by_kind.entry(group.failure.kind).or_default();
            entry.0 += group.count;
            entry.1 += 1;
        }
        if self.groups.is_empty() {
            return writeln!(f, "failures: none");
        }
        let kinds: Vec<String> = by_kind
            .iter()
            .map(|(kind, (inputs, groups))| format!("{kind}: {inputs} inputs in {groups} groups"))
            .collect();
        writeln!(f, "failures: {}", kinds.join("; "))?;
        for group in &self.groups {
            let size = group
                .minimised
                .as_ref()
                .map_or(group.input.bytes.len(), Vec::len);
            writeln!(
                f,
                "  {} {} ({} inputs; minimised to {size} bytes): {}",
                group.failure.stage,
                group.failure.kind,
                group.count,
                first_line(&group.failure.message, 160)
            )?;
            writeln!(f, "    {}", self.out.join(group.dir_name()).display())?;
        }
        Ok(())
    }
}

/// The first line of `text`, at most `max` characters.
fn first_line(text: &str, max: usize) -> String {
    let line = text.lines().next().unwrap_or("");
    if line.chars().count() > max {
        format!("{}…", line.chars().take(max).collect::<String>())
    } else {
        line.to_owned()
    }
}

/// The command that replays a failure's input.
fn replay_command(file: &Path, input: &Input, stage: Stage) -> String {
    let radius = match input.radius {
        Radius::OfDiagonal(f) => format!("--radius-fraction {f}"),
        Radius::Absolute(r) => format!("--radius {r}"),
    };
    format!(
        "cargo run --release -p qcsg-fuzz -- --replay {} --name {} --session-seed {} {radius} \
         --stages {stage}",
        file.display(),
        input.name.display(),
        input.session_seed
    )
}

/// Writes a group's directory: `input.qcsg` (minimised), `original.qcsg` and `report.txt`.
///
/// # Errors
/// If the directory or a file cannot be written.
pub fn write_group(out: &Path, seed: u64, group: &FailureGroup) -> io::Result<PathBuf> {
    let dir = out.join(group.dir_name());
    std::fs::create_dir_all(&dir)?;
    let minimised = group.minimised.as_ref().unwrap_or(&group.input.bytes);
    std::fs::write(dir.join("input.qcsg"), minimised)?;
    std::fs::write(dir.join("original.qcsg"), &group.input.bytes)?;
    let failure = &group.failure;
    let mut text = String::new();
    let _ = writeln!(text, "stage: {}", failure.stage);
    let _ = writeln!(text, "kind: {}", failure.kind);
    let _ = writeln!(text, "signature: {}", failure.signature);
    let _ = writeln!(text, "inputs that failed so: {}", group.count);
    let _ = writeln!(text, "seed: {seed}, input {}", group.input.index);
    let _ = writeln!(text, "origin: {}", group.input.origin);
    let _ = writeln!(text, "checked as: {}", group.input.name.display());
    let _ = writeln!(
        text,
        "sizes: {} bytes, minimised to {} bytes",
        group.input.bytes.len(),
        minimised.len()
    );
    let _ = writeln!(
        text,
        "replay: {}",
        replay_command(&dir.join("input.qcsg"), &group.input, failure.stage)
    );
    let _ = writeln!(text, "\nmessage:\n{}", failure.message);
    std::fs::write(dir.join("report.txt"), text)?;
    Ok(dir)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn directory_names_depend_on_the_failure_only() {
        let input = |index| Input {
            index,
            bytes: vec![index as u8],
            name: PathBuf::from("/x/main.qcsg"),
            radius: Radius::OfDiagonal(0.05),
            session_seed: index,
            origin: "generated".into(),
        };
        let failure = Failure {
            stage: Stage::Parse,
            kind: FailureKind::Hang,
            message: "slow".into(),
            signature: String::new(),
        };
        let a = FailureGroup::new(input(1), failure.clone());
        let b = FailureGroup::new(input(2), failure.clone());
        assert_eq!(a.dir_name(), b.dir_name());
        let other = FailureGroup::new(
            input(1),
            Failure {
                signature: "src/x.rs:1:2".into(),
                ..failure
            },
        );
        assert_ne!(a.dir_name(), other.dir_name());
        assert!(a.dir_name().starts_with("parse-hang-"));
    }
}
