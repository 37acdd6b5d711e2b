//! Packing for the GPU: the space ([`GpuSpace`], kept in a
//! [`PackedSpace`]), the scene's objects ([`GpuObjects`]) and the view
//! ([`GpuView`]) into the [`GpuParams`] uniform and the buffers of
//! [`crate::bindings::BINDINGS`], from the same [`FlatScene`] the CPU
//! tracer reads (in f32), so both trace identical inputs. The render pass
//! and the headless runner pack through here alike.

mod objects;
mod space;

pub use objects::GpuObjects;
pub use space::{GpuSpace, PackedSpace};

use crate::bindings::Binding;
use crate::layout::{GpuParams, settings_flags};
use bevy_manifold_core::space::Space;
use bevy_manifold_core::space::cells::CellScheme;
use bevy_manifold_core::space::element::CellElement;
use bevy_manifold_core::trace::{FlatScene, TraceSettings, pixel_half_angle_of};
use bytemuck::Zeroable;
use glam::{Mat4, Vec4};

/// The per-frame view: where the camera is and what the frame looks like.
#[derive(Clone, Debug, PartialEq)]
pub struct GpuView {
    /// The camera isometry, inside the domain.
    pub camera: Mat4,
    /// The camera's cell element (f64: its id is computed from it).
    pub camera_cell: glam::DMat4,
    /// The same, exact where the space's ids are: where the walk starts
    /// in the cell table ([`PackedSpace::index_of`]).
    pub camera_element: CellElement,
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
    /// The point of each light's disc its shadow rays aim at
    /// ([`GpuParams::light_sample_u`]); `[0, 0]`, the centre, unless an
    /// accumulating view's sample moves it ([`GpuParams::sample`]).
    pub light_sample: [f32; 2],
    /// Reflections: the most reflections a ray takes (read under the
    /// `REFLECTIONS` def).
    pub reflections: u32,
    /// Path tracing (`PATH_TRACE`): the most bounces, the seed and the
    /// sample's index.
    pub path: [u32; 3],
}

/// `bevy_manifold_core::trace::light_sample_point(k)` as the GPU reads it.
fn light_sample(k: u32) -> [f32; 2] {
    bevy_manifold_core::trace::light_sample_point(k).map(|u| u as f32)
}

/// Everything one trace uploads.
#[derive(Clone, Debug)]
pub struct GpuScene {
    /// The uniform.
    pub params: GpuParams,
    /// The space's faces and cell table.
    pub space: std::sync::Arc<GpuSpace>,
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

fn bits(v: [f32; 3], w: u32) -> [u32; 4] {
    [v[0].to_bits(), v[1].to_bits(), v[2].to_bits(), w]
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

impl GpuParams {
    /// The uniform for one view of `objects` in `space`, packed as
    /// `packed`.
    #[must_use]
    pub fn new(space: &Space, packed: &PackedSpace, objects: &GpuObjects, view: &GpuView) -> Self {
        let (fog_density, fog_color) = view.fog.unwrap_or((0.0, [0.0; 3]));
        let camera_cell_index = match space.cells() {
            CellScheme::Finite { .. } => space.cell_id(&view.camera_cell).0 as u32,
            CellScheme::Exact(_) => packed.index_of(space, &view.camera_element),
            _ => 0,
        };
        let packed = packed.gpu();
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
            camera_cell_index,
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
            light_sample_u: view.light_sample[0],
            ball_leaves: objects.ball_nodes.len().saturating_sub(2) as u32,
            chart_stretch: objects.cone[2],
            footprint_cap: objects.cone[3],
            light_sample_v: view.light_sample[1],
            frustum: view.frustum.unwrap_or([0.0; 4]),
            cone: [view.footprint, objects.cone[0], packed.near_scale, objects.cone[1]],
            occupied: occupied(&objects.groups),
            reflections: view.reflections.min(bevy_manifold_core::trace::MAX_REFLECTIONS),
            path_depth: view.path[0].min(bevy_manifold_core::trace::MAX_PATH_DEPTH),
            seed: view.path[1],
            sample: view.path[2],
            instance_trees: objects.instance_trees,
            pad_a: 0,
            pad_b: 0,
            pad_c: 0,
        }
    }
}

impl GpuParams {
    /// The same view with its pixel grid moved by `offset` pixels
    /// (`bevy_manifold_core::trace::sample_offset`: a sample of an
    /// accumulating view), its frustum made off-centre by as much. Needs
    /// the frustum given whole (`frustum`'s half-sizes set), as a view
    /// traced into textures of its own has it. CPU twin:
    /// `bevy_manifold_core::trace::Frustum::jittered`.
    #[must_use]
    pub fn jittered(mut self, [ox, oy]: [f64; 2]) -> Self {
        self.jitter([ox, oy]);
        self
    }

