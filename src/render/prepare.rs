//! Preparation: each space's scene packed for the GPU
//! ([`prepare_manifold_scenes`], when its generation or its space
//! changed), then per manifold view the pipeline variant it needs and its
//! GPU buffers ([`prepare_manifold_views`]). The space's buffers are
//! rebuilt only when the space changed, the objects' only when an object
//! changed, and the 240-byte params buffer only when the camera or the
//! settings changed. [`ManifoldUploads`] counts what was uploaded, so this
//! is testable.

use super::extract::ExtractedManifoldView;
use super::pipeline::{TracePipeline, TracePipelineKey};
use super::scale::ManifoldRenderScale;
use super::upscale::{HISTORY_FORMAT, TracedTextures, UpscaleKey, UpscalePipeline};
use crate::space::Space;
use crate::space::ball::OUTSIDE;
use crate::space::element::CellElement;
use crate::trace::{FlatScene, Projection, pixel_half_angle};
use bevy::camera::CompositingSpace;
use bevy::platform::collections::{HashMap, HashSet};
use bevy::prelude::*;
use bevy::render::camera::ExtractedCamera;
use bevy::render::render_resource::{
    BindGroup, BindGroupEntries, Buffer, BufferInitDescriptor, BufferUsages, CachedPipelineState,
    CachedRenderPipelineId, PipelineCache, SpecializedRenderPipelines, TextureView,
};
use bevy::render::renderer::{RenderDevice, RenderQueue};
use bevy::render::view::{ExtractedView, Msaa};
use bevy::tasks::futures_lite::future::{block_on, poll_once};
use bevy::tasks::{AsyncComputeTaskPool, Task};
use bevy_manifold_gpu::{GpuObjects, GpuParams, GpuSpace, GpuView};
use std::sync::Arc;

/// What the pass needs to draw a manifold view this frame.
#[derive(Component, Clone)]
pub struct ManifoldViewBinding {
    /// The specialised pipeline.
    pub pipeline: CachedRenderPipelineId,
    /// Group 0.
    pub bind_group: BindGroup,
    /// For a view traced below full scale: where the trace goes and how
    /// it is upscaled.
    pub scaled: Option<ScaledBinding>,
}

/// A view traced into textures of its own (below full scale, or
/// accumulating): the traced textures, the blend into the history, the
/// upscale.
#[derive(Clone)]
pub struct ScaledBinding {
    /// The upscale pipeline for the view target.
    pub pipeline: CachedRenderPipelineId,
    /// The traced colour the trace draws into.
    pub color: TextureView,
    /// The traced depth.
    pub depth: TextureView,
    /// Group 0 of the upscale (the history when accumulating).
    pub bind_group: BindGroup,
    /// Trace this frame (false once a still view has all its samples).
    pub trace: bool,
    /// The blend of this frame's trace into the history.
    pub blend: Option<BlendIn>,
}

/// The blend of a trace into a view's accumulation history.
#[derive(Clone)]
pub struct BlendIn {
    /// The `blend_in` pipeline.
    pub pipeline: CachedRenderPipelineId,
    /// The history drawn into.
    pub history: TextureView,
    /// Group 0: the trace.
    pub source: BindGroup,
    /// The first sample: the history is cleared before it is added.
    pub first: bool,
}

/// Running totals of what the pass uploaded (render world). Uploads happen
/// on change only: a still camera in a still scene uploads nothing.
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ManifoldUploads {
    /// Times a space's faces and cell table were uploaded.
    pub space: u64,
    /// Times a scene's balls, tubes, lights and instances were uploaded
    /// (the meshes' data only when it changed).
    pub objects: u64,
    /// Times a view's params buffer was written.
    pub params: u64,
    /// Bytes uploaded in all.
    pub bytes: u64,
}

/// One space's scene, packed for the GPU, and what it was packed from.
struct PackedScene {
    space: Arc<Space>,
    generation: u64,
    /// The cell the exact-id table is centred on (`CELLS_TABLE`).
    centre: CellElement,
    /// The table being recentred on another cell, off the frame.
    pending: Option<(CellElement, Task<GpuSpace>)>,
    gpu_space: Arc<GpuSpace>,
    objects: Arc<GpuObjects>,
}

/// Every space's packed scene, by the main-world root entity; spaces no
/// view looks into any more are dropped the next frame.
#[derive(Resource, Default)]
pub struct ManifoldPackedScenes {
    scenes: HashMap<Entity, PackedScene>,
}

