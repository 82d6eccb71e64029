//! What a run of the pipeline is asked to do: where `include <…>` and `use <…>` look, the `-D`
//! overrides, and the limits of evaluation and of the DNF.

use std::path::PathBuf;

use qcsg_csg::DnfOptions;
use qcsg_eval::EvalOptions;
use qcsg_sema::CheckOptions;

/// The settings of a run: one value that every stage reads its part of.
#[derive(Clone, Debug, Default)]
pub struct Options {
    /// Directories searched for `include <…>` / `use <…>` after the including file's directory.
    pub search_path: Vec<PathBuf>,
    /// `-D name=value` overrides of top-level variables, value as source text.
    pub defines: Vec<(String, String)>,
    /// Evaluation limits. Its `defines` are ignored: [`Options::defines`] is the one list.
    pub eval: EvalOptions,
    /// The DNF's limits.
    pub dnf: DnfOptions,
}

impl Options {
    /// Default limits, the search path of `QCSG_PATH` and the given overrides.
    pub fn from_env(defines: Vec<(String, String)>) -> Self {
        Self {
            search_path: search_path_from_env(),
            defines,
            ..Self::default()
        }
    }

    /// The static checker's part.
    pub fn check_options(&self) -> CheckOptions {
        CheckOptions {
            search_path: self.search_path.clone(),
            defines: self.defines.clone(),
        }
    }

    /// The evaluator's part, with the overrides.
    pub fn eval_options(&self) -> EvalOptions {
        EvalOptions {
            defines: self.defines.clone(),
            ..self.eval.clone()
        }
    }
}

/// The library directories, in the order they are searched: those of `QCSG_PATH`, then
/// OpenSCAD's (`OPENSCADPATH`, the user's library folder and the installation's), so that a
/// `.scad` file finds the libraries it finds in OpenSCAD, e.g. `use <MCAD/gears.scad>`.
/// `QCSG_PATH` and `OPENSCADPATH` are separated as `PATH` is on this platform (empty entries
/// skipped); OpenSCAD's own folders are searched only where they exist.
pub fn search_path_from_env() -> Vec<PathBuf> {
    let mut path = paths_of("QCSG_PATH");
    path.extend(paths_of("OPENSCADPATH"));
    path.extend(
        openscad_library_folders()
            .into_iter()
            .filter(|p| p.is_dir()),
    );
    path
}

fn paths_of(variable: &str) -> Vec<PathBuf> {
    std::env::var_os(variable)
        .map(|paths| {
            std::env::split_paths(&paths)
                .filter(|p| !p.as_os_str().is_empty())
                .collect()
        })
        .unwrap_or_default()
}

/// Where OpenSCAD 2021.01 looks for libraries after `OPENSCADPATH` on Linux: the user's folder
/// (`$XDG_DATA_HOME/OpenSCAD/libraries`, by default under `~/.local/share`), then those of an
/// installation from packages or from source.
fn openscad_library_folders() -> Vec<PathBuf> {
    let user_data = std::env::var_os("XDG_DATA_HOME")
        .filter(|d| !d.is_empty())
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|home| PathBuf::from(home).join(".local/share")));
    user_data
        .map(|data| data.join("OpenSCAD/libraries"))
        .into_iter()
        .chain([
            PathBuf::from("/usr/share/openscad/libraries"),
            PathBuf::from("/usr/local/share/openscad/libraries"),
        ])
        .collect()
}
