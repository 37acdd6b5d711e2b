// The tracer's data as the GPU sees it: the structs of bind group 0, the
// bindings themselves, and the constants the CPU and GPU sides share.
//
// Rust twin: crates/bevy_manifold_gpu/src/layout.rs (the Gpu… structs,
// `#[repr(C)]`, byte for byte; a naga layouter test holds the two to the
// same sizes and offsets). The bind group layout that matches the
// `@binding`s below is built in crates/bevy_manifold_gpu (headless runner,
// render pass).
//
// Shader defs read: MESHES (the mesh instances, binding 6); FACE_COUNT (a
// value, when set).
//
// Padding is `pad: array<u32, 3>` as in Rust (`pad: [u32; 3]`): the same
// bytes as the single file's `_pad0`..`_pad2`, which naga_oil rejects in an
// import module (a member name ending in a digit does not survive naga's
// write-back unchanged).
#define_import_path bevy_manifold::bindings

// The domain's faces: the value def FACE_COUNT (TraceDefs::face_count,
// set for every scene), a constant, so every loop over the faces has a
// constant trip count and is unrolled (in chunks: step.wgsl's FACE_CHUNK)
// and reads each face at a constant index; else params.face_count (read
// once, `cached`). On lavapipe a run-time bound also cut long walks: it
// ends all loops of an invocation after 65,535 iterations between them.
fn face_count() -> u32 {
#ifdef FACE_COUNT
    return #{FACE_COUNT}u;
#else
    return cached.face_count;
#endif
}

// Rust twin: GpuParams in crates/bevy_manifold_gpu/src/layout.rs.
struct Params {
    camera: mat4x4<f32>,
    camera_cell: mat4x4<f32>,
    fog_color: vec4<f32>,
    width: u32,
    height: u32,
    // Most transports per ray (TraceSettings::levels).
    levels: u32,
    face_count: u32,
    ball_count: u32,
    tube_count: u32,
    light_count: u32,
    camera_cell_index: u32,
    tan_half_fov: f32,
    max_distance: f32,
    fog_density: f32,
    tube_k: f32,
    // The render pass: the viewport's top-left pixel in the target, and the
    // camera's near plane (Bevy's reverse-z depth is near / view depth).
    origin_x: u32,
    origin_y: u32,
    near: f32,
    // FLAG_NO_EARLY_STOP, FLAG_NO_RENORMALIZE: measurement switches
    // (TraceSettings::fog_early_stop, ::renormalize), both off by default.
    flags: u32,
    // CELLS_LATTICE: 1 / edge lengths of the box; CELLS_HASHED: 1 / grid
    // step in x, the f32 horizon (HASHED_HORIZON_F32) in y; CELLS_TABLE:
    // the bits of x are where the ids start in cell_table.
    cell_scale: vec4<f32>,
    instance_count: u32,
    // CELL_COLORS: the tint (CellTint::words): mode 0 by cell, 1 highlight
    // the cell (cell_a, cell_b), 2 on/off pattern with threshold cell_a.
    cell_mode: u32,
    cell_a: u32,
    cell_b: u32,
    // CELL_RULES: CellRule::words (the on threshold and seed, the wall
    // threshold and seed).
    rule_hidden: u32,
    rule_hidden_seed: u32,
    rule_walls: u32,
    rule_walls_seed: u32,
    // Projection::words: 0 perspective, 1 equirectangular, 2 ODS top-bottom
    // with the eyes eye_offset either side of the camera.
    projection: u32,
    eye_offset: f32,
    // FaceTables::near_scale * FlatScene::near_reach: the bound of
    // near_faces' test (step.wgsl); infinite when nothing is culled.
    near_reach: f32,
    // SOFT_SHADOWS: the point of each light's disc shadow rays aim at
    // (light_sample_point of TraceSettings::light_sample), u here, v
    // below; [0, 0] is the centre.
    light_sample_u: f32,
    // How many leaves of the ball tree ball_nodes holds (0: no tree).
    // ball_tree.wgsl's cache_leaves reads them.
    ball_leaves: u32,
    // FOOTPRINT: FaceTables::chart_stretch, what the ball tree's boxes are
    // padded by per unit of growth, and FlatScene::footprint_cap, the
    // widest a pixel's cone grows.
    chart_stretch: f32,
    footprint_cap: f32,
    light_sample_v: f32,
    // An off-centre frustum (Frustum::half_extent_and_centre): half width,
    // half height, centre x, centre y, in slopes; all zero for the
    // symmetric one of tan_half_fov and the image's aspect.
    frustum: vec4<f32>,
    // FOOTPRINT (cone tracing, footprint.wgsl): the pixel's half-angle
    // (pixel_half_angle), FlatScene::near_distance, FaceTables::near_scale
    // and FlatScene::cell_shadow.
    cone: vec4<f32>,
    // The faces (below 32) whose group holds any ball, tube, instance (x,
    // y, z): nearest_object walks only these of a segment's near faces.
    // WGSL only (GpuParams::occupied).
    occupied: vec4<u32>,
    // REFLECTIONS: the most reflections a ray takes (TraceSettings::reflections).
    reflections: u32,
    // PATH_TRACE: the most bounces of a path, the seed, the sample's
    // index (TraceSettings::path_depth, seed, light_sample).
    path_depth: u32,
    seed: u32,
    sample: u32,
    // INSTANCE_TREE: where in mesh_data the instance trees' table starts
    // (GpuObjects::instance_trees; instance_tree.wgsl), or
    // NO_INSTANCE_TREES.
    instance_trees: u32,
    pad_a: u32,
    pad_b: u32,
    pad_c: u32,
}

