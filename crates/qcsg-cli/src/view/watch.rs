//! Watching the program's files: the main file and everything it includes or uses. Editors
//! often save by writing a new file and renaming it over the old one, which ends a watch on the
//! file itself, so the watcher watches each file's directory and picks out the files' events.
//! One save is several events; the last of them, a file closed after writing or renamed into
//! place, says the save is whole, so that the caller can rebuild at once instead of waiting out
//! a fixed delay ([`Change`]).

use std::collections::HashSet;
use std::path::PathBuf;
use std::sync::{Arc, Mutex, PoisonError};

use notify::event::{AccessKind, AccessMode, ModifyKind, RenameMode};
use notify::{EventKind, RecommendedWatcher, RecursiveMode, Watcher};
use tokio::sync::mpsc::UnboundedSender;

/// What an event says about a followed file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Change {
    /// The file is being changed (written, truncated, created, removed): more may follow.
    Partial,
    /// A save ended: the file was closed after writing, or another was renamed over it.
    Saved,
}

impl Change {
    /// What `kind` says about a followed file, `None` for an event that changes nothing.
    fn of(kind: EventKind) -> Option<Self> {
        match kind {
            EventKind::Access(AccessKind::Close(AccessMode::Write))
            | EventKind::Modify(ModifyKind::Name(RenameMode::To | RenameMode::Both)) => {
                Some(Self::Saved)
            }
            EventKind::Access(_) => None,
            _ => Some(Self::Partial),
        }
    }
}

/// A watcher over a set of files that may change with every rebuild.
pub struct FileWatch {
    watcher: RecommendedWatcher,
    directories: HashSet<PathBuf>,
    files: Arc<Mutex<HashSet<PathBuf>>>,
}

impl FileWatch {
    /// A watcher that sends a [`Change`] on `changed` whenever a followed file changes.
    pub fn new(changed: UnboundedSender<Change>) -> notify::Result<Self> {
        let files: Arc<Mutex<HashSet<PathBuf>>> = Arc::default();
        let followed = Arc::clone(&files);
        let watcher = notify::recommended_watcher(move |event: notify::Result<notify::Event>| {
            let Ok(event) = event else {
                // An overflowed queue may have lost a change: rebuild to be sure.
                let _ = changed.send(Change::Saved);
                return;
            };
            let Some(change) = Change::of(event.kind) else {
                return;
            };
            let files = followed.lock().unwrap_or_else(PoisonError::into_inner);
            if event.paths.iter().any(|path| files.contains(path)) {
                let _ = changed.send(change);
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
