//! Orbit frames of the CPU ray tracer alone, as `qcsg view` asks for them while the mouse turns
//! the solid: 24 perspective frames at 640×480 around the iso view, in a circle at the eye's
//! height (as `tests/view/bench.py` asks them through HTTP), plus the four named views in both
//! projections. Prints frames per second per scene and, with `--hashes FILE`, writes one hash
//! of every frame's pixels, depths and ids, so that two builds can be compared byte for byte:
//!
//! ```sh
//! cargo run --release -p qcsg-render --example orbit_frames -- --hashes before.txt examples/*.qcsg
//! # change the ray tracer, then
//! cargo run --release -p qcsg-render --example orbit_frames -- --hashes after.txt examples/*.qcsg
//! cmp before.txt after.txt
//! ```
//!
//! Options: `--frames N` (24), `--size WxH` (640x480), `--rounds N` (1: the best round counts).

use std::collections::hash_map::DefaultHasher;
use std::hash::{Hash, Hasher};
use std::io::Write;
use std::time::Instant;

use qcsg_driver::{Options, Stage, compile};
use qcsg_quadric::DVec3;
use qcsg_render::{Camera, Frame, ImageSize, Projection, RenderOptions, Scene, View, render};
use qcsg_sema::FsLoader;

struct Args {
    frames: u32,
    size: ImageSize,
    rounds: u32,
    hashes: Option<String>,
    files: Vec<String>,
}

fn parse_args() -> Result<Args, String> {
    let mut args = Args {
        frames: 24,
        size: ImageSize::new(640, 480).map_err(|e| e.to_string())?,
        rounds: 1,
        hashes: None,
        files: Vec::new(),
    };
    let mut it = std::env::args().skip(1);
    while let Some(arg) = it.next() {
        let mut value = || it.next().ok_or(format!("{arg} needs a value"));
        match arg.as_str() {
            "--frames" => args.frames = value()?.parse().map_err(|_| "bad --frames")?,
            "--rounds" => args.rounds = value()?.parse().map_err(|_| "bad --rounds")?,
            "--size" => args.size = ImageSize::parse(&value()?).map_err(|e| e.to_string())?,
            "--hashes" => args.hashes = Some(value()?),
            // `cargo bench` passes this to every bench target; the example ignores it.
            "--bench" => {}
            file => args.files.push(file.to_owned()),
        }
    }
    Ok(args)
}

fn hash_frame(frame: &Frame) -> u64 {
    let mut hasher = DefaultHasher::new();
    frame.rgb.hash(&mut hasher);
    for depth in &frame.depth {
        depth.to_bits().hash(&mut hasher);
    }
    frame.ids.hash(&mut hasher);
    hasher.finish()
}

/// The process's CPU time (user and system, all threads) in seconds, where `/proc` tells it.
fn cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // The fields after the command's closing parenthesis; utime and stime are the 12th and 13th.
    let fields: Vec<&str> = stat.rsplit_once(')')?.1.split_whitespace().collect();
    let ticks: f64 = fields.get(11)?.parse::<f64>().ok()? + fields.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}

fn main() {
    let args = match parse_args() {
        Ok(args) => args,
        Err(message) => {
            eprintln!("error: {message}");
            std::process::exit(2);
        }
    };
    let mut hashes = args.hashes.as_ref().map(|path| {
        std::io::BufWriter::new(std::fs::File::create(path).expect("the hash file can be written"))
    });
    let options = Options::from_env(Vec::new());
    let mut total_frames = 0u32;
    let mut total_seconds = 0.0;
    for file in &args.files {
        let text = match std::fs::read_to_string(file) {
            Ok(text) => text,
            Err(error) => {
                eprintln!("{file}: {error}");
                continue;
            }
        };
        let compilation = compile(file, text, &options, &FsLoader, Stage::Dnf);
        let Some(layers) = compilation
            .layers
            .filter(|_| !compilation.analysis.has_errors())
        else {
            eprintln!("{file}: does not compile");
            continue;
        };
        let scene = Scene::from_layers(layers);
        let bounds = scene.bounds();
        let center = if bounds.is_empty() || !bounds.is_bounded() {
            DVec3::ZERO
        } else {
            bounds.centre()
        };
        let Ok(iso) = Camera::fit(&View::Iso, Projection::Perspective, &bounds, args.size) else {
            eprintln!("{file}: no camera");
            continue;
        };
        let eye = iso.eye();
        let d = eye - center;
        let radius = d.x.hypot(d.y);
        let cameras: Vec<Camera> = (0..args.frames)
            .filter_map(|i| {
                let angle = d.y.atan2(d.x)
                    + 2.0 * std::f64::consts::PI * f64::from(i) / f64::from(args.frames);
                let at = DVec3::new(
                    center.x + radius * angle.cos(),
                    center.y + radius * angle.sin(),
                    eye.z,
                );
                let view = View::Explicit { eye: at, center };
                Camera::fit(&view, Projection::Perspective, &bounds, args.size).ok()
            })
            .collect();
        let mut best = f64::INFINITY;
        let mut best_cpu = f64::INFINITY;
        let mut frames = Vec::new();
        for _ in 0..args.rounds.max(1) {
            let started = Instant::now();
            let cpu_before = cpu_seconds();
            frames = cameras
                .iter()
                .map(|camera| {
                    render(
                        &scene,
                        camera,
                        args.size,
                        &RenderOptions::default(),
                        &|_| {},
                    )
                })
                .collect();
            best = best.min(started.elapsed().as_secs_f64());
            if let (Some(before), Some(after)) = (cpu_before, cpu_seconds()) {
                best_cpu = best_cpu.min(after - before);
            }
        }
        total_frames += cameras.len() as u32;
        total_seconds += best;
        let per_frame = |seconds: f64| 1000.0 * seconds / f64::from(cameras.len().max(1) as u32);
        println!(
            "{file}: {} quadrics, {:.1} frames/s ({:.1} ms per frame, CPU {:.0} ms per frame)",
            scene.quadric_count(),
            f64::from(cameras.len() as u32) / best,
            per_frame(best),
            per_frame(best_cpu)
        );
        if let Some(out) = &mut hashes {
            for (i, frame) in frames.iter().enumerate() {
                let _ = writeln!(out, "{file} orbit {i} {:016x}", hash_frame(frame));
            }
            for view in [View::Iso, View::Front, View::Top, View::Right] {
                for projection in [Projection::Perspective, Projection::Orthographic] {
                    if let Ok(camera) = Camera::fit(&view, projection, &bounds, args.size) {
                        let frame = render(
                            &scene,
                            &camera,
                            args.size,
                            &RenderOptions::default(),
                            &|_| {},
                        );
                        let _ = writeln!(
                            out,
                            "{file} {view:?} {projection:?} {:016x}",
                            hash_frame(&frame)
                        );
                    }
                }
            }
        }
    }
    if total_seconds > 0.0 {
        println!(
            "all: {total_frames} frames in {total_seconds:.2} s, {:.1} frames/s",
            f64::from(total_frames) / total_seconds
        );
    }
}
