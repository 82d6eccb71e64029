//! `qcsg render FILE -o OUT.png`: a preview image of the program's solid.
//!
//! The program is checked and evaluated, its DAG turned into the DNF of the solid plus the
//! translucent `#` and `%` parts, and rendered by one of two renderers that show the same
//! image: the exact CPU ray tracer (`qcsg-render`) or the splat renderer on a GPU
//! (`qcsg-splat`). The PNG is written through a temporary file and a rename, so a failed run
//! leaves no partial file.
//!
//! Choosing the renderer ([`Choice`]): `--device auto` (the default) uses the splat renderer
//! when a *hardware* GPU adapter exists and the CPU ray tracer otherwise; a software adapter
//! (Mesa's lavapipe or llvmpipe) does not count, since rasterising splats on the CPU is slower
//! than ray tracing there. `--device gpu` insists on a hardware adapter; `--renderer splat`
//! takes any adapter, and with `--device cpu` a software one. `--renderer raytrace` runs on the
//! CPU only. A request that cannot be met is a usage error, never a silent fallback; the
//! renderer and device used are said on standard error.

use std::io::Write;
use std::path::Path;
use std::time::Instant;

use clap::{Args, ValueEnum};
use qcsg_driver::Stage;
use qcsg_render::{Camera, ImageSize, Projection, RenderOptions, Scene, View};
use qcsg_splat::{AdapterRequirement, SplatRenderer};

use crate::compile::LimitArgs;
use crate::program;
use crate::progress::DelayedProgress;
use crate::{CommonArgs, EXIT_INPUT_ERRORS, EXIT_OK, EXIT_USAGE};

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

    /// The renderer: splats on a GPU adapter, or the exact CPU ray tracer. Unset, `--device`
    /// decides.
    #[arg(long, value_enum)]
    renderer: Option<Renderer>,

    /// Where to render: `auto` uses splats on a hardware GPU when there is one and the CPU ray
    /// tracer otherwise; `gpu` requires a hardware GPU; `cpu` the CPU (the ray tracer, or with
    /// `--renderer splat` a software adapter such as Mesa's lavapipe).
    #[arg(long, value_enum, default_value_t = Device::Auto)]
    device: Device,

    #[command(flatten)]
    limits: LimitArgs,

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
pub(crate) enum Renderer {
    /// Surface splats with local quadric ray tracing on the GPU.
    Splat,
    /// The exact CSG ray tracer on the CPU.
    Raytrace,
}

/// `--device`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum Device {
    /// A hardware GPU when there is one, the CPU otherwise.
    Auto,
    /// A hardware GPU.
    Gpu,
    /// The CPU.
    Cpu,
}

/// The renderer a run uses, with the reason for a fallback.
pub(crate) enum Choice {
    /// The CPU ray tracer; for `auto`, why no GPU was used.
    RayTracer { fallback: Option<String> },
    /// The splat renderer on an open adapter.
    Splats(Box<SplatRenderer>),
}

/// Resolves `--renderer` and `--device` (see the module docs); `Err` is a usage error.
pub(crate) fn choose(renderer: Option<Renderer>, device: Device) -> Result<Choice, String> {
    let open = |requirement| SplatRenderer::new(requirement).map(|r| Choice::Splats(Box::new(r)));
    match (renderer, device) {
        (Some(Renderer::Raytrace), Device::Gpu) => {
            Err("the ray tracer runs on the CPU only; use `--renderer splat` for the GPU".into())
        }
        (Some(Renderer::Raytrace), _) | (None, Device::Cpu) => {
            Ok(Choice::RayTracer { fallback: None })
        }
        (None, Device::Auto) => {
            Ok(
                open(AdapterRequirement::Hardware).unwrap_or_else(|error| Choice::RayTracer {
                    fallback: Some(error.to_string()),
                }),
            )
        }
        (_, Device::Gpu) => open(AdapterRequirement::Hardware).map_err(|e| e.to_string()),
        (Some(Renderer::Splat), Device::Auto) => {
            open(AdapterRequirement::Any).map_err(|e| e.to_string())
        }
        (Some(Renderer::Splat), Device::Cpu) => {
            open(AdapterRequirement::Software).map_err(|e| e.to_string())
        }
    }
}

fn parse_size(text: &str) -> Result<ImageSize, String> {
    ImageSize::parse(text).map_err(|e| e.to_string())
}

fn parse_view(text: &str) -> Result<View, String> {
    View::parse(text).map_err(|e| e.to_string())
}

/// Runs `qcsg render` and returns the process exit status.
pub fn run(args: RenderArgs) -> u8 {
    let (name, text) = match program::read(&args.file) {
        Ok(input) => input,
        Err(message) => {
            eprintln!("error: {message}");
            return EXIT_USAGE;
        }
    };
    let options = args.limits.options(&args.common.defines);
    let compilation = program::compile(&name, text, &options, Stage::Dnf);
    let analysis = compilation.analysis;
    let scene = compilation.layers.map(Scene::from_layers);
    program::print_diagnostics(
        &analysis,
        args.common.quiet,
        args.common.format,
        args.output != "-",
    );
    let Some(scene) = scene.filter(|_| !analysis.has_errors()) else {
        return EXIT_INPUT_ERRORS;
    };

    let pool = match program::thread_pool(args.common.threads) {
        Ok(pool) => pool,
        Err(message) => {
            eprintln!("error: {message}");
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
    let choice = match choose(args.renderer, args.device) {
        Ok(choice) => choice,
        Err(message) => {
            eprintln!("error: {message}");
            return EXIT_USAGE;
        }
    };
    let options = RenderOptions::default();
    let (frame, how) = match &choice {
        Choice::RayTracer { fallback } => {
            let progress = DelayedProgress::new(
                "rendering",
                u64::from(args.size.height()),
                !args.common.quiet,
            );
            let frame = pool.install(|| {
                qcsg_render::render(&scene, &camera, args.size, &options, &|_| progress.inc(1))
            });
            progress.finish();
            let why = fallback
                .as_ref()
                .map_or(String::new(), |why| format!("; {why}"));
            let how = format!(
                "with the CPU ray tracer (device: cpu, {} threads{why})",
                pool.current_num_threads()
            );
            (frame, how)
        }
        Choice::Splats(renderer) => {
            match pool.install(|| renderer.render(&scene, &camera, args.size, &options)) {
                Ok(frame) => {
                    let adapter = renderer.adapter();
                    let device = if adapter.software { "cpu" } else { "gpu" };
                    let how =
                        format!("with the splat renderer (device: {device}, adapter: {adapter})");
                    (frame, how)
                }
                Err(error) => {
                    eprintln!("error: the splat renderer failed: {error}");
                    return EXIT_USAGE;
                }
            }
        }
    };
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
            "rendered {}x{} {how}, {} quadrics, in {:.2} s",
            args.size.width(),
            args.size.height(),
            scene.quadric_count(),
            started.elapsed().as_secs_f64()
        );
    }
    EXIT_OK
}
