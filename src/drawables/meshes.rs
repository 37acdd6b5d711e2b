//! Bevy meshes in a manifold (feature `render`): an entity under a
//! [`ManifoldSpace`] with a [`Placement`] is drawn by the tracer with its
//! `Mesh3d` and every `Mesh3d` below it that has no placement of its own
//! (as a glTF scene spawns them), in its local chart, scaled by
//! its `Transform`'s scale (each axis by its own). Base colour and base-colour texture come from
//! `StandardMaterial` (feature `standard_material`).
//!
//! Traced meshes are taken off Bevy's rasteriser (`RenderLayers::none()`),
//! unless they carry [`Rasterized`]: then they are ordinary Bevy meshes (a
//! map, an overlay) and the tracer leaves them alone. A BVH is built once
//! per mesh asset and rebuilt only when the asset changes; moving an
//! instance only changes its matrix. A mesh that cannot be traced (not
//! triangles, NaN positions) is reported once and left out; the rest of
//! the scene still renders.
//!
//! A whole glTF scene works as a Bevy user expects: put
//! `WorldAssetRoot(assets.load("models/suzanne.glb#Scene0"))` on a placed
//! entity and every mesh the scene spawns below it is traced. (Bevy spawns
//! scenes through reflection: the app needs Bevy's `reflect_auto_register`
//! feature so every component a scene holds is known, as the explorer
//! and the examples turn on.)
//! A single mesh can be loaded by label, as below.
//!
//! ```no_run
//! use bevy::prelude::*;
//! use bevy_manifold::prelude::*;
//!
//! fn setup(mut commands: Commands, assets: Res<AssetServer>) {
//!     let space = catalog::poincare();
//!     let root = commands.spawn(ManifoldSpace::new(space.clone())).id();
//!     commands.spawn((ChildOf(root), ManifoldCamera::default(), Placement::at(&space, glam::DVec3::Z * 0.2)));
//!     // Suzanne, traced in every copy of the domain.
//!     commands.spawn((
//!         ChildOf(root),
//!         Mesh3d(assets.load("models/suzanne.glb#Mesh0/Primitive0")),
//!         Placement::default(),
//!         Transform::from_scale(Vec3::splat(0.05)),
//!     ));
//! }
//! ```

use super::components::ManifoldMeshes;
use crate::mesh::{MeshData, MeshMaterial, Texture, TriMesh};
use crate::placement::{InSpace, ManifoldSpace, Placement};
use crate::trace::SceneMesh;
use bevy::asset::AssetEvent;
use bevy::camera::visibility::RenderLayers;
use bevy::mesh::morph::{MeshMorphWeights, MorphWeights};
use bevy::mesh::skinning::{SkinnedMesh, SkinnedMeshInverseBindposes};
use bevy::mesh::{Indices, Mesh, Mesh3d, PrimitiveTopology, VertexAttributeValues};
use bevy::platform::collections::{HashMap, HashSet};
use bevy::prelude::*;
use std::sync::Arc;

/// Marks a `Mesh3d` under a manifold root as an ordinary Bevy mesh: drawn
/// by the rasteriser as usual, not by the tracer.
#[derive(Component, Clone, Copy, Debug, Default, Reflect)]
#[reflect(Component, Debug, Default)]
pub struct Rasterized;

/// Marks a traced mesh (or a placed entity, for every mesh below it) as
/// the viewer's own body, as the paper attaches Suzanne to the camera: its
/// home copy is not drawn (the camera sits inside it), every other copy is,
/// so the viewer sees its own images around the space. Put the mesh under
/// the [`crate::camera::ManifoldCamera`]'s entity, without a
/// placement of its own, and it moves with the camera.
///
/// ```no_run
/// use bevy::prelude::*;
/// use bevy_manifold::prelude::*;
///
/// fn setup(mut commands: Commands, assets: Res<AssetServer>) {
///     let space = catalog::torus(1.0);
///     let root = commands.spawn(ManifoldSpace::new(space)).id();
///     let eye = commands.spawn((ChildOf(root), ManifoldCamera::default())).id();
///     commands.spawn((
///         ChildOf(eye),
///         CameraBody,
///         Mesh3d(assets.load("models/suzanne.glb#Mesh0/Primitive0")),
///         Transform::from_scale(Vec3::splat(0.1)).with_rotation(Quat::from_rotation_y(std::f32::consts::PI)),
///     ));
/// }
/// ```
#[derive(Component, Clone, Copy, Debug, Default, Reflect)]
#[reflect(Component, Debug, Default)]
pub struct CameraBody;

