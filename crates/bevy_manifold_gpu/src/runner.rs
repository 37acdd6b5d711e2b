//! The WGSL tracer run directly on a wgpu device, outside Bevy's renderer:
//! headless renders for the CLI, and the GPU side of the GPU/CPU agreement
//! tests. The shader and its inputs are exactly what the render pass uses.

use crate::GpuError;
use crate::TRACE_WGSL;
use crate::bindings::{BINDINGS, BindingKind};
use crate::layout::{GpuPixel, GpuScene};
use crate::shader_defs::TraceDefs;
use bevy_manifold_core::space::Space;
use bevy_manifold_core::space::cells::CellId;
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
    kept: Option<KeptSpace>,
}

/// A packed space and what it was packed for: the same faces, the same
/// table of cells (one `Arc`) and the same camera cell give the same
/// [`GpuSpace`].
struct KeptSpace {
    faces: Vec<bevy_manifold_core::space::Face>,
    ball: std::sync::Arc<bevy_manifold_core::space::ball::CellBall>,
    camera: bevy_manifold_core::space::element::CellElement,
    packed: crate::layout::GpuSpace,
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

    /// The composed, validated shader for a specialisation.
    ///
    /// # Errors
    /// [`GpuError::Shader`] when composition fails.
    pub fn compose(defs: &TraceDefs) -> Result<naga::Module, GpuError> {
        Self::compose_with(&defs.names(), &defs.values())
    }

