//! The components that say what the tracer draws: balls, lights and the
//! domain's edges placed in a manifold, the meshes and the scene gathered
//! per space.

use crate::placement::Placement;
use crate::trace::Scene;
use bevy::color::Color;
use bevy::prelude::*;
use bevy_manifold_core::material::Pbr;
use std::sync::Arc;

/// A ball the tracer draws at the entity's [`Placement`]: an exact metric
/// ball of the space (a round sphere in E3, a hyperbolic or spherical one
/// elsewhere), seen in every copy of the domain.
///
/// ```
/// use bevy::prelude::*;
/// use bevy_manifold::prelude::*;
/// let ball = TracedBall::new(0.25, Color::WHITE);
/// assert_eq!(ball.radius, 0.25);
/// ```
#[derive(Component, Clone, Copy, Debug, PartialEq, Reflect)]
#[reflect(Component, Debug)]
#[require(Placement)]
pub struct TracedBall {
    /// Radius, in the space's own distance.
    pub radius: f64,
    /// Albedo.
    pub color: Color,
    /// Light it gives off, in units of its albedo ([`crate::trace::Ball::glow`]):
    /// 0 for a plain ball; a shot or a lamp glows at 1 or more.
    pub glow: f32,
    /// Metallic and perceptual roughness (the GGX lobe of Bevy's PBR);
    /// `None`: the tracer's classic look. Out-of-range values are drawn
    /// classic.
    #[reflect(ignore)]
    pub pbr: Option<Pbr>,
}

impl TracedBall {
    /// A ball of `radius` and albedo `color`.
    #[must_use]
    pub fn new(radius: f64, color: Color) -> Self {
        TracedBall {
            radius,
            color,
            glow: 0.0,
            pbr: None,
        }
    }

    /// The same ball with Bevy's PBR surface: `metallic` and perceptual
    /// `roughness`, each in `[0, 1]`.
    ///
    /// ```
    /// use bevy::prelude::*;
    /// use bevy_manifold::prelude::*;
    /// let mirror = TracedBall::new(0.3, Color::WHITE).with_pbr(1.0, 0.1);
    /// assert_eq!(mirror.pbr.map(|p| p.metallic), Some(1.0));
    /// ```
    #[must_use]
    pub fn with_pbr(self, metallic: f32, roughness: f32) -> Self {
        TracedBall {
            pbr: Some(Pbr { metallic, roughness }),
            ..self
        }
    }

    /// The same ball, glowing: it shows at least `color * glow` with no
    /// light on it.
    ///
    /// ```
    /// use bevy::prelude::*;
    /// use bevy_manifold::prelude::*;
    /// let shot = TracedBall::new(0.03, Color::srgb(1.0, 0.8, 0.3)).glowing(1.5);
    /// assert_eq!(shot.glow, 1.5);
    /// ```
    #[must_use]
    pub fn glowing(self, glow: f32) -> Self {
        TracedBall { glow, ..self }
    }
}

/// A point light at the entity's [`Placement`]. Its irradiance at distance
/// `d` is `intensity / area(d)`, the area of the geodesic sphere of radius
/// `d` (so light falls off faster in H3 and refocuses in S3). Under the
/// space's [`ManifoldLighting`] it lights a point by every image of it
/// in the cover within its range, each along its own geodesic.
///
/// ```
/// use bevy::prelude::*;
/// use bevy_manifold::prelude::*;
/// let lamp = ManifoldLight { intensity: 0.6, range: Some(2.0), ..default() };
/// assert_eq!((lamp.radius, lamp.color), (0.0, Color::WHITE));
/// ```
#[derive(Component, Clone, Copy, Debug, PartialEq, Reflect)]
#[reflect(Component, Debug)]
#[require(Placement)]
pub struct ManifoldLight {
    /// Power.
    pub intensity: f64,
    /// Colour.
    pub color: Color,
    /// How far its light reaches (a smooth cut-off, as Bevy's
    /// `PointLight::range`), in the space's distance; `None`: as far as
    /// [`ManifoldLighting::images`] images of it allow.
    pub range: Option<f64>,
    /// Its radius: nearer than this the irradiance stays that of its
    /// surface. 0: a point.
    pub radius: f64,
    /// A spot light's cone, pointing along the placement's forward (its
    /// local -z, as Bevy's `SpotLight`); `None`: light in every
    /// direction.
    pub cone: Option<SpotCone>,
}

