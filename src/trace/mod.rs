//! The CPU reference ray tracer: Algorithm 1 of the paper as DESIGN.md §2
//! spells it out, in f64 (the reference) and f32 (the same arithmetic as the
//! GPU), parallel over pixels.
//!
//! ```
//! use bevy_manifold::prelude::*;
//! let space = catalog::torus(1.0);
//! let scene = Scene::default_for(&space);
//! let settings = TraceSettings { width: 16, height: 16, ..TraceSettings::default() };
//! let img = render::<f32>(&space, &scene, &settings);
//! assert!(img.pixels.iter().all(|p| p.color.iter().all(|c| c.is_finite())));
//! ```

mod cast;
mod drift;
mod flow;
mod mesh_hit;
mod output;
mod paper;
mod prepare;
mod render;
mod scene;
mod scene_mesh;
pub mod step;
mod walk;

pub use cast::{CastBall, CastHit, cast_balls};
pub use drift::{RayDrift, ray_drift};
pub use flow::{Flowed, flow};
pub use mesh_hit::{InstanceHit, hit_instance, meets_ball, mesh_albedo, mesh_normal};
pub use output::{id_pixel, srgb8, write_ids_png, write_png};
pub use paper::{HAND_COLOR, PaperOptions, SUZANNE_COLOR, SuzanneMode, hand_offset, suzanne_offset};
pub use prepare::{
    EDGE_ID, FaceTables, Prepared, PreparedBall, PreparedInstance, PreparedLight, PreparedTube, ghost_centres,
    ghost_elements,
};
pub use render::{PathStep, Stop, TraceImage, TracePixel, TraceSettings, camera_ray, render, trace_ray};
pub use scene::{Ball, Camera, Fog, Light, Scene, SceneError};
pub use scene_mesh::{SceneMesh, baked, builtin, meshes_of};
pub use walk::Walker;
