//! The product cameras' pass in Bevy's renderer: each frame a
//! [`ProductCamera`]'s scene is extracted and packed
//! ([`bevy_manifold_gpu::product::GpuProductScene`]), its buffers written
//! where what they hold changed ([`ProductBuffers`]: the params when the
//! view moves, the faces and balls when they change), and a
//! `Core3d` system, before Bevy's opaque pass as the main tracer's, draws
//! the product tracer's `product_fragment` entry over the viewport.
//! Ordinary meshes drawn by Bevy afterwards land over the trace.
//!
//! A camera that shades by cell (its view's `tint`) also binds the table
//! of cells about its eye ([`ProductCellWords`], made in the main world by
//! [`update_product_cells`]: the space's exact table once, grown on first
//! use, about half a second for the octagon's 22,289 cells in a release
//! build; the tiles about the eye each time it crosses a face).

use super::ProductCamera;
use bevy::camera::CompositingSpace;
use bevy::core_pipeline::core_3d::main_opaque_pass_3d;
use bevy::core_pipeline::{Core3d, Core3dSystems, FullscreenShader};
use bevy::platform::collections::HashMap;
use bevy::prelude::*;
use bevy::render::camera::ExtractedCamera;
use bevy::render::render_resource::{
    BindGroup, BindGroupEntry, BindGroupLayoutDescriptor, BindGroupLayoutEntry, BindingType, Buffer, BufferBindingType,
    BufferInitDescriptor, BufferUsages, CachedRenderPipelineId, ColorTargetState, ColorWrites, FragmentState,
    MultisampleState, PipelineCache, RenderPassDescriptor, RenderPipelineDescriptor, ShaderStages,
    SpecializedRenderPipeline, SpecializedRenderPipelines, TextureFormat,
};
use bevy::render::renderer::{RenderContext, RenderDevice, RenderQueue, ViewQuery};
use bevy::render::view::{ExtractedView, Msaa, ViewTarget};
use bevy::render::{
    Extract, ExtractSchedule, Render, RenderApp, RenderStartup, RenderSystems, sync_world::RenderEntity,
};
use bevy::shader::{Shader, ShaderDefVal};
use bevy::tasks::futures_lite::future;
use bevy::tasks::{AsyncComputeTaskPool, Task, block_on};
use bevy_manifold_core::space::product::ProductSpace;
use bevy_manifold_core::space::product_cells::{
    DEFAULT_PRODUCT_TABLE_CELLS, ProductCellTable, ProductCells, ProductElement,
};
use bevy_manifold_core::trace::product::{ProductLight, ProductLighting, ProductScene};
use bevy_manifold_gpu::product::{
    GpuProductCells, GpuProductLight, GpuProductScene, ProductMeshWords, ProductShaderDefs, storage_bytes,
};
use bevy_manifold_gpu::{CELL_TINT_WGSL, PRODUCT_WGSL};
use std::sync::{Arc, Weak};

/// The product cameras' pass: extract, prepare and draw. Added by
/// [`super::ProductPlugin`].
#[derive(Debug, Clone, Copy, Default)]
pub struct ProductRenderPlugin;

impl Plugin for ProductRenderPlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(PostUpdate, update_product_cells);
        let Some(render_app) = app.get_sub_app_mut(RenderApp) else {
            return;
        };
        render_app
            .init_resource::<SpecializedRenderPipelines<ProductPipeline>>()
            .init_resource::<ProductBuffers>()
            .init_resource::<ProductLightJobs>()
            .add_systems(RenderStartup, init_product_pipeline)
            .add_systems(ExtractSchedule, extract_product_views)
            .add_systems(
                Render,
                prepare_product_views
                    .in_set(RenderSystems::PrepareBindGroups)
                    .run_if(resource_exists::<ProductPipeline>),
            )
            .add_systems(
                Core3d,
                product_pass.in_set(Core3dSystems::MainPass).before(main_opaque_pass_3d),
            );
    }

    fn finish(&self, app: &mut App) {
        let Some(mut shaders) = app.world_mut().get_resource_mut::<Assets<Shader>>() else {
            return;
        };
        let tint = shaders.add(Shader::from_wgsl(CELL_TINT_WGSL.source, CELL_TINT_WGSL.path));
        let shader = shaders.add(Shader::from_wgsl(PRODUCT_WGSL.source, PRODUCT_WGSL.path));
        if let Some(render_app) = app.get_sub_app_mut(RenderApp) {
            render_app.insert_resource(ProductShader(shader, tint));
        }
    }
}

