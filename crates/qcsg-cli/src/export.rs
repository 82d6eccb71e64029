//! `qcsg export FILE -o OUT.{stl,obj,off,3mf} [--tolerance T|P%] [--ascii]`: a watertight,
//! outward-oriented triangle mesh of the solid within `T` of its exact surface both ways
//! (`qcsg-export`, `docs/export.md`).
//!
//! The program is compiled to its DNF as `sample` does; the mesh is built, checked against the
//! exact surface and refined where the check fails; the file is written through a temporary
//! file and a rename, so a failed run leaves none. The format follows the extension.

use std::time::Instant;

use clap::Args;
use qcsg_diag::Diagnostic;
use qcsg_driver::Stage;
use qcsg_export::formats::{self, Format};
use qcsg_export::{ExportError, ExportOptions, Progress, export};
use qcsg_sema::Analysis;

use crate::compile::LimitArgs;
use crate::program;
use crate::progress::DelayedProgress;
use crate::sample::{RadiusArg, limit_diagnostic, parse_radius, write_output};
use crate::{CommonArgs, EXIT_INPUT_ERRORS, EXIT_OK, EXIT_USAGE};

/// Arguments of `qcsg export`.
#[derive(Debug, Args)]
pub struct ExportArgs {
    /// The program (`.qcsg` or `.scad`); `-` reads standard input.
    #[arg(value_name = "FILE")]
    file: String,

    /// The mesh file; its extension picks the format: `.stl` (binary unless `--ascii`),
    /// `.obj`, `.off`, `.3mf`.
    #[arg(short = 'o', value_name = "OUT")]
    output: String,

    /// The largest distance between the mesh and the exact surface, both ways: a length
    /// (`0.01`) or a percentage of the bounding-box diagonal (`0.1%`, the default).
    #[arg(long, value_name = "T", value_parser = parse_radius)]
    tolerance: Option<RadiusArg>,

    /// Write STL as text (f64 coordinates) instead of binary float32.
    #[arg(long)]
    ascii: bool,

    /// Skip the check against the exact surface (and the refinement it drives): faster, but
    /// the tolerance then rests on the construction's bounds alone.
    #[arg(long)]
    no_verify: bool,

    /// Most triangles of the mesh, and of one surface's mesh.
    #[arg(long, value_name = "N", default_value_t = qcsg_export::DEFAULT_MAX_TRIANGLES)]
    max_triangles: u64,

    /// Most samples the check may take (as `qcsg sample --max-samples`).
    #[arg(long, value_name = "N", default_value_t = qcsg_sample::DEFAULT_MAX_SAMPLES)]
    max_samples: u64,

    #[command(flatten)]
    limits: LimitArgs,

    #[command(flatten)]
    common: CommonArgs,
}

