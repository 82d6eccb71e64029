//! Running a command-line binary the way end-to-end tests do: arguments, a working directory,
//! standard input from bytes or any [`Stdio`], both output pipes captured, an optional deadline
//! and an optional cap on the address space.
//!
//! The environment variables that change what `qcsg` prints (`QCSG_PATH`, `COLUMNS`) are
//! removed unless a test sets them, so that a developer's shell cannot change a test's result.

use std::ffi::OsStr;
use std::io::{Read, Write};
use std::path::Path;
use std::process::{Child, Command, ExitStatus, Stdio};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// What a run of the binary produced.
#[derive(Clone, Debug)]
pub struct Run {
    /// The exit status; `-1` when a signal ended the run.
    pub status: i32,
    /// Standard output, as written.
    pub stdout: Vec<u8>,
    /// Standard error, which every command writes as UTF-8 text.
    pub stderr: String,
    /// From the start to the end of the run.
    pub took: Duration,
}

impl Run {
    /// Standard output as text; panics (naming the test's failure) when it is not UTF-8.
    pub fn stdout_text(&self) -> &str {
        std::str::from_utf8(&self.stdout).expect("standard output is UTF-8")
    }
}

/// Where standard input comes from.
enum Input {
    Bytes(Vec<u8>),
    Stdio(Stdio),
}

/// One run of a binary, configured and then started by [`Invocation::run`].
pub struct Invocation {
    command: Command,
    /// The program and arguments, for messages.
    shown: Vec<String>,
    input: Input,
    deadline: Option<Duration>,
}

impl Invocation {
    /// A run of `program` (for a test of this workspace's binary, `env!("CARGO_BIN_EXE_qcsg")`)
    /// with empty standard input.
    pub fn new(program: impl AsRef<OsStr>) -> Self {
        let mut command = Command::new(&program);
        command.env_remove("QCSG_PATH").env_remove("COLUMNS");
        Self {
            command,
            shown: vec![program.as_ref().to_string_lossy().into_owned()],
            input: Input::Bytes(Vec::new()),
            deadline: None,
        }
    }

    /// The same program run under `sh` with its address space capped at `kib` KiB
    /// (`ulimit -v`): a run that starts filling memory fails instead of exhausting the machine.
    #[cfg(unix)]
    pub fn with_address_space(program: impl AsRef<OsStr>, kib: u64) -> Self {
        let mut invocation = Self::new("sh");
        invocation.command.arg("-c");
        invocation
            .command
            .arg(format!("ulimit -v {kib} && exec \"$0\" \"$@\""));
        invocation.command.arg(&program);
        invocation.shown = vec![program.as_ref().to_string_lossy().into_owned()];
        invocation
    }

    /// Appends one argument.
    pub fn arg(mut self, arg: impl AsRef<OsStr>) -> Self {
        self.shown.push(arg.as_ref().to_string_lossy().into_owned());
        self.command.arg(arg);
        self
    }

    /// Appends arguments.
    pub fn args<I, S>(mut self, args: I) -> Self
    where
        I: IntoIterator<Item = S>,
        S: AsRef<OsStr>,
    {
        for arg in args {
            self = self.arg(arg);
        }
        self
    }

    /// Runs in `dir` instead of the test's working directory.
    pub fn current_dir(mut self, dir: impl AsRef<Path>) -> Self {
        self.command.current_dir(dir);
        self
    }

    /// Sets an environment variable for the run.
    pub fn env(mut self, key: impl AsRef<OsStr>, value: impl AsRef<OsStr>) -> Self {
        self.command.env(key, value);
        self
    }

    /// Standard input from these bytes. A run that exits without reading them all closes the
    /// pipe early; that is not a failure of the run.
    pub fn stdin(mut self, bytes: impl Into<Vec<u8>>) -> Self {
        self.input = Input::Bytes(bytes.into());
        self
    }

    /// Standard input from a file, a device or nothing ([`Stdio::null`]).
    pub fn stdin_from(mut self, stdio: Stdio) -> Self {
        self.input = Input::Stdio(stdio);
        self
    }

