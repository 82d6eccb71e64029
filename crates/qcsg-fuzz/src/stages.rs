//! The pipeline a worker runs on one input, in process, mirroring the commands of `qcsg`
//! (crates/qcsg-cli/src/{program,compile,sample,render}.rs): parse, format, check, evaluate,
//! DNF, the `compile --emit` printers, sample, ray trace, then a language server session and
//! `qcsg check` through the binary.
//!
//! Each stage runs under [`run_stage`]: inside `catch_unwind`, timed, with the heap's peak
//! measured from the counting allocator (`peak_alloc`, the worker's global allocator) and
//! compared to the budget, and with the panics recorded meanwhile ([`crate::panics`]) turned
//! into a failure even when something else caught them. A stage feeds the next only with what a
//! command would go on with: evaluation only after a check without errors, as `qcsg` does.
//!
//! Besides "no panic, no hang, bounded memory", stages check stated properties: every
//! diagnostic span lies inside its file on character boundaries (the syntax crate's and the
//! checker's promise, which the CLI's excerpts and the LSP's positions rely on), formatting is
//! idempotent, keeps every token and comment and gives text that parses (the formatter's
//! documented contract), samples are finite.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;
use std::time::{Duration, Instant};

use peak_alloc::PeakAlloc;
use qcsg_csg::{Dag, Dnf, DnfOptions, build_dnf};
use qcsg_diag::{Diagnostic, FileId, SourceMap};
use qcsg_eval::{EvalOptions, evaluate};
use qcsg_render::{Camera, ImageSize, Projection, RenderOptions, Scene, View};
use qcsg_sample::{SampleLimits, sample_with_limits};
use qcsg_sema::{Analysis, CheckOptions, FsLoader, SourceText, check_source};

use crate::protocol::{Event, Failure, FailureKind, Fault, Radius, Request, Stage};
use crate::{cli_stage, lsp_session, panics};

/// Most samples a run may emit: a coarse radius needs far fewer, a tiny one must stop here.
/// The same limit bounds the basic regions and what eq. 22 set up for the sampled surfaces
/// holds, as the samples that take as much memory; a region costs more than its one sample's
/// worth (927,000 regions of a needle-like cone took 2 GB), so the limit stays low enough for
/// the memory budget, and scenes of a few hundred terms or a line of text are refused.
pub const MAX_SAMPLES: u64 = 200_000;
/// Most distance queries a run may make.
pub const MAX_QUERIES: u64 = 5_000_000;
/// An injected fault fires only on inputs containing this, so that minimisation can be tested
/// on it too.
pub const FAULT_MARKER: &[u8] = b"qcsg-fuzz-fault";
/// The ray-traced image's size.
pub const IMAGE: (u32, u32) = (64, 48);

/// Why a stage failed, before it is tied to the stage.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Problem {
    /// How.
    pub kind: FailureKind,
    /// What happened.
    pub message: String,
    /// What tells it from other problems of its kind (see [`Failure::signature`]).
    pub signature: String,
}

impl Problem {
    /// A broken property, its name as the signature.
    pub fn invariant(property: &str, detail: impl Into<String>) -> Self {
        Self {
            kind: FailureKind::Invariant,
            message: format!("{property}: {}", detail.into()),
            signature: property.to_owned(),
        }
    }
}

/// What a stage gives the next: `Ok(None)` when it ran fine but there is nothing to go on with
/// (a program with errors is not evaluated).
type StageResult<T> = Result<Option<T>, Problem>;

/// What a worker keeps between inputs.
pub struct Context {
    /// Threads for the sampler and the ray tracer.
    pub pool: rayon::ThreadPool,
    /// The language server's runtime.
    pub lsp: lsp_session::Runtime,
    /// The `qcsg` binary, when there is one.
    pub qcsg: Option<std::path::PathBuf>,
    /// The most heap one stage may hold, in bytes.
    pub memory_budget: u64,
    /// How long one stage may take (the `qcsg` binary is stopped after it).
    pub stage_timeout: Duration,
}

/// The evaluator's limits: the editor's, small enough that a runaway loop ends in well under a
/// second, so that time over the stage budget is a real problem, not a legitimately long run.
pub fn eval_options() -> EvalOptions {
    qcsg_lsp::geometry::editor_limits()
}

