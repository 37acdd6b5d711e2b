//! The tracer's render pipeline, specialised per view: the scene's shader
//! defs ([`TraceDefs`]) and the view target's format and sample count.
//! Bevy's pipeline cache composes the tracer's WGSL with those defs, so a
//! fog-free torus compiles no fog and no hyperbolic code.

use bevy::core_pipeline::FullscreenShader;
use bevy::core_pipeline::core_3d::CORE_3D_DEPTH_FORMAT;
use bevy::prelude::*;
use bevy::render::render_resource::{
    BindGroupLayoutDescriptor, BindGroupLayoutEntry, BindingType, ColorTargetState, ColorWrites, CompareFunction,
    DepthStencilState, FragmentState, MultisampleState, RenderPipelineDescriptor, ShaderStages,
    SpecializedRenderPipeline, TextureFormat,
};
use bevy::shader::{Shader, ShaderDefVal};
use bevy_manifold_gpu::TraceDefs;
use bevy_manifold_gpu::bindings::render_bindings;

/// The embedded tracer shader, added to `Assets<Shader>` by the plugin:
/// the entry module, and the import modules it needs (their handles kept
/// here, or Bevy would drop them and the pipeline would wait for an
/// import forever).
#[derive(Resource, Clone)]
pub struct TraceShader {
    /// `render.wgsl`, the entry points.
    pub entry: Handle<Shader>,
    /// The modules it imports, kept alive.
    pub imports: Vec<Handle<Shader>>,
    /// `upscale.wgsl`, for views traced below full scale.
    pub upscale: Handle<Shader>,
}

/// What the tracer pipeline is specialised on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TracePipelineKey {
    /// The scene's defs.
    pub defs: TraceDefs,
    /// The view target's format.
    pub format: TextureFormat,
    /// The view target's sample count (MSAA).
    pub samples: u32,
    /// The target stores sRGB-encoded values the shader must encode
    /// (`ENCODE_SRGB`).
    pub encode_srgb: bool,
}

impl TracePipelineKey {
    /// The shader defs of this key.
    #[must_use]
    pub fn shader_defs(&self) -> Vec<ShaderDefVal> {
        let mut names = self.defs.names();
        if self.encode_srgb {
            names.push("ENCODE_SRGB");
        }
        let mut defs: Vec<ShaderDefVal> = names.into_iter().map(ShaderDefVal::from).collect();
        defs.extend(
            self.defs
                .values()
                .into_iter()
                .map(|(name, value)| ShaderDefVal::UInt(name.into(), value)),
        );
        defs
    }
}

/// The tracer pipeline's layout and shaders (render world).
#[derive(Resource, Clone)]
pub struct TracePipeline {
    /// Group 0: the params, then faces, balls, tubes, lights, the
    /// cell table, mesh instances and mesh data (the compute path's
    /// `pixels` is not bound here).
    pub layout: BindGroupLayoutDescriptor,
    shader: Handle<Shader>,
    fullscreen: FullscreenShader,
}

impl TracePipeline {
    /// The pipeline for `shader`.
    #[must_use]
    pub fn new(shader: Handle<Shader>, fullscreen: FullscreenShader) -> Self {
        // The render bindings of the one table, as the runner's layout.
        let entries: Vec<BindGroupLayoutEntry> = render_bindings()
            .map(|b| BindGroupLayoutEntry {
                binding: b.binding,
                visibility: ShaderStages::FRAGMENT,
                ty: BindingType::Buffer {
                    ty: b.kind.buffer_binding_type(),
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            })
            .collect();
        let layout = BindGroupLayoutDescriptor::new("manifold_trace", &entries);
        TracePipeline {
            layout,
            shader,
            fullscreen,
        }
    }
}

impl SpecializedRenderPipeline for TracePipeline {
    type Key = TracePipelineKey;

    fn specialize(&self, key: Self::Key) -> RenderPipelineDescriptor {
        fullscreen_with_depth(
            "manifold_trace",
            &self.layout,
            &self.fullscreen,
            (&self.shader, "fragment", key.shader_defs()),
            key.format,
            key.samples,
        )
    }
}

/// A pipeline drawing Bevy's full-screen triangle with the fragment
/// entry `entry` of `shader` (with `defs`) into a colour target of
/// `format` and `samples`, writing the depth it outputs (any, always):
/// the trace's and the upscale's.
pub(crate) fn fullscreen_with_depth(
    label: &'static str,
    layout: &BindGroupLayoutDescriptor,
    fullscreen: &FullscreenShader,
    (shader, entry, defs): (&Handle<Shader>, &'static str, Vec<ShaderDefVal>),
    format: TextureFormat,
    samples: u32,
) -> RenderPipelineDescriptor {
    RenderPipelineDescriptor {
        label: Some(label.into()),
        layout: vec![layout.clone()],
        vertex: fullscreen.to_vertex_state(),
        fragment: Some(FragmentState {
            shader: shader.clone(),
            shader_defs: defs,
            entry_point: Some(entry.into()),
            targets: vec![Some(ColorTargetState {
                format,
                blend: None,
                write_mask: ColorWrites::ALL,
            })],
        }),
        depth_stencil: Some(DepthStencilState {
            format: CORE_3D_DEPTH_FORMAT,
            depth_write_enabled: Some(true),
            depth_compare: Some(CompareFunction::Always),
            stencil: default(),
            bias: default(),
        }),
        multisample: MultisampleState {
            count: samples,
            ..default()
        },
        ..default()
    }
}