impl ManifoldPackedScenes {
    /// The space and objects packed for `root`'s space, if a view looks
    /// into it this frame.
    #[must_use]
    pub fn get(&self, root: Entity) -> Option<(&Arc<GpuSpace>, &Arc<GpuObjects>)> {
        self.scenes.get(&root).map(|p| (&p.gpu_space, &p.objects))
    }

    /// The cell `root`'s table of exact ids is centred on.
    #[must_use]
    pub fn centre(&self, root: Entity) -> Option<&CellElement> {
        self.scenes.get(&root).map(|p| &p.centre)
    }
}

/// Packs each space's scene for the GPU when its generation or its space
/// changed (in f32, as the CPU tracer's f32 mode reads it). A repacked
/// scene equal to the old one keeps the old `Arc`, so nothing is uploaded.
pub fn prepare_manifold_scenes(views: Query<&ExtractedManifoldView>, mut packed: ResMut<ManifoldPackedScenes>) {
    let mut seen = HashSet::new();
    for view in &views {
        if !seen.insert(view.root) {
            continue;
        }
        let space = view.space.shared();
        let generation = view.scene.generation();
        let old = packed.scenes.get(&view.root);
        let same_space = old.is_some_and(|o| Arc::ptr_eq(&o.space, space));
        // The camera's cell, exactly (the first view into the space
        // decides where the table is centred; every view finds its own
        // cell in it: see prepare_manifold_views).
        let centre = match &view.element {
            // A camera not yet crossed (or placed by hand): located once.
            CellElement::Float(m) => space.cell_of_matrix(m),
            exact => exact.clone(),
        };
        // A table still growing: repacked once it has grown.
        if same_space
            && let Some(o) = packed.scenes.get_mut(&view.root)
            && o.gpu_space.table_pending(space)
            && let crate::space::cells::CellScheme::Exact(exact) = space.cells()
            && exact.grown_ball().is_some()
        {
            let mut table = GpuSpace::pack(space);
            table.centre_on(space, &o.centre);
            o.gpu_space = Arc::new(table);
            o.pending = None;
        }
        let old = packed.scenes.get(&view.root);
        let same_centre = old.is_some_and(|o| o.centre == centre);
        let same_generation = old.is_some_and(|o| o.generation == generation);
        if same_space
            && !same_centre
            && let Some(o) = packed.scenes.get_mut(&view.root)
        {
            if matches!(centre, CellElement::Exact(_)) {
                // Only the table's ids move with the camera (11 ms in
                // Seifert-Weber's 16,129 cells, 35 in the mirrored
                // dodecahedron's 57,741): recomputed off the frame on the
                // async compute pool, while the views walk the old table
                // from the camera's cell in it (prepare_manifold_views).
                if o.pending.as_ref().is_none_or(|(c, _)| *c != centre) {
                    let (table, space, target) = (o.gpu_space.clone(), space.clone(), centre.clone());
                    let task = AsyncComputeTaskPool::get().spawn(async move {
                        let mut table = (*table).clone();
                        table.centre_on(&space, &target);
                        table
                    });
                    o.pending = Some((centre.clone(), task));
                }
                if let Some((c, task)) = &mut o.pending
                    && let Some(table) = block_on(poll_once(task))
                {
                    o.centre = c.clone();
                    o.gpu_space = Arc::new(table);
                    o.pending = None;
                }
            } else {
                o.centre = centre.clone();
            }
            if o.generation == generation {
                // The scene is the same, but a camera-attached mesh's home
                // (the copy not drawn) is the camera's new cell.
                let objects = GpuObjects::pack(&flat_scene(space, &view.scene, &centre));
                if *o.objects != objects {
                    o.objects = Arc::new(objects);
                }
                continue;
            }
        } else if same_space && same_generation {
            continue;
        }
        let old = packed.scenes.get(&view.root);
        let objects = GpuObjects::pack(&flat_scene(space, &view.scene, &centre));
        let (gpu_space, objects) = match old {
            Some(o) if same_space => (
                o.gpu_space.clone(),
                if *o.objects == objects {
                    o.objects.clone()
                } else {
                    Arc::new(objects)
                },
            ),
            _ => {
                let mut gpu_space = GpuSpace::pack(space);
                gpu_space.centre_on(space, &centre);
                if gpu_space.table_pending(space) {
                    // Grown off the frame (0.4 s in Seifert-Weber, 1.5 s in
                    // the mirrored dodecahedron); until then the camera's
                    // own cell is exact and the rest grey.
                    let space = space.clone();
                    AsyncComputeTaskPool::get()
                        .spawn(async move {
                            if let crate::space::cells::CellScheme::Exact(exact) = space.cells() {
                                exact.ball();
                            }
                        })
                        .detach();
                }
                (Arc::new(gpu_space), Arc::new(objects))
            }
        };
        packed.scenes.insert(
            view.root,
            PackedScene {
                space: space.clone(),
                generation,
                centre,
                pending: None,
                gpu_space,
                objects,
            },
        );
    }
    packed.scenes.retain(|root, _| seen.contains(root));
}

