// Algorithm 1 for one ray (trace_ray): on each segment of its walk
// through the faces (walk.wgsl), the objects the segment may meet
// (cull.wgsl's each_candidate), the nearest of them for a ray or a cone's
// layers (nearest.wgsl, cone.wgsl), shaded (shade.wgsl) and added front
// to back; else on through the exit face.
//
// Rust twin: crates/bevy_manifold_core/src/trace/trace.rs (trace_ray,
// nearest_object, segment_layers).
//
// Shader defs read: FOG (early stop, fog colour), CELL_RULES (hidden
// cells, walls), FOOTPRINT (cone tracing), BALL_TREE (the leaves cached
// once a ray), REFLECTIONS (the legs of a path off mirrors, trace_ray's
// loop); the rest through the imports.
//
// Written for lavapipe too, which runs the body of every branch under a
// mask whether or not any SIMD lane takes it (only loops end early, once
// all lanes are done): what a scene does not need is left out by a def,
// and the shading is done once, after the walk, not inside it.
#define_import_path bevy_manifold::trace

#import bevy_manifold::bindings::{params, cached, cache_params, faces, Pixel, FLAG_NO_EARLY_STOP, WALL_OBJECT}
#import bevy_manifold::geometry::chart_to_distance
#import bevy_manifold::step::{Ray, near_faces}
#import bevy_manifold::cells::cell_id
#import bevy_manifold::walk::{Walker, walker_new, max_passes, segment_end, walk_segment}
#import bevy_manifold::cull::each_candidate
#import bevy_manifold::nearest::{Hit, best, hit_id}
#import bevy_manifold::shade::shade
#ifdef BALL_TREE
#import bevy_manifold::ball_tree::cache_leaves
#endif
#ifdef REFLECTIONS
#import bevy_manifold::shade::{Mirror, last_mirror}
#endif
#ifdef CELL_RULES
#import bevy_manifold::rule::cell_visible
#import bevy_manifold::shade::{shade_wall, unknown_rules}
#endif
#ifdef FOOTPRINT
#import bevy_manifold::nearest::{met_t, met_id, met_count}
#import bevy_manifold::cone::{cone_layers, cone_front, cone_has_front, cone_grow, cone_travelled, near_balls, cone_layer, kept_cover}
#import bevy_manifold::footprint::{Layers, inflation_new, grown_reach, widest_spread, add_layer, layers_full, layers_over, BALL_GROWTH}
#endif

// ln 255 (the f32 nearest it): once fog_density * distance passes it, fog
// has left less than 1/255 of an object's light and the ray may stop.
// Rust twin: FOG_CUT.
const FOG_CUT: f32 = 5.5412636;

// What a ray that meets nothing shows: the fog's colour, else black
// (Rust: trace_ray's `background`).
fn background() -> vec3<f32> {
#ifdef FOG
    return params.fog_color.xyz;
#else
    return vec3<f32>(0.0);
#endif
}

// The pixel that ends the walk, `behind` seen through the cone's layers
// (Rust twin: trace_ray's `finish`); `behind` itself for a ray.
fn finish(behind: Pixel) -> Pixel {
#ifdef FOOTPRINT
    var p = behind;
    if cone_has_front {
        p = cone_front;
    }
    p.color = vec4<f32>(layers_over(cone_layers, behind.color.xyz), p.color.w);
    return p;
#else
    return behind;
#endif
}

// The nearest object on the segment of `ray` ending at t_end, seen from
// the cell of `cell_point`, of those each_candidate hands out near the
// faces `near`. Rust twin: nearest_object.
fn nearest_object(ray: Ray, t_end: f32, cell_point: vec4<f32>, near: u32) -> Hit {
    best = Hit(-1.0, 0u, 0u, 0u, 0.0, 0.0);
    each_candidate(ray, t_end, cell_point, near);
    return best;
}

#ifdef FOOTPRINT
// The layers of the pixel's cone on the segment (in met_t and met_id,
// nearest first) and the first mesh hit, whole (in best). Rust twin:
// segment_layers.
fn segment_layers(ray: Ray, t_end: f32, cell_point: vec4<f32>, near: u32) {
    best = Hit(-1.0, 0u, 0u, 0u, 0.0, 0.0);
    each_candidate(ray, t_end, cell_point, near);
}
#endif