// Rust twin: GpuFace in crates/bevy_manifold_gpu/src/layout.rs.
struct Face {
    plane: vec4<f32>,
    pairing: mat4x4<f32>,
    // T_i^-1: what the ray's cell element is right-multiplied by.
    crossing: mat4x4<f32>,
    partner: u32,
    // One word a field: in a uniform array a member array would need a
    // 16-byte stride.
    pad_a: u32,
    pad_b: u32,
    pad_c: u32,
}

// Rust twin: GpuBall in crates/bevy_manifold_gpu/src/layout.rs.
struct Ball {
    center: vec4<f32>,
    color: vec3<f32>,
    // cosh r (H3), cos r (S3), r^2 (E3)
    k: f32,
    id: u32,
    // The faces whose planes it lies near (FlatBall::faces): tested only
    // on segments near all of them (step.wgsl's may_hit).
    face_mask: u32,
    // FlatBall::glow: shown at least albedo * glow, lit or not.
    glow: f32,
    // FlatBall::pbr in one word (pack_pbr in Rust, shade.wgsl's ball_pbr):
    // 0 for the classic look. Also pads the element to a 16-byte stride.
    pbr: u32,
}

// Rust twin: GpuTube in crates/bevy_manifold_gpu/src/layout.rs (the
// geometry of Segment in crates/bevy_manifold_core/src/trace/step.rs, and
// a colour).
struct Tube {
    a: vec4<f32>,
    e: vec4<f32>,
    b: vec4<f32>,
    e_b: vec4<f32>,
    color: vec3<f32>,
    // The two faces whose planes hold its edge (FlatTube::face_mask).
    face_mask: u32,
    // The vertex joint tested after it (FlatTube::joint), or NO_JOINT.
    joint: u32,
    pad_a: u32,
    pad_b: u32,
    pad_c: u32,
}

// Rust twin: GpuInstance in crates/bevy_manifold_gpu/src/layout.rs. A mesh
// instance: offsets into mesh_data.
struct Instance {
    // World chart to the mesh's own coordinates.
    to_local: mat4x4<f32>,
    // Bounding ball.
    center: vec4<f32>,
    color: vec3<f32>,
    k: f32,
    nodes: u32,
    vertices: u32,
    triangles: u32,
    id: u32,
    // Base colour, metallic-roughness, emission and normal textures: each
    // the offset in mesh_data of a header [width, height, 0, 0] and then
    // the texels, four a word; NO_TEXTURE (0xffffffff) for none.
    textures: vec4<u32>,
    node_count: u32,
    // 1: a copy of a mesh attached to the camera (see `home`).
    attached: u32,
    // The faces its bounding ball lies near (FlatInstance::faces).
    face_mask: u32,
    // The alpha mask's cutoff; negative: opaque.
    alpha_cutoff: f32,
    // Emitted radiance, linear RGB.
    emissive: vec3<f32>,
    // Negative: the classic look (no GGX lobe).
    metallic: f32,
    roughness: f32,
    // The base alpha factor (for the mask).
    alpha: f32,
    pad: array<u32, 2>,
    // With `attached`: the cell point g o from which this copy is the
    // camera's own body, never hit from there (FlatInstance::home in Rust).
    home: vec4<f32>,
}

