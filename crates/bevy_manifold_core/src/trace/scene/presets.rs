//! The scenes made in code: the default scene of a space, and the
//! paper's scene, laid out once for the CPU/GPU tracer ([`Scene::paper`])
//! and for Bevy entities (`bevy_manifold::drawables::paper`): the domain's
//! edges as coloured tubes, Suzanne attached to the camera (or free in
//! front of it), the two hands low left and right, a light at the eye.
//! Every placement is given relative to the camera, so the two versions
//! agree.
//!
//! ```
//! use bevy_manifold_core::prelude::*;
//! use bevy_manifold_core::trace::{PaperOptions, SuzanneMode};
//! let space = catalog::poincare();
//! let free = Scene::paper(&space, &PaperOptions { suzanne: SuzanneMode::Free, ..PaperOptions::default() });
//! assert_eq!(free.meshes.len(), 3);
//! assert!(!free.meshes[0].attached);
//! let bare = Scene::paper(&space, &PaperOptions { suzanne: SuzanneMode::Hidden, hands: false, edges: false, ..PaperOptions::default() });
//! assert!(bare.meshes.is_empty() && bare.edge_radius.is_none());
//! ```

use super::mesh::SceneMesh;
use super::{Ball, Camera, Light, Lighting, Scene};
use crate::geometry::isometry;
#[cfg(feature = "gltf")]
use crate::mesh::MeshData;
use crate::mesh::MeshMaterial;
use crate::space::Space;
use glam::{DMat4, DVec3, DVec4};
use serde::{Deserialize, Serialize};
#[cfg(feature = "gltf")]
use std::path::Path;
#[cfg(feature = "gltf")]
use std::sync::{Arc, OnceLock};

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
    /// The vehicle ([`crate::mesh::vehicle`]) the camera rides, ahead and
    /// below the eye, seen in the home copy and every other.
    #[serde(default)]
    pub vehicle: bool,
    /// A mirror ball ([`mirror_ball`]) in the middle of the domain, as in
    /// the paper's Fig. 11: seen with reflections on
    /// ([`crate::trace::TraceSettings::reflections`]).
    #[serde(default)]
    pub mirror: bool,
}

impl Default for PaperOptions {
    fn default() -> Self {
        PaperOptions {
            edges: true,
            suzanne: SuzanneMode::Attached,
            hands: true,
            vehicle: false,
            mirror: false,
        }
    }
}

/// The mirror ball of the paper's Fig. 11 in `space`: a smooth metal
/// ([`crate::material::Pbr`] metallic 1, roughness 0) of radius 0.2
/// inradii at the centre of the domain, silver (linear RGB 0.95, 0.93,
/// 0.88).
#[must_use]
pub fn mirror_ball(space: &Space) -> Ball {
    Ball {
        center: DVec4::W,
        radius: 0.2 * space.inradius(),
        color: [0.95, 0.93, 0.88],
        glow: 0.0,
        pbr: Some(crate::material::Pbr {
            metallic: 1.0,
            roughness: 0.0,
        }),
    }
}

/// Suzanne's colour (linear RGB).
pub const SUZANNE_COLOR: [f32; 3] = [0.85, 0.62, 0.3];
/// The hands' colour (linear RGB).
pub const HAND_COLOR: [f32; 3] = [0.9, 0.75, 0.65];

/// The vehicle's colour (linear RGB).
pub const VEHICLE_COLOR: [f32; 3] = [0.8, 0.16, 0.1];

