//! The tracer's GPU data: `#[repr(C)]` twins of the structs in
//! `shaders/bindings.wgsl` (held to them by `tests/contract.rs`), packed from the same [`FlatScene`] scene the CPU
//! tracer reads (in f32), so both trace identical inputs.

use bevy_manifold_core::mesh::bvh::BvhNode;
use bevy_manifold_core::space::Space;
use bevy_manifold_core::space::ball::OUTSIDE;
use bevy_manifold_core::space::cells::{CellId, CellScheme};
use bevy_manifold_core::space::element::CellElement;
use bevy_manifold_core::trace::{FlatScene, TraceSettings, pixel_half_angle_of};
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec4};

/// WGSL twin: `Params` in `shaders/bindings.wgsl`.
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct GpuParams {
    /// Camera isometry (wrapped into the domain).
    pub camera: [f32; 16],
    /// The camera's cell element.
    pub camera_cell: [f32; 16],
    /// Fog colour (rgb, 1).
    pub fog_color: [f32; 4],
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Most transports per ray.
    pub levels: u32,
    /// Number of faces.
    pub face_count: u32,
    /// Number of balls.
    pub ball_count: u32,
    /// Number of tubes.
    pub tube_count: u32,
    /// Number of lights.
    pub light_count: u32,
    /// The camera's index in the Cayley table (finite groups).
    pub camera_cell_index: u32,
    /// `tan(fov_y / 2)`.
    pub tan_half_fov: f32,
    /// Rays stop after this distance.
    pub max_distance: f32,
    /// Fog density (0 without fog).
    pub fog_density: f32,
    /// `k` of the edge tubes.
    pub tube_k: f32,
    /// The render pass: the viewport's left pixel column in the target.
    pub origin_x: u32,
    /// The render pass: the viewport's top pixel row in the target.
    pub origin_y: u32,
    /// The camera's near plane, for reverse-z depth.
    pub near: f32,
    /// [`FLAG_NO_EARLY_STOP`] | [`FLAG_NO_RENORMALIZE`]: measurement
    /// switches, 0 for normal tracing.
    pub flags: u32,
    /// Lattice: 1 / box edges; hashed: 1 / grid step in x, the f32 horizon
    /// in y.
    pub cell_scale: [f32; 4],
    /// Number of mesh instances.
    pub instance_count: u32,
    /// Per-cell shading, the three words of
    /// [`bevy_manifold_core::space::cells::CellTint::words`]: the mode
    /// (0 by cell, 1 highlight, 2 on/off pattern)...
    pub cell_mode: u32,
    /// ... the highlighted cell's low word, or the pattern's threshold...
    pub cell_a: u32,
    /// ... and the highlighted cell's high word.
    pub cell_b: u32,
    /// Per-cell rules, the four words of
    /// [`bevy_manifold_core::space::rule::CellRule::words`]: the on
    /// threshold...
    pub rule_hidden: u32,
    /// ... its seed...
    pub rule_hidden_seed: u32,
    /// ... the wall threshold...
    pub rule_walls: u32,
    /// ... and its seed.
    pub rule_walls_seed: u32,
    /// [`bevy_manifold_core::trace::Projection::words`]: 0 perspective,
    /// 1 equirectangular, 2 omni-directional stereo...
    pub projection: u32,
    /// ... and, for stereo, half the eye separation.
    pub eye_offset: f32,
    /// `FaceTables::near_scale` times `FlatScene::near_reach`: the bound
    /// of `near_faces`' test.
    pub near_reach: f32,
    /// Padding.
    pub pad_a: u32,
    /// How many leaves [`GpuObjects::ball_nodes`] holds (0: no tree).
    pub ball_leaves: u32,
    /// Cone tracing: `FaceTables::chart_stretch`...
    pub chart_stretch: f32,
    /// ... and `FlatScene::footprint_cap`.
    pub footprint_cap: f32,
    /// Padding to 16 bytes.
    pub pad_b: u32,
    /// An off-centre frustum, `[half width, half height, centre x, centre
    /// y]` in slopes ([`bevy_manifold_core::trace::Frustum`]); all zero
    /// for the symmetric frustum of `tan_half_fov` and the image's aspect.
    pub frustum: [f32; 4],
    /// Cone tracing (`FOOTPRINT`): the pixels' half-angle
    /// ([`GpuView::footprint`]), `FlatScene::near_distance`,
    /// `FaceTables::near_scale`, `FlatScene::cell_shadow`.
    pub cone: [f32; 4],
    /// The faces whose group holds any ball, tube, mesh instance (x, y,
    /// z; bit `f` for face `f` below 32, from [`GpuObjects::groups`]):
    /// the WGSL walks only these of a segment's near faces, so that empty
    /// groups cost no reads (WGSL only; the CPU's empty ranges cost
    /// nothing).
    pub occupied: [u32; 4],
}

