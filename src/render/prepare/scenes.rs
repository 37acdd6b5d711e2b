//! Each space's scene packed for the GPU ([`prepare_manifold_scenes`]),
//! kept per space root in [`ManifoldPackedScenes`].

use super::super::extract::ExtractedManifoldView;
use crate::drawables::ManifoldScene;
use crate::space::Space;
use crate::space::element::CellElement;
use crate::trace::FlatScene;
use bevy::platform::collections::{HashMap, HashSet};
use bevy::prelude::*;
use bevy::tasks::futures_lite::future::{block_on, poll_once};
use bevy::tasks::{AsyncComputeTaskPool, Task};
use bevy_manifold_gpu::{GpuObjects, PackedSpace};
use std::sync::Arc;

/// One space's scene, packed for the GPU, and what it was packed from.
struct PackedScene {
    space: Arc<Space>,
    generation: u64,
    /// The faces and the cell table, centred on a camera's cell.
    packed: PackedSpace,
    /// The table being recentred on another cell, off the frame.
    pending: Option<(CellElement, Task<PackedSpace>)>,
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
    pub fn get(&self, root: Entity) -> Option<(&PackedSpace, &Arc<GpuObjects>)> {
        self.scenes.get(&root).map(|p| (&p.packed, &p.objects))
    }
}

/// Packs each space's scene for the GPU when its generation or its space
/// changed (in f32, as the CPU tracer's f32 mode reads it), and recentres
/// its cell table on the camera's cell when that changed. A repacked scene
/// equal to the old one keeps the old `Arc`, so nothing is uploaded.
pub fn prepare_manifold_scenes(views: Query<&ExtractedManifoldView>, mut packed: ResMut<ManifoldPackedScenes>) {
    let mut seen = HashSet::new();
    for view in &views {
        if !seen.insert(view.root) {
            continue;
        }
        let space = view.space.shared();
        let generation = view.scene.generation();
        // The camera's cell, exactly (the first view into the space
        // decides where the table is centred; every view finds its own
        // cell in it: `PackedSpace::index_of`).
        let centre = match &view.cell {
            // A camera not yet crossed (or placed by hand): located once.
            CellElement::Float(m) => space.cell_of_matrix(m),
            exact => exact.clone(),
        };
        match packed.scenes.get_mut(&view.root) {
            Some(old) if Arc::ptr_eq(&old.space, space) => old.update(space, &view.scene, centre, generation),
            _ => {
                packed
                    .scenes
                    .insert(view.root, PackedScene::new(space, &view.scene, centre, generation));
            }
        }
    }
    packed.scenes.retain(|root, _| seen.contains(root));
}

impl PackedScene {
    /// `scene` in `space` packed for a camera in `centre`.
    fn new(space: &Arc<Space>, scene: &ManifoldScene, centre: CellElement, generation: u64) -> Self {
        let objects = GpuObjects::pack(&flat_scene(space, scene, &centre));
        let packed = PackedSpace::pack(space, centre);
        if packed.table_pending(space) {
            // Grown off the frame (0.4 s in Seifert-Weber, 1.5 s in the
            // mirrored dodecahedron); until then the camera's own cell is
            // exact and the rest grey.
            let space = space.clone();
            AsyncComputeTaskPool::get()
                .spawn(async move {
                    if let crate::space::cells::CellScheme::Exact(exact) = space.cells() {
                        exact.table();
                    }
                })
                .detach();
        }
        PackedScene {
            space: space.clone(),
            generation,
            packed,
            pending: None,
            objects: Arc::new(objects),
        }
    }

    /// The same space, seen from a camera in `centre`, its scene at
    /// `generation`: the table repacked once it has grown, recentred when
    /// the camera's cell changed, the objects repacked when the scene
    /// changed or the camera's cell did (a camera-attached mesh's home is
    /// the camera's cell).
    fn update(&mut self, space: &Arc<Space>, scene: &ManifoldScene, centre: CellElement, generation: u64) {
        // A table still growing: repacked once it has grown.
        if self.packed.outgrown(space) {
            self.packed = PackedSpace::pack(space, self.packed.centre().clone());
            self.pending = None;
        }
        let moved = *self.packed.centre() != centre;
        if moved {
            if matches!(centre, CellElement::Exact(_)) {
                // Only the table's ids move with the camera (11 ms in
                // Seifert-Weber's 16,129 cells, 35 in the mirrored
                // dodecahedron's 57,741): recomputed off the frame on the
                // async compute pool, while the views walk the old table
                // from the camera's cell in it (`PackedSpace::index_of`).
                if self.pending.as_ref().is_none_or(|(c, _)| *c != centre) {
                    let (packed, space, target) = (self.packed.clone(), space.clone(), centre.clone());
                    let task = AsyncComputeTaskPool::get().spawn(async move { packed.recentred(&space, target) });
                    self.pending = Some((centre.clone(), task));
                }
                if let Some((_, task)) = &mut self.pending
                    && let Some(recentred) = block_on(poll_once(task))
                {
                    self.packed = recentred;
                    self.pending = None;
                }
            } else {
                self.packed = self.packed.recentred(space, centre.clone());
            }
        }
        if !moved && self.generation == generation {
            return;
        }
        // The scene changed, or it is the same but a camera-attached
        // mesh's home (the copy not drawn) is the camera's new cell.
        let objects = GpuObjects::pack(&flat_scene(space, scene, &centre));
        if *self.objects != objects {
            self.objects = Arc::new(objects);
        }
        self.generation = generation;
    }
}

/// The scene's objects seen from the camera's cell `cell`: the objects
/// are copies in every cell, but a camera-attached mesh's home (its copy
/// that is the camera's own body, not drawn) is the copy the camera is in.
/// CPU twin: the scene a headless render packs (`FlatScene::new` with the
/// camera's word).
fn flat_scene(space: &Space, scene: &ManifoldScene, cell: &CellElement) -> FlatScene<f32> {
    let flat = FlatScene::<f32>::new(space, scene.scene()).in_cell(space, cell);
    let most = bevy_manifold_gpu::bindings::MAX_BALLS;
    if flat.balls.len() > most {
        warn!(
            "the manifold scene makes {} balls (ghost copies and edge joints included); the GPU draws the first {most}",
            flat.balls.len()
        );
    }
    flat
}
