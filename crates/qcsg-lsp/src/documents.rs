//! The open documents: text, version and the latest analysis, behind one lock.
//!
//! LSP messages are processed concurrently, so a `didChange` can arrive while a request is being
//! answered. The lock is a plain mutex held only to read or replace a document, never across an
//! `.await` or an analysis; analyses run on a snapshot and are cached only if the document has
//! not changed meanwhile.
//!
//! Analyses run one at a time, each of the latest text when its turn comes; evaluations (the
//! geometry of an analysis) run one at a time too, and one whose documents changed while it
//! waited is not run: typing fast in a heavy document would otherwise start an analysis and an
//! evaluation per keystroke, all at once, each holding the memory of a whole tree or solid.

use std::collections::HashMap;
use std::ops::Deref;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard, OnceLock};

use qcsg_diag::{LineCol, LineIndex, Span};
use qcsg_ide::{Analysis, CheckOptions, FileId, FileLoader, HoverExtension};
use tower_lsp_server::ls_types::{Range, TextDocumentContentChangeEvent, Uri};

use crate::geometry::{Geometry, editor_limits};

/// One open document.
#[derive(Debug)]
struct Document {
    text: String,
    version: i32,
    /// The analysis of this version, once computed (and the generation it was computed in).
    analysis: Option<(u64, Arc<Analyzed>)>,
}

/// All open documents.
#[derive(Debug, Default)]
pub struct Documents {
    state: Mutex<State>,
    /// The generation of the latest edit, readable without the lock by analyses that wait to be
    /// evaluated.
    latest: Arc<AtomicU64>,
}

/// Held by the one evaluation that runs.
static EVALUATING: Mutex<()> = Mutex::new(());

/// Held by the one analysis (parse and check) that runs.
static ANALYZING: Mutex<()> = Mutex::new(());

#[derive(Debug, Default)]
struct State {
    documents: HashMap<Uri, Document>,
    /// Increases with every edit of any document: an analysis also depends on the buffers of the
    /// files it includes.
    generation: u64,
}

/// A checked document and, once something needs it, its evaluation.
#[derive(Debug)]
pub struct Analyzed {
    analysis: Analysis,
    /// Evaluated on first need, once: concurrent callers wait for the first one. `None` also
    /// when a newer edit superseded the analysis before its turn to be evaluated came.
    geometry: OnceLock<Option<Geometry>>,
    /// The generation of the documents the analysis was made from.
    generation: u64,
    /// The generation of the latest edit.
    latest: Arc<AtomicU64>,
}

impl Analyzed {
    /// Wraps a checked document made from the documents of `generation`, while `latest` follows
    /// the latest edit; nothing is evaluated yet.
    pub fn new(analysis: Analysis, generation: u64, latest: Arc<AtomicU64>) -> Self {
        Self {
            analysis,
            geometry: OnceLock::new(),
            generation,
            latest,
        }
    }

    /// Whether a document changed since the analysis was made.
    pub fn is_superseded(&self) -> bool {
        self.latest.load(Ordering::Acquire) != self.generation
    }

    /// The checked document.
    pub fn analysis(&self) -> &Analysis {
        &self.analysis
    }

    /// The evaluated solid under the editor's limits (evaluated now if it was not yet, after
    /// any evaluation running); `None` when the program has static errors, or when a document
    /// changed before the evaluation could start (see [`Analyzed::is_superseded`]).
    pub fn geometry(&self) -> Option<&Geometry> {
        self.geometry
            .get_or_init(|| {
                // A panic in an evaluation leaves nothing behind the lock to repair.
                let _turn = EVALUATING
                    .lock()
                    .unwrap_or_else(|poisoned| poisoned.into_inner());
                if self.is_superseded() {
                    return None;
                }
                Geometry::evaluate(&self.analysis, &editor_limits())
            })
            .as_ref()
    }
}

impl Deref for Analyzed {
    type Target = Analysis;

    fn deref(&self) -> &Analysis {
        &self.analysis
    }
}

/// Hover's geometry, evaluated only when the hover is on a module instantiation.
impl HoverExtension for Analyzed {
    fn instantiation(&self, analysis: &Analysis, file: FileId, name_span: Span) -> Option<String> {
        self.geometry()?.instantiation(analysis, file, name_span)
    }
}

