// Shading a hit: Lambert plus a Blinn lobe, or with MATERIALS the
// material's GGX lobe (brdf), under each light image, each
// along its own geodesic (both arcs in S3) with the fall-off of the
// geometry (1 / area of the geodesic sphere), the light's range and the
// fog on its way (image_irradiance), and only if the way is free
// (shadow.wgsl's shadow_step); per-cell colour and fog (shade); the ray a
// surface with a material reflects (Mirror, mirror_ray, under
// REFLECTIONS); a wall between cells lit by a lamp at the eye
// (shade_wall); what lies past the table of exact ids under rules
// (unknown_rules).
//
// Rust twin: crates/bevy_manifold_core/src/trace/shade.rs (the same
// names; Rust has no unknown_rules: the CPU goes on exactly past the
// table).
//
// Shader defs read: BALLS, TUBES, MESHES (which objects are shaded),
// CELL_COLORS, LIGHTS, LIGHT_IMAGES (without it each light's copy in the
// domain, as before light images), SHADOWS, MATERIALS (metallic and
// roughness, emission, normal maps), REFLECTIONS, FOG, GEOMETRY_SPHERICAL.
#define_import_path bevy_manifold::shade

#import bevy_manifold::bindings::{params, cached}
#import bevy_manifold::geometry::{form, normalize_point, normalize_tangent, project_tangent, distance, sphere_area, PI}
#import bevy_manifold::step::{Ray, normal_from}
#import bevy_manifold::nearest::Hit
#ifdef BALLS
#import bevy_manifold::bindings::balls
#endif
#ifdef TUBES
#import bevy_manifold::bindings::tubes
#import bevy_manifold::step::foot_on_line
#endif
#ifdef MESHES
#import bevy_manifold::bindings::instances
#import bevy_manifold::bvh::MeshHit
#import bevy_manifold::mesh_hit::{mesh_normal, mesh_surface}
#import bevy_manifold::texture::hit_uv
#endif
#ifdef CELL_COLORS
#import bevy_manifold::cells::cell_color
#endif
#ifdef LIGHTS
#import bevy_manifold::bindings::{lights, Light}
#endif
#ifdef SHADOWS
#import bevy_manifold::shadow::{ShadowWalk, shadow_walk_new, shadow_step, SHADOW_ON, SHADOW_FREE, SHADOW_LEVELS}
#import bevy_manifold::nearest::{best, shadow_ray}
#ifdef FOOTPRINT
#import bevy_manifold::cone::near_balls
#endif
#endif
#ifdef SOFT_SHADOWS
#import bevy_manifold::shadow::aim_at_light
#endif

// How far off the surface a reflected ray starts (chart units along the
// normal). Rust twin: MIRROR_OFFSET.
const MIRROR_OFFSET: f32 = 1.0e-4;

// The ray a surface reflects, the share of its light the eye sees and the
// fog's transmittance to the hit; `on` false where the surface has no
// material. Rust twin: Mirror in shade.rs (an Option there).
struct Mirror {
    ray: Ray,
    weight: vec3<f32>,
    fog_kept: f32,
    on: bool,
}

// The roughest surface that reflects. Rust twin: MAX_MIRROR_ROUGHNESS.
const MAX_MIRROR_ROUGHNESS: f32 = 0.4;

// What the last shade() reflects (REFLECTIONS; Rust returns it).
var<private> last_mirror: Mirror;

// The reflected ray at x, normal `normal`, seen along `view` (towards the
// eye): from MIRROR_OFFSET off the surface along 2 (n.v) n - v.
// Rust twin: mirror_ray.
fn mirror_ray(x: vec4<f32>, normal: vec4<f32>, view: vec4<f32>) -> Ray {
    let nv = form(normal, view);
    let dir = normal * (nv + nv) - view;
    let origin = normalize_point(x + normal * MIRROR_OFFSET);
    return Ray(origin, normalize_tangent(origin, dir));
}

// A light nearer a hit than this (|tangent towards it|^2) is on the hit
// point, and lights it along the normal (toward_light).
// Rust twin: LIGHT_AT_HIT.
const LIGHT_AT_HIT: f32 = 1.0e-10;