/// WGSL twin: `Face` in `shaders/bindings.wgsl`.
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct GpuFace {
    /// Plane.
    pub plane: [f32; 4],
    /// `T_i`.
    pub pairing: [f32; 16],
    /// `T_i^-1`.
    pub crossing: [f32; 16],
    /// Partner face.
    pub partner: u32,
    /// Padding to 16 bytes, one word a field: the faces are a uniform
    /// array, where an array member would need a 16-byte stride.
    pub pad_a: u32,
    /// Padding.
    pub pad_b: u32,
    /// Padding.
    pub pad_c: u32,
}

/// WGSL twin: `Ball` in `shaders/bindings.wgsl`.
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct GpuBall {
    /// Centre.
    pub center: [f32; 4],
    /// Albedo.
    pub color: [f32; 3],
    /// `cosh r`, `cos r` or `r^2`.
    pub k: f32,
    /// Object id.
    pub id: u32,
    /// `FlatBall::face_mask`.
    pub face_mask: u32,
    /// `FlatBall::glow`.
    pub glow: f32,
    /// Padding to 16 bytes (one word: the balls are a uniform array).
    pub pad: u32,
}

/// WGSL twin: `Tube` in `shaders/bindings.wgsl`.
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct GpuTube {
    /// Start point.
    pub a: [f32; 4],
    /// Unit tangent at `a` towards `b`.
    pub e: [f32; 4],
    /// End point.
    pub b: [f32; 4],
    /// Unit tangent at `b`, away from `a`.
    pub e_b: [f32; 4],
    /// Albedo.
    pub color: [f32; 3],
    /// `FlatTube::face_mask`.
    pub face_mask: u32,
    /// `FlatTube::joint`: the index of the vertex joint tested after this
    /// tube, or [`NO_JOINT`].
    pub joint: u32,
    /// Padding to 16 bytes.
    pub pad_a: u32,
    /// Padding.
    pub pad_b: u32,
    /// Padding.
    pub pad_c: u32,
}

/// WGSL twin: `Instance` in `shaders/bindings.wgsl`: one placement of a mesh, with offsets into
/// [`GpuObjects::mesh_data`].
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct GpuInstance {
    /// From the domain's chart to the mesh's coordinates.
    pub to_local: [f32; 16],
    /// Bounding ball centre.
    pub center: [f32; 4],
    /// Base colour.
    pub color: [f32; 3],
    /// Bounding ball `k`.
    pub k: f32,
    /// Offset of the mesh's BVH nodes (two words each).
    pub nodes: u32,
    /// Offset of its vertices (two words each).
    pub vertices: u32,
    /// Offset of its triangles (one word each).
    pub triangles: u32,
    /// Object id.
    pub id: u32,
    /// Offset of its texture's texels (four per word).
    pub texture: u32,
    /// Texture width, 0 without a texture.
    pub tex_width: u32,
    /// Texture height.
    pub tex_height: u32,
    /// Number of BVH nodes (bounds the traversal loop).
    pub node_count: u32,
    /// 1 for a copy of a mesh attached to the camera (see `home`).
    pub attached: u32,
    /// `FlatInstance::face_mask`.
    pub face_mask: u32,
    /// Padding to 16 bytes.
    pub pad: [u32; 2],
    /// With `attached`: the cell point `g o` from which this copy is the
    /// camera's own body (`FlatInstance::home`).
    pub home: [f32; 4],
}

