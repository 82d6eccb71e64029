//! Scaling beside the peers: plates with 16–1,024 holes, a cube minus 15–960 balls and unions
//! of 27–1,000 balls, each at the error of a pixel of a 1920×1080 image: qcsg's stages (check
//! and evaluation, DNF, sampling, ray tracing) against Manifold, build123d and OpenSCAD's CGAL
//! export, with each one's growth exponent and failures.

use std::fmt::Write as _;
use std::path::Path;
use std::time::{Duration, Instant};

use qcsg_bench::image::{camera_for, ray_traced};
use qcsg_bench::openscad::{Export, export_stl};
use qcsg_bench::pipeline::compile_source;
use qcsg_bench::plot::{Plot, Series};
use qcsg_bench::python_peer::{self, Installed, Peer};
use qcsg_bench::shape::{Shape, ball_union, cube_minus_balls, plate_with_holes};
use qcsg_csg::DnfOptions;
use qcsg_render::ImageSize;
use qcsg_sample::sample;

use crate::to_image::SIZE;
use crate::{fit_text, ms, secs};

/// A family: its name, what the count counts, its sizes, and the tree at a size.
pub struct Family {
    pub name: &'static str,
    pub unit: &'static str,
    pub sizes: Vec<usize>,
    pub make: fn(usize) -> Shape,
}

/// The three families, with all sizes or (quick) the two smallest.
pub fn families(quick: bool) -> Vec<Family> {
    let take = |v: Vec<usize>| if quick { v[..2].to_vec() } else { v };
    vec![
        Family {
            name: "plate with holes",
            unit: "holes",
            sizes: take(vec![16, 64, 256, 1024]),
            make: plate_with_holes,
        },
        Family {
            name: "cube minus balls",
            unit: "balls",
            sizes: take(vec![15, 60, 240, 960]),
            make: cube_minus_balls,
        },
        Family {
            name: "union of balls",
            unit: "balls",
            sizes: take(vec![27, 125, 343, 1000]),
            make: ball_union,
        },
    ]
}

/// One tool's result at one size: its time, or why none.
#[derive(Clone, Debug)]
pub enum Outcome {
    /// Finished, valid.
    Ok(Duration),
    /// Finished, but the tool finds its result invalid.
    Invalid(Duration),
    /// Failed, timed out or was not run; why.
    Failed(String),
    /// Not measured (the tool is missing).
    Missing,
}

impl Outcome {
    /// The table cell.
    pub fn cell(&self) -> String {
        match self {
            Outcome::Ok(t) => ms(*t),
            Outcome::Invalid(t) => format!("{} (invalid)", ms(*t)),
            Outcome::Failed(why) => why.replace('|', "/"),
            Outcome::Missing => "not measured".into(),
        }
    }

    /// The time, where the tool finished.
    pub fn time(&self) -> Option<Duration> {
        match self {
            Outcome::Ok(t) | Outcome::Invalid(t) => Some(*t),
            _ => None,
        }
    }

    fn failed(&self) -> bool {
        matches!(self, Outcome::Invalid(_) | Outcome::Failed(_))
    }
}

/// One size of one family.
pub struct SizeRow {
    pub count: usize,
    /// A pixel's size over the diagonal.
    pub pixel: f64,
    /// The segment count that keeps a circle's chord within a pixel.
    pub segments: u32,
    /// qcsg: check + evaluation, DNF, sampling, ray tracing; or why it failed.
    pub qcsg: Result<[Duration; 4], String>,
    pub samples: usize,
    pub manifold: Outcome,
    pub build123d: Outcome,
    pub openscad: Outcome,
}

impl SizeRow {
    /// qcsg's time to the image (check, DNF, ray tracer).
    pub fn qcsg_image(&self) -> Option<Duration> {
        self.qcsg.as_ref().ok().map(|t| t[0] + t[1] + t[3])
    }
}

/// The peers available to the families.
pub struct Tools<'a> {
    pub manifold: Option<&'a Installed>,
    pub build123d: Option<&'a Installed>,
    pub openscad: Option<&'a Path>,
}

/// The segment count whose chordal error on a circle of radius `r` is at most `error`, rounded
/// up to a multiple of 4 (Manifold's spheres need it).
fn segments_for(r: f64, error: f64) -> u32 {
    if r <= 0.0 {
        return 4;
    }
    let half = (1.0 - (error / r).min(1.0)).acos();
    let n = (std::f64::consts::PI / half.max(1e-9)).ceil() as u32;
    n.div_ceil(4).max(1) * 4
}

fn not_run(no_pixel: bool) -> String {
    if no_pixel {
        "not run (no pixel size without qcsg's DNF)".into()
    } else {
        "not run (a smaller size timed out)".into()
    }
}

