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
use std::sync::Arc;
use std::sync::atomic::{AtomicU32, Ordering};

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

/// How many samples a camera's [`ManifoldAccumulation`] has averaged in
/// the image last drawn: put it beside the accumulation and read
/// [`AccumulationProgress::samples`] in the main world (the explorer shows
/// it for the path tracer). The render world writes it each frame it
/// draws the view; clones share the count.
///
/// ```
/// use bevy::prelude::*;
/// use bevy_manifold::prelude::*;
///
/// fn report(cameras: Query<(&ManifoldAccumulation, &AccumulationProgress)>) {
///     for (wanted, progress) in &cameras {
///         info!("{} of {} samples", progress.samples(), wanted.samples);
///     }
/// }
/// # let _ = report;
/// ```
#[derive(Component, Clone, Debug, Default)]
pub struct AccumulationProgress(Arc<AtomicU32>);

impl AccumulationProgress {
    /// Samples averaged in the image last drawn (0 before the first).
    #[must_use]
    pub fn samples(&self) -> u32 {
        self.0.load(Ordering::Relaxed)
    }

    /// Sets the count (the render world does, each frame it draws).
    pub fn set(&self, samples: u32) {
        self.0.store(samples, Ordering::Relaxed);
    }
}