/// A [`TriMesh`] as a Bevy triangle-list mesh (positions, normals, UVs,
/// `u32` indices), kept in the main world so the tracer can read it back:
/// how the crate's built-in models (`trace::builtin`, feature `gltf`)
/// become `Mesh3d` assets without an asset folder.
#[must_use]
pub fn bevy_mesh(mesh: &TriMesh) -> Mesh {
    use bevy::asset::RenderAssetUsages;
    Mesh::new(PrimitiveTopology::TriangleList, RenderAssetUsages::default())
        .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, mesh.positions.clone())
        .with_inserted_attribute(Mesh::ATTRIBUTE_NORMAL, mesh.normals.clone())
        .with_inserted_attribute(Mesh::ATTRIBUTE_UV_0, mesh.uvs.clone())
        .with_inserted_indices(Indices::U32(mesh.triangles.iter().flatten().copied().collect()))
}

/// BVHs and textures by asset, rebuilt when the asset changes; and the
/// assets already reported as untraceable.
#[derive(Resource, Default)]
pub struct MeshBvhCache {
    meshes: HashMap<AssetId<Mesh>, Option<Arc<MeshData>>>,
    /// BVHs of large meshes being built on the async compute pool.
    pending: HashMap<AssetId<Mesh>, bevy::tasks::Task<Arc<MeshData>>>,
    // Base-colour textures come from StandardMaterial (feature
    // `standard_material`).
    #[cfg_attr(
        not(feature = "standard_material"),
        expect(dead_code, reason = "read only with StandardMaterial")
    )]
    textures: HashMap<AssetId<Image>, Option<Arc<Texture>>>,
    /// Mesh asset events seen since the last gathering.
    dirty: bool,
}

impl MeshBvhCache {
    /// How many mesh assets have a BVH.
    #[must_use]
    pub fn built(&self) -> usize {
        self.meshes.values().filter(|m| m.is_some()).count()
    }

    /// How many BVHs are being built off the frame.
    #[must_use]
    pub fn building(&self) -> usize {
        self.pending.len()
    }
}

/// A Bevy mesh as a [`TriMesh`]: triangle lists only.
///
/// # Errors
/// What keeps it from being traced, in words.
pub fn tri_mesh(mesh: &Mesh) -> Result<TriMesh, String> {
    if mesh.primitive_topology() != PrimitiveTopology::TriangleList {
        return Err(format!("{:?} meshes are not traced", mesh.primitive_topology()));
    }
    let positions = match mesh.attribute(Mesh::ATTRIBUTE_POSITION) {
        Some(VertexAttributeValues::Float32x3(p)) => p.clone(),
        Some(_) => return Err("positions are not Float32x3".into()),
        None => return Err("no positions (or the mesh data is not kept in the main world)".into()),
    };
    let normals = match mesh.attribute(Mesh::ATTRIBUTE_NORMAL) {
        Some(VertexAttributeValues::Float32x3(n)) => Some(n.clone()),
        _ => None,
    };
    let uvs = match mesh.attribute(Mesh::ATTRIBUTE_UV_0) {
        Some(VertexAttributeValues::Float32x2(t)) => Some(t.clone()),
        _ => None,
    };
    let indices: Vec<u32> = match mesh.indices() {
        Some(Indices::U16(i)) => i.iter().map(|&x| u32::from(x)).collect(),
        Some(Indices::U32(i)) => i.clone(),
        None => (0..positions.len() as u32).collect(),
    };
    let triangles = indices.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    TriMesh::new(positions, normals, uvs, triangles).map_err(|e| e.to_string())
}

