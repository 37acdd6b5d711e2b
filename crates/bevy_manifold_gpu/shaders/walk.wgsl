// A ray walking segment by segment through the manifold: the part of
// Algorithm 1 shared by the tracer (trace.wgsl's
// trace_ray) and the drift probe (drift.wgsl), objects aside. It is
// written once, here; both walks call it.
//
// Rust twin: crates/bevy_manifold_core/src/trace/walk.rs (Walker::new,
// Walker::segment_end, Walker::step), and of trace_ray in
// crates/bevy_manifold_core/src/trace/trace.rs the part after the object
// test (advance, add the length, stop past max_distance or at the level
// limit, step on). Rust shares that part through trace_ray's on_step
// callback, which WGSL lacks, so here it is walk_segment, and the distance
// travelled is on the Walker.
//
// Shader defs read: CELLS_FINITE, CELLS_TABLE (the table index);
// CELL_RULES (walls stop the walk: rule.wgsl);
// GEOMETRY_* through geometry and step, TRANSLATIONS_ONLY through step,
// MESHES through bindings.
#define_import_path bevy_manifold::walk

#import bevy_manifold::bindings::{params, cached, faces, cell_table, face_count, NO_FACE, CELL_OUTSIDE}
#import bevy_manifold::geometry::{chart_to_distance, max_chart_parameter}
#import bevy_manifold::step::{Ray, Exit, exit_face, advance_or_raw, transport_or_raw}
#ifdef CELL_RULES
#import bevy_manifold::cells::cell_id
#import bevy_manifold::rule::cell_wall
#endif

// Where a walking ray is: the start of its current segment, the face it
// came in through, the cell it is in, how many faces it has crossed, and
// how far it has gone. Rust twin: Walker in
// crates/bevy_manifold_core/src/trace/walk.rs (the distance and the
// Cayley-table index are WGSL-only: Rust keeps them in trace_ray).
struct Walker {
    // Start of the current segment (inside the domain).
    ray: Ray,
    // The face it entered by (skipped when looking for the exit), or
    // NO_FACE.
    entered: u32,
    // The group element of the current cell: the ray's point in the cover
    // is cell * ray.origin.
    cell: mat4x4<f32>,
    // CELLS_FINITE: the cell's index in the Cayley table (cell_table);
    // CELLS_TABLE: in the table of cells around the camera, or
    // CELL_OUTSIDE. Rust finds the first from `cell` (CellScheme::
    // id_within) and follows the exact element for the second
    // (trace_ray's `exact`).
    index: u32,
    // Faces crossed so far (the paper's level).
    levels: u32,
    // Distance travelled (a local of trace_ray in Rust).
    travelled: f32,
}

// A walk starting at `ray` in the cell (cell, index).
fn walker_new(ray: Ray, cell: mat4x4<f32>, index: u32) -> Walker {
    return Walker(ray, NO_FACE, cell, index, 0u, 0.0);
}

// The hard bound on a walk's passes, as the CPU's: every pass either
// transports (at most params.levels times) or, in S3, advances by a fixed
// distance of 1 (at most max_distance times), so no input makes it spin.
fn max_passes() -> u32 {
    return cached.levels + u32(min(cached.max_distance, 1.0e4)) + 2u;
}

// Where the current segment ends: the face it leaves through (NO_FACE in
// S3 when no face is within a quarter turn) and the chart parameter.
fn segment_end(walk: Walker) -> Exit {
    let t_cap = max_chart_parameter();
    var exit = exit_face(walk.ray, walk.entered);
    // As Walker::segment_end: a face is kept only when t < t_cap, so a NaN
    // t keeps none.
    if exit.face != NO_FACE && !(exit.t < t_cap) {
        exit.face = NO_FACE;
    }
    exit.t = select(exit.t, t_cap, exit.face == NO_FACE);
    return exit;
}

