//! The splat renderer of qcsg on wgpu (paper 000 §6 and §6.1).
//!
//! The surface of each layer of a [`Scene`] (the solid, the `#` highlighted and the `%`
//! background parts) is sampled with the coverage guarantee of `qcsg-sample` ([`PreparedScene`]).
//! Every sample is drawn, instanced, as the back faces of a box aligned with the surface at the
//! sample: half extent `r` along two tangents and a rigorous bound on the surface's departure
//! from the tangent plane along the normal ([`splats`]). The fragment shader ray-traces the
//! sample's own quadric locally, keeps the hit nearest the eye that lies within `r` of the
//! sample and inside every quadric of the sample's clip list, and writes the hit's exact ray
//! parameter as depth, with the quadric and the term. Since every point of the CSG surface has a
//! sample on its quadric within `r`, and its box contains that part of the surface, every
//! visible surface point is found; clipping removes the rest (§6, steps 1-3).
//!
//! The GPU only finds *what* each pixel sees and *where*; the colour is made on the CPU from
//! the read-back depth and ids, by the same shading code as the reference ray tracer
//! ([`qcsg_render::shade_pixel`]), with the normal computed in f64 from the quadric. The result
//! is a [`qcsg_render::Frame`], so PNG output and comparisons are shared with the ray tracer.
//!
//! Precision (§6): the CPU works in f64; f32 reaches the GPU only relative to local origins —
//! sample positions and quadric origins relative to the eye, the sample's own quadric re-expanded
//! about the sample. A scene translated by 10⁶ renders like the same scene at the origin.
//!
//! Rendering is headless (no window or surface): offscreen targets are copied to buffers with
//! rows padded to 256 bytes, mapped and read back. Adapter selection ([`AdapterRequirement`])
//! honours `WGPU_BACKEND` (`vulkan`, `gl`, ...); without a GPU, Mesa's lavapipe (Vulkan) or
//! llvmpipe (GL) serve as software adapters.
//!
//! Differences from the reference that are by design: faces of a term's box (solids cut by the
//! DNF's region) carry no samples and are not drawn.

pub mod compare;
mod gpu;
pub mod splats;

use std::fmt;
use std::sync::mpsc;

use qcsg_quadric::DVec3;
use qcsg_render::frame::frame_from_pixels;
use qcsg_render::scene::Layer;
use qcsg_render::{
    Camera, Frame, Hit, ImageSize, LayerHits, Projection, RenderOptions, Scene, shade_pixel,
};

pub use crate::gpu::{AdapterRequirement, AdapterSummary};
use crate::gpu::{DEPTH_FORMAT, DEPTH_T_FORMAT, Gpu, IDS_FORMAT};
pub use crate::splats::{SampledLayer, splat_radius};

/// Why the splat renderer cannot render.
#[derive(Clone, Debug, PartialEq)]
pub enum SplatError {
    /// No adapter meets the requirement; `rejected` lists the adapters seen and why.
    NoAdapter {
        /// Which adapters were acceptable.
        requirement: AdapterRequirement,
        /// The adapters found but not usable, with the reason.
        rejected: Vec<String>,
    },
    /// The device was lost (driver reset, GPU removed).
    DeviceLost(String),
    /// The GPU ran out of memory.
    OutOfMemory,
    /// More samples than the adapter's buffers can hold.
    TooManySamples {
        /// The samples of the largest layer.
        samples: usize,
        /// The most the adapter allows.
        limit: usize,
    },
    /// The image is larger than the adapter's textures can be.
    ImageTooLarge {
        /// The requested size.
        size: ImageSize,
        /// The adapter's largest texture dimension.
        limit: u32,
    },
    /// The scene has no bounds to derive a splat radius from, or the radius is invalid.
    Sampling(String),
    /// Any other error reported by the GPU.
    Gpu(String),
}

impl fmt::Display for SplatError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NoAdapter {
                requirement,
                rejected,
            } => {
                let what = match requirement {
                    AdapterRequirement::Hardware => "no hardware GPU adapter found",
                    AdapterRequirement::Software => {
                        "no software GPU adapter found (such as Mesa's lavapipe or llvmpipe)"
                    }
                    AdapterRequirement::Any => {
                        "no GPU adapter found (not even a software one such as Mesa's lavapipe or llvmpipe)"
                    }
                };
                write!(f, "{what}")?;
                if !rejected.is_empty() {
                    write!(f, "; unusable: {}", rejected.join(", "))?;
                }
                Ok(())
            }
            Self::DeviceLost(message) => write!(f, "the GPU device was lost: {message}"),
            Self::OutOfMemory => write!(f, "the GPU ran out of memory"),
            Self::TooManySamples { samples, limit } => write!(
                f,
                "{samples} splats exceed the adapter's buffer limit of {limit}; use a larger radius"
            ),
            Self::ImageTooLarge { size, limit } => write!(
                f,
                "a {}x{} image exceeds the adapter's texture limit of {limit} pixels",
                size.width(),
                size.height()
            ),
            Self::Sampling(message) => write!(f, "cannot sample the scene: {message}"),
            Self::Gpu(message) => write!(f, "GPU error: {message}"),
        }
    }
}