/// A skinned Bevy mesh posed by its joints: linear-blend skinning, each
/// vertex moved by the weighted sum of its (up to four) joints'
/// matrices, `p' = sum_k w_k M[j_k] p` (weights scaled to sum to 1), its
/// normal by the inverse transpose of that sum, as Bevy's own vertex
/// shader skins it. `joints[j]` is joint `j`'s matrix in the mesh's own
/// frame: the mesh entity's transform inverted, times the joint's, times
/// its inverse bind pose.
///
/// ```
/// use bevy::mesh::{Indices, Mesh, PrimitiveTopology, VertexAttributeValues};
/// use bevy::asset::RenderAssetUsages;
/// use bevy::math::{Mat4, Vec3};
/// let mut mesh = Mesh::new(PrimitiveTopology::TriangleList, RenderAssetUsages::all());
/// mesh.insert_attribute(Mesh::ATTRIBUTE_POSITION, vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
/// mesh.insert_attribute(Mesh::ATTRIBUTE_JOINT_INDEX, VertexAttributeValues::Uint16x4(vec![[0, 0, 0, 0], [0, 0, 0, 0], [1, 0, 0, 0]]));
/// mesh.insert_attribute(Mesh::ATTRIBUTE_JOINT_WEIGHT, vec![[1.0f32, 0.0, 0.0, 0.0]; 3]);
/// mesh.insert_indices(Indices::U32(vec![0, 1, 2]));
/// // Joint 1 lifts its vertex by 2.
/// let posed = bevy_manifold::drawables::skinned_tri_mesh(&mesh, &[Mat4::IDENTITY, Mat4::from_translation(Vec3::Z * 2.0)]).unwrap();
/// assert_eq!(posed.positions[2], [0.0, 1.0, 2.0]);
/// ```
///
/// # Errors
/// What keeps it from being traced: no joint indices or weights, a
/// joint index past `joints`, or what [`tri_mesh`] says.
pub fn skinned_tri_mesh(mesh: &Mesh, joints: &[Mat4]) -> Result<TriMesh, String> {
    skin(tri_mesh(mesh)?, mesh, joints)
}

/// `rest` (the triangles of `mesh`, morphed or not) skinned by `joints`,
/// as [`skinned_tri_mesh`] says.
fn skin(rest: TriMesh, mesh: &Mesh, joints: &[Mat4]) -> Result<TriMesh, String> {
    let Some(VertexAttributeValues::Uint16x4(indices)) = mesh.attribute(Mesh::ATTRIBUTE_JOINT_INDEX) else {
        return Err("a skinned mesh without Uint16x4 joint indices".into());
    };
    let Some(VertexAttributeValues::Float32x4(weights)) = mesh.attribute(Mesh::ATTRIBUTE_JOINT_WEIGHT) else {
        return Err("a skinned mesh without Float32x4 joint weights".into());
    };
    if indices.len() != rest.positions.len() || weights.len() != rest.positions.len() {
        return Err("joint indices or weights not one per vertex".into());
    }
    let mut positions = Vec::with_capacity(rest.positions.len());
    let mut normals = Vec::with_capacity(rest.positions.len());
    for (v, (ji, w)) in indices.iter().zip(weights).enumerate() {
        let sum: f32 = w.iter().sum();
        let mut m = Mat4::ZERO;
        for (&j, &wk) in ji.iter().zip(w) {
            if wk == 0.0 {
                continue;
            }
            let joint = joints
                .get(usize::from(j))
                .ok_or_else(|| format!("vertex {v}: joint {j} of {} joints", joints.len()))?;
            m += *joint * (if sum > 0.0 { wk / sum } else { wk });
        }
        positions.push(m.transform_point3(Vec3::from(rest.positions[v])).to_array());
        let n = Mat3::from_mat4(m).inverse().transpose() * Vec3::from(rest.normals[v]);
        normals.push(n.normalize_or_zero().to_array());
    }
    TriMesh::new(positions, Some(normals), Some(rest.uvs), rest.triangles).map_err(|e| e.to_string())
}

/// A Bevy mesh with morph targets in the shape its `weights` blend: each
/// vertex's position and normal moved by the weighted sum of the
/// targets' displacements of it, `p' = p + sum_i w_i d_i`, the normal
/// made a unit one again, as Bevy's own vertex shader morphs it (before
/// skinning). Weights past the mesh's targets, and targets past the
/// weights, count for nothing.
///
/// ```
/// use bevy::mesh::{Indices, Mesh, PrimitiveTopology};
/// use bevy::mesh::morph::MorphAttributes;
/// use bevy::asset::RenderAssetUsages;
/// use bevy::math::Vec3;
/// let mut mesh = Mesh::new(PrimitiveTopology::TriangleList, RenderAssetUsages::all());
/// mesh.insert_attribute(Mesh::ATTRIBUTE_POSITION, vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
/// mesh.insert_indices(Indices::U32(vec![0, 1, 2]));
/// // One target: the third vertex up by 2.
/// let lift = |v: usize| MorphAttributes::new(if v == 2 { Vec3::Z * 2.0 } else { Vec3::ZERO }, Vec3::ZERO, Vec3::ZERO);
/// mesh.set_morph_targets((0..3).map(lift).collect());
/// let half = bevy_manifold::drawables::morphed_tri_mesh(&mesh, &[0.5]).unwrap();
/// assert_eq!(half.positions[2], [0.0, 1.0, 1.0]);
/// ```
///
/// A mesh without morph targets keeps its shape.
///
/// # Errors
/// Morph targets that are not a whole number of displacements per
/// vertex, or what [`tri_mesh`] says.
pub fn morphed_tri_mesh(mesh: &Mesh, weights: &[f32]) -> Result<TriMesh, String> {
    morph(tri_mesh(mesh)?, mesh, weights)
}

