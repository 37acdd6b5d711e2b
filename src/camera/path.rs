//! The path tracer in the render pass: [`ManifoldPathTracer`] on a
//! manifold camera makes each traced frame one sample of the rendering
//! equation per pixel (the core's [`crate::trace::path`], the GPU's
//! `PATH_TRACE` specialisation), and [`super::ManifoldAccumulation`], which
//! it requires, averages the samples while the view is still, starting
//! again when anything moves. A moving view shows one sample a frame
//! (noisy); a still one converges.

use super::ManifoldAccumulation;
use bevy::prelude::*;

/// Path traces this camera's view: paths of up to `depth` bounces, their
/// random numbers from `seed` (the same seed, sample and pixel give the
/// same path, on the CPU and the GPU). Requires
/// [`ManifoldAccumulation`] (whose `samples` says how many are averaged;
/// the default 16 is a start, 256 the most). Cell rules, cones and
/// reflections do not apply to path-traced views (the paths take every
/// lobe whole).
///
/// ```
/// use bevy::prelude::*;
/// use bevy_manifold::prelude::*;
///
/// fn spawn(mut commands: Commands, root: Single<Entity, With<ManifoldSpace>>) {
///     commands.spawn((
///         ChildOf(*root),
///         ManifoldCamera::default(),
///         ManifoldPathTracer::default(),
///         ManifoldAccumulation { samples: 256 },
///     ));
/// }
/// # let _ = spawn;
/// ```
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq, Reflect)]
#[reflect(Component, Debug, Default)]
#[require(ManifoldAccumulation)]
pub struct ManifoldPathTracer {
    /// The most bounces of a path (1 to
    /// [`crate::trace::MAX_PATH_DEPTH`]).
    pub depth: u32,
    /// The paths' seed.
    pub seed: u32,
}

impl Default for ManifoldPathTracer {
    /// Paths of up to 8 bounces, seed 0.
    fn default() -> Self {
        ManifoldPathTracer { depth: 8, seed: 0 }
    }
}
