//! OpenSCAD 2021.01 as the oracle of meaning: its STL export of a scene, cached by content.
//!
//! The export runs the `openscad` command (or `$OPENSCAD`) with no display. Its result is cached
//! under a folder the caller names, keyed by a hash of the scene's text, of every other file the
//! scene may read, and of the `-D` definitions, so OpenSCAD runs again whenever any of them
//! changes and always on a fresh checkout.
//!
//! A scene that qcsg reads as its input format means it where OpenSCAD misreads that input (a DXF
//! polyline's bulges, which OpenSCAD draws as chords) names, in a line `// reference: PATH`
//! (relative to the scene's folder), a scene that writes the same shape in constructs OpenSCAD
//! reads as meant; OpenSCAD exports that one instead.

use std::collections::hash_map::DefaultHasher;
use std::hash::{Hash, Hasher};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use crate::TriangleMesh;

/// One export: the scene, what it may read besides, and how.
#[derive(Clone, Debug)]
pub struct Export {
    /// The scene file.
    pub scene: PathBuf,
    /// Files the scene may read (`include`, `import`, …): part of the cache key.
    pub inputs: Vec<PathBuf>,
    /// `-D name=value` definitions, as on OpenSCAD's command line.
    pub defines: Vec<(String, String)>,
    /// Where exports are cached.
    pub cache: PathBuf,
    /// How long OpenSCAD may take.
    pub timeout: Duration,
}

/// Why there is no mesh.
#[derive(Clone, Debug)]
pub enum ExportError {
    /// OpenSCAD could not be run at all (not installed).
    Unavailable(String),
    /// OpenSCAD ran and refused or failed (its messages), e.g. a top-level 2-D object.
    Failed(String),
    /// OpenSCAD took longer than the timeout.
    TimedOut,
    /// OpenSCAD wrote a file that is no mesh.
    BadMesh(String),
}

impl std::fmt::Display for ExportError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ExportError::Unavailable(e) => write!(f, "cannot run OpenSCAD 2021.01: {e}"),
            ExportError::Failed(e) => write!(f, "OpenSCAD failed: {e}"),
            ExportError::TimedOut => write!(f, "OpenSCAD took too long"),
            ExportError::BadMesh(e) => write!(f, "OpenSCAD's STL is no mesh: {e}"),
        }
    }
}

impl Export {
    /// The export of `scene` cached under `cache`, with a ten-minute timeout.
    pub fn new(scene: impl Into<PathBuf>, cache: impl Into<PathBuf>) -> Self {
        Self {
            scene: scene.into(),
            inputs: Vec::new(),
            defines: Vec::new(),
            cache: cache.into(),
            timeout: Duration::from_secs(600),
        }
    }

    /// The file OpenSCAD exports: the one the scene's `// reference: PATH` line names, or the
    /// scene itself.
    pub fn source(&self) -> PathBuf {
        std::fs::read_to_string(&self.scene)
            .ok()
            .and_then(|text| {
                text.lines()
                    .find_map(|l| l.trim().strip_prefix("// reference:"))
                    .map(|path| {
                        let dir = self.scene.parent().unwrap_or(Path::new("."));
                        dir.join(path.trim())
                    })
            })
            .unwrap_or_else(|| self.scene.clone())
    }

    /// The key of this export's result.
    fn content_hash(&self) -> u64 {
        let mut hasher = DefaultHasher::new();
        std::fs::read(&self.scene)
            .unwrap_or_default()
            .hash(&mut hasher);
        let source = self.source();
        if source != self.scene {
            std::fs::read(&source).unwrap_or_default().hash(&mut hasher);
        }
        let mut inputs = self.inputs.clone();
        inputs.sort();
        for input in inputs {
            input.hash(&mut hasher);
            std::fs::read(&input).unwrap_or_default().hash(&mut hasher);
        }
        self.defines.hash(&mut hasher);
        hasher.finish()
    }