impl std::error::Error for SplatError {}

/// The samples of every layer of a scene, view-independent: sample once, render many views.
#[derive(Clone, Debug)]
pub struct PreparedScene {
    radius: f64,
    layers: [Option<SampledLayer>; 3],
}

impl PreparedScene {
    /// Samples every layer of `scene` at `radius`.
    pub fn new(scene: &Scene, radius: f64) -> Result<Self, SplatError> {
        let sample = |layer: &Option<Layer>| -> Result<Option<SampledLayer>, SplatError> {
            layer
                .as_ref()
                .map(|layer| SampledLayer::new(layer, radius))
                .transpose()
        };
        Ok(Self {
            radius,
            layers: [
                sample(&scene.solid)?,
                sample(&scene.highlights)?,
                sample(&scene.backgrounds)?,
            ],
        })
    }

    /// The radius it was sampled at.
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// Samples over all layers.
    pub fn sample_count(&self) -> usize {
        self.layers.iter().flatten().map(|l| l.samples.len()).sum()
    }

    /// Quadric indices in the clip lists over all layers (paper Table 2's "#clip").
    pub fn clip_index_count(&self) -> usize {
        self.layers
            .iter()
            .flatten()
            .map(|l| l.clip_lists.indices.len())
            .sum()
    }
}

/// What the GPU found for one layer: per pixel the ray parameter (f32) and `[quadric, term]`,
/// `u32::MAX` for a miss.
struct LayerImage {
    t: Vec<f32>,
    ids: Vec<[u32; 2]>,
}

/// The splat renderer on one GPU adapter.
pub struct SplatRenderer {
    gpu: Gpu,
}

impl fmt::Debug for SplatRenderer {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("SplatRenderer")
            .field("adapter", &self.gpu.summary)
            .finish()
    }
}

/// The indices of the splat box's 12 triangles, counter-clockwise seen from outside; corner `k`
/// has coordinates `(k & 1, k >> 1 & 1, k >> 2 & 1)` mapped to `±1` (see `splat.wgsl`).
fn box_indices() -> Vec<u16> {
    let mut indices = Vec::with_capacity(36);
    for axis in 0..3 {
        let (b, c) = ((axis + 1) % 3, (axis + 2) % 3);
        for side in [0u16, 1] {
            let corner = |u: u16, v: u16| (side << axis) | (u << b) | (v << c);
            let mut quad = [corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)];
            // (e_b × e_c) = e_axis: the order above faces +axis; the −axis side is reversed.
            if side == 0 {
                quad.reverse();
            }
            indices.extend([quad[0], quad[1], quad[2], quad[0], quad[2], quad[3]]);
        }
    }
    indices
}

impl SplatRenderer {
    /// Opens the best adapter that meets `requirement` (see [`AdapterRequirement`]).
    pub fn new(requirement: AdapterRequirement) -> Result<Self, SplatError> {
        Ok(Self {
            gpu: Gpu::open(requirement)?,
        })
    }

    /// The adapter in use.
    pub fn adapter(&self) -> &AdapterSummary {
        &self.gpu.summary
    }

    /// Renders `scene`, sampled at the radius [`splat_radius`] picks for this view.
    pub fn render(
        &self,
        scene: &Scene,
        camera: &Camera,
        size: ImageSize,
        options: &RenderOptions,
    ) -> Result<Frame, SplatError> {
        let Some(radius) = splat_radius(scene, camera, size) else {
            // Nothing bounded to draw: the background alone, as the ray tracer shows it.
            return Ok(qcsg_render::render(scene, camera, size, options, &|_| {}));
        };
        let prepared = PreparedScene::new(scene, radius)?;
        self.render_prepared(scene, &prepared, camera, size, options)
    }