/// What an analysis needs, taken under the lock and used after releasing it.
#[derive(Debug)]
pub struct Snapshot {
    /// The document's path (or its URI for documents that are not files).
    pub path: String,
    /// The document's text.
    pub text: String,
    /// Its version.
    pub version: i32,
    generation: u64,
    /// The generation of the latest edit.
    latest: Arc<AtomicU64>,
    /// Every open file's text by path, so includes see unsaved edits.
    buffers: HashMap<PathBuf, String>,
}

/// The path an analysis uses for a document.
pub fn document_path(uri: &Uri) -> String {
    match uri.to_file_path() {
        Some(path) => path.to_string_lossy().into_owned(),
        None => uri.as_str().to_owned(),
    }
}

impl Documents {
    /// Counts an edit of any document: every analysis made before it is superseded.
    fn next_generation(&self, state: &mut State) {
        state.generation += 1;
        self.latest.store(state.generation, Ordering::Release);
    }

    fn lock(&self) -> MutexGuard<'_, State> {
        // A panic while holding the lock cannot leave a document half-written (every update is a
        // single assignment), so a poisoned lock is still usable.
        self.state
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner())
    }

    /// Opens (or reopens) a document.
    pub fn open(&self, uri: Uri, text: String, version: i32) {
        let mut state = self.lock();
        self.next_generation(&mut state);
        state.documents.insert(
            uri,
            Document {
                text,
                version,
                analysis: None,
            },
        );
    }

    /// Closes a document.
    pub fn close(&self, uri: &Uri) {
        let mut state = self.lock();
        self.next_generation(&mut state);
        state.documents.remove(uri);
    }

    /// Applies edits (ranges in UTF-16 positions, or whole-text replacements) in order.
    /// Returns `false` when the document is not open.
    pub fn change(
        &self,
        uri: &Uri,
        version: i32,
        changes: Vec<TextDocumentContentChangeEvent>,
    ) -> bool {
        let mut state = self.lock();
        self.next_generation(&mut state);
        let Some(document) = state.documents.get_mut(uri) else {
            return false;
        };
        for change in changes {
            match change.range {
                Some(range) => apply_edit(&mut document.text, range, &change.text),
                None => document.text = change.text,
            }
        }
        document.version = version;
        document.analysis = None;
        true
    }

    /// The current text and version of a document.
    pub fn text(&self, uri: &Uri) -> Option<(String, i32)> {
        let state = self.lock();
        state
            .documents
            .get(uri)
            .map(|d| (d.text.clone(), d.version))
    }

    /// The URIs of every open document.
    pub fn uris(&self) -> Vec<Uri> {
        self.lock().documents.keys().cloned().collect()
    }

    /// The current version of a document.
    pub fn version(&self, uri: &Uri) -> Option<i32> {
        self.lock().documents.get(uri).map(|d| d.version)
    }

    /// The cached analysis of the current version, or a snapshot to compute it from.
    pub fn analysis_or_snapshot(&self, uri: &Uri) -> Option<Result<Arc<Analyzed>, Snapshot>> {
        let state = self.lock();
        let document = state.documents.get(uri)?;
        if let Some((generation, analysis)) = &document.analysis
            && *generation == state.generation
        {
            return Some(Ok(analysis.clone()));
        }
        let buffers = state
            .documents
            .iter()
            .filter_map(|(uri, d)| Some((uri.to_file_path()?.into_owned(), d.text.clone())))
            .collect();
        Some(Err(Snapshot {
            path: document_path(uri),
            text: document.text.clone(),
            version: document.version,
            generation: state.generation,
            latest: self.latest.clone(),
            buffers,
        }))
    }

    /// An analysis of `uri`, made in its turn: analyses run one at a time, across all documents,
    /// and the one whose turn comes analyses the document as it is then (or takes the analysis
    /// another made meanwhile), not the older `snapshot` it was asked for. A burst of edits
    /// would otherwise analyse every version at once, each holding a whole syntax tree and its
    /// diagnostics. Returns the analysis and, when it was made here, the snapshot it was made
    /// from (to [`Documents::store`]).
    pub fn analyze_in_turn(
        &self,
        uri: &Uri,
        snapshot: Snapshot,
    ) -> (Arc<Analyzed>, Option<Snapshot>) {
        let _turn = ANALYZING
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner());
        let snapshot = match self.analysis_or_snapshot(uri) {
            Some(Ok(analysis)) => return (analysis, None),
            Some(Err(latest)) => latest,
            // Closed meanwhile: the request still gets an answer.
            None => snapshot,
        };
        (Arc::new(snapshot.analyze()), Some(snapshot))
    }

    /// Caches an analysis computed from `snapshot` unless anything changed since. Returns whether
    /// it is still current.
    pub fn store(&self, uri: &Uri, snapshot: &Snapshot, analysis: &Arc<Analyzed>) -> bool {
        let mut state = self.lock();
        let generation = state.generation;
        let Some(document) = state.documents.get_mut(uri) else {
            return false;
        };
        if document.version != snapshot.version {
            return false;
        }
        if generation == snapshot.generation {
            document.analysis = Some((generation, analysis.clone()));
        }
        true
    }
}

