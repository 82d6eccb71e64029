//! Watching the program's files: the main file and everything it includes or uses. Editors
//! often save by writing a new file and renaming it over the old one, which ends a watch on the
//! file itself, so the watcher watches each file's directory and picks out the files' events.
//! Bursts of events (one save is several) are gathered by the caller's debounce.

use std::collections::HashSet;
use std::path::PathBuf;
use std::sync::{Arc, Mutex, PoisonError};

use notify::{EventKind, RecommendedWatcher, RecursiveMode, Watcher};
use tokio::sync::mpsc::UnboundedSender;

/// A watcher over a set of files that may change with every rebuild.
pub struct FileWatch {
    watcher: RecommendedWatcher,
    directories: HashSet<PathBuf>,
    files: Arc<Mutex<HashSet<PathBuf>>>,
}

impl FileWatch {
    /// A watcher that sends `()` on `changed` whenever a followed file changes.
    pub fn new(changed: UnboundedSender<()>) -> notify::Result<Self> {
        let files: Arc<Mutex<HashSet<PathBuf>>> = Arc::default();
        let followed = Arc::clone(&files);
        let watcher = notify::recommended_watcher(move |event: notify::Result<notify::Event>| {
            let Ok(event) = event else {
                // An overflowed queue may have lost a change: rebuild to be sure.
                let _ = changed.send(());
                return;
            };
            if matches!(event.kind, EventKind::Access(_)) {
                return;
            }
            let files = followed.lock().unwrap_or_else(PoisonError::into_inner);
            if event.paths.iter().any(|path| files.contains(path)) {
                let _ = changed.send(());
            }
        })?;
        Ok(Self {
            watcher,
            directories: HashSet::new(),
            files,
        })
    }

    /// Follows exactly `files` from now on (directories already watched stay watched).
    pub fn follow(&mut self, files: &[PathBuf]) {
        for file in files {
            if let Some(directory) = file.parent()
                && !self.directories.contains(directory)
                && self
                    .watcher
                    .watch(directory, RecursiveMode::NonRecursive)
                    .is_ok()
            {
                self.directories.insert(directory.to_path_buf());
            }
        }
        *self.files.lock().unwrap_or_else(PoisonError::into_inner) =
            files.iter().cloned().collect();
    }
}