/// WGSL twin: `Light` in `shaders/bindings.wgsl`.
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct GpuLight {
    /// Position.
    pub position: [f32; 4],
    /// Colour.
    pub color: [f32; 3],
    /// Power.
    pub intensity: f32,
}

/// WGSL twin: `Pixel` in `shaders/bindings.wgsl`.
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct GpuPixel {
    /// Colour, and the distance in `w`.
    pub color: [f32; 4],
    /// Object id.
    pub object: u32,
    /// Levels used.
    pub levels: u32,
    /// Cell id, low word.
    pub cell_lo: u32,
    /// Cell id, high word.
    pub cell_hi: u32,
}

/// The space's part of the GPU data: faces and the cell table. Uploaded
/// when the space changes.
#[derive(Clone, Debug, PartialEq)]
pub struct GpuSpace {
    /// Faces.
    pub faces: Vec<GpuFace>,
    /// Cayley table, `[k * faces + f]` (at least one element: empty storage
    /// buffers are not allowed).
    pub cell_table: Vec<u32>,
    /// [`GpuParams::cell_scale`].
    pub cell_scale: [f32; 4],
    /// `FaceTables::near_scale`.
    pub near_scale: f32,
}

/// The scene's objects on the GPU: balls (ghost copies and the edge tubes'
/// vertex joints included), tubes and lights. Uploaded when an object
/// changes, not when the camera moves.
#[derive(Clone, Debug, PartialEq)]
pub struct GpuObjects {
    /// Balls (at least one element: empty storage buffers are not allowed).
    pub balls: Vec<GpuBall>,
    /// Tubes (likewise).
    pub tubes: Vec<GpuTube>,
    /// Lights (likewise).
    pub lights: Vec<GpuLight>,
    /// Mesh instances, ghosts included (at least one element).
    pub instances: Vec<GpuInstance>,
    /// The meshes' BVH nodes, vertices, triangles and texels, as words
    /// of four `u32` (floats by their bits; at least one word).
    pub mesh_data: Vec<[u32; 4]>,
    /// The frame of `FlatScene::ball_tree`'s packed boxes, two words, then
    /// its leaves, one word each (`BallTree::words`; the `ball_nodes`
    /// uniform array: see `shaders/bindings.wgsl`); empty
    /// when there is no tree or the scene has more than
    /// [`crate::bindings::MAX_BALLS`] balls (the GPU then tests every
    /// ball with no face mask).
    pub ball_nodes: Vec<[u32; 4]>,
    /// How many of each are real: balls, tubes, lights, instances.
    pub counts: [u32; 4],
    /// `k` of the edge tubes.
    pub tube_k: f32,
    /// `FlatScene::near_reach`.
    pub near_reach: f32,
    /// `FlatScene::near_distance`, `FlatScene::cell_shadow`,
    /// `FaceTables::chart_stretch` and `FlatScene::footprint_cap`: what
    /// cone tracing grows objects with.
    pub cone: [f32; 4],
    /// `FlatScene::groups`, the `groups` uniform array
    /// ([`crate::bindings::BINDINGS`]): entry `f` holds where face `f`'s
    /// group starts in the balls, tubes and instances (x, y, z) and the
    /// tubes' edge table of face `f` (w, `FaceGroups::edges`); the entry
    /// after the last face (at most 32) holds their counts, as do the
    /// ones after it.
    pub groups: [[u32; 4]; crate::bindings::GROUPS],
}

