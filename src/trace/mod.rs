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
mod flow;
mod output;
mod prepare;
mod render;
mod scene;
pub mod step;
mod walk;

pub use cast::{CastBall, CastHit, cast_balls};
pub use flow::{Flowed, flow};
pub use output::{id_pixel, write_ids_png, write_png};
pub use prepare::{EDGE_ID, FaceTables, Prepared, PreparedBall, PreparedLight, PreparedTube, ghost_centres};
pub use render::{PathStep, Stop, TraceImage, TracePixel, TraceSettings, camera_ray, render, trace_ray};
pub use scene::{Ball, Camera, Fog, Light, Scene, SceneError};
pub use walk::Walker;