// Rust twin: GpuLight in crates/bevy_manifold_gpu/src/layout.rs.
// One image of a light (light_images in Rust): with LIGHT_IMAGES, its
// range's 1 / range^2 (0: none) and the least area its irradiance is
// divided by; a spot's fall-off (scale 0 and offset 1: none) and axis.
struct Light {
    position: vec4<f32>,
    color: vec3<f32>,
    intensity: f32,
    inv_range_sq: f32,
    min_area: f32,
    spot_scale: f32,
    spot_offset: f32,
    spot_dir: vec4<f32>,
    // FlatLight::radius: soft shadows (SOFT_SHADOWS, shadow.wgsl's
    // aim_at_light).
    radius: f32,
    pad_a: f32,
    pad_b: f32,
    pad_c: f32,
}

// Rust twin: GpuPixel in crates/bevy_manifold_gpu/src/layout.rs. What one
// pixel saw: colour, then object id, levels, cell id (two words).
struct Pixel {
    color: vec4<f32>,
    object: u32,
    levels: u32,
    cell_lo: u32,
    cell_hi: u32,
}

// The most faces, light images, balls, edge tubes and ball tree leaves
// the uniform arrays hold, and the face groups' entries. Rust twins:
// bevy_manifold_core's MAX_FACES and MAX_LIGHT_IMAGES, and MAX_BALLS,
// MAX_TUBES, GROUPS and MAX_BALL_LEAVES in
// crates/bevy_manifold_gpu/src/bindings.rs (BINDINGS' capacities, which
// the contract test holds to these lengths).
const MAX_FACES: u32 = 128u;
const MAX_LIGHTS: u32 = 256u;
const MAX_BALLS: u32 = 1024u;
const MAX_TUBES: u32 = 378u;
const GROUPS: u32 = 33u;
const MAX_BALL_LEAVES: u32 = 64u;

// A read-only storage buffer, not a uniform: see BINDINGS in
// crates/bevy_manifold_gpu/src/bindings.rs (with a uniform, lavapipe's
// memory grew at every draw). Read it once per invocation where a loop
// would read it again: see cache_params.
@group(0) @binding(0) var<storage, read> params: Params;
// Uniform arrays, full size whatever the space: lavapipe reads a storage
// buffer one lane at a time, a uniform by a gather.
@group(0) @binding(1) var<uniform> faces: array<Face, MAX_FACES>;
@group(0) @binding(2) var<uniform> balls: array<Ball, MAX_BALLS>;
@group(0) @binding(3) var<uniform> tubes: array<Tube, MAX_TUBES>;
@group(0) @binding(4) var<uniform> lights: array<Light, MAX_LIGHTS>;
// CELLS_FINITE: table[k * face_count + f] = index of element k * T_f.
@group(0) @binding(5) var<storage, read> cell_table: array<u32>;
#ifdef MESHES
@group(0) @binding(6) var<storage, read> instances: array<Instance>;
#endif
// Per mesh: BVH nodes, vertices, triangles, texels (bvh.wgsl reads them).
@group(0) @binding(7) var<storage, read> mesh_data: array<vec4<u32>>;
// The compute entries' output.
@group(0) @binding(8) var<storage, read_write> pixels: array<Pixel>;
// FlatScene::groups (GpuObjects::groups in Rust): groups[f] is where face
// f's group starts in the balls, tubes and instances (x, y, z); the entry
// after the last face (at most 32) holds their counts. Objects before
// groups[0] carry no face mask (tubes: no edge bits) and are tested on
// every segment. w: the tubes' edge table (FaceGroups::edges) of face f.
// Read by cull.wgsl's each_candidate.
@group(0) @binding(9) var<uniform> groups: array<vec4<u32>, GROUPS>;
// FlatScene::ball_tree (GpuObjects::ball_nodes in Rust): the frame of
// the packed boxes, BallTree::origin and BallTree::step (bits, xyz), then
// params.ball_leaves leaves, one word each (BallTree::words): per axis
// the box's sides in 16-bit steps from the origin, low and high halves;
// then its first ball | its ball count << 16. ball_tree.wgsl's
// cache_leaves reads them.
@group(0) @binding(10) var<uniform> ball_nodes: array<vec4<u32>, MAX_BALL_LEAVES + 2u>;

