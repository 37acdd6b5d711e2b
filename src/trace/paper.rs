//! The paper's scene, laid out once for the CPU/GPU tracer
//! ([`Scene::paper`]) and for Bevy entities
//! (`bevy_manifold::paper_scene`): the domain's edges as coloured tubes,
//! Suzanne attached to the camera (or free in front of it), the two hands
//! low left and right, a light at the eye. Every placement is given
//! relative to the camera, so the two versions agree.
//!
//! ```
//! use bevy_manifold::prelude::*;
//! use bevy_manifold::trace::{PaperOptions, SuzanneMode};
//! let space = catalog::poincare();
//! let free = Scene::paper(&space, &PaperOptions { suzanne: SuzanneMode::Free, ..PaperOptions::default() });
//! assert_eq!(free.meshes.len(), 3);
//! assert!(!free.meshes[0].attached);
//! let bare = Scene::paper(&space, &PaperOptions { suzanne: SuzanneMode::Hidden, hands: false, edges: false });
//! assert!(bare.meshes.is_empty() && bare.edge_radius.is_none());
//! ```

use super::scene::Scene;
use super::scene_mesh::{SceneMesh, builtin};
use crate::geometry::isometry;
use crate::mesh::MeshMaterial;
use crate::space::Space;
use glam::{DMat4, DVec3};
use serde::{Deserialize, Serialize};

/// Where Suzanne is.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum SuzanneMode {
    /// Attached to the camera, as in most of the paper's figures: the
    /// camera looks out of her head, so only her images in the other copies
    /// are seen.
    #[default]
    Attached,
    /// Left in front of where the camera starts: she is seen in the home
    /// copy too (the paper's Fig. 5, where the large upside-down Suzanne in
    /// the background is her antipodal image).
    Free,
    /// Not in the scene.
    Hidden,
}

/// What [`Scene::paper`] holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct PaperOptions {
    /// The domain's edges as tubes coloured by edge cycle.
    pub edges: bool,
    /// Suzanne.
    pub suzanne: SuzanneMode,
    /// The two hands.
    pub hands: bool,
}

impl Default for PaperOptions {
    fn default() -> Self {
        PaperOptions {
            edges: true,
            suzanne: SuzanneMode::Attached,
            hands: true,
        }
    }
}

/// Suzanne's colour (linear RGB).
pub const SUZANNE_COLOR: [f32; 3] = [0.85, 0.62, 0.3];
/// The hands' colour (linear RGB).
pub const HAND_COLOR: [f32; 3] = [0.9, 0.75, 0.65];

/// Suzanne relative to the camera, and her scale, in `space` (`None` when
/// hidden). Suzanne is about 2.65 wide: a head 0.45 inradii across, turned
/// to face the way the camera looks (she faces +z, the camera -z); free,
/// she stands 0.7 inradii ahead, facing the camera.
#[must_use]
pub fn suzanne_offset(space: &Space, mode: SuzanneMode) -> Option<(DMat4, f64)> {
    let r = space.inradius();
    let scale = 0.17 * r;
    match mode {
        SuzanneMode::Attached => Some((isometry::rotation(DVec3::Y, std::f64::consts::PI), scale)),
        SuzanneMode::Free => Some((isometry::translation(space.geometry(), DVec3::Z * (-0.7 * r)), scale)),
        SuzanneMode::Hidden => None,
    }
}

/// A hand relative to the camera, and its scale: low left (`left`) or low
/// right, 0.3 inradii ahead, fingers along -z (the hands are about 0.2
/// long).
#[must_use]
pub fn hand_offset(space: &Space, left: bool) -> (DMat4, f64) {
    let r = space.inradius();
    let x = if left { -1.0 } else { 1.0 };
    (
        isometry::translation(space.geometry(), DVec3::new(0.16 * x, -0.12, -0.3) * r),
        0.9 * r,
    )
}

impl Scene {
    /// The paper's scene (see the module docs) for `space`, with the
    /// camera and light of [`Scene::default_for`].
    #[must_use]
    pub fn paper(space: &Space, options: &PaperOptions) -> Scene {
        let mut scene = Scene::default_for(space);
        scene.balls.clear();
        if !options.edges {
            scene.edge_radius = None;
        }
        let camera = scene.camera.isometry;
        let material = |base_color| MeshMaterial {
            base_color,
            texture: None,
        };
        if let Some((offset, scale)) = suzanne_offset(space, options.suzanne) {
            let mut suzanne = SceneMesh::new(builtin::suzanne(), material(SUZANNE_COLOR), camera * offset, scale);
            suzanne.attached = options.suzanne == SuzanneMode::Attached;
            scene.meshes.push(suzanne);
        }
        if options.hands {
            for left in [true, false] {
                let (offset, scale) = hand_offset(space, left);
                scene.meshes.push(SceneMesh::new(
                    builtin::hand(left),
                    material(HAND_COLOR),
                    camera * offset,
                    scale,
                ));
            }
        }
        scene
    }
}