/// The embedded `product.wgsl` and the `cell_tint.wgsl` it imports, as
/// shader assets (render world).
#[derive(Resource, Clone)]
pub struct ProductShader(pub Handle<Shader>, pub Handle<Shader>);

/// A product camera's scene in the render world, packed.
#[derive(Component, Clone, Debug)]
pub struct ExtractedProductView {
    /// The scene as the GPU reads it (its size set by prepare).
    pub packed: GpuProductScene,
    /// The table of cells about the eye, where the camera shades by cell.
    pub cells: Option<Arc<GpuProductCells>>,
}

/// The table of cells about a [`ProductCamera`]'s eye, packed for the
/// GPU, on a camera whose view shades by cell (main world; made by
/// [`update_product_cells`], extracted with the camera).
#[derive(Component, Clone, Debug)]
pub struct ProductCellWords {
    /// The space it was made for.
    space: Weak<ProductSpace>,
    /// The eye's copy it was made about.
    eye: Option<ProductElement>,
    /// The words.
    pub cells: Arc<GpuProductCells>,
}

/// Each space's exact cells and table, grown once (by the space's
/// address, held weakly so a dropped space's entry is not taken for a
/// new one at the same address).
type CellTables = HashMap<usize, (Weak<ProductSpace>, Option<Arc<(ProductCells, ProductCellTable)>>)>;

/// Gives each product camera that shades by cell the table of cells
/// about its eye ([`ProductCellWords`]), made again when its eye's copy
/// or its space changes; takes it off cameras that stop shading by cell.
/// A space without exact cells gets an empty table (its copies shade
/// `CellTint::UNKNOWN`).
pub fn update_product_cells(
    mut commands: Commands,
    cameras: Query<(Entity, &ProductCamera, Option<&ProductCellWords>)>,
    mut tables: Local<CellTables>,
) {
    tables.retain(|_, (space, _)| space.strong_count() > 0);
    for (entity, camera, words) in &cameras {
        if camera.view.tint.is_none() {
            if words.is_some() {
                commands.entity(entity).remove::<ProductCellWords>();
            }
            continue;
        }
        let same_space = |w: &ProductCellWords| w.space.upgrade().is_some_and(|s| Arc::ptr_eq(&s, &camera.space));
        if words.is_some_and(|w| w.eye == camera.view.cell && same_space(w)) {
            continue;
        }
        let key = Arc::as_ptr(&camera.space) as usize;
        let (_, exact) = tables.entry(key).or_insert_with(|| {
            let exact = ProductCells::of(&camera.space).map(|cells| {
                let table = ProductCellTable::grow(&cells, DEFAULT_PRODUCT_TABLE_CELLS);
                Arc::new((cells, table))
            });
            (Arc::downgrade(&camera.space), exact)
        });
        let cells = match exact {
            Some(exact) => GpuProductCells::pack(&exact.0, &exact.1, camera.view.cell.as_ref()),
            None => GpuProductCells::none(),
        };
        commands.entity(entity).insert(ProductCellWords {
            space: Arc::downgrade(&camera.space),
            eye: camera.view.cell,
            cells: Arc::new(cells),
        });
    }
}

/// What the pass needs to draw a product view this frame.
#[derive(Component, Clone)]
pub struct ProductViewBinding {
    /// The specialised pipeline.
    pub pipeline: CachedRenderPipelineId,
    /// Group 0: the params, the faces, the balls.
    pub bind_group: BindGroup,
}

/// What [`extract_product_views`] reads of a camera: its render entity,
/// the camera and its product camera, with their change ticks.
type ExtractedCameraItem = (
    RenderEntity,
    Ref<'static, Camera>,
    Option<Ref<'static, ProductCamera>>,
    Option<Ref<'static, ProductCellWords>>,
);

/// The light images of the product cameras' scenes (the render world's
/// resource), worked out off the main thread on Bevy's async compute
/// pool and shared by every camera that shows the same lights in the
/// same space (a headset's two eyes share one). In genus 2 x S1 they
/// take about 65 ms; a camera whose lights change keeps drawing its
/// last ones until the new ones are ready, and only a camera that has
/// none yet (its first frame) waits for them.
#[derive(Resource, Default)]
pub struct ProductLightJobs {
    jobs: Vec<LightJob>,
    /// Light images worked out so far (a job per change of lights, not
    /// per camera).
    pub started: u64,
}

