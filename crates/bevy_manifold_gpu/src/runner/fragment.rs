//! The render pass's way of tracing, run headless: the `fragment` entry
//! over a full-screen triangle into a colour and a depth target
//! ([`GpuTracer::render_fragment`]).

use super::{GpuTracer, scene_defs};
use crate::GpuError;
use crate::pack::GpuScene;
use crate::shader_defs::TraceDefs;
use bevy_manifold_core::space::Space;
use bevy_manifold_core::trace::{FlatScene, Scene, TraceSettings};

impl GpuTracer {
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
        let flat = FlatScene::<f32>::new(space, scene);
        let gpu = GpuScene::pack_in(space, &self.packed_space(space, &flat), &flat, settings);
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