/// `rest` (the triangles of `mesh`) morphed by `weights`, as
/// [`morphed_tri_mesh`] says.
fn morph(mut rest: TriMesh, mesh: &Mesh, weights: &[f32]) -> Result<TriMesh, String> {
    // A mesh with no morph targets keeps its shape, as Bevy draws it.
    let Ok(targets) = mesh.try_morph_targets() else {
        return Ok(rest);
    };
    let n = rest.positions.len();
    if n == 0 || targets.len() % n != 0 {
        return Err(format!("{} morph displacements for {n} vertices", targets.len()));
    }
    for (i, &w) in weights.iter().enumerate().take(targets.len() / n) {
        if w == 0.0 || !w.is_finite() {
            continue;
        }
        for (v, d) in targets[i * n..(i + 1) * n].iter().enumerate() {
            rest.positions[v] = (Vec3::from(rest.positions[v]) + w * d.position).to_array();
            rest.normals[v] = (Vec3::from(rest.normals[v]) + w * d.normal).to_array();
        }
    }
    for n in &mut rest.normals {
        *n = Vec3::from(*n).normalize_or(Vec3::Z).to_array();
    }
    TriMesh::new(rest.positions, Some(rest.normals), Some(rest.uvs), rest.triangles).map_err(|e| e.to_string())
}

/// Joint `j`'s matrix in the frame of the mesh entity whose transform
/// relative to the placed entity is `mesh_local`: the joint's transforms
/// up to that placed entity (the first ancestor with a placement), after
/// `stretch` (the placed entity's scale over its largest axis, which
/// `mesh_local` starts with too), `mesh_local` inverted before them, its
/// inverse bind pose after. `None` when a joint is not below the placed
/// entity.
#[expect(clippy::type_complexity, reason = "the gathering system's queries, passed on")]
fn joint_matrices(
    skin: &SkinnedMesh,
    bindposes: &[Mat4],
    (stretch, mesh_local): (Mat4, Mat4),
    (parents, transforms, flags): (
        &Query<&ChildOf>,
        &Query<&Transform>,
        &Query<(Has<Placement>, Has<CameraBody>)>,
    ),
) -> Option<Vec<Mat4>> {
    let to_mesh = mesh_local.inverse();
    skin.joints
        .iter()
        .zip(bindposes)
        .map(|(&joint, ibp)| {
            let mut chain = Mat4::IDENTITY;
            let mut e = joint;
            // Up to (not including) the placed entity, whose frame the
            // tracer's `local` matrices are in.
            for _ in 0..256 {
                if flags.get(e).is_ok_and(|(placed, _)| placed) {
                    return Some(to_mesh * stretch * chain * *ibp);
                }
                chain = transforms.get(e).ok()?.to_matrix() * chain;
                e = parents.get(e).ok()?.parent();
            }
            None
        })
        .collect()
}

/// An RGBA8 Bevy image as a [`Texture`].
///
/// # Errors
/// Another texel format, or no data in the main world.
pub fn texture(image: &Image) -> Result<Texture, String> {
    use bevy::render::render_resource::TextureFormat;
    let format = image.texture_descriptor.format;
    if !matches!(format, TextureFormat::Rgba8UnormSrgb | TextureFormat::Rgba8Unorm) {
        return Err(format!("{format:?} textures are not traced (RGBA8 only)"));
    }
    let data = image.data.as_ref().ok_or("no texel data in the main world")?;
    let (width, height) = (image.width(), image.height());
    let texels: Vec<u32> = data
        .chunks_exact(4)
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    Texture::new(width, height, texels)
}

