//! Hostile input through the real binary: diagnostics far along a line, floods of diagnostics on
//! one line, devices, directories, pipes and oversized files named as sources, and bytes that are
//! not UTF-8. Each run must end quickly with a clear message and exit status, never panic (exit
//! 101), hang or read without bound. The time bounds are generous (the inputs are sized so that
//! the quadratic or unbounded behaviour these tests guard against would take minutes).

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Duration;

use qcsg_testkit::cli::{Invocation, Run};

/// The longest any run here may take.
const DEADLINE: Duration = Duration::from_secs(20);

/// A fresh directory for one test's files, removed when the test ends.
struct Scratch(PathBuf);

impl Scratch {
    fn new(test: &str) -> Self {
        let dir = std::env::temp_dir().join(format!("qcsg-hostile-{}-{test}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("a scratch directory");
        Scratch(dir)
    }
}

impl std::ops::Deref for Scratch {
    type Target = Path;

    fn deref(&self) -> &Path {
        &self.0
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn write(dir: &Path, name: &str, bytes: impl AsRef<[u8]>) {
    std::fs::write(dir.join(name), bytes).expect("a scratch file");
}

/// Runs `qcsg args…` in `dir` with `stdin` as standard input, killing it past [`DEADLINE`].
fn qcsg_in(dir: &Path, args: &[&str], stdin: Stdio) -> Run {
    Invocation::new(env!("CARGO_BIN_EXE_qcsg"))
        .args(args)
        .current_dir(dir)
        .stdin_from(stdin)
        .deadline(DEADLINE)
        .run()
}

fn qcsg(dir: &Path, args: &[&str]) -> Run {
    qcsg_in(dir, args, Stdio::null())
}

fn json(run: &Run) -> Vec<serde_json::Value> {
    serde_json::from_str(run.stdout_text())
        .unwrap_or_else(|e| panic!("stdout is not a JSON array ({e}):\n{}", run.stdout_text()))
}

/// The human output of a run never has a line that miette could not have drawn short.
fn assert_lines_short(run: &Run) {
    let longest = run.stderr.lines().map(|l| l.chars().count()).max();
    assert!(
        longest.unwrap_or(0) < 400,
        "a line of {longest:?} characters"
    );
}

#[test]
fn a_diagnostic_past_column_65535_is_drawn_every_way() {
    let dir = Scratch::new("column");
    write(&dir, "error.qcsg", format!("{})", " ".repeat(65_536)));
    write(
        &dir,
        "warning.qcsg",
        format!("{}x = 1;\n", " ".repeat(65_536)),
    );
    for command in [
        &["check", "error.qcsg"][..],
        &["compile", "--emit", "dnf", "error.qcsg"],
        &["render", "error.qcsg", "-o", "error.png"],
    ] {
        let run = qcsg(&dir, command);
        assert_eq!(run.status, 1, "{command:?}: {}", run.stderr);
        assert!(
            run.stderr.contains("error[E0009]") && run.stderr.contains("error.qcsg:1:65537"),
            "{}",
            run.stderr
        );
        assert_lines_short(&run);
    }
    for command in [
        &["check", "warning.qcsg"][..],
        &["compile", "--emit", "dnf", "warning.qcsg"],
        &["render", "warning.qcsg", "-o", "warning.png"],
    ] {
        let run = qcsg(&dir, command);
        assert_eq!(run.status, 0, "{command:?}: {}", run.stderr);
        assert!(
            run.stderr.contains("warning[W0101]") && run.stderr.contains("warning.qcsg:1:65537"),
            "{}",
            run.stderr
        );
        // The excerpt is cut to the end of the line, where the marker is.
        assert!(run.stderr.contains("│ …"), "{}", run.stderr);
        assert_lines_short(&run);
    }
}

#[test]
fn a_flood_of_errors_on_one_line_prints_a_page_and_the_count() {
    let dir = Scratch::new("flood");
    let count = 50_000;
    write(&dir, "flood.qcsg", "@([0,0,0])".repeat(count));
    let run = qcsg(&dir, &["check", "flood.qcsg"]);
    assert_eq!(run.status, 1);
    assert_eq!(run.stderr.matches("error[E0001]").count(), 50);
    assert!(
        run.stderr.ends_with(
            "… 49950 more errors not shown (--format json lists them all)\n\
             50000 errors, 0 warnings\n"
        ),
        "{}",
        &run.stderr[run.stderr.len().saturating_sub(500)..]
    );
    assert!(run.stderr.len() < 100_000, "{} bytes", run.stderr.len());
    assert_lines_short(&run);

    // JSON lists every one, with its UTF-16 column on the one line.
    let run = qcsg(&dir, &["check", "--format", "json", "flood.qcsg"]);
    let elements = json(&run);
    assert_eq!(elements.len(), count);
    let last = &elements[count - 1]["range"]["start"];
    assert_eq!(
        (last["line"].as_u64(), last["character"].as_u64()),
        (Some(0), Some(499_990))
    );
}

#[test]
fn nested_comment_openers_show_their_error_first() {
    let dir = Scratch::new("comments");
    write(
        &dir,
        "comments.qcsg",
        "/*".repeat(100_000) + &"*/".repeat(100_000),
    );
    let run = qcsg(&dir, &["check", "comments.qcsg"]);
    assert_eq!(run.status, 1);
    // One file shows at most 50 diagnostics, errors before warnings, in source order.
    assert_eq!(run.stderr.matches("error[E").count(), 1, "{}", run.stderr);
    assert_eq!(run.stderr.matches("warning[W0107]").count(), 49);
    assert!(
        run.stderr.ends_with(
            "… 975 more warnings not shown (--format json lists them all)\n\
             1 error, 1024 warnings\n"
        ),
        "{}",
        &run.stderr[run.stderr.len().saturating_sub(500)..]
    );
    assert_lines_short(&run);
}

#[cfg(unix)]
#[test]
fn devices_and_directories_named_as_sources_are_refused_unread() {
    let dir = Scratch::new("devices");
    std::fs::create_dir(dir.join("parts")).expect("a directory");
    write(
        &dir,
        "scene.qcsg",
        "include </dev/zero>\nuse </dev/urandom>\ninclude <parts>\ncube(1);\n",
    );
    let run = qcsg(&dir, &["check", "--format", "json", "scene.qcsg"]);
    assert_eq!(run.status, 1, "{}", run.stderr);
    let found: Vec<(String, String)> = json(&run)
        .iter()
        .map(|d| (d["code"].to_string(), d["message"].to_string()))
        .collect();
    assert_eq!(
        found,
        [
            (
                "\"E0403\"".to_owned(),
                "\"cannot read `/dev/zero` named by `include`: it is a character device, not a \
                 regular file\""
                    .to_owned()
            ),
            (
                "\"E0403\"".to_owned(),
                "\"cannot read `/dev/urandom` named by `use`: it is a character device, not a \
                 regular file\""
                    .to_owned()
            ),
            (
                "\"E0403\"".to_owned(),
                "\"cannot read `parts` named by `include`: it is a directory, not a regular \
                 file\""
                    .to_owned()
            ),
        ]
    );

    let run = qcsg(&dir, &["check", "/dev/zero"]);
    assert_eq!(run.status, 2);
    assert!(
        run.stderr.starts_with(
            "error: cannot read `/dev/zero`: it is a character device, not a regular file\n"
        ),
        "{}",
        run.stderr
    );
    let run = qcsg(&dir, &["fmt", "/dev/zero"]);
    assert_eq!(run.status, 2, "{}", run.stderr);

    // Standard input has no size to ask for: the read stops at the limit.
    let zero = std::fs::File::open("/dev/zero").expect("/dev/zero opens");
    let run = qcsg_in(&dir, &["check", "-"], Stdio::from(zero));
    assert_eq!(run.status, 2);
    assert!(
        run.stderr.starts_with(
            "error: cannot read standard input: it is over the 64 MiB limit on source files\n"
        ),
        "{}",
        run.stderr
    );
}

#[cfg(unix)]
#[test]
fn a_named_pipe_is_refused_without_waiting_for_a_writer() {
    let dir = Scratch::new("fifo");
    let made = Command::new("mkfifo")
        .arg(dir.join("pipe.qcsg"))
        .status()
        .expect("mkfifo runs");
    assert!(made.success());
    write(&dir, "scene.qcsg", "include <pipe.qcsg>\n");
    let run = qcsg(&dir, &["check", "scene.qcsg"]);
    assert_eq!(run.status, 1, "{}", run.stderr);
    assert!(
        run.stderr.contains("error[E0403]") && run.stderr.contains("it is a named pipe"),
        "{}",
        run.stderr
    );
}

#[test]
fn a_source_over_the_size_limit_is_refused_by_its_size() {
    let dir = Scratch::new("large");
    // Sparse: its size is 65 MiB, but it occupies no disk.
    let file = std::fs::File::create(dir.join("huge.qcsg")).expect("a scratch file");
    file.set_len(65 << 20).expect("a sparse file");
    write(&dir, "scene.qcsg", "include <huge.qcsg>\ncube(1);\n");
    let run = qcsg(&dir, &["check", "--format", "json", "scene.qcsg"]);
    assert_eq!(run.status, 1, "{}", run.stderr);
    let elements = json(&run);
    assert_eq!(elements[0]["code"], "E0404");
    assert_eq!(
        elements[0]["message"],
        "cannot read `huge.qcsg` named by `include`: it is 65 MiB (68157440 bytes), over the \
         64 MiB limit on source files"
    );
    let run = qcsg(&dir, &["check", "huge.qcsg"]);
    assert_eq!(run.status, 2);
    assert!(
        run.stderr.contains("over the 64 MiB limit"),
        "{}",
        run.stderr
    );
}

#[test]
fn invalid_utf8_is_an_error_at_the_byte_and_the_rest_is_checked() {
    let dir = Scratch::new("utf8");
    let latin1 = b"x = 1;\ns = \"caf\xE9\";\necho(x, s, y);\n// \xFF\xFE\n";
    write(&dir, "latin1.qcsg", latin1);
    write(&dir, "scene.qcsg", "include <latin1.qcsg>\n");

    let run = qcsg(&dir, &["check", "latin1.qcsg"]);
    assert_eq!(run.status, 1, "{}", run.stderr);
    assert!(
        run.stderr.starts_with(
            "error[E0406]\n\n  × not valid UTF-8: byte 0xE9; 2 more invalid sequences follow\n   \
             ╭─[latin1.qcsg:2:9]"
        ),
        "{}",
        run.stderr
    );
    // The rest of the file is checked: `y` is undefined.
    assert!(run.stderr.contains("error[E0101]"), "{}", run.stderr);
    assert!(
        run.stderr.ends_with("2 errors, 0 warnings\n"),
        "{}",
        run.stderr
    );

    // Through an include, the error is in the included file.
    let run = qcsg(&dir, &["check", "--format", "json", "scene.qcsg"]);
    let elements = json(&run);
    assert_eq!(elements[0]["code"], "E0406");
    assert_eq!(elements[0]["file"], "latin1.qcsg");
    assert_eq!(elements[0]["byte_range"], serde_json::json!([15, 18]));

    // Standard input too.
    let run = Invocation::new(env!("CARGO_BIN_EXE_qcsg"))
        .args(["check", "-q", "-"])
        .current_dir(&*dir)
        .stdin(&latin1[..])
        .deadline(DEADLINE)
        .run();
    assert_eq!(run.status, 1);
    assert!(run.stderr.contains("<stdin>:2:9"), "{}", run.stderr);

    // Formatting would write the replacement characters over the bytes: the file is left alone.
    let run = qcsg(&dir, &["fmt", "latin1.qcsg"]);
    assert_eq!(run.status, 1);
    assert_eq!(
        run.stderr,
        "error: latin1.qcsg:2: not valid UTF-8; the file is left as it is\n"
    );
    assert_eq!(
        std::fs::read(dir.join("latin1.qcsg")).expect("readable"),
        latin1
    );
}
