//! The upscale of a view traced at a render scale below 1
//! ([`super::scale::ManifoldRenderScale`]): the trace goes into a smaller
//! colour and depth texture of the view's own ([`TracedTextures`]), then
//! `bevy_manifold_gpu`'s `shaders/upscale.wgsl` draws them over the whole
//! viewport, colour bilinear and depth nearest. Its Rust twin is
//! [`crate::trace::upscale`].

use bevy::core_pipeline::FullscreenShader;
use bevy::core_pipeline::core_3d::CORE_3D_DEPTH_FORMAT;
use bevy::prelude::*;
use bevy::render::render_resource::binding_types::{sampler, texture_2d, texture_depth_2d};
use bevy::render::render_resource::{
    BindGroup, BindGroupEntries, BindGroupLayoutDescriptor, BindGroupLayoutEntries, ColorTargetState, ColorWrites,
    CompareFunction, DepthStencilState, Extent3d, FilterMode, FragmentState, MultisampleState, PipelineCache,
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

/// What the upscale pipeline is specialised on: the view target's.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct UpscaleKey {
    /// The view target's format (the traced texture has the same).
    pub format: TextureFormat,
    /// The view target's sample count.
    pub samples: u32,
}

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
        RenderPipelineDescriptor {
            label: Some("manifold_upscale".into()),
            layout: vec![self.layout.clone()],
            vertex: self.fullscreen.to_vertex_state(),
            fragment: Some(FragmentState {
                shader: self.shader.clone(),
                entry_point: Some("upscale".into()),
                targets: vec![Some(ColorTargetState {
                    format: key.format,
                    blend: None,
                    write_mask: ColorWrites::ALL,
                })],
                ..default()
            }),
            depth_stencil: Some(DepthStencilState {
                format: CORE_3D_DEPTH_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(CompareFunction::Always),
                stencil: default(),
                bias: default(),
            }),
            multisample: MultisampleState {
                count: key.samples,
                ..default()
            },
            ..default()
        }
    }
}

/// A view's traced textures at its render scale, and the bind group that
/// upscales them.
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
    _textures: [Texture; 2],
}

impl TracedTextures {
    /// Textures of `size` in `format`, bound for the upscale.
    #[must_use]
    pub fn new(
        device: &RenderDevice,
        pipeline_cache: &PipelineCache,
        pipeline: &UpscalePipeline,
        size: UVec2,
        format: TextureFormat,
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
        let bind_group = device.create_bind_group(
            "manifold_upscale",
            &pipeline_cache.get_bind_group_layout(&pipeline.layout),
            &BindGroupEntries::sequential((&color, &pipeline.sampler, &depth)),
        );
        TracedTextures {
            size,
            format,
            color,
            depth,
            bind_group,
            _textures: [color_texture, depth_texture],
        }
    }
}
