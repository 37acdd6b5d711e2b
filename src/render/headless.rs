//! The WGSL tracer run directly on a wgpu device, outside Bevy's renderer:
//! headless renders for the CLI, and the GPU side of the GPU/CPU agreement
//! tests. The shader and its inputs are exactly what the render pass uses.

use super::TRACE_WGSL;
use super::gpu::{GpuPixel, GpuScene};
use super::shader_defs::TraceDefs;
use crate::cell::CellId;
use crate::space::Space;
use crate::trace::{Prepared, Scene, TraceImage, TracePixel, TraceSettings};
use std::collections::HashMap;
use wgpu::util::DeviceExt;

/// Why the GPU tracer could not run.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    /// No adapter at all (no Vulkan/Metal/DX12 driver; on Debian install
    /// `mesa-vulkan-drivers` for the software one).
    #[error("no GPU adapter found ({0}); on Debian, `apt-get install mesa-vulkan-drivers` gives a software one")]
    NoAdapter(String),
    /// The adapter would not give a device.
    #[error("the GPU adapter '{adapter}' refused a device: {message}")]
    NoDevice {
        /// The adapter's name.
        adapter: String,
        /// wgpu's message.
        message: String,
    },
    /// The shader failed to compose (a bug in the shader or its defs).
    #[error("the tracer shader does not compose with defs {defs:?}: {message}")]
    Shader {
        /// The defs that were on.
        defs: Vec<&'static str>,
        /// The composer's message.
        message: String,
    },
    /// wgpu reported a validation error.
    #[error("wgpu validation error: {0}")]
    Validation(String),
    /// Reading the image back failed.
    #[error("reading the image back from the GPU failed: {0}")]
    Readback(String),
}

/// A wgpu device with the tracer's pipelines, one per specialisation used.
pub struct GpuTracer {
    device: wgpu::Device,
    queue: wgpu::Queue,
    adapter: wgpu::AdapterInfo,
    layout: wgpu::BindGroupLayout,
    pipelines: HashMap<TraceDefs, wgpu::ComputePipeline>,
}

