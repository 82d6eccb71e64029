//! Time to an image: for each benchmark scene and peer, from the source file to a 1920×1080
//! image accurate to a pixel — qcsg's ray tracer, qcsg's samples drawn by the CPU splat model,
//! OpenSCAD's preview PNG and its CGAL export, and Manifold's and build123d's mesh times as
//! lower bounds of a mesh pipeline.

use std::fmt::Write as _;
use std::path::Path;
use std::time::{Duration, Instant};

use qcsg_bench::image::{Agreement, camera_for, ray_traced, splat};
use qcsg_bench::openscad::{Display, Export, preview_png};
use qcsg_bench::pipeline::compile_file;
use qcsg_csg::DnfOptions;
use qcsg_render::ImageSize;
use qcsg_sample::sample;

use crate::peers::{PeerRow, PythonScene};
use crate::{Scene, ms, sci, secs};

/// The image size of this section.
pub const SIZE: (u32, u32) = (1920, 1080);

/// One peer's way to the image of one scene.
pub struct Way {
    /// Who, and how.
    pub peer: String,
    /// The setting used and its error in pixels ("–" where not measured).
    pub setting: String,
    /// Time from the source to the image (or the lower bound), `None` where not measured.
    pub time: Option<Duration>,
    /// What the time covers, or why there is none.
    pub note: String,
}

/// One scene's ways to its image.
pub struct SceneImage {
    /// The scene.
    pub name: String,
    /// A pixel's size in world units, over the diagonal.
    pub pixel: f64,
    /// qcsg's ray tracer first.
    pub ways: Vec<Way>,
}

/// The peer rows of a sweep, the coarsest whose Hausdorff distance is at most `pixel`; else the
/// finest measured, marked as short of a pixel.
fn at_pixel(rows: &[PeerRow], pixel: f64) -> Option<(&PeerRow, bool)> {
    if let Some(r) = rows.iter().find(|r| r.measured() && r.hausdorff() <= pixel) {
        return Some((r, true));
    }
    rows.iter()
        .filter(|r| r.measured())
        .min_by(|a, b| a.hausdorff().total_cmp(&b.hausdorff()))
        .map(|r| (r, false))
}

fn setting_text(r: &PeerRow, reached: bool, pixel: f64) -> String {
    format!(
        "{} ({:.2} px{})",
        r.setting,
        r.hausdorff() / pixel,
        if reached {
            ""
        } else {
            ", the finest of the sweep"
        }
    )
}