    /// Renders `scene` from samples prepared earlier (by [`PreparedScene::new`] on the same
    /// scene).
    pub fn render_prepared(
        &self,
        scene: &Scene,
        prepared: &PreparedScene,
        camera: &Camera,
        size: ImageSize,
        options: &RenderOptions,
    ) -> Result<Frame, SplatError> {
        let limit = self.gpu.limits.max_texture_dimension_2d;
        if size.width() > limit || size.height() > limit {
            return Err(SplatError::ImageTooLarge { size, limit });
        }
        let layers = [&scene.solid, &scene.highlights, &scene.backgrounds];
        let mut images: [Option<LayerImage>; 3] = [None, None, None];
        for ((image, layer), sampled) in images.iter_mut().zip(layers).zip(&prepared.layers) {
            if let (Some(layer), Some(sampled)) = (layer, sampled) {
                *image = Some(self.draw_layer(scene, layer, sampled, camera, size, prepared)?);
            }
        }
        let width = size.width() as usize;
        Ok(frame_from_pixels(size, &|x, y| {
            let index = y as usize * width + x as usize;
            let ray = camera.ray(f64::from(x) + 0.5, f64::from(y) + 0.5, size);
            let hits = LayerHits {
                solid: hit_of(&scene.solid, &images[0], index, &ray),
                highlight: hit_of(&scene.highlights, &images[1], index, &ray),
                background: hit_of(&scene.backgrounds, &images[2], index, &ray),
            };
            shade_pixel(scene, camera, options, &ray, &hits)
        }))
    }

    /// Draws the splats of one layer and reads back its ray parameters and ids.
    fn draw_layer(
        &self,
        scene: &Scene,
        layer: &Layer,
        sampled: &SampledLayer,
        camera: &Camera,
        size: ImageSize,
        prepared: &PreparedScene,
    ) -> Result<LayerImage, SplatError> {
        let gpu = &self.gpu;
        let device = &gpu.device;
        let eye = camera.eye();

        let instance_limit =
            (gpu.limits.max_buffer_size as usize / splats::INSTANCE_BYTES).min(u32::MAX as usize);
        if sampled.samples.len() > instance_limit {
            return Err(SplatError::TooManySamples {
                samples: sampled.samples.len(),
                limit: instance_limit,
            });
        }

        let (near, far) = splats::depth_range(scene, camera, 2.0 * prepared.radius);
        let mut view = Vec::with_capacity(64);
        let push = |bytes: &mut Vec<u8>, v: DVec3, w: f64| {
            for value in [v.x, v.y, v.z, w] {
                bytes.extend((value as f32).to_le_bytes());
            }
        };
        push(
            &mut view,
            camera.right(),
            1.0 / (camera.half_height() * camera.aspect()),
        );
        push(&mut view, camera.up(), 1.0 / camera.half_height());
        let perspective = camera.projection() == Projection::Perspective;
        push(
            &mut view,
            camera.forward(),
            if perspective { 1.0 } else { 0.0 },
        );
        push(&mut view, DVec3::new(near, far, 1.0 / (far - near)), 0.0);

        let buffer = |label: &str, contents: &[u8], usage: wgpu::BufferUsages| {
            let buffer = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: contents.len().max(16) as u64,
                usage: usage | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            gpu.queue.write_buffer(&buffer, 0, contents);
            buffer
        };
        let view_buffer = buffer("view", &view, wgpu::BufferUsages::UNIFORM);
        let quadric_buffer = buffer(
            "quadrics",
            &splats::quadric_bytes(layer.dnf(), eye),
            wgpu::BufferUsages::STORAGE,
        );
        let clip_bytes: Vec<u8> = sampled
            .clip_lists
            .indices
            .iter()
            .flat_map(|i| i.to_le_bytes())
            .collect();
        let clip_buffer = buffer("clip lists", &clip_bytes, wgpu::BufferUsages::STORAGE);
        let instance_buffer = buffer(
            "splats",
            &sampled.instance_bytes(eye),
            wgpu::BufferUsages::VERTEX,
        );
        let index_bytes: Vec<u8> = box_indices().iter().flat_map(|i| i.to_le_bytes()).collect();
        let index_buffer = buffer("box", &index_bytes, wgpu::BufferUsages::INDEX);
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("splat bindings"),
            layout: &gpu.bind_group_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: view_buffer.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: quadric_buffer.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: clip_buffer.as_entire_binding(),
                },
            ],
        });

        let extent = wgpu::Extent3d {
            width: size.width(),
            height: size.height(),
            depth_or_array_layers: 1,
        };
        let target = |label: &str, format: wgpu::TextureFormat| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: extent,
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
                view_formats: &[],
            })
        };
        let t_texture = target("ray parameters", DEPTH_T_FORMAT);
        let ids_texture = target("ids", IDS_FORMAT);
        let depth_texture = target("depth", DEPTH_FORMAT);
        let t_view = t_texture.create_view(&Default::default());
        let ids_view = ids_texture.create_view(&Default::default());
        let depth_view = depth_texture.create_view(&Default::default());

        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("splats"),
                color_attachments: &[
                    Some(wgpu::RenderPassColorAttachment {
                        view: &t_view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                            store: wgpu::StoreOp::Store,
                        },
                    }),
                    Some(wgpu::RenderPassColorAttachment {
                        view: &ids_view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(wgpu::Color {
                                r: f64::from(u32::MAX),
                                g: f64::from(u32::MAX),
                                b: 0.0,
                                a: 0.0,
                            }),
                            store: wgpu::StoreOp::Store,
                        },
                    }),
                ],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &depth_view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Discard,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            if !sampled.samples.is_empty() {
                pass.set_pipeline(&gpu.pipeline);
                pass.set_bind_group(0, &bind_group, &[]);
                pass.set_vertex_buffer(0, instance_buffer.slice(..));
                pass.set_index_buffer(index_buffer.slice(..), wgpu::IndexFormat::Uint16);
                pass.draw_indexed(0..36, 0, 0..sampled.samples.len() as u32);
            }
        }
        let t_read = ReadBack::new(device, &mut encoder, &t_texture, extent, 4);
        let ids_read = ReadBack::new(device, &mut encoder, &ids_texture, extent, 8);
        gpu.queue.submit([encoder.finish()]);
        gpu.errors.take()?;

        let t_bytes = t_read.read(gpu)?;
        let ids_bytes = ids_read.read(gpu)?;
        gpu.errors.take()?;
        let word = |b: &[u8]| [b[0], b[1], b[2], b[3]];
        Ok(LayerImage {
            t: t_bytes
                .chunks_exact(4)
                .map(|b| f32::from_le_bytes(word(b)))
                .collect(),
            ids: ids_bytes
                .chunks_exact(8)
                .map(|b| {
                    [
                        u32::from_le_bytes(word(&b[..4])),
                        u32::from_le_bytes(word(&b[4..])),
                    ]
                })
                .collect(),
        })
    }
}