/// Runs the stages `request` asks for (and what they need) on `bytes`, reporting each through
/// `emit`.
pub fn run(context: &Context, request: &Request, bytes: &[u8], emit: &mut dyn FnMut(Event)) {
    let wanted = |stage: Stage| {
        request
            .stages
            .iter()
            .any(|s| s.with_prerequisites().contains(&stage))
    };
    let budget = context.memory_budget;
    // The parser, the formatter and the language server see what an editor would send: the
    // text decoded, invalid UTF-8 replaced. The checker and the binary get the bytes.
    let text = String::from_utf8_lossy(bytes).into_owned();

    if let Some(fault) = request.fault
        && bytes.windows(FAULT_MARKER.len()).any(|w| w == FAULT_MARKER)
    {
        run_stage(Stage::Parse, emit, budget, || inject(fault));
        emit(Event::Done);
        return;
    }
    if wanted(Stage::Parse) {
        run_stage(Stage::Parse, emit, budget, || parse(&text));
    }
    if wanted(Stage::Format) {
        run_stage(Stage::Format, emit, budget, || format(&text));
    }
    let analysis = if wanted(Stage::Check) {
        run_stage(Stage::Check, emit, budget, || check(&request.name, bytes))
    } else {
        None
    };
    let dag = match &analysis {
        Some(analysis) if wanted(Stage::Eval) => {
            run_stage(Stage::Eval, emit, budget, || eval(analysis))
        }
        _ => None,
    };
    let dnf = match &dag {
        Some(dag) if wanted(Stage::Dnf) => run_stage(Stage::Dnf, emit, budget, || dnf(dag)),
        _ => None,
    };
    if let (Some(analysis), Some(dag), Some(dnf)) = (&analysis, &dag, &dnf)
        && wanted(Stage::Emit)
    {
        run_stage(Stage::Emit, emit, budget, || emit_all(analysis, dag, dnf));
    }
    if let Some(dnf) = &dnf
        && wanted(Stage::Sample)
    {
        run_stage(Stage::Sample, emit, budget, || {
            sample(&context.pool, dnf, request.radius)
        });
    }
    if let Some(dag) = dag
        && wanted(Stage::Render)
    {
        run_stage(Stage::Render, emit, budget, || render(&context.pool, dag));
    }
    if wanted(Stage::Lsp) {
        run_stage(Stage::Lsp, emit, budget, || {
            lsp_session::run(
                &context.lsp,
                Path::new(&request.name),
                &text,
                request.session_seed,
            )
            .map(Some)
        });
    }
    if let Some(qcsg) = &context.qcsg
        && wanted(Stage::Cli)
    {
        run_stage(Stage::Cli, emit, budget, || {
            cli_stage::run(qcsg, Path::new(&request.name), bytes, context.stage_timeout).map(Some)
        });
    }
    emit(Event::Done);
}

/// Runs one stage: start and end events, panics caught and recorded, time and peak heap.
pub fn run_stage<T>(
    stage: Stage,
    emit: &mut dyn FnMut(Event),
    memory_budget: u64,
    work: impl FnOnce() -> StageResult<T>,
) -> Option<T> {
    emit(Event::Start { stage });
    panics::take();
    let allocator = PeakAlloc;
    let before = allocator.current_usage();
    allocator.reset_peak_usage();
    let started = Instant::now();
    let result = catch_unwind(AssertUnwindSafe(work));
    let micros = u64::try_from(started.elapsed().as_micros()).unwrap_or(u64::MAX);
    let peak = allocator.peak_usage().saturating_sub(before) as u64;
    let recorded = panics::take();
    let panic_problem = |payload: Option<String>| {
        let first = recorded.first();
        Problem {
            kind: FailureKind::Panic,
            message: match first {
                Some(p) => format!(
                    "panicked at {} (thread {}): {}",
                    p.location, p.thread, p.message
                ),
                None => format!("panicked: {}", payload.unwrap_or_default()),
            },
            signature: first.map_or_else(String::new, |p| p.location.clone()),
        }
    };
    let (value, mut problem) = match result {
        Err(payload) => (
            None,
            Some(panic_problem(Some(panics::payload_text(&*payload)))),
        ),
        // A panic something else caught (the server answers it with an internal error) is
        // the cause of what the stage saw: its location tells one bug from another.
        Ok(_) if !recorded.is_empty() => (None, Some(panic_problem(None))),
        Ok(Err(problem)) => (None, Some(problem)),
        Ok(Ok(value)) => (value, None),
    };
    if problem.is_none() && peak > memory_budget {
        problem = Some(Problem {
            kind: FailureKind::Memory,
            message: format!(
                "held {} MiB of heap at its peak, over the budget of {} MiB",
                peak >> 20,
                memory_budget >> 20
            ),
            signature: String::new(),
        });
    }
    let failure = problem.map(|p| Failure {
        stage,
        kind: p.kind,
        message: p.message,
        signature: p.signature,
    });
    let failed = failure.is_some();
    emit(Event::End {
        stage,
        micros,
        peak,
        failure,
    });
    if failed { None } else { value }
}

