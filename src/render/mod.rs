//! The ray-traced render pass in Bevy's renderer (feature `render`):
//! a [`crate::camera::ManifoldCamera`] looks into the manifold it lives in.
//!
//! Following Bevy's own passes, in order:
//! - main world: [`crate::drawables::gather_scenes`] gathers each space's
//!   scene when it changes (no GPU data);
//! - extract ([`extract`]): each manifold camera's view, sharing the
//!   space and the scene;
//! - prepare ([`prepare`], by stage: [`ManifoldPrepareSystems`]): each
//!   scene packed for the GPU when its generation changed, each space's
//!   buffers uploaded on change, the pipeline specialised to the view
//!   ([`pipeline`]), the view's params and bind group;
//! - the pass ([`pass`]): a `Core3d` system in the main-pass set, before
//!   Bevy's opaque pass, that draws the tracer's `fragment` entry
//!   (`bevy_manifold_gpu`'s `shaders/render.wgsl`) over the viewport; or,
//!   for a camera traced at a render scale below 1
//!   ([`crate::camera::ManifoldRenderScale`]), into smaller textures that
//!   [`upscale`] then draws over the viewport.
//!
//! The components a user puts on a camera are in [`crate::camera`].
//!
//! The fragment path was chosen over compute by measurement on lavapipe
//! (docs/benchmarks/history.md, "The pass in Bevy, and Bevy's
//! rasteriser"): it writes the view target and its depth directly, where
//! compute needs a storage texture and a copy (and Bevy's sRGB view
//! targets are not storage formats).

pub mod extract;
#[cfg(feature = "offscreen")]
pub mod offscreen;
pub mod pass;
pub mod pipeline;
pub mod prepare;
pub mod upscale;

pub use prepare::{ManifoldBufferCache, ManifoldPrepareSystems, ManifoldUploads};

use bevy::core_pipeline::core_3d::main_opaque_pass_3d;
use bevy::core_pipeline::{Core3d, Core3dSystems, FullscreenShader};
use bevy::prelude::*;
use bevy::render::render_resource::SpecializedRenderPipelines;
use bevy::render::renderer::RenderDevice;
use bevy::render::{ExtractSchedule, Render, RenderApp, RenderStartup, RenderSystems};
use bevy::shader::Shader;
use bevy_manifold_gpu::{RENDER_WGSL, SHADER_IMPORTS, UPSCALE_WGSL};

/// The render pass: the render world's extract, prepare and pass systems.
/// Part of [`crate::ManifoldPlugins`]; does nothing in an app without a
/// renderer, or without the ECS layer.
#[derive(Debug, Clone, Copy, Default)]
pub struct ManifoldRenderPlugin;

impl Plugin for ManifoldRenderPlugin {
    fn build(&self, app: &mut App) {
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
            .configure_sets(
                Render,
                (
                    ManifoldPrepareSystems::Scenes,
                    ManifoldPrepareSystems::Buffers,
                    ManifoldPrepareSystems::Pipelines,
                    ManifoldPrepareSystems::Views,
                )
                    .chain()
                    .in_set(RenderSystems::PrepareResources),
            )
            .add_systems(
                Render,
                (
                    prepare::prepare_manifold_scenes.in_set(ManifoldPrepareSystems::Scenes),
                    // Nothing is drawn (or uploaded) without the pipelines:
                    // init_trace_pipeline reported why.
                    (
                        prepare::prepare_manifold_scene_buffers.in_set(ManifoldPrepareSystems::Buffers),
                        prepare::prepare_manifold_pipelines.in_set(ManifoldPrepareSystems::Pipelines),
                        prepare::prepare_manifold_views.in_set(ManifoldPrepareSystems::Views),
                    )
                        .run_if(
                            resource_exists::<pipeline::TracePipeline>
                                .and_then(resource_exists::<upscale::UpscalePipeline>),
                        ),
                ),
            )
            .add_systems(
                Core3d,
                pass::trace_pass
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
        let entry = shaders.add(Shader::from_wgsl(RENDER_WGSL.source, RENDER_WGSL.path));
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