/// The per-frame view: where the camera is and what the frame looks like.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GpuView {
    /// The camera isometry, inside the domain.
    pub camera: Mat4,
    /// The camera's cell element (f64: its id is computed from it).
    pub camera_cell: glam::DMat4,
    /// `tan(fov_y / 2)`.
    pub tan_half_fov: f32,
    /// An off-centre frustum in place of `tan_half_fov` ([`GpuParams::frustum`]).
    pub frustum: Option<[f32; 4]>,
    /// Fog density and colour, when on.
    pub fog: Option<(f32, [f32; 3])>,
    /// Image (viewport) size in pixels.
    pub size: [u32; 2],
    /// The viewport's top-left pixel in its target.
    pub origin: [u32; 2],
    /// The near plane, for depth.
    pub near: f32,
    /// Most transports per ray.
    pub levels: u32,
    /// Rays stop after this distance.
    pub max_distance: f32,
    /// [`GpuParams::flags`].
    pub flags: u32,
    /// [`GpuParams::cell_mode`], `cell_a`, `cell_b`.
    pub cell_tint: [u32; 3],
    /// [`bevy_manifold_core::space::rule::CellRule::words`].
    pub cell_rule: [u32; 4],
    /// [`bevy_manifold_core::trace::Projection::words`].
    pub projection: (u32, f32),
    /// Cone tracing: the half-angle of a pixel's cone
    /// (`bevy_manifold_core::trace::pixel_half_angle`), read under the
    /// `FOOTPRINT` def; 0 for rays.
    pub footprint: f32,
}

/// [`GpuParams::flags`]: fog does not stop rays early
/// (`TraceSettings::fog_early_stop` off).
pub const FLAG_NO_EARLY_STOP: u32 = 1;
/// [`GpuParams::flags`]: no renormalisation (`TraceSettings::renormalize`
/// off).
pub const FLAG_NO_RENORMALIZE: u32 = 2;
/// [`GpuParams::flags`]: every object tested on every segment
/// (`TraceSettings::cull` off).
pub const FLAG_NO_CULL: u32 = 4;

/// [`GpuTube::joint`] of a tube that carries no vertex joint (or one past
/// the balls packed). WGSL twin: `NO_JOINT` in `shaders/bindings.wgsl`.
pub const NO_JOINT: u32 = u32::MAX;

/// The flags that say how `settings` differs from normal tracing.
#[must_use]
pub fn settings_flags(settings: &TraceSettings) -> u32 {
    let mut flags = 0;
    if !settings.fog_early_stop {
        flags |= FLAG_NO_EARLY_STOP;
    }
    if !settings.renormalize {
        flags |= FLAG_NO_RENORMALIZE;
    }
    if !settings.cull {
        flags |= FLAG_NO_CULL;
    }
    flags
}

/// Everything one trace uploads.
#[derive(Clone, Debug)]
pub struct GpuScene {
    /// The uniform.
    pub params: GpuParams,
    /// The space's faces and cell table.
    pub space: GpuSpace,
    /// Balls, tubes, lights.
    pub objects: GpuObjects,
}

fn m(m: Mat4) -> [f32; 16] {
    m.to_cols_array()
}

fn v(v: Vec4) -> [f32; 4] {
    v.to_array()
}

fn non_empty<T: Zeroable>(mut x: Vec<T>) -> Vec<T> {
    if x.is_empty() {
        x.push(T::zeroed());
    }
    x
}