/// The cone of a spot light ([`ManifoldLight::cone`]): full light within
/// `inner` of its axis, none past `outer` (radians), Bevy's fall-off
/// between.
#[derive(Clone, Copy, Debug, PartialEq, Reflect)]
pub struct SpotCone {
    /// Half-angle of full light.
    pub inner: f64,
    /// Half-angle past which there is none.
    pub outer: f64,
}

impl Default for ManifoldLight {
    fn default() -> Self {
        ManifoldLight {
            intensity: 1.0,
            color: Color::WHITE,
            range: None,
            radius: 0.0,
            cone: None,
        }
    }
}

/// On a [`ManifoldSpace`] root: how its lights reach what they light
/// (the tracer's [`crate::trace::Lighting`]); the default when absent:
/// each light's images in the cover, 64 at most, no shadows (turn them
/// on here: they cost a shadow ray per light image per hit).
///
/// ```
/// use bevy::prelude::*;
/// use bevy_manifold::prelude::*;
/// // The lighting before light images, and no shadows: cheaper, seams at faces.
/// let flat = ManifoldLighting { images: 0, shadows: false };
/// assert_eq!(flat.to_lighting(), bevy_manifold::trace::Lighting::DOMAIN_COPY);
/// assert!(!ManifoldLighting::default().shadows);
/// ```
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq, Reflect)]
#[reflect(Component, Debug)]
pub struct ManifoldLighting {
    /// The most images of each light that light a point (at most
    /// [`crate::trace::MAX_LIGHT_IMAGES`] in all); 0: each light's copy
    /// in the domain only.
    pub images: u32,
    /// Shadows through the faces.
    pub shadows: bool,
}

impl Default for ManifoldLighting {
    fn default() -> Self {
        crate::trace::Lighting::default().into()
    }
}

impl From<crate::trace::Lighting> for ManifoldLighting {
    fn from(l: crate::trace::Lighting) -> Self {
        ManifoldLighting {
            images: l.images,
            shadows: l.shadows,
        }
    }
}

impl ManifoldLighting {
    /// The tracer's lighting.
    #[must_use]
    pub fn to_lighting(self) -> crate::trace::Lighting {
        crate::trace::Lighting {
            images: self.images.min(crate::trace::MAX_LIGHT_IMAGES as u32),
            shadows: self.shadows,
        }
    }
}

/// On a [`ManifoldSpace`] root: draw the fundamental domain's edges as tubes
/// of this radius, coloured by edge cycle (edges the pairings glue together
/// share a colour), with a ball at each vertex.
#[derive(Component, Clone, Copy, Debug, PartialEq, Reflect)]
#[reflect(Component, Debug)]
pub struct DomainEdges {
    /// Tube radius, in the space's distance.
    pub radius: f64,
}

impl Default for DomainEdges {
    fn default() -> Self {
        DomainEdges { radius: 0.02 }
    }
}

/// On a [`ManifoldSpace`] root: the space's traced meshes and the entity
/// each belongs to, as [`gather_scenes`] reads them. Kept by the mesh
/// gathering (feature `render`, see [`super::meshes`]), replaced only
/// when a mesh, material or placement changed; or inserted by hand, which
/// lasts only until the gathering runs again (any placed entity moving,
/// a mesh added): with the `render` feature, give meshes entities.
#[derive(Component, Clone, Debug, Default, PartialEq)]
pub struct ManifoldMeshes {
    /// The entity of each mesh.
    pub entities: Vec<Entity>,
    /// The meshes, in the tracer's terms.
    pub meshes: Vec<crate::trace::SceneMesh>,
}

/// What the tracer draws in one space, kept on the space's root entity by
/// [`gather_scenes`]: the scene (without a camera), shared. Ball `i` of the
/// scene has object id `i + 1` in the id buffer and belongs to
/// `entities()[i]`; the meshes follow the balls, in ids and in
/// `entities()`. The render world packs it for the GPU when
/// [`ManifoldScene::generation`] changes.
#[derive(Component, Clone, Debug)]
pub struct ManifoldScene {
    pub(super) scene: Arc<Scene>,
    pub(super) entities: Arc<Vec<Entity>>,
    pub(super) generation: u64,
}

impl ManifoldScene {
    /// The scene, for [`crate::trace::render`] (its camera is the identity).
    #[must_use]
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The entity each ball and mesh belongs to, in object-id order (id 1
    /// first).
    #[must_use]
    pub fn entities(&self) -> &[Entity] {
        &self.entities
    }

    /// Bumped each time the objects are rebuilt.
    #[must_use]
    pub fn generation(&self) -> u64 {
        self.generation
    }
}