/// Measures every way for every scene.
#[allow(clippy::too_many_arguments)]
pub fn measure(
    scenes: &[Scene],
    openscad: Option<(&Path, &[Vec<PeerRow>])>,
    display: Option<&Display>,
    manifold: Option<&[PythonScene]>,
    build123d: Option<&[PythonScene]>,
    work: &Path,
    limit: Duration,
) -> Result<Vec<SceneImage>, String> {
    let size = ImageSize::new(SIZE.0, SIZE.1).map_err(|e| e.to_string())?;
    let mut out = Vec::new();
    for (k, scene) in scenes.iter().enumerate() {
        let camera = camera_for(&scene.dnf, size).ok_or("no camera")?;
        let pixel = camera.pixel_footprint(1.0, size);
        let mut ways = Vec::new();

        // qcsg: the source to the DNF, then the ray tracer.
        let start = Instant::now();
        let compiled = compile_file(&scene.path, &DnfOptions::default())?;
        let dnf = compiled.dnf.ok_or("the scene no longer compiles")?;
        let front = start.elapsed();
        let (frame, trace) = ray_traced(&dnf, &camera, size);
        ways.push(Way {
            peer: "qcsg ray tracer".into(),
            setting: "exact".into(),
            time: Some(front + trace),
            note: format!("check + DNF {} ms, trace {} ms", ms(front), ms(trace)),
        });

        // qcsg: samples at a pixel's radius, drawn by the CPU splat model.
        let start = Instant::now();
        let sampling = sample(&dnf, pixel).map_err(|e| e.to_string())?;
        let sampled = start.elapsed();
        let start = Instant::now();
        let drawn = splat(&dnf, &sampling.samples, &camera, size);
        let drawing = start.elapsed();
        let agreement = Agreement::compare(&frame, &drawn.pixels, 1e-6 * scene.diag);
        ways.push(Way {
            peer: "qcsg samples + CPU splat model".into(),
            setting: format!("r = 1 px, {} samples", sampling.samples.len()),
            time: Some(front + sampled + drawing),
            note: format!(
                "sampling {} ms, splats {} ms; {} pixels differ from the ray tracer's",
                ms(sampled),
                ms(drawing),
                agreement.holes + agreement.spill + agreement.wrong_quadric
            ),
        });

        // OpenSCAD: preview and CGAL export at the coarsest $fn within a pixel.
        match openscad {
            Some((program, sweeps)) => {
                let rows = sweeps.get(k).map_or(&[][..], Vec::as_slice);
                match at_pixel(rows, pixel) {
                    Some((row, reached)) => {
                        let fn_value: u32 = row.setting.parse().unwrap_or(0);
                        let setting = setting_text(row, reached, pixel);
                        match display {
                            Some(display) => {
                                let (time, note) = match preview_png(
                                    program,
                                    &scene.path,
                                    fn_value,
                                    SIZE,
                                    display,
                                    work,
                                    limit,
                                ) {
                                    Export::Done(_, t) => {
                                        (Some(t), "preview (OpenCSG) PNG, process time".into())
                                    }
                                    Export::TimedOut(t) => {
                                        (None, format!("timed out after {:.0} s", secs(t)))
                                    }
                                    Export::Failed(e) => (None, format!("failed: {e}")),
                                };
                                ways.push(Way {
                                    peer: "OpenSCAD preview".into(),
                                    setting: setting.clone(),
                                    time,
                                    note,
                                });
                            }
                            None => ways.push(Way {
                                peer: "OpenSCAD preview".into(),
                                setting: setting.clone(),
                                time: None,
                                note: "not measured: no Xvfb (apt-get install xvfb)".into(),
                            }),
                        }
                        ways.push(Way {
                            peer: "OpenSCAD CGAL export (mesh only)".into(),
                            setting,
                            time: Some(row.time),
                            note: "STL export of section 2, process time; an image needs more"
                                .into(),
                        });
                    }
                    None => ways.push(Way {
                        peer: "OpenSCAD".into(),
                        setting: "–".into(),
                        time: None,
                        note: "no measured export".into(),
                    }),
                }
            }
            None => ways.push(Way {
                peer: "OpenSCAD".into(),
                setting: "–".into(),
                time: None,
                note: "not measured: OpenSCAD is not installed".into(),
            }),
        }

        for (name, runs) in [("Manifold", manifold), ("build123d", build123d)] {
            let Some(runs) = runs else {
                ways.push(Way {
                    peer: format!("{name} (mesh only)"),
                    setting: "–".into(),
                    time: None,
                    note: "not measured: not installed (section 2)".into(),
                });
                continue;
            };
            let run = &runs[k];
            match at_pixel(&run.rows, pixel) {
                Some((row, reached)) => {
                    let exact = run.exact.map_or(Duration::ZERO, |e| e.0);
                    ways.push(Way {
                        peer: format!("{name} (mesh only)"),
                        setting: setting_text(row, reached, pixel),
                        time: Some(exact + row.time),
                        note: if run.exact.is_some() {
                            format!(
                                "exact boolean {} ms + tessellation and STL {} ms, in the script; \
                                 a lower bound",
                                ms(exact),
                                ms(row.time)
                            )
                        } else {
                            "mesh booleans and mesh out, in the script; a lower bound".into()
                        },
                    });
                }
                None => ways.push(Way {
                    peer: format!("{name} (mesh only)"),
                    setting: "–".into(),
                    time: None,
                    note: "no measured mesh".into(),
                }),
            }
        }
        eprintln!("time to an image: {} done", scene.name);
        out.push(SceneImage {
            name: scene.name.clone(),
            pixel: pixel / scene.diag,
            ways,
        });
    }
    Ok(out)
}

/// The section.
pub fn write(md: &mut String, images: &[SceneImage]) {
    let _ = writeln!(md, "## 3. Time to a {}×{} image\n", SIZE.0, SIZE.1);
    let _ = writeln!(
        md,
        "From the source file to an image of {w}×{h} pixels whose geometry is accurate to a pixel \
         (the isometric orthographic camera fitted to the scene; a pixel's size is given per \
         scene). qcsg: the check, evaluation and DNF, then the exact ray tracer on all threads; or \
         the samples at a radius of one pixel (all threads) drawn by the CPU splat model (a CPU \
         stand-in for the GPU splat renderer; this machine has no GPU), with its pixels compared \
         to the ray tracer's. Mesh peers: the coarsest setting of section 2's sweep whose \
         Hausdorff distance is at most a pixel (else the finest, marked). OpenSCAD's preview is \
         `openscad -o scene.png --imgsize={w},{h}` under a virtual X display (Xvfb, Mesa's \
         software OpenGL), timed as a process; its CGAL export and the Python peers' meshes are \
         lower bounds for a mesh pipeline's image (no image is drawn from them). Ratios are over \
         qcsg's ray tracer in the same run.\n",
        w = SIZE.0,
        h = SIZE.1
    );
    for s in images {
        let _ = writeln!(
            md,
            "### {} (a pixel is {} of the diagonal)\n",
            s.name,
            sci(s.pixel)
        );
        let _ = writeln!(
            md,
            "| way | setting (error) | ms | ratio to qcsg ray tracer | what the time covers |"
        );
        let _ = writeln!(md, "|---|---|---:|---:|---|");
        let base = s.ways.first().and_then(|w| w.time);
        for w in &s.ways {
            let (t, ratio) = match (w.time, base) {
                (Some(t), Some(b)) => (ms(t), format!("{:.2}", secs(t) / secs(b).max(1e-9))),
                (Some(t), None) => (ms(t), "–".into()),
                (None, _) => ("not measured".into(), "–".into()),
            };
            let _ = writeln!(
                md,
                "| {} | {} | {t} | {ratio} | {} |",
                w.peer,
                w.setting,
                w.note.replace('|', "/")
            );
        }
        let _ = writeln!(md);
    }
}