    /// Kills the run and panics once it has taken longer than `deadline`.
    pub fn deadline(mut self, deadline: Duration) -> Self {
        self.deadline = Some(deadline);
        self
    }

    /// Starts the binary and waits for it. Both pipes are drained on their own threads, so
    /// that a large output cannot stall the child while its input is written.
    pub fn run(mut self) -> Run {
        let (stdin, bytes) = match self.input {
            Input::Bytes(bytes) => (Stdio::piped(), Some(bytes)),
            Input::Stdio(stdio) => (stdio, None),
        };
        let started = Instant::now();
        let mut child = self
            .command
            .stdin(stdin)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap_or_else(|e| panic!("`{}` does not start: {e}", self.shown[0]));
        let writer = bytes.map(|bytes| {
            let mut pipe = child.stdin.take().expect("piped standard input");
            std::thread::spawn(move || {
                let _ = pipe.write_all(&bytes);
            })
        });
        let stdout = drain(child.stdout.take().expect("piped standard output"));
        let stderr = drain(child.stderr.take().expect("piped standard error"));
        let status = wait(&mut child, started, self.deadline, &self.shown);
        if let Some(writer) = writer {
            writer.join().expect("the input writer ends");
        }
        let stderr = stderr.join().expect("the error reader ends");
        Run {
            status: status.code().unwrap_or(-1),
            stdout: stdout.join().expect("the output reader ends"),
            stderr: String::from_utf8(stderr).expect("standard error is UTF-8"),
            took: started.elapsed(),
        }
    }
}

/// Reads a pipe to its end on a thread.
fn drain(mut pipe: impl Read + Send + 'static) -> JoinHandle<Vec<u8>> {
    std::thread::spawn(move || {
        let mut bytes = Vec::new();
        pipe.read_to_end(&mut bytes)
            .expect("a pipe of the child reads");
        bytes
    })
}

/// Waits for `child`, killing it and panicking past `deadline`.
fn wait(
    child: &mut Child,
    started: Instant,
    deadline: Option<Duration>,
    shown: &[String],
) -> ExitStatus {
    let Some(deadline) = deadline else {
        return child.wait().expect("the child can be waited for");
    };
    loop {
        if let Some(status) = child.try_wait().expect("the child can be waited for") {
            return status;
        }
        if started.elapsed() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            panic!("`{}` ran past {deadline:?}", shown.join(" "));
        }
        std::thread::sleep(Duration::from_millis(10));
    }
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;

    #[test]
    fn input_reaches_the_child_and_both_outputs_come_back() {
        let run = Invocation::new("sh")
            .args(["-c", "cat; echo oops >&2; exit 3"])
            .stdin("hello\n")
            .run();
        assert_eq!(run.status, 3);
        assert_eq!(run.stdout_text(), "hello\n");
        assert_eq!(run.stderr, "oops\n");
    }

    #[test]
    fn output_larger_than_a_pipe_does_not_stall_the_run() {
        let input = vec![b'x'; 1 << 20];
        let run = Invocation::new("sh")
            .args(["-c", "cat; cat >&2 </dev/null"])
            .stdin(input.clone())
            .deadline(Duration::from_secs(20))
            .run();
        assert_eq!(run.status, 0);
        assert_eq!(run.stdout, input);
    }

    #[test]
    fn an_unread_input_is_no_failure() {
        let run = Invocation::new("sh")
            .args(["-c", "exit 0"])
            .stdin(vec![0u8; 1 << 20])
            .run();
        assert_eq!(run.status, 0);
    }

    #[test]
    #[should_panic(expected = "ran past")]
    fn a_run_past_its_deadline_is_killed() {
        Invocation::new("sh")
            .args(["-c", "sleep 30"])
            .deadline(Duration::from_millis(200))
            .run();
    }

    #[test]
    fn the_address_space_is_capped() {
        let run = Invocation::with_address_space("sh", 1 << 20)
            .args(["-c", "ulimit -v"])
            .run();
        assert_eq!(run.stdout_text().trim(), (1u64 << 20).to_string());
    }
}