/// Meshes with more triangles than this have their BVH built on Bevy's
/// async compute pool, off the frame; smaller ones (Suzanne has 3,936) are
/// built in place.
pub const ASYNC_BVH_TRIANGLES: usize = 50_000;

/// Takes the BVHs finished on the async pool into the cache, and marks the
/// scene for gathering again so their meshes appear.
fn collect_bvh_builds(mut cache: ResMut<MeshBvhCache>) {
    if cache.pending.is_empty() {
        return;
    }
    let mut done = Vec::new();
    for (id, task) in &mut cache.pending {
        if let Some(data) = bevy::tasks::futures::check_ready(task) {
            done.push((*id, data));
        }
    }
    for (id, data) in done {
        cache.pending.remove(&id);
        cache.meshes.insert(id, Some(data));
        cache.dirty = true;
    }
}

fn note_mesh_events(mut events: MessageReader<AssetEvent<Mesh>>, mut cache: ResMut<MeshBvhCache>) {
    for e in events.read() {
        match e {
            // A mesh that arrives: gather again (nothing was cached for it
            // while it was missing).
            AssetEvent::Added { .. } | AssetEvent::LoadedWithDependencies { .. } => cache.dirty = true,
            // Changed or gone: its BVH, or the build under way for its old
            // contents, is dropped.
            AssetEvent::Modified { id } | AssetEvent::Removed { id } | AssetEvent::Unused { id } => {
                cache.meshes.remove(id);
                cache.pending.remove(id);
                cache.dirty = true;
            }
        }
    }
}

/// Textures likewise: an image that loads or changes after its material
/// was gathered is read again.
#[cfg(feature = "standard_material")]
fn note_image_events(mut events: MessageReader<AssetEvent<Image>>, mut cache: ResMut<MeshBvhCache>) {
    for e in events.read() {
        match e {
            // A new image may be one a material waits for.
            AssetEvent::Added { .. } | AssetEvent::LoadedWithDependencies { .. } => cache.dirty = true,
            AssetEvent::Modified { id } | AssetEvent::Removed { id } | AssetEvent::Unused { id } => {
                if cache.textures.remove(id).is_some() {
                    cache.dirty = true;
                }
            }
        }
    }
}

/// A mesh entity's own morph weights and the `MorphWeights` they may
/// refer to.
type MorphQueries<'w, 's> = (
    Query<'w, 's, &'static MeshMorphWeights>,
    Query<'w, 's, &'static MorphWeights>,
);

/// The morph weights of mesh entity `e`: its `MeshMorphWeights`' own, or
/// those of the `MorphWeights` it refers to (as a glTF scene spawns
/// them); `None` without any, or when every weight is 0 (the rest shape,
/// traced as a plain mesh).
fn morph_weights(e: Entity, (own, shared): &MorphQueries) -> Option<Vec<f32>> {
    let weights = match own.get(e).ok()? {
        MeshMorphWeights::Value { weights } => weights.clone(),
        MeshMorphWeights::Reference(r) => shared.get(*r).ok()?.weights().to_vec(),
    };
    weights.iter().any(|&w| w != 0.0).then_some(weights)
}

/// The material of a traced mesh entity.
#[cfg(feature = "standard_material")]
type MaterialOf<'a> = Option<&'a MeshMaterial3d<StandardMaterial>>;
/// Without `standard_material` there is no `StandardMaterial`: a placeholder the query
/// can hold (`()` is no component), never read.
#[cfg(not(feature = "standard_material"))]
type MaterialOf<'a> = Option<&'a Mesh3d>;

/// Everything a traced mesh entity brings.
type MeshEntity<'a> = (
    Entity,
    &'a Mesh3d,
    MaterialOf<'a>,
    Option<&'a InheritedVisibility>,
    Option<&'a RenderLayers>,
);

/// A skinned or morphing mesh's last pose: its joints' matrices, its
/// morph weights and the mesh (with its BVH) they made.
#[derive(Debug)]
pub struct PosedMesh {
    mesh: AssetId<Mesh>,
    joints: Vec<Mat4>,
    weights: Vec<f32>,
    data: Option<Arc<MeshData>>,
    /// The BVH's box area when it was last built, not refitted.
    built_area: f32,
}

/// A refitted BVH is built again once its boxes' area passes this many
/// times the area it had when built (the surface-area heuristic's
/// measure of what a ray pays).
pub const REFIT_GROWTH: f32 = 1.5;

