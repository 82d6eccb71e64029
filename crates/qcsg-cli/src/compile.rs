//! `qcsg compile FILE --emit ast|dag|dnf [--format text|json] [-o OUT]`: prints a stage of the
//! compilation, and the evaluation step that `qcsg check` runs after a clean static check.
//!
//! Diagnostics go to standard error for people; the chosen stage goes to OUT (standard output by
//! default) only when the input has no errors, so a failed run never writes a partial file.

use std::io::Write;

use clap::{Args, ValueEnum};
use qcsg_csg::{DnfOptions, dag_to_json, dag_to_text, dnf_to_json, dnf_to_text};
use qcsg_driver::{Options, Stage, search_path_from_env};
use qcsg_eval::EvalOptions;
use qcsg_sema::Analysis;

use crate::program;
use crate::{EXIT_INPUT_ERRORS, EXIT_OK, EXIT_USAGE};

/// Arguments of `qcsg compile`.
#[derive(Debug, Args)]
pub struct CompileArgs {
    /// The program (`.qcsg` or `.scad`); `-` reads standard input.
    #[arg(value_name = "FILE")]
    file: String,

    /// The stage to print: the syntax tree, the CSG DAG or its disjunctive normal form.
    #[arg(long, value_enum)]
    emit: Emit,

    /// How the stage is printed.
    #[arg(long, value_enum, default_value_t = OutputFormat::Text)]
    format: OutputFormat,

    /// Where to write the stage; `-` is standard output.
    #[arg(short = 'o', value_name = "OUT", default_value = "-")]
    output: String,

    /// Override a top-level variable, as OpenSCAD's `-D` (VALUE is an expression); repeatable.
    #[arg(short = 'D', value_name = "NAME=VALUE", value_parser = crate::parse_define)]
    defines: Vec<(String, String)>,

    /// Report errors only: no warnings, echo output or summary line.
    #[arg(short, long)]
    quiet: bool,

    #[command(flatten)]
    limits: LimitArgs,
}

/// Evaluation limits (a program crossing one gets a diagnostic at a span, never a hang).
#[derive(Debug, Args)]
pub struct EvalLimitArgs {
    /// Deepest nesting of module and function calls (tail calls do not nest).
    #[arg(long, value_name = "N", default_value_t = EvalOptions::DEFAULT_MAX_RECURSION)]
    max_recursion: usize,

    /// Most loop iterations and function calls in total.
    #[arg(long, value_name = "N", default_value_t = EvalOptions::DEFAULT_MAX_ITERATIONS)]
    max_iterations: u64,

    /// Most elements of one vector.
    #[arg(long, value_name = "N", default_value_t = EvalOptions::DEFAULT_MAX_VECTOR_LEN)]
    max_vector_len: u64,

    /// Most primitive instances.
    #[arg(long, value_name = "N", default_value_t = EvalOptions::DEFAULT_MAX_INSTANCES)]
    max_instances: u64,

    /// Most bytes of one string (`str`, `chr`).
    #[arg(long, value_name = "N", default_value_t = EvalOptions::DEFAULT_MAX_STRING_LEN)]
    max_string_len: u64,

    /// Most bytes of `echo` output in all, each line counting 64 more; past it, output is cut
    /// with a warning.
    #[arg(long, value_name = "N", default_value_t = EvalOptions::DEFAULT_MAX_ECHO_LEN)]
    max_echo_len: u64,

    /// Most bytes of one file that `import` reads.
    #[arg(long, value_name = "N", default_value_t = EvalOptions::DEFAULT_MAX_IMPORT_BYTES)]
    max_import_bytes: u64,

    /// Most distinct points of one 3-D `hull` or convex part of a `minkowski` (64 times as many
    /// in 2-D).
    #[arg(long, value_name = "N", default_value_t = EvalOptions::DEFAULT_MAX_HULL_POINTS)]
    max_hull_points: usize,

    /// Most distinct faces of one convex part of a `hull` or `minkowski` child.
    #[arg(long, value_name = "N", default_value_t = EvalOptions::DEFAULT_MAX_PART_PLANES)]
    max_part_planes: usize,

    /// Most convex parts of one `minkowski`.
    #[arg(long, value_name = "N", default_value_t = EvalOptions::DEFAULT_MAX_MINKOWSKI_PARTS)]
    max_minkowski_parts: usize,
}

impl EvalLimitArgs {
    /// The evaluator's options: these limits and the `-D` overrides.
    pub fn eval_options(&self, defines: &[(String, String)]) -> EvalOptions {
        EvalOptions {
            defines: defines.to_vec(),
            max_recursion: self.max_recursion,
            max_iterations: self.max_iterations,
            max_vector_len: self.max_vector_len,
            max_instances: self.max_instances,
            max_string_len: self.max_string_len,
            max_echo_len: self.max_echo_len,
            max_import_bytes: self.max_import_bytes,
            max_hull_points: self.max_hull_points,
            max_part_planes: self.max_part_planes,
            max_minkowski_parts: self.max_minkowski_parts,
        }
    }
}

