//! A view traced into textures of its own ([`TracedTextures`]) rather
//! than straight into its view target: at a render scale below 1
//! ([`crate::camera::ManifoldRenderScale`]) the trace is smaller, and
//! `bevy_manifold_gpu`'s `shaders/upscale.wgsl` draws it over the whole
//! viewport, colour bilinear and depth nearest (Rust twin:
//! [`crate::trace::upscale`]); with [`crate::camera::ManifoldAccumulation`] each
//! trace is first blended into a history (`blend_in`, Rust twin
//! [`crate::trace::accumulate`]) and the history is drawn.

use bevy::core_pipeline::FullscreenShader;
use bevy::core_pipeline::core_3d::CORE_3D_DEPTH_FORMAT;
use bevy::prelude::*;
use bevy::render::render_resource::binding_types::{sampler, texture_2d, texture_depth_2d};
use bevy::render::render_resource::{
    BindGroup, BindGroupEntries, BindGroupLayoutDescriptor, BindGroupLayoutEntries, BlendComponent, BlendFactor,
    BlendOperation, BlendState, ColorTargetState, ColorWrites, Extent3d, FilterMode, FragmentState, PipelineCache,
    RenderPipelineDescriptor, Sampler, SamplerBindingType, SamplerDescriptor, ShaderStages, SpecializedRenderPipeline,
    Texture, TextureDescriptor, TextureDimension, TextureFormat, TextureSampleType, TextureUsages, TextureView,
    TextureViewDescriptor,
};
use bevy::render::renderer::RenderDevice;
use bevy::shader::Shader;

/// The upscale pipeline's layout, sampler and shaders (render world).
#[derive(Resource, Clone)]
pub struct UpscalePipeline {
    /// Group 0: the traced colour, the bilinear sampler, the traced depth.
    pub layout: BindGroupLayoutDescriptor,
    sampler: Sampler,
    shader: Handle<Shader>,
    fullscreen: FullscreenShader,
}

/// What the upscale pipeline is specialised on: the view target's, or
/// the blend into a history.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct UpscaleKey {
    /// The view target's format (the traced texture has the same).
    pub format: TextureFormat,
    /// The view target's sample count.
    pub samples: u32,
    /// The target stores sRGB-encoded values without encoding them: the
    /// upscale encodes (`ENCODE_SRGB`).
    pub encode_srgb: bool,
    /// The `blend_in` pipeline (added into a [`HISTORY_FORMAT`] history,
    /// no depth); `format`, `samples` and `encode_srgb` are then unused.
    pub blend: bool,
}

/// The format of the traced colour and of an accumulation history:
/// linear 16-bit float, so filtering and averaging happen on linear
/// colour; a history holds the sum of its samples, alpha their count
/// (exact to 2048).
pub const HISTORY_FORMAT: TextureFormat = TextureFormat::Rgba16Float;

impl UpscalePipeline {
    /// The pipeline for `shader` (`upscale.wgsl`).
    #[must_use]
    pub fn new(device: &RenderDevice, shader: Handle<Shader>, fullscreen: FullscreenShader) -> Self {
        let layout = BindGroupLayoutDescriptor::new(
            "manifold_upscale",
            &BindGroupLayoutEntries::sequential(
                ShaderStages::FRAGMENT,
                (
                    texture_2d(TextureSampleType::Float { filterable: true }),
                    sampler(SamplerBindingType::Filtering),
                    texture_depth_2d(),
                ),
            ),
        );
        let sampler = device.create_sampler(&SamplerDescriptor {
            label: Some("manifold_upscale"),
            mag_filter: FilterMode::Linear,
            min_filter: FilterMode::Linear,
            ..default()
        });
        UpscalePipeline {
            layout,
            sampler,
            shader,
            fullscreen,
        }
    }
}

impl SpecializedRenderPipeline for UpscalePipeline {
    type Key = UpscaleKey;

