//! The stages, run in order as far as a [`Stage`]: static check, evaluation to the scene DAG,
//! and the DNF of each layer. Each stage appends its diagnostics to the analysis and runs only
//! when the stages before it found no error, so what a command reports is all that the stages
//! up to its own would report.

use std::collections::HashSet;

use qcsg_csg::{Dag, Dnf, Layers, NodeId, Source, build_layers};
use qcsg_diag::Diagnostic;
use qcsg_eval::Evaluation;
use qcsg_sema::{Analysis, FileLoader, SourceText, check_source};

use crate::options::Options;

/// How far a run goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Stage {
    /// Parse, resolve names and check statically.
    Check,
    /// Also evaluate into the scene DAG.
    Evaluate,
    /// Also build the DNF of every layer, with its bounds (what a render needs).
    Dnf,
}

/// What a run produced. The analysis holds the sources and every stage's diagnostics.
#[derive(Debug)]
pub struct Compilation {
    /// Sources, syntax trees, definitions and all diagnostics.
    pub analysis: Analysis,
    /// The scene DAG, when evaluation ran and found no error.
    pub dag: Option<Dag>,
    /// The DNF layers, when they were built without error.
    pub layers: Option<Layers>,
    /// Which DAG node each module instantiation statement produced (see
    /// [`qcsg_eval::Evaluation::instantiations`]), for tools that go from a part back to the
    /// calls that made it; empty when evaluation did not run.
    pub instantiations: Vec<(Source, NodeId)>,
    /// The files `import` read or tried to read (see [`qcsg_eval::Evaluation::imports`]), which
    /// a viewer watches beside the sources; empty when evaluation did not run.
    pub imports: Vec<std::path::PathBuf>,
}

impl Compilation {
    /// Whether any stage found an error.
    pub fn has_errors(&self) -> bool {
        self.analysis.has_errors()
    }

    /// The solid's DNF, when the layers were built.
    pub fn solid(&self) -> Option<&Dnf> {
        self.layers.as_ref()?.solid.as_ref()
    }
}

/// Runs the pipeline on a program whose main file is `name` with contents `text`, reading
/// included and used files through `loader`.
pub fn compile(
    name: &str,
    text: String,
    options: &Options,
    loader: &dyn FileLoader,
    stage: Stage,
) -> Compilation {
    compile_source(name, text.into(), options, loader, stage)
}

/// [`compile`] for a main file read by `qcsg_sema::read_source` (invalid UTF-8 in it is
/// reported as in any included file).
pub fn compile_source(
    name: &str,
    source: SourceText,
    options: &Options,
    loader: &dyn FileLoader,
    stage: Stage,
) -> Compilation {
    let mut analysis = check_source(name, source, &options.check_options(), loader);
    let built = build(&analysis, options, stage);
    let mut instantiations = Vec::new();
    let mut imports = Vec::new();
    let dag = built.evaluation.and_then(|evaluation| {
        let failed = evaluation.has_errors();
        analysis.diagnostics.extend(evaluation.diagnostics);
        instantiations = evaluation.instantiations;
        imports = evaluation.imports;
        (!failed).then_some(evaluation.dag)
    });
    analysis.diagnostics.extend(built.diagnostics);
    Compilation {
        analysis,
        dag,
        layers: built.layers,
        instantiations,
        imports,
    }
}

/// What the stages after the static check produced for one analysis.
#[derive(Debug, Default)]
pub struct Built {
    /// The evaluation (its DAG, diagnostics and what each call produced), when it ran: the
    /// analysis had no error and the stage asked for it.
    pub evaluation: Option<Evaluation>,
    /// The DNF layers, when they were built without error.
    pub layers: Option<Layers>,
    /// The DNF stage's diagnostics: its errors, or the layers' warnings.
    pub diagnostics: Vec<Diagnostic>,
}

/// Runs the stages after the static check on `analysis`, as far as `stage`: evaluation when
/// the analysis has no error, then the DNF layers when evaluation had none. For callers that
/// keep the analysis apart, such as the language server; [`compile`] is this after a check.
pub fn build(analysis: &Analysis, options: &Options, stage: Stage) -> Built {
    let mut built = Built::default();
    if stage < Stage::Evaluate || analysis.has_errors() {
        return built;
    }
    let mut evaluation = qcsg_eval::evaluate(analysis, &options.eval_options());
    if stage >= Stage::Dnf && !evaluation.has_errors() {
        match build_layers(&mut evaluation.dag, &options.dnf) {
            Ok(layers) => {
                // A highlighted part is also part of the solid: its warnings are said once. A
                // set, as a scene may have a warning for each of many instances.
                let mut seen = HashSet::new();
                let every = layers.solid.iter().chain(&layers.highlights);
                for warning in every.chain(&layers.backgrounds).flat_map(|l| &l.warnings) {
                    if seen.insert(warning) {
                        built.diagnostics.push(warning.clone());
                    }
                }
                built.layers = Some(layers);
            }
            Err(errors) => built.diagnostics = errors,
        }
    }
    built.evaluation = Some(evaluation);
    built
}