/// One scene's lights and their images, ready or being worked out.
struct LightJob {
    space: Arc<ProductSpace>,
    lights: Vec<ProductLight>,
    lighting: ProductLighting,
    state: LightState,
    /// Asked for since the last sweep of unused jobs.
    used: bool,
}

enum LightState {
    Ready(Arc<Vec<GpuProductLight>>),
    Pending(Task<Vec<GpuProductLight>>),
}

impl ProductLightJobs {
    /// `scene`'s light images in `space`: ready, or `None` while they are
    /// worked out off the main thread (started on the first ask); with
    /// `wait`, waited for.
    fn get(
        &mut self,
        space: &Arc<ProductSpace>,
        scene: &ProductScene,
        wait: bool,
    ) -> Option<Arc<Vec<GpuProductLight>>> {
        let same = |j: &LightJob| {
            (Arc::ptr_eq(&j.space, space) || *j.space == **space)
                && j.lights == scene.lights
                && j.lighting == scene.lighting
        };
        let k = match self.jobs.iter().position(same) {
            Some(k) => k,
            None => {
                let (s, sc) = (space.clone(), scene.clone());
                let state = if scene.lights.is_empty() {
                    LightState::Ready(Arc::new(Vec::new()))
                } else {
                    self.started += 1;
                    LightState::Pending(
                        AsyncComputeTaskPool::get().spawn(async move { GpuProductScene::pack_lights(&s, &sc) }),
                    )
                };
                self.jobs.push(LightJob {
                    space: space.clone(),
                    lights: scene.lights.clone(),
                    lighting: scene.lighting,
                    state,
                    used: false,
                });
                self.jobs.len() - 1
            }
        };
        let job = &mut self.jobs[k];
        job.used = true;
        if let LightState::Pending(task) = &mut job.state {
            let done = if wait {
                Some(block_on(task))
            } else {
                block_on(future::poll_once(task))
            };
            if let Some(images) = done {
                job.state = LightState::Ready(Arc::new(images));
            }
        }
        match &job.state {
            LightState::Ready(images) => Some(images.clone()),
            LightState::Pending(_) => None,
        }
    }

    /// Drops the jobs no camera asked for since the last sweep.
    fn sweep(&mut self) {
        self.jobs.retain(|j| j.used);
        for j in &mut self.jobs {
            j.used = false;
        }
    }
}

/// What a camera was last packed with: its light images (kept while
/// new ones are worked out) and its meshes' words.
#[derive(Default)]
pub struct KeptPacking {
    lights: Option<Arc<Vec<GpuProductLight>>>,
    words: Option<Arc<ProductMeshWords>>,
    /// Packed with stale lights: packed again each frame until the new
    /// ones are ready.
    stale: bool,
}

/// Copies each active product camera's scene, packed, to its render
/// entity when the camera or its scene changed (the render entity keeps
/// it otherwise); takes it off cameras that no longer have one. A
/// camera's light images are worked out again only when its space, lights
/// or lighting change, off the main thread and once for every camera
/// that shows them ([`ProductLightJobs`]), and its meshes' words only when
/// its meshes change, not as its eye (or a mesh) moves.
pub fn extract_product_views(
    mut commands: Commands,
    cameras: Extract<Query<ExtractedCameraItem>>,
    mut jobs: ResMut<ProductLightJobs>,
    mut kept: Local<HashMap<Entity, KeptPacking>>,
) {
    let mut live = Vec::new();
    for (entity, camera, product, words) in &cameras {
        match product.filter(|_| camera.is_active) {
            Some(p) => {
                live.push(entity);
                let words = words.filter(|_| p.view.tint.is_some());
                let kept = kept.entry(entity).or_default();
                let changed = p.is_changed() || camera.is_changed() || words.as_ref().is_some_and(Ref::is_changed);
                if changed || kept.stale {
                    let scene = p.scene();
                    let fresh = jobs.get(&p.space, &scene, kept.lights.is_none());
                    kept.stale = fresh.is_none();
                    if let Some(fresh) = fresh {
                        kept.lights = Some(fresh);
                    }
                    let lights = kept.lights.as_deref().cloned().unwrap_or_default();
                    let mesh_words = ProductMeshWords::get(kept.words.as_ref(), &scene.meshes);
                    kept.words = Some(mesh_words.clone());
                    let mut packed = GpuProductScene::pack_with(&p.space, &scene, (lights, mesh_words), (1, 1));
                    let cells = words.map(|w| w.cells.clone());
                    packed.params.cell_count = cells.as_ref().map_or(0, |c| c.count);
                    commands.entity(entity).insert(ExtractedProductView { packed, cells });
                }
            }
            None => {
                commands
                    .entity(entity)
                    .remove::<(ExtractedProductView, ProductViewBinding)>();
            }
        }
    }
    kept.retain(|e, _| live.contains(e));
    jobs.sweep();
}