/// Measures every family with every tool.
pub fn measure(
    families: &[Family],
    tools: &Tools,
    work: &Path,
    limit: Duration,
) -> Result<Vec<Vec<SizeRow>>, String> {
    let size = ImageSize::new(SIZE.0, SIZE.1).map_err(|e| e.to_string())?;
    let mut out = Vec::new();
    std::fs::create_dir_all(work).map_err(|e| e.to_string())?;
    for family in families {
        let mut rows = Vec::new();
        // A tool that timed out at a size is not run at larger ones.
        let mut stopped = [false; 3];
        for &count in &family.sizes {
            let shape = (family.make)(count);
            let text = shape.to_scad();
            let compiled = compile_source("family.scad", text.clone(), &DnfOptions::default());
            let front = compiled.front_end;
            let normal = compiled.normal_form;
            let codes = compiled.error_codes();
            let (qcsg, pixel, samples, pixel_world) = match compiled.dnf {
                None => (
                    Err(format!("error {}", codes.join(", "))),
                    f64::NAN,
                    0,
                    f64::NAN,
                ),
                Some(dnf) => {
                    let camera = camera_for(&dnf, size).ok_or("no camera")?;
                    let pixel = camera.pixel_footprint(1.0, size);
                    let diag = qcsg_bench::reference::diagonal(&dnf);
                    let t = Instant::now();
                    let sampled = sample(&dnf, pixel);
                    let sampling = t.elapsed();
                    let (_, trace) = ray_traced(&dnf, &camera, size);
                    match sampled {
                        Ok(s) => (
                            Ok([front, normal, sampling, trace]),
                            pixel / diag,
                            s.samples.len(),
                            pixel,
                        ),
                        Err(e) => (Err(e.to_string()), pixel / diag, 0, pixel),
                    }
                }
            };
            // Without qcsg's DNF there is no camera, so no pixel to hold the peers to.
            let no_pixel = !pixel_world.is_finite();
            let segments = if no_pixel {
                0
            } else {
                segments_for(shape.largest_radius(), pixel_world)
            };

            let manifold = match tools.manifold {
                None => Outcome::Missing,
                Some(_) if no_pixel || stopped[0] => Outcome::Failed(not_run(no_pixel)),
                Some(m) => python_outcome(m, &shape, &[f64::from(segments)], work, limit),
            };
            let build123d = match tools.build123d {
                None => Outcome::Missing,
                Some(_) if no_pixel || stopped[1] => Outcome::Failed(not_run(no_pixel)),
                Some(b) => python_outcome(b, &shape, &[pixel_world], work, limit),
            };
            let openscad = match tools.openscad {
                None => Outcome::Missing,
                Some(_) if no_pixel || stopped[2] => Outcome::Failed(not_run(no_pixel)),
                Some(program) => {
                    let path = work.join(format!("{}-{count}.scad", family.unit));
                    std::fs::write(&path, &text).map_err(|e| e.to_string())?;
                    match export_stl(program, &path, segments, work, limit) {
                        Export::Done(_, t) => Outcome::Ok(t),
                        Export::TimedOut(t) => {
                            Outcome::Failed(format!("timed out ({:.0} s)", secs(t)))
                        }
                        Export::Failed(e) => Outcome::Failed(format!("failed: {e}")),
                    }
                }
            };
            for (k, o) in [&manifold, &build123d, &openscad].iter().enumerate() {
                if matches!(o, Outcome::Failed(w) if w.starts_with("timed out")) {
                    stopped[k] = true;
                }
            }
            eprintln!(
                "{} {count}: qcsg {:?}, manifold {}, build123d {}, openscad {}",
                family.name,
                qcsg.as_ref().map(|t| secs(t[0] + t[1] + t[2] + t[3])),
                manifold.cell(),
                build123d.cell(),
                openscad.cell()
            );
            rows.push(SizeRow {
                count,
                pixel,
                segments,
                qcsg,
                samples,
                manifold,
                build123d,
                openscad,
            });
        }
        out.push(rows);
    }
    Ok(out)
}

/// A Python peer at one setting: Manifold's mesh, or build123d's exact boolean plus its
/// tessellation at a pixel.
fn python_outcome(
    installed: &Installed,
    shape: &Shape,
    settings: &[f64],
    work: &Path,
    limit: Duration,
) -> Outcome {
    let run = python_peer::run(
        installed,
        shape,
        settings,
        &work.join(installed.peer.name()),
        limit,
    );
    if let Some(why) = run.failure {
        return Outcome::Failed(if why == "timed out" {
            format!("timed out ({:.0} s)", secs(run.process))
        } else {
            format!("failed: {why}")
        });
    }
    let total: Duration = run.results.iter().map(|r| r.time).sum();
    let valid = run.results.iter().all(|r| r.valid);
    match installed.peer {
        Peer::Manifold | Peer::Build123d if valid => Outcome::Ok(total),
        _ => Outcome::Invalid(total),
    }
}

