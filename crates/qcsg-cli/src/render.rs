//! `qcsg render FILE -o OUT.png`: a preview image of the program's solid.
//!
//! The program is checked and evaluated, its DAG turned into the DNF of the solid plus the
//! translucent `#` and `%` parts, and every pixel ray traced exactly on the CPU. The PNG is
//! written through a temporary file and a rename, so a failed run leaves no partial file.
//! The splat renderer (`--renderer splat`, `--device gpu`) does not exist yet: asking for it is
//! a usage error rather than a silent fallback.

use std::io::{IsTerminal, Read, Write};
use std::path::Path;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use clap::{Args, ValueEnum};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use qcsg_csg::DnfOptions;
use qcsg_diag::Diagnostic;
use qcsg_eval::{EvalOptions, evaluate};
use qcsg_render::{Camera, ImageSize, Projection, RenderOptions, Scene, View};
use qcsg_sema::{Analysis, CheckOptions, FsLoader};

use crate::human::{HumanRenderer, summary_line};
use crate::{CommonArgs, DiagnosticFormat, EXIT_INPUT_ERRORS, EXIT_OK, EXIT_USAGE};

/// Renders that take longer than this show a progress bar (on a terminal).
const PROGRESS_DELAY: Duration = Duration::from_secs(1);

/// Arguments of `qcsg render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// The program (`.qcsg` or `.scad`); `-` reads standard input.
    #[arg(value_name = "FILE")]
    file: String,

    /// The PNG to write; `-` is standard output.
    #[arg(short = 'o', value_name = "OUT.png")]
    output: String,

    /// Image size in pixels.
    #[arg(long, value_name = "W,H", default_value = "800,600", value_parser = parse_size)]
    size: ImageSize,

    /// A named view fitted to the scene (iso, front, top, right) or
    /// `eye_x,eye_y,eye_z,center_x,center_y,center_z`.
    #[arg(long, value_name = "VIEW", default_value = "iso", value_parser = parse_view)]
    camera: View,

    /// Perspective or orthographic projection.
    #[arg(long, value_enum, default_value_t = ProjectionArg::Perspective)]
    projection: ProjectionArg,

    /// The renderer: the exact CPU ray tracer, or the splat renderer (not available yet).
    #[arg(long, value_enum)]
    renderer: Option<Renderer>,

    /// Where to render: `auto` picks the best available, today the CPU.
    #[arg(long, value_enum, default_value_t = Device::Auto)]
    device: Device,

    /// Most terms of the disjunctive normal form.
    #[arg(long, value_name = "N", default_value_t = qcsg_csg::DEFAULT_TERM_LIMIT)]
    max_terms: usize,

    #[command(flatten)]
    common: CommonArgs,
}

/// `--projection`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum ProjectionArg {
    /// Rays from the eye (30° vertical field of view).
    Perspective,
    /// Parallel rays.
    Ortho,
}

/// `--renderer`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Renderer {
    /// Surface splats with local quadric ray tracing on the GPU.
    Splat,
    /// The exact CSG ray tracer on the CPU.
    Raytrace,
}

/// `--device`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Device {
    /// The best available.
    Auto,
    /// The GPU.
    Gpu,
    /// The CPU.
    Cpu,
}

fn parse_size(text: &str) -> Result<ImageSize, String> {
    ImageSize::parse(text).map_err(|e| e.to_string())
}

fn parse_view(text: &str) -> Result<View, String> {
    View::parse(text).map_err(|e| e.to_string())
}

/// Runs `qcsg render` and returns the process exit status.
pub fn run(args: RenderArgs) -> u8 {
    if args.renderer == Some(Renderer::Splat) || args.device == Device::Gpu {
        eprintln!(
            "error: the splat renderer (GPU) is not available yet; use `--renderer raytrace` \
             or `--device cpu` (the CPU ray tracer)"
        );
        return EXIT_USAGE;
    }
    let (name, text) = match read(&args.file) {
        Ok(input) => input,
        Err(message) => {
            eprintln!("error: {message}");
            return EXIT_USAGE;
        }
    };
    let check_options = CheckOptions {
        search_path: crate::search_path_from_env(),
        defines: args.common.defines.clone(),
    };
    let mut analysis = qcsg_sema::check_file(&name, text, &check_options, &FsLoader);
    let scene = build_scene(&mut analysis, &args);
    print_diagnostics(&analysis, &args.common, args.output != "-");
    let Some(scene) = scene.filter(|_| !analysis.has_errors()) else {
        return EXIT_INPUT_ERRORS;
    };

    let pool = match rayon::ThreadPoolBuilder::new()
        .num_threads(args.common.threads.map_or(0, |n| n.get()))
        .build()
    {
        Ok(pool) => pool,
        Err(error) => {
            eprintln!("error: cannot start worker threads: {error}");
            return EXIT_USAGE;
        }
    };
    let projection = match args.projection {
        ProjectionArg::Perspective => Projection::Perspective,
        ProjectionArg::Ortho => Projection::Orthographic,
    };
    let camera = match Camera::fit(&args.camera, projection, &scene.bounds(), args.size) {
        Ok(camera) => camera,
        Err(error) => {
            eprintln!("error: {error}");
            return EXIT_USAGE;
        }
    };

    let started = Instant::now();
    let progress = Progress::new(args.size.height(), !args.common.quiet);
    let frame = pool.install(|| {
        qcsg_render::render(
            &scene,
            &camera,
            args.size,
            &RenderOptions::default(),
            &|_| progress.row_done(),
        )
    });
    progress.finish();
    let png = match qcsg_render::png::encode(&frame) {
        Ok(png) => png,
        Err(error) => {
            eprintln!("error: {error}");
            return EXIT_USAGE;
        }
    };
    let written = if args.output == "-" {
        std::io::stdout()
            .lock()
            .write_all(&png)
            .map_err(|e| format!("cannot write standard output: {e}"))
    } else {
        qcsg_render::png::write_atomically(Path::new(&args.output), &png).map_err(|e| e.to_string())
    };
    if let Err(message) = written {
        eprintln!("error: {message}");
        return EXIT_USAGE;
    }
    if !args.common.quiet {
        eprintln!(
            "rendered {}x{} with the CPU ray tracer (device: cpu, {} threads, {} quadrics) in {:.2} s",
            args.size.width(),
            args.size.height(),
            pool.current_num_threads(),
            scene.quadric_count(),
            started.elapsed().as_secs_f64()
        );
    }
    EXIT_OK
}

