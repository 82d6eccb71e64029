//! Images: the exact CPU ray tracer's frame as the reference, and a CPU model of splat rendering
//! from the samples (paper 000, §6) to compare with it.
//!
//! The splat model draws every sample as a disc of its radius facing the camera
//! (orthographic projection); inside the disc, each pixel's ray is intersected exactly with the
//! sample's own quadric, and the hit is kept when it lies within the sample's radius of the
//! sample and on the CSG surface (the solid changes across it) — the local ray casting and
//! clipping that make splats pixel-exact. The nearest kept hit wins. Where the samples cover the
//! visible surface, the result matches the ray tracer pixel for pixel; holes show where they do
//! not. A GPU splat renderer plugs in at the same place: [`Agreement::compare`] takes any
//! per-pixel depth and quadric buffers.

use std::time::{Duration, Instant};

use qcsg_csg::Dnf;
use qcsg_render::{Camera, Frame, ImageSize, PixelId, Projection, RenderOptions, Scene, View};
use qcsg_sample::Samples;
use rayon::prelude::*;

use crate::reference::side_step;

/// The orthographic isometric camera fitted to the DNF's box.
pub fn camera_for(dnf: &Dnf, size: ImageSize) -> Option<Camera> {
    Camera::fit(&View::Iso, Projection::Orthographic, &dnf.bounds, size).ok()
}

/// The ray tracer's frame of `dnf` and the time it took.
pub fn ray_traced(dnf: &Dnf, camera: &Camera, size: ImageSize) -> (Frame, Duration) {
    let scene = Scene::new(dnf.clone());
    let start = Instant::now();
    let frame = qcsg_render::render(&scene, camera, size, &RenderOptions::default(), &|_| {});
    (frame, start.elapsed())
}

/// Whether every depth of a frame is finite or infinite (a miss), never NaN, and every hit's
/// depth is finite.
pub fn frame_is_finite(frame: &Frame) -> bool {
    frame
        .depth
        .iter()
        .zip(&frame.ids)
        .all(|(&d, id)| !d.is_nan() && (id.term == PixelId::MISS.term || d.is_finite()))
}

/// Per-pixel depth and quadric of an image made from samples (`None`: nothing drawn).
#[derive(Clone, Debug)]
pub struct SplatFrame {
    /// The image size.
    pub size: ImageSize,
    /// Depth and quadric index per pixel, rows from the top.
    pub pixels: Vec<Option<(f64, u32)>>,
    /// Pixel rays cast against splats' quadrics.
    pub fragments: u64,
}

/// Draws `samples` as splats with exact local ray casting and CSG clipping (orthographic
/// cameras only; a perspective camera draws nothing).
pub fn splat(dnf: &Dnf, samples: &Samples, camera: &Camera, size: ImageSize) -> SplatFrame {
    let width = size.width() as usize;
    let mut frame = SplatFrame {
        size,
        pixels: vec![None; size.pixel_count()],
        fragments: 0,
    };
    if camera.projection() != Projection::Orthographic || width == 0 {
        return frame;
    }
    let corner = camera.ray(0.0, 0.0, size).origin;
    let pixel = (camera.ray(1.0, 0.0, size).origin - corner).length();
    if !(pixel.is_finite() && pixel > 0.0) {
        return frame;
    }
    let eps = side_step(dnf);
    // Rows are drawn in parallel: each row looks at the samples whose disc reaches it.
    type Row = (Vec<Option<(f64, u32)>>, u64);
    let rows: Vec<Row> = (0..size.height())
        .into_par_iter()
        .map(|y| {
            let mut row = vec![None; width];
            let mut fragments = 0u64;
            let row_centre = f64::from(y) + 0.5;
            for s in samples {
                let Some(entry) = dnf.quadrics.get(s.quadric as usize) else {
                    continue;
                };
                let offset = s.position - corner;
                let (px, py) = (
                    offset.dot(camera.right()) / pixel,
                    -offset.dot(camera.up()) / pixel,
                );
                let reach = s.radius / pixel;
                if !(px.is_finite() && py.is_finite() && reach.is_finite())
                    || (row_centre - py).abs() > reach
                {
                    continue;
                }
                let x0 = (px - reach).floor().max(0.0) as usize;
                let x1 = ((px + reach).ceil().max(0.0) as usize).min(width);
                for (x, slot) in row.iter_mut().enumerate().take(x1).skip(x0) {
                    fragments += 1;
                    let ray = camera.ray(x as f64 + 0.5, row_centre, size);
                    let q = &entry.quadric;
                    let mut roots = q.intersect_line(ray.origin, ray.direction).roots();
                    roots.sort_by(f64::total_cmp);
                    for t in roots {
                        let hit = ray.at(t);
                        if (hit - s.position).length() > s.radius {
                            continue;
                        }
                        if slot.is_some_and(|(depth, _): (f64, u32)| depth <= t) {
                            break;
                        }
                        let Some(n) = q.normal(hit) else { continue };
                        if dnf.contains(hit - eps * n) != dnf.contains(hit + eps * n) {
                            *slot = Some((t, s.quadric));
                            break;
                        }
                    }
                }
            }
            (row, fragments)
        })
        .collect();
    frame.pixels.clear();
    for (row, fragments) in rows {
        frame.pixels.extend(row);
        frame.fragments += fragments;
    }
    frame
}

/// How an image made from samples differs from the ray tracer's.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Agreement {
    /// Pixels where the ray tracer sees the solid.
    pub reference_hits: usize,
    /// Of those, pixels the samples left empty.
    pub holes: usize,
    /// Pixels drawn from samples where the ray tracer sees nothing.
    pub spill: usize,
    /// Pixels both see, with a different quadric in front.
    pub wrong_quadric: usize,
    /// Pixels both see whose depths differ by more than a millionth of the diagonal.
    pub depth_mismatch: usize,
}

impl Agreement {
    /// Compares per-pixel `(depth, quadric)` buffers with the ray tracer's frame (same camera,
    /// same size); `depth_tolerance` is in world units.
    pub fn compare(reference: &Frame, pixels: &[Option<(f64, u32)>], depth_tolerance: f64) -> Self {
        let mut a = Agreement::default();
        for ((id, &depth), drawn) in reference.ids.iter().zip(&reference.depth).zip(pixels) {
            let hit = id.term != PixelId::MISS.term;
            match (hit, drawn) {
                (true, None) => {
                    a.reference_hits += 1;
                    a.holes += 1;
                }
                (false, Some(_)) => a.spill += 1,
                (true, Some((d, q))) => {
                    a.reference_hits += 1;
                    if id.quadric != *q {
                        a.wrong_quadric += 1;
                    }
                    if (d - depth).abs() > depth_tolerance {
                        a.depth_mismatch += 1;
                    }
                }
                (false, None) => {}
            }
        }
        a
    }

    /// Pixels that differ (holes, spill, or a different quadric), as a fraction of the pixels
    /// the ray tracer sees the solid in.
    pub fn disagreement(&self) -> f64 {
        let wrong = self.holes + self.spill + self.wrong_quadric;
        if self.reference_hits == 0 {
            if wrong == 0 { 0.0 } else { 1.0 }
        } else {
            wrong as f64 / self.reference_hits as f64
        }
    }
}