/// The section; returns the names of the plots drawn.
pub fn write(
    md: &mut String,
    families: &[Family],
    results: &[Vec<SizeRow>],
    out_dir: &Path,
    limit: Duration,
) -> Result<Vec<String>, String> {
    let mut plots = Vec::new();
    let _ = writeln!(md, "## 4. Scaling beside the peers\n");
    let _ = writeln!(
        md,
        "Three families at the error of a pixel of a {w}×{h} image of each solid (the camera of \
         section 3): qcsg checks, evaluates and builds the DNF, samples at a radius of one pixel \
         (all threads) and ray traces the image; its time to the image is check + DNF + ray \
         tracer (the samples are the splat renderer's input, timed separately). Manifold builds \
         the mesh at the segment count whose chord stays within a pixel of the largest circle \
         (rounded up to a multiple of 4); build123d makes the exact boolean, checks it and \
         tessellates it at a pixel; OpenSCAD exports the CGAL mesh at the same segment count. \
         Peer times are measured in their scripts (Manifold, build123d) or as the process \
         (OpenSCAD). Each tool has {limit:.0} s per size; after a time-out, larger sizes are not \
         run. Exponents are least-squares fits of `t = c·N^k` over the sizes that finished.\n",
        w = SIZE.0,
        h = SIZE.1,
        limit = secs(limit)
    );
    for (family, rows) in families.iter().zip(results) {
        let _ = writeln!(md, "### {}\n", family.name);
        let _ = writeln!(
            md,
            "| {} | pixel / diag | segments | qcsg check ms | DNF ms | sampling ms (samples) | ray tracer ms | qcsg to image ms | Manifold ms | build123d ms | OpenSCAD CGAL ms |",
            family.unit
        );
        let _ = writeln!(
            md,
            "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
        );
        for r in rows {
            let q = match &r.qcsg {
                Ok(t) => format!(
                    "{} | {} | {} ({}) | {} | {}",
                    ms(t[0]),
                    ms(t[1]),
                    ms(t[2]),
                    r.samples,
                    ms(t[3]),
                    ms(t[0] + t[1] + t[3])
                ),
                Err(e) => format!("{} | – | – | – | –", e.replace('|', "/")),
            };
            let _ = writeln!(
                md,
                "| {} | {} | {} | {q} | {} | {} | {} |",
                r.count,
                crate::sci(r.pixel),
                r.segments,
                r.manifold.cell(),
                r.build123d.cell(),
                r.openscad.cell()
            );
        }
        let series = |f: &dyn Fn(&SizeRow) -> Option<Duration>| -> Vec<(f64, f64)> {
            rows.iter()
                .filter_map(|r| f(r).map(|t| (r.count as f64, secs(t))))
                .collect()
        };
        let lines: Vec<(&str, Vec<(f64, f64)>)> = vec![
            ("qcsg to image", series(&SizeRow::qcsg_image)),
            (
                "qcsg sampling",
                series(&|r: &SizeRow| r.qcsg.as_ref().ok().map(|t| t[2])),
            ),
            ("Manifold", series(&|r: &SizeRow| r.manifold.time())),
            ("build123d", series(&|r: &SizeRow| r.build123d.time())),
            ("OpenSCAD CGAL", series(&|r: &SizeRow| r.openscad.time())),
        ];
        let failures = |f: &dyn Fn(&SizeRow) -> bool| rows.iter().filter(|r| f(r)).count();
        let _ = writeln!(
            md,
            "\nGrowth exponents: {}. Failures (invalid results, errors, time-outs, sizes not run \
             after one): qcsg {}, Manifold {}, build123d {}, OpenSCAD {}.\n",
            lines
                .iter()
                .map(|(n, p)| format!("{n} {}", fit_text(p)))
                .collect::<Vec<_>>()
                .join(", "),
            failures(&|r| r.qcsg.is_err()),
            failures(&|r| r.manifold.failed()),
            failures(&|r| r.build123d.failed()),
            failures(&|r| r.openscad.failed()),
        );
        let plot = Plot {
            title: format!("{}: time against size", family.name),
            x_label: family.unit.into(),
            y_label: "time (s)".into(),
            series: lines
                .iter()
                .map(|(n, p)| Series {
                    name: format!("{n} (k = {})", fit_text(p)),
                    points: p.clone(),
                })
                .collect(),
        };
        let file = format!("family_{}.svg", family.name.replace(' ', "_"));
        if plot.write_svg(&out_dir.join(&file))? {
            let _ = writeln!(md, "![{}](report/{file})\n", plot.title);
            plots.push(file);
        }
    }
    Ok(plots)
}
