//! The camera: the components a user puts on a Bevy camera to look into
//! a manifold, apart from the render code that draws it (`crate::render`).
//!
//! - [`ManifoldCamera`] (feature `render`): the camera's view is ray-traced;
//! - [`ManifoldFog`] and [`CellShading`]: fog and per-cell shading, the
//!   view's settings (no renderer needed);
//! - [`ManifoldRenderScale`] and [`AdaptiveRenderScale`] (feature
//!   `render`): trace fewer pixels, or hold a frame rate;
//! - [`ManifoldAccumulation`] and [`ManifoldFootprint`] (feature
//!   `render`): anti-aliasing while still, and cone tracing;
//! - [`ManifoldPathTracer`] (feature `render`): the view path traced,
//!   converging while still;
//! - [`FlyCamera`], [`Vehicle`] and [`FlyCameraPlugin`] (feature
//!   `fly_camera`): flying the camera from the keyboard and mouse.

#[cfg(feature = "render")]
mod accumulate;
#[cfg(feature = "fly_camera")]
mod fly;
#[cfg(feature = "render")]
mod footprint;
#[cfg(feature = "render")]
mod path;
#[cfg(feature = "render")]
mod scale;
mod view;

#[cfg(feature = "render")]
pub use accumulate::{AccumulationProgress, ManifoldAccumulation};
#[cfg(feature = "gamepad")]
pub use fly::gamepad_motion;
#[cfg(feature = "fly_camera")]
pub use fly::{FlyCamera, FlyCameraPlugin, Vehicle, fly_camera_input, vehicle_input};
#[cfg(feature = "render")]
pub use footprint::ManifoldFootprint;
#[cfg(feature = "render")]
pub use path::ManifoldPathTracer;
#[cfg(feature = "render")]
pub use scale::{AdaptiveRenderScale, MIN_RENDER_SCALE, ManifoldRenderScale, adapt_render_scale};
pub use view::{CellShading, ManifoldFog};

#[cfg(feature = "render")]
use crate::placement::Placement;
#[cfg(feature = "render")]
use bevy::core_pipeline::tonemapping::Tonemapping;
use bevy::prelude::*;
#[cfg(feature = "render")]
use bevy::render::view::Msaa;

/// The camera components registered for reflection (fog and per-cell
/// shading; with `render`, the manifold camera, its render scale,
/// accumulation and cone tracing), and (feature `render`) the system that
/// picks an [`AdaptiveRenderScale`]'s scale each frame. Part of
/// [`crate::ManifoldPlugins`]; needs no renderer.
#[derive(Debug, Clone, Copy, Default)]
pub struct ManifoldCameraPlugin;

impl Plugin for ManifoldCameraPlugin {
    fn build(&self, app: &mut App) {
        app.register_type::<ManifoldFog>().register_type::<CellShading>();
        #[cfg(feature = "render")]
        app.register_type::<ManifoldCamera>()
            .register_type::<ManifoldRenderScale>()
            .register_type::<AdaptiveRenderScale>()
            .register_type::<ManifoldAccumulation>()
            .register_type::<ManifoldFootprint>()
            .register_type::<ManifoldPathTracer>()
            .add_systems(PostUpdate, adapt_render_scale);
    }
}

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
/// and [`CellShading`] (off). Fog is [`ManifoldFog`] on the same entity.
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
/// App::new().add_plugins((DefaultPlugins, ManifoldPlugins::default())).add_systems(Startup, setup).run();
/// ```
#[cfg(feature = "render")]
#[derive(Component, Clone, Copy, Debug, PartialEq, Reflect)]
#[reflect(Component, Debug, Default)]
#[require(Camera3d, Placement, CellShading, Tonemapping = Tonemapping::None, Msaa = Msaa::Off)]
pub struct ManifoldCamera {
    /// Most face transports per ray: the paper's levels.
    pub levels: u32,
    /// Rays stop after this distance.
    pub max_distance: f32,
    /// Reflections: how many times a ray may reflect off a surface with a
    /// material (a `StandardMaterial`'s metallic and roughness, a
    /// [`crate::drawables::TracedBall`]'s) and go on through the faces,
    /// each reflection with `levels` of its own (at most
    /// [`crate::trace::MAX_REFLECTIONS`]). 0, the default, costs nothing.
    pub reflections: u32,
}

#[cfg(feature = "render")]
impl Default for ManifoldCamera {
    fn default() -> Self {
        ManifoldCamera {
            levels: 8,
            max_distance: 100.0,
            reflections: 0,
        }
    }
}
