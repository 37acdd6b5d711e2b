//! Shadows through the faces: a light image lights a hit only if the
//! geodesic between them is free. The shadow ray walks through the faces
//! as a camera ray does ([`Walker`], the same exit and transport), and on
//! each segment meets the same objects ([`each_candidate`]): balls
//! (glowing ones, the lamps, cast no shadow), edge tubes and meshes,
//! ghost copies straddling a face included. It stops at the light.
//!
//! WGSL twin: `shaders/shadow.wgsl` in `bevy_manifold_gpu` (the same
//! names).

use super::cull::{Candidate, each_candidate};
use super::flat::FlatScene;
use super::mesh_hit::hit_instance;
use super::nearest::instance_shown;
use super::step::{ALL_FACES, Ray, advance, hit_ball, hit_tube, may_hit, near_faces};
use super::walk::Walker;
use crate::geometry::Real;

/// How far off the surface a shadow ray starts, along the normal, so
/// that the surface it leaves does not shadow itself.
/// WGSL twin: `SHADOW_OFFSET` in `shaders/shadow.wgsl`.
pub const SHADOW_OFFSET: f64 = 1e-4;

/// Most faces a shadow ray crosses; past them the light is taken as seen.
/// WGSL twin: `SHADOW_LEVELS` in `shaders/shadow.wgsl`.
pub const SHADOW_LEVELS: u32 = 24;

/// True when something lies on the geodesic leaving the hit `x` (normal
/// `normal`, in the cell `cell`) along the unit tangent `dir` within
/// distance `length`, the arc to a light image.
/// WGSL twin: `light_blocked` in `shaders/shadow.wgsl`.
pub fn light_blocked<R: Real>(
    flat: &FlatScene<R>,
    (x, normal): (R::V4, R::V4),
    dir: R::V4,
    length: R,
    (cell, cull): (R::M4, bool),
) -> bool {
    let g = flat.faces.geometry;
    let offset = R::of(SHADOW_OFFSET);
    let origin = g.normalize_point::<R>(x + normal * offset);
    let ray = Ray {
        origin,
        dir: g.normalize_tangent::<R>(origin, dir),
    };
    let mut walk = Walker::new(ray, cell);
    let mut left = length - offset;
    for _ in 0..=SHADOW_LEVELS {
        if left <= R::of(0.0) {
            return false;
        }
        let (face, t_end) = walk.segment_end(&flat.faces);
        let seg = g.chart_to_distance::<R>(t_end);
        let last = left <= seg;
        let t_stop = if last { g.distance_to_chart::<R>(left) } else { t_end };
        let near = if cull {
            near_faces(
                &flat.faces.planes,
                flat.faces.near_scale,
                flat.near_reach,
                &walk.ray,
                t_stop,
            )
        } else {
            ALL_FACES
        };
        let cell_point = walk.cell * R::v4_of(glam::DVec4::W);
        if segment_blocked(flat, &walk.ray, t_stop, cell_point, (near, cull)) {
            return true;
        }
        if last {
            return false;
        }
        let end = advance(g, &walk.ray, t_end);
        walk.step(&flat.faces, face, end, true);
        left = left - seg;
    }
    false
}

/// True when the segment of `ray` up to `t_end` meets an object that
/// casts shadows. WGSL twin: `segment_blocked` in `shaders/shadow.wgsl`.
fn segment_blocked<R: Real>(
    flat: &FlatScene<R>,
    ray: &Ray<R>,
    t_end: R,
    cell_point: R::V4,
    (near, cull): (u32, bool),
) -> bool {
    let g = flat.faces.geometry;
    let zero = R::of(0.0);
    let mut blocked = false;
    each_candidate(flat, ray, t_end, ([near; 2], cull), 0.0, |c| {
        if blocked {
            return;
        }
        blocked = match c {
            Candidate::Ball(i) => {
                let b = &flat.balls[i];
                b.glow <= 0.0
                    && may_hit(b.face_mask, near)
                    && hit_ball(g, ray, b.center, b.k, zero).is_some_and(|t| t <= t_end)
            }
            Candidate::Tube(i) => {
                let tube = &flat.tubes[i];
                may_hit(tube.face_mask, near)
                    && hit_tube(g, ray, &tube.segment, flat.tube_k, zero).is_some_and(|t| t <= t_end)
            }
            Candidate::Instance(i) => {
                let inst = &flat.instances[i];
                instance_shown(inst, near, cell_point)
                    && hit_instance(g, flat, ray, inst, t_end).is_some_and(|h| h.t <= t_end)
            }
        };
    });
    blocked
}
