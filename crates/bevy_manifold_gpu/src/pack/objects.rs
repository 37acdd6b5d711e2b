//! The scene's part of the GPU data ([`GpuObjects`]): balls, tubes,
//! lights, mesh instances and the meshes' data, the face groups and the
//! ball tree, packed from a [`FlatScene`] in `f32`.

use super::{bits, m, non_empty, v};
use crate::layout::{GpuBall, GpuInstance, GpuLight, GpuTube, NO_INSTANCE_TREES, NO_JOINT, NO_TEXTURE, pack_pbr};
use bevy_manifold_core::mesh::bvh::BvhNode;
use bevy_manifold_core::trace::FlatScene;
use bevy_manifold_core::trace::MAX_LIGHT_IMAGES;

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
    /// Where in `mesh_data` the instance trees' table starts
    /// (`FlatScene::instance_trees`, `shaders/instance_tree.wgsl` reads
    /// it): one word per face group of the instances (up to
    /// [`crate::bindings::GROUPS`]), `[nodes, node_count, 0, 0]`, the
    /// offset of the tree's eight orders of `node_count` nodes each (two
    /// words a node, as a mesh's, the order for octant `o` at
    /// `nodes + 2 o node_count`), `node_count` 0 for a group with no
    /// tree. [`crate::layout::NO_INSTANCE_TREES`] when no group has one.
    pub instance_trees: u32,
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