// The unit tangent at x towards the light at l; the normal when the light
// is on x (or, in S3, at its antipode), where the direction is 0 / 0.
// Rust twin: toward_light.
fn toward_light(x: vec4<f32>, l: vec4<f32>, normal: vec4<f32>) -> vec4<f32> {
    let t = project_tangent(x, l);
    let len2 = abs(form(t, t));
    if len2 > LIGHT_AT_HIT {
        return t / sqrt(len2);
    }
    return normal;
}

// What a hit's light is worked out from (Rust twin: Lit in shade.rs):
// metallic negative for the classic look.
struct Lit {
    normal: vec4<f32>,
    view: vec4<f32>,
    albedo: vec3<f32>,
    metallic: f32,
    roughness: f32,
}

// The least perceptual roughness shaded. Rust twin: MIN_ROUGHNESS.
const MIN_ROUGHNESS: f32 = 0.089;
// A dielectric's reflectance at normal incidence. Rust twin: DIELECTRIC_F0.
const DIELECTRIC_F0: f32 = 0.04;

// Rust twin: brdf in crates/bevy_manifold_core/src/material.rs. Lambert
// albedo (1 - metallic) plus the GGX lobe pi D V F (Trowbridge-Reitz D,
// height-correlated Smith V, Schlick F from mix(0.04, albedo, metallic)),
// per unit irradiance from straight above.
fn brdf(albedo: vec3<f32>, metallic: f32, roughness: f32, nl_in: f32, nv_in: f32, nh_in: f32, vh: f32) -> vec3<f32> {
    let r = max(roughness, MIN_ROUGHNESS);
    let a2 = (r * r) * (r * r);
    let nl = max(nl_in, 0.0);
    let nv = max(nv_in, 1.0e-4);
    let nh = clamp(nh_in, 0.0, 1.0);
    let k = nh * nh * (a2 - 1.0) + 1.0;
    let d = a2 / (PI * k * k);
    let vis = 0.5 / (nl * sqrt(nv * nv * (1.0 - a2) + a2) + nv * sqrt(nl * nl * (1.0 - a2) + a2));
    let fresnel = pow(1.0 - clamp(vh, 0.0, 1.0), 5.0);
    let f0 = DIELECTRIC_F0 * (1.0 - metallic) + albedo * metallic;
    let f = f0 + (1.0 - f0) * fresnel;
    return albedo * (1.0 - metallic) + PI * d * vis * f;
}

// The share of the light along the mirror direction a PBR surface sends
// to the eye (Karis's fit of the split-sum GGX term: F0 A + B). Rust
// twin: reflectance in crates/bevy_manifold_core/src/material.rs.
fn reflectance(albedo: vec3<f32>, metallic: f32, roughness: f32, nv_in: f32) -> vec3<f32> {
    let r = clamp(roughness, 0.0, 1.0);
    let nv = clamp(nv_in, 0.0, 1.0);
    let r0 = 1.0 - r;
    let a004 = min(r0 * r0, exp2(-9.28 * nv)) * r0 + (0.0425 - 0.0275 * r);
    let a = -1.04 * a004 + (1.04 - 0.572 * r);
    let b = 1.04 * a004 + (0.022 * r - 0.04);
    let f0 = DIELECTRIC_F0 * (1.0 - metallic) + albedo * metallic;
    return clamp(f0 * a + b, vec3<f32>(0.0), vec3<f32>(1.0));
}

// Rust twin: pack_pbr in crates/bevy_manifold_gpu/src/layout.rs (this
// unpacks it): a ball's metallic and roughness, metallic -1 for the
// classic look.
fn ball_pbr(w: u32) -> vec2<f32> {
    if (w & 1u) == 0u {
        return vec2<f32>(-1.0, 0.0);
    }
    return vec2<f32>(f32((w >> 1u) & 0x7fffu) / 32767.0, f32(w >> 16u) / 65535.0);
}

// Adds to rgb the light of colour `color` arriving along the unit
// tangent to_light with irradiance `irradiance`: Lambert plus a Blinn
// lobe, or with a material (MATERIALS, metallic >= 0) brdf's GGX lobe.
// Rust twin: Lit::add in shade.rs.
fn add_light(rgb: ptr<function, vec3<f32>>, lit: Lit, to_light: vec4<f32>, irradiance: f32, color: vec3<f32>) {
    let c = cosines(lit.normal, lit.view, to_light);
    let lambert = max(c.nl, 0.0);
    let nh = max(c.nh, 0.0);
#ifdef MATERIALS
    if lit.metallic >= 0.0 {
        let f = brdf(lit.albedo, lit.metallic, lit.roughness, lambert, c.nv, nh, c.vh);
        *rgb += f * lambert * irradiance * color;
        return;
    }
#endif
    // nh is 0 where the half-vector vanishes: no highlight.
    let spec = pow(nh, 32.0) * 0.35;
    *rgb += (lit.albedo * lambert + spec) * irradiance * color;
}

