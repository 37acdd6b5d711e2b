// The manifold ray tracer's entry points: Algorithm 1 of Velho, da Silva,
// Novello (GI 2020), whose loop the core's trace/mod.rs docs spell out.
// The work is in the imported modules, each the WGSL twin of a Rust file
// of the CPU reference tracer (crates/bevy_manifold_core/src/trace/
// unless named), with the same names and the same arithmetic in the same
// order, so the CPU reference in f32 and this shader can be compared
// pixel by pixel:
//
//   bindings   crates/bevy_manifold_gpu/src/layout.rs   structs, bindings, constants
//   geometry   crates/bevy_manifold_core/src/geometry/mod.rs
//   step       step.rs       where a ray crosses a face
//   cells      crates/bevy_manifold_core/src/space/cells.rs
//   rule       crates/bevy_manifold_core/src/space/rule.rs
//   bvh        crates/bevy_manifold_core/src/mesh/bvh.rs
//   mesh_hit   mesh_hit.rs
//   ball_tree  ball_tree.rs
//   footprint  footprint.rs  a pixel's cone, its geometry
//   walk       walk.rs       the ray walk loop
//   camera     camera.rs     a pixel's ray
//   cone       cone.rs       a pixel's cone in the walk
//   nearest    nearest.rs    what a segment keeps of what it meets
//   cull       cull.rs       which objects a segment may meet
//   shade      shade.rs      shading a hit
//   trace      trace.rs      one ray, Algorithm 1
//   drift      drift.rs
//   output     output.rs
//
// Rust twin of this file: render.rs (render, every pixel's ray traced);
// its callers are in crates/bevy_manifold_gpu (the headless runner
// dispatches `trace` and `drift`) and the bevy_manifold crate (the render
// pass draws `fragment`).
//
// Shader defs (the pipeline is specialised on the scene; see
// crates/bevy_manifold_gpu/src/shader_defs.rs, which picks them):
//   GEOMETRY_EUCLIDEAN | GEOMETRY_HYPERBOLIC | GEOMETRY_SPHERICAL  exactly one
//   TRANSLATIONS_ONLY  every pairing is a Euclidean translation: transport
//                      moves the point, the direction is unchanged
//   CELLS_LATTICE | CELLS_FINITE | CELLS_HASHED | CELLS_TABLE  how cell ids
//                      are made (cells.rs): box lattice, Cayley-table
//                      index, hash of the copy's rounded centre, the table
//                      of exact cells around the camera
//   CELL_COLORS        per-cell shading
//   CELL_RULES         hidden cells and walls between cells
//   FOG                exponential fog and the early stop it allows
//   BALLS, TUBES, MESHES  which object kinds the scene has
//   BALL_HITS          derived: BALLS or MESHES (ball tests, also of the
//                      meshes' bounding balls)
//   LIGHTS             point lights (else ambient only)
//   FOOTPRINT          cone tracing
//   ENCODE_SRGB        the render pass's target stores sRGB-encoded bytes
//                      without doing the encoding itself (Bevy's
//                      CompositingSpace::Srgb): the fragment entry encodes
// This file reads ENCODE_SRGB; every other def is read in the modules.
//
// Entry points: `trace` (compute) writes every pixel with its ids to a
// storage buffer (headless renders, the agreement tests); `fragment` is the
// Bevy render pass's full-screen trace into a camera's view target, with
// depth. Both call `trace_ray` on the pixel's `view_ray`, so they cannot
// disagree. `drift` (compute) is the drift probe; it walks rays with the
// same walker as trace_ray.

#import bevy_manifold::bindings::{params, pixels, Pixel}
#import bevy_manifold::camera::{camera_ray, view_ray, view_direction}
#import bevy_manifold::trace::trace_ray
#import bevy_manifold::drift::ray_drift
#ifdef PATH_TRACE
#import bevy_manifold::path::path_sample
#endif
#ifdef ENCODE_SRGB
#import bevy_manifold::output::encode_srgb
#endif

// The pixel of invocation `index` (local_invocation_index) of the
// workgroup `tile`: its 8x8 pixels in Z order (x from the index's even
// bits, y from its odd ones), so each run of 8 invocations, which
// lavapipe runs as the 8 lanes of one SIMD pass, is a 4x2 block (16 a 4x4
// one, 32 an 8x4 one) and not a row of 8. A ray's cost follows the
// longest walk among its lanes: with 128 balls the rays of a 4x2 block
// walk 3.93 segments at most, of a row 4.22 (torus, 320x180, 8 levels,
// the mean being 3.30), and the frames traced 5-8% faster; see
// docs/benchmarks/history.md, "Lanes in 4x2 blocks".
fn tile_pixel(tile: vec2<u32>, index: u32) -> vec2<u32> {
    let x = (index & 1u) | ((index >> 1u) & 2u) | ((index >> 2u) & 4u);
    let y = ((index >> 1u) & 1u) | ((index >> 2u) & 2u) | ((index >> 3u) & 4u);
    return tile * 8u + vec2<u32>(x, y);
}

// The pixel at column i, row j: its ray traced, or under PATH_TRACE one
// path sample of it. Rust twin: the body of `render`'s loop.
fn pixel_at(i: u32, j: u32) -> Pixel {
#ifdef PATH_TRACE
    return path_sample(view_ray(i, j), j * params.width + i);
#else
    return trace_ray(view_ray(i, j));
#endif
}

// Every pixel traced into `pixels`. Rust twin: `render`.
@compute @workgroup_size(8, 8, 1)
fn trace(@builtin(workgroup_id) tile: vec3<u32>, @builtin(local_invocation_index) index: u32) {
    let p = tile_pixel(tile.xy, index);
    if p.x >= params.width || p.y >= params.height {
        return;
    }
    pixels[p.y * params.width + p.x] = pixel_at(p.x, p.y);
}

// The drift probe (Rust twin: ray_drift): see drift.wgsl.
@compute @workgroup_size(8, 8, 1)
fn drift(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= params.width || id.y >= params.height {
        return;
    }
    pixels[id.y * params.width + id.x] = ray_drift(camera_ray(id.x, id.y));
}

struct FragmentOutput {
    @location(0) color: vec4<f32>,
    @builtin(frag_depth) depth: f32,
}

@fragment
fn fragment(@builtin(position) position: vec4<f32>) -> FragmentOutput {
    let i = u32(position.x) - params.origin_x;
    let j = u32(position.y) - params.origin_y;
    let p = pixel_at(i, j);
    var rgb = p.color.xyz;
#ifdef ENCODE_SRGB
    rgb = encode_srgb(rgb);
#endif
    // Reverse-z depth of the hit along the view axis, so ordinary Bevy
    // meshes drawn after the trace (overlays, a HUD) sort against it;
    // 0 (infinitely far) where nothing was hit.
    var depth = 0.0;
    if p.object != 0u {
        let along = p.color.w * -view_direction(i, j).z;
        depth = params.near / max(along, params.near);
    }
    return FragmentOutput(vec4<f32>(rgb, 1.0), depth);
}
