//! `qcsg sample FILE --radius R [-o OUT.ply] [--ascii] [--stats [FILE]]`: samples exactly on the
//! solid's surface, every surface point within `R` of a sample on the same quadric.
//!
//! The program is checked, evaluated and turned into its DNF like `compile` does; the sampler
//! (`qcsg-sample`) runs on `--threads` workers and its output does not depend on their number.
//! The PLY (binary little-endian unless `--ascii`) and the stats file are written through a
//! temporary file and a rename, so a failed run leaves no partial file. Runs longer than a
//! second show a progress bar on a terminal.

use std::fmt::Write as _;
use std::io::Write;
use std::path::Path;
use std::time::Instant;

use clap::Args;
use qcsg_csg::{Dnf, codes};
use qcsg_diag::Diagnostic;
use qcsg_driver::Stage;
use qcsg_sample::{Progress, SampleError, SampleLimits, Sampling, sample_with_limits};
use qcsg_sema::Analysis;

use crate::compile::LimitArgs;
use crate::program;
use crate::progress::DelayedProgress;
use crate::{CommonArgs, EXIT_INPUT_ERRORS, EXIT_OK, EXIT_USAGE};

/// Arguments of `qcsg sample`.
#[derive(Debug, Args)]
pub struct SampleArgs {
    /// The program (`.qcsg` or `.scad`); `-` reads standard input.
    #[arg(value_name = "FILE")]
    file: String,

    /// Coverage radius: a length (`0.1`) or a percentage of the scene's bounding-box diagonal
    /// (`1%`).
    #[arg(long, value_name = "R", value_parser = parse_radius)]
    radius: RadiusArg,

    /// The PLY file to write (`-`: standard output); without it nothing is written.
    #[arg(short = 'o', value_name = "OUT.ply")]
    output: Option<String>,

    /// Write the PLY as text instead of binary little-endian.
    #[arg(long)]
    ascii: bool,

    /// Print counters and time as JSON, to FILE if given (`-` or nothing: standard output, or
    /// standard error when the PLY goes to standard output).
    #[arg(long, value_name = "FILE", num_args = 0..=1, default_missing_value = "-")]
    stats: Option<String>,

    #[command(flatten)]
    limits: LimitArgs,

    /// Most samples to emit: a radius far below the scene's size would need more memory than
    /// there is.
    #[arg(long, value_name = "N", default_value_t = qcsg_sample::DEFAULT_MAX_SAMPLES)]
    max_samples: u64,

    /// Most distance queries to make: surfaces that nearly coincide over an area defeat the
    /// subdivision's proofs, and the work grows as 1 / radius².
    #[arg(long, value_name = "N", default_value_t = qcsg_sample::DEFAULT_MAX_QUERIES)]
    max_queries: u64,

    #[command(flatten)]
    common: CommonArgs,
}

/// `--radius`: a length, or a fraction of the bounding-box diagonal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RadiusArg {
    /// An absolute length.
    Absolute(f64),
    /// A fraction (not a percentage) of the diagonal.
    OfDiagonal(f64),
}

/// Parses `0.1` or `1%`; the value must be positive and finite.
pub fn parse_radius(text: &str) -> Result<RadiusArg, String> {
    let trimmed = text.trim();
    let (number, percent) = match trimmed.strip_suffix('%') {
        Some(number) => (number.trim(), true),
        None => (trimmed, false),
    };
    let value: f64 = number
        .parse()
        .map_err(|_| format!("`{text}` is not a length (`0.1`) or a percentage (`1%`)"))?;
    if !(value.is_finite() && value > 0.0) {
        return Err(format!(
            "the radius must be positive and finite, got `{text}`"
        ));
    }
    Ok(if percent {
        RadiusArg::OfDiagonal(value / 100.0)
    } else {
        RadiusArg::Absolute(value)
    })
}

