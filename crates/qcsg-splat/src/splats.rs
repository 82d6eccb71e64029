//! The CPU side of the splats: sampling a layer, the splat radius, the surface-aligned box of
//! every splat (§6.1) and the f32 data uploaded per frame (§6: relative to local origins).

use qcsg_csg::Dnf;
use qcsg_quadric::DVec3;
use qcsg_render::scene::Layer;
use qcsg_render::{Camera, ImageSize, Projection, Scene};
use qcsg_sample::{ClipLists, Sample, Samples};

use crate::SplatError;

/// Bytes per splat instance: four `vec4<f32>` and one `vec4<u32>` (see `splat.wgsl`).
pub(crate) const INSTANCE_BYTES: usize = 80;
/// Bytes per quadric in the quadric buffer: four `vec4<f32>`.
pub(crate) const QUADRIC_BYTES: usize = 64;

/// The splat radius as a fraction of the scene's bounding-box diagonal. The sampler's cost
/// falls steeply with a growing radius while its sample count barely changes (features and
/// small regions dominate it), so a coarse radius is fastest overall: at 1920x1080 on Mesa's
/// lavapipe, `chess_bishop` samples in 0.4 s at 1/10 of the diagonal and in 158 s at 6 pixels,
/// and draws in about the same time.
pub const RADIUS_OF_DIAGONAL: f64 = 0.1;

/// The radius in pixels at the scene's centre never exceeds this (it bounds overdraw in
/// close-ups) ...
const MAX_RADIUS_PIXELS: f64 = 100.0;
/// ... nor falls below this (for scenes that are small in the image).
const MIN_RADIUS_PIXELS: f64 = 6.0;
/// The radius never falls below this fraction of the diagonal, whatever the view.
const MIN_RADIUS_OF_DIAGONAL: f64 = 1.0 / 3000.0;

/// The box's extent along the normal gets this fraction of the radius as slack, for the f32
/// rounding of the box and of the sample's own value.
const HEIGHT_SLACK: f64 = 1e-3;

/// The sample radius for rendering `scene` through `camera` at `size`: [`RADIUS_OF_DIAGONAL`]
/// of the scene's bounding-box diagonal, kept between 6 and 100 pixels at the distance of the
/// scene's centre, and above 1/3000 of the diagonal. Any positive radius renders the same image
/// (the sampler's guarantee holds for every radius); the radius only trades sampling time
/// against overdraw. `None` for a scene without bounds.
pub fn splat_radius(scene: &Scene, camera: &Camera, size: ImageSize) -> Option<f64> {
    let bounds = scene.bounds();
    if bounds.is_empty() || !bounds.is_bounded() {
        return None;
    }
    let diagonal = 2.0 * bounds.half_diagonal();
    let distance = (bounds.centre() - camera.eye()).dot(camera.forward()).abs();
    let footprint = camera.pixel_footprint(distance, size);
    let radius = (RADIUS_OF_DIAGONAL * diagonal)
        .min(MAX_RADIUS_PIXELS * footprint)
        .max(MIN_RADIUS_PIXELS * footprint)
        .max(MIN_RADIUS_OF_DIAGONAL * diagonal);
    (radius.is_finite() && radius > 0.0).then_some(radius)
}

/// The samples of one layer and the view-independent part of their instance data.
#[derive(Clone, Debug)]
pub struct SampledLayer {
    /// The samples.
    pub samples: Samples,
    /// Their deduplicated clip lists.
    pub clip_lists: ClipLists,
    /// Per sample: (tangent, half height along the normal).
    boxes: Vec<(DVec3, f64)>,
    /// Per sample: the own quadric about the sample, half-linear vector and constant.
    local_quadrics: Vec<(DVec3, f64)>,
}

impl SampledLayer {
    /// Samples `layer` at `radius`.
    pub fn new(layer: &Layer, radius: f64) -> Result<Self, SplatError> {
        let dnf = layer.dnf();
        let sampling = qcsg_sample::sample(dnf, radius)
            .map_err(|error| SplatError::Sampling(error.to_string()))?;
        let boxes = sampling
            .samples
            .iter()
            .map(|sample| splat_box(dnf, sample))
            .collect();
        let local_quadrics = sampling
            .samples
            .iter()
            .map(|sample| {
                let moved = dnf.quadrics[sample.quadric as usize]
                    .quadric
                    .with_origin(sample.position);
                (moved.linear(), moved.constant())
            })
            .collect();
        Ok(Self {
            samples: sampling.samples,
            clip_lists: sampling.clip_lists,
            boxes,
            local_quadrics,
        })
    }

