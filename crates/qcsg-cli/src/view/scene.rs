//! The scene a preview shows: the program compiled by the one pipeline driver, the last good
//! [`Preview`] kept while the text has errors, and the `change` event that tells the page.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use qcsg_csg::Dag;
use qcsg_driver::{Options, Stage};
use qcsg_lsp::preview::Preview;
use serde_json::json;

use crate::json::JsonDiagnostic;
use crate::program;

/// A scene that compiled without error: its preview, and the DAG in which a pick finds the
/// module calls that made a part.
pub struct Image {
    /// The scene drawn, and what each of its parts came from.
    pub preview: Preview,
    /// The solid's DAG.
    pub dag: Dag,
}

/// One compiled state of the program.
#[derive(Clone)]
pub struct Snapshot {
    /// Counts the rebuilds, from 1.
    pub generation: u64,
    /// The last scene that compiled without error, with the generation it came from.
    pub image: Option<(u64, Arc<Image>)>,
    /// The `change` event of this generation (JSON).
    pub event: String,
    /// Every file the program read, imported meshes included (absolute where they could be
    /// resolved), to watch.
    pub files: Vec<PathBuf>,
}

/// Compiles `file` again, keeping the image of `previous` when the new text has errors.
pub fn rebuild(file: &str, options: &Options, previous: Option<&Snapshot>) -> Snapshot {
    let generation = previous.map_or(1, |p| p.generation + 1);
    let started = Instant::now();
    let (event, image, files) = match program::read(file) {
        Err(message) => {
            let event = json!({
                "generation": generation,
                "ok": false,
                "image_generation": previous.and_then(|p| p.image.as_ref()).map(|(g, _)| *g),
                "file": file,
                "diagnostics": [],
                "error": message,
            });
            let files =
                previous.map_or_else(|| vec![absolute(Path::new(file))], |p| p.files.clone());
            (event, previous.and_then(|p| p.image.clone()), files)
        }
        Ok((name, source)) => {
            let compilation = program::compile(&name, source, options, Stage::Dnf);
            let compile_ms = started.elapsed().as_secs_f64() * 1e3;
            let analysis = &compilation.analysis;
            let ok = !analysis.has_errors();
            let diagnostics: Vec<_> = analysis
                .diagnostics
                .iter()
                .map(|d| JsonDiagnostic::new(&analysis.sources, d))
                .collect();
            let diagnostics = serde_json::to_value(&diagnostics).unwrap_or_default();
            let files = analysis
                .sources
                .iter()
                .map(|(_, source)| absolute(Path::new(&source.name)))
                .chain(compilation.imports.iter().map(|path| absolute(path)))
                .collect();
            let image = match (ok, compilation.dag, compilation.layers) {
                (true, Some(dag), Some(layers)) => Some((
                    generation,
                    Arc::new(Image {
                        preview: Preview::new(analysis, layers, &compilation.instantiations),
                        dag,
                    }),
                )),
                _ => previous.and_then(|p| p.image.clone()),
            };
            let quadrics = image
                .as_ref()
                .filter(|(g, _)| *g == generation)
                .map(|(_, image)| image.preview.scene().quadric_count());
            let event = json!({
                "generation": generation,
                "ok": ok,
                "image_generation": image.as_ref().map(|(g, _)| *g),
                "file": name,
                "diagnostics": diagnostics,
                "compile_ms": compile_ms,
                "quadrics": quadrics,
            });
            (event, image, files)
        }
    };
    Snapshot {
        generation,
        image,
        event: event.to_string(),
        files,
    }
}

/// `path` made absolute against the working directory, symbolic links resolved where it
/// exists (the watcher reports real paths).
pub fn absolute(path: &Path) -> PathBuf {
    path.canonicalize().unwrap_or_else(|_| {
        std::env::current_dir()
            .map(|dir| dir.join(path))
            .unwrap_or_else(|_| path.to_path_buf())
    })
}