/// `mesh` (the asset `id`) morphed by `weights` (none without morph
/// targets) and then skinned by `joints` (none when it is not skinned),
/// as Bevy's vertex shader poses it: the last pose's BVH refitted to the
/// moved vertices, or built again when there is none or refitting has
/// let its boxes grow past [`REFIT_GROWTH`].
fn pose(
    id: AssetId<Mesh>,
    mesh: &Mesh,
    (joints, weights): (&[Mat4], &[f32]),
    last: Option<&PosedMesh>,
) -> Result<PosedMesh, String> {
    use crate::mesh::bvh::surface_area;
    let mut posed = tri_mesh(mesh)?;
    if !weights.is_empty() {
        posed = morph(posed, mesh, weights)?;
    }
    if !joints.is_empty() {
        posed = skin(posed, mesh, joints)?;
    }
    let done = |data: Arc<MeshData>, built_area: f32| PosedMesh {
        mesh: id,
        joints: joints.to_vec(),
        weights: weights.to_vec(),
        data: Some(data),
        built_area,
    };
    // The last pose's BVH, when it was made for as many vertices.
    let previous = last
        .and_then(|l| Some((l.data.as_ref()?, l.built_area)))
        .filter(|(data, _)| data.mesh.positions.len() == posed.positions.len());
    let moved = match previous {
        Some((data, built)) => {
            let refit = data.refit(posed.positions, posed.normals).map_err(|e| e.to_string())?;
            if surface_area(&refit.nodes) <= REFIT_GROWTH * built {
                return Ok(done(Arc::new(refit), built));
            }
            // Grown too loose: a new BVH over the same moved triangles.
            refit.mesh
        }
        None => posed,
    };
    let data = MeshData::shared(moved);
    let area = surface_area(&data.nodes);
    Ok(done(data, area))
}