impl GpuSpace {
    /// Packs a space's faces (in f32) and its cell scheme.
    #[must_use]
    pub fn pack(space: &Space) -> Self {
        let t = bevy_manifold_core::trace::FaceTables::<f32>::new(space);
        let faces = (0..t.planes.len())
            .map(|i| GpuFace {
                plane: v(t.planes[i]),
                pairing: m(t.pairings[i]),
                crossing: m(t.crossings[i]),
                partner: t.partners[i] as u32,
                pad_a: 0,
                pad_b: 0,
                pad_c: 0,
            })
            .collect();
        let (cell_scale, cell_table) = match space.cells() {
            CellScheme::Lattice { inverse_basis } => (
                [
                    inverse_basis.x_axis.x as f32,
                    inverse_basis.y_axis.y as f32,
                    inverse_basis.z_axis.z as f32,
                    0.0,
                ],
                Vec::new(),
            ),
            CellScheme::Finite { table, .. } => ([0.0; 4], table.iter().flatten().copied().collect()),
            // The neighbours, then each cell's id as (lo, hi) from
            // cell_scale.x's bits on; centred on the origin copy until
            // GpuSpace::centre_on moves it. Before the table is grown
            // (the render pass grows it on a task), one cell: the camera's.
            CellScheme::Exact(exact) => match exact.grown_ball() {
                Some(ball) => {
                    let offset = ball.neighbours.len() as u32;
                    let mut table = ball.neighbours.clone();
                    table.extend(
                        ball.ids_around(&exact.group, &exact.group.identity())
                            .iter()
                            .flat_map(|id| id_words(*id)),
                    );
                    ([f32::from_bits(offset), 0.0, 0.0, 0.0], table)
                }
                None => {
                    let faces = space.faces().len();
                    let mut table = vec![OUTSIDE; faces];
                    table.extend([0, 0]);
                    ([f32::from_bits(faces as u32), 0.0, 0.0, 0.0], table)
                }
            },
            CellScheme::Hashed { quantum } => (
                [
                    (1.0 / quantum) as f32,
                    bevy_manifold_core::space::cells::HASHED_HORIZON_F32 as f32,
                    0.0,
                    0.0,
                ],
                Vec::new(),
            ),
        };
        GpuSpace {
            faces,
            cell_table: non_empty(cell_table),
            cell_scale,
            near_scale: t.near_scale,
        }
    }
}

impl GpuSpace {
    /// For `CELLS_TABLE`: true while the table is the one cell of a space
    /// whose table of cells is still being grown.
    #[must_use]
    pub fn table_pending(&self, space: &Space) -> bool {
        matches!(space.cells(), CellScheme::Exact(_))
            && self.cell_table.len() == space.faces().len() + 2
            && self.cell_scale[0].to_bits() as usize == space.faces().len()
    }

    /// For `CELLS_TABLE`: the table's ids for a camera in `camera` (cell
    /// `k` becomes `camera e_k`); nothing for other schemes. One exact
    /// product per cell (10 ms for Seifert-Weber's 16,129 cells).
    pub fn centre_on(&mut self, space: &Space, camera: &CellElement) {
        let (CellScheme::Exact(exact), CellElement::Exact(centre)) = (space.cells(), camera) else {
            return;
        };
        let offset = self.cell_scale[0].to_bits() as usize;
        let ids = match exact.grown_ball() {
            // The table grown when packed.
            Some(ball) if self.cell_table.len() == offset + 2 * ball.len() => ball.ids_around(&exact.group, centre),
            // The one-cell table of a space whose table is still growing.
            _ => vec![centre.cell_id()],
        };
        for (k, id) in ids.iter().enumerate() {
            let [lo, hi] = id_words(*id);
            self.cell_table[offset + 2 * k] = lo;
            self.cell_table[offset + 2 * k + 1] = hi;
        }
    }
}

impl GpuSpace {
    /// For `CELLS_TABLE`: the index of the cell with id `id` in the table,
    /// if it is there (a scan of the ids, 20-60 us).
    #[must_use]
    pub fn index_of(&self, id: CellId) -> Option<u32> {
        let offset = self.cell_scale[0].to_bits() as usize;
        let [lo, hi] = id_words(id);
        self.cell_table
            .get(offset..)?
            .chunks_exact(2)
            .position(|w| w[0] == lo && w[1] == hi)
            .map(|k| k as u32)
    }
}

/// A cell id as the two words the shader reads.
fn id_words(id: CellId) -> [u32; 2] {
    [id.0 as u32, (id.0 >> 32) as u32]
}

