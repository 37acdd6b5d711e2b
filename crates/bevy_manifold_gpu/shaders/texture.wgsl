// A mesh's textures in mesh_data, sampled nearest with repeat: where a
// hit's texture coordinates are (hit_uv), a texel as four numbers in
// [0, 1] (texel_unorm) or as linear colour from sRGB (texture_rgb), and
// the alpha of an alpha-masked material (mesh_alpha). Each texture is a
// header word [width, height, 0, 0] and then its texels, four a word
// (GpuInstance::textures in crates/bevy_manifold_gpu/src/layout.rs).
//
// Rust twins: Texture::texel, Texture::sample_unorm and Texture::sample in
// crates/bevy_manifold_core/src/mesh/mod.rs (texel_index, srgb_to_linear
// there too); hit_uv and mesh_alpha in
// crates/bevy_manifold_core/src/trace/mesh_hit.rs.
//
// Shader defs read: MESHES (the whole module).
#define_import_path bevy_manifold::texture

#ifdef MESHES
#import bevy_manifold::bindings::{Instance, mesh_data}

// An Instance::textures slot with no texture.
const NO_TEXTURE: u32 = 0xffffffffu;

// Rust twin: hit_uv. The triangle's corners' texture coordinates (the w
// of the vertex's two words), weighted by the hit's barycentrics.
fn hit_uv(inst: Instance, triangle: u32, u: f32, v: f32) -> vec2<f32> {
    let tri = mesh_data[inst.triangles + triangle];
    let w = vec3<f32>(1.0 - u - v, u, v);
    var uv = vec2<f32>(0.0);
    for (var k = 0u; k < 3u; k++) {
        let a = mesh_data[inst.vertices + 2u * tri[k]];
        let b = mesh_data[inst.vertices + 2u * tri[k] + 1u];
        uv += w[k] * vec2<f32>(bitcast<f32>(a.w), bitcast<f32>(b.w));
    }
    return uv;
}

// Rust twin: texel_index.
fn texel_index(x: f32, n: u32) -> u32 {
    let f = x - floor(x);
    return min(u32(f * f32(n)), max(n, 1u) - 1u);
}

// Rust twin: srgb_to_linear.
fn srgb_to_linear(c: f32) -> f32 {
    return select(pow((c + 0.055) / 1.055, 2.4), c / 12.92, c <= 0.04045);
}

// Rust twin: Texture::sample_unorm. The texel of the texture at `header`
// nearest `uv`, repeating, as four numbers in [0, 1].
fn texel_unorm(header: u32, uv: vec2<f32>) -> vec4<f32> {
    let size = mesh_data[header].xy;
    let k = texel_index(uv.y, size.y) * size.x + texel_index(uv.x, size.x);
    return unpack4x8unorm(mesh_data[header + 1u + k / 4u][k % 4u]);
}

// Rust twin: Texture::sample. The linear colour of an sRGB texture.
fn texture_rgb(header: u32, uv: vec2<f32>) -> vec3<f32> {
    let c = texel_unorm(header, uv);
    return vec3<f32>(srgb_to_linear(c.x), srgb_to_linear(c.y), srgb_to_linear(c.z));
}

// Rust twin: mesh_alpha. The base alpha factor times the base texture's
// alpha.
fn mesh_alpha(inst: Instance, uv: vec2<f32>) -> f32 {
    if inst.textures.x == NO_TEXTURE {
        return inst.alpha;
    }
    return inst.alpha * texel_unorm(inst.textures.x, uv).w;
}
#endif
