// The per-cell tint of a cell id, shared by the tracer of E3, H3 and S3
// (cells.wgsl) and that of the product spaces (product.wgsl): u32
// arithmetic only, so the GPU and the CPU make the same colours.
//
// Rust twins: crates/bevy_manifold_core/src/space/cell_id.rs (hash32,
// CellId::hash, CellId::color) and space/cells.rs (CellTint::tint, with
// the mode and words of CellTint::words).
#define_import_path bevy_manifold::cell_tint

// PCG's output permutation. Rust twin: `hash32`.
fn hash32(x: u32) -> u32 {
    let state = x * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// The id's 32 hashed bits. Rust twin: `CellId::hash`.
fn cell_hash(id: vec2<u32>) -> u32 {
    return hash32(id.x ^ hash32(id.y));
}

// The tint of cell `id` (its lo and hi words) in `mode` (0 by cell, 1
// highlight of the cell (a, b), 2 pattern with threshold a). Rust twin:
// `CellTint::tint`.
fn cell_tint(id: vec2<u32>, mode: u32, a: u32, b: u32) -> vec3<f32> {
    let origin = id.x == 0u && id.y == 0u;
    // CellTint::UNKNOWN for a cell the table does not reach.
    if id.x == 0u && id.y == 0x40000000u {
        return vec3<f32>(0.5);
    }
    if mode == 1u {
        return select(vec3<f32>(1.0), vec3<f32>(1.0, 0.55, 0.15), id.x == a && id.y == b);
    }
    if mode == 2u {
        return vec3<f32>(select(0.12, 1.0, origin || (cell_hash(id) >> 8u) < a));
    }
    if origin {
        return vec3<f32>(1.0);
    }
    let h = cell_hash(id);
    return 0.25 + 0.75 * vec3<f32>(f32(h & 0xffu), f32((h >> 8u) & 0xffu), f32((h >> 16u) & 0xffu)) / 255.0;
}