// The cosines of the unit tangent l (towards a light, or a path's next
// direction) at a surface of unit normal `normal` seen along the unit
// tangent `view`: n.l, n.v, and the half-vector's n.h and v.h (0 where it
// vanishes). Unclamped. Rust twin: cosines (Cosines in material.rs).
struct Cosines {
    nl: f32,
    nv: f32,
    nh: f32,
    vh: f32,
}

fn cosines(normal: vec4<f32>, view: vec4<f32>, l: vec4<f32>) -> Cosines {
    let half = l + view;
    let hl = sqrt(form(half, half));
    var nh = 0.0;
    var vh = 0.0;
    if hl > 1.0e-12 {
        nh = form(normal, half) / hl;
        vh = form(view, half) / hl;
    }
    return Cosines(form(normal, l), form(normal, view), nh, vh);
}

#ifdef LIGHTS
// The unit tangent at the light image l towards x, for its spot's cone
// (its zero axis for a light in every direction, which needs none).
// Rust twin: from_light.
fn from_light(l: Light, x: vec4<f32>) -> vec4<f32> {
    if l.spot_scale == 0.0 {
        return l.spot_dir;
    }
    return toward_light(l.position, x, l.spot_dir);
}

// How much of a light image's light leaves along from_dir (a unit tangent
// at the image, pointing at the lit point): 1 for a light in every
// direction, a spot's clamp(cos a * scale + offset, 0, 1)^2. Rust twin:
// spot_factor.
fn spot_factor(l: Light, from_dir: vec4<f32>) -> f32 {
    if l.spot_scale == 0.0 {
        return 1.0;
    }
    let f = clamp(form(from_dir, l.spot_dir) * l.spot_scale + l.spot_offset, 0.0, 1.0);
    return f * f;
}
#endif

#ifdef LIGHT_IMAGES
// The irradiance one image of a light gives at arc length s from it:
// intensity / max(area(s), min_area), times the range's smooth window
// (1 - (s^2 / range^2)^2)^2, times exp(-density s) for the fog on the
// way. Rust twin: image_irradiance.
fn image_irradiance(l: Light, s: f32, fog_density: f32) -> f32 {
    let f = s * s * l.inv_range_sq;
    let window = clamp(1.0 - f * f, 0.0, 1.0);
    let area = max(sphere_area(s), l.min_area);
    // The fog on the way (none without FOG: no exp compiled in).
    var through = 1.0;
#ifdef FOG
    through = exp(-(fog_density * s));
#endif
    return l.intensity * window * window / area * through;
}
#endif

#ifdef LIGHT_IMAGES
// One arc from x to a light image: the unit tangent it leaves along, its
// length, and the irradiance it brings (0 when none, or when it arrives
// from behind the surface of normal `normal`).
struct LightArc {
    dir: vec4<f32>,
    s: f32,
    e: f32,
}

// Light image i's arcs to x: the short one, and in S3 (the second) the
// long way round, arriving from the other side. Rust twin: the arcs of
// shade's loop.
fn light_arcs(x: vec4<f32>, normal: vec4<f32>, i: u32, density: f32) -> array<LightArc, 2> {
    let l = lights[i];
    let d = distance(x, l.position);
    let to_light = toward_light(x, l.position, normal);
    let from_dir = from_light(l, x);
    var out = array<LightArc, 2>(LightArc(to_light, d, 0.0), LightArc(-to_light, 2.0 * PI - d, 0.0));
#ifdef GEOMETRY_SPHERICAL
    let count = 2u;
#else
    let count = 1u;
#endif
    for (var a = 0u; a < count; a++) {
        let e = image_irradiance(l, out[a].s, density) * spot_factor(l, select(from_dir, -from_dir, a == 1u));
        out[a].e = select(0.0, e, form(normal, out[a].dir) > 0.0);
    }
    return out;
}
#endif