// The most reflections a ray follows. Rust twin: MAX_REFLECTIONS.
const MAX_REFLECTIONS: u32 = 8u;

#ifdef REFLECTIONS
// Where a leg of a path ended on a surface that reflects: its mirror (the
// weight times the share of the pixel the surface took), the cell, the
// distance travelled to it. Rust twin: Reflection in trace.rs.
struct Reflection {
    mirror: Mirror,
    cell: mat4x4<f32>,
    index: u32,
    travelled: f32,
}

var<private> reflection: Reflection;

// Keeps what the last shade() reflects as the leg's reflection, seen in
// `share` of the pixel, at distance `dist` in the walk's cell.
fn keep_reflection(walk: Walker, dist: f32, share: f32) {
    reflection = Reflection(last_mirror, walk.cell, walk.index, dist);
    reflection.mirror.weight *= share;
}
#endif

// Algorithm 1 for one ray (Rust twin: trace_ray and trace_path): the
// camera's leg, then under REFLECTIONS up to params.reflections legs off the
// mirrors met, each from the mirror's cell with a fresh budget of levels,
// their colours added in front of the fog.
fn trace_ray(ray: Ray) -> Pixel {
    cache_params();
#ifdef BALL_TREE
    cache_leaves();
#endif
    var walk = walker_new(ray, params.camera_cell, params.camera_cell_index);
#ifdef REFLECTIONS
    // One call of trace_leg for every leg (each call site is a copy of
    // the walk in the compiled shader): the first leg's pixel, then each
    // reflected leg's colour added in front of the fog.
    var pixel: Pixel;
    var weight = vec3<f32>(1.0);
    var kept = 1.0;
    let legs = min(params.reflections, MAX_REFLECTIONS) + 1u;
    for (var leg = 0u; leg < legs; leg++) {
        let seen = trace_leg(walk);
        if leg == 0u {
            pixel = seen;
        } else {
            pixel.color = vec4<f32>(pixel.color.xyz + weight * (seen.color.xyz - background() * (1.0 - kept)), pixel.color.w);
        }
        if !reflection.mirror.on {
            break;
        }
        weight *= reflection.mirror.weight;
        kept = reflection.mirror.fog_kept;
        walk = walker_new(reflection.mirror.ray, reflection.cell, reflection.index);
        walk.travelled = reflection.travelled;
    }
    return pixel;
#else
    return trace_leg(walk);
#endif
}