/// What the product pipeline is specialised on: the view target.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ProductPipelineKey {
    /// The view target's format.
    pub format: TextureFormat,
    /// Its sample count.
    pub samples: u32,
    /// The shader encodes sRGB itself (`ENCODE_SRGB`).
    pub encode_srgb: bool,
    /// The code the view's scene needs (cells, lights).
    pub defs: ProductShaderDefs,
}

/// The product pipeline's layout and shader (render world).
#[derive(Resource, Clone)]
pub struct ProductPipeline {
    /// Group 0: params (uniform), faces, balls, the cell table, the
    /// light images, the mesh images and the meshes' words (storage).
    pub layout: BindGroupLayoutDescriptor,
    shader: Handle<Shader>,
    fullscreen: FullscreenShader,
}

fn init_product_pipeline(
    mut commands: Commands,
    shader: Option<Res<ProductShader>>,
    fullscreen: Res<FullscreenShader>,
) {
    let Some(shader) = shader else {
        error!("bevy_manifold: the product tracer shader was not registered; product cameras will not render");
        return;
    };
    let entry = |binding, ty| BindGroupLayoutEntry {
        binding,
        visibility: ShaderStages::FRAGMENT,
        ty: BindingType::Buffer {
            ty,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    };
    let read = BufferBindingType::Storage { read_only: true };
    let layout = BindGroupLayoutDescriptor::new(
        "manifold_product",
        &[
            entry(0, BufferBindingType::Uniform),
            entry(1, read),
            entry(2, read),
            // 3 is the compute entry's pixels.
            entry(4, read),
            entry(5, read),
            entry(6, read),
            entry(7, read),
        ],
    );
    commands.insert_resource(ProductPipeline {
        layout,
        shader: shader.0.clone(),
        fullscreen: fullscreen.clone(),
    });
}

impl SpecializedRenderPipeline for ProductPipeline {
    type Key = ProductPipelineKey;

    fn specialize(&self, key: Self::Key) -> RenderPipelineDescriptor {
        let mut shader_defs: Vec<ShaderDefVal> = if key.encode_srgb {
            vec!["ENCODE_SRGB".into()]
        } else {
            Vec::new()
        };
        shader_defs.extend(key.defs.names().into_iter().map(ShaderDefVal::from));
        RenderPipelineDescriptor {
            label: Some("manifold_product".into()),
            layout: vec![self.layout.clone()],
            vertex: self.fullscreen.to_vertex_state(),
            fragment: Some(FragmentState {
                shader: self.shader.clone(),
                shader_defs,
                entry_point: Some("product_fragment".into()),
                targets: vec![Some(ColorTargetState {
                    format: key.format,
                    blend: None,
                    write_mask: ColorWrites::ALL,
                })],
            }),
            multisample: MultisampleState {
                count: key.samples,
                ..default()
            },
            ..default()
        }
    }
}

/// A product view's buffers and bind group, kept between frames: the
/// params written again when the view moves, the faces and balls when
/// they change, everything made again when their counts change.
struct ProductViewBuffers {
    scene: GpuProductScene,
    cells: Option<Arc<GpuProductCells>>,
    params: Buffer,
    faces: Buffer,
    balls: Buffer,
    table: Buffer,
    lights: Buffer,
    meshes: Buffer,
    mesh_data: Buffer,
    bind_group: BindGroup,
}

/// The words a view's cell table binds (one zero word where it has none).
fn table_words(cells: Option<&Arc<GpuProductCells>>) -> &[u32] {
    cells.map_or(&[], |c| c.words.as_slice())
}

/// The product views' buffers, by render entity, and what was uploaded.
#[derive(Resource, Default)]
pub struct ProductBuffers {
    views: HashMap<Entity, ProductViewBuffers>,
    /// What has been uploaded so far.
    pub uploads: ProductUploads,
}

/// What the product views have uploaded since the app started: how many
/// writes of each kind and their bytes (for the tests, and to see that a
/// still view uploads nothing).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ProductUploads {
    /// Writes of a view's params (its eye moved or turned, its size
    /// changed).
    pub params: u64,
    /// Writes of a view's faces or balls.
    pub scenes: u64,
    /// Writes of a view's cell table (its eye crossed a face).
    pub tables: u64,
    /// Bytes written, buffers made new included.
    pub bytes: u64,
}