// Lambert + Blinn (or the material's GGX) shading at the hit, lights with geometry-correct
// fall-off (1 / area of the sphere of radius d), per-cell colour, fog.
// The hit's chart parameter is where it is shaded; `normal_at`, when not
// zero, the normal there in place of the object's own (a cone's layer,
// cone.wgsl's cone_layer). Rust twin: `shade` (its `normal_at`).
// What a hit's surface is: the point, the unit tangent towards the eye,
// the unit normal, albedo, glow, emission and material (pbr: metallic,
// roughness; metallic -1 for the classic look). Rust twin: HitSurface.
struct HitSurface {
    x: vec4<f32>,
    view: vec4<f32>,
    normal: vec4<f32>,
    albedo: vec3<f32>,
    glow: f32,
    emissive: vec3<f32>,
    pbr: vec2<f32>,
}

// The surface of `hit` on `ray`, with the object's normal there unless
// `normal_at` (not zero) gives another. Rust twin: surface.
fn surface(ray: Ray, hit: Hit, normal_at: vec4<f32>) -> HitSurface {
    let x = normalize_point(ray.origin + ray.dir * hit.t);
    let view = -normalize_tangent(x, ray.dir);
    var normal = vec4<f32>(0.0);
    var albedo = vec3<f32>(1.0);
    var glow = 0.0;
    var emissive = vec3<f32>(0.0);
    var pbr = vec2<f32>(-1.0, 0.0);
#ifdef BALLS
    if hit.kind == 1u {
        normal = normal_from(x, balls[hit.index].center);
        albedo = balls[hit.index].color;
        glow = balls[hit.index].glow;
#ifdef MATERIALS
        pbr = ball_pbr(balls[hit.index].pbr);
#endif
    }
#endif
#ifdef TUBES
    if hit.kind == 2u {
        let seg = tubes[hit.index];
        normal = normal_from(x, foot_on_line(x, seg));
        albedo = seg.color;
    }
#endif
#ifdef MESHES
    if hit.kind == 3u {
        let inst = instances[hit.index];
        let h = MeshHit(0.0, hit.triangle, hit.u, hit.v);
        let uv = hit_uv(inst, hit.triangle, hit.u, hit.v);
        let m = mesh_surface(inst, uv);
        normal = mesh_normal(inst, h, uv, x, view);
        albedo = m.albedo;
        emissive = m.emissive;
        pbr = vec2<f32>(m.metallic, m.roughness);
    }
#endif
    if any(normal_at != vec4<f32>(0.0)) {
        normal = normal_at;
    }
    return HitSurface(x, view, normal, albedo, glow, emissive, pbr);
}

// The light of every light image the point x receives (each along its
// own geodesic, both arcs in S3, its fall-off, range and fog, and only if
// the way is free): add_light summed over them. Rust twin: direct.
fn direct(x: vec4<f32>, lit: Lit, cell_matrix: mat4x4<f32>) -> vec3<f32> {
    var rgb = vec3<f32>(0.0);
    let normal = lit.normal;
#ifdef LIGHTS
#ifdef LIGHT_IMAGES
    var density = 0.0;
#ifdef FOG
    density = cached.fog_density;
#endif
    // The short arc, and in S3 the long way round, arriving from the
    // other side.
#ifdef GEOMETRY_SPHERICAL
    let arcs = 2u;
#else
    let arcs = 1u;
#endif
#ifdef SHADOWS
    // Each lane walks its own shadow rays side by side with the other
    // lanes of its SIMD group, a segment per pass (shadow_step), taking
    // its next light image arc when one ends: the group then pays for
    // the longest of its lanes' walks, not, image by image, for every
    // image some lane's ray goes to. The Rust twin's loop takes them one
    // after the other; the terms and their order are the same.
    let kept = best;
#ifdef FOOTPRINT
    let kept_near = near_balls;
#endif
    shadow_ray = true;
    var next = 0u;
    var walking = false;
    var w: ShadowWalk;
    var pending = LightArc(vec4<f32>(0.0), 0.0, 0.0);
    var pending_light = 0u;
    // The arcs of light next / arcs, worked out once for both.
    var of_light = array<LightArc, 2>(pending, pending);
    // At most every arc's walk, each at most SHADOW_LEVELS + 1 segments,
    // plus one pass to find that none is left.
    let rounds = params.light_count * arcs * (SHADOW_LEVELS + 2u) + 1u;
    for (var round = 0u; round < rounds; round++) {
        if !walking {
            for (; next < params.light_count * arcs && !walking; next++) {
                if next % arcs == 0u {
                    of_light = light_arcs(x, normal, next / arcs, density);
                }
                let arc = of_light[next % arcs];
                if arc.e > 0.0 {
                    var aim = arc.dir;
                    var length = arc.s;
#ifdef SOFT_SHADOWS
                    let sampled = aim_at_light(x, arc.dir, arc.s, lights[next / arcs].radius, vec2<f32>(params.light_sample_u, params.light_sample_v));
                    aim = sampled.dir;
                    length = sampled.length;
#endif
                    w = shadow_walk_new(x, normal, aim, length, cell_matrix);
                    pending = arc;
                    pending_light = next / arcs;
                    walking = true;
                }
            }
            if !walking {
                break;
            }
        }
        let state = shadow_step(&w);
        if state != SHADOW_ON {
            if state == SHADOW_FREE {
                add_light(&rgb, lit, pending.dir, pending.e, lights[pending_light].color);
            }
            walking = false;
        }
    }
    shadow_ray = false;
    best = kept;
#ifdef FOOTPRINT
    near_balls = kept_near;
#endif
#else
    for (var i = 0u; i < params.light_count; i++) {
        let of_light = light_arcs(x, normal, i, density);
        for (var a = 0u; a < arcs; a++) {
            if of_light[a].e > 0.0 {
                add_light(&rgb, lit, of_light[a].dir, of_light[a].e, lights[i].color);
            }
        }
    }
#endif
#else
    for (var i = 0u; i < params.light_count; i++) {
        let l = lights[i];
        let d = distance(x, l.position);
        let to_light = toward_light(x, l.position, normal);
        let spot = spot_factor(l, from_light(l, x));
        add_light(&rgb, lit, to_light, l.intensity * spot / max(sphere_area(d), l.min_area), l.color);
    }
#endif
#endif
    return rgb;
}