/// The evaluation limits and the DNF's term limit, for commands that build the DNF.
#[derive(Debug, Args)]
pub struct LimitArgs {
    #[command(flatten)]
    eval: EvalLimitArgs,

    /// Most terms of the disjunctive normal form.
    #[arg(long, value_name = "N", default_value_t = qcsg_csg::DEFAULT_TERM_LIMIT)]
    max_terms: usize,
}

impl LimitArgs {
    /// The evaluator's options: these limits and the `-D` overrides.
    pub fn eval_options(&self, defines: &[(String, String)]) -> EvalOptions {
        self.eval.eval_options(defines)
    }

    /// The DNF builder's options: the term limit.
    pub fn dnf_options(&self) -> DnfOptions {
        DnfOptions {
            term_limit: self.max_terms,
            ..DnfOptions::default()
        }
    }

    /// The pipeline's options: these limits, the `-D` overrides and `QCSG_PATH`.
    pub fn options(&self, defines: &[(String, String)]) -> Options {
        Options {
            search_path: search_path_from_env(),
            defines: defines.to_vec(),
            eval: self.eval_options(defines),
            dnf: self.dnf_options(),
        }
    }
}

/// What `--emit` prints.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Emit {
    /// The syntax tree as S-expressions, one top-level statement per line.
    Ast,
    /// The transformed CSG DAG.
    Dag,
    /// The disjunctive normal form over world-space quadrics.
    Dnf,
}

/// The `--format` of the emitted stage.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum OutputFormat {
    /// Readable text.
    Text,
    /// JSON (the formats of docs/cli.md).
    Json,
}

/// Runs `qcsg compile` and returns the process exit status.
pub fn run(args: CompileArgs) -> u8 {
    let (name, text) = match program::read(&args.file) {
        Ok(input) => input,
        Err(message) => {
            eprintln!("error: {message}");
            return EXIT_USAGE;
        }
    };
    let stage = match args.emit {
        Emit::Ast => Stage::Check,
        Emit::Dag => Stage::Evaluate,
        Emit::Dnf => Stage::Dnf,
    };
    let options = args.limits.options(&args.defines);
    let compilation = program::compile(&name, text, &options, stage);
    let analysis = &compilation.analysis;
    let output = match args.emit {
        _ if analysis.has_errors() => None,
        Emit::Ast => Some(emit_ast(analysis, args.format)),
        Emit::Dag => compilation
            .dag
            .as_ref()
            .map(|dag| emit_dag(analysis, dag, args.format)),
        Emit::Dnf => compilation.solid().map(|dnf| match args.format {
            OutputFormat::Text => dnf_to_text(dnf, &qcsg_csg::line_locator(&analysis.sources)),
            OutputFormat::Json => dnf_to_json(dnf, &|file| file_name(analysis, file)),
        }),
    };
    let analysis = &compilation.analysis;
    program::print_human(analysis, args.quiet);
    if analysis.has_errors() {
        return EXIT_INPUT_ERRORS;
    }
    let Some(mut text) = output else {
        return EXIT_INPUT_ERRORS;
    };
    if !text.ends_with('\n') {
        text.push('\n');
    }
    let written = if args.output == "-" {
        std::io::stdout().lock().write_all(text.as_bytes())
    } else {
        std::fs::write(&args.output, text.as_bytes())
    };
    match written {
        Ok(()) => EXIT_OK,
        Err(err) => {
            eprintln!("error: cannot write `{}`: {err}", args.output);
            EXIT_USAGE
        }
    }
}

fn file_name(analysis: &Analysis, file: qcsg_diag::FileId) -> String {
    analysis
        .sources
        .iter()
        .find(|(id, _)| *id == file)
        .map_or_else(|| "<unknown>".to_string(), |(_, f)| f.name.clone())
}

fn emit_ast(analysis: &Analysis, format: OutputFormat) -> String {
    let tree = analysis.tree(analysis.main);
    match format {
        OutputFormat::Text => tree
            .map(qcsg_syntax::sexpr::file_to_sexpr)
            .unwrap_or_default(),
        OutputFormat::Json => {
            let statements: Vec<String> = tree
                .map(|t| {
                    t.stmts
                        .iter()
                        .map(qcsg_syntax::sexpr::stmt_to_sexpr)
                        .collect()
                })
                .unwrap_or_default();
            let json = serde_json::json!({
                "file": file_name(analysis, analysis.main),
                "statements": statements,
            });
            serde_json::to_string_pretty(&json).unwrap_or_default()
        }
    }
}

fn emit_dag(analysis: &Analysis, dag: &qcsg_csg::Dag, format: OutputFormat) -> String {
    match format {
        OutputFormat::Text => dag_to_text(dag, &qcsg_csg::line_locator(&analysis.sources)),
        OutputFormat::Json => dag_to_json(dag, &|file| file_name(analysis, file)),
    }
}