/// Runs `qcsg export` and returns the process exit status.
pub fn run(args: ExportArgs) -> u8 {
    let Some(format) = Format::from_extension(&args.output, args.ascii) else {
        eprintln!(
            "error: `{}` has no mesh extension: use one of {}",
            args.output,
            Format::EXTENSIONS
                .iter()
                .map(|e| format!(".{e}"))
                .collect::<Vec<_>>()
                .join(", ")
        );
        return EXIT_USAGE;
    };
    let (name, text) = match program::read(&args.file) {
        Ok(input) => input,
        Err(message) => {
            eprintln!("error: {message}");
            return EXIT_USAGE;
        }
    };
    let options = args.limits.options(&args.common.defines);
    let compilation = program::compile(&name, text, &options, Stage::Dnf);
    let (mut analysis, dnf) = (
        compilation.analysis,
        compilation.layers.and_then(|l| l.solid),
    );
    let print = |analysis: &Analysis| {
        program::print_diagnostics(analysis, args.common.quiet, args.common.format, true)
    };
    let Some(dnf) = dnf.filter(|_| !analysis.has_errors()) else {
        print(&analysis);
        return EXIT_INPUT_ERRORS;
    };
    let diagonal = (dnf.bounds.max - dnf.bounds.min).length();
    let tolerance = match args.tolerance.unwrap_or(RadiusArg::OfDiagonal(
        qcsg_export::DEFAULT_TOLERANCE_FRACTION,
    )) {
        RadiusArg::Absolute(t) => t,
        RadiusArg::OfDiagonal(_) if dnf.terms.is_empty() => 1.0,
        RadiusArg::OfDiagonal(f) if diagonal.is_finite() => f * diagonal,
        RadiusArg::OfDiagonal(_) => {
            print(&analysis);
            eprintln!(
                "error: the solid is unbounded, so it has no finite mesh; bound it (e.g. \
                 intersect it with a cube)"
            );
            return EXIT_INPUT_ERRORS;
        }
    };
    if !(tolerance.is_finite() && tolerance > 0.0) {
        print(&analysis);
        eprintln!(
            "error: the tolerance as a percentage of the diagonal ({diagonal}) comes to \
             {tolerance}, not a positive finite length; give a length instead"
        );
        return EXIT_USAGE;
    }
    let pool = match program::thread_pool(args.common.threads) {
        Ok(pool) => pool,
        Err(message) => {
            print(&analysis);
            eprintln!("error: {message}");
            return EXIT_USAGE;
        }
    };
    let mut export_options = ExportOptions::new(tolerance);
    export_options.max_triangles = args.max_triangles;
    export_options.verify = !args.no_verify;
    export_options.sample_limits.max_samples = args.max_samples;

    let started = Instant::now();
    let bar = DelayedProgress::new("meshing", 0, !args.common.quiet);
    let result = pool.install(|| {
        export(&dnf, &export_options, &|event| match event {
            Progress::Pass { terms } => bar.add_length(terms),
            Progress::TermDone => bar.inc(1),
            Progress::Checking => {}
        })
    });
    bar.finish();
    let seconds = started.elapsed().as_secs_f64();
    let exported = match result {
        Ok(exported) => exported,
        Err(error) => {
            if let Some(diagnostic) = error_diagnostic(&dnf, &error) {
                analysis.diagnostics.push(diagnostic);
            }
            print(&analysis);
            eprintln!("error: {error}");
            return EXIT_INPUT_ERRORS;
        }
    };
    print(&analysis);
    let bytes = match formats::write(&exported.mesh, format) {
        Ok(bytes) => bytes,
        Err(e) => {
            eprintln!("error: cannot encode the mesh: {e}");
            return EXIT_USAGE;
        }
    };
    if let Err(message) = write_output(&args.output, &bytes) {
        eprintln!("error: {message}");
        return EXIT_USAGE;
    }
    if !args.common.quiet {
        let checked = match exported.deviation {
            Some(d) => format!(
                "within {:.3e} of the surface (checked: surface to mesh ≤ {:.3e}, mesh to \
                 surface ≤ {:.3e})",
                tolerance, d.surface_to_mesh, d.mesh_to_surface
            ),
            None => format!("meshed to {tolerance:.3e} per surface (not checked)"),
        };
        eprintln!(
            "exported {} triangles, {checked}, {} pass(es), in {seconds:.2} s",
            exported.mesh.triangles.len(),
            exported.passes
        );
    }
    EXIT_OK
}

/// The export's limits as diagnostics at the surface that crossed them.
fn error_diagnostic(dnf: &qcsg_csg::Dnf, error: &ExportError) -> Option<Diagnostic> {
    match error {
        ExportError::Sampling(e) => limit_diagnostic(dnf, e),
        ExportError::TooManyTriangles {
            quadric,
            needed,
            limit,
        } => {
            let source = dnf.quadrics.get(*quadric as usize)?.source;
            Some(
                Diagnostic::error(
                    qcsg_csg::codes::TRIANGLE_LIMIT,
                    format!(
                        "meshing this surface needs about {needed} triangles, more than {limit}"
                    ),
                    source.file,
                    source.span,
                )
                .with_help(
                    "use a larger `--tolerance`, or raise the limit with `--max-triangles N`",
                ),
            )
        }
        _ => None,
    }
}
