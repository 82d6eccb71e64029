//! The `qcsg check` stage: the real binary, for what only it does: reading the source bytes
//! (invalid UTF-8 included) and drawing human-readable diagnostics with source excerpts.
//!
//! The input goes to `qcsg check -` on standard input, run in the directory of the name the
//! input is checked under (so its includes resolve as in process), with the evaluator's limits
//! set to the in-process stages' ([`crate::stages::eval_options`]). A panic (exit status 101), a
//! signal, a run past the stage's time, output out of proportion to the input, or exit status 2
//! ("unreadable input") for a program are failures; errors in the program (status 1) are not.
//! The process inherits the worker's address-space limit, so a runaway allocation aborts it.

use std::io::{Read, Write};
use std::os::unix::process::ExitStatusExt;
use std::path::Path;
use std::process::{Command, Stdio};
use std::thread;
use std::time::Duration;

use crate::cpu_clock::{Verdict, Watch};

use crate::panics::relative;
use crate::protocol::FailureKind;
use crate::stages::{Problem, eval_options};

/// Bytes of standard error kept for a report (the end, where a panic or abort message is).
const KEPT_TAIL: usize = 4096;

/// The most output a run may print: generous for `echo` in loops, far below what a quadratic
/// renderer prints for a long line.
fn output_budget(input_len: usize) -> u64 {
    (64 << 20) + 64 * input_len as u64
}

/// What was read from one of the child's streams.
#[derive(Default)]
struct Drained {
    total: u64,
    tail: Vec<u8>,
}

/// Reads `stream` to its end on a thread, counting it and keeping its tail.
fn drain(mut stream: impl Read + Send + 'static) -> thread::JoinHandle<Drained> {
    thread::spawn(move || {
        let mut drained = Drained::default();
        let mut buffer = vec![0; 64 * 1024];
        while let Ok(n) = stream.read(&mut buffer) {
            if n == 0 {
                break;
            }
            drained.total += n as u64;
            drained.tail.extend_from_slice(&buffer[..n]);
            if drained.tail.len() > 2 * KEPT_TAIL {
                let cut = drained.tail.len() - KEPT_TAIL;
                drained.tail.drain(..cut);
            }
        }
        drained
    })
}

/// Runs `qcsg check -` on `bytes` as if they were the file `name`.
pub fn run(qcsg: &Path, name: &Path, bytes: &[u8], timeout: Duration) -> Result<(), Problem> {
    let limits = eval_options();
    let dir = name
        .parent()
        .filter(|d| d.is_dir())
        .unwrap_or_else(|| Path::new("."));
    let mut child = Command::new(qcsg)
        .arg("check")
        .arg("-")
        .args(["--threads", "1"])
        .args(["--max-recursion", &limits.max_recursion.to_string()])
        .args(["--max-iterations", &limits.max_iterations.to_string()])
        .args(["--max-vector-len", &limits.max_vector_len.to_string()])
        .args(["--max-instances", &limits.max_instances.to_string()])
        .current_dir(dir)
        .env("NO_COLOR", "1")
        .env("RUST_BACKTRACE", "0")
        .env_remove("QCSG_PATH")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|error| Problem {
            kind: FailureKind::Crash,
            message: format!("cannot start {}: {error}", qcsg.display()),
            signature: "spawn".to_owned(),
        })?;
    let stdin = child.stdin.take();
    let input = bytes.to_vec();
    let writer = thread::spawn(move || {
        if let Some(mut stdin) = stdin {
            // The binary may stop reading early (it refused the input): not our failure.
            let _ = stdin.write_all(&input);
        }
    });
    let stdout = child.stdout.take().map(drain);
    let stderr = child.stderr.take().map(drain);

    // The binary's work against the budget, as the supervisor watches the worker.
    let watch = Watch::start(child.id(), timeout);
    let mut pause = Duration::from_millis(1);
    let status = loop {
        match child.try_wait() {
            Ok(Some(status)) => break Some(status),
            Ok(None) if watch.look() == Verdict::Over => {
                let _ = child.kill();
                let _ = child.wait();
                break None;
            }
            Ok(None) => {
                thread::sleep(pause);
                pause = (pause * 2).min(Duration::from_millis(20));
            }
            Err(error) => {
                return Err(Problem {
                    kind: FailureKind::Crash,
                    message: format!("cannot wait for qcsg: {error}"),
                    signature: "wait".to_owned(),
                });
            }
        }
    };
    let _ = writer.join();
    // The streams end with the process (it starts no other), so the readers finish too.
    let collect = |handle: Option<thread::JoinHandle<Drained>>| {
        handle.and_then(|h| h.join().ok()).unwrap_or_default()
    };
    let out = collect(stdout);
    let err = collect(stderr);
    let err_tail = String::from_utf8_lossy(&err.tail).into_owned();

    let Some(status) = status else {
        return Err(Problem {
            kind: FailureKind::Hang,
            message: format!("`qcsg check` ran past {} s", timeout.as_secs_f64()),
            signature: String::new(),
        });
    };
    classify(status, &err_tail, out.total + err.total, bytes.len())
}

