//! The pass: a `Core3d` system, in the main-pass set before Bevy's opaque
//! pass, that traces every pixel of a manifold camera's viewport into its
//! view target and depth. Views without a [`ManifoldViewBinding`] (every
//! ordinary camera) skip it: the `ViewQuery` does not match them.

use bevy::prelude::*;
use bevy::render::camera::ExtractedCamera;
use bevy::render::render_resource::{
    BindGroup, CachedRenderPipelineId, LoadOp, Operations, PipelineCache, RenderPassColorAttachment,
    RenderPassDepthStencilAttachment, RenderPassDescriptor, StoreOp, TextureView,
};
use bevy::render::renderer::{RenderContext, ViewQuery};
use bevy::render::view::{ViewDepthTexture, ViewTarget};

/// What the pass needs to draw a manifold view this frame.
#[derive(Component, Clone)]
pub struct ManifoldViewBinding {
    /// The specialised pipeline.
    pub pipeline: CachedRenderPipelineId,
    /// Group 0.
    pub bind_group: BindGroup,
    /// For a view traced below full scale: where the trace goes and how
    /// it is upscaled.
    pub scaled: Option<ScaledBinding>,
}

/// A view traced into textures of its own (below full scale, or
/// accumulating): the traced textures, the blend into the history, the
/// upscale.
#[derive(Clone)]
pub struct ScaledBinding {
    /// The upscale pipeline for the view target.
    pub pipeline: CachedRenderPipelineId,
    /// The traced colour the trace draws into.
    pub color: TextureView,
    /// The traced depth.
    pub depth: TextureView,
    /// Group 0 of the upscale (the history when accumulating).
    pub bind_group: BindGroup,
    /// Trace this frame (false once a still view has all its samples).
    pub trace: bool,
    /// The blend of this frame's trace into the history.
    pub blend: Option<BlendIn>,
}

/// The blend of a trace into a view's accumulation history.
#[derive(Clone)]
pub struct BlendIn {
    /// The `blend_in` pipeline.
    pub pipeline: CachedRenderPipelineId,
    /// The history drawn into.
    pub history: TextureView,
    /// Group 0: the trace.
    pub source: BindGroup,
    /// The first sample: the history is cleared before it is added.
    pub first: bool,
}

/// Draws the full-screen trace of one manifold view. The colour target is
/// taken with Bevy's clear-on-first-use, so the opaque pass that follows
/// draws ordinary meshes over the trace, depth-tested against it. A view
/// traced below full scale, or accumulating samples while still, is
/// traced into textures of its own (blended into its history when
/// accumulating, and not traced at all once a still view has all its
/// samples), then drawn over the viewport (`upscale.wgsl`).
pub fn trace_pass(
    view: ViewQuery<(&ExtractedCamera, &ViewTarget, &ViewDepthTexture, &ManifoldViewBinding)>,
    pipeline_cache: Res<PipelineCache>,
    mut ctx: RenderContext,
) {
    let (camera, target, depth, binding) = view.into_inner();
    // Still compiling (or failed, which prepare reported): the view shows
    // its clear colour this frame.
    let Some(pipeline) = pipeline_cache.get_render_pipeline(binding.pipeline) else {
        return;
    };
    let (pipeline, bind_group) = match &binding.scaled {
        None => (pipeline, &binding.bind_group),
        Some(scaled) => {
            let Some(upscale) = pipeline_cache.get_render_pipeline(scaled.pipeline) else {
                return;
            };
            let blend = match &scaled.blend {
                Some(b) => match pipeline_cache.get_render_pipeline(b.pipeline) {
                    Some(p) => Some((p, b)),
                    None => return,
                },
                None => None,
            };
            if scaled.trace {
                let color = [Some(RenderPassColorAttachment {
                    view: &scaled.color,
                    depth_slice: None,
                    resolve_target: None,
                    ops: Operations {
                        load: LoadOp::Clear(Default::default()),
                        store: StoreOp::Store,
                    },
                })];
                let mut pass = ctx.begin_tracked_render_pass(RenderPassDescriptor {
                    label: Some("manifold_trace_own"),
                    color_attachments: &color,
                    depth_stencil_attachment: Some(RenderPassDepthStencilAttachment {
                        view: &scaled.depth,
                        depth_ops: Some(Operations {
                            load: LoadOp::Clear(0.0),
                            store: StoreOp::Store,
                        }),
                        stencil_ops: None,
                    }),
                    timestamp_writes: None,
                    occlusion_query_set: None,
                    multiview_mask: None,
                });
                pass.set_render_pipeline(pipeline);
                pass.set_bind_group(0, &binding.bind_group, &[]);
                pass.draw(0..3, 0..1);
            }
            if let Some((blend_in, b)) = blend {
                // The history is the samples' sum (their count in alpha);
                // the first sample starts it from zero.
                let color = [Some(RenderPassColorAttachment {
                    view: &b.history,
                    depth_slice: None,
                    resolve_target: None,
                    ops: Operations {
                        load: if b.first {
                            LoadOp::Clear(Default::default())
                        } else {
                            LoadOp::Load
                        },
                        store: StoreOp::Store,
                    },
                })];
                let mut pass = ctx.begin_tracked_render_pass(RenderPassDescriptor {
                    label: Some("manifold_blend_in"),
                    color_attachments: &color,
                    depth_stencil_attachment: None,
                    timestamp_writes: None,
                    occlusion_query_set: None,
                    multiview_mask: None,
                });
                pass.set_render_pipeline(blend_in);
                pass.set_bind_group(0, &b.source, &[]);
                pass.draw(0..3, 0..1);
            }
            (upscale, &scaled.bind_group)
        }
    };
    let color = [Some(target.get_color_attachment())];
    let mut pass = ctx.begin_tracked_render_pass(RenderPassDescriptor {
        label: Some("manifold_trace"),
        color_attachments: &color,
        depth_stencil_attachment: Some(depth.get_attachment(StoreOp::Store)),
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    });
    if let Some(viewport) = camera.viewport.as_ref() {
        pass.set_camera_viewport(viewport);
    }
    pass.set_render_pipeline(pipeline);
    pass.set_bind_group(0, bind_group, &[]);
    pass.draw(0..3, 0..1);
}
