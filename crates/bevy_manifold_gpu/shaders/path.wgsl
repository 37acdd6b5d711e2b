// The path tracer (PATH_TRACE): one sample of the rendering equation per
// pixel. Each leg of the path walks through the faces like a camera ray
// (next_hit); at the surface it meets it adds the emission and the light
// of every light image (shade.wgsl's direct), then goes on in a direction
// drawn from the surface's lobes (bounce), weighted by the BRDF over the
// mixture's density; Russian roulette ends long paths; fog absorbs and
// glows. The random numbers hash the seed, the sample and the pixel.
//
// Rust twin: crates/bevy_manifold_core/src/trace/path.rs (the same
// names).
//
// Shader defs read: FOG; the rest through the imports. Cell rules are off
// under PATH_TRACE (TraceDefs::for_path).
#define_import_path bevy_manifold::path

#import bevy_manifold::bindings::{params, cached, cache_params, Pixel, FLAG_NO_EARLY_STOP}
#import bevy_manifold::geometry::{form, normalize_point, normalize_tangent, project_tangent, chart_to_distance, PI}
#import bevy_manifold::step::{Ray, near_faces}
#import bevy_manifold::cells::cell_id
#import bevy_manifold::walk::{Walker, walker_new, max_passes, segment_end, walk_segment}
#import bevy_manifold::nearest::{Hit, hit_id}
#import bevy_manifold::trace::{nearest_object, FOG_CUT}
#import bevy_manifold::shade::{Lit, surface, direct, brdf, MIRROR_OFFSET, MIN_ROUGHNESS}
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
// false past the levels, the distance or the fog. Rust twin: next_hit.
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
    var first = 0u;
    var second = 1u;
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
    first = order[0];
    second = order[1];
    var e1 = vec4<f32>(0.0);
    e1[first] = 1.0;
    var e2 = vec4<f32>(0.0);
    e2[second] = 1.0;
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

// A direction drawn from the lobes (`dir`) and the path's weight along it
// (`weight`); `ok` false below the surface. Rust twin: Lobes::bounce.
struct Bounce {
    dir: vec4<f32>,
    weight: vec3<f32>,
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
    let nl = form(lit.normal, l);
    if nl <= 0.0 {
        return Bounce(l, vec3<f32>(0.0), false);
    }
    if lit.metallic < 0.0 {
        return Bounce(l, lit.albedo, true);
    }
    let half = l + lit.view;
    let hl = sqrt(form(half, half));
    var nh = 0.0;
    var vh = 0.0;
    if hl > 1.0e-12 {
        nh = form(lit.normal, half) / hl;
        vh = form(lit.view, half) / hl;
    }
    let pdf = lobe_pdf(lit.metallic, lit.roughness, nl, nh, vh);
    if pdf <= 0.0 {
        return Bounce(l, vec3<f32>(0.0), false);
    }
    let f = brdf_of(lit, nl, nh, vh);
    return Bounce(l, f * nl / (PI * pdf), true);
}

// The material's brdf (shade.wgsl's brdf) at these cosines.
fn brdf_of(lit: Lit, nl: f32, nh: f32, vh: f32) -> vec3<f32> {
    return brdf(lit.albedo, lit.metallic, lit.roughness, nl, form(lit.normal, lit.view), nh, vh);
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
    var throughput = vec3<f32>(1.0);
    var radiance = vec3<f32>(0.0);
    var first = Pixel(vec4<f32>(0.0), 0u, 0u, 0u, 0x40000000u);
    var has_first = false;
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
        let lit = Lit(s.normal, s.view, s.albedo, s.pbr.x, s.pbr.y);
        let light = direct(s.x, lit, walk.cell);
        radiance += throughput * (s.emissive + s.albedo * s.glow + light);
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
        let origin = normalize_point(s.x + s.normal * MIRROR_OFFSET);
        let cell = walk.cell;
        let index = walk.index;
        walk = walker_new(Ray(origin, normalize_tangent(origin, next.dir)), cell, index);
        walk.travelled = dist;
    }
    if !has_first {
        first = Pixel(vec4<f32>(0.0, 0.0, 0.0, walk.travelled), 0u, walk.levels, 0u, 0x40000000u);
    }
    first.color = vec4<f32>(radiance, first.color.w);
    return first;
}