/// Runs `qcsg sample` and returns the process exit status.
pub fn run(args: SampleArgs) -> u8 {
    let (name, text) = match program::read(&args.file) {
        Ok(input) => input,
        Err(message) => {
            eprintln!("error: {message}");
            return EXIT_USAGE;
        }
    };
    let stdout_taken = args.output.as_deref() == Some("-");
    let stats_to_stdout = !stdout_taken && args.stats.as_deref() == Some("-");
    let options = args.limits.options(&args.common.defines);
    let compilation = program::compile(&name, text, &options, Stage::Dnf);
    let (mut analysis, dnf) = (
        compilation.analysis,
        compilation.layers.and_then(|l| l.solid),
    );
    let stdout_free = !stdout_taken && !stats_to_stdout;
    let print = |analysis: &Analysis| {
        program::print_diagnostics(analysis, args.common.quiet, args.common.format, stdout_free)
    };
    let Some(dnf) = dnf.filter(|_| !analysis.has_errors()) else {
        print(&analysis);
        return EXIT_INPUT_ERRORS;
    };

    let diagonal = (dnf.bounds.max - dnf.bounds.min).length();
    let radius = match args.radius {
        RadiusArg::Absolute(r) => r,
        RadiusArg::OfDiagonal(_) if dnf.terms.is_empty() => 0.0,
        RadiusArg::OfDiagonal(fraction) if diagonal.is_finite() => fraction * diagonal,
        RadiusArg::OfDiagonal(_) => {
            print(&analysis);
            eprintln!(
                "error: the solid is unbounded, so `--radius` cannot be a percentage of its \
                 diagonal; give a length, and bound the solid (e.g. intersect it with a cube)"
            );
            return EXIT_USAGE;
        }
    };
    // A percentage of a tiny or huge diagonal can round to no length at all.
    if (!radius.is_finite() || radius <= 0.0) && !dnf.terms.is_empty() {
        print(&analysis);
        eprintln!(
            "error: `--radius` as a percentage of the solid's diagonal ({diagonal}) comes to \
             {radius}, not a positive finite length; give a length instead"
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

    let started = Instant::now();
    let bar = DelayedProgress::new("sampling", 0, !args.common.quiet);
    let limits = SampleLimits {
        max_samples: args.max_samples,
        max_queries: args.max_queries,
    };
    let sampled = if dnf.terms.is_empty() {
        Ok(Sampling::default())
    } else {
        pool.install(|| {
            sample_with_limits(&dnf, radius, limits, &|event| match event {
                Progress::Regions { work, .. } | Progress::Refining { work, .. } => {
                    bar.add_length(work)
                }
                Progress::RegionDone { work } | Progress::RectangleRefined { work } => {
                    bar.inc(work)
                }
            })
        })
    };
    bar.finish();
    let seconds = started.elapsed().as_secs_f64();
    let sampling = match sampled {
        Ok(sampling) => sampling,
        Err(error) => match limit_diagnostic(&dnf, &error) {
            Some(diagnostic) => {
                analysis.diagnostics.push(diagnostic);
                print(&analysis);
                return EXIT_INPUT_ERRORS;
            }
            None => {
                print(&analysis);
                eprintln!("error: {error}");
                return EXIT_USAGE;
            }
        },
    };
    // Warnings, after the sampling: a crossed limit joins them as an error.
    print(&analysis);

    if let Some(output) = &args.output {
        let bytes = if args.ascii {
            ply_ascii(&sampling)
        } else {
            ply_binary(&sampling)
        };
        if let Err(message) = write_output(output, &bytes) {
            eprintln!("error: {message}");
            return EXIT_USAGE;
        }
    }
    let threads = pool.current_num_threads();
    if let Some(stats_file) = &args.stats {
        let json = stats_json(&sampling, &dnf, radius, seconds, threads);
        let written = if stats_file == "-" && stdout_taken {
            eprintln!("{json}");
            Ok(())
        } else {
            write_output(stats_file, format!("{json}\n").as_bytes())
        };
        if let Err(message) = written {
            eprintln!("error: {message}");
            return EXIT_USAGE;
        }
    }
    if !args.common.quiet {
        let stats = &sampling.stats;
        if stats.unbounded_terms > 0 {
            eprintln!(
                "warning: {} terms of the solid are unbounded and were not sampled; bound the \
                 solid (e.g. intersect it with a cube)",
                stats.unbounded_terms
            );
        }
        let unresolved = stats.unresolved();
        if unresolved > 0 {
            eprintln!(
                "warning: {unresolved} small rectangles were given up unproven: no corner or \
                 centre of theirs is on the surface down to a small fraction of the radius, and \
                 no sample is near; a sliver of surface there could be missed (see `unresolved` \
                 in --stats)"
            );
        }
        eprintln!(
            "sampled {} points (radius {radius}, {} quadrics, {} terms, {} clip indices) on {threads} threads in {seconds:.2} s",
            stats.samples,
            dnf.quadrics.len(),
            dnf.terms.len(),
            stats.clip_indices,
        );
    }
    EXIT_OK
}

/// The diagnostic of a crossed sampling limit, at the source of the quadric being sampled.
pub(crate) fn limit_diagnostic(dnf: &Dnf, error: &SampleError) -> Option<Diagnostic> {
    let (code, message, quadric, help) = match *error {
        SampleError::TooManySamples { limit, quadric } => (
            codes::SAMPLE_LIMIT,
            format!("sampling this surface needs more than {limit} samples"),
            quadric,
            "use a larger `--radius`, or raise the limit with `--max-samples N` (each sample \
             takes about 72 bytes)",
        ),
        SampleError::DistancesTooLarge { limit, quadric } => (
            codes::SAMPLE_LIMIT,
            format!(
                "the distances set up for the surfaces sampled, up to this one, need more \
                 memory than {limit} samples"
            ),
            quadric,
            "each surface's distance holds the terms near it, and many parts overlap here; \
             raise the limit with `--max-samples N` (each sample takes about 72 bytes), or \
             union fewer overlapping parts",
        ),
        SampleError::TooManyQueries { limit, quadric } => (
            codes::QUERY_LIMIT,
            format!("sampling this surface needs more than {limit} distance queries"),
            quadric,
            "surfaces that nearly coincide over an area (a gap far below the radius) cannot be \
             told apart by the subdivision; use a larger `--radius`, separate the surfaces, or \
             raise the limit with `--max-queries N`",
        ),
        SampleError::InvalidRadius(_) => return None,
    };
    let source = dnf.quadrics.get(quadric as usize)?.source;
    Some(Diagnostic::error(code, message, source.file, source.span).with_help(help))
}

/// The stats JSON of docs/cli.md: the documented keys first, then the sampler's other counters.
pub fn stats_json(
    sampling: &Sampling,
    dnf: &Dnf,
    radius: f64,
    seconds: f64,
    threads: usize,
) -> String {
    let stats = &sampling.stats;
    let subdivision = &stats.subdivision;
    serde_json::json!({
        "samples": stats.samples,
        "distance_queries": subdivision.distance_queries,
        "seconds": seconds,
        "threads": threads,
        "radius": radius,
        "quadrics": dnf.quadrics.len(),
        "terms": dnf.terms.len(),
        "clip_lists": stats.clip_lists,
        "clip_indices": stats.clip_indices,
        "basic_regions": stats.basic_regions,
        "rectangles": subdivision.rectangles,
        "unresolved": stats.unresolved(),
        "unbounded_terms": stats.unbounded_terms,
        "distance_bytes": stats.distance_bytes,
        "diagonal": (dnf.bounds.max - dnf.bounds.min).length(),
    })
    .to_string()
}

/// The PLY header for `count` vertices in `format`.
fn ply_header(format: &str, count: usize) -> String {
    format!(
        "ply\nformat {format} 1.0\ncomment qcsg surface samples\nelement vertex {count}\n\
         property double x\nproperty double y\nproperty double z\n\
         property float nx\nproperty float ny\nproperty float nz\n\
         property float radius\nproperty uint quadric\nproperty uint term\nend_header\n"
    )
}

/// Binary little-endian PLY: 48 bytes per sample.
pub fn ply_binary(sampling: &Sampling) -> Vec<u8> {
    let header = ply_header("binary_little_endian", sampling.samples.len());
    let mut bytes = Vec::with_capacity(header.len() + 48 * sampling.samples.len());
    bytes.extend_from_slice(header.as_bytes());
    for s in &sampling.samples {
        for v in s.position.to_array() {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
        for v in s.normal.to_array() {
            bytes.extend_from_slice(&(v as f32).to_le_bytes());
        }
        bytes.extend_from_slice(&(s.radius as f32).to_le_bytes());
        bytes.extend_from_slice(&s.quadric.to_le_bytes());
        bytes.extend_from_slice(&s.term.to_le_bytes());
    }
    bytes
}

/// Text PLY; positions with full precision (shortest round-trip form).
pub fn ply_ascii(sampling: &Sampling) -> Vec<u8> {
    let mut text = ply_header("ascii", sampling.samples.len());
    for s in &sampling.samples {
        let p = s.position;
        let n = s.normal.as_vec3();
        let _ = writeln!(
            text,
            "{:?} {:?} {:?} {:?} {:?} {:?} {:?} {} {}",
            p.x, p.y, p.z, n.x, n.y, n.z, s.radius as f32, s.quadric, s.term
        );
    }
    text.into_bytes()
}

/// Writes `bytes` to standard output (`-`) or atomically to a file.
pub(crate) fn write_output(target: &str, bytes: &[u8]) -> Result<(), String> {
    if target == "-" {
        let mut stdout = std::io::stdout().lock();
        return stdout
            .write_all(bytes)
            .and_then(|()| stdout.flush())
            .map_err(|e| format!("cannot write standard output: {e}"));
    }
    qcsg_render::png::write_atomically(Path::new(target), bytes).map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn radius_is_a_length_or_a_percentage() {
        assert_eq!(parse_radius("0.1"), Ok(RadiusArg::Absolute(0.1)));
        assert_eq!(parse_radius("2.5%"), Ok(RadiusArg::OfDiagonal(0.025)));
        for bad in ["0", "-1", "abc", "%", "1%%", "inf", "nan", "0%"] {
            assert!(parse_radius(bad).is_err(), "{bad}");
        }
    }
}
