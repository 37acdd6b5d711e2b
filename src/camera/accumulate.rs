//! Anti-aliasing while the view is still: [`ManifoldAccumulation`] on a
//! manifold camera makes the pass trace the view again each frame with
//! its pixel grid moved by a sub-pixel offset and keep the running mean,
//! until `samples` frames are in; then it stops tracing and shows the
//! mean until something changes (the camera, the scene, a setting, the
//! size), when it starts again from the plain trace. Copies smaller than a
//! pixel settle to their average colour instead of flickering. The CPU
//! twin is [`crate::trace::accumulate`]; the render world's side is in
//! [`crate::render::upscale`].

use bevy::prelude::*;

/// Accumulates up to `samples` jittered traces of a still view (1: off).
/// A moving view costs what it did without it (one trace a frame, the
/// first sample is the pixel centre, plus one blend and one copy over the
/// viewport); a still one costs one copy a frame once the samples are in.
///
/// ```
/// use bevy::prelude::*;
/// use bevy_manifold::prelude::*;
///
/// fn spawn(mut commands: Commands, root: Single<Entity, With<ManifoldSpace>>) {
///     commands.spawn((ChildOf(*root), ManifoldCamera::default(), ManifoldAccumulation::default()));
/// }
/// # let _ = spawn;
/// ```
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq, Reflect)]
#[reflect(Component, Debug, Default)]
pub struct ManifoldAccumulation {
    /// The most samples per pixel kept (clamped to `1..=MAX_SAMPLES`).
    pub samples: u32,
}

impl ManifoldAccumulation {
    /// The most samples accumulated.
    pub const MAX_SAMPLES: u32 = 256;
}

impl Default for ManifoldAccumulation {
    /// 16 samples.
    fn default() -> Self {
        ManifoldAccumulation { samples: 16 }
    }
}
