//! What the pass keeps between frames in the render world: each space's
//! buffers ([`SceneBuffers`]), each view's params buffer, bind group and
//! textures ([`ViewBuffers`]) and the pipeline it was drawn with
//! ([`ViewPipeline`]), and the totals of what was uploaded
//! ([`ManifoldUploads`]).

use super::super::pipeline::TracePipelineKey;
use super::super::upscale::TracedTextures;
use bevy::platform::collections::{HashMap, HashSet};
use bevy::prelude::*;
use bevy::render::render_resource::{BindGroup, Buffer, CachedRenderPipelineId};
use bevy_manifold_gpu::bindings::Binding;
use bevy_manifold_gpu::{GpuObjects, GpuParams, GpuSpace};
use std::sync::Arc;

/// Running totals of what the pass uploaded (render world). Uploads happen
/// on change only: a still camera in a still scene uploads nothing.
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ManifoldUploads {
    /// Times a space's faces and cell table were uploaded.
    pub space: u64,
    /// Times a scene's balls, tubes, lights and instances were uploaded
    /// (the meshes' data only when it changed).
    pub objects: u64,
    /// Times a view's params buffer was written.
    pub params: u64,
    /// Bytes uploaded in all.
    pub bytes: u64,
}

/// One space's buffers (by the main-world root entity) and what they
/// hold: shared by every view into that space, so a headset's two eyes
/// upload the scene once, not once each.
pub(super) struct SceneBuffers {
    pub(super) space: Arc<GpuSpace>,
    pub(super) objects: Arc<GpuObjects>,
    /// A buffer for each binding of `BINDINGS` the space or its objects
    /// fill, in binding order.
    pub(super) buffers: Vec<(&'static Binding, Buffer)>,
    /// Bumped whenever a buffer is made anew (the views' bind groups then
    /// are made again).
    pub(super) made: u64,
}

/// One view's own buffer (its params) and its bind group.
pub(super) struct ViewBuffers {
    /// The root whose [`SceneBuffers`] the bind group binds, and their
    /// `made` then.
    pub(super) bound: Option<(Entity, u64)>,
    pub(super) params: GpuParams,
    pub(super) params_buffer: Buffer,
    pub(super) bind_group: Option<BindGroup>,
    /// The traced textures of a view below full scale or accumulating.
    pub(super) traced: Option<TracedTextures>,
    /// The params before any jitter last frame, the space and objects
    /// they were packed from, and the samples wanted: a still view has
    /// all four unchanged.
    pub(super) still: Option<(GpuParams, usize, usize, u32)>,
    /// Samples accumulated in the history so far.
    pub(super) samples: u32,
}

/// The pipeline a view is drawn with this frame, and how it was last
/// drawn.
#[derive(Clone, Copy)]
pub(super) struct ViewPipeline {
    /// The pipeline drawn with: the view's own, or while that compiles the
    /// last one drawn.
    pub(super) id: CachedRenderPipelineId,
    /// The size it is traced at into textures of its own, if it is (at
    /// the pipeline drawn with).
    pub(super) traced: Option<UVec2>,
    /// The view target's sample count and whether its target stores
    /// sRGB-encoded values the shader encodes.
    pub(super) samples: u32,
    /// The view target stores sRGB-encoded values without encoding them.
    pub(super) encode_srgb: bool,
    /// How the view was last drawn: into textures of its own, and the
    /// trace pipeline and its key.
    pub(super) drawn: Option<(bool, CachedRenderPipelineId, TracePipelineKey)>,
}

/// Every manifold view's buffers and pipeline, by render-world view
/// entity, and every space's buffers, by root; views that went away are
/// dropped (with their buffers) the next frame, and spaces no view looks
/// into with them.
#[derive(Resource, Default)]
pub struct ManifoldBufferCache {
    pub(super) views: HashMap<Entity, ViewBuffers>,
    pub(super) pipelines: HashMap<Entity, ViewPipeline>,
    pub(super) scenes: HashMap<Entity, SceneBuffers>,
    pub(super) failed: HashSet<CachedRenderPipelineId>,
}

impl ManifoldBufferCache {
    /// How many views hold buffers.
    #[must_use]
    pub fn len(&self) -> usize {
        self.views.len()
    }

    /// Drops every view's buffers and bind groups, so the next frame
    /// uploads everything again as if nothing had been uploaded before
    /// (`bench specialise` measures what change detection saves this way).
    pub fn invalidate(&mut self) {
        self.views.clear();
        self.pipelines.clear();
        self.scenes.clear();
    }

    /// How many spaces' scenes are held on the GPU (one for any number of
    /// views into a space).
    #[must_use]
    pub fn scenes(&self) -> usize {
        self.scenes.len()
    }

    /// True when no view holds buffers.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.views.is_empty()
    }
}
