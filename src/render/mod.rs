//! The ray-traced render pass in Bevy's renderer (feature `render`):
//! a [`ManifoldCamera`] looks into the manifold it lives in.
//!
//! Following Bevy's own passes, in order:
//! - main world: [`crate::drawables::gather_scenes`] gathers each space's
//!   scene when it changes (no GPU data);
//! - extract ([`extract`]): each manifold camera's view, sharing the
//!   space and the scene;
//! - prepare ([`prepare`]): each scene packed for the GPU when its
//!   generation changed, the pipeline specialised to the view
//!   ([`pipeline`]), buffers uploaded on change, the bind group;
//! - the pass ([`node`]): a `Core3d` system in the main-pass set, before
//!   Bevy's opaque pass, that draws the tracer's `fragment` entry (`bevy_manifold_gpu`'s
//!   `shaders/trace.wgsl`)
//!   over the viewport; or, for a camera traced at a render scale below 1
//!   ([`scale`]), into smaller textures that [`upscale`] then draws over
//!   the viewport.
//!
//! The fragment path was chosen over compute by measurement on lavapipe
//! (see BENCHMARKS.md): it writes the view target and its depth directly,
//! where compute needs a storage texture and a copy (and Bevy's sRGB view
//! targets are not storage formats).

pub mod accumulate;
pub mod camera;
pub mod extract;
mod footprint;
pub mod node;
#[cfg(feature = "offscreen")]
pub mod offscreen;
pub mod pipeline;
pub mod prepare;
pub mod scale;
pub mod upscale;

pub use accumulate::ManifoldAccumulation;
pub use camera::ManifoldCamera;
pub use footprint::ManifoldFootprint;
pub use prepare::{ManifoldBufferCache, ManifoldUploads};
pub use scale::{AdaptiveRenderScale, MIN_RENDER_SCALE, ManifoldRenderScale};

use bevy::core_pipeline::core_3d::main_opaque_pass_3d;
use bevy::core_pipeline::{Core3d, Core3dSystems, FullscreenShader};
use bevy::prelude::*;
use bevy::render::render_resource::SpecializedRenderPipelines;
use bevy::render::renderer::RenderDevice;
use bevy::render::{ExtractSchedule, Render, RenderApp, RenderStartup, RenderSystems};
use bevy::shader::Shader;
use bevy_manifold_gpu::{SHADER_IMPORTS, TRACE_WGSL, UPSCALE_WGSL};

/// The render pass. Added by [`crate::ManifoldPlugin`] when the app has a
/// renderer; on its own it does nothing without the ECS layer.
#[derive(Debug, Clone, Copy, Default)]
pub struct ManifoldRenderPlugin;

impl Plugin for ManifoldRenderPlugin {
    fn build(&self, app: &mut App) {
        app.register_type::<ManifoldCamera>()
            .register_type::<ManifoldRenderScale>()
            .register_type::<AdaptiveRenderScale>()
            .register_type::<ManifoldAccumulation>()
            .register_type::<ManifoldFootprint>()
            .add_systems(PostUpdate, scale::adapt_render_scale);
        let Some(render_app) = app.get_sub_app_mut(RenderApp) else {
            return;
        };
        render_app
            .init_resource::<SpecializedRenderPipelines<pipeline::TracePipeline>>()
            .init_resource::<SpecializedRenderPipelines<upscale::UpscalePipeline>>()
            .init_resource::<ManifoldBufferCache>()
            .init_resource::<ManifoldUploads>()
            .init_resource::<prepare::ManifoldPackedScenes>()
            .add_systems(RenderStartup, init_trace_pipeline)
            .add_systems(ExtractSchedule, extract::extract_manifold_views)
            .add_systems(
                Render,
                (prepare::prepare_manifold_scenes, prepare::prepare_manifold_views)
                    .chain()
                    .in_set(RenderSystems::PrepareResources),
            )
            .add_systems(
                Core3d,
                node::trace_pass
                    .in_set(Core3dSystems::MainPass)
                    .before(main_opaque_pass_3d),
            );
    }

    fn finish(&self, app: &mut App) {
        // The shader is embedded in the crate, so an app using it from
        // crates.io finds it wherever it runs from.
        let Some(mut shaders) = app.world_mut().get_resource_mut::<Assets<Shader>>() else {
            return;
        };
        let imports = SHADER_IMPORTS
            .iter()
            .map(|m| shaders.add(Shader::from_wgsl(m.source, m.path)))
            .collect();
        let entry = shaders.add(Shader::from_wgsl(TRACE_WGSL.source, TRACE_WGSL.path));
        let upscale = shaders.add(Shader::from_wgsl(UPSCALE_WGSL.source, UPSCALE_WGSL.path));
        if let Some(render_app) = app.get_sub_app_mut(RenderApp) {
            render_app.insert_resource(pipeline::TraceShader {
                entry,
                imports,
                upscale,
            });
        }
    }
}

fn init_trace_pipeline(
    mut commands: Commands,
    shader: Option<Res<pipeline::TraceShader>>,
    fullscreen: Res<FullscreenShader>,
    device: Res<RenderDevice>,
) {
    let Some(shader) = shader else {
        error!(
            "bevy_manifold: the tracer shader was not registered (no Assets<Shader>); manifold cameras will not render"
        );
        return;
    };
    if let Some(why) = bevy_manifold_gpu::bindings::uniform_limit_error(device.limits().max_uniform_buffer_binding_size)
    {
        error!("bevy_manifold: {why}; manifold cameras will not render");
        return;
    }
    commands.insert_resource(pipeline::TracePipeline::new(shader.entry.clone(), fullscreen.clone()));
    commands.insert_resource(upscale::UpscalePipeline::new(
        &device,
        shader.upscale.clone(),
        fullscreen.clone(),
    ));
}