/// Every diagnostic's span (and its labels') inside its file, on character boundaries, and
/// convertible to a line and UTF-16 column as the JSON output and the language server do.
fn check_spans<'a>(
    what: &str,
    sources: &SourceMap,
    diagnostics: impl IntoIterator<Item = &'a Diagnostic>,
) -> Result<(), Problem> {
    for diagnostic in diagnostics {
        let spans = std::iter::once((diagnostic.file, diagnostic.span))
            .chain(diagnostic.labels.iter().map(|l| (l.file, l.span)));
        for (file, span) in spans {
            let Some((_, source)) = sources.iter().find(|(id, _)| *id == file) else {
                return Err(Problem::invariant(
                    "diagnostic in an unknown file",
                    format!(
                        "{what} {} ({}) names file {}",
                        diagnostic.code, diagnostic.message, file.0
                    ),
                ));
            };
            let text = &source.text;
            let range = span.range();
            if range.start > range.end
                || range.end > text.len()
                || !text.is_char_boundary(range.start)
                || !text.is_char_boundary(range.end)
            {
                return Err(Problem::invariant(
                    "diagnostic span outside its file or inside a character",
                    format!(
                        "{what} {} ({}) at {}..{} of a {}-byte file",
                        diagnostic.code,
                        diagnostic.message,
                        range.start,
                        range.end,
                        text.len()
                    ),
                ));
            }
            source.line_index.line_col(text, range.start);
            source.line_index.line_col(text, range.end);
        }
    }
    Ok(())
}

fn parse(text: &str) -> StageResult<()> {
    let parse = qcsg_syntax::parse(text, FileId(0));
    let mut sources = SourceMap::new();
    sources.add("main", text);
    check_spans("syntax error", &sources, &parse.diagnostics)?;
    Ok(Some(()))
}

/// Tokens and comments as text, in order: what formatting must not change.
fn words(text: &str) -> Vec<&str> {
    let lexed = qcsg_syntax::lexer::lex(text, FileId(0));
    let mut spans: Vec<_> = lexed.tokens.iter().map(|(_, span)| *span).collect();
    spans.extend(lexed.comments.iter().map(|c| c.span));
    spans.sort_by_key(|s| s.start);
    spans.iter().filter_map(|s| text.get(s.range())).collect()
}

fn format(text: &str) -> StageResult<()> {
    let Ok(once) = qcsg_ide::format::format(text) else {
        // Text with syntax errors is refused, as documented.
        return Ok(Some(()));
    };
    let twice = qcsg_ide::format::format(&once).map_err(|error| {
        Problem::invariant("formatted text has syntax errors", error.to_string())
    })?;
    if once != twice {
        return Err(Problem::invariant(
            "formatting is not idempotent",
            first_difference(&once, &twice),
        ));
    }
    if words(text) != words(&once) {
        return Err(Problem::invariant(
            "formatting changed more than whitespace",
            first_difference(text, &once),
        ));
    }
    Ok(Some(()))
}

/// Where two texts first differ, with a little context, for a report.
fn first_difference(a: &str, b: &str) -> String {
    let at = a
        .bytes()
        .zip(b.bytes())
        .position(|(x, y)| x != y)
        .unwrap_or(a.len().min(b.len()));
    let excerpt = |s: &str| {
        let start = s.floor_char_boundary(at.saturating_sub(40));
        let end = s.ceil_char_boundary((at + 40).min(s.len()));
        format!("{:?}", &s[start..end])
    };
    format!("at byte {at}: {} became {}", excerpt(a), excerpt(b))
}

/// As `qcsg check`: the bytes decoded by the source reader (invalid UTF-8 is a diagnostic),
/// then checked with includes read from the file system.
fn check(name: &str, bytes: &[u8]) -> StageResult<Analysis> {
    let source = SourceText::decode(bytes.to_vec());
    let analysis = check_source(name, source, &CheckOptions::default(), &FsLoader);
    check_spans("diagnostic", &analysis.sources, &analysis.diagnostics)?;
    Ok((!analysis.has_errors()).then_some(analysis))
}

fn eval(analysis: &Analysis) -> StageResult<Dag> {
    let evaluation = evaluate(analysis, &eval_options());
    check_spans(
        "runtime diagnostic",
        &analysis.sources,
        &evaluation.diagnostics,
    )?;
    Ok((!evaluation.has_errors()).then_some(evaluation.dag))
}

