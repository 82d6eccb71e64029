//! The headless GPU: adapter selection (no surface), the device, the splat pipeline, and
//! errors reported by wgpu turned into [`SplatError`]s.

use std::fmt;
use std::sync::{Arc, Mutex};

use crate::SplatError;

/// The colour target that receives each pixel's ray parameter, as the bits of an `f32`: an
/// integer format every backend can render to (OpenGL ES renders to `R32Float` only with an
/// extension, which Mesa's llvmpipe lacks through GL).
pub(crate) const DEPTH_T_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;
/// The colour target that receives each pixel's quadric and term.
pub(crate) const IDS_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg32Uint;
/// The depth buffer.
pub(crate) const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// Which adapters may be used.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AdapterRequirement {
    /// Any adapter, software rasterisers (Mesa's llvmpipe, lavapipe) included.
    Any,
    /// Only a hardware GPU (integrated, discrete or virtual).
    Hardware,
    /// Only a software rasteriser (Mesa's lavapipe or llvmpipe): the splat renderer on the CPU.
    Software,
}

/// What the renderer runs on, for messages and reports.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AdapterSummary {
    /// The adapter's name, e.g. `llvmpipe (LLVM 15.0.6, 256 bits)`.
    pub name: String,
    /// The graphics API: `Vulkan`, `Gl`, ...
    pub backend: String,
    /// Whether it is a software rasteriser running on the CPU.
    pub software: bool,
}

impl fmt::Display for AdapterSummary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let kind = if self.software {
            "software"
        } else {
            "hardware"
        };
        write!(f, "{} ({}, {kind})", self.name, self.backend)
    }
}

/// Errors wgpu reported through its callbacks since they were last taken.
#[derive(Clone, Default)]
pub(crate) struct ErrorSink {
    errors: Arc<Mutex<Vec<SplatError>>>,
}

impl ErrorSink {
    fn push(&self, error: SplatError) {
        if let Ok(mut errors) = self.errors.lock() {
            errors.push(error);
        }
    }

    /// The first error reported since the last call, if any.
    pub(crate) fn take(&self) -> Result<(), SplatError> {
        let Ok(mut errors) = self.errors.lock() else {
            return Err(SplatError::Gpu("the error log was poisoned".into()));
        };
        let first = errors.drain(..).next();
        first.map_or(Ok(()), Err)
    }
}

/// An open device with the splat pipeline.
pub(crate) struct Gpu {
    pub(crate) device: wgpu::Device,
    pub(crate) queue: wgpu::Queue,
    pub(crate) pipeline: wgpu::RenderPipeline,
    pub(crate) bind_group_layout: wgpu::BindGroupLayout,
    pub(crate) limits: wgpu::Limits,
    pub(crate) summary: AdapterSummary,
    pub(crate) errors: ErrorSink,
}

/// How much an adapter is preferred: hardware first, then compliant Vulkan over GL.
fn preference(info: &wgpu::AdapterInfo) -> (u8, u8) {
    let kind = match info.device_type {
        wgpu::DeviceType::DiscreteGpu => 4,
        wgpu::DeviceType::IntegratedGpu => 3,
        wgpu::DeviceType::VirtualGpu => 2,
        wgpu::DeviceType::Cpu => 1,
        wgpu::DeviceType::Other => 0,
    };
    let backend = match info.backend {
        wgpu::Backend::Vulkan | wgpu::Backend::Metal | wgpu::Backend::Dx12 => 1,
        _ => 0,
    };
    (kind, backend)
}

fn is_software(info: &wgpu::AdapterInfo) -> bool {
    matches!(
        info.device_type,
        wgpu::DeviceType::Cpu | wgpu::DeviceType::Other
    )
}