impl Snapshot {
    /// Checks the snapshot's document.
    pub fn analyze(&self) -> Analyzed {
        let analysis = Analysis::new(
            &self.path,
            self.text.clone(),
            &CheckOptions {
                search_path: qcsg_driver::search_path_from_env(),
                defines: Vec::new(),
            },
            self,
        );
        Analyzed::new(analysis, self.generation, self.latest.clone())
    }
}

impl FileLoader for Snapshot {
    fn load(&self, path: &Path) -> std::io::Result<String> {
        match self.buffers.get(path) {
            Some(text) => Ok(text.clone()),
            None => qcsg_ide::FsLoader.load(path),
        }
    }
}

/// Replaces `range` (UTF-16 positions; out-of-range positions clamp) of `text` with `new_text`.
pub fn apply_edit(text: &mut String, range: Range, new_text: &str) {
    let index = LineIndex::new(text);
    let offset = |p: tower_lsp_server::ls_types::Position| {
        index.offset(
            text,
            LineCol {
                line: p.line,
                character: p.character,
            },
        )
    };
    let start = offset(range.start);
    let end = offset(range.end).max(start);
    text.replace_range(start..end, new_text);
}

#[cfg(test)]
mod tests {
    use super::*;
    use tower_lsp_server::ls_types::Position;

    fn range(a: (u32, u32), b: (u32, u32)) -> Range {
        Range::new(Position::new(a.0, a.1), Position::new(b.0, b.1))
    }

    #[test]
    fn an_analysis_superseded_before_its_evaluation_is_not_evaluated() {
        let documents = Documents::default();
        let uri: Uri = "file:///tmp/superseded.qcsg".parse().unwrap();
        documents.open(uri.clone(), "sphere(1);".into(), 1);
        let analyze = || match documents.analysis_or_snapshot(&uri) {
            Some(Err(snapshot)) => snapshot.analyze(),
            _ => panic!("a snapshot of an open document"),
        };
        let first = analyze();
        documents.change(
            &uri,
            2,
            vec![TextDocumentContentChangeEvent {
                range: None,
                range_length: None,
                text: "sphere(2);".into(),
            }],
        );
        assert!(first.is_superseded());
        assert!(first.geometry().is_none());
        let second = analyze();
        assert!(!second.is_superseded());
        assert!(second.geometry().is_some());
        // Once evaluated, an analysis keeps its geometry through later edits.
        documents.close(&uri);
        assert!(second.is_superseded() && second.geometry().is_some());
    }

    #[test]
    fn edits_count_utf16_units() {
        let mut text = "s = \"😀\"; x = 1;\ny = 2;\n".to_owned();
        // The emoji is two UTF-16 units: `x` is at column 10.
        apply_edit(&mut text, range((0, 10), (0, 11)), "width");
        assert_eq!(text, "s = \"😀\"; width = 1;\ny = 2;\n");
        apply_edit(&mut text, range((1, 0), (2, 0)), "");
        assert_eq!(text, "s = \"😀\"; width = 1;\n");
        apply_edit(&mut text, range((5, 0), (9, 9)), "z = 3;\n");
        assert_eq!(text, "s = \"😀\"; width = 1;\nz = 3;\n");
    }
}
