// Writing colour out: the sRGB encoding for targets that store encoded
// values without encoding them (Bevy's CompositingSpace::Srgb), used by
// the render pass's `fragment` (trace.wgsl) and `upscale` (upscale.wgsl)
// under ENCODE_SRGB.
//
// Rust twin: crates/bevy_manifold_core/src/trace/output.rs.
#define_import_path bevy_manifold::output

// Rust twin: `srgb8` (before its rounding to a byte).
fn encode_srgb(c: vec3<f32>) -> vec3<f32> {
    let x = clamp(c, vec3<f32>(0.0), vec3<f32>(1.0));
    return select(1.055 * pow(x, vec3<f32>(1.0 / 2.4)) - 0.055, 12.92 * x, x <= vec3<f32>(0.0031308));
}