/// Each product view's params (its viewport's size and place), buffers,
/// bind group and pipeline. A view's buffers are kept between frames and
/// written only where what they hold changed.
#[allow(clippy::too_many_arguments, reason = "a render system's resources")]
pub fn prepare_product_views(
    mut commands: Commands,
    views: Query<(
        Entity,
        &ExtractedProductView,
        &ExtractedView,
        &ExtractedCamera,
        Option<&Msaa>,
    )>,
    pipeline: Res<ProductPipeline>,
    mut pipelines: ResMut<SpecializedRenderPipelines<ProductPipeline>>,
    pipeline_cache: Res<PipelineCache>,
    device: Res<RenderDevice>,
    queue: Res<RenderQueue>,
    mut buffers: ResMut<ProductBuffers>,
) {
    let buffers = &mut *buffers;
    for (entity, view, extracted, camera, msaa) in &views {
        let mut scene = view.packed.clone();
        scene.params.width = extracted.viewport.z.max(1);
        scene.params.height = extracted.viewport.w.max(1);
        scene.params.origin_x = extracted.viewport.x;
        scene.params.origin_y = extracted.viewport.y;
        let uploads = &mut buffers.uploads;
        let cells = view.cells.clone();
        let kept = buffers.views.get_mut(&entity).filter(|b| {
            b.scene.faces.len() == scene.faces.len()
                && b.scene.balls.len() == scene.balls.len()
                && b.scene.lights.len() == scene.lights.len()
                && b.scene.meshes.len() == scene.meshes.len()
                && b.scene.mesh_data.words.len() == scene.mesh_data.words.len()
                && table_words(b.cells.as_ref()).len() == table_words(cells.as_ref()).len()
        });
        let bind_group = match kept {
            Some(kept) => {
                if kept.scene.params != scene.params {
                    queue.write_buffer(&kept.params, 0, bytemuck::bytes_of(&scene.params));
                    uploads.params += 1;
                    uploads.bytes += std::mem::size_of_val(&scene.params) as u64;
                }
                for (old, new, buffer) in [
                    (
                        bytemuck::cast_slice::<_, u8>(&kept.scene.faces),
                        bytemuck::cast_slice::<_, u8>(&scene.faces),
                        &kept.faces,
                    ),
                    (
                        bytemuck::cast_slice(&kept.scene.balls),
                        bytemuck::cast_slice(&scene.balls),
                        &kept.balls,
                    ),
                    (
                        bytemuck::cast_slice(&kept.scene.lights),
                        bytemuck::cast_slice(&scene.lights),
                        &kept.lights,
                    ),
                    (
                        bytemuck::cast_slice(&kept.scene.meshes),
                        bytemuck::cast_slice(&scene.meshes),
                        &kept.meshes,
                    ),
                ] {
                    if old != new && !new.is_empty() {
                        queue.write_buffer(buffer, 0, new);
                        uploads.scenes += 1;
                        uploads.bytes += new.len() as u64;
                    }
                }
                // The meshes' words, compared only where they were made
                // again (the same meshes share them).
                if !Arc::ptr_eq(&kept.scene.mesh_data, &scene.mesh_data)
                    && kept.scene.mesh_data.words != scene.mesh_data.words
                    && !scene.mesh_data.words.is_empty()
                {
                    let words = bytemuck::cast_slice(&scene.mesh_data.words);
                    queue.write_buffer(&kept.mesh_data, 0, words);
                    uploads.scenes += 1;
                    uploads.bytes += words.len() as u64;
                }
                let same_table = match (&kept.cells, &cells) {
                    (Some(a), Some(b)) => Arc::ptr_eq(a, b) || a.words == b.words,
                    (a, b) => a.is_none() && b.is_none(),
                };
                if !same_table && !table_words(cells.as_ref()).is_empty() {
                    let words = bytemuck::cast_slice(table_words(cells.as_ref()));
                    queue.write_buffer(&kept.table, 0, words);
                    uploads.tables += 1;
                    uploads.bytes += words.len() as u64;
                }
                kept.scene = scene;
                kept.cells = cells;
                kept.bind_group.clone()
            }
            None => {
                let made = ProductViewBuffers::new(&device, &pipeline_cache, &pipeline, (scene, cells), uploads);
                let bind_group = made.bind_group.clone();
                buffers.views.insert(entity, made);
                bind_group
            }
        };
        let key = ProductPipelineKey {
            format: extracted.target_format,
            samples: msaa.map_or(1, Msaa::samples),
            encode_srgb: camera.compositing_space == Some(CompositingSpace::Srgb),
            defs: ProductShaderDefs::of(&view.packed.params),
        };
        let id = pipelines.specialize(&pipeline_cache, &pipeline, key);
        commands.entity(entity).insert(ProductViewBinding {
            pipeline: id,
            bind_group,
        });
    }
    // The buffers of views that are gone.
    buffers.views.retain(|e, _| views.contains(*e));
}