fn dnf(dag: &Dag) -> StageResult<Dnf> {
    match build_dnf(dag, &DnfOptions::default()) {
        Ok(dnf) => Ok(Some(dnf)),
        Err(_) => Ok(None),
    }
}

fn emit_all(analysis: &Analysis, dag: &Dag, dnf: &Dnf) -> StageResult<()> {
    let name = |file: FileId| {
        analysis
            .sources
            .iter()
            .find(|(id, _)| *id == file)
            .map_or_else(|| "<unknown>".to_owned(), |(_, f)| f.name.clone())
    };
    if let Some(tree) = analysis.tree(analysis.main) {
        qcsg_syntax::sexpr::file_to_sexpr(tree);
    }
    let locator = qcsg_csg::line_locator(&analysis.sources);
    qcsg_csg::dag_to_text(dag, &locator);
    qcsg_csg::dag_to_json(dag, &name);
    qcsg_csg::dnf_to_text(dnf, &locator);
    let json = qcsg_csg::dnf_to_json(dnf, &name);
    serde_json::from_str::<serde_json::Value>(&json)
        .map_err(|error| Problem::invariant("the DNF's JSON does not parse", error.to_string()))?;
    Ok(Some(()))
}

fn sample(pool: &rayon::ThreadPool, dnf: &Dnf, radius: Radius) -> StageResult<()> {
    if dnf.terms.is_empty() {
        return Ok(None);
    }
    let diagonal = (dnf.bounds.max - dnf.bounds.min).length();
    let radius = match radius {
        Radius::Absolute(r) => r,
        // As `qcsg sample`: a percentage of an unbounded solid is a usage error.
        Radius::OfDiagonal(_) if !diagonal.is_finite() => return Ok(None),
        Radius::OfDiagonal(fraction) => fraction * diagonal,
    };
    let limits = SampleLimits {
        max_samples: MAX_SAMPLES,
        max_queries: MAX_QUERIES,
    };
    // Crossed limits and invalid radii are reported to the user by `qcsg sample`: not failures.
    let Ok(sampling) = pool.install(|| sample_with_limits(dnf, radius, limits, &|_| {})) else {
        return Ok(None);
    };
    if let Some(bad) = sampling
        .samples
        .iter()
        .find(|s| !(s.position.is_finite() && s.normal.is_finite() && s.radius.is_finite()))
    {
        return Err(Problem::invariant(
            "a sample is not finite",
            format!("{bad:?}"),
        ));
    }
    Ok(Some(()))
}

fn render(pool: &rayon::ThreadPool, mut dag: Dag) -> StageResult<()> {
    let Ok(scene) = Scene::from_dag(&mut dag, &DnfOptions::default()) else {
        return Ok(None);
    };
    let Ok(size) = ImageSize::new(IMAGE.0, IMAGE.1) else {
        return Ok(None);
    };
    let Ok(camera) = Camera::fit(&View::Iso, Projection::Perspective, &scene.bounds(), size) else {
        return Ok(None);
    };
    let frame = pool
        .install(|| qcsg_render::render(&scene, &camera, size, &RenderOptions::default(), &|_| {}));
    qcsg_render::png::encode(&frame).map_err(|error| {
        Problem::invariant("the frame does not encode as PNG", error.to_string())
    })?;
    Ok(Some(()))
}

/// The injected faults of the harness's own tests.
fn inject(fault: Fault) -> StageResult<()> {
    match fault {
        Fault::Panic => panic!("injected panic"),
        Fault::Hang => {
            let mut x = 1u64;
            loop {
                x = std::hint::black_box(x.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1));
            }
        }
        Fault::Stall => loop {
            std::thread::sleep(Duration::from_millis(50));
        },
        // One allocation far past any address-space limit, as a runaway size computation
        // makes: the allocator fails and the process aborts.
        Fault::Memory => {
            // `black_box` of the vector too: an optimised build may elide an unused allocation.
            let huge: Vec<u8> =
                std::hint::black_box(Vec::with_capacity(std::hint::black_box(1 << 42)));
            Ok(Some(()).filter(|_| huge.capacity() > 0))
        }
        Fault::StackOverflow => {
            fn deeper(n: u64) -> u64 {
                if n == u64::MAX {
                    return 0;
                }
                let pad = std::hint::black_box([n; 64]);
                deeper(pad[3] + 1) + pad[7]
            }
            Ok(Some(()).filter(|_| deeper(0) > 0))
        }
        Fault::Abort => std::process::abort(),
    }
}
