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
//! geodesic flow and the ray casts. The tracer is split by stage, each
//! file with a WGSL twin of the same name in `bevy_manifold_gpu`'s
//! `shaders/` (the same functions, by the same names, in the same
//! order):
//!
//! | stage | Rust | WGSL |
//! |---|---|---|
//! | what to trace | `settings.rs` ([`TraceSettings`]) | `bindings.wgsl` (`Params`) |
//! | a pixel's ray | `camera.rs` ([`view_ray`]) | `camera.wgsl` |
//! | one ray, Algorithm 1 | `trace.rs` ([`trace_ray`]) | `trace.wgsl` |
//! | the walk through the faces | `walk.rs`, `step.rs` | `walk.wgsl`, `step.wgsl` |
//! | which objects a segment may meet | `cull.rs` ([`each_candidate`]) | `cull.wgsl` |
//! | what it keeps of them | `nearest.rs` | `nearest.wgsl` |
//! | the trees of balls and of instances | `ball_tree.rs`, `instance_tree.rs` | `ball_tree.wgsl`, `instance_tree.wgsl` |
//! | a pixel's cone | `cone.rs`, `footprint.rs` | `cone.wgsl`, `footprint.wgsl` |
//! | shading a hit | `shade.rs` | `shade.wgsl` |
//! | every pixel | `render.rs` ([`render`]) | `render.wgsl` (entry points) |
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
mod camera;
mod cast;
mod cone;
mod cull;
mod drift;
mod exact_cell;
mod exr;
mod face_groups;
mod flat;
mod flow;
pub mod footprint;
mod instance_tree;
mod light_images;
mod mesh_hit;
mod nearest;
mod output;
pub mod path;
pub mod product;
mod render;
pub mod scene;
mod settings;
mod shade;
pub mod shadow;
pub mod step;
#[expect(
    clippy::module_inception,
    reason = "the stage that traces one ray, named as its WGSL twin trace.wgsl"
)]
mod trace;
mod walk;

pub use accumulate::{accumulate, light_sample_point, sample_frustum, sample_offset};
pub use ball_tree::{
    BALL_LEAF_SIZE, BallTree, FULL_LEAF_SIZE, MAX_BALL_LEAVES, SMALL_LEAVES, UNBOUNDED, ball_box, chart_segment,
    leaf_count, tree_leaves,
};
pub use camera::{camera_ray, pixel_half_angle_of, view_ray, view_slopes};
pub use cast::{CastBall, CastHit, CastWall, cast_balls, cast_with_rule};
pub use cull::{Candidate, each_candidate};
pub use drift::{RayDrift, ray_drift};
pub use exr::{exr_bytes, write_exr};
pub use face_groups::{FaceGroups, near_reach};
pub use flat::{
    EDGE_ID, FaceTables, FlatBall, FlatInstance, FlatLight, FlatScene, FlatTube, MIN_BALL_TREE, ghost_centres,
    ghost_elements,
};
pub use flow::{Flowed, flow};
pub use footprint::{Layers, pixel_half_angle};
pub use instance_tree::{InstanceTree, MIN_INSTANCE_TREE, TreeOrder, chart_fraction, octant, tree_instances};
pub use light_images::{MAX_LIGHT_IMAGES, MIN_AREA, image_irradiance, light_images, spot_factor};
pub use mesh_hit::{
    InstanceHit, hit_instance, hit_uv, meets_ball, mesh_alpha, mesh_normal, mesh_surface, normal_mapped,
};
pub use nearest::same_cell_point;
pub use output::{id_pixel, srgb8, upscale};
#[cfg(feature = "png")]
pub use output::{write_hdr, write_ids_png, write_png, write_rgba_png};
pub use path::{Bounce, Lobes, PathRng, path_sample, power_heuristic};
pub use render::{TraceImage, render};
pub use scene::MeshPart;
pub use scene::{
    Ball, Camera, Fog, Frustum, HAND_COLOR, Light, Lighting, MAX_GLOW, MAX_LIGHTS, MAX_MESHES, PaperOptions,
    SUZANNE_COLOR, Scene, SceneError, SceneMesh, Spot, SuzanneMode, VEHICLE_COLOR, baked, hand_offset, max_radius,
    mirror_ball, suzanne_offset, vehicle_offset,
};
#[cfg(feature = "gltf")]
pub use scene::{builtin, meshes_of};
pub use settings::{MAX_LEVELS, MAX_PATH_DEPTH, MAX_PIXELS, MAX_REFLECTIONS, Projection, TraceSettings};
pub use shade::{LIGHT_AT_HIT, MAX_MIRROR_ROUGHNESS, MIRROR_OFFSET, Mirror, mirror_ray};
pub use trace::{FOG_CUT, PathStep, Stop, TracePixel, trace_path, trace_ray};
pub use walk::Walker;