/// Builds every space's [`ManifoldMeshes`] when a mesh, material, placement
/// or transform below a placed entity changed, or a mesh asset did; hides
/// traced meshes from the rasteriser.
#[expect(
    clippy::too_many_arguments,
    clippy::type_complexity,
    reason = "a system's parameters"
)]
pub fn gather_meshes(
    mut commands: Commands,
    mut cache: ResMut<MeshBvhCache>,
    mesh_assets: Res<Assets<Mesh>>,
    images: Option<Res<Assets<Image>>>,
    #[cfg(feature = "standard_material")] materials: Option<Res<Assets<StandardMaterial>>>,
    roots: Query<(Entity, &ManifoldSpace, Option<&ManifoldMeshes>)>,
    placed: Query<(Entity, &Placement, &Transform, &InSpace)>,
    meshes: Query<MeshEntity, Without<Rasterized>>,
    children: Query<&Children>,
    transforms: Query<&Transform>,
    // Whether an entity is placed itself, and whether it is a camera body.
    flags: Query<(Has<Placement>, Has<CameraBody>)>,
    changed: Query<
        (),
        (
            Or<(
                Changed<Mesh3d>,
                Changed<Transform>,
                Changed<CameraBody>,
                Changed<Placement>,
                Changed<ChildOf>,
                Changed<InSpace>,
                Changed<MeshMorphWeights>,
                Changed<MorphWeights>,
            )>,
            Without<Rasterized>,
        ),
    >,
    mut removed: RemovedComponents<Mesh3d>,
    mut left_spaces: RemovedComponents<InSpace>,
    mut warned: Local<HashSet<AssetId<Mesh>>>,
    (skins, parents, bindposes, mut posed, morphs): (
        Query<&SkinnedMesh>,
        Query<&ChildOf>,
        Option<Res<Assets<SkinnedMeshInverseBindposes>>>,
        Local<HashMap<Entity, PosedMesh>>,
        MorphQueries,
    ),
) {
    let dirty = std::mem::take(&mut cache.dirty)
        || removed.read().count() + left_spaces.read().count() > 0
        || !changed.is_empty();
    #[cfg(feature = "standard_material")]
    let materials_changed = materials.as_ref().is_some_and(|m| m.is_changed());
    #[cfg(not(feature = "standard_material"))]
    let materials_changed = false;
    if !dirty && !materials_changed {
        return;
    }
    let mut per_root: HashMap<Entity, ManifoldMeshes> = HashMap::new();
    for (entity, placement, transform, in_space) in &placed {
        let root = in_space.space();
        // The largest axis of the scale as the mesh's scale, the rest of
        // it (each axis over the largest) in its local transform: a
        // linear map of the chart, so the triangles stay flat. Its signs
        // are in the placement (a mirror image).
        let axes = transform.scale.abs();
        let scale = f64::from(axes.max_element());
        let stretch = if scale > 0.0 && axes.is_finite() {
            Mat4::from_scale(axes / axes.max_element())
        } else {
            Mat4::IDENTITY
        };
        // The entity's own mesh, and those below it with no placement of
        // their own, positioned by their transforms relative to it.
        let mut stack = vec![(entity, stretch, false)];
        while let Some((e, local, body)) = stack.pop() {
            let body = body || flags.get(e).is_ok_and(|(_, b)| b);
            if let Ok((_, mesh3d, material, visible, layers)) = meshes.get(e) {
                if layers != Some(&RenderLayers::none()) {
                    commands.entity(e).insert(RenderLayers::none());
                }
                if visible.is_none_or(|v| v.get()) {
                    let id = mesh3d.0.id();
                    // A skinned or morphing mesh, posed by its joints and
                    // its morph weights: built again when they changed,
                    // else the last pose's BVH is kept.
                    let joints = skins.get(e).ok().and_then(|skin| {
                        let ibp = bindposes.as_ref()?.get(&skin.inverse_bindposes)?;
                        joint_matrices(skin, ibp, (stretch, local), (&parents, &transforms, &flags))
                    });
                    let weights = morph_weights(e, &morphs);
                    let skinned = (joints.is_some() || weights.is_some())
                        .then(|| {
                            let (joints, weights) = (joints.unwrap_or_default(), weights.unwrap_or_default());
                            if let Some(last) = posed.get(&e)
                                && last.mesh == id
                                && last.joints == joints
                                && last.weights == weights
                            {
                                return Some(last.data.clone());
                            }
                            let last = posed.remove(&e).filter(|last| last.mesh == id);
                            let pose = pose(id, mesh_assets.get(id)?, (&joints, &weights), last.as_ref());
                            let pose = match pose {
                                Ok(pose) => pose,
                                Err(err) => {
                                    if warned.insert(id) {
                                        warn!("bevy_manifold: posed mesh {id} of entity {e} is not traced: {err}");
                                    }
                                    PosedMesh {
                                        mesh: id,
                                        joints,
                                        weights,
                                        data: None,
                                        built_area: 0.0,
                                    }
                                }
                            };
                            let data = pose.data.clone();
                            posed.insert(e, pose);
                            Some(data)
                        })
                        .flatten();
                    // Cached only once the asset is there: one still loading
                    // is looked up again when its load event arrives.
                    let data = if let Some(data) = skinned {
                        data
                    } else {
                        match cache.meshes.get(&id) {
                            Some(cached) => cached.clone(),
                            // A large BVH still building: the mesh appears when
                            // it is ready (`collect_bvh_builds`).
                            None if cache.pending.contains_key(&id) => None,
                            None => match mesh_assets.get(id) {
                                None => None,
                                Some(mesh) => match tri_mesh(mesh) {
                                    Ok(m) if m.triangles.len() > ASYNC_BVH_TRIANGLES => {
                                        let task = bevy::tasks::AsyncComputeTaskPool::get()
                                            .spawn(async move { MeshData::shared(m) });
                                        cache.pending.insert(id, task);
                                        None
                                    }
                                    Ok(m) => {
                                        let built = Some(MeshData::shared(m));
                                        cache.meshes.insert(id, built.clone());
                                        built
                                    }
                                    Err(err) => {
                                        if warned.insert(id) {
                                            warn!("bevy_manifold: mesh {id} of entity {e} is not traced: {err}");
                                        }
                                        cache.meshes.insert(id, None);
                                        None
                                    }
                                },
                            },
                        }
                    };
                    if let Some(data) = data {
                        #[cfg(feature = "standard_material")]
                        let surface = surface(material, materials.as_deref(), images.as_deref(), &mut cache.textures);
                        #[cfg(not(feature = "standard_material"))]
                        let surface = {
                            let _ = (material, &images);
                            MeshMaterial::default()
                        };
                        let mut m = SceneMesh::new(data, surface, placement.isometry, scale);
                        m.local = local.as_dmat4();
                        m.attached = body;
                        let list = per_root.entry(root).or_default();
                        list.entities.push(e);
                        list.meshes.push(m);
                    }
                }
            }
            if let Ok(kids) = children.get(e) {
                for &k in kids {
                    if !flags.get(k).is_ok_and(|(placed, _)| placed)
                        && let Ok(t) = transforms.get(k)
                    {
                        stack.push((k, local * t.to_matrix(), body));
                    }
                }
            }
        }
    }
    // The poses of skinned and morphing meshes that are gone.
    posed.retain(|e, _| skins.contains(*e) || morphs.0.contains(*e));
    for (root, _, old) in &roots {
        let new = per_root.remove(&root).unwrap_or_default();
        if old != Some(&new) {
            commands.entity(root).insert(new);
        }
    }
}