/// Turns the binary's exit into a verdict.
fn classify(
    status: std::process::ExitStatus,
    stderr_tail: &str,
    output: u64,
    input_len: usize,
) -> Result<(), Problem> {
    let tail = stderr_tail.trim_end();
    let last_lines = {
        let lines: Vec<&str> = tail.lines().collect();
        lines[lines.len().saturating_sub(6)..].join("\n")
    };
    if tail.contains("memory allocation of") {
        return Err(Problem {
            kind: FailureKind::Memory,
            message: format!("`qcsg check` ran out of memory: {last_lines}"),
            signature: String::new(),
        });
    }
    if tail.contains("has overflowed its stack") {
        return Err(Problem {
            kind: FailureKind::StackOverflow,
            message: format!("`qcsg check` overflowed its stack: {last_lines}"),
            signature: String::new(),
        });
    }
    match status.code() {
        Some(0 | 1) if output > output_budget(input_len) => Err(Problem::invariant(
            "`qcsg check` printed out of proportion to its input",
            format!("{output} bytes of output for {input_len} bytes of input"),
        )),
        Some(0 | 1) => Ok(()),
        Some(2) => Err(Problem {
            kind: FailureKind::Refused,
            message: format!("`qcsg check` refused the program (exit status 2): {last_lines}"),
            signature: tail
                .lines()
                .find(|l| l.starts_with("error:"))
                .map_or_else(String::new, |l| {
                    l.chars().filter(|c| !c.is_ascii_digit()).take(80).collect()
                }),
        }),
        Some(101) => {
            let location = panic_location(tail);
            Err(Problem {
                kind: FailureKind::Panic,
                message: format!("`qcsg check` panicked: {last_lines}"),
                signature: location,
            })
        }
        Some(code) => Err(Problem {
            kind: FailureKind::Crash,
            message: format!("`qcsg check` exited with status {code}: {last_lines}"),
            signature: format!("status {code}"),
        }),
        None => Err(Problem {
            kind: FailureKind::Crash,
            message: format!(
                "`qcsg check` was killed by signal {}: {last_lines}",
                status.signal().unwrap_or(0)
            ),
            signature: format!("signal {}", status.signal().unwrap_or(0)),
        }),
    }
}

/// The `file:line:column` of a panic message (`thread 'main' panicked at FILE:L:C:`).
fn panic_location(stderr: &str) -> String {
    stderr
        .lines()
        .find_map(|line| {
            let at = line.find("panicked at ")?;
            let rest = &line[at + "panicked at ".len()..];
            Some(relative(rest.trim_end_matches(':')))
        })
        .unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn panic_locations_are_read_from_the_message() {
        let stderr = "\nthread 'main' panicked at /home/x/.cargo/registry/src/index-1/miette-7.6.0/src/handlers/graphical.rs:123:45:\nFormatting argument out of range\n";
        assert_eq!(
            panic_location(stderr),
            "registry/src/index-1/miette-7.6.0/src/handlers/graphical.rs:123:45"
        );
    }

    #[test]
    fn exit_statuses_are_classified() {
        use std::process::ExitStatus;
        let code = |c: i32| ExitStatus::from_raw(c << 8);
        assert!(classify(code(0), "", 10, 10).is_ok());
        assert!(classify(code(1), "error[E0101]", 10, 10).is_ok());
        assert_eq!(
            classify(code(2), "error: cannot read", 10, 10)
                .unwrap_err()
                .kind,
            FailureKind::Refused
        );
        assert_eq!(
            classify(
                code(101),
                "thread 'main' panicked at src/a.rs:1:2:\nboom",
                10,
                10
            )
            .unwrap_err()
            .signature,
            "src/a.rs:1:2"
        );
        assert_eq!(
            classify(code(1), "", 1 << 40, 10).unwrap_err().kind,
            FailureKind::Invariant
        );
        assert_eq!(
            classify(
                ExitStatus::from_raw(6),
                "memory allocation of 8 bytes failed",
                0,
                1
            )
            .unwrap_err()
            .kind,
            FailureKind::Memory
        );
    }
}
