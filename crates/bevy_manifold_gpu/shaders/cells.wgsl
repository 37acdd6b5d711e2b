// Cells of the covering space: which copy of the domain a
// ray ended in, as the two words of a CellId, and the per-cell tint.
//
// Rust twin: crates/bevy_manifold_core/src/space/cells.rs (CellScheme::
// id_within, hash_key; u32 arithmetic only, so both sides make the same
// ids); the tint itself is cell_tint.wgsl's.
//
// Shader defs read: CELLS_FINITE, CELLS_TABLE, CELLS_LATTICE (else
// CELLS_HASHED),
// CELL_COLORS (cell_color); MESHES through bindings.
#define_import_path bevy_manifold::cells

#import bevy_manifold::bindings::{params, cell_table, CELL_OUTSIDE}
#import bevy_manifold::cell_tint::{hash32, cell_tint}

// The cell id as (lo, hi) words of CellId, from the cell's group element
// (and, for finite groups, its table index). Rust twin: CellScheme::id_within.
fn cell_id(cell: mat4x4<f32>, index: u32) -> vec2<u32> {
#ifdef CELLS_FINITE
    return vec2<u32>(index, 0u);
#else ifdef CELLS_TABLE
    // Beyond the table: CellId::BEYOND_TABLE, the far bit alone. Rust:
    // CellTable::ids_around, in the words GpuSpace::centre_on writes.
    if index == CELL_OUTSIDE {
        return vec2<u32>(0u, 0x40000000u);
    }
    let ids = bitcast<u32>(params.cell_scale.x);
    return vec2<u32>(cell_table[ids + 2u * index], cell_table[ids + 2u * index + 1u]);
#else ifdef CELLS_LATTICE
    let c = cell[3].xyz / cell[3].w * params.cell_scale.xyz;
    let l = vec3<i32>(round(c));
    if all(l == vec3<i32>(0)) {
        return vec2<u32>(0u);
    }
    // 21 bits per coordinate, tag bit 63 (CellId::from_lattice).
    let m = 0x1fffffu;
    let x = bitcast<u32>(l.x) & m;
    let y = bitcast<u32>(l.y) & m;
    let z = bitcast<u32>(l.z) & m;
    let lo = x | (y << 21u);
    let hi = (y >> 11u) | (z << 10u) | 0x80000000u;
    return vec2<u32>(lo, hi);
#else
    let c = cell[3];
    // Not finite (NaN or infinite exponent bits): flagged far, id 1, as
    // Rust's hashed_id does.
    let exponent = bitcast<vec4<u32>>(c) & vec4<u32>(0x7f800000u);
    if any(exponent == vec4<u32>(0x7f800000u)) {
        return vec2<u32>(1u, 0x40000000u);
    }
    // Rust: hash_key_of (times the scale, round half to even, clamped to
    // HASH_KEY_LIMIT = 2^30, exact in f32).
    let limit = vec4<f32>(1073741824.0);
    let key = vec4<i32>(clamp(round(c * params.cell_scale.x), -limit, limit));
    let origin = vec4<i32>(clamp(round(vec4<f32>(0.0, 0.0, 0.0, 1.0) * params.cell_scale.x), -limit, limit));
    if all(key == origin) {
        return vec2<u32>(0u);
    }
    let lo = hash_key(key, 0x9e3779b9u);
    var hi = hash_key(key, 0x85ebca6bu) & 0x3fffffffu;
    if abs(c.w) >= params.cell_scale.y {
        hi |= 0x40000000u; // CellId::FAR, past the f32 horizon
    }
    return vec2<u32>(select(lo, 1u, lo == 0u && hi == 0u), hi);
#endif
}

#ifdef CELL_COLORS
// CellTint::tint with the tracer's mode and words.
fn cell_color(id: vec2<u32>) -> vec3<f32> {
    return cell_tint(id, params.cell_mode, params.cell_a, params.cell_b);
}
#endif

// Hash of a rounded cell centre, seeded. Rust twin: `hash_key`.
fn hash_key(key: vec4<i32>, seed: u32) -> u32 {
    var h = seed;
    h = hash32(h ^ bitcast<u32>(key.x));
    h = hash32(h ^ bitcast<u32>(key.y));
    h = hash32(h ^ bitcast<u32>(key.z));
    h = hash32(h ^ bitcast<u32>(key.w));
    return h;
}
