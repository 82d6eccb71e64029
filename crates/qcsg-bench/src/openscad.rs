//! The mesh-based peer: OpenSCAD's CGAL export to STL and its preview PNG (under a virtual X
//! display), run with a time limit. OpenSCAD is
//! optional: [`find`] says whether it is installed, and callers report "not installed".

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// The `openscad` executable on `PATH` (or `QCSG_OPENSCAD`), with its version line; `None` when
/// it is not installed or does not run.
pub fn find() -> Option<(PathBuf, String)> {
    let program = std::env::var_os("QCSG_OPENSCAD")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("openscad"));
    let output = Command::new(&program)
        .arg("--version")
        .stdin(Stdio::null())
        .output()
        .ok()?;
    // OpenSCAD prints its version on standard error.
    let text = String::from_utf8_lossy(&output.stderr).to_string()
        + &String::from_utf8_lossy(&output.stdout);
    let version = text
        .lines()
        .find(|l| l.contains("OpenSCAD"))?
        .trim()
        .to_owned();
    Some((program, version))
}

/// What one export gave.
#[derive(Debug)]
pub enum Export {
    /// The STL file's bytes and the wall time of the export.
    Done(Vec<u8>, Duration),
    /// The export ran past the time limit and was stopped.
    TimedOut(Duration),
    /// OpenSCAD failed; its last lines of output.
    Failed(String),
}

/// Exports `scene` to STL with `$fn = fn_value`, stopping it after `limit`.
pub fn export_stl(
    program: &Path,
    scene: &Path,
    fn_value: u32,
    work_dir: &Path,
    limit: Duration,
) -> Export {
    let out = work_dir.join(format!(
        "{}-fn{fn_value}.stl",
        scene
            .file_stem()
            .map_or_else(String::new, |s| s.to_string_lossy().into_owned())
    ));
    let mut command = Command::new(program);
    command
        .arg("-o")
        .arg(&out)
        .arg("-D")
        .arg(format!("$fn={fn_value}"))
        .arg(scene);
    run_limited(command, &out, limit)
}

/// A virtual X display (`Xvfb`) for OpenSCAD's preview images, stopped when dropped.
#[derive(Debug)]
pub struct Display {
    child: Child,
    /// The `DISPLAY` value.
    pub name: String,
}

impl Display {
    /// Starts `Xvfb` on a free display number with a 1920×1080 screen; `Err` when Xvfb is not
    /// installed (`apt-get install xvfb`).
    pub fn start() -> Result<Self, String> {
        let number = 90 + std::process::id() % 400;
        let name = format!(":{number}");
        let child = Command::new("Xvfb")
            .arg(&name)
            .args(["-screen", "0", "1920x1080x24", "-nolisten", "tcp"])
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .map_err(|e| {
                format!("Xvfb does not start ({e}); install it with apt-get install xvfb")
            })?;
        // Xvfb takes a moment to accept clients.
        std::thread::sleep(Duration::from_millis(500));
        Ok(Self { child, name })
    }
}

impl Drop for Display {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// OpenSCAD's preview (OpenCSG, not CGAL) of `scene` with `$fn = fn_value` as a PNG of
/// `width`×`height` on `display`, stopped after `limit`.
pub fn preview_png(
    program: &Path,
    scene: &Path,
    fn_value: u32,
    (width, height): (u32, u32),
    display: &Display,
    work_dir: &Path,
    limit: Duration,
) -> Export {
    let out = work_dir.join(format!(
        "{}-fn{fn_value}.png",
        scene
            .file_stem()
            .map_or_else(String::new, |s| s.to_string_lossy().into_owned())
    ));
    let mut command = Command::new(program);
    command
        .env("DISPLAY", &display.name)
        .arg("-o")
        .arg(&out)
        .arg(format!("--imgsize={width},{height}"))
        .arg("-D")
        .arg(format!("$fn={fn_value}"))
        .arg(scene);
    run_limited(command, &out, limit)
}

/// Runs `command`, stopping it after `limit`; its product is the file `out`.
fn run_limited(mut command: Command, out: &Path, limit: Duration) -> Export {
    let start = Instant::now();
    let child = command
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn();
    let mut child = match child {
        Ok(c) => c,
        Err(err) => return Export::Failed(err.to_string()),
    };
    loop {
        match child.try_wait() {
            Ok(Some(status)) => {
                let elapsed = start.elapsed();
                let mut log = String::new();
                if let Some(mut stderr) = child.stderr.take() {
                    use std::io::Read;
                    let _ = stderr.read_to_string(&mut log);
                }
                if !status.success() {
                    let tail: Vec<&str> = log.lines().rev().take(3).collect();
                    return Export::Failed(tail.into_iter().rev().collect::<Vec<_>>().join(" / "));
                }
                return match std::fs::read(out) {
                    Ok(bytes) => Export::Done(bytes, elapsed),
                    Err(err) => Export::Failed(format!("no file written: {err}")),
                };
            }
            Ok(None) if start.elapsed() > limit => {
                let _ = child.kill();
                let _ = child.wait();
                return Export::TimedOut(start.elapsed());
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(20)),
            Err(err) => return Export::Failed(err.to_string()),
        }
    }
}
