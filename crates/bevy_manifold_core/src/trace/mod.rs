//! The CPU reference ray tracer: Algorithm 1 of the paper, in f64 (the
//! reference) and f32 (the same arithmetic as the GPU), parallel over
//! pixels. Each pixel's ray, from the camera's cell:
//!
//! ```text
//! for level in 0..levels:
//!     t_obj  = nearest scene-object hit inside the domain
//!     t_face = nearest exit face (n . d > 0), skipping the face just entered
//!     if t_obj < t_face: shade at the hit (lights, fog by distance so far); stop
//!     transport: (o, d) <- T_face (hit point, d); cell <- cell * g_face
//!     renormalise (o, d); add the segment length to the travelled distance
//!     stop early when fog has made the rest invisible (transmittance < 1/255)
//! no hit: fog / background colour
//! ```
//!
//! Where a ray crosses a face is [`step::exit_face`]; the loop above is
//! [`Walker`] (`walk.rs`), shared by the render, the drift probe, the
//! geodesic flow and the ray casts. The WGSL twin of each file is named in
//! its docs (`bevy_manifold_gpu`'s `shaders/`).
//!
//! ```
//! use bevy_manifold_core::prelude::*;
//! let space = catalog::torus(1.0);
//! let scene = Scene::default_for(&space);
//! let settings = TraceSettings { width: 16, height: 16, ..TraceSettings::default() };
//! let img = render::<f32>(&space, &scene, &settings);
//! assert!(img.pixels.iter().all(|p| p.color.iter().all(|c| c.is_finite())));
//! ```

mod accumulate;
mod ball_tree;
mod cast;
mod cull;
mod drift;
mod exact_cell;
mod flat;
mod flow;
pub mod footprint;
mod mesh_hit;
mod output;
mod render;
pub mod scene;
pub mod step;
mod walk;

pub use accumulate::{accumulate, sample_offset};
pub use ball_tree::{
    BALL_LEAF_SIZE, BallTree, FULL_LEAF_SIZE, MAX_BALL_LEAVES, SMALL_LEAVES, UNBOUNDED, ball_box, chart_segment,
    leaf_count, tree_leaves,
};
pub use cast::{CastBall, CastHit, CastWall, cast_balls, cast_with_rule};
pub use cull::{Candidate, FaceGroups, each_candidate, near_reach};
pub use drift::{RayDrift, ray_drift};
pub use flat::{
    EDGE_ID, FaceTables, FlatBall, FlatInstance, FlatLight, FlatScene, FlatTube, MIN_BALL_TREE, ghost_centres,
    ghost_elements, same_cell_point,
};
pub use flow::{Flowed, flow};
pub use footprint::{Layers, pixel_half_angle};
pub use mesh_hit::{InstanceHit, hit_instance, meets_ball, mesh_albedo, mesh_normal};
pub use output::{id_pixel, srgb8, upscale};
#[cfg(feature = "png")]
pub use output::{write_ids_png, write_png, write_rgba_png};
pub use render::{
    FOG_CUT, LIGHT_AT_HIT, MAX_LEVELS, MAX_PIXELS, PathStep, Projection, Stop, TraceImage, TracePixel, TraceSettings,
    camera_ray, pixel_half_angle_of, render, trace_ray, view_ray, view_slopes,
};
pub use scene::MeshPart;
pub use scene::{
    Ball, Camera, Fog, Frustum, HAND_COLOR, Light, MAX_GLOW, MAX_LIGHTS, PaperOptions, SUZANNE_COLOR, Scene,
    SceneError, SceneMesh, SuzanneMode, VEHICLE_COLOR, baked, hand_offset, max_radius, suzanne_offset, vehicle_offset,
};
#[cfg(feature = "gltf")]
pub use scene::{builtin, meshes_of};
pub use walk::Walker;