/// Evaluates the checked program and builds the scene; `None` after errors (in the analysis).
fn build_scene(analysis: &mut Analysis, args: &RenderArgs) -> Option<Scene> {
    if analysis.has_errors() {
        return None;
    }
    let options = EvalOptions {
        defines: args.common.defines.clone(),
        ..EvalOptions::default()
    };
    let mut evaluation = evaluate(analysis, &options);
    let failed = evaluation.has_errors();
    analysis.diagnostics.append(&mut evaluation.diagnostics);
    if failed {
        return None;
    }
    let dnf_options = DnfOptions {
        term_limit: args.max_terms,
        ..DnfOptions::default()
    };
    match Scene::from_dag(&mut evaluation.dag, &dnf_options) {
        Ok(scene) => {
            for layer in [&scene.solid, &scene.highlights, &scene.backgrounds]
                .into_iter()
                .flatten()
            {
                analysis
                    .diagnostics
                    .extend(layer.dnf().warnings.iter().cloned());
            }
            Some(scene)
        }
        Err(errors) => {
            analysis.diagnostics.extend(errors);
            None
        }
    }
}

/// A progress bar on standard error, shown only on a terminal and only once a render has taken
/// longer than [`PROGRESS_DELAY`].
struct Progress {
    bar: Option<ProgressBar>,
    started: Instant,
    shown: AtomicBool,
    show_lock: Mutex<()>,
}

impl Progress {
    fn new(rows: u32, wanted: bool) -> Self {
        let bar = (wanted && std::io::stderr().is_terminal()).then(|| {
            let bar =
                ProgressBar::with_draw_target(Some(u64::from(rows)), ProgressDrawTarget::hidden());
            if let Ok(style) =
                ProgressStyle::with_template("rendering {bar:40} {percent}% ({eta} left)")
            {
                bar.set_style(style);
            }
            bar
        });
        Self {
            bar,
            started: Instant::now(),
            shown: AtomicBool::new(false),
            show_lock: Mutex::new(()),
        }
    }

    fn row_done(&self) {
        let Some(bar) = &self.bar else {
            return;
        };
        bar.inc(1);
        if !self.shown.load(Ordering::Relaxed) && self.started.elapsed() > PROGRESS_DELAY {
            let _guard = self.show_lock.lock();
            if !self.shown.swap(true, Ordering::Relaxed) {
                bar.set_draw_target(ProgressDrawTarget::stderr());
            }
        }
    }

    fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}

/// Prints the diagnostics: JSON on standard output (standard error when that carries the PNG),
/// human-readable on standard error.
fn print_diagnostics(analysis: &Analysis, common: &CommonArgs, stdout_free: bool) {
    let shown: Vec<&Diagnostic> = analysis
        .diagnostics
        .iter()
        .filter(|d| !common.quiet || d.is_error())
        .collect();
    if common.format == DiagnosticFormat::Json {
        let elements: Vec<_> = shown
            .iter()
            .map(|d| crate::json::JsonDiagnostic::new(&analysis.sources, d))
            .collect();
        let text = crate::json::array_text(&elements);
        if stdout_free {
            print!("{text}");
        } else {
            eprint!("{text}");
        }
        return;
    }
    let stderr = std::io::stderr();
    let colour = stderr.is_terminal() && std::env::var_os("NO_COLOR").is_none_or(|v| v.is_empty());
    let renderer = HumanRenderer::for_terminal(colour);
    let mut out = String::new();
    let mut counts = [0usize; 4];
    for diagnostic in shown {
        counts[diagnostic.severity as usize] += 1;
        out.push_str(&renderer.render(&analysis.sources, diagnostic));
    }
    if !common.quiet && counts.iter().sum::<usize>() > 0 {
        out.push_str(&summary_line(counts));
        out.push('\n');
    }
    let _ = stderr.lock().write_all(out.as_bytes());
}

/// The name and text of FILE (`-`: standard input).
fn read(file: &str) -> Result<(String, String), String> {
    if file == "-" {
        let mut text = String::new();
        std::io::stdin()
            .read_to_string(&mut text)
            .map_err(|err| format!("cannot read standard input: {err}"))?;
        return Ok((crate::check::STDIN_NAME.to_owned(), text));
    }
    std::fs::read_to_string(file)
        .map(|text| (file.to_owned(), text))
        .map_err(|err| format!("cannot read `{file}`: {err}"))
}