impl GpuObjects {
    /// Packs the objects of a prepared scene.
    #[must_use]
    pub fn pack(prep: &FlatScene<f32>) -> Self {
        let (instances, mesh_data) = pack_meshes(prep);
        GpuObjects {
            // At most MAX_BALLS, the uniform array's length (the runner
            // refuses a scene with more).
            balls: non_empty(
                prep.balls
                    .iter()
                    .take(crate::bindings::MAX_BALLS)
                    .map(|b| GpuBall {
                        center: v(b.center),
                        color: b.color,
                        k: b.k,
                        id: b.id,
                        face_mask: b.face_mask,
                        glow: b.glow,
                        pad: 0,
                    })
                    .collect(),
            ),
            // At most MAX_TUBES, the uniform array's length, which a
            // convex domain's edges never pass.
            tubes: non_empty(
                prep.tubes
                    .iter()
                    .take(crate::bindings::MAX_TUBES)
                    .map(|tb| GpuTube {
                        a: v(tb.segment.a),
                        e: v(tb.segment.e),
                        b: v(tb.segment.b),
                        e_b: v(tb.segment.e_b),
                        color: tb.color,
                        face_mask: tb.face_mask,
                        joint: tb
                            .joint
                            .filter(|&j| j < crate::bindings::MAX_BALLS)
                            .map_or(NO_JOINT, |j| j as u32),
                        pad_a: 0,
                        pad_b: 0,
                        pad_c: 0,
                    })
                    .collect(),
            ),
            // At most MAX_LIGHTS, the uniform array's length (the ECS
            // layer and scene files keep to it already).
            lights: non_empty(
                prep.lights
                    .iter()
                    .take(bevy_manifold_core::trace::MAX_LIGHTS)
                    .map(|l| GpuLight {
                        position: v(l.position),
                        color: l.color,
                        intensity: l.intensity,
                    })
                    .collect(),
            ),
            instances: non_empty(instances),
            mesh_data: non_empty(mesh_data),
            ball_nodes: pack_ball_tree(prep),
            counts: [
                prep.balls.len().min(crate::bindings::MAX_BALLS) as u32,
                prep.tubes.len().min(crate::bindings::MAX_TUBES) as u32,
                prep.lights.len().min(bevy_manifold_core::trace::MAX_LIGHTS) as u32,
                prep.instances.len() as u32,
            ],
            tube_k: prep.tube_k,
            near_reach: prep.near_reach,
            cone: [
                prep.near_distance,
                prep.cell_shadow,
                prep.faces.chart_stretch,
                prep.footprint_cap,
            ],
            groups: pack_groups(prep),
        }
    }
}

/// [`GpuObjects::ball_nodes`] of a prepared scene: the frame of the
/// packed boxes (`BallTree::origin`, then `BallTree::step`, as bits),
/// then one word a leaf (`BallTree::words`). None past the arrays'
/// capacities, or where the tree has no words.
fn pack_ball_tree(prep: &FlatScene<f32>) -> Vec<[u32; 4]> {
    let tree = &prep.ball_tree;
    if tree.is_empty()
        || tree.words.len() > crate::bindings::MAX_BALL_LEAVES
        || prep.balls.len() > crate::bindings::MAX_BALLS
    {
        return Vec::new();
    }
    [bits(tree.origin, 0), bits(tree.step, 0)]
        .into_iter()
        .chain(tree.words.iter().copied())
        .collect()
}

/// [`GpuObjects::groups`] of a prepared scene (the balls' starts clamped
/// to the balls packed).
fn pack_groups(prep: &FlatScene<f32>) -> [[u32; 4]; crate::bindings::GROUPS] {
    let g = &prep.groups;
    let counts = [
        prep.balls.len().min(crate::bindings::MAX_BALLS),
        prep.tubes.len(),
        prep.instances.len(),
    ]
    .map(|n| n as u32);
    // Past the last face, the last start (the balls' is not their count
    // when tubes carry joints, FlatTube::joint).
    let at = |starts: &[u32], f: usize, count: u32| starts.get(f).or(starts.last()).copied().unwrap_or(0).min(count);
    core::array::from_fn(|f| {
        [
            at(&g.balls, f, counts[0]),
            at(&g.tubes, f, counts[1]),
            at(&g.instances, f, counts[2]),
            g.edges.get(f).copied().unwrap_or(0),
        ]
    })
}