fn shade(ray: Ray, hit: Hit, normal_at: vec4<f32>, dist: f32, cell: vec2<u32>, cell_matrix: mat4x4<f32>) -> vec3<f32> {
    let s = surface(ray, hit, normal_at);
    let x = s.x;
    let view = s.view;
    let normal = s.normal;
    let pbr = s.pbr;
    var albedo = s.albedo;
#ifdef CELL_COLORS
    albedo *= cell_color(cell);
#endif
    // Ambient light, the object's own glow and its emission.
    var rgb = albedo * (0.08 + s.glow) + s.emissive;
    let lit = Lit(normal, view, albedo, pbr.x, pbr.y);
    rgb += direct(x, lit, cell_matrix);
    var fog_kept = 1.0;
#ifdef FOG
    let tr = exp(-(cached.fog_density * dist));
    rgb = rgb * tr + params.fog_color.xyz * (1.0 - tr);
    fog_kept = tr;
#endif
#ifdef REFLECTIONS
    last_mirror.on = pbr.x >= 0.0 && pbr.y <= MAX_MIRROR_ROUGHNESS;
    if last_mirror.on {
        last_mirror.ray = mirror_ray(x, normal, view);
        last_mirror.weight = reflectance(albedo, pbr.x, pbr.y, form(normal, view));
        last_mirror.fog_kept = fog_kept;
    }
#endif
    return rgb;
}

// Rust twin: shade_wall. WALL_COLOR lit by the angle the ray meets the face
// plane at, then fog over `dist`.
fn shade_wall(plane: vec4<f32>, ray: Ray, dist: f32) -> vec3<f32> {
    let facing = min(abs(dot(plane, ray.dir) / (sqrt(dot(plane, plane)) * sqrt(dot(ray.dir, ray.dir)))), 1.0);
    return fogged(vec3<f32>(0.62, 0.58, 0.52) * (0.3 + 0.7 * facing), dist);
}

// `rgb` seen through the fog over `dist` (as shade's fog).
fn fogged(rgb: vec3<f32>, dist: f32) -> vec3<f32> {
#ifdef FOG
    let keep = exp(-params.fog_density * dist);
    return rgb * keep + params.fog_color.xyz * (1.0 - keep);
#else
    return rgb;
#endif
}

// What a ray shows where it would leave the table of exact ids under
// rules (CELLS_TABLE): CellTint::UNKNOWN's grey, then fog over `dist`.
fn unknown_rules(dist: f32) -> vec3<f32> {
    return fogged(vec3<f32>(0.5), dist);
}
