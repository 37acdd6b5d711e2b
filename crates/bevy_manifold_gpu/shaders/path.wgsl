// The path tracer (PATH_TRACE): one sample of the rendering equation per
// pixel. Each leg of the path walks through the faces like a camera ray
// (next_hit); at the surface it meets it adds the emission and the light
// of every light image (shade.wgsl's direct), and the light of the
// glowing balls twice, weighed by the power heuristic: along a direction
// aimed at one of them (aim_at_emitter) and along the lobes' own next
// direction (multiple importance sampling); then it goes on in a
// direction drawn from the surface's lobes (bounce), weighted by the BRDF
// over the mixture's density; Russian roulette ends long paths; fog
// absorbs and glows. The random numbers hash the seed, the sample and the
// pixel.
//
// Rust twin: crates/bevy_manifold_core/src/trace/path.rs (the same
// names).
//
// Shader defs read: FOG; the rest through the imports. Cell rules are off
// under PATH_TRACE (TraceDefs::for_path).
#define_import_path bevy_manifold::path

#import bevy_manifold::bindings::{params, cached, cache_params, Pixel, FLAG_NO_EARLY_STOP}
#import bevy_manifold::geometry::{form, normalize_point, normalize_tangent, project_tangent, chart_to_distance, distance, sphere_area, PI}
#import bevy_manifold::step::{Ray, near_faces}
#import bevy_manifold::cells::cell_id
#import bevy_manifold::walk::{Walker, walker_new, max_passes, segment_end, walk_segment}
#import bevy_manifold::nearest::{Hit, hit_id}
#import bevy_manifold::trace::{nearest_object, FOG_CUT}
#import bevy_manifold::shade::{Lit, HitSurface, Cosines, cosines, surface, direct, brdf, MIRROR_OFFSET, MIN_ROUGHNESS}
#ifdef BALLS
#import bevy_manifold::bindings::balls
#endif
#ifdef BALL_TREE
#import bevy_manifold::ball_tree::cache_leaves
#endif

// Most bounces of a path. Rust twin: MAX_PATH_DEPTH.
const MAX_PATH_DEPTH: u32 = 64u;
// Bounces after which Russian roulette may end a path. Rust twin:
// ROULETTE_AFTER.
const ROULETTE_AFTER: u32 = 3u;