impl ProductViewBuffers {
    /// A view's buffers made and filled, and its bind group.
    fn new(
        device: &RenderDevice,
        pipeline_cache: &PipelineCache,
        pipeline: &ProductPipeline,
        (scene, cells): (GpuProductScene, Option<Arc<GpuProductCells>>),
        uploads: &mut ProductUploads,
    ) -> Self {
        let mut buffer = |label: &'static str, contents: &[u8], usage: BufferUsages| {
            uploads.bytes += contents.len() as u64;
            device.create_buffer_with_data(&BufferInitDescriptor {
                label: Some(label),
                contents,
                usage: usage | BufferUsages::COPY_DST,
            })
        };
        let params = buffer(
            "manifold_product_params",
            bytemuck::bytes_of(&scene.params),
            BufferUsages::UNIFORM,
        );
        let faces = buffer(
            "manifold_product_faces",
            &storage_bytes(&scene.faces),
            BufferUsages::STORAGE,
        );
        let balls = buffer(
            "manifold_product_balls",
            &storage_bytes(&scene.balls),
            BufferUsages::STORAGE,
        );
        let table = buffer(
            "manifold_product_cells",
            &storage_bytes(table_words(cells.as_ref())),
            BufferUsages::STORAGE,
        );
        let lights = buffer(
            "manifold_product_lights",
            &storage_bytes(&scene.lights),
            BufferUsages::STORAGE,
        );
        let meshes = buffer(
            "manifold_product_meshes",
            &storage_bytes(&scene.meshes),
            BufferUsages::STORAGE,
        );
        let mesh_data = buffer(
            "manifold_product_mesh_data",
            &storage_bytes(&scene.mesh_data.words),
            BufferUsages::STORAGE,
        );
        uploads.params += 1;
        uploads.scenes += 5;
        uploads.tables += 1;
        let bind_group = device.create_bind_group(
            "manifold_product",
            &pipeline_cache.get_bind_group_layout(&pipeline.layout),
            &[
                BindGroupEntry {
                    binding: 0,
                    resource: params.as_entire_binding(),
                },
                BindGroupEntry {
                    binding: 1,
                    resource: faces.as_entire_binding(),
                },
                BindGroupEntry {
                    binding: 2,
                    resource: balls.as_entire_binding(),
                },
                BindGroupEntry {
                    binding: 4,
                    resource: table.as_entire_binding(),
                },
                BindGroupEntry {
                    binding: 5,
                    resource: lights.as_entire_binding(),
                },
                BindGroupEntry {
                    binding: 6,
                    resource: meshes.as_entire_binding(),
                },
                BindGroupEntry {
                    binding: 7,
                    resource: mesh_data.as_entire_binding(),
                },
            ],
        );
        Self {
            scene,
            cells,
            params,
            faces,
            balls,
            table,
            lights,
            meshes,
            mesh_data,
            bind_group,
        }
    }
}

/// Draws one product view over its viewport.
pub fn product_pass(
    view: ViewQuery<(&ExtractedCamera, &ViewTarget, &ProductViewBinding)>,
    pipeline_cache: Res<PipelineCache>,
    mut ctx: RenderContext,
) {
    let (camera, target, binding) = view.into_inner();
    // Still compiling: the view shows its clear colour this frame.
    let Some(pipeline) = pipeline_cache.get_render_pipeline(binding.pipeline) else {
        return;
    };
    let color = [Some(target.get_color_attachment())];
    let mut pass = ctx.begin_tracked_render_pass(RenderPassDescriptor {
        label: Some("manifold_product"),
        color_attachments: &color,
        depth_stencil_attachment: None,
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    });
    if let Some(viewport) = camera.viewport.as_ref() {
        pass.set_camera_viewport(viewport);
    }
    pass.set_render_pipeline(pipeline);
    pass.set_bind_group(0, &binding.bind_group, &[]);
    pass.draw(0..3, 0..1);
}
