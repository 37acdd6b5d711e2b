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
//! Add [`ManifoldPlugin`], put a [`placement::ManifoldSpace`] on a root
//! entity and give its descendants a [`placement::Placement`]; they move
//! along geodesics and wrap through the face pairings like light does
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
//!     .add_plugins((MinimalPlugins, ManifoldPlugin::default(), FlyCameraPlugin))
//!     .add_systems(Startup, setup)
//!     .run();
//! ```
//!
//! ## The math alone
//!
//! - [`geometry`]: E3, H3 and S3 in one projective chart; isometries; planes.
//! - [`space`]: fundamental polyhedra with face pairings, validation, the
//!   catalog of the paper's five spaces, space files.
//! - [`cell`]: path-independent ids for the copies of the domain.
//! - [`mesh`]: triangle meshes, their BVH, and glTF loading.
//! - [`trace`]: the CPU reference ray tracer (Algorithm 1), in f64 and in an
//!   f32 mode that mirrors the GPU arithmetic; geodesic flow; ray casts.
//! - [`motion`]: moving placements through the faces (the math of wrapping).
//! - [`stress`]: the degenerate rays and far-travel paths the numerical
//!   stability checks use.
//! - [`placement`]: the ECS layer: components, wrapping systems, ray casts.
//! - [`camera_controller`]: an optional fly camera.
//! - `explorer` (feature `app`): what `cargo run --release` opens; its
//!   plugins, settings and headless fallback.
//! - `paper_scene`, `showcase` (feature `app`): the paper's scene as
//!   entities, and what the examples (one per paper figure) share.
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

pub mod camera_controller;
pub mod cell;
pub mod drawables;
#[cfg(feature = "app")]
pub mod explorer;
pub mod geometry;
pub mod mesh;
pub mod motion;
#[cfg(feature = "app")]
pub mod paper_scene;
pub mod placement;
mod plugin;
pub mod render;
#[cfg(feature = "app")]
pub mod showcase;
pub mod space;
pub mod stress;
pub mod trace;
#[cfg(feature = "render")]
pub mod traced_meshes;

pub use plugin::ManifoldPlugin;

/// The types most users need.
pub mod prelude {
    pub use crate::ManifoldPlugin;
    pub use crate::camera_controller::{FlyCamera, FlyCameraPlugin};
    pub use crate::cell::CellId;
    pub use crate::drawables::{
        DomainEdges, DrawablesPlugin, ManifoldLight, ManifoldMeshes, ManifoldScene, TracedBall,
    };
    pub use crate::geometry::{Geometry, Real, isometry, plane};
    pub use crate::placement::{
        DomainCell, FaceCrossed, GeodesicVelocity, ManifoldCollider, ManifoldRayCast, ManifoldSpace, ManifoldSystems,
        Placement, PlacementPlugin, RayCastSettings, RayHit,
    };
    #[cfg(feature = "render")]
    pub use crate::render::pass::{CellShading, ManifoldCamera, ManifoldFog};
    pub use crate::space::{Face, FaceKind, Space, SpaceDesc, SpaceError, catalog};
    pub use crate::trace::{Ball, Fog, Light, Scene, SceneMesh, TraceImage, TraceSettings, render};
    #[cfg(feature = "render")]
    pub use crate::traced_meshes::{CameraBody, Rasterized};
}