/// Per kind (balls, tubes, instances), the faces below 32 whose group in
/// `groups` is not empty, as bits (`GpuParams::occupied`).
fn occupied(groups: &[[u32; 4]; crate::bindings::GROUPS]) -> [u32; 4] {
    let mut out = [0; 4];
    for f in 0..32 {
        for (k, word) in out.iter_mut().take(3).enumerate() {
            if groups[f + 1][k] > groups[f][k] {
                *word |= 1 << f;
            }
        }
    }
    out
}

fn bits(v: [f32; 3], w: u32) -> [u32; 4] {
    [v[0].to_bits(), v[1].to_bits(), v[2].to_bits(), w]
}

/// Appends a mesh's hierarchy nodes as two words each: min and, for a
/// leaf, its first triangle, for an inner node its skip link
/// (`MeshData::skip`); max and `count` (`shaders/bvh.wgsl` reads them so).
fn push_nodes(data: &mut Vec<[u32; 4]>, nodes: &[BvhNode], skip: &[u32]) {
    for (n, &past) in nodes.iter().zip(skip) {
        data.push(bits(n.min, if n.count > 0 { n.first } else { past }));
        data.push(bits(n.max, n.count));
    }
}

/// Packs the prepared meshes into mesh data words and the instances that
/// point into it.
fn pack_meshes(prep: &FlatScene<f32>) -> (Vec<GpuInstance>, Vec<[u32; 4]>) {
    let mut data: Vec<[u32; 4]> = Vec::new();
    // Per mesh: offsets of nodes, vertices, triangles, and the node count.
    let mut offsets = Vec::new();
    for m in &prep.meshes {
        let nodes = data.len() as u32;
        push_nodes(&mut data, &m.nodes, &m.skip);
        let vertices = data.len() as u32;
        let mesh = &m.mesh;
        for i in 0..mesh.positions.len() {
            data.push(bits(mesh.positions[i], mesh.uvs[i][0].to_bits()));
            data.push(bits(mesh.normals[i], mesh.uvs[i][1].to_bits()));
        }
        let triangles = data.len() as u32;
        data.extend(mesh.triangles.iter().map(|t| [t[0], t[1], t[2], 0]));
        offsets.push([nodes, vertices, triangles, m.nodes.len() as u32]);
    }
    let mut texels = Vec::new();
    for t in &prep.textures {
        texels.push(data.len() as u32);
        data.extend(t.texels.chunks(4).map(|c| {
            let mut w = [0u32; 4];
            w[..c.len()].copy_from_slice(c);
            w
        }));
    }
    let instances = prep
        .instances
        .iter()
        .map(|inst| {
            let [nodes, vertices, triangles, node_count] = offsets[inst.mesh];
            let (texture, tex_width, tex_height) = inst.texture.map_or((0, 0, 0), |t| {
                let tex = &prep.textures[t];
                (texels[t], tex.width, tex.height)
            });
            GpuInstance {
                to_local: m(inst.to_local),
                center: v(inst.center),
                color: inst.color,
                k: inst.k,
                nodes,
                vertices,
                triangles,
                id: inst.id,
                texture,
                tex_width,
                tex_height,
                node_count,
                attached: u32::from(inst.home.is_some()),
                face_mask: inst.face_mask,
                pad: [0; 2],
                home: inst.home.map_or([0.0; 4], v),
            }
        })
        .collect();
    (instances, data)
}

