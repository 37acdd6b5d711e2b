//! # bevy_manifold
//!
//! Look around and move inside non-Euclidean 3-manifolds and orbifolds,
//! rendered by ray tracing: a ray that leaves the fundamental polyhedron
//! through a face comes back in through its partner, so the whole
//! tessellated cover is seen (Velho, da Silva, Novello, GI 2020).
//!
//! The crate is layered like avian: a math core free of the ECS and the
//! renderer, shared by tests, the CLI, the CPU reference tracer, the Bevy
//! plugin and its WGSL pass.
//!
//! ## In a Bevy app
//!
//! Add [`ManifoldPlugins`], put a [`placement::ManifoldSpace`] on a root
//! entity and give its descendants a [`placement::Placement`]; they move
//! along geodesics and wrap through the face pairings like light does, and
//! a [`camera::ManifoldCamera`] among them sees the manifold
//! (`examples/drop_in.rs` is a whole app):
//!
//! ```no_run
//! use bevy::prelude::*;
//! use bevy_manifold::prelude::*;
//! use glam::DVec3;
//!
//! fn setup(mut commands: Commands) {
//!     let space = catalog::seifert_weber();
//!     let root = commands.spawn(ManifoldSpace::new(space.clone())).id();
//!     commands.spawn((ChildOf(root), FlyCamera::default(), Placement::at(&space, DVec3::Z * 0.3)));
//!     commands.spawn((ChildOf(root), Placement::default(), ManifoldCollider::Ball { radius: 0.2 }));
//! }
//!
//! App::new()
//!     .add_plugins((MinimalPlugins, ManifoldPlugins::default(), FlyCameraPlugin))
//!     .add_systems(Startup, setup)
//!     .run();
//! ```
//!
//! ## The math alone
//!
//! The math is [`bevy_manifold_core`] (re-exported here as [`geometry`],
//! [`space`], [`mesh`], [`material`], [`trace`], [`motion`]); the WGSL tracer and its
//! data layout are [`bevy_manifold_gpu`]. This crate is the Bevy layer:
//!
//! - [`placement`]: the ECS layer: components, wrapping systems, ray casts.
//! - [`drawables`]: what a space's entities look like to the tracer (balls,
//!   lights, edges, Bevy meshes; `drawables::paper`, feature
//!   `paper_scene`: the paper's scene as entities).
//! - [`camera`]: what a user puts on a camera: [`camera::ManifoldCamera`],
//!   fog, per-cell shading, render scale, anti-aliasing, and (feature
//!   `fly_camera`) a fly camera and the vehicle.
//! - [`tour`]: tours played by entities.
//! - `assets` (feature `asset`): space and tour files as Bevy assets.
//! - `render` (feature `render`, default): the ray-traced pass in Bevy's
//!   renderer, by stage; `render::offscreen` (feature `offscreen`) for
//!   windowless apps that read their images back.
//! - `xr` (feature `xr`): VR through OpenXR.
//!
//! [`ManifoldPlugins`] lists the plugins, each of which can be left out.
//!
//! Features: `render` (default) is the pass only: never a window, never
//! egui. `standard_material` reads traced meshes' `StandardMaterial`s.
//! The explorer and the command line are the `bevy_manifold_app` crate.
//!
//! ```
//! use bevy_manifold::prelude::*;
//!
//! let space = catalog::poincare();
//! let scene = Scene::default_for(&space);
//! let settings = TraceSettings { width: 32, height: 18, ..TraceSettings::default() };
//! let image = render::<f64>(&space, &scene, &settings);
//! assert_eq!(image.pixels.len(), 32 * 18);
//! // The ball at the centre of the domain is seen in the middle of the view.
//! assert!(image.pixels.iter().any(|p| p.object == 1));
//! ```

#[cfg(feature = "asset")]
pub mod assets;
#[cfg(feature = "audio")]
pub mod audio;
pub mod camera;
pub mod drawables;
pub mod placement;
mod plugin;
pub mod product;
#[cfg(feature = "render")]
pub mod render;
pub mod tour;
#[cfg(feature = "xr")]
pub mod xr;

pub use bevy_manifold_core;
pub use bevy_manifold_core::{contact, geometry, material, mesh, motion, space, trace};
pub use bevy_manifold_gpu;
pub use plugin::ManifoldPlugins;

/// The types most users need.
pub mod prelude {
    pub use crate::ManifoldPlugins;
    #[cfg(feature = "asset")]
    pub use crate::assets::{ManifoldAssetsPlugin, ManifoldSpaceSource, SpaceAsset, TourAsset, TourSource};
    #[cfg(feature = "render")]
    pub use crate::camera::{
        AccumulationProgress, AdaptiveRenderScale, ManifoldAccumulation, ManifoldCamera, ManifoldFootprint,
        ManifoldPathTracer, ManifoldRenderScale,
    };
    pub use crate::camera::{CellShading, ManifoldCameraPlugin, ManifoldFog};
    #[cfg(feature = "fly_camera")]
    pub use crate::camera::{FlyCamera, FlyCameraPlugin, Vehicle};
    #[cfg(feature = "render")]
    pub use crate::drawables::{CameraBody, Rasterized};
    pub use crate::drawables::{
        DomainEdges, DrawablesPlugin, ManifoldLight, ManifoldLighting, ManifoldMeshes, ManifoldScene, SpotCone,
        TracedBall,
    };
    pub use crate::placement::{
        ContactEnded, ContactEvents, ContactStarted, DomainCell, FaceCrossed, GeodesicVelocity, InSpace,
        ManifoldCollider, ManifoldContacts, ManifoldRayCast, ManifoldSpace, ManifoldSystems, Overlap, Placement,
        PlacementPlugin, RayCastSettings, RayHit, SpaceMembers, WallHit,
    };
    #[cfg(feature = "render")]
    pub use crate::render::ManifoldRenderPlugin;
    pub use crate::tour::{Tour, TourPlayer};
    pub use bevy_manifold_core::prelude::*;
}