/// One space's buffers (by the main-world root entity) and what they
/// hold: shared by every view into that space, so a headset's two eyes
/// upload the scene once, not once each.
struct SceneBuffers {
    space: Arc<GpuSpace>,
    objects: Arc<GpuObjects>,
    faces: Buffer,
    cell_table: Buffer,
    balls: Buffer,
    tubes: Buffer,
    lights: Buffer,
    instances: Buffer,
    mesh_data: Buffer,
    groups: Buffer,
    ball_nodes: Buffer,
    /// Bumped whenever a buffer is made anew (the views' bind groups then
    /// are made again).
    made: u64,
}

impl SceneBuffers {
    /// The objects' buffers, in [`object_data`]'s order.
    fn objects_mut(&mut self) -> [&mut Buffer; 7] {
        [
            &mut self.balls,
            &mut self.tubes,
            &mut self.lights,
            &mut self.instances,
            &mut self.mesh_data,
            &mut self.groups,
            &mut self.ball_nodes,
        ]
    }
}

/// One view's own buffer (its params) and its bind group.
struct ViewBuffers {
    /// The root whose [`SceneBuffers`] the bind group binds, and their
    /// `made` then.
    bound: Option<(Entity, u64)>,
    params: GpuParams,
    params_buffer: Buffer,
    bind_group: Option<BindGroup>,
    /// The traced textures of a view below full scale or accumulating.
    traced: Option<TracedTextures>,
    /// The params before any jitter last frame, the space and objects
    /// they were packed from, and the samples wanted: a still view has
    /// all four unchanged.
    still: Option<(GpuParams, usize, usize, u32)>,
    /// Samples accumulated in the history so far.
    samples: u32,
    /// How the view was last drawn: into textures of its own, and the
    /// trace pipeline and its key.
    drawn: Option<(bool, CachedRenderPipelineId, TracePipelineKey)>,
}

/// Every manifold view's buffers, by render-world view entity, and every
/// space's, by root; views that went away are dropped (with their
/// buffers) the next frame, and spaces no view looks into with them.
#[derive(Resource, Default)]
pub struct ManifoldBufferCache {
    views: HashMap<Entity, ViewBuffers>,
    scenes: HashMap<Entity, SceneBuffers>,
    failed: HashSet<CachedRenderPipelineId>,
}

impl ManifoldBufferCache {
    /// How many views hold buffers.
    #[must_use]
    pub fn len(&self) -> usize {
        self.views.len()
    }

    /// Drops every view's buffers and bind groups, so the next frame
    /// uploads everything again as if nothing had been uploaded before
    /// (`bench specialise` measures what change detection saves this way).
    pub fn invalidate(&mut self) {
        self.views.clear();
        self.scenes.clear();
    }

    /// How many spaces' scenes are held on the GPU (one for any number of
    /// views into a space).
    #[must_use]
    pub fn scenes(&self) -> usize {
        self.scenes.len()
    }

    /// True when no view holds buffers.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.views.is_empty()
    }
}

/// The uniform binding a buffer labelled `manifold_<name>` is made for,
/// if its binding is a uniform.
fn uniform_binding(label: &str) -> Option<&'static bevy_manifold_gpu::bindings::Binding> {
    let name = label.strip_prefix("manifold_")?;
    bevy_manifold_gpu::bindings::BINDINGS
        .iter()
        .find(|b| b.name == name && b.kind == bevy_manifold_gpu::bindings::BindingKind::Uniform)
}

/// Smallest storage buffer made, in bytes.
const MIN_BUFFER: u64 = 256;