/// The hit a layer's read-back shows at pixel `index`, if any.
fn hit_of(
    layer: &Option<Layer>,
    image: &Option<LayerImage>,
    index: usize,
    ray: &qcsg_render::Ray,
) -> Option<Hit> {
    let (layer, image) = (layer.as_ref()?, image.as_ref()?);
    let [quadric, term] = *image.ids.get(index)?;
    if term == u32::MAX {
        return None;
    }
    Hit::on_quadric(layer.dnf(), ray, f64::from(image.t[index]), quadric, term)
}

/// A texture copied into a buffer with rows padded to `COPY_BYTES_PER_ROW_ALIGNMENT`.
struct ReadBack {
    buffer: wgpu::Buffer,
    row_bytes: usize,
    padded_row_bytes: usize,
    rows: usize,
}

impl ReadBack {
    fn new(
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        texture: &wgpu::Texture,
        extent: wgpu::Extent3d,
        pixel_bytes: usize,
    ) -> Self {
        let row_bytes = extent.width as usize * pixel_bytes;
        let align = wgpu::COPY_BYTES_PER_ROW_ALIGNMENT as usize;
        let padded_row_bytes = row_bytes.div_ceil(align) * align;
        let rows = extent.height as usize;
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("read-back"),
            size: (padded_row_bytes * rows) as u64,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        encoder.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &buffer,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(padded_row_bytes as u32),
                    rows_per_image: Some(extent.height),
                },
            },
            extent,
        );
        Self {
            buffer,
            row_bytes,
            padded_row_bytes,
            rows,
        }
    }

    /// Maps the buffer and returns the rows without their padding.
    fn read(self, gpu: &Gpu) -> Result<Vec<u8>, SplatError> {
        let (sender, receiver) = mpsc::channel();
        self.buffer
            .map_async(wgpu::MapMode::Read, .., move |result| {
                // The receiver outlives the poll below; a failed send only means it gave up.
                let _ = sender.send(result);
            });
        gpu.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|error| SplatError::Gpu(error.to_string()))?;
        gpu.errors.take()?;
        receiver
            .recv()
            .map_err(|_| SplatError::Gpu("the read-back was never mapped".into()))?
            .map_err(|error| SplatError::Gpu(error.to_string()))?;
        let mapped = self
            .buffer
            .get_mapped_range(..)
            .map_err(|error| SplatError::Gpu(error.to_string()))?;
        let mut out = Vec::with_capacity(self.row_bytes * self.rows);
        for row in mapped.chunks_exact(self.padded_row_bytes).take(self.rows) {
            out.extend_from_slice(&row[..self.row_bytes]);
        }
        drop(mapped);
        self.buffer.unmap();
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_triangles_face_outwards() {
        let corner = |k: u16| {
            DVec3::new(
                f64::from(k & 1),
                f64::from((k >> 1) & 1),
                f64::from((k >> 2) & 1),
            ) * 2.0
                - DVec3::ONE
        };
        let indices = box_indices();
        assert_eq!(indices.len(), 36);
        for triangle in indices.chunks_exact(3) {
            let [a, b, c] = [0, 1, 2].map(|i| corner(triangle[i]));
            let normal = (b - a).cross(c - a);
            let centre = (a + b + c) / 3.0;
            assert!(normal.dot(centre) > 0.0, "{triangle:?} faces inwards");
        }
    }
}