    /// The shader composed with these shader defs on (those of a
    /// [`TraceDefs`], and `ENCODE_SRGB` as the render pass may add) and
    /// these value defs (`FACE_COUNT`, [`TraceDefs::values`]): the
    /// import modules ([`crate::SHADER_IMPORTS`]) added to naga_oil's
    /// composer, then the entry module, as Bevy's pipeline cache does.
    ///
    /// # Errors
    /// [`GpuError::Shader`] when composition fails.
    pub fn compose_with(names: &[&'static str], values: &[(&'static str, u32)]) -> Result<naga::Module, GpuError> {
        Self::compose_modules(&crate::SHADER_IMPORTS, TRACE_WGSL, names, values)
    }

    /// `entry` composed with these import modules (each after those it
    /// imports), these shader defs on and these value defs: what
    /// [`Self::compose_with`] does
    /// with the tracer's own modules, open to a changed module (the
    /// contract test's deliberately broken copy).
    ///
    /// # Errors
    /// [`GpuError::Shader`] when composition fails.
    pub fn compose_modules(
        imports: &[crate::WgslModule],
        entry: crate::WgslModule,
        names: &[&'static str],
        values: &[(&'static str, u32)],
    ) -> Result<naga::Module, GpuError> {
        use naga_oil::compose::{
            ComposableModuleDescriptor, Composer, NagaModuleDescriptor, ShaderDefValue, ShaderLanguage, ShaderType,
        };
        let mut composer = Composer::default();
        let fail = |composer: &Composer, e: naga_oil::compose::ComposerError| GpuError::Shader {
            defs: names.to_vec(),
            message: e.emit_to_string(composer),
        };
        for module in imports {
            let added = composer
                .add_composable_module(ComposableModuleDescriptor {
                    source: module.source,
                    file_path: module.path,
                    language: ShaderLanguage::Wgsl,
                    ..Default::default()
                })
                .map(|_| ());
            added.map_err(|e| fail(&composer, e))?;
        }
        let shader_defs = names
            .iter()
            .map(|n| (n.to_string(), ShaderDefValue::Bool(true)))
            .chain(values.iter().map(|&(n, v)| (n.to_string(), ShaderDefValue::UInt(v))))
            .collect();
        composer
            .make_naga_module(NagaModuleDescriptor {
                source: entry.source,
                file_path: entry.path,
                shader_type: ShaderType::Wgsl,
                shader_defs,
                additional_imports: &[],
            })
            .map_err(|e| fail(&composer, e))
    }

    fn shader(&self, defs: &TraceDefs) -> Result<wgpu::ShaderModule, GpuError> {
        let module = Self::compose(defs)?;
        Ok(self.device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("trace.wgsl"),
            source: wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(module)),
        }))
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

    fn fragment_pipeline(&mut self, defs: TraceDefs) -> Result<&wgpu::RenderPipeline, GpuError> {
        if !self.fragment_pipelines.contains_key(&defs) {
            let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
            let shader = self.shader(&defs)?;
            // Parsed by naga here, as the tracer is: wgpu's own WGSL
            // front end is not built in.
            let fullscreen = naga::front::wgsl::parse_str(FULLSCREEN_WGSL).map_err(|e| GpuError::Shader {
                defs: vec![],
                message: e.to_string(),
            })?;
            let vertex = self.device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("fullscreen"),
                source: wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(fullscreen)),
            });
            let pipeline = self.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("trace"),
                layout: Some(&self.layout()),
                vertex: wgpu::VertexState {
                    module: &vertex,
                    entry_point: Some("main"),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: wgpu::PrimitiveState::default(),
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: wgpu::TextureFormat::Depth32Float,
                    depth_write_enabled: Some(true),
                    depth_compare: Some(wgpu::CompareFunction::Always),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: wgpu::MultisampleState::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &shader,
                    entry_point: Some("fragment"),
                    compilation_options: Default::default(),
                    targets: &[Some(wgpu::ColorTargetState {
                        format: FRAGMENT_FORMAT,
                        blend: None,
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                }),
                multiview_mask: None,
                cache: None,
            });
            if let Some(e) = pollster::block_on(scope.pop()) {
                return Err(GpuError::Validation(e.to_string()));
            }
            self.fragment_pipelines.insert(defs, pipeline);
        }
        Ok(&self.fragment_pipelines[&defs])
    }

    /// Uploads a scene and binds it, with a `pixels` buffer of `count`.
    fn upload(&self, gpu: &GpuScene, count: usize) -> (wgpu::BindGroup, wgpu::Buffer) {
        let d = &self.device;
        let buffer = |label, contents: &[u8], usage| {
            d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage,
            })
        };
        // Each binding's buffer as BINDINGS says: its usage, and a uniform
        // array padded to its declared length (copied only then: the cell
        // table and the meshes' data run to megabytes).
        let bound = |index: usize, data: &[u8]| {
            let b = &BINDINGS[index];
            let size = b.bytes_for(data.len());
            if size == data.len() {
                return buffer(b.name, data, b.usage());
            }
            let mut contents = data.to_vec();
            contents.resize(size, 0);
            buffer(b.name, &contents, b.usage())
        };
        let storage = wgpu::BufferUsages::STORAGE;
        let params = bound(0, bytemuck::bytes_of(&gpu.params));
        let faces = bound(1, bytemuck::cast_slice(&gpu.space.faces));
        let balls = bound(2, bytemuck::cast_slice(&gpu.objects.balls));
        let tubes = bound(3, bytemuck::cast_slice(&gpu.objects.tubes));
        let lights = bound(4, bytemuck::cast_slice(&gpu.objects.lights));
        let table = bound(5, bytemuck::cast_slice(&gpu.space.cell_table));
        let instances = bound(6, bytemuck::cast_slice(&gpu.objects.instances));
        let mesh_data = bound(7, bytemuck::cast_slice(&gpu.objects.mesh_data));
        let groups = bound(9, bytemuck::cast_slice(&gpu.objects.groups));
        let ball_nodes = bound(10, bytemuck::cast_slice(&gpu.objects.ball_nodes));
        let pixels = d.create_buffer(&wgpu::BufferDescriptor {
            label: Some("pixels"),
            size: (count.max(1) * std::mem::size_of::<GpuPixel>()) as u64,
            usage: storage | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let entries: Vec<wgpu::BindGroupEntry> = [
            &params,
            &faces,
            &balls,
            &tubes,
            &lights,
            &table,
            &instances,
            &mesh_data,
            &pixels,
            &groups,
            &ball_nodes,
        ]
        .into_iter()
        .enumerate()
        .map(|(i, b)| wgpu::BindGroupEntry {
            binding: i as u32,
            resource: b.as_entire_binding(),
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

    /// The space packed for `prep`'s camera cell: kept from the last call
    /// where the space has exact ids and nothing it was packed for changed
    /// (the frames of a tour in one copy of the domain), else packed again
    /// and, where the ids are exact, kept.
    fn packed_space(&mut self, space: &Space, prep: &FlatScene<f32>) -> crate::layout::GpuSpace {
        use bevy_manifold_core::space::cells::CellScheme;
        if let Some(k) = &self.kept
            && let CellScheme::Exact(exact) = space.cells()
            && exact.grown_ball().is_some_and(|b| std::sync::Arc::ptr_eq(b, &k.ball))
            && k.camera == prep.camera_element
            && k.faces == space.faces()
        {
            return k.packed.clone();
        }
        let packed = GpuScene::pack_space(space, prep);
        self.kept = match space.cells() {
            CellScheme::Exact(exact) => exact.grown_ball().map(|ball| KeptSpace {
                faces: space.faces().to_vec(),
                ball: ball.clone(),
                camera: prep.camera_element.clone(),
                packed: packed.clone(),
            }),
            _ => None,
        };
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
        let prep = FlatScene::<f32>::new(space, scene);
        if prep.balls.len() > crate::bindings::MAX_BALLS {
            return Err(GpuError::Settings(format!(
                "the scene makes {} balls (ghost copies and edge joints included), more than the {} the GPU tracer holds",
                prep.balls.len(),
                crate::bindings::MAX_BALLS
            )));
        }
        let gpu = GpuScene::pack_in(space, self.packed_space(space, &prep), &prep, settings);
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

    /// How long tracing `scene` takes once it is on the device: `repeats`
    /// traces of the same upload, back to back in one submission, with no
    /// read-back, after untimed traces for at least 250 ms (a GPU
    /// idling between calls runs at a fraction of its clock). The device
    /// time is the median pass by the adapter's timestamps at the start and
    /// end of each compute pass (none where the adapter has no timestamp
    /// queries); the wall time is the submission's, from submitting until
    /// the device is idle, over `repeats`. [`GpuTracer::render`] times
    /// more: the packing, the upload and the read-back, which on a discrete
    /// GPU at headset sizes outweigh the trace.
    ///
    /// ```no_run
    /// use bevy_manifold_core::prelude::*;
    /// use bevy_manifold_gpu::GpuTracer;
    ///
    /// let mut gpu = GpuTracer::new()?;
    /// let space = catalog::seifert_weber();
    /// let settings = TraceSettings { width: 1512, height: 1680, levels: 8, ..TraceSettings::default() };
    /// let t = gpu.time_trace(&space, &Scene::default_for(&space), &settings, 10)?;
    /// println!("{:.2} ms", t.device_ms.unwrap_or(t.wall_ms));
    /// # Ok::<(), bevy_manifold_gpu::GpuError>(())
    /// ```
    ///
    /// # Errors
    /// As [`GpuTracer::render`].
    pub fn time_trace(
        &mut self,
        space: &Space,
        scene: &Scene,
        settings: &TraceSettings,
        repeats: u32,
    ) -> Result<TraceTiming, GpuError> {
        let defs = scene_defs(space, scene, settings);
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let bound = self.bind(space, scene, settings, defs, "trace")?;
        let repeats = repeats.clamp(1, 1024);
        let queries = self.has_timestamps().then(|| {
            self.device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("trace timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: 2 * repeats,
            })
        });
        let wait = || {
            self.device
                .poll(wgpu::PollType::wait_indefinitely())
                .map_err(|e| GpuError::Readback(e.to_string()))
        };
        let warm = std::time::Instant::now();
        for _ in 0..256 {
            self.queue.submit([self.trace_encoder(&bound, settings).finish()]);
            wait()?;
            if warm.elapsed() >= WARM_UP {
                break;
            }
        }
        let mut encoder = self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("timed traces"),
        });
        for i in 0..repeats {
            self.encode_trace(&mut encoder, &bound, settings, queries.as_ref().map(|q| (q, 2 * i)));
        }
        let commands = encoder.finish();
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(GpuError::Validation(e.to_string()));
        }
        let start = std::time::Instant::now();
        self.queue.submit([commands]);
        wait()?;
        let wall_ms = start.elapsed().as_secs_f64() * 1e3 / f64::from(repeats);
        let device_ms = match &queries {
            Some(set) => {
                let bytes = u64::from(2 * repeats) * 8;
                let resolved = self.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("timestamps"),
                    size: bytes,
                    usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                });
                let readback = self.readback_buffer(bytes);
                let mut encoder = self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("timestamps"),
                });
                encoder.resolve_query_set(set, 0..2 * repeats, &resolved, 0);
                encoder.copy_buffer_to_buffer(&resolved, 0, &readback, 0, bytes);
                let ticks: Vec<u64> = bytemuck::pod_collect_to_vec(&self.finish(encoder, &readback)?);
                let period = f64::from(self.queue.get_timestamp_period()) * 1e-6;
                let spans: Vec<f64> = ticks
                    .chunks_exact(2)
                    .map(|t| t[1].saturating_sub(t[0]) as f64 * period)
                    .collect();
                Some(median(spans))
            }
            None => None,
        };
        Ok(TraceTiming { device_ms, wall_ms })
    }

    /// Traces `scene` the way the Bevy render pass does: the `fragment`
    /// entry over a full-screen triangle into an sRGB colour target and a
    /// depth target. Returns the target's RGBA bytes (sRGB-encoded, rows
    /// top to bottom). No ids: those come from [`GpuTracer::render`].
    ///
    /// # Errors
    /// As [`GpuTracer::render`].
    pub fn render_fragment(
        &mut self,
        space: &Space,
        scene: &Scene,
        settings: &TraceSettings,
    ) -> Result<Vec<u8>, GpuError> {
        let prep = FlatScene::<f32>::new(space, scene);
        let gpu = GpuScene::pack_in(space, self.packed_space(space, &prep), &prep, settings);
        let defs = scene_defs(space, scene, settings).for_objects(&gpu.objects);
        self.fragment_pipeline(defs)?;
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let (bind, _) = self.upload(&gpu, 1);
        let (w, h) = (settings.width, settings.height);
        let extent = wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        };
        let texture = |format, usage| {
            self.device.create_texture(&wgpu::TextureDescriptor {
                label: Some("trace target"),
                size: extent,
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        let color = texture(
            FRAGMENT_FORMAT,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        );
        let depth = texture(
            wgpu::TextureFormat::Depth32Float,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        );
        let color_view = color.create_view(&Default::default());
        let depth_view = depth.create_view(&Default::default());
        let row = (w * 4).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
        let readback = self.readback_buffer(u64::from(row * h));
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("trace") });
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("trace"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &color_view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations::default(),
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &depth_view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(0.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&self.fragment_pipelines[&defs]);
            pass.set_bind_group(0, &bind, &[]);
            pass.draw(0..3, 0..1);
        }
        encoder.copy_texture_to_buffer(
            color.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &readback,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(row),
                    rows_per_image: Some(h),
                },
            },
            extent,
        );
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(GpuError::Validation(e.to_string()));
        }
        let data = self.finish(encoder, &readback)?;
        Ok(data
            .chunks_exact(row as usize)
            .flat_map(|r| &r[..(w * 4) as usize])
            .copied()
            .collect())
    }
}

