//! Extraction: each frame, what a manifold camera sees is copied to the
//! render world as an [`ExtractedManifoldView`]. The space and the scene
//! are shared `Arc`s (gathered once, in
//! [`crate::drawables::gather_scenes`]); only the camera is new data. The
//! prepare stage packs them for the GPU when they changed.

use super::pass::ManifoldViewBinding;
use crate::camera::{
    AccumulationProgress, CellShading, ManifoldAccumulation, ManifoldCamera, ManifoldFog, ManifoldFootprint,
    ManifoldPathTracer, ManifoldRenderScale,
};
use crate::drawables::ManifoldScene;
use crate::placement::{DomainCell, InSpace, ManifoldSpace, Placement};
use crate::space::element::CellElement;
use bevy::platform::collections::HashSet;
use bevy::prelude::*;
use bevy::render::{Extract, sync_world::RenderEntity};
use bevy_manifold_gpu::TraceDefs;
use glam::DMat4;

/// A manifold camera's view in the render world.
#[derive(Component, Clone, Debug)]
pub struct ExtractedManifoldView {
    /// The main-world root entity of the camera's space.
    pub root: Entity,
    /// The space.
    pub space: ManifoldSpace,
    /// What is drawn there.
    pub scene: ManifoldScene,
    /// The camera's placement (inside the domain).
    pub camera: DMat4,
    /// The camera's cell element, rounded to `f64` ([`DomainCell::element`]).
    pub element: DMat4,
    /// The same, exact where the space's ids are ([`DomainCell::cell`]):
    /// what the GPU's cell table is centred on.
    pub cell: CellElement,
    /// Fog density and linear colour, when on.
    pub fog: Option<(f32, [f32; 3])>,
    /// Most transports per ray.
    pub levels: u32,
    /// Rays stop after this distance.
    pub max_distance: f32,
    /// Most reflections a ray follows ([`ManifoldCamera::reflections`]).
    pub reflections: u32,
    /// Path tracing: the most bounces (0: off) and the seed
    /// ([`crate::camera::ManifoldPathTracer`]).
    pub path_depth: u32,
    /// The paths' seed.
    pub seed: u32,
    /// The shader defs this view needs.
    pub defs: TraceDefs,
    /// Per-cell shading words ([`crate::space::cells::CellTint::words`]).
    pub cell_tint: [u32; 3],
    /// The render scale ([`ManifoldRenderScale::get`]; 1 without one).
    pub scale: f32,
    /// Samples accumulated while still ([`ManifoldAccumulation`]; 1: off).
    pub samples: u32,
    /// Where the count of samples drawn goes, if the camera asks
    /// ([`AccumulationProgress`]).
    pub progress: Option<AccumulationProgress>,
}

/// Main-world data of one manifold camera.
type CameraData<'a> = (
    Entity,
    &'a RenderEntity,
    &'a Camera,
    &'a ManifoldCamera,
    &'a Placement,
    &'a DomainCell,
    Option<&'a InSpace>,
    Option<&'a ManifoldFog>,
    Option<&'a CellShading>,
    Option<&'a ManifoldRenderScale>,
    Option<&'a ManifoldAccumulation>,
    Has<ManifoldFootprint>,
    Option<&'a ManifoldPathTracer>,
    Option<&'a AccumulationProgress>,
);

/// Copies every active [`ManifoldCamera`]'s view to its render entity, and
/// takes it off render entities whose camera stopped being one. A camera
/// that is not under a [`ManifoldSpace`] is reported once and renders as a
/// plain camera.
pub fn extract_manifold_views(
    mut commands: Commands,
    cameras: Extract<Query<CameraData>>,
    roots: Extract<Query<(&ManifoldSpace, Option<&ManifoldScene>)>>,
    mut last: Local<HashSet<Entity>>,
    mut warned: Local<HashSet<Entity>>,
) {
    let mut now = HashSet::new();
    for (
        entity,
        render_entity,
        camera,
        mc,
        placement,
        cell,
        in_space,
        fog,
        shading,
        scale,
        accumulation,
        footprint,
        path,
        progress,
    ) in &cameras
    {
        if !camera.is_active {
            continue;
        }
        let root = in_space.map(InSpace::space);
        let Some((root, (space, scene))) = root.and_then(|r| Some((r, roots.get(r).ok()?))) else {
            if warned.insert(entity) {
                warn!("ManifoldCamera {entity} is not under a ManifoldSpace root: it renders as a plain camera");
            }
            continue;
        };
        // The scene is gathered in PostUpdate; a space created this frame
        // has none yet.
        let Some(scene) = scene else { continue };
        let fog = fog.and_then(ManifoldFog::to_fog).map(|f| (f.density as f32, f.color));
        let tint = shading.copied().unwrap_or_default().tint();
        let levels = mc.levels.min(crate::trace::MAX_LEVELS);
        let mut defs = TraceDefs::for_scene(space.space(), scene.scene(), tint.is_some())
            .for_rule(space.rule())
            .for_footprint(footprint)
            .for_reflections(mc.reflections)
            .for_path(path.map_or(0, |p| p.depth.clamp(1, crate::trace::MAX_PATH_DEPTH)));
        defs.fog = fog.is_some();
        commands.entity(render_entity.id()).insert(ExtractedManifoldView {
            root,
            space: space.clone(),
            scene: scene.clone(),
            camera: placement.isometry,
            element: cell.element,
            cell: cell.cell.clone(),
            fog,
            levels,
            // NaN or not positive: the default distance.
            max_distance: if mc.max_distance > 0.0 { mc.max_distance } else { 100.0 },
            reflections: mc.reflections.min(crate::trace::MAX_REFLECTIONS),
            path_depth: path.map_or(0, |p| p.depth.clamp(1, crate::trace::MAX_PATH_DEPTH)),
            seed: path.map_or(0, |p| p.seed),
            defs,
            cell_tint: tint.unwrap_or_default().words(),
            scale: scale.map_or(1.0, |s| s.get()),
            samples: accumulation.map_or(1, |a| a.samples.clamp(1, ManifoldAccumulation::MAX_SAMPLES)),
            progress: progress.cloned(),
        });
        now.insert(render_entity.id());
    }
    for gone in last.difference(&now) {
        if let Ok(mut e) = commands.get_entity(*gone) {
            e.remove::<(ExtractedManifoldView, ManifoldViewBinding)>();
        }
    }
    *last = now;
}