/// The vehicle relative to the camera, and its scale, in `space`: its
/// length 0.45 inradii, its middle 0.4 inradii ahead and 0.12 below the
/// eye, so the rider looks over its back and tail along its nose.
#[must_use]
pub fn vehicle_offset(space: &Space) -> (DMat4, f64) {
    let r = space.inradius();
    (
        isometry::translation(space.geometry(), DVec3::new(0.0, -0.12, -0.4) * r),
        0.45 * r,
    )
}

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
    /// The default scene for a space: a ball at the centre of the domain,
    /// the domain's edges as tubes, a light at the camera, and the camera
    /// off-centre looking along -z so the ball is in view.
    #[must_use]
    pub fn default_for(space: &Space) -> Scene {
        let g = space.geometry();
        let r = space.inradius();
        let eye_offset = DVec3::new(0.12, 0.08, 0.62) * r;
        let camera = isometry::translation(g, eye_offset);
        let eye = camera * DVec4::W;
        let ball_radius = 0.22 * r;
        let to_ball = (g.distance::<f64>(eye, DVec4::W) - ball_radius).max(1e-3);
        Scene {
            camera: Camera {
                isometry: camera,
                fov_y_degrees: 60.0,
                frustum: None,
                cell: Vec::new(),
            },
            balls: vec![Ball {
                center: DVec4::W,
                radius: ball_radius,
                color: [0.95, 0.55, 0.2],
                glow: 0.0,
                pbr: None,
            }],
            lights: vec![Light {
                position: eye,
                // Irradiance 0.8 on the near side of the ball: lit, with
                // room left for the highlight.
                intensity: 0.8 * g.sphere_area::<f64>(to_ball),
                color: [1.0, 1.0, 1.0],
                range: None,
                radius: 0.0,
                spot: None,
            }],
            meshes: Vec::new(),
            edge_radius: Some(0.035 * r),
            fog: None,
            lighting: Lighting::default(),
            skipped: Vec::new(),
        }
    }

    /// The paper's scene: the domain's edges as coloured tubes, Suzanne
    /// attached to the camera (the viewer sees its own images in the other
    /// copies) and the two hands in front of it, low left and right, lit
    /// by a light at the eye. What `render` draws when no scene is given;
    /// [`Scene::paper`] with [`super::PaperOptions::default`].
    #[must_use]
    pub fn paper_default(space: &Space) -> Scene {
        Scene::paper(space, &PaperOptions::default())
    }

    /// The paper's scene (see the module docs) for `space`, with the
    /// camera and light of [`Scene::default_for`].
    #[must_use]
    pub fn paper(space: &Space, options: &PaperOptions) -> Scene {
        let mut scene = Scene::default_for(space);
        scene.balls.clear();
        if !options.edges {
            scene.edge_radius = None;
        }
        if options.mirror {
            scene.balls.push(mirror_ball(space));
        }
        #[cfg(feature = "gltf")]
        add_models(&mut scene, space, options);
        if options.vehicle {
            let (offset, scale) = vehicle_offset(space);
            scene.meshes.push(SceneMesh::new(
                crate::mesh::vehicle::airplane(),
                MeshMaterial::standard(VEHICLE_COLOR),
                scene.camera.isometry * offset,
                scale,
            ));
        }
        scene
    }
}

/// The paper's meshes: Suzanne and the hands, placed relative to the
/// camera (without the `gltf` feature there are no models to place).
#[cfg(feature = "gltf")]
fn add_models(scene: &mut Scene, space: &Space, options: &PaperOptions) {
    {
        let camera = scene.camera.isometry;
        let material = MeshMaterial::standard;
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
    }
}

/// The models the crate carries (`assets/models/`, embedded so an app
/// from crates.io has them): Suzanne and the two hands, parsed and
/// BVH-built once.
#[cfg(feature = "gltf")]
pub mod builtin {
    use super::*;
    use crate::trace::scene::file::from_loaded;

    fn parse(bytes: &[u8], name: &str) -> Arc<MeshData> {
        let loaded = crate::mesh::gltf::from_slice(bytes, Path::new(name))
            .unwrap_or_else(|e| panic!("the embedded {name} is broken: {e}"));
        from_loaded(loaded).0.remove(0).0
    }

    /// Blender's Suzanne, 3,936 triangles, about 2.65 wide, facing +z.
    ///
    /// # Panics
    /// Never: the embedded file is checked by the tests.
    pub fn suzanne() -> Arc<MeshData> {
        static M: OnceLock<Arc<MeshData>> = OnceLock::new();
        M.get_or_init(|| parse(include_bytes!("../../../assets/models/suzanne.glb"), "suzanne.glb"))
            .clone()
    }

    /// A left (`true`) or right hand, in metres (about 0.2 long), in its
    /// bind pose.
    ///
    /// # Panics
    /// Never: the embedded files are checked by the tests.
    pub fn hand(left: bool) -> Arc<MeshData> {
        static L: OnceLock<Arc<MeshData>> = OnceLock::new();
        static R: OnceLock<Arc<MeshData>> = OnceLock::new();
        if left {
            L.get_or_init(|| parse(include_bytes!("../../../assets/models/left.glb"), "left.glb"))
                .clone()
        } else {
            R.get_or_init(|| parse(include_bytes!("../../../assets/models/right.glb"), "right.glb"))
                .clone()
        }
    }
}
