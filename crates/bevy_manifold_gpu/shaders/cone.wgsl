// Cone tracing in the walk (FOOTPRINT): what a pixel's cone does on each
// segment, on top of the footprint's geometry (footprint.wgsl). Each
// segment grows the objects by its widest footprint (`cone_grow`) and
// tests balls near the faces it comes near grown (`near_balls`); each
// ball or tube the cone passes within its grown radius of covers a part
// of the pixel (Cover, cover), a layer shaded where the ray passes it
// (ConeLayer, cone_layer); trace_ray adds the layers front to back
// (`cone_layers`, `cone_front`).
//
// Rust twin: crates/bevy_manifold_core/src/trace/cone.rs (the same
// names).
//
// Shader defs read: FOOTPRINT (the whole module), BALLS, TUBES.
#define_import_path bevy_manifold::cone

#ifdef FOOTPRINT
#import bevy_manifold::bindings::{params, cached, Pixel}
#import bevy_manifold::geometry::{normalize_point, normalize_tangent, distance, chart_to_distance}
#import bevy_manifold::step::{Ray, normal_from}
#import bevy_manifold::footprint::{Approach, Inflation, Layers, within, gap_of, coverage, side_by_side, radius_of, spread, ball_approach, tube_approach, grow_k, shading_offset, normal_at_offset}
#ifdef BALLS
#import bevy_manifold::bindings::balls
#import bevy_manifold::step::hit_ball
#endif
#ifdef TUBES
#import bevy_manifold::bindings::tubes
#import bevy_manifold::step::{hit_tube, foot_on_line}
#endif

// The cone's layers so far (Rust twin: trace_ray's `layers`), and the
// first covering half the pixel or more (`front`), which names its object.
var<private> cone_layers: Layers;
var<private> cone_front: Pixel;
var<private> cone_has_front: bool;

// What a ball or tube met by a pixel's cone covers (Rust twin: Cover): where
// the ray passes nearest it, the footprint there, its radius and the part
// of the pixel it covers (0: none).
struct Cover {
    near: Approach,
    gap: f32,
    w: f32,
    r: f32,
    part: f32,
}

// The segment's growth and the distance travelled to its start (Rust
// twin: SegmentReach::grow, and the distance segment_layers takes).
var<private> cone_grow: Inflation;
var<private> cone_travelled: f32;
// The faces the segment comes near for grown balls (Rust twin:
// SegmentReach::near[0]); the walk's `near` serves tubes and meshes.
var<private> near_balls: u32;

// What the ball (kind 1) or tube (kind 2) `index` covers when the ray's
// approach `near` to it lies in [0, end] within the grown radius (`k`
// grown to `grown`); part 0 otherwise. Rust twin: `cover`.
fn cover(kind: u32, index: u32, near: Approach, end: f32, grown: f32, k: f32) -> Cover {
    var c = Cover(near, 0.0, 0.0, 0.0, 0.0);
    if !(near.t >= 0.0 && near.t <= end && within(near, grown)) {
        return c;
    }
    // Never wider than the segment's growth (the cap).
    c.w = min(params.cone.x * spread(cone_travelled + chart_to_distance(near.t)), cone_grow.w);
    c.r = radius_of(k);
    let ball = kind == 1u;
    var length = 0.0;
#ifdef TUBES
    if !ball {
        length = distance(tubes[index].a, tubes[index].b);
    }
#endif
    c.gap = gap_of(near.lambda);
    c.part = min(coverage(ball, c.gap, c.r, length, c.w) * side_by_side(c.w, params.cone.w), 1.0);
    return c;
}

// The cover of a kept layer (its id from met_id), worked out again as
// consider_ball and consider_tube did.
fn kept_cover(ray: Ray, kind: u32, index: u32, t_end: f32) -> Cover {
#ifdef BALLS
    if kind == 1u {
        return cover(1u, index, ball_approach(ray, balls[index].center), t_end, grow_k(balls[index].k, cone_grow.ball), balls[index].k);
    }
#endif
#ifdef TUBES
    if kind == 2u {
        return cover(2u, index, tube_approach(ray, tubes[index].a, tubes[index].e), t_end, grow_k(cached.tube_k, cone_grow.tube), cached.tube_k);
    }
#endif
    return Cover(Approach(0.0, 0.0), 0.0, 0.0, 0.0, 0.0);
}

// Where a layer is shaded (Rust twin: ConeLayer): the part of the pixel, the
// chart parameter, and the normal there (zero: the object's own).
struct ConeLayer {
    part: f32,
    t: f32,
    normal: vec4<f32>,
}

// Rust twin: cone_layer. At the ray's own hit when shading_offset puts
// the shading there, else where the ray passes nearest, with the normal
// of that offset.
fn cone_layer(ray: Ray, kind: u32, index: u32, c: Cover, t_end: f32) -> ConeLayer {
    let ball = kind == 1u;
    var own = -1.0;
    var n0 = vec4<f32>(0.0);
    let x = normalize_point(ray.origin + ray.dir * c.near.t);
    let view = -normalize_tangent(x, ray.dir);
#ifdef BALLS
    if ball {
        own = hit_ball(ray, balls[index].center, balls[index].k, 0.0);
        n0 = normal_from(x, balls[index].center);
    }
#endif
#ifdef TUBES
    if kind == 2u {
        own = hit_tube(ray, tubes[index], cached.tube_k, 0.0);
        n0 = normal_from(x, foot_on_line(x, tubes[index]));
    }
#endif
    let s = shading_offset(ball, c.gap, c.r, c.w);
    if own >= 0.0 && own <= t_end && c.gap <= s * c.r {
        return ConeLayer(c.part, own, vec4<f32>(0.0));
    }
    return ConeLayer(c.part, c.near.t, normal_at_offset(n0, view, s));
}
#endif
