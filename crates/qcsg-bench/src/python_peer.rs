//! The Python peers, Manifold and build123d (OpenCascade), run as subprocesses of
//! `crates/qcsg-bench/peers/peer.py` in the pinned environment that
//! `crates/qcsg-bench/peers/setup.sh` makes under `target/qcsg-bench-peers/venv`. A peer that
//! is not installed is reported as such ([`find`]); the report then says "not measured".
//!
//! One process runs one scene's whole sweep; `peer.py` writes one JSON line per finished
//! setting, so a process stopped at the time limit keeps what it finished and the setting in
//! progress is the one that timed out.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use crate::mesh::{Mesh, parse_stl};
use crate::shape::Shape;

/// Which Python peer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Peer {
    /// `manifold3d`: settings are circular segment counts.
    Manifold,
    /// `build123d`: settings are linear tessellation tolerances in world units.
    Build123d,
}

impl Peer {
    /// The name `peer.py` takes and the module it imports.
    pub fn name(self) -> &'static str {
        match self {
            Peer::Manifold => "manifold",
            Peer::Build123d => "build123d",
        }
    }

    fn module(self) -> &'static str {
        match self {
            Peer::Manifold => "manifold3d",
            Peer::Build123d => "build123d",
        }
    }
}

/// An installed peer: the interpreter, the script and the package's version.
#[derive(Clone, Debug)]
pub struct Installed {
    /// Which peer.
    pub peer: Peer,
    /// The Python interpreter of the environment.
    pub python: PathBuf,
    /// `peer.py`.
    pub script: PathBuf,
    /// `module version`, as the package reports it.
    pub version: String,
}

/// The interpreter of the peers' environment: `QCSG_PEERS_PYTHON`, else
/// `target/qcsg-bench-peers/venv/bin/python` under `root`.
pub fn python(root: &Path) -> PathBuf {
    std::env::var_os("QCSG_PEERS_PYTHON").map_or_else(
        || root.join("target/qcsg-bench-peers/venv/bin/python"),
        PathBuf::from,
    )
}

/// The peer, when its package imports in the environment; else why not.
pub fn find(root: &Path, peer: Peer) -> Result<Installed, String> {
    let python = python(root);
    let script = root.join("crates/qcsg-bench/peers/peer.py");
    let probe = format!(
        "import importlib.metadata as m; print(m.version('{}'))",
        peer.module()
    );
    let output = Command::new(&python)
        .args(["-c", &probe])
        .stdin(Stdio::null())
        .output()
        .map_err(|e| format!("no Python environment at {}: {e}", python.display()))?;
    if !output.status.success() {
        return Err(format!(
            "{} is not installed in {}",
            peer.module(),
            python.display()
        ));
    }
    let version = String::from_utf8_lossy(&output.stdout).trim().to_owned();
    Ok(Installed {
        peer,
        python,
        script,
        version: format!("{} {version}", peer.module()),
    })
}

/// One setting's result.
#[derive(Clone, Debug)]
pub struct PeerResult {
    /// The setting (segment count or tolerance); `None` for build123d's exact boolean.
    pub setting: Option<f64>,
    /// Wall time of the peer's own work for this setting, measured in the script.
    pub time: Duration,
    /// CPU time of the same work (all the interpreter's threads), where the script reports it.
    pub cpu: Option<Duration>,
    /// Whether the peer finds its result valid (Manifold's status, OpenCascade's check).
    pub valid: bool,
    /// The mesh, when the setting made one.
    pub mesh: Option<Mesh>,
}

/// A whole run: the settings finished, and how it ended.
#[derive(Clone, Debug)]
pub struct PeerRun {
    /// Finished settings, in order.
    pub results: Vec<PeerResult>,
    /// Wall time of the process, from start to exit (interpreter, imports, every setting).
    pub process: Duration,
    /// `None` when every setting finished; else "timed out" or the error.
    pub failure: Option<String>,
}

/// Runs `shape` through the peer for every setting, stopping the process after `limit`.
pub fn run(
    installed: &Installed,
    shape: &Shape,
    settings: &[f64],
    work: &Path,
    limit: Duration,
) -> PeerRun {
    let failed = |why: String| PeerRun {
        results: Vec::new(),
        process: Duration::ZERO,
        failure: Some(why),
    };
    let _ = std::fs::remove_dir_all(work);
    if let Err(e) = std::fs::create_dir_all(work) {
        return failed(format!("cannot create {}: {e}", work.display()));
    }
    let settings: Vec<String> = settings.iter().map(|s| format!("{s:?}")).collect();
    let job = format!(
        r#"{{"shape":{},"settings":[{}]}}"#,
        shape.to_json(),
        settings.join(",")
    );
    let job_path = work.join("job.json");
    if let Err(e) = std::fs::write(&job_path, job) {
        return failed(format!("cannot write {}: {e}", job_path.display()));
    }
    let start = Instant::now();
    let child = Command::new(&installed.python)
        .arg(&installed.script)
        .arg(installed.peer.name())
        .arg(&job_path)
        .arg(work)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn();
    let mut child = match child {
        Ok(c) => c,
        Err(e) => return failed(e.to_string()),
    };
    let mut failure = None;
    loop {
        match child.try_wait() {
            Ok(Some(status)) => {
                if !status.success() {
                    let mut log = String::new();
                    if let Some(mut stderr) = child.stderr.take() {
                        use std::io::Read;
                        let _ = stderr.read_to_string(&mut log);
                    }
                    let last = log.lines().last().unwrap_or("no output").to_owned();
                    failure = Some(last);
                }
                break;
            }
            Ok(None) if start.elapsed() > limit => {
                let _ = child.kill();
                let _ = child.wait();
                failure = Some("timed out".into());
                break;
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(10)),
            Err(e) => {
                failure = Some(e.to_string());
                break;
            }
        }
    }
    let process = start.elapsed();
    let text = std::fs::read_to_string(work.join("results.jsonl")).unwrap_or_default();
    let mut results = Vec::new();
    for line in text.lines() {
        let Ok(v) = serde_json::from_str::<serde_json::Value>(line) else {
            continue;
        };
        if let Some(e) = v.get("error").and_then(|e| e.as_str()) {
            failure = Some(e.to_owned());
            continue;
        }
        let mesh = v
            .get("stl")
            .and_then(|p| p.as_str())
            .and_then(|p| std::fs::read(p).ok())
            .and_then(|bytes| parse_stl(&bytes).ok());
        results.push(PeerResult {
            setting: v.get("setting").and_then(serde_json::Value::as_f64),
            time: Duration::from_secs_f64(
                v.get("build_s")
                    .and_then(serde_json::Value::as_f64)
                    .unwrap_or(0.0),
            ),
            cpu: v
                .get("cpu_s")
                .and_then(serde_json::Value::as_f64)
                .map(Duration::from_secs_f64),
            valid: v
                .get("valid")
                .and_then(serde_json::Value::as_bool)
                .unwrap_or(false),
            mesh,
        });
    }
    PeerRun {
        results,
        process,
        failure,
    }
}