    /// The `k`-th sample of an accumulating view: its pixel grid moved by
    /// `bevy_manifold_core::trace::sample_offset(k)` ([`GpuParams::jittered`])
    /// and its shadow rays aimed at the `k`-th point of each light's disc
    /// (`light_sample_point(k)`: soft shadows). CPU twin: the `k`-th
    /// trace of `bevy_manifold_core::trace::accumulate`.
    #[must_use]
    pub fn sample(mut self, k: u32) -> Self {
        self.jitter(bevy_manifold_core::trace::sample_offset(k));
        [self.light_sample_u, self.light_sample_v] = light_sample(k);
        self.sample = k;
        self
    }

    fn jitter(&mut self, [ox, oy]: [f64; 2]) {
        let (w, h) = (f64::from(self.width), f64::from(self.height));
        let [hw, hh, cx, cy] = self.frustum.map(f64::from);
        self.frustum[2] = (cx + 2.0 * hw / w * ox) as f32;
        self.frustum[3] = (cy - 2.0 * hh / h * oy) as f32;
    }
}

impl GpuScene {
    /// Packs a prepared scene for the GPU, growing the space's cell table
    /// first where it has exact ids and has not grown yet.
    #[must_use]
    pub fn pack(space: &Space, flat: &FlatScene<f32>, settings: &TraceSettings) -> Self {
        Self::pack_in(space, &Self::pack_space(space, flat), flat, settings)
    }

    /// The space's part of [`GpuScene::pack`]: its faces and its cell
    /// table (grown here if it is not yet), centred on the camera's cell.
    #[must_use]
    pub fn pack_space(space: &Space, flat: &FlatScene<f32>) -> PackedSpace {
        if let CellScheme::Exact(exact) = space.cells() {
            exact.table();
        }
        PackedSpace::pack(space, flat.camera_element.clone())
    }

    /// [`GpuScene::pack`] with the space already packed ([`GpuScene::pack_space`]
    /// for this space and camera cell, or kept from an earlier frame).
    #[must_use]
    pub fn pack_in(space: &Space, packed: &PackedSpace, flat: &FlatScene<f32>, settings: &TraceSettings) -> Self {
        let objects = GpuObjects::pack(flat);
        let view = GpuView {
            camera: flat.camera,
            camera_cell: flat.camera_cell,
            camera_element: flat.camera_element.clone(),
            tan_half_fov: flat.tan_half_fov,
            frustum: flat.frustum,
            fog: flat.fog,
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
                pixel_half_angle_of(flat, settings) as f32
            } else {
                0.0
            },
            light_sample: light_sample(settings.light_sample),
            reflections: settings.reflections,
            path: [settings.path_depth, settings.seed, settings.light_sample],
        };
        GpuScene {
            params: GpuParams::new(space, packed, &objects, &view),
            space: packed.gpu().clone(),
            objects,
        }
    }
}

/// The bytes a space and a scene's objects put in the buffer of
/// `binding` ([`crate::bindings::BINDINGS`]); `None` for the params and
/// the compute entries' output, which belong to a view. The render pass
/// and the headless runner both fill their buffers by it.
///
/// ```
/// use bevy_manifold_core::prelude::*;
/// use bevy_manifold_gpu::bindings::BINDINGS;
/// use bevy_manifold_gpu::{GpuObjects, PackedSpace, binding_bytes};
/// use bevy_manifold_core::trace::FlatScene;
///
/// let space = catalog::torus(1.0);
/// let packed = PackedSpace::pack(&space, space.origin_cell());
/// let objects = GpuObjects::pack(&FlatScene::<f32>::new(&space, &Scene::default_for(&space)));
/// let faces = BINDINGS.iter().find(|b| b.name == "faces").unwrap();
/// assert_eq!(binding_bytes(faces, packed.gpu(), &objects).unwrap().len(), 6 * 160);
/// ```
#[must_use]
pub fn binding_bytes<'a>(binding: &Binding, space: &'a GpuSpace, objects: &'a GpuObjects) -> Option<&'a [u8]> {
    Some(match binding.name {
        "faces" => bytemuck::cast_slice(&space.faces),
        "cell_table" => bytemuck::cast_slice(&space.cell_table),
        "balls" => bytemuck::cast_slice(&objects.balls),
        "tubes" => bytemuck::cast_slice(&objects.tubes),
        "lights" => bytemuck::cast_slice(&objects.lights),
        "instances" => bytemuck::cast_slice(&objects.instances),
        "mesh_data" => bytemuck::cast_slice(&objects.mesh_data),
        "groups" => bytemuck::cast_slice(&objects.groups),
        "ball_nodes" => bytemuck::cast_slice(&objects.ball_nodes),
        _ => return None,
    })
}