impl GpuParams {
    /// The uniform for one view of `objects` in `space`.
    #[must_use]
    pub fn new(space: &Space, packed: &GpuSpace, objects: &GpuObjects, view: &GpuView) -> Self {
        let (fog_density, fog_color) = view.fog.unwrap_or((0.0, [0.0; 3]));
        GpuParams {
            camera: m(view.camera),
            camera_cell: m(view.camera_cell.as_mat4()),
            fog_color: [fog_color[0], fog_color[1], fog_color[2], 1.0],
            width: view.size[0],
            height: view.size[1],
            levels: view.levels,
            face_count: packed.faces.len() as u32,
            ball_count: objects.counts[0],
            tube_count: objects.counts[1],
            light_count: objects.counts[2],
            camera_cell_index: match space.cells() {
                CellScheme::Finite { .. } => space.cell_id(&view.camera_cell).0 as u32,
                _ => 0,
            },
            tan_half_fov: view.tan_half_fov,
            max_distance: view.max_distance,
            fog_density,
            tube_k: objects.tube_k,
            origin_x: view.origin[0],
            origin_y: view.origin[1],
            near: view.near,
            flags: view.flags,
            cell_scale: packed.cell_scale,
            instance_count: objects.counts[3],
            cell_mode: view.cell_tint[0],
            cell_a: view.cell_tint[1],
            cell_b: view.cell_tint[2],
            rule_hidden: view.cell_rule[0],
            rule_hidden_seed: view.cell_rule[1],
            rule_walls: view.cell_rule[2],
            rule_walls_seed: view.cell_rule[3],
            projection: view.projection.0,
            eye_offset: view.projection.1,
            near_reach: packed.near_scale * objects.near_reach,
            pad_a: 0,
            ball_leaves: objects.ball_nodes.len().saturating_sub(2) as u32,
            chart_stretch: objects.cone[2],
            footprint_cap: objects.cone[3],
            pad_b: 0,
            frustum: view.frustum.unwrap_or([0.0; 4]),
            cone: [view.footprint, objects.cone[0], packed.near_scale, objects.cone[1]],
            occupied: occupied(&objects.groups),
        }
    }
}

impl GpuScene {
    /// Packs a prepared scene for the GPU.
    #[must_use]
    pub fn pack(space: &Space, prep: &FlatScene<f32>, settings: &TraceSettings) -> Self {
        Self::pack_in(space, Self::pack_space(space, prep), prep, settings)
    }

    /// The space's part of [`GpuScene::pack`]: its faces and its table of
    /// cells (grown here if it is not yet), centred on the camera's cell.
    #[must_use]
    pub fn pack_space(space: &Space, prep: &FlatScene<f32>) -> GpuSpace {
        // Headless: the whole table, grown here if it is not yet.
        if let CellScheme::Exact(exact) = space.cells() {
            exact.ball();
        }
        let mut packed = GpuSpace::pack(space);
        packed.centre_on(space, &prep.camera_element);
        packed
    }

    /// [`GpuScene::pack`] with the space already packed ([`GpuScene::pack_space`]
    /// for this space and camera cell, or kept from an earlier frame).
    #[must_use]
    pub fn pack_in(space: &Space, packed: GpuSpace, prep: &FlatScene<f32>, settings: &TraceSettings) -> Self {
        let objects = GpuObjects::pack(prep);
        let view = GpuView {
            camera: prep.camera,
            camera_cell: prep.camera_cell,
            tan_half_fov: prep.tan_half_fov,
            frustum: prep.frustum,
            fog: prep.fog,
            size: [settings.width, settings.height],
            origin: [0, 0],
            near: 0.1,
            levels: settings.levels,
            max_distance: settings.max_distance as f32,
            flags: settings_flags(settings),
            cell_tint: settings.cell_tint.words(),
            cell_rule: settings.cell_rule.words(),
            projection: settings.projection.words(),
            footprint: if settings.footprint {
                pixel_half_angle_of(prep, settings) as f32
            } else {
                0.0
            },
        };
        GpuScene {
            params: GpuParams::new(space, &packed, &objects, &view),
            space: packed,
            objects,
        }
    }
}