impl GpuTracer {
    /// Opens the default GPU adapter (a software one is fine).
    ///
    /// # Errors
    /// [`GpuError::NoAdapter`] or [`GpuError::NoDevice`], in words a user can
    /// act on.
    pub fn new() -> Result<Self, GpuError> {
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
        desc.flags |= wgpu::InstanceFlags::VALIDATION;
        let instance = wgpu::Instance::new(desc);
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: false,
            compatible_surface: None,
        }))
        .map_err(|e| GpuError::NoAdapter(e.to_string()))?;
        let info = adapter.get_info();
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("bevy_manifold tracer"),
            ..Default::default()
        }))
        .map_err(|e| GpuError::NoDevice {
            adapter: info.name.clone(),
            message: e.to_string(),
        })?;
        let storage = |binding, read_only| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("trace"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
                storage(1, true),
                storage(2, true),
                storage(3, true),
                storage(4, true),
                storage(5, true),
                storage(6, false),
            ],
        });
        Ok(GpuTracer {
            device,
            queue,
            adapter: info,
            layout,
            pipelines: HashMap::new(),
        })
    }

    /// The adapter's name and driver, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
    #[must_use]
    pub fn adapter_name(&self) -> String {
        format!(
            "{} ({:?}, {})",
            self.adapter.name, self.adapter.backend, self.adapter.driver_info
        )
    }

    /// The composed, validated shader for a specialisation.
    ///
    /// # Errors
    /// [`GpuError::Shader`] when composition fails.
    pub fn compose(defs: &TraceDefs) -> Result<naga::Module, GpuError> {
        use naga_oil::compose::{Composer, NagaModuleDescriptor, ShaderDefValue, ShaderType};
        let mut composer = Composer::default();
        let shader_defs = defs
            .names()
            .into_iter()
            .map(|n| (n.to_string(), ShaderDefValue::Bool(true)))
            .collect();
        composer
            .make_naga_module(NagaModuleDescriptor {
                source: TRACE_WGSL,
                file_path: "shaders/trace.wgsl",
                shader_type: ShaderType::Wgsl,
                shader_defs,
                additional_imports: &[],
            })
            .map_err(|e| GpuError::Shader {
                defs: defs.names(),
                message: e.emit_to_string(&composer),
            })
    }

    fn pipeline(&mut self, defs: TraceDefs) -> Result<&wgpu::ComputePipeline, GpuError> {
        if !self.pipelines.contains_key(&defs) {
            let module = Self::compose(&defs)?;
            let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
            let shader = self.device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("trace.wgsl"),
                source: wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(module)),
            });
            let layout = self.device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("trace"),
                bind_group_layouts: &[Some(&self.layout)],
                immediate_size: 0,
            });
            let pipeline = self.device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("trace"),
                layout: Some(&layout),
                module: &shader,
                entry_point: Some("trace"),
                compilation_options: Default::default(),
                cache: None,
            });
            if let Some(e) = pollster::block_on(scope.pop()) {
                return Err(GpuError::Validation(e.to_string()));
            }
            self.pipelines.insert(defs, pipeline);
        }
        Ok(&self.pipelines[&defs])
    }

    /// Traces `scene` in `space` on the GPU.
    ///
    /// # Errors
    /// A shader, validation or readback failure, as [`GpuError`].
    pub fn render(&mut self, space: &Space, scene: &Scene, settings: &TraceSettings) -> Result<TraceImage, GpuError> {
        let defs = TraceDefs::for_scene(space, scene, settings.cell_colors);
        self.render_with(space, scene, settings, defs)
    }

    /// [`GpuTracer::render`] with the shader specialised by `defs` instead
    /// of by the scene (they must include what the scene uses; used to
    /// measure what specialisation saves).
    ///
    /// # Errors
    /// As [`GpuTracer::render`].
    pub fn render_with(
        &mut self,
        space: &Space,
        scene: &Scene,
        settings: &TraceSettings,
        defs: TraceDefs,
    ) -> Result<TraceImage, GpuError> {
        let prep = Prepared::<f32>::new(space, scene);
        let gpu = GpuScene::pack(space, &prep, settings);
        self.pipeline(defs)?;
        let pipeline = &self.pipelines[&defs];
        let d = &self.device;
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let buffer = |label, contents: &[u8], usage| {
            d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage,
            })
        };
        let storage = wgpu::BufferUsages::STORAGE;
        let params = buffer("params", bytemuck::bytes_of(&gpu.params), wgpu::BufferUsages::UNIFORM);
        let faces = buffer("faces", bytemuck::cast_slice(&gpu.space.faces), storage);
        let balls = buffer("balls", bytemuck::cast_slice(&gpu.objects.balls), storage);
        let tubes = buffer("tubes", bytemuck::cast_slice(&gpu.objects.tubes), storage);
        let lights = buffer("lights", bytemuck::cast_slice(&gpu.objects.lights), storage);
        let table = buffer("cell table", bytemuck::cast_slice(&gpu.space.cell_table), storage);
        let count = (settings.width * settings.height) as usize;
        let size = (count * std::mem::size_of::<GpuPixel>()) as u64;
        let pixels = d.create_buffer(&wgpu::BufferDescriptor {
            label: Some("pixels"),
            size,
            usage: storage | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let readback = d.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let bind = d.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("trace"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: params.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: faces.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: balls.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: tubes.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: lights.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 5,
                    resource: table.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 6,
                    resource: pixels.as_entire_binding(),
                },
            ],
        });
        let mut encoder = d.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("trace") });
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("trace"),
                timestamp_writes: None,
            });
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, &bind, &[]);
            pass.dispatch_workgroups(settings.width.div_ceil(8), settings.height.div_ceil(8), 1);
        }
        encoder.copy_buffer_to_buffer(&pixels, 0, &readback, 0, size);
        self.queue.submit([encoder.finish()]);
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(GpuError::Validation(e.to_string()));
        }
        let (tx, rx) = std::sync::mpsc::channel();
        readback.map_async(wgpu::MapMode::Read, .., move |r| {
            let _ = tx.send(r);
        });
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| GpuError::Readback(e.to_string()))?;
        rx.recv()
            .map_err(|e| GpuError::Readback(e.to_string()))?
            .map_err(|e| GpuError::Readback(e.to_string()))?;
        let data = readback.get_mapped_range(..);
        let raw: &[GpuPixel] = bytemuck::cast_slice(&data);
        let pixels = raw
            .iter()
            .map(|p| TracePixel {
                color: [p.color[0], p.color[1], p.color[2]],
                object: p.object,
                levels: p.levels,
                cell: CellId((u64::from(p.cell_hi) << 32) | u64::from(p.cell_lo)),
                distance: p.color[3],
            })
            .collect();
        Ok(TraceImage {
            width: settings.width,
            height: settings.height,
            pixels,
        })
    }
}
