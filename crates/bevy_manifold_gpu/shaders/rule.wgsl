// Per-cell rules from cell ids: objects in off cells hidden, walls
// between cells (a wall is shaded in shade.wgsl).
//
// Rust twin: crates/bevy_manifold_core/src/space/rule.rs (CellRule::
// visible as cell_visible, CellRule::wall as cell_wall, bits as
// rule_bits); u32 arithmetic only, so both sides decide the same cells
// and faces.
#define_import_path bevy_manifold::rule

#import bevy_manifold::bindings::params
#import bevy_manifold::cell_tint::hash32

// CellId::BEYOND_TABLE.
fn beyond_table(id: vec2<u32>) -> bool {
    return id.x == 0u && id.y == 0x40000000u;
}

// Rust twin: `bits`.
fn rule_bits(id: vec2<u32>, seed: u32) -> u32 {
    return hash32(hash32(seed ^ id.x) ^ id.y) >> 8u;
}

// Rust twin: CellRule::visible.
fn cell_visible(id: vec2<u32>) -> bool {
    let origin = id.x == 0u && id.y == 0u;
    return origin || beyond_table(id) || rule_bits(id, params.rule_hidden_seed) < params.rule_hidden;
}

// Rust twin: CellRule::wall (the pair ordered as u64, mixed as there).
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