    fn specialize(&self, key: Self::Key) -> RenderPipelineDescriptor {
        if key.blend {
            // history += trace: alpha (1 per trace) counts the samples,
            // and the upscale divides by it. Sums are exact where a
            // weighted blend would round its weight.
            let weighted = BlendComponent {
                src_factor: BlendFactor::One,
                dst_factor: BlendFactor::One,
                operation: BlendOperation::Add,
            };
            return RenderPipelineDescriptor {
                label: Some("manifold_blend_in".into()),
                layout: vec![self.layout.clone()],
                vertex: self.fullscreen.to_vertex_state(),
                fragment: Some(FragmentState {
                    shader: self.shader.clone(),
                    entry_point: Some("blend_in".into()),
                    targets: vec![Some(ColorTargetState {
                        format: HISTORY_FORMAT,
                        blend: Some(BlendState {
                            color: weighted,
                            alpha: weighted,
                        }),
                        write_mask: ColorWrites::ALL,
                    })],
                    ..default()
                }),
                ..default()
            };
        }
        let defs = if key.encode_srgb {
            vec!["ENCODE_SRGB".into()]
        } else {
            Vec::new()
        };
        super::pipeline::fullscreen_with_depth(
            "manifold_upscale",
            &self.layout,
            &self.fullscreen,
            (&self.shader, "upscale", defs),
            key.format,
            key.samples,
        )
    }
}

/// A view's accumulation history and the bind group that draws it.
pub struct History {
    /// The samples' sum, their count in alpha ([`HISTORY_FORMAT`]).
    pub view: TextureView,
    /// Group 0 of the upscale, drawing the history (and the trace's
    /// depth).
    pub bind_group: BindGroup,
    _texture: Texture,
}

/// A view's traced textures at its render scale, and the bind group that
/// upscales them (the trace's group also feeds `blend_in`).
pub struct TracedTextures {
    /// Their size in pixels.
    pub size: UVec2,
    /// The colour format (the view target's).
    pub format: TextureFormat,
    /// The traced colour.
    pub color: TextureView,
    /// The traced depth.
    pub depth: TextureView,
    /// Group 0 of the upscale.
    pub bind_group: BindGroup,
    /// The accumulation history, when the view accumulates.
    pub history: Option<History>,
    _textures: [Texture; 2],
}

impl TracedTextures {
    /// Textures of `size` (the colour in `format`), bound for the upscale,
    /// with a history when `accumulate`.
    #[must_use]
    pub fn new(
        device: &RenderDevice,
        pipeline_cache: &PipelineCache,
        pipeline: &UpscalePipeline,
        size: UVec2,
        format: TextureFormat,
        accumulate: bool,
    ) -> Self {
        let texture = |label: &'static str, format: TextureFormat| {
            device.create_texture(&TextureDescriptor {
                label: Some(label),
                size: Extent3d {
                    width: size.x,
                    height: size.y,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: TextureDimension::D2,
                format,
                usage: TextureUsages::RENDER_ATTACHMENT | TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            })
        };
        let color_texture = texture("manifold_traced_color", format);
        let depth_texture = texture("manifold_traced_depth", CORE_3D_DEPTH_FORMAT);
        let color = color_texture.create_view(&TextureViewDescriptor::default());
        let depth = depth_texture.create_view(&TextureViewDescriptor::default());
        let layout = pipeline_cache.get_bind_group_layout(&pipeline.layout);
        let bind_group = device.create_bind_group(
            "manifold_upscale",
            &layout,
            &BindGroupEntries::sequential((&color, &pipeline.sampler, &depth)),
        );
        let history = accumulate.then(|| {
            let texture = texture("manifold_history", HISTORY_FORMAT);
            let view = texture.create_view(&TextureViewDescriptor::default());
            let bind_group = device.create_bind_group(
                "manifold_upscale_history",
                &layout,
                &BindGroupEntries::sequential((&view, &pipeline.sampler, &depth)),
            );
            History {
                view,
                bind_group,
                _texture: texture,
            }
        });
        TracedTextures {
            size,
            format,
            color,
            depth,
            bind_group,
            history,
            _textures: [color_texture, depth_texture],
        }
    }
}
