//! The ray-traced render pass inside a real (headless) Bevy app on a wgpu
//! device (lavapipe in CI): what a manifold camera shows against the
//! headless tracer and the CPU reference, cameras without the marker
//! untouched, uploads only on change, no buffers left behind.
//!
//! Without a GPU adapter these tests are listed as ignored; under CI
//! (`CI` set) a missing adapter is a failure.
//!
//! By topic: `agreement.rs` (what the pass draws against the tracers),
//! `uploads.rs` (what it uploads and keeps), `sampling.rs` (render scale,
//! accumulation, cones), `meshes.rs` (Bevy meshes), `animation.rs` (an
//! animated glTF character), `hdr.rs` (HDR
//! targets), `materials.rs` (Bevy's materials and lights), `product.rs` (a camera
//! in an H2xR or S2xR space); `support.rs` holds
//! what they share.

mod agreement;
mod animation;
mod hdr;
mod materials;
mod meshes;
mod product;
mod sampling;
mod support;
mod uploads;

use agreement::*;
use animation::*;
use hdr::*;
use materials::*;
use meshes::*;
use product::*;
use sampling::*;
use uploads::*;

bevy_manifold_test_support::test_main! {
    cpu: [],
    gpu: [
        a_product_camera_draws_what_the_cpu_reference_traces,
        a_product_camera_shades_each_copy_by_its_cell,
        a_product_camera_is_lit_by_its_roots_lights,
        meshes_in_a_product_space_are_traced,
        light_images_are_worked_out_once_for_every_camera_that_shows_them,
        a_cone_traced_view_is_the_cpu_cone_trace_and_nearer_supersampling,
        the_pass_draws_exact_cells_and_walls_far_from_the_origin_copy,
        the_pass_draws_what_the_tracer_computes_in_every_space,
        uploads_happen_only_when_something_changed,
        a_view_whose_space_changes_draws_each_space_from_its_reused_buffers,
        a_viewport_shows_the_same_trace_as_a_whole_target,
        cameras_without_the_marker_render_exactly_as_before,
        gltf_meshes_in_a_manifold_are_traced_and_not_rasterised,
        gltf_scene_roots_in_a_manifold_are_traced,
        a_skinned_mesh_is_traced_as_its_joints_pose_it,
        an_animated_gltf_character_is_traced_as_bevy_skins_it,
        the_papers_scene_as_entities_matches_the_tracers,
        cell_tints_agree_between_the_pass_and_the_cpu,
        a_view_at_half_scale_is_the_half_size_trace_upscaled_bilinearly,
        an_adaptive_scale_lowers_the_pixels_traced_when_frames_are_slow,
        a_still_view_accumulates_jittered_samples_then_stops_tracing,
        a_still_view_softens_the_shadows_of_a_light_with_a_radius,
        a_still_path_traced_view_is_the_cpus_mean_of_the_same_paths,
        a_scene_past_the_gpus_ball_copies_is_drawn_and_the_next_scene_is_right,
        a_view_keeps_drawing_its_balls_while_a_new_leaf_count_compiles,
        an_hdr_camera_gets_linear_radiance_above_one,
        bevy_pbr_materials_and_lights_render_as_the_cpu_reference_says,
    ],
}
