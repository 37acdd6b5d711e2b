//! Anti-aliasing that costs little, moving or still: [`ManifoldFootprint`]
//! on a manifold camera traces each pixel as a cone half a pixel wide
//! instead of a ray. Balls and edge tubes thinner than the cone's
//! footprint cover the part of the pixel they would cover and let the rest
//! through, so the far copies of a hyperbolic space fade to their average
//! colour instead of sparkling, and every silhouette is smooth. The CPU
//! twin is [`crate::trace::TraceSettings::footprint`] (the core's
//! `trace::footprint`); on the GPU it is the `FOOTPRINT` specialisation
//! (`footprint.wgsl`), compiled only for views that ask for it and have
//! balls or tubes.

use bevy::prelude::*;

/// Traces this camera's pixels as cones ([`crate::trace::footprint`]).
/// It composes with [`super::ManifoldRenderScale`] (the cones are as wide
/// as the traced pixels) and [`super::ManifoldAccumulation`] (each jittered
/// sample is a cone).
///
/// ```
/// use bevy::prelude::*;
/// use bevy_manifold::prelude::*;
///
/// fn spawn(mut commands: Commands, root: Single<Entity, With<ManifoldSpace>>) {
///     commands.spawn((ChildOf(*root), ManifoldCamera::default(), ManifoldFootprint));
/// }
/// # let _ = spawn;
/// ```
#[derive(Component, Clone, Copy, Debug, Default, PartialEq, Eq, Reflect)]
#[reflect(Component, Debug, Default)]
pub struct ManifoldFootprint;