/// A buffer holding `data` for the binding its label names
/// (`manifold_<name>`), with `COPY_DST` so later data is written in place.
fn scene_buffer(device: &RenderDevice, label: &'static str, data: &[u8], stats: &mut ManifoldUploads) -> Buffer {
    stats.bytes += data.len() as u64;
    let (size, usage) = match uniform_binding(label) {
        // A uniform array (faces, tubes, lights, face groups: BINDINGS) is
        // always its declared length, so every space and scene fits in place.
        Some(b) => (b.bytes_for(data.len()), b.usage()),
        // Room to grow (a power of two), so the next space or scene that
        // fits is written in place and keeps the bind group (see
        // `write_or_grow`); never past what the device binds, unless the
        // data itself is larger (then binding fails as it would have
        // without the room).
        None => {
            let limit = usize::try_from(device.limits().max_storage_buffer_binding_size).unwrap_or(usize::MAX);
            let size = data
                .len()
                .max(MIN_BUFFER as usize)
                .next_power_of_two()
                .min(limit & !3)
                .max(data.len());
            (size, BufferUsages::STORAGE)
        }
    };
    let mut contents = vec![0u8; size];
    contents[..data.len()].copy_from_slice(data);
    device.create_buffer_with_data(&BufferInitDescriptor {
        label: Some(label),
        contents: &contents,
        usage: usage | BufferUsages::COPY_DST,
    })
}

/// Writes `data` into `slot` in place when it fits, else replaces `slot`
/// with a larger buffer holding it; true when replaced (the view's bind
/// group must then be made again). Writing in place lets a view whose
/// space or scene changes keep its buffers and bind group instead of
/// making ten new GPU objects per change. The shader reads only the
/// counts in the params, so a buffer larger than its data is harmless.
fn write_or_grow(
    device: &RenderDevice,
    queue: &RenderQueue,
    slot: &mut Buffer,
    label: &'static str,
    data: &[u8],
    stats: &mut ManifoldUploads,
) -> bool {
    if data.len() as u64 <= slot.size() {
        if !data.is_empty() {
            queue.write_buffer(slot, 0, data);
        }
        stats.bytes += data.len() as u64;
        false
    } else {
        *slot = scene_buffer(device, label, data, stats);
        true
    }
}

fn space_buffers(device: &RenderDevice, s: &GpuSpace, stats: &mut ManifoldUploads) -> (Buffer, Buffer) {
    stats.space += 1;
    (
        scene_buffer(device, "manifold_faces", bytemuck::cast_slice(&s.faces), stats),
        scene_buffer(
            device,
            "manifold_cell_table",
            bytemuck::cast_slice(&s.cell_table),
            stats,
        ),
    )
}

