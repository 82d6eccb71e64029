//! End-to-end tests of `qcsg render`: a PNG on success, exit codes, no file after a failure,
//! standard input and output, and the refusal of the not-yet-available splat renderer.

use std::io::Write;
use std::path::PathBuf;
use std::process::{Command, Stdio};

const SCENE: &str =
    "difference() { cube(2, center = true); #sphere(1.3); }\n%translate([3, 0, 0]) sphere(1);\n";

struct Run {
    status: i32,
    stdout: Vec<u8>,
    stderr: String,
}

fn qcsg(args: &[&str], stdin: &str) -> Run {
    let mut child = Command::new(env!("CARGO_BIN_EXE_qcsg"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("qcsg runs");
    // A run refused before reading its input closes the pipe early: that is not a failure.
    let _ = child
        .stdin
        .take()
        .expect("stdin")
        .write_all(stdin.as_bytes());
    let output = child.wait_with_output().expect("qcsg finishes");
    Run {
        status: output.status.code().unwrap_or(-1),
        stdout: output.stdout,
        stderr: String::from_utf8_lossy(&output.stderr).into_owned(),
    }
}

fn scratch_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("qcsg-render-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch dir");
    dir
}

#[test]
fn renders_a_png_and_says_how() {
    let dir = scratch_dir("ok");
    let out = dir.join("out.png");
    let run = qcsg(
        &[
            "render",
            "-",
            "-o",
            out.to_str().unwrap(),
            "--size",
            "40,30",
        ],
        SCENE,
    );
    assert_eq!(run.status, 0, "{}", run.stderr);
    let png = std::fs::read(&out).expect("the PNG");
    assert!(png.starts_with(b"\x89PNG"));
    assert!(run.stderr.contains("CPU ray tracer"), "{}", run.stderr);
    // Quiet runs say nothing; the image does not depend on the thread count.
    let again = dir.join("again.png");
    let quiet = qcsg(
        &[
            "render",
            "-",
            "-o",
            again.to_str().unwrap(),
            "--size",
            "40,30",
            "-q",
            "--threads",
            "1",
        ],
        SCENE,
    );
    assert_eq!(quiet.status, 0);
    assert!(quiet.stderr.is_empty(), "{}", quiet.stderr);
    assert_eq!(std::fs::read(&again).unwrap(), png);
    // Standard output.
    let piped = qcsg(
        &[
            "render", "-", "-o", "-", "--size", "40,30", "--camera", "front",
        ],
        SCENE,
    );
    assert_eq!(piped.status, 0, "{}", piped.stderr);
    assert!(piped.stdout.starts_with(b"\x89PNG"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_splat_renderer_is_refused_until_it_exists() {
    let dir = scratch_dir("splat");
    let out = dir.join("out.png");
    for flags in [["--renderer", "splat"], ["--device", "gpu"]] {
        let mut args = vec!["render", "-", "-o", out.to_str().unwrap()];
        args.extend(flags);
        let run = qcsg(&args, SCENE);
        assert_eq!(run.status, 2);
        assert!(run.stderr.contains("not available yet"), "{}", run.stderr);
        assert!(!out.exists());
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn failures_leave_no_file() {
    let dir = scratch_dir("fail");
    let out = dir.join("out.png");
    let path = out.to_str().unwrap();
    let errors = qcsg(&["render", "-", "-o", path], "cube(;\n");
    assert_eq!(errors.status, 1);
    for bad in [
        vec!["render", "-", "-o", path, "--size", "0,10"],
        vec!["render", "-", "-o", path, "--camera", "1,1,1,1,1,1"],
        vec!["render", "-", "-o", path, "--camera", "sideways"],
        vec!["render", "no-such-file.qcsg", "-o", path],
    ] {
        let run = qcsg(&bad, SCENE);
        assert_eq!(run.status, 2, "{bad:?}: {}", run.stderr);
    }
    assert!(!out.exists());
    let unwritable = dir.join("missing-dir").join("out.png");
    let run = qcsg(
        &[
            "render",
            "-",
            "-o",
            unwritable.to_str().unwrap(),
            "--size",
            "8,6",
        ],
        SCENE,
    );
    assert_eq!(run.status, 2, "{}", run.stderr);
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
    let _ = std::fs::remove_dir_all(&dir);
}