impl GpuObjects {
    /// Packs the objects of a prepared scene.
    #[must_use]
    pub fn pack(flat: &FlatScene<f32>) -> Self {
        let (instances, mut mesh_data) = pack_meshes(flat);
        let instance_trees = pack_instance_trees(flat, &mut mesh_data);
        GpuObjects {
            // At most MAX_BALLS, the uniform array's length (the runner
            // refuses a scene with more).
            balls: non_empty(
                flat.balls
                    .iter()
                    .take(crate::bindings::MAX_BALLS)
                    .map(|b| GpuBall {
                        center: v(b.center),
                        color: b.color,
                        k: b.k,
                        id: b.id,
                        face_mask: b.face_mask,
                        glow: b.glow,
                        pbr: pack_pbr(b.pbr),
                    })
                    .collect(),
            ),
            // At most MAX_TUBES, the uniform array's length, which a
            // convex domain's edges never pass.
            tubes: non_empty(
                flat.tubes
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
            // At most MAX_LIGHT_IMAGES, the uniform array's length
            // (light_images keeps to it already).
            lights: non_empty(
                flat.lights
                    .iter()
                    .take(MAX_LIGHT_IMAGES)
                    .map(|l| GpuLight {
                        position: v(l.position),
                        color: l.color,
                        intensity: l.intensity,
                        inv_range_sq: l.inv_range_sq,
                        min_area: l.min_area,
                        spot_scale: l.spot_scale,
                        spot_offset: l.spot_offset,
                        spot_dir: v(l.spot_dir),
                        radius: l.radius,
                        pad_a: 0.0,
                        pad_b: 0.0,
                        pad_c: 0.0,
                    })
                    .collect(),
            ),
            instances: non_empty(instances),
            mesh_data: non_empty(mesh_data),
            ball_nodes: pack_ball_tree(flat),
            instance_trees,
            counts: [
                flat.balls.len().min(crate::bindings::MAX_BALLS) as u32,
                flat.tubes.len().min(crate::bindings::MAX_TUBES) as u32,
                flat.lights.len().min(MAX_LIGHT_IMAGES) as u32,
                flat.instances.len() as u32,
            ],
            tube_k: flat.tube_k,
            near_reach: flat.near_reach,
            cone: [
                flat.near_distance,
                flat.cell_shadow,
                flat.faces.chart_stretch,
                flat.footprint_cap,
            ],
            groups: pack_groups(flat),
        }
    }
}

/// [`GpuObjects::ball_nodes`] of a prepared scene: the frame of the
/// packed boxes (`BallTree::origin`, then `BallTree::step`, as bits),
/// then one word a leaf (`BallTree::words`). None past the arrays'
/// capacities, or where the tree has no words.
fn pack_ball_tree(flat: &FlatScene<f32>) -> Vec<[u32; 4]> {
    let tree = &flat.ball_tree;
    if tree.is_empty()
        || tree.words.len() > crate::bindings::MAX_BALL_LEAVES
        || flat.balls.len() > crate::bindings::MAX_BALLS
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
fn pack_groups(flat: &FlatScene<f32>) -> [[u32; 4]; crate::bindings::GROUPS] {
    let g = &flat.groups;
    let counts = [
        flat.balls.len().min(crate::bindings::MAX_BALLS),
        flat.tubes.len(),
        flat.instances.len(),
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

/// Appends a mesh's hierarchy nodes as two words each: min and, for a
/// leaf, its first triangle, for an inner node its skip link
/// (`MeshData::skip`); max and `count` (`shaders/bvh.wgsl` reads them so).
fn push_nodes(data: &mut Vec<[u32; 4]>, nodes: &[BvhNode], skip: &[u32]) {
    for (n, &past) in nodes.iter().zip(skip) {
        data.push(bits(n.min, if n.count > 0 { n.first } else { past }));
        data.push(bits(n.max, n.count));
    }
}

/// Appends the instance trees' table and their nodes to `data`
/// ([`GpuObjects::instance_trees`]) and returns where the table starts,
/// or [`NO_INSTANCE_TREES`] when no group has a tree.
fn pack_instance_trees(flat: &FlatScene<f32>, data: &mut Vec<[u32; 4]>) -> u32 {
    let trees = &flat.instance_trees[..flat.instance_trees.len().min(crate::bindings::GROUPS)];
    if trees.iter().all(|t| t.is_empty()) {
        return NO_INSTANCE_TREES;
    }
    let table = data.len();
    data.resize(table + trees.len(), [0; 4]);
    for (g, tree) in trees.iter().enumerate() {
        let Some(count) = tree.orders.first().map(|o| o.nodes.len() as u32) else {
            continue;
        };
        data[table + g] = [data.len() as u32, count, 0, 0];
        for order in &tree.orders {
            push_nodes(data, &order.nodes, &order.skip);
        }
    }
    table as u32
}

/// Packs the prepared meshes into mesh data words and the instances that
/// point into it.
fn pack_meshes(flat: &FlatScene<f32>) -> (Vec<GpuInstance>, Vec<[u32; 4]>) {
    let mut data: Vec<[u32; 4]> = Vec::new();
    // Per mesh: offsets of nodes, vertices, triangles, and the node count.
    let mut offsets = Vec::new();
    for m in &flat.meshes {
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
    for t in &flat.textures {
        texels.push(data.len() as u32);
        data.push([t.width, t.height, 0, 0]);
        data.extend(t.texels.chunks(4).map(|c| {
            let mut w = [0u32; 4];
            w[..c.len()].copy_from_slice(c);
            w
        }));
    }
    let instances = flat
        .instances
        .iter()
        .map(|inst| {
            let [nodes, vertices, triangles, node_count] = offsets[inst.mesh];
            let slot = |t: Option<usize>| t.map_or(NO_TEXTURE, |t| texels[t]);
            let maps = &inst.textures;
            GpuInstance {
                to_local: m(inst.to_local),
                center: v(inst.center),
                color: inst.color,
                k: inst.k,
                nodes,
                vertices,
                triangles,
                id: inst.id,
                textures: [
                    slot(maps.base),
                    slot(maps.metallic_roughness),
                    slot(maps.emissive),
                    slot(maps.normal),
                ],
                node_count,
                attached: u32::from(inst.home.is_some()),
                face_mask: inst.face_mask,
                alpha_cutoff: inst.alpha_mask.map_or(-1.0, |(c, _)| c),
                emissive: inst.emissive,
                metallic: inst.pbr.map_or(-1.0, |p| p.metallic),
                roughness: inst.pbr.map_or(0.0, |p| p.roughness),
                alpha: inst.alpha_mask.map_or(1.0, |(_, a)| a),
                pad: [0; 2],
                home: inst.home.map_or([0.0; 4], v),
            }
        })
        .collect();
    (instances, data)
}
