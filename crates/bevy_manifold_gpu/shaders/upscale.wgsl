// The render pass's upscale: a view traced at a render scale below 1
// (src/render/scale.rs, ManifoldRenderScale) is drawn over the whole
// viewport from the smaller traced texture, colour filtered bilinearly
// (the sampler's linear filter, on linear colour: an sRGB texture is
// decoded before filtering) and depth taken from the nearest traced pixel,
// so ordinary meshes drawn after the trace still sort against it.
//
// Rust twin: `upscale` in crates/bevy_manifold_core/src/trace/output.rs (the
// same bilinear filter on the CPU, texel centres at half-integers, edges
// clamped), which the pass's test compares this against. Caller:
// src/render/upscale.rs, after the trace in src/render/node.rs.
//
// The vertex stage is Bevy's full-screen triangle, whose `uv` runs over
// [0, 1] across the viewport. The traced textures and the history hold
// linear colour (Rgba16Float); ENCODE_SRGB encodes it for a target that
// stores encoded values without encoding them, as trace.wgsl's fragment
// does.

#ifdef ENCODE_SRGB
#import bevy_manifold::output::encode_srgb
#endif

@group(0) @binding(0) var traced: texture_2d<f32>;
@group(0) @binding(1) var bilinear: sampler;
@group(0) @binding(2) var traced_depth: texture_depth_2d;

struct UpscaleOutput {
    @location(0) color: vec4<f32>,
    @builtin(frag_depth) depth: f32,
}

@fragment
fn upscale(@location(0) uv: vec2<f32>) -> UpscaleOutput {
    // A history holds the sum of its samples and their count in alpha; a
    // trace has alpha 1.
    let sum = textureSampleLevel(traced, bilinear, uv, 0.0);
    var color = vec4<f32>(sum.xyz / max(sum.w, 1.0e-6), 1.0);
#ifdef ENCODE_SRGB
    color = vec4<f32>(encode_srgb(color.xyz), color.w);
#endif
    let size = textureDimensions(traced_depth);
    let texel = min(vec2<u32>(uv * vec2<f32>(size)), size - vec2<u32>(1u));
    return UpscaleOutput(color, textureLoad(traced_depth, texel, 0));
}

// Accumulation while the view is still (src/render/accumulate.rs): the
// new trace (alpha 1), copied texel for texel into the view's history,
// which the pipeline's additive blend turns into the sum of the samples
// with their count in alpha. Rust twin: `accumulate` in
// crates/bevy_manifold_core/src/trace/accumulate.rs. The upscale above
// then reads the history in place of the trace and divides.
@fragment
fn blend_in(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    return textureLoad(traced, vec2<u32>(position.xy), 0);
}