// Starts the next segment from `end`, the end of the current one: through
// the pairing of `face` (moving to the neighbouring cell), or straight on
// when there is no face. FLAG_NO_RENORMALIZE only to measure drift.
fn walker_step(walk: ptr<function, Walker>, face: u32, end: Ray) {
    if face == NO_FACE {
        (*walk).ray = end;
        (*walk).entered = NO_FACE;
        return;
    }
    (*walk).ray = transport_or_raw(face, end);
    (*walk).entered = faces[face].partner;
    (*walk).cell = cross_cell((*walk).cell, face);
#ifdef CELLS_FINITE
    (*walk).index = cell_table[(*walk).index * face_count() + faces[face].partner];
#endif
#ifdef CELLS_TABLE
    // Rust: CellTable's neighbours (space/cell_table.rs); once outside the table
    // the walk stays outside.
    if (*walk).index != CELL_OUTSIDE {
        (*walk).index = cell_table[(*walk).index * face_count() + faces[face].partner];
    }
#endif
    (*walk).levels += 1u;
}

// The cell across `face` from `cell`: cell * T_face^-1, as Walker::step
// multiplies (Rust multiplies whole matrices). In E3 both are affine (last
// row 0, 0, 0, 1, exactly, in f32 too), so only the sums whose terms are
// not all exactly 0 are made; under TRANSLATIONS_ONLY the linear part
// stays the identity and only the translation moves. The same numbers,
// without 64 multiplies and 16 lane-by-lane reads a transport in a
// shader where every lane may cross a different face.
fn cross_cell(cell: mat4x4<f32>, face: u32) -> mat4x4<f32> {
#ifdef TRANSLATIONS_ONLY
    var out = cell;
    out[3] = vec4<f32>(cell[3].xyz + faces[face].crossing[3].xyz, 1.0);
    return out;
#else ifdef GEOMETRY_EUCLIDEAN
    let m = faces[face].crossing;
    let lin = mat3x3<f32>(cell[0].xyz, cell[1].xyz, cell[2].xyz);
    return mat4x4<f32>(vec4<f32>(lin * m[0].xyz, 0.0), vec4<f32>(lin * m[1].xyz, 0.0), vec4<f32>(lin * m[2].xyz, 0.0), vec4<f32>(lin * m[3].xyz + cell[3].xyz, 1.0));
#else
    return cell * faces[face].crossing;
#endif
}

// One segment walked, as trace_ray's on_step sees it (Rust twin: PathStep).
struct PathStep {
    // Where the segment ended: on the face, or where the walk stopped.
    end: Ray,
    // The walk ends here (Rust: Stop::MaxDistance, Stop::MaxLevel).
    stop: bool,
    // CELL_RULES: 1 when it ends at a wall (Rust: Stop::Hit(WALL_OBJECT));
    // 2 when it would leave the table of exact ids, where the rules are
    // unknown (CELLS_TABLE; the CPU, exact everywhere, has no twin).
    wall: u32,
}

#ifdef CELL_RULES
// The id of the cell across `face` from the walk's. Rust twin: cross_cell and
// cell_id_of in crates/bevy_manifold_core/src/space/element.rs.
fn next_cell_id(walk: Walker, face: u32) -> vec2<u32> {
#ifdef CELLS_FINITE
    return cell_id(walk.cell, cell_table[walk.index * face_count() + faces[face].partner]);
#else ifdef CELLS_TABLE
    if walk.index == CELL_OUTSIDE {
        return cell_id(walk.cell, CELL_OUTSIDE);
    }
    return cell_id(walk.cell, cell_table[walk.index * face_count() + faces[face].partner]);
#else
    return cell_id(cross_cell(walk.cell, face), 0u);
#endif
}
#endif

// The rest of a pass once no object was hit on the segment `seg` (from
// segment_end): advance to its end, add its length, stop past
// max_distance, at a wall (CELL_RULES), or at a face once params.levels
// faces are crossed, else step on. Branches in trace_ray's order.
fn walk_segment(walk: ptr<function, Walker>, seg: Exit) -> PathStep {
    let end = advance_or_raw((*walk).ray, seg.t);
    (*walk).travelled += chart_to_distance(seg.t);
    if (*walk).travelled > cached.max_distance {
        return PathStep(end, true, 0u);
    }
#ifdef CELL_RULES
    if seg.face != NO_FACE {
        let next = next_cell_id(*walk, seg.face);
        if next.x == 0u && next.y == 0x40000000u {
            return PathStep(end, true, 2u);
        }
        if cell_wall(cell_id((*walk).cell, (*walk).index), next) {
            return PathStep(end, true, 1u);
        }
    }
#endif
    if seg.face != NO_FACE && (*walk).levels >= cached.levels {
        return PathStep(end, true, 0u);
    }
    walker_step(walk, seg.face, end);
    return PathStep(end, false, 0u);
}