    /// The instance buffer for a camera at `eye`: per sample, its position relative to the eye
    /// (rounded to f32 only after the f64 subtraction), radius, box and ids.
    pub(crate) fn instance_bytes(&self, eye: DVec3) -> Vec<u8> {
        let mut bytes = Vec::with_capacity(self.samples.len() * INSTANCE_BYTES);
        for ((sample, &(tangent, height)), &(linear, constant)) in self
            .samples
            .iter()
            .zip(&self.boxes)
            .zip(&self.local_quadrics)
        {
            let list = self.clip_lists.offsets.get(sample.clip_list as usize);
            let next = self.clip_lists.offsets.get(sample.clip_list as usize + 1);
            let (first, count) = match (list, next) {
                (Some(&first), Some(&next)) => (first, next.saturating_sub(first)),
                _ => (0, 0),
            };
            push_f32s(&mut bytes, sample.position - eye, sample.radius);
            push_f32s(&mut bytes, tangent, height);
            push_f32s(&mut bytes, sample.normal, 0.0);
            push_f32s(&mut bytes, linear, constant);
            for id in [sample.quadric, sample.term, first, count] {
                bytes.extend(id.to_le_bytes());
            }
        }
        bytes
    }
}

/// The quadric buffer for a camera at `eye`: coefficients, and each local origin relative to
/// the eye.
pub(crate) fn quadric_bytes(dnf: &Dnf, eye: DVec3) -> Vec<u8> {
    let mut bytes = Vec::with_capacity(dnf.quadrics.len().max(1) * QUADRIC_BYTES);
    for entry in &dnf.quadrics {
        let q = &entry.quadric;
        let k = q.coefficients();
        for value in k.iter().chain(&[0.0, 0.0]) {
            bytes.extend((*value as f32).to_le_bytes());
        }
        push_f32s(&mut bytes, q.origin() - eye, 0.0);
    }
    if bytes.is_empty() {
        bytes.resize(QUADRIC_BYTES, 0);
    }
    bytes
}

fn push_f32s(bytes: &mut Vec<u8>, v: DVec3, w: f64) {
    for value in [v.x, v.y, v.z, w] {
        bytes.extend((value as f32).to_le_bytes());
    }
}

/// The surface-aligned box of a splat (paper §6.1): half extent `r` along two tangents and
/// `h` along the normal, where `h` bounds how far the quadric's surface within the radius
/// departs from the tangent plane. On the surface `q(s + x) = q(s) + ∇q(s)·x + xᵀAx = 0`, so
/// `|n·x| ≤ |xᵀAx| / |∇q(s)| ≤ λ r² / |∇q(s)|` with `λ` bounding `|A|`'s eigenvalues: a
/// rigorous bound in place of the paper's distortion-based one (eq. 23).
fn splat_box(dnf: &Dnf, sample: &Sample) -> (DVec3, f64) {
    let r = sample.radius;
    let tangent = sample.normal.any_orthonormal_vector();
    let Some(entry) = dnf.quadrics.get(sample.quadric as usize) else {
        return (tangent, r);
    };
    let q = &entry.quadric;
    let (lower, upper) = q.eigenvalue_bounds();
    let lambda = lower.abs().max(upper.abs());
    let gradient = q.gradient(sample.position).length();
    let bend = lambda * r * r / gradient;
    let height = if bend.is_finite() { bend.min(r) } else { r };
    (tangent, height + HEIGHT_SLACK * r)
}

/// The parameter range `[near, far]` of the rays that can meet `scene` grown by `margin`.
pub(crate) fn depth_range(scene: &Scene, camera: &Camera, margin: f64) -> (f64, f64) {
    let bounds = scene.bounds();
    let grown = bounds.expanded(margin);
    let eye = camera.eye();
    let depths = grown.corners().map(|corner| match camera.projection() {
        Projection::Perspective => (corner - eye).length(),
        Projection::Orthographic => (corner - eye).dot(camera.forward()),
    });
    let far = depths.iter().fold(f64::NEG_INFINITY, |m, &d| m.max(d));
    let near = match camera.projection() {
        Projection::Perspective => {
            let closest = eye.clamp(grown.min, grown.max);
            (closest - eye).length().max(far * 1e-6)
        }
        Projection::Orthographic => depths.iter().fold(f64::INFINITY, |m, &d| m.min(d)),
    };
    let far = if far > near { far } else { near + 1.0 };
    (near, far)
}