    /// OpenSCAD's mesh of the scene, from the cache or by running `openscad`.
    pub fn mesh(&self) -> Result<TriangleMesh, ExportError> {
        let stl = self.stl()?;
        TriangleMesh::from_stl(&stl).map_err(ExportError::BadMesh)
    }

    /// OpenSCAD's STL file of the scene, from the cache or by running `openscad`.
    pub fn stl(&self) -> Result<Vec<u8>, ExportError> {
        let unavailable = |e: std::io::Error| ExportError::Unavailable(e.to_string());
        std::fs::create_dir_all(&self.cache).map_err(unavailable)?;
        let stem = self.scene.file_stem().unwrap_or_default().to_string_lossy();
        let key = format!("{stem}-{:016x}", self.content_hash());
        let cached = self.cache.join(format!("{key}.stl"));
        let refused = self.cache.join(format!("{key}.failed"));
        if let Ok(bytes) = std::fs::read(&cached) {
            return Ok(bytes);
        }
        if let Ok(message) = std::fs::read_to_string(&refused) {
            return Err(ExportError::Failed(message));
        }
        let partial = self.cache.join(format!("{key}.partial.stl"));
        let log = self.cache.join(format!("{key}.log"));
        let openscad = std::env::var("OPENSCAD").unwrap_or_else(|_| "openscad".to_owned());
        let mut command = Command::new(&openscad);
        command.arg("-o").arg(&partial);
        for (name, value) in &self.defines {
            command.arg("-D").arg(format!("{name}={value}"));
        }
        let log_file = std::fs::File::create(&log).map_err(unavailable)?;
        let mut child = command
            .arg(self.source())
            .env_remove("DISPLAY")
            // Export needs no display; without this Qt may still look for one.
            .env(
                "QT_QPA_PLATFORM",
                std::env::var("QT_QPA_PLATFORM").unwrap_or_else(|_| "offscreen".to_owned()),
            )
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(log_file)
            .spawn()
            .map_err(|e| ExportError::Unavailable(format!("`{openscad}`: {e}")))?;
        let start = Instant::now();
        let status = loop {
            if let Some(status) = child.try_wait().map_err(unavailable)? {
                break status;
            }
            if start.elapsed() > self.timeout {
                let _ = child.kill();
                let _ = child.wait();
                return Err(ExportError::TimedOut);
            }
            std::thread::sleep(Duration::from_millis(20));
        };
        let messages = std::fs::read_to_string(&log).unwrap_or_default();
        if !status.success() || !partial.exists() {
            // A refusal is as deterministic as a mesh: remember it too.
            let _ = std::fs::write(&refused, &messages);
            return Err(ExportError::Failed(messages));
        }
        std::fs::rename(&partial, &cached).map_err(unavailable)?;
        std::fs::read(&cached).map_err(unavailable)
    }
}

/// How far OpenSCAD's polygons may stray from the exact curved surfaces of a scene whose
/// smallest circle is cut into `fragments` pieces and whose mesh's box has half-diagonal
/// `half_diagonal`: the error of a circle of that radius, `r (1 − cos(π/n))`, with a margin.
pub fn tessellation_tolerance(fragments: f64, half_diagonal: f64) -> f64 {
    2.5 * half_diagonal * (1.0 - (std::f64::consts::PI / fragments).cos()) + 1e-3
}

/// The directory that holds `scene` and every file beside it or below it: what a scene may
/// `include`, `use` or `import` without naming another folder.
pub fn files_beside(scene: &Path) -> Vec<PathBuf> {
    fn walk(dir: &Path, depth: usize, out: &mut Vec<PathBuf>) {
        let Ok(entries) = std::fs::read_dir(dir) else {
            return;
        };
        for entry in entries.flatten() {
            let path = entry.path();
            if path.is_dir() && depth > 0 {
                walk(&path, depth - 1, out);
            } else if path.is_file() {
                out.push(path);
            }
        }
    }
    let mut files = Vec::new();
    if let Some(dir) = scene.parent() {
        walk(dir, 2, &mut files);
    }
    files.retain(|f| f != scene);
    files.sort();
    files
}
