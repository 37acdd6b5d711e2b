//! The WGSL tracer run directly on a wgpu device, outside Bevy's renderer:
//! headless renders for the CLI, and the GPU side of the GPU/CPU agreement
//! tests. The shader and its inputs are exactly what the render pass uses.

mod compose;
mod fragment;
mod product;
mod timing;

pub use product::MAX_PRODUCT_BALLS;
pub use timing::TraceTiming;

use crate::GpuError;
use crate::bindings::{BINDINGS, BindingKind};
use crate::layout::GpuPixel;
use crate::pack::{GpuScene, PackedSpace, binding_bytes};
use crate::shader_defs::TraceDefs;
use bevy_manifold_core::space::Space;
use bevy_manifold_core::space::cells::{CellId, CellScheme};
use bevy_manifold_core::trace::{FlatScene, RayDrift, Scene, TraceImage, TracePixel, TraceSettings};
use std::collections::HashMap;
use wgpu::util::DeviceExt;

/// A wgpu device with the tracer's pipelines, one per specialisation used.
pub struct GpuTracer {
    device: wgpu::Device,
    queue: wgpu::Queue,
    adapter: wgpu::AdapterInfo,
    layout: wgpu::BindGroupLayout,
    pipelines: HashMap<(TraceDefs, &'static str), wgpu::ComputePipeline>,
    fragment_pipelines: HashMap<TraceDefs, wgpu::RenderPipeline>,
    /// The last space packed where packing costs (exact ids: a product
    /// per cell of its table, 16,129 in Seifert-Weber), for the frames of
    /// a tour.
    kept: Option<PackedSpace>,
    /// The product spaces' pipelines, one per specialisation
    /// (`ProductShaderDefs::index`), each built on first use.
    product: [Option<product::ProductPipeline>; 16],
    /// The last product space traced, with its exact cells and their
    /// table (none where it has no exact cells): grown once per space.
    product_cells: Option<product::ProductCellsKept>,
    /// The last product scene's lights with their images, packed: worked
    /// out again only when the space, the lights or the lighting change
    /// (a tour's frames share them).
    product_lights: crate::product::PackedLights,
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
        // The storage buffers of [`BINDINGS`] (the params among them) and
        // its largest uniform array, each checked against the adapter.
        let storage = BINDINGS.iter().filter(|b| b.kind != BindingKind::Uniform).count() as u32;
        let allowed = adapter.limits().max_storage_buffers_per_shader_stage;
        if allowed < storage {
            return Err(GpuError::NoDevice {
                adapter: info.name.clone(),
                message: format!(
                    "the tracer binds {storage} storage buffers in one shader stage; this adapter allows {allowed}"
                ),
            });
        }
        if let Some(message) = crate::bindings::uniform_limit_error(adapter.limits().max_uniform_buffer_binding_size) {
            return Err(GpuError::NoDevice {
                adapter: info.name.clone(),
                message,
            });
        }
        let uniform = crate::bindings::largest_uniform();
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("bevy_manifold tracer"),
            required_limits: wgpu::Limits {
                max_storage_buffers_per_shader_stage:
                    storage.max(wgpu::Limits::default().max_storage_buffers_per_shader_stage),
                max_uniform_buffer_binding_size: uniform.max(wgpu::Limits::default().max_uniform_buffer_binding_size),
                ..wgpu::Limits::default()
            },
            // Timestamps, where the adapter has them, time a trace on the
            // device itself ([`GpuTracer::time_trace`]).
            required_features: adapter.features() & wgpu::Features::TIMESTAMP_QUERY,
            ..Default::default()
        }))
        .map_err(|e| GpuError::NoDevice {
            adapter: info.name.clone(),
            message: e.to_string(),
        })?;
        // The layout of [`BINDINGS`]: every binding but the compute
        // output is read by both entries (compute `trace`, and `fragment`
        // as the render pass runs it).
        let both = wgpu::ShaderStages::COMPUTE | wgpu::ShaderStages::FRAGMENT;
        let entries: Vec<wgpu::BindGroupLayoutEntry> = BINDINGS
            .iter()
            .map(|b| wgpu::BindGroupLayoutEntry {
                binding: b.binding,
                visibility: if b.compute_only {
                    wgpu::ShaderStages::COMPUTE
                } else {
                    both
                },
                ty: wgpu::BindingType::Buffer {
                    ty: b.kind.buffer_binding_type(),
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            })
            .collect();
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("trace"),
            entries: &entries,
        });
        Ok(GpuTracer {
            device,
            queue,
            adapter: info,
            layout,
            pipelines: HashMap::new(),
            fragment_pipelines: HashMap::new(),
            kept: None,
            product: Default::default(),
            product_cells: None,
            product_lights: Default::default(),
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

    /// Whether the device times passes itself (timestamp queries), so that
    /// [`GpuTracer::time_trace`] gives `device_ms`.
    #[must_use]
    pub fn has_timestamps(&self) -> bool {
        self.device.features().contains(wgpu::Features::TIMESTAMP_QUERY)
    }

    fn layout(&self) -> wgpu::PipelineLayout {
        self.device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("trace"),
            bind_group_layouts: &[Some(&self.layout)],
            immediate_size: 0,
        })
    }

    /// The compute pipeline of `entry` (`trace` or `drift`) for `defs`.
    fn pipeline(&mut self, defs: TraceDefs, entry: &'static str) -> Result<&wgpu::ComputePipeline, GpuError> {
        let key = (defs, entry);
        if !self.pipelines.contains_key(&key) {
            let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
            let shader = self.shader(&defs)?;
            let pipeline = self.device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("trace"),
                layout: Some(&self.layout()),
                module: &shader,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            });
            if let Some(e) = pollster::block_on(scope.pop()) {
                return Err(GpuError::Validation(e.to_string()));
            }
            self.pipelines.insert(key, pipeline);
        }
        Ok(&self.pipelines[&key])
    }

    /// Uploads a scene and binds it, with a `pixels` buffer of `count`:
    /// each binding of [`BINDINGS`] its buffer, filled by
    /// [`binding_bytes`] (the params apart).
    fn upload(&self, gpu: &GpuScene, count: usize) -> (wgpu::BindGroup, wgpu::Buffer) {
        let d = &self.device;
        let pixels = d.create_buffer(&wgpu::BufferDescriptor {
            label: Some("pixels"),
            size: (count.max(1) * std::mem::size_of::<GpuPixel>()) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        // Each binding's buffer as BINDINGS says: its usage, and a uniform
        // array padded to its declared length (copied only then: the cell
        // table and the meshes' data run to megabytes).
        let buffers: Vec<Option<wgpu::Buffer>> = BINDINGS
            .iter()
            .map(|b| {
                let data = match b.name {
                    "params" => Some(bytemuck::bytes_of(&gpu.params)),
                    _ => binding_bytes(b, &gpu.space, &gpu.objects),
                }?;
                let size = b.bytes_for(data.len());
                let padded;
                let contents = if size == data.len() {
                    data
                } else {
                    padded = [data, &vec![0; size - data.len()]].concat();
                    &padded
                };
                Some(d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(b.name),
                    contents,
                    usage: b.usage(),
                }))
            })
            .collect();
        let entries: Vec<wgpu::BindGroupEntry> = BINDINGS
            .iter()
            .zip(&buffers)
            .map(|(b, buffer)| wgpu::BindGroupEntry {
                binding: b.binding,
                // The one binding with no scene data is the output.
                resource: buffer.as_ref().unwrap_or(&pixels).as_entire_binding(),
            })
            .collect();
        let bind = d.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("trace"),
            layout: &self.layout,
            entries: &entries,
        });
        (bind, pixels)
    }

    /// Submits `encoder`, waits, and maps `readback`'s bytes.
    fn finish(&self, encoder: wgpu::CommandEncoder, readback: &wgpu::Buffer) -> Result<Vec<u8>, GpuError> {
        self.queue.submit([encoder.finish()]);
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
        let data = readback.get_mapped_range(..).to_vec();
        Ok(data)
    }

    fn readback_buffer(&self, size: u64) -> wgpu::Buffer {
        self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        })
    }

    /// Traces `scene` in `space` on the GPU.
    ///
    /// # Errors
    /// A shader, validation or readback failure, as [`GpuError`].
    pub fn render(&mut self, space: &Space, scene: &Scene, settings: &TraceSettings) -> Result<TraceImage, GpuError> {
        self.render_with(space, scene, settings, scene_defs(space, scene, settings))
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
        let raw = self.dispatch(space, scene, settings, defs, "trace")?;
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

    /// The drift probe on the GPU (the shader's `drift` entry, twin of
    /// [`bevy_manifold_core::trace::ray_drift`]): every camera ray of `scene`'s camera at
    /// `settings`' size walked through `settings.levels` transports,
    /// objects ignored, renormalising or not as `settings.renormalize` says.
    /// One [`RayDrift`] per pixel, row-major.
    ///
    /// # Errors
    /// As [`GpuTracer::render`].
    pub fn drift(&mut self, space: &Space, scene: &Scene, settings: &TraceSettings) -> Result<Vec<RayDrift>, GpuError> {
        let defs = TraceDefs::for_scene(space, &Scene::empty(), false);
        let raw = self.dispatch(space, scene, settings, defs, "drift")?;
        Ok(raw
            .iter()
            .map(|p| RayDrift {
                point_error: f64::from(p.color[0]),
                tangent_error: f64::from(p.color[1]),
                outside: f64::from(p.color[2]),
                levels: p.levels,
                distance: f64::from(p.color[3]),
            })
            .collect())
    }

    /// The space packed for `flat`'s camera cell: kept from the last call
    /// where the space has exact ids and nothing it was packed for changed
    /// (the frames of a tour in one copy of the domain), else packed again
    /// (the table grown first) and, where the ids are exact, kept.
    fn packed_space(&mut self, space: &Space, flat: &FlatScene<f32>) -> PackedSpace {
        let exact = matches!(space.cells(), CellScheme::Exact(_));
        if let Some(kept) = &self.kept
            && exact
            && kept.is_for(space)
            && *kept.centre() == flat.camera_element
        {
            return kept.clone();
        }
        let packed = GpuScene::pack_space(space, flat);
        self.kept = exact.then(|| packed.clone());
        packed
    }

    /// Runs the compute `entry` over every pixel and reads the pixels back.
    fn dispatch(
        &mut self,
        space: &Space,
        scene: &Scene,
        settings: &TraceSettings,
        defs: TraceDefs,
        entry: &'static str,
    ) -> Result<Vec<GpuPixel>, GpuError> {
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let bound = self.bind(space, scene, settings, defs, entry)?;
        let size = (bound.count * std::mem::size_of::<GpuPixel>()) as u64;
        let readback = self.readback_buffer(size);
        let mut encoder = self.trace_encoder(&bound, settings);
        encoder.copy_buffer_to_buffer(&bound.pixels, 0, &readback, 0, size);
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(GpuError::Validation(e.to_string()));
        }
        let data = self.finish(encoder, &readback)?;
        Ok(bytemuck::pod_collect_to_vec(&data))
    }

    /// Packs and uploads a scene for the compute `entry`, with its pipeline
    /// built, after checking every buffer against the device's limits.
    fn bind(
        &mut self,
        space: &Space,
        scene: &Scene,
        settings: &TraceSettings,
        defs: TraceDefs,
        entry: &'static str,
    ) -> Result<Bound, GpuError> {
        settings.check().map_err(GpuError::Settings)?;
        let flat = FlatScene::<f32>::new(space, scene);
        if flat.balls.len() > crate::bindings::MAX_BALLS {
            return Err(GpuError::Settings(format!(
                "the scene makes {} balls (ghost copies and edge joints included), more than the {} the GPU tracer holds",
                flat.balls.len(),
                crate::bindings::MAX_BALLS
            )));
        }
        let gpu = GpuScene::pack_in(space, &self.packed_space(space, &flat), &flat, settings);
        let defs = defs.for_objects(&gpu.objects);
        self.pipeline(defs, entry)?;
        let count = (u64::from(settings.width) * u64::from(settings.height)) as usize;
        // Every storage buffer within what the device binds, checked before
        // wgpu would raise a validation error.
        let limit = self.device.limits().max_storage_buffer_binding_size;
        for (what, bytes) in [
            ("the pixels", count * std::mem::size_of::<GpuPixel>()),
            ("the meshes", std::mem::size_of_val(&gpu.objects.mesh_data[..])),
            ("the mesh instances", std::mem::size_of_val(&gpu.objects.instances[..])),
            ("the cell table", std::mem::size_of_val(&gpu.space.cell_table[..])),
        ] {
            if bytes as u64 > limit {
                return Err(GpuError::Settings(format!(
                    "{what} need a {bytes}-byte buffer, more than the {limit} bytes this adapter binds"
                )));
            }
        }
        let (bind, pixels) = self.upload(&gpu, count);
        Ok(Bound {
            bind,
            pixels,
            count,
            key: (defs, entry),
        })
    }

    /// An encoder holding one compute pass over every pixel of `bound`.
    fn trace_encoder(&self, bound: &Bound, settings: &TraceSettings) -> wgpu::CommandEncoder {
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("trace") });
        self.encode_trace(&mut encoder, bound, settings, None);
        encoder
    }

    /// Records one compute pass over every pixel of `bound` into
    /// `encoder`, its start and end written to `timestamps` at the given
    /// index and the next when given.
    fn encode_trace(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        bound: &Bound,
        settings: &TraceSettings,
        timestamps: Option<(&wgpu::QuerySet, u32)>,
    ) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("trace"),
            timestamp_writes: timestamps.map(|(query_set, at)| wgpu::ComputePassTimestampWrites {
                query_set,
                beginning_of_pass_write_index: Some(at),
                end_of_pass_write_index: Some(at + 1),
            }),
        });
        pass.set_pipeline(&self.pipelines[&bound.key]);
        pass.set_bind_group(0, &bound.bind, &[]);
        pass.dispatch_workgroups(settings.width.div_ceil(8), settings.height.div_ceil(8), 1);
    }
}

/// The specialisation `scene` is traced with (by the compute and the
/// fragment entry alike).
fn scene_defs(space: &Space, scene: &Scene, settings: &TraceSettings) -> TraceDefs {
    TraceDefs::for_scene(space, scene, settings.cell_colors)
        .for_rule(&settings.cell_rule)
        .for_footprint(settings.footprint)
        .for_reflections(settings.reflections)
        .for_path(settings.path_depth)
}

/// A scene uploaded and bound for one compute entry.
struct Bound {
    bind: wgpu::BindGroup,
    pixels: wgpu::Buffer,
    count: usize,
    key: (TraceDefs, &'static str),
}