impl Gpu {
    /// Opens the most preferred adapter that meets `requirement` and can run the pipeline.
    /// The backends searched are those of the `WGPU_BACKEND` environment variable when set
    /// (e.g. `vulkan`, `gl`), otherwise Vulkan (Metal, DX12) and then, except for
    /// [`AdapterRequirement::Hardware`], GL.
    pub(crate) fn open(requirement: AdapterRequirement) -> Result<Self, SplatError> {
        // Vulkan, Metal and DX12 first; GL only when they offer nothing usable, and never for
        // a hardware GPU (every current hardware driver offers one of the others, and probing
        // GL's platforms without a display is slow and prints to standard error).
        let rounds = match wgpu::Backends::from_env() {
            Some(backends) => vec![backends],
            None if requirement == AdapterRequirement::Hardware => vec![wgpu::Backends::PRIMARY],
            None => vec![wgpu::Backends::PRIMARY, wgpu::Backends::SECONDARY],
        };
        let mut rejected = Vec::new();
        for backends in rounds {
            let mut descriptor = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
            descriptor.backends = backends;
            let instance = wgpu::Instance::new(descriptor);
            let mut adapters = pollster::block_on(instance.enumerate_adapters(backends));
            adapters.sort_by_key(|adapter| std::cmp::Reverse(preference(&adapter.get_info())));
            for adapter in adapters {
                let info = adapter.get_info();
                let software = is_software(&info);
                match requirement {
                    AdapterRequirement::Hardware if software => {
                        rejected.push(format!("{} (software)", info.name));
                        continue;
                    }
                    AdapterRequirement::Software if !software => {
                        rejected.push(format!("{} (hardware)", info.name));
                        continue;
                    }
                    _ => {}
                }
                let downlevel = adapter.get_downlevel_capabilities();
                if !downlevel
                    .flags
                    .contains(wgpu::DownlevelFlags::FRAGMENT_STORAGE)
                {
                    rejected.push(format!(
                        "{} (no storage buffers in fragment shaders)",
                        info.name
                    ));
                    continue;
                }
                match Self::open_adapter(&adapter, &info) {
                    Ok(gpu) => return Ok(gpu),
                    Err(error) => rejected.push(format!("{} ({error})", info.name)),
                }
            }
        }
        Err(SplatError::NoAdapter {
            requirement,
            rejected,
        })
    }

    fn open_adapter(adapter: &wgpu::Adapter, info: &wgpu::AdapterInfo) -> Result<Self, SplatError> {
        let limits = adapter.limits();
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("qcsg-splat"),
            required_features: wgpu::Features::empty(),
            required_limits: limits.clone(),
            ..Default::default()
        }))
        .map_err(|error| SplatError::Gpu(error.to_string()))?;
        let errors = ErrorSink::default();
        let sink = errors.clone();
        device.on_uncaptured_error(Arc::new(move |error: wgpu::Error| {
            sink.push(match error {
                wgpu::Error::OutOfMemory { .. } => SplatError::OutOfMemory,
                other => SplatError::Gpu(other.to_string()),
            });
        }));
        let sink = errors.clone();
        device.set_device_lost_callback(move |reason, message| {
            if reason != wgpu::DeviceLostReason::Destroyed {
                sink.push(SplatError::DeviceLost(message));
            }
        });

        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("splat.wgsl"),
            source: wgpu::ShaderSource::Wgsl(include_str!("splat.wgsl").into()),
        });
        let storage = |binding| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only: true },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let bind_group_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("splat bindings"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
                storage(1),
                storage(2),
            ],
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("splat layout"),
            bind_group_layouts: &[Some(&bind_group_layout)],
            immediate_size: 0,
        });
        let attributes = wgpu::vertex_attr_array![
            0 => Float32x4,
            1 => Float32x4,
            2 => Float32x4,
            3 => Float32x4,
            4 => Uint32x4,
        ];
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("splats"),
            layout: Some(&layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: crate::splats::INSTANCE_BYTES as u64,
                    step_mode: wgpu::VertexStepMode::Instance,
                    attributes: &attributes,
                })],
            },
            primitive: wgpu::PrimitiveState {
                topology: wgpu::PrimitiveTopology::TriangleList,
                front_face: wgpu::FrontFace::Ccw,
                // The back faces of a convex box cover its whole projection exactly once, also
                // when the eye is inside the box.
                cull_mode: Some(wgpu::Face::Front),
                ..Default::default()
            },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_main"),
                compilation_options: Default::default(),
                targets: &[
                    Some(wgpu::ColorTargetState {
                        format: DEPTH_T_FORMAT,
                        blend: None,
                        write_mask: wgpu::ColorWrites::ALL,
                    }),
                    Some(wgpu::ColorTargetState {
                        format: IDS_FORMAT,
                        blend: None,
                        write_mask: wgpu::ColorWrites::ALL,
                    }),
                ],
            }),
            multiview_mask: None,
            cache: None,
        });
        errors.take()?;
        Ok(Self {
            device,
            queue,
            pipeline,
            bind_group_layout,
            limits,
            summary: AdapterSummary {
                name: info.name.clone(),
                backend: format!("{:?}", info.backend),
                software: is_software(info),
            },
            errors,
        })
    }
}