// The PCG hash (Jarzynski and Olano 2020). Rust twin: pcg.
fn pcg(v: u32) -> u32 {
    let state = v * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// The path's random state. Rust twin: PathRng.
var<private> rng: u32;

// Rust twin: PathRng::new.
fn rng_new(seed: u32, sample: u32, pixel: u32) {
    rng = pcg(pixel ^ pcg(sample ^ pcg(seed)));
}

// The next number in [0, 1). Rust twin: PathRng::uniform.
fn rng_uniform() -> f32 {
    rng = pcg(rng);
    return f32(rng >> 8u) * (1.0 / 16777216.0);
}

// The walk to the first object it meets (true), the hit left in `found`;
// false past the levels, the distance or the fog. The walker's table
// index follows the crossings itself (Rust's on_cross). Rust twin:
// next_hit.
var<private> found: Hit;

fn next_hit(walk: ptr<function, Walker>) -> bool {
    let passes = max_passes();
    for (var pass_index = 0u; pass_index < passes; pass_index++) {
#ifdef FOG
        let early_stop = (cached.flags & FLAG_NO_EARLY_STOP) == 0u;
        if early_stop && cached.fog_density * (*walk).travelled > FOG_CUT {
            return false;
        }
#endif
        let seg = segment_end(*walk);
        found = nearest_object((*walk).ray, seg.t, (*walk).cell[3], near_faces((*walk).ray, seg.t, cached.near_reach));
        if found.kind != 0u {
            return true;
        }
        let step = walk_segment(walk, seg);
        if step.stop {
            return false;
        }
    }
    return false;
}

// Two unit tangents at x orthogonal to n and to each other. Rust twin:
// tangent_frame.
fn tangent_frame(x: vec4<f32>, n: vec4<f32>) -> array<vec4<f32>, 2> {
    let along = abs(n.xyz);
    // The two chart axes least along the normal, in order.
    var order = array<u32, 3>(0u, 1u, 2u);
    for (var i = 0u; i < 3u; i++) {
        for (var j = 0u; j + 1u < 3u - i; j++) {
            if along[order[j + 1u]] < along[order[j]] {
                let t = order[j];
                order[j] = order[j + 1u];
                order[j + 1u] = t;
            }
        }
    }
    var e1 = vec4<f32>(0.0);
    e1[order[0]] = 1.0;
    var e2 = vec4<f32>(0.0);
    e2[order[1]] = 1.0;
    var t1 = project_tangent(x, e1);
    t1 -= n * form(t1, n);
    t1 /= sqrt(abs(form(t1, t1)));
    var t2 = project_tangent(x, e2);
    t2 -= n * form(t2, n);
    t2 -= t1 * form(t2, t1);
    t2 /= sqrt(abs(form(t2, t2)));
    return array<vec4<f32>, 2>(t1, t2);
}

// The share of paths sent along the GGX lobe. Rust twin: specular_share.
fn specular_share(metallic: f32) -> f32 {
    if metallic < 0.0 {
        return 0.0;
    }
    return 0.2 + 0.8 * metallic;
}

fn alpha2(roughness: f32) -> f32 {
    let r = max(roughness, MIN_ROUGHNESS);
    return (r * r) * (r * r);
}

// The lobe mixture's density. Rust twin: lobe_pdf.
fn lobe_pdf(metallic: f32, roughness: f32, nl: f32, nh_in: f32, vh: f32) -> f32 {
    let s = specular_share(metallic);
    let diffuse = (1.0 - s) * max(nl, 0.0) / PI;
    if metallic < 0.0 {
        return diffuse;
    }
    let a2 = alpha2(roughness);
    let nh = clamp(nh_in, 0.0, 1.0);
    let k = nh * nh * (a2 - 1.0) + 1.0;
    let d = a2 / (PI * k * k);
    return diffuse + s * d * nh / (4.0 * max(vh, 1.0e-6));
}

// A direction drawn from the lobes (`dir`), the path's weight along it
// (`weight`) and the mixture's density there (`pdf`); `ok` false below
// the surface. Rust twin: Bounce and Lobes::bounce.
struct Bounce {
    dir: vec4<f32>,
    weight: vec3<f32>,
    pdf: f32,
    ok: bool,
}

fn bounce(x: vec4<f32>, lit: Lit, u: vec3<f32>) -> Bounce {
    let frame = tangent_frame(x, lit.normal);
    let phi = 2.0 * PI * u.z;
    var cos_t = sqrt(u.y);
    let specular = u.x < specular_share(lit.metallic);
    if specular {
        let a2 = alpha2(select(1.0, lit.roughness, lit.metallic >= 0.0));
        cos_t = sqrt(max((1.0 - u.y) / (1.0 + (a2 - 1.0) * u.y), 0.0));
    }
    let sin_t = sqrt(max(1.0 - cos_t * cos_t, 0.0));
    let m = frame[0] * (sin_t * cos(phi)) + frame[1] * (sin_t * sin(phi)) + lit.normal * cos_t;
    var l = m;
    if specular {
        let vh = form(lit.view, m);
        l = m * (vh + vh) - lit.view;
    }
    if form(lit.normal, l) <= 0.0 {
        return Bounce(l, vec3<f32>(0.0), 0.0, false);
    }
    let c = cosines(lit.normal, lit.view, l);
    let pdf = lobe_pdf(lit.metallic, lit.roughness, c.nl, c.nh, c.vh);
    if pdf <= 0.0 {
        return Bounce(l, vec3<f32>(0.0), 0.0, false);
    }
    return Bounce(l, lobe_weight(lit, c, pdf), pdf, true);
}

// The path's weight along a direction of cosines c drawn with density
// pdf: brdf cos / (pi pdf), Lambert's albedo cos / (pi pdf) without a
// material. Rust twin: Lobes::weight.
fn lobe_weight(lit: Lit, c: Cosines, pdf: f32) -> vec3<f32> {
    if lit.metallic < 0.0 {
        return lit.albedo * c.nl / (PI * pdf);
    }
    let f = brdf(lit.albedo, lit.metallic, lit.roughness, c.nl, c.nv, c.nh, c.vh);
    return f * c.nl / (PI * pdf);
}

// The power heuristic (Veach 1997, beta 2). Rust twin: power_heuristic.
fn power_heuristic(a: f32, b: f32) -> f32 {
    let a2 = a * a;
    let b2 = b * b;
    if a2 + b2 > 0.0 {
        return a2 / (a2 + b2);
    }
    return 0.0;
}

// What a surface gives off: its emission and its glow.
fn emitted(s: HitSurface) -> vec3<f32> {
    return s.emissive + s.albedo * s.glow;
}

// The glowing balls (BALLS only; none without). Rust twin: is_emitter.
fn is_emitter(i: u32) -> bool {
#ifdef BALLS
    return balls[i].glow > 0.0 && any(balls[i].color > vec3<f32>(0.0));
#else
    return false;
#endif
}

fn emitter_count() -> u32 {
    var n = 0u;
#ifdef BALLS
    for (var i = 0u; i < params.ball_count; i++) {
        if is_emitter(i) {
            n += 1u;
        }
    }
#endif
    return n;
}

// The cone of directions at x meeting ball i: the unit tangent towards
// its centre (xyzw of `dir`) and the cosine of the half-angle, sin a =
// sin_k(r) / sin_k(s); `ok` false inside the ball. Rust twin:
// emitter_cone.
struct EmitterCone {
    dir: vec4<f32>,
    cos_a: f32,
    ok: bool,
}

fn emitter_cone(i: u32, x: vec4<f32>) -> EmitterCone {
    var out = EmitterCone(vec4<f32>(0.0), 1.0, false);
#ifdef BALLS
    let b = balls[i];
    let s = distance(x, b.center);
    // sin_k(r)^2 from the ball's k: r^2, cos r or cosh r.
#ifdef GEOMETRY_HYPERBOLIC
    let sin_r2 = b.k * b.k - 1.0;
#else ifdef GEOMETRY_SPHERICAL
    let sin_r2 = 1.0 - b.k * b.k;
#else
    let sin_r2 = b.k;
#endif
    let sin_a2 = sin_r2 * (4.0 * PI) / sphere_area(s);
    if !(sin_a2 < 1.0) {
        return out;
    }
    let t = project_tangent(x, b.center);
    let len2 = abs(form(t, t));
    if !(len2 > 1.0e-12) {
        return out;
    }
    out = EmitterCone(t / sqrt(len2), sqrt(1.0 - sin_a2), true);
#endif
    return out;
}

// The density with which aim_at_emitter draws the unit tangent l at x:
// the mean over the `count` emitters of their cones' even densities, the
// cone of ball `drawn` counted whatever the rounding says. Rust twin:
// emitter_pdf.
fn emitter_pdf(x: vec4<f32>, l: vec4<f32>, count: u32, drawn: u32) -> f32 {
    var sum = 0.0;
#ifdef BALLS
    for (var i = 0u; i < params.ball_count; i++) {
        if !is_emitter(i) {
            continue;
        }
        let ec = emitter_cone(i, x);
        if !ec.ok {
            continue;
        }
        if i == drawn || form(l, ec.dir) >= ec.cos_a {
            sum += 1.0 / (2.0 * PI * max(1.0 - ec.cos_a, 1.0e-7));
        }
    }
#endif
    return sum / f32(max(count, 1u));
}

// A direction at x towards one of the `count` emitters drawn with u (the
// emitter floor(u.x count), then its cone evenly in solid angle) and the
// density of drawing it; pdf 0 when x is inside that emitter. Rust twin:
// aim_at_emitter (None there for pdf 0).
struct Aimed {
    dir: vec4<f32>,
    pdf: f32,
}

fn aim_at_emitter(x: vec4<f32>, count: u32, u: vec3<f32>) -> Aimed {
    let k = min(u32(u.x * f32(count)), count - 1u);
    var seen = 0u;
    var drawn = 0u;
#ifdef BALLS
    for (var i = 0u; i < params.ball_count; i++) {
        if is_emitter(i) {
            if seen == k {
                drawn = i;
            }
            seen += 1u;
        }
    }
#endif
    let ec = emitter_cone(drawn, x);
    if !ec.ok {
        return Aimed(vec4<f32>(0.0), 0.0);
    }
    let cos_t = 1.0 - u.y * (1.0 - ec.cos_a);
    let sin_t = sqrt(max(1.0 - cos_t * cos_t, 0.0));
    let phi = 2.0 * PI * u.z;
    let frame = tangent_frame(x, ec.dir);
    let l = normalize_tangent(x, ec.dir * cos_t + frame[0] * (sin_t * cos(phi)) + frame[1] * (sin_t * sin(phi)));
    return Aimed(l, emitter_pdf(x, l, count, drawn));
}

// The walk of a leg leaving x (normal n) along the unit tangent dir from
// the copy of `walk`, having travelled `travelled`. Rust twin: leave.
fn leave(x: vec4<f32>, n: vec4<f32>, dir: vec4<f32>, walk: Walker, travelled: f32) -> Walker {
    let origin = normalize_point(x + n * MIRROR_OFFSET);
    var next = walker_new(Ray(origin, normalize_tangent(origin, dir)), walk.cell, walk.index);
    next.travelled = travelled;
    return next;
}

// One sample of the rendering equation for the pixel of `ray` (`pixel`
// its row-major index): the estimate, and the first leg's ids. Rust twin:
// path_sample.
fn path_sample(ray: Ray, pixel: u32) -> Pixel {
    cache_params();
#ifdef BALL_TREE
    cache_leaves();
#endif
    rng_new(params.seed, params.sample, pixel);
    var walk = walker_new(ray, params.camera_cell, params.camera_cell_index);
    var density = 0.0;
    var fog = vec3<f32>(0.0);
#ifdef FOG
    density = cached.fog_density;
    fog = params.fog_color.xyz;
#endif
    let emitters = emitter_count();
    var throughput = vec3<f32>(1.0);
    var radiance = vec3<f32>(0.0);
    var first = Pixel(vec4<f32>(0.0), 0u, 0u, 0u, 0x40000000u);
    var has_first = false;
    // Where the path left the last surface (Rust's Left): the point, the
    // direction and the lobes' density; pdf 0 before the first bounce.
    var left_x = vec4<f32>(0.0);
    var left_dir = vec4<f32>(0.0);
    var left_pdf = 0.0;
    let depth = min(params.path_depth, MAX_PATH_DEPTH);
    for (var b = 0u; b <= depth; b++) {
        let start = walk.travelled;
        if !next_hit(&walk) {
            radiance += throughput * fog;
            break;
        }
        let dist = walk.travelled + chart_to_distance(found.t);
        if !has_first {
            let cid = cell_id(walk.cell, walk.index);
            first = Pixel(vec4<f32>(0.0, 0.0, 0.0, dist), hit_id(found), walk.levels, cid.x, cid.y);
            has_first = true;
        }
        let kept = exp(-(density * (dist - start)));
        radiance += throughput * fog * (1.0 - kept);
        throughput *= kept;
        let s = surface(walk.ray, found, vec4<f32>(0.0));
        var mis = 1.0;
        if left_pdf > 0.0 && emitters > 0u {
            mis = power_heuristic(left_pdf, emitter_pdf(left_x, left_dir, emitters, 0xffffffffu));
        }
        let lit = Lit(s.normal, s.view, s.albedo, s.pbr.x, s.pbr.y);
        let light = direct(s.x, lit, walk.cell);
        radiance += throughput * (emitted(s) * mis + light);
        // Next-event estimation towards the glowing balls.
        let u_aim = vec3<f32>(rng_uniform(), rng_uniform(), rng_uniform());
        if emitters > 0u {
            let aimed = aim_at_emitter(s.x, emitters, u_aim);
            let c = cosines(s.normal, s.view, aimed.dir);
            if aimed.pdf > 0.0 && c.nl > 0.0 {
                let w = lobe_weight(lit, c, aimed.pdf);
                let weight = power_heuristic(aimed.pdf, lobe_pdf(lit.metallic, lit.roughness, c.nl, c.nh, c.vh));
                var aim = leave(s.x, s.normal, aimed.dir, walk, dist);
                if next_hit(&aim) {
                    let there = surface(aim.ray, found, vec4<f32>(0.0));
                    let far = aim.travelled + chart_to_distance(found.t);
                    let through = exp(-(density * (far - dist)));
                    radiance += throughput * w * (weight * through) * emitted(there);
                }
            }
        }
        let u = vec3<f32>(rng_uniform(), rng_uniform(), rng_uniform());
        let next = bounce(s.x, lit, u);
        if !next.ok {
            break;
        }
        throughput *= next.weight;
        if b >= ROULETTE_AFTER {
            let keep = min(max(throughput.x, max(throughput.y, throughput.z)), 0.95);
            if rng_uniform() >= keep {
                break;
            }
            throughput /= keep;
        }
        if all(throughput <= vec3<f32>(0.0)) {
            break;
        }
        left_x = s.x;
        left_dir = next.dir;
        left_pdf = next.pdf;
        walk = leave(s.x, s.normal, next.dir, walk, dist);
    }
    if !has_first {
        first = Pixel(vec4<f32>(0.0, 0.0, 0.0, walk.travelled), 0u, walk.levels, 0u, 0x40000000u);
    }
    first.color = vec4<f32>(radiance, first.color.w);
    return first;
}