/// What the tracer draws of a `StandardMaterial`: base colour and its
/// texture, metallic and perceptual roughness (and their texture),
/// emission (and its texture; Bevy's `emissive_exposure_weight` applied
/// with Bevy's default exposure, as Bevy's own shader does), the normal
/// map and an alpha mask (`AlphaMode::Mask`; other alpha modes are drawn
/// opaque). A textured field whose image is not RGBA8 is drawn without
/// its texture, with a warning.
#[cfg(feature = "standard_material")]
fn surface(
    material: Option<&MeshMaterial3d<StandardMaterial>>,
    materials: Option<&Assets<StandardMaterial>>,
    images: Option<&Assets<Image>>,
    textures: &mut HashMap<AssetId<Image>, Option<Arc<Texture>>>,
) -> MeshMaterial {
    let Some(m) = material.and_then(|m| materials?.get(&m.0)) else {
        return MeshMaterial::default();
    };
    let mut load = |handle: &Option<Handle<Image>>, what: &str| {
        handle.as_ref().and_then(|h| {
            // Not cached while the image is still loading (its load event
            // makes the next gathering read it).
            let image = images?.get(h)?;
            textures
                .entry(h.id())
                .or_insert_with(|| match texture(image) {
                    Ok(t) => Some(Arc::new(t)),
                    Err(e) => {
                        warn!(
                            "bevy_manifold: texture {} is not traced: {e}; the {what} is drawn without it",
                            h.id()
                        );
                        None
                    }
                })
                .clone()
        })
    };
    let base = m.base_color.to_linear();
    let exposure = 1.0 + (crate::drawables::BEVY_EXPOSURE as f32 - 1.0) * m.emissive_exposure_weight;
    let e = m.emissive;
    let emissive = [e.red, e.green, e.blue].map(|c| {
        let c = c * exposure;
        if c.is_finite() {
            c.clamp(0.0, bevy_manifold_core::material::MAX_EMISSIVE)
        } else {
            0.0
        }
    });
    let unit = |x: f32| if x.is_finite() { x.clamp(0.0, 1.0) } else { 0.0 };
    MeshMaterial {
        base_color: [base.red, base.green, base.blue].map(|c| if c.is_finite() { c.max(0.0) } else { 0.0 }),
        texture: load(&m.base_color_texture, "base colour"),
        alpha: unit(base.alpha),
        alpha_cutoff: match m.alpha_mode {
            AlphaMode::Mask(c) => Some(unit(c)),
            _ => None,
        },
        pbr: Some(bevy_manifold_core::material::Pbr {
            metallic: unit(m.metallic),
            roughness: unit(m.perceptual_roughness),
        }),
        metallic_roughness: load(&m.metallic_roughness_texture, "metallic and roughness"),
        emissive,
        emissive_texture: load(&m.emissive_texture, "emission"),
        normal_map: load(&m.normal_map_texture, "normal map"),
    }
}

/// Registers the mesh gathering in `set` (part of
/// [`super::DrawablesPlugin`], from its `finish`): only in apps that have
/// Bevy's meshes.
pub(super) fn build(app: &mut App, schedule: bevy::ecs::schedule::InternedScheduleLabel, set: impl SystemSet) {
    app.register_type::<Rasterized>().register_type::<CameraBody>();
    if !app.world().contains_resource::<Assets<Mesh>>() {
        return;
    }
    app.init_resource::<MeshBvhCache>().add_systems(
        schedule,
        (note_mesh_events, collect_bvh_builds, gather_meshes)
            .chain()
            .in_set(set),
    );
    #[cfg(feature = "standard_material")]
    app.add_systems(
        schedule,
        note_image_events
            .run_if(resource_exists::<Messages<AssetEvent<Image>>>)
            .before(gather_meshes),
    );
}
