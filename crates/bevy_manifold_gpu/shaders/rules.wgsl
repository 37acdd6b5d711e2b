// Per-cell rules from cell ids: objects in off cells hidden, walls
// between cells, and how a wall is shaded.
//
// Rust twin: crates/bevy_manifold_core/src/space/rule.rs (CellRule::
// visible, CellRule::wall, bits) and shade_wall in trace/render.rs; u32
// arithmetic only, so both sides decide the same cells and faces.
//
// Shader defs read: FOG (the wall's fog).
#define_import_path bevy_manifold::rules

#import bevy_manifold::bindings::params
#import bevy_manifold::cells::hash32
#import bevy_manifold::step::Ray

// CellId::BEYOND_TABLE.
fn beyond_table(id: vec2<u32>) -> bool {
    return id.x == 0u && id.y == 0x40000000u;
}

// Rust: bits.
fn rule_bits(id: vec2<u32>, seed: u32) -> u32 {
    return hash32(hash32(seed ^ id.x) ^ id.y) >> 8u;
}

// Rust: CellRule::visible.
fn cell_visible(id: vec2<u32>) -> bool {
    let origin = id.x == 0u && id.y == 0u;
    return origin || beyond_table(id) || rule_bits(id, params.rule_hidden_seed) < params.rule_hidden;
}

// Rust: CellRule::wall (the pair ordered as u64, mixed as there).
fn cell_wall(a: vec2<u32>, b: vec2<u32>) -> bool {
    if params.rule_walls == 0u || all(a == b) || beyond_table(a) || beyond_table(b) {
        return false;
    }
    let a_first = a.y < b.y || (a.y == b.y && a.x < b.x);
    let lo = select(b, a, a_first);
    let hi = select(a, b, a_first);
    // bits(lo) | (hi << 24) ^ (hi >> 40), in two words.
    let pair = vec2<u32>(rule_bits(lo, params.rule_walls_seed) | ((hi.x << 24u) ^ (hi.y >> 8u)), (hi.y << 24u) | (hi.x >> 8u));
    return rule_bits(pair, params.rule_walls_seed ^ 0x5bd1e995u) < params.rule_walls;
}

// Rust: shade_wall. WALL_COLOR lit by the angle the ray meets the face
// plane at, then fog over `dist`.
fn shade_wall(plane: vec4<f32>, ray: Ray, dist: f32) -> vec3<f32> {
    let facing = min(abs(dot(plane, ray.dir) / (sqrt(dot(plane, plane)) * sqrt(dot(ray.dir, ray.dir)))), 1.0);
    return fogged(vec3<f32>(0.62, 0.58, 0.52) * (0.3 + 0.7 * facing), dist);
}

// `rgb` seen through the fog over `dist` (as shade's fog in render.wgsl).
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
