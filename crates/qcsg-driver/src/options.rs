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

/// The library directories of `QCSG_PATH` (separated as `PATH` is on this platform; empty entries
/// skipped).
pub fn search_path_from_env() -> Vec<PathBuf> {
    std::env::var_os("QCSG_PATH")
        .map(|paths| {
            std::env::split_paths(&paths)
                .filter(|p| !p.as_os_str().is_empty())
                .collect()
        })
        .unwrap_or_default()
}
