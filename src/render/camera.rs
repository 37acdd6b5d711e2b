//! The main-world side of the pass: the components that make a Bevy camera
//! look into a manifold.

use crate::placement::Placement;
use crate::view::CellShading;
use bevy::core_pipeline::tonemapping::Tonemapping;
use bevy::prelude::*;
use bevy::render::view::Msaa;

/// Makes a Bevy 3D camera look into the manifold it lives in: its view is
/// ray-traced (every copy of the domain, as far as `levels` transports
/// reach) instead of rasterised. The camera goes under a
/// [`crate::placement::ManifoldSpace`] root like any placed entity; its
/// [`Placement`] and [`crate::placement::DomainCell`] say where it looks from.
///
/// Required components: `Camera3d` (so Bevy gives it a view target, and
/// ordinary meshes, gizmos and UI can still be drawn over the trace, sorted
/// by the depth the trace writes), [`Placement`], `Tonemapping::None` (the
/// tracer's colours are shown as the CPU reference computes them; set
/// another tonemapper if you like), `Msaa::Off` (the trace is per pixel)
/// and [`CellShading`] (off). Fog is [`crate::view::ManifoldFog`] on the
/// same entity.
///
/// ```no_run
/// use bevy::prelude::*;
/// use bevy_manifold::prelude::*;
/// use glam::DVec3;
///
/// fn setup(mut commands: Commands) {
///     let space = catalog::seifert_weber();
///     let root = commands.spawn((ManifoldSpace::new(space.clone()), DomainEdges::default())).id();
///     commands.spawn((ChildOf(root), ManifoldCamera::default(), Placement::at(&space, DVec3::Z * 0.3)));
///     commands.spawn((ChildOf(root), TracedBall::new(0.2, Color::srgb(0.9, 0.4, 0.2))));
///     commands.spawn((ChildOf(root), ManifoldLight::default(), Placement::at(&space, DVec3::Y * 0.4)));
/// }
///
/// App::new().add_plugins((DefaultPlugins, ManifoldPlugin::default())).add_systems(Startup, setup).run();
/// ```
#[derive(Component, Clone, Copy, Debug, PartialEq, Reflect)]
#[reflect(Component, Debug, Default)]
#[require(Camera3d, Placement, CellShading, Tonemapping = Tonemapping::None, Msaa = Msaa::Off)]
pub struct ManifoldCamera {
    /// Most face transports per ray: the paper's levels.
    pub levels: u32,
    /// Rays stop after this distance.
    pub max_distance: f32,
}

impl Default for ManifoldCamera {
    fn default() -> Self {
        ManifoldCamera {
            levels: 8,
            max_distance: 100.0,
        }
    }
}