/// The objects' data, each with the label of its buffer, in
/// [`SceneBuffers::objects_mut`]'s order: balls, tubes, lights,
/// instances, the meshes' data, the face groups and the ball tree's leaves.
fn object_data(o: &GpuObjects) -> [(&'static str, &[u8]); 7] {
    [
        ("manifold_balls", bytemuck::cast_slice(&o.balls)),
        ("manifold_tubes", bytemuck::cast_slice(&o.tubes)),
        ("manifold_lights", bytemuck::cast_slice(&o.lights)),
        ("manifold_instances", bytemuck::cast_slice(&o.instances)),
        ("manifold_mesh_data", bytemuck::cast_slice(&o.mesh_data)),
        ("manifold_groups", bytemuck::cast_slice(&o.groups)),
        ("manifold_ball_nodes", bytemuck::cast_slice(&o.ball_nodes)),
    ]
}

/// The objects' buffers, first made ([`object_data`]'s order).
fn object_buffers(device: &RenderDevice, o: &GpuObjects, stats: &mut ManifoldUploads) -> [Buffer; 7] {
    stats.objects += 1;
    object_data(o).map(|(label, data)| scene_buffer(device, label, data, stats))
}

/// The scene's objects seen from the camera's cell `cell`: the objects
/// are copies in every cell, but a camera-attached mesh's home (its copy
/// that is the camera's own body, not drawn) is the copy the camera is in.
/// CPU twin: the scene a headless render packs (`FlatScene::new` with the
/// camera's word).
fn flat_scene(space: &Space, scene: &crate::drawables::ManifoldScene, cell: &CellElement) -> FlatScene<f32> {
    let prep = FlatScene::<f32>::new(space, scene.scene()).in_cell(space, cell);
    let most = bevy_manifold_gpu::bindings::MAX_BALLS;
    if prep.balls.len() > most {
        warn!(
            "the manifold scene makes {} balls (ghost copies and edge joints included); the GPU draws the first {most}",
            prep.balls.len()
        );
    }
    prep
}

/// The off-centre frustum of a view's projection `p` (an OpenXR eye's),
/// `None` for a symmetric one whose aspect is the viewport's (Bevy's
/// perspective), which the tracer makes from `tan_half_fov` exactly as
/// before. A direction `(x_v, y_v, -1)` lands at NDC
/// `x = p.x_axis.x x_v - p.z_axis.x`, so `x_v = (x + p.z_axis.x) / p.x_axis.x`
/// (likewise y).
#[must_use]
pub(crate) fn view_frustum(p: Mat4, width: u32, height: u32) -> Option<[f32; 4]> {
    let aspect = width as f32 / height.max(1) as f32;
    let symmetric =
        p.z_axis.x == 0.0 && p.z_axis.y == 0.0 && (p.x_axis.x * aspect - p.y_axis.y).abs() <= 1e-5 * p.y_axis.y.abs();
    if symmetric || p.x_axis.x == 0.0 || p.y_axis.y == 0.0 {
        return None;
    }
    Some([
        1.0 / p.x_axis.x,
        1.0 / p.y_axis.y,
        p.z_axis.x / p.x_axis.x,
        p.z_axis.y / p.y_axis.y,
    ])
}

/// The per-frame view data of an extracted view, traced at `traced`
/// pixels into textures of its own when given (a render scale below 1),
/// else into its viewport.
fn gpu_view(view: &ExtractedManifoldView, extracted: &ExtractedView, traced: Option<UVec2>) -> GpuView {
    // Bevy's perspective projection: y_axis.y = 1 / tan(fov/2); the near
    // plane sits in w_axis.z (infinite reverse z).
    let p = extracted.clip_from_view;
    let frustum = view_frustum(p, extracted.viewport.z, extracted.viewport.w);
    let (size, origin, frustum) = match traced {
        // The traced size rounds the viewport's, so its aspect is not
        // quite the viewport's: the frustum is given whole, so the view
        // covers what the full-size view covers.
        Some(t) => (
            [t.x, t.y],
            [0, 0],
            frustum.or(Some([1.0 / p.x_axis.x, 1.0 / p.y_axis.y, 0.0, 0.0])),
        ),
        None => (
            [extracted.viewport.z, extracted.viewport.w],
            [extracted.viewport.x, extracted.viewport.y],
            frustum,
        ),
    };
    GpuView {
        camera: view.camera.as_mat4(),
        camera_cell: view.cell,
        tan_half_fov: 1.0 / p.y_axis.y,
        frustum,
        fog: view.fog,
        size,
        origin,
        near: p.w_axis.z,
        levels: view.levels,
        max_distance: view.max_distance,
        flags: 0,
        cell_tint: view.cell_tint,
        cell_rule: view.space.rule().words(),
        projection: bevy_manifold_core::trace::Projection::Perspective.words(),
        // The cones are as wide as the traced pixels.
        footprint: if view.defs.footprint {
            let half_height = frustum.map_or(1.0 / p.y_axis.y, |f| f[1]);
            pixel_half_angle(Projection::Perspective, f64::from(half_height), size[1]) as f32
        } else {
            0.0
        },
    }
}

/// Specialises the pipeline for each manifold view and brings its buffers
/// up to date (uploading only what changed), then binds them.
#[expect(clippy::too_many_arguments, reason = "a system's parameters")]
pub fn prepare_manifold_views(
    mut commands: Commands,
    views: Query<(
        Entity,
        &ExtractedManifoldView,
        &ExtractedView,
        &ExtractedCamera,
        Option<&Msaa>,
    )>,
    pipeline: Option<Res<TracePipeline>>,
    mut pipelines: ResMut<SpecializedRenderPipelines<TracePipeline>>,
    upscale: Option<Res<UpscalePipeline>>,
    mut upscales: ResMut<SpecializedRenderPipelines<UpscalePipeline>>,
    pipeline_cache: Res<PipelineCache>,
    device: Res<RenderDevice>,
    queue: Res<RenderQueue>,
    mut cache: ResMut<ManifoldBufferCache>,
    mut stats: ResMut<ManifoldUploads>,
    packed: Res<ManifoldPackedScenes>,
) {
    let (Some(pipeline), Some(upscale)) = (pipeline, upscale) else {
        return;
    };
    let cache = &mut *cache;
    let stats = &mut *stats;
    let mut seen = HashSet::new();
    for (entity, view, extracted, camera, msaa) in &views {
        seen.insert(entity);
        let viewport = UVec2::new(extracted.viewport.z, extracted.viewport.w);
        let accumulate = view.samples > 1;
        let traced =
            Some(ManifoldRenderScale(view.scale).traced_size(viewport)).filter(|t| *t != viewport || accumulate);
        let samples = msaa.map_or(1, Msaa::samples);
        let encode_srgb = camera.compositing_space == Some(CompositingSpace::Srgb);
        // What the packed objects decide (TraceDefs::for_objects).
        let defs = packed
            .get(view.root)
            .map_or(view.defs, |(_, o)| view.defs.for_objects(o));
        // Traced into textures of its own: linear colour, one sample; the
        // upscale encodes and writes the view target's samples.
        let key = match traced {
            Some(_) => TracePipelineKey {
                defs,
                format: HISTORY_FORMAT,
                samples: 1,
                encode_srgb: false,
            },
            None => TracePipelineKey {
                defs,
                format: extracted.target_format,
                samples,
                encode_srgb,
            },
        };
        let mut id = pipelines.specialize(&pipeline_cache, &pipeline, key);
        if let CachedPipelineState::Err(e) = pipeline_cache.get_render_pipeline_state(id)
            && cache.failed.insert(id)
        {
            error!("the manifold tracer pipeline for {:?} failed: {e}", key.defs.names());
        }
        // Switching between drawing straight into the target and into
        // textures of its own (a render scale crossing 1) needs the other
        // pipeline: until it is compiled the view is drawn the way it was
        // last drawn, if that pipeline is ready, rather than not at all.
        let mut traced = traced;
        let mut drawn_key = key;
        if pipeline_cache.get_render_pipeline(id).is_none()
            && let Some((own, last, last_key)) = cache.views.get(&entity).and_then(|e| e.drawn)
            && pipeline_cache.get_render_pipeline(last).is_some()
        {
            if own != traced.is_some() {
                id = last;
                drawn_key = last_key;
                traced = own.then_some(viewport);
            } else if last_key.defs.same_but_ball_tree(&key.defs)
                && (TracePipelineKey {
                    defs: key.defs,
                    ..last_key
                }) == key
            {
                // Balls came or went across a doubling of the ball tree's
                // leaves (the shooter's shots): the last pipeline draws
                // the new scene, testing every ball or only the leaves it
                // has, until the new one is compiled.
                id = last;
                drawn_key = last_key;
            }
        }
        let Some((space, objects)) = packed.get(view.root) else {
            continue;
        };
        let mut params = GpuParams::new(view.space.space(), space, objects, &gpu_view(view, extracted, traced));
        if matches!(view.element, CellElement::Exact(_)) && packed.centre(view.root) != Some(&view.element) {
            // The table is centred on another cell (another camera's, or
            // this one's before a crossing while it is recentred): the
            // walk starts from this camera's cell in it, found by its id.
            let id = view.space.space().cell_id_of(&view.element);
            params.camera_cell_index = space.index_of(id).unwrap_or(OUTSIDE);
        }
        let shared = cache.scenes.entry(view.root).or_insert_with(|| {
            let (faces, cell_table) = space_buffers(&device, space, stats);
            let [balls, tubes, lights, instances, mesh_data, groups, ball_nodes] =
                object_buffers(&device, objects, stats);
            SceneBuffers {
                space: space.clone(),
                objects: objects.clone(),
                faces,
                cell_table,
                balls,
                tubes,
                lights,
                instances,
                mesh_data,
                groups,
                ball_nodes,
                made: 0,
            }
        });
        update_scene_buffers(&device, &queue, shared, space, objects, stats);
        let entry = cache.views.entry(entity).or_insert_with(|| {
            stats.params += 1;
            stats.bytes += std::mem::size_of::<GpuParams>() as u64;
            let params_buffer = device.create_buffer_with_data(&BufferInitDescriptor {
                label: Some("manifold_params"),
                contents: bytemuck::bytes_of(&params),
                usage: BufferUsages::STORAGE | BufferUsages::COPY_DST,
            });
            ViewBuffers {
                bound: None,
                params,
                params_buffer,
                bind_group: None,
                traced: None,
                still: None,
                samples: 0,
                drawn: None,
            }
        });
        if pipeline_cache.get_render_pipeline(id).is_some() {
            entry.drawn = Some((traced.is_some(), id, drawn_key));
        }
        // Accumulation: the same view as last frame (params, space and
        // objects, textures) adds a sample, jittered; anything else starts
        // again from the plain trace.
        let format = HISTORY_FORMAT;
        let scene_key = (Arc::as_ptr(space) as usize, Arc::as_ptr(objects) as usize);
        let textures_fit = entry
            .traced
            .as_ref()
            .is_some_and(|t| Some(t.size) == traced && t.format == format && t.history.is_some() == accumulate);
        // A sample counts only if this frame draws it: every pipeline the
        // frame needs must be compiled. (Asked only of accumulating views,
        // so a plain view never compiles the upscale and blend pipelines.)
        let ready = |id| pipeline_cache.get_render_pipeline(id).is_some();
        let blend_key = UpscaleKey {
            format: extracted.target_format,
            samples,
            encode_srgb,
            blend: true,
        };
        let pipelines_ready = accumulate
            && ready(id)
            && ready(upscales.specialize(
                &pipeline_cache,
                &upscale,
                UpscaleKey {
                    blend: false,
                    ..blend_key
                },
            ))
            && ready(upscales.specialize(&pipeline_cache, &upscale, blend_key));
        let still = pipelines_ready
            && textures_fit
            && entry.still.as_ref().is_some_and(|(p, a, b, n)| {
                bytemuck::bytes_of(p) == bytemuck::bytes_of(&params)
                    && (*a, *b, *n) == (scene_key.0, scene_key.1, view.samples)
            });
        entry.samples = if still {
            (entry.samples + 1).min(view.samples)
        } else {
            0
        };
        entry.still = pipelines_ready.then_some((params, scene_key.0, scene_key.1, view.samples));
        let sample = entry.samples;
        let trace = sample < view.samples;
        if accumulate && trace && sample > 0 {
            let [ox, oy] = crate::trace::sample_offset(sample);
            let size = traced.unwrap_or(viewport).as_dvec2();
            let [hw, hh, cx, cy] = params.frustum.map(f64::from);
            params.frustum[2] = (cx + 2.0 * hw / size.x * ox) as f32;
            params.frustum[3] = (cy - 2.0 * hh / size.y * oy) as f32;
        }
        if entry.bound != Some((view.root, shared.made)) {
            entry.bound = Some((view.root, shared.made));
            entry.bind_group = None;
        }
        if bytemuck::bytes_of(&entry.params) != bytemuck::bytes_of(&params) {
            queue.write_buffer(&entry.params_buffer, 0, bytemuck::bytes_of(&params));
            entry.params = params;
            stats.params += 1;
            stats.bytes += std::mem::size_of::<GpuParams>() as u64;
        }
        let bind_group = entry.bind_group.get_or_insert_with(|| {
            device.create_bind_group(
                "manifold_trace",
                &pipeline_cache.get_bind_group_layout(&pipeline.layout),
                // BINDINGS' numbers; 8, the compute entries' output, is
                // not bound here.
                &BindGroupEntries::with_indices((
                    (0, entry.params_buffer.as_entire_binding()),
                    (1, shared.faces.as_entire_binding()),
                    (2, shared.balls.as_entire_binding()),
                    (3, shared.tubes.as_entire_binding()),
                    (4, shared.lights.as_entire_binding()),
                    (5, shared.cell_table.as_entire_binding()),
                    (6, shared.instances.as_entire_binding()),
                    (7, shared.mesh_data.as_entire_binding()),
                    (9, shared.groups.as_entire_binding()),
                    (10, shared.ball_nodes.as_entire_binding()),
                )),
            )
        });
        let bind_group = bind_group.clone();
        let scaled = traced.map(|size| {
            let textures = match entry.traced.take() {
                Some(t) if textures_fit => t,
                _ => TracedTextures::new(&device, &pipeline_cache, &upscale, size, format, accumulate),
            };
            let textures = entry.traced.insert(textures);
            let key = UpscaleKey {
                format: extracted.target_format,
                samples,
                encode_srgb,
                blend: false,
            };
            let blend = textures.history.as_ref().map(|history| BlendIn {
                pipeline: upscales.specialize(&pipeline_cache, &upscale, UpscaleKey { blend: true, ..key }),
                history: history.view.clone(),
                source: textures.bind_group.clone(),
                first: sample == 0,
            });
            ScaledBinding {
                pipeline: upscales.specialize(&pipeline_cache, &upscale, key),
                color: textures.color.clone(),
                depth: textures.depth.clone(),
                bind_group: textures
                    .history
                    .as_ref()
                    .map_or_else(|| textures.bind_group.clone(), |h| h.bind_group.clone()),
                trace,
                blend: blend.filter(|_| trace),
            }
        });
        if scaled.is_none() {
            entry.traced = None;
        }
        commands.entity(entity).insert(ManifoldViewBinding {
            pipeline: id,
            bind_group,
            scaled,
        });
    }
    cache.views.retain(|e, _| seen.contains(e));
    let roots: HashSet<Entity> = views.iter().map(|(_, v, ..)| v.root).collect();
    cache.scenes.retain(|root, _| roots.contains(root));
}

/// Brings a space's shared buffers up to `space` and `objects`, writing in
/// place where the new data fits and growing (bumping `made`) where it
/// does not; an unchanged `Arc` uploads nothing.
fn update_scene_buffers(
    device: &RenderDevice,
    queue: &RenderQueue,
    shared: &mut SceneBuffers,
    space: &Arc<GpuSpace>,
    objects: &Arc<GpuObjects>,
    stats: &mut ManifoldUploads,
) {
    let mut grew = false;
    if !Arc::ptr_eq(&shared.space, space) {
        stats.space += 1;
        grew |= write_or_grow(
            device,
            queue,
            &mut shared.faces,
            "manifold_faces",
            bytemuck::cast_slice(&space.faces),
            stats,
        ) | write_or_grow(
            device,
            queue,
            &mut shared.cell_table,
            "manifold_cell_table",
            bytemuck::cast_slice(&space.cell_table),
            stats,
        );
        shared.space = space.clone();
    }
    if !Arc::ptr_eq(&shared.objects, objects) {
        stats.objects += 1;
        // A moved instance changes its matrix, not its mesh: the BVHs
        // stay uploaded.
        let same_meshes = shared.objects.mesh_data == objects.mesh_data;
        for (slot, (label, data)) in shared.objects_mut().into_iter().zip(object_data(objects)) {
            if !(same_meshes && label == "manifold_mesh_data") {
                grew |= write_or_grow(device, queue, slot, label, data, stats);
            }
        }
        shared.objects = objects.clone();
    }
    if grew {
        shared.made += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::view_frustum;
    use bevy::camera::{CameraProjection, PerspectiveProjection};
    use bevy::math::{Mat4, Vec4};

    /// Bevy's own perspective keeps the symmetric path (the desktop image
    /// is traced exactly as before); an OpenXR eye's `glFrustum`-style
    /// matrix gives back its slopes.
    #[test]
    fn the_tracer_reads_off_centre_frusta_and_leaves_the_desktop_alone() {
        for (w, h) in [(1280u32, 720u32), (640, 640), (333, 1000)] {
            let mut p = PerspectiveProjection::default();
            p.update(w as f32, h as f32);
            assert_eq!(view_frustum(p.get_clip_from_view(), w, h), None, "{w}x{h}");
        }
        let (l, r, b, t) = ((-0.87f32).tan(), 0.70f32.tan(), (-0.84f32).tan(), 0.77f32.tan());
        let m = Mat4::from_cols(
            Vec4::new(2.0 / (r - l), 0.0, 0.0, 0.0),
            Vec4::new(0.0, 2.0 / (t - b), 0.0, 0.0),
            Vec4::new((r + l) / (r - l), (t + b) / (t - b), 0.0, -1.0),
            Vec4::new(0.0, 0.0, 0.1, 0.0),
        );
        let f = view_frustum(m, 320, 240).expect("off-centre");
        let want = [(r - l) / 2.0, (t - b) / 2.0, (r + l) / 2.0, (t + b) / 2.0];
        for k in 0..4 {
            assert!((f[k] - want[k]).abs() < 1e-6, "{f:?} vs {want:?}");
        }
    }
}