/// How long [`GpuTracer::time_trace`] keeps the device busy before timing.
const WARM_UP: std::time::Duration = std::time::Duration::from_millis(250);

/// The specialisation `scene` is traced with (by the compute and the
/// fragment entry alike).
fn scene_defs(space: &Space, scene: &Scene, settings: &TraceSettings) -> TraceDefs {
    TraceDefs::for_scene(space, scene, settings.cell_colors)
        .for_rule(&settings.cell_rule)
        .for_footprint(settings.footprint)
}

/// A scene uploaded and bound for one compute entry.
struct Bound {
    bind: wgpu::BindGroup,
    pixels: wgpu::Buffer,
    count: usize,
    key: (TraceDefs, &'static str),
}

/// What [`GpuTracer::time_trace`] measured for one trace, in ms.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TraceTiming {
    /// The device's own time for the compute pass (its timestamps); `None`
    /// where the adapter has no timestamp queries.
    pub device_ms: Option<f64>,
    /// Wall time from submitting the trace until the device is idle.
    pub wall_ms: f64,
}

/// The median of `values` (the mean of the middle two for an even count).
fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    let n = values.len();
    match n {
        0 => f64::NAN,
        _ if n % 2 == 1 => values[n / 2],
        _ => 0.5 * (values[n / 2 - 1] + values[n / 2]),
    }
}

/// The colour format of [`GpuTracer::render_fragment`]: Bevy's default
/// view target format.
const FRAGMENT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;

/// A full-screen triangle (what Bevy's `FullscreenShader` draws).
const FULLSCREEN_WGSL: &str = "
@vertex
fn main(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}
";
