//! Preparation, by stage, each a system of
//! `RenderSystems::PrepareResources` in the order of
//! [`ManifoldPrepareSystems`]:
//!
//! 1. [`prepare_manifold_scenes`] (`scenes.rs`): each space's scene packed
//!    for the GPU when its generation or its space changed, its cell
//!    table recentred off the frame when the camera's cell changed
//!    ([`bevy_manifold_gpu::PackedSpace`], the one cache the headless
//!    runner keeps too);
//! 2. [`prepare_manifold_scene_buffers`] (`buffers.rs`): each space's
//!    buffers, shared by every view into it, written only where what they
//!    hold changed;
//! 3. [`prepare_manifold_pipelines`] (`pipelines.rs`): per view, the
//!    pipeline specialised to it, or the last one while that compiles;
//! 4. [`prepare_manifold_views`] (`views.rs`): per view, its params
//!    (written only when the camera or a setting changed), its bind group
//!    (built from [`bevy_manifold_gpu::bindings::BINDINGS`]), and for a
//!    view traced below full scale or accumulating, its textures.
//!
//! The params buffer (`GpuParams`) is per view, the rest per space.
//! [`ManifoldUploads`] counts what was uploaded, so this is testable.

mod buffers;
mod cache;
mod pipelines;
mod scenes;
mod views;

pub use buffers::prepare_manifold_scene_buffers;
pub use cache::{ManifoldBufferCache, ManifoldUploads};
pub use pipelines::prepare_manifold_pipelines;
pub use scenes::{ManifoldPackedScenes, prepare_manifold_scenes};
pub use views::prepare_manifold_views;

use bevy::prelude::*;

/// The stages of the pass's preparation, in order, in
/// `RenderSystems::PrepareResources`.
#[derive(SystemSet, Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ManifoldPrepareSystems {
    /// Scenes packed ([`prepare_manifold_scenes`]).
    Scenes,
    /// Each space's buffers written ([`prepare_manifold_scene_buffers`]).
    Buffers,
    /// Each view's pipeline specialised ([`prepare_manifold_pipelines`]).
    Pipelines,
    /// Each view's params, bind group and textures
    /// ([`prepare_manifold_views`]).
    Views,
}