// The params a walk reads at every segment or object, read once per
// invocation by cache_params: lavapipe reads a storage buffer one lane at
// a time, in a loop of its own, and does not hoist the same read out of
// the walk's loops. WGSL only: Rust reads its settings directly.
struct CachedParams {
    occupied: vec4<u32>,
    face_count: u32,
    flags: u32,
    levels: u32,
    max_distance: f32,
    fog_density: f32,
    near_reach: f32,
    tube_k: f32,
    ball_leaves: u32,
}
var<private> cached: CachedParams;

// Fills `cached` from params. Every entry point calls it (through
// trace_ray or ray_drift) before anything reads `cached`.
fn cache_params() {
    cached = CachedParams(params.occupied, params.face_count, params.flags, params.levels, params.max_distance, params.fog_density, params.near_reach, params.tube_k, params.ball_leaves);
#ifdef FACE_COUNT
    // In chunks of 16 with constant bounds, as step.wgsl's FACE_CHUNK.
    cache_planes(0u, min(face_count(), 16u));
    cache_planes(16u, min(face_count(), 32u));
    cache_planes(32u, min(face_count(), 48u));
    cache_planes(48u, min(face_count(), 64u));
    cache_planes(64u, min(face_count(), 80u));
    cache_planes(80u, min(face_count(), 96u));
    cache_planes(96u, min(face_count(), 112u));
    cache_planes(112u, min(face_count(), 128u));
#endif
}

#ifdef FACE_COUNT
// The face planes, copied once per invocation by cache_params, for the
// loops over every face (step.wgsl's exit_face and near_faces), which
// read them at constant indices. On lavapipe (Mesa 22.3) a plane read
// from the `faces` uniform, even at a constant index, cost several times
// its two dot products: padded to 52 planes, the 12-face domain's frame
// with nothing to hit grew by 15 ms when the 40 extra planes were copies
// of loaded ones and by 65-80 ms when each was loaded. A private array
// read at a constant index is a plain load: Seifert-Weber's 52-face
// domain traced in 122-132 ms before this copy and 54-59 after
// (docs/benchmarks/history.md, "Face planes copied once"). WGSL only: Rust reads
// FaceTables::planes.
var<private> planes: array<vec4<f32>, #{FACE_COUNT}u>;

// Faces lo to hi - 1 of `planes` from `faces`.
fn cache_planes(lo: u32, hi: u32) {
    for (var i = lo; i < hi; i++) {
        planes[i] = faces[i].plane;
    }
}
#endif

// Face i's plane: from `planes` under FACE_COUNT (i must then be a
// constant after unrolling, or the private array is read lane by lane),
// else from `faces`. Rust twin: FaceTables::planes[i].
fn face_plane(i: u32) -> vec4<f32> {
#ifdef FACE_COUNT
    return planes[i];
#else
    return faces[i].plane;
#endif
}

// Pixel::object of a domain edge (a tube). Rust twin: EDGE_ID in
// crates/bevy_manifold_core/src/trace/flat.rs.
const EDGE_ID: u32 = 0xfffffffdu;
// Params::flags bits. Rust twins: FLAG_NO_EARLY_STOP, FLAG_NO_RENORMALIZE,
// FLAG_NO_CULL in crates/bevy_manifold_gpu/src/layout.rs.
const FLAG_NO_EARLY_STOP: u32 = 1u;
const FLAG_NO_RENORMALIZE: u32 = 2u;
const FLAG_NO_CULL: u32 = 4u;
// No face: a ray that entered by none, or leaves by none (S3, no face
// within a quarter turn). Rust: None, or usize::MAX for Walker::entered.
const NO_FACE: u32 = 0xffffffffu;

// A tube that carries no vertex joint. Rust: None, or NO_JOINT in
// crates/bevy_manifold_gpu/src/layout.rs.
const NO_JOINT: u32 = 0xffffffffu;

// Params::instance_trees when no group of instances has a tree. Rust
// twin: NO_INSTANCE_TREES in crates/bevy_manifold_gpu/src/layout.rs.
const NO_INSTANCE_TREES: u32 = 0xffffffffu;

// The object id of a wall. Rust twin: rule::WALL_OBJECT.
const WALL_OBJECT: u32 = 0xfffffffeu;

// CELLS_TABLE: a cell beyond the table. Rust twin: cell_table::OUTSIDE.
const CELL_OUTSIDE: u32 = 0xffffffffu;