// One leg of a path (Rust twin: trace_leg): on each segment the nearest
// object, else walk on through the exit face. Under FOOTPRINT each
// segment's layers, front to back. Under REFLECTIONS it leaves in
// `reflection` the mirror of the surface it ends on (`on` false if none).
fn trace_leg(start: Walker) -> Pixel {
    var walk = start;
#ifdef REFLECTIONS
    reflection.mirror.on = false;
#endif
#ifdef FOOTPRINT
    cone_layers = Layers(vec3<f32>(0.0), 1.0, 0u);
    cone_has_front = false;
#endif
    let passes = max_passes();
#ifndef FOOTPRINT
    var hit = Hit(-1.0, 0u, 0u, 0u, 0.0, 0.0);
#endif
    for (var pass_index = 0u; pass_index < passes; pass_index++) {
#ifdef FOG
        let early_stop = (cached.flags & FLAG_NO_EARLY_STOP) == 0u;
        if early_stop && cached.fog_density * walk.travelled > FOG_CUT {
            break;
        }
#endif
        let seg = segment_end(walk);
        var shown = true;
#ifdef CELL_RULES
        // Objects in an off cell are not there (Rust: CellRule::visible).
        shown = cell_visible(cell_id(walk.cell, walk.index));
#endif
#ifdef FOOTPRINT
        // Objects grow by the segment's widest footprint, at most the cap.
        let w = min(params.cone.x * widest_spread(walk.travelled, walk.travelled + chart_to_distance(seg.t)), params.footprint_cap);
        cone_grow = inflation_new(w);
        cone_travelled = walk.travelled;
        met_count = 0u;
        if shown {
            // The faces the segment comes near for balls (grown
            // BALL_GROWTH footprints) and for tubes and meshes (one).
            near_balls = near_faces(walk.ray, seg.t, params.cone.z * grown_reach(params.cone.y, w * BALL_GROWTH));
            segment_layers(walk.ray, seg.t, walk.cell[3], near_faces(walk.ray, seg.t, params.cone.z * grown_reach(params.cone.y, w)));
        }
        // The layers in order, then the mesh hit, whole (Rust twin:
        // Nearest::iter).
        for (var k = 0u; k < met_count; k++) {
            if best.kind != 0u && best.t < met_t[k] {
                break;
            }
            let kind = met_id[k] >> 30u;
            let index = met_id[k] & 0x3fffffffu;
            let layer = cone_layer(walk.ray, kind, index, kept_cover(walk.ray, kind, index, seg.t), seg.t);
            let hit = Hit(layer.t, kind, index, 0u, 0.0, 0.0);
            let dist = walk.travelled + chart_to_distance(layer.t);
            let cid = cell_id(walk.cell, walk.index);
            let color = shade(walk.ray, hit, layer.normal, dist, cid, walk.cell);
            let here = Pixel(vec4<f32>(color, dist), hit_id(hit), walk.levels, cid.x, cid.y);
            if layer.part >= 0.5 && !cone_has_front {
                cone_front = here;
                cone_has_front = true;
            }
#ifdef REFLECTIONS
            let share = cone_layers.left;
#endif
            if add_layer(&cone_layers, color, layer.part) {
#ifdef REFLECTIONS
                keep_reflection(walk, dist, share);
#endif
                return finish(here);
            }
            if layers_full(cone_layers) {
                return finish(Pixel(vec4<f32>(background(), walk.travelled), 0u, walk.levels, cid.x, cid.y));
            }
        }
        if best.kind != 0u {
            let dist = walk.travelled + chart_to_distance(best.t);
            let cid = cell_id(walk.cell, walk.index);
            let color = shade(walk.ray, best, vec4<f32>(0.0), dist, cid, walk.cell);
            let here = Pixel(vec4<f32>(color, dist), hit_id(best), walk.levels, cid.x, cid.y);
            if !cone_has_front {
                cone_front = here;
                cone_has_front = true;
            }
#ifdef REFLECTIONS
            keep_reflection(walk, dist, cone_layers.left);
#endif
            add_layer(&cone_layers, color, 1.0);
            return finish(here);
        }
#else
        if shown {
            hit = nearest_object(walk.ray, seg.t, walk.cell[3], near_faces(walk.ray, seg.t, cached.near_reach));
        }
        // Shaded after the loop (Rust shades and returns here): lavapipe
        // runs a branch's body, under a mask, whether or not any lane
        // takes it, so shading here cost every pass of every ray.
        if hit.kind != 0u {
            break;
        }
#endif
        let segment_start = walk.ray;
        let step = walk_segment(&walk, seg);
#ifdef CELL_RULES
        if step.wall == 1u {
            let cid = cell_id(walk.cell, walk.index);
            let color = shade_wall(faces[seg.face].plane, segment_start, walk.travelled);
#ifdef FOOTPRINT
            add_layer(&cone_layers, color, 1.0);
#endif
            return finish(Pixel(vec4<f32>(color, walk.travelled), WALL_OBJECT, walk.levels, cid.x, cid.y));
        }
        if step.wall == 2u {
            // Beyond the table the rules are unknown: CellTint::UNKNOWN's
            // grey, in fog, and the cell CellId::BEYOND_TABLE.
            return finish(Pixel(vec4<f32>(unknown_rules(walk.travelled), walk.travelled), 0u, walk.levels, 0u, 0x40000000u));
        }
#endif
        if step.stop {
            break;
        }
    }
#ifndef FOOTPRINT
    if hit.kind != 0u {
        let dist = walk.travelled + chart_to_distance(hit.t);
        let cid = cell_id(walk.cell, walk.index);
        let color = shade(walk.ray, hit, vec4<f32>(0.0), dist, cid, walk.cell);
#ifdef REFLECTIONS
        keep_reflection(walk, dist, 1.0);
#endif
        return Pixel(vec4<f32>(color, dist), hit_id(hit), walk.levels, cid.x, cid.y);
    }
#endif
    let cid = cell_id(walk.cell, walk.index);
    return finish(Pixel(vec4<f32>(background(), walk.travelled), 0u, walk.levels, cid.x, cid.y));
}
