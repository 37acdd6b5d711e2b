//! What the tracer draws: a camera, balls, the domain's edges as tubes,
//! point lights, fog and triangle meshes. The model is here; `file`
//! reads and writes it as JSON (validated field by field), and
//! `presets` makes the scenes the paper and the examples use.

mod file;
mod mesh;
mod presets;

pub use file::MeshPart;
#[cfg(feature = "gltf")]
pub use file::meshes_of;
pub use file::{MAX_GLOW, MAX_LIGHTS, MAX_MESHES, SceneError, max_radius};
pub use mesh::{SceneMesh, baked};
#[cfg(feature = "gltf")]
pub use presets::builtin;
pub use presets::{
    HAND_COLOR, PaperOptions, SUZANNE_COLOR, SuzanneMode, VEHICLE_COLOR, hand_offset, mirror_ball, suzanne_offset,
    vehicle_offset,
};

use glam::{DMat4, DVec4};

/// The camera: where it is and how wide it sees.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    /// Carries the origin to the eye, the origin's frame to the camera's.
    pub isometry: DMat4,
    /// Vertical field of view in degrees (of a symmetric frustum; unused
    /// when `frustum` is set).
    pub fov_y_degrees: f64,
    /// An off-centre frustum (a headset's eye), in place of the symmetric
    /// one `fov_y_degrees` and the image's aspect make.
    pub frustum: Option<Frustum>,
    /// The copy of the domain `isometry` is read in, as the faces crossed
    /// from the origin copy to reach it (crossing face `i` from cell `g`
    /// leads to `g T_i^-1`); empty for the origin copy. Exact at any
    /// length where the space's ids are ([`crate::space::exact`]).
    pub cell: Vec<usize>,
}

/// An off-centre view frustum, as OpenXR gives each eye: the slopes
/// (tangents of the angles) of the image's left, right, bottom and top
/// edges in the camera's frame, left and bottom negative. The ray of a
/// pixel at normalised device coordinates `(x, y)` leaves the camera in
/// the direction `(l + (x + 1)(r - l)/2, b + (y + 1)(t - b)/2, -1)`.
///
/// ```
/// use bevy_manifold_core::trace::Frustum;
/// // OpenXR's angles (radians), as `XrFovf` gives them.
/// let f = Frustum::from_angles(-0.9, 0.8, -0.85, 0.75);
/// assert!((f.left - (-0.9f64).tan()).abs() < 1e-15);
/// // The centre of that image looks a little left of and below the axis.
/// let [hw, hh, cx, cy] = f.half_extent_and_centre();
/// assert!(hw > 0.0 && hh > 0.0 && cx < 0.0 && cy < 0.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frustum {
    /// Slope of the left edge (negative left of the axis).
    pub left: f64,
    /// Slope of the right edge.
    pub right: f64,
    /// Slope of the bottom edge (negative below the axis).
    pub down: f64,
    /// Slope of the top edge.
    pub up: f64,
}

impl Frustum {
    /// From the four angles of an OpenXR field of view (radians, left and
    /// down negative).
    #[must_use]
    pub fn from_angles(left: f64, right: f64, down: f64, up: f64) -> Self {
        Frustum {
            left: left.tan(),
            right: right.tan(),
            down: down.tan(),
            up: up.tan(),
        }
    }

    /// `[half width, half height, centre x, centre y]` in slopes: the view
    /// direction of NDC `(x, y)` is `(x hw + cx, y hh + cy, -1)`. The
    /// tracers read this form (GPU: `Params::frustum`).
    #[must_use]
    pub fn half_extent_and_centre(&self) -> [f64; 4] {
        [
            (self.right - self.left) / 2.0,
            (self.up - self.down) / 2.0,
            (self.right + self.left) / 2.0,
            (self.up + self.down) / 2.0,
        ]
    }

    /// Whether all four slopes are finite and the frustum has positive
    /// width and height.
    #[must_use]
    pub fn is_valid(&self) -> bool {
        [self.left, self.right, self.down, self.up]
            .iter()
            .all(|v| v.is_finite())
            && self.right > self.left
            && self.up > self.down
    }
}

/// A ball (a metric ball of the space, drawn exactly).
#[derive(Clone, Debug, PartialEq)]
pub struct Ball {
    /// Centre: a normalised point inside the fundamental domain.
    pub center: DVec4,
    /// Radius, in the space's own distance.
    pub radius: f64,
    /// Linear RGB albedo.
    pub color: [f32; 3],
    /// Light it gives off, in units of its albedo: it shows at least
    /// `color * glow` with no light on it (a shot, a lamp); 0 for a plain
    /// ball. The direct tracer lights nothing else by it; the path tracer
    /// takes it as an area light, aiming paths at it
    /// ([`crate::trace::path`]).
    pub glow: f32,
    /// Metallic and roughness (the GGX lobe, as a mesh's
    /// [`crate::material::MeshMaterial::pbr`]); `None`: the classic look.
    pub pbr: Option<crate::material::Pbr>,
}

/// A point light (a small sphere when `radius` is set).
///
/// With [`Lighting::images`] on, it lights a point by every image of it
/// in the cover within `range`, each along its own geodesic (and in S3
/// the long way round as well): the irradiance of one image at distance
/// `d` is `intensity / max(area(d), area(radius))`, times the range's
/// smooth cut-off `(1 - (d / range)^4)^2` (Bevy's point-light window),
/// times the fog's transmittance over `d`; see
/// [`super::light_images`].
#[derive(Clone, Debug, PartialEq)]
pub struct Light {
    /// Position: a normalised point inside the fundamental domain.
    pub position: DVec4,
    /// Power: the irradiance at distance `d` is `intensity / area(d)`.
    pub intensity: f64,
    /// Linear RGB colour.
    pub color: [f32; 3],
    /// How far its light reaches (a smooth cut-off, as Bevy's
    /// `PointLight::range`); `None`: as far as [`Lighting::images`]
    /// images of it allow.
    pub range: Option<f64>,
    /// Its radius: nearer than this the irradiance stays that of its
    /// surface, so no point is lit infinitely (in S3 the light's
    /// antipode too). 0: a point.
    pub radius: f64,
    /// A spot light's cone; `None`: light in every direction.
    pub spot: Option<Spot>,
}

/// A spot light's cone, as Bevy's `SpotLight`: full light within `inner`
/// of `direction`, none past `outer`, and between them Bevy's fall-off
/// `clamp((cos a - cos outer) / (cos inner - cos outer), 0, 1)^2` at the
/// angle `a` from `direction`. Each image of the light carries its
/// direction with it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spot {
    /// Where the cone points: a tangent at the light's position (made a
    /// unit one there).
    pub direction: DVec4,
    /// Half-angle of full light, radians.
    pub inner: f64,
    /// Half-angle past which there is none, radians (at least `inner`).
    pub outer: f64,
}

impl Light {
    /// A point light with no range of its own and no size.
    #[must_use]
    pub fn point(position: DVec4, intensity: f64, color: [f32; 3]) -> Light {
        Light {
            position,
            intensity,
            color,
            range: None,
            radius: 0.0,
            spot: None,
        }
    }
}

/// How light reaches what it lights: the light's images in the cover,
/// and shadows.
///
/// ```
/// use bevy_manifold_core::prelude::*;
/// let lighting = Lighting::default();
/// // Light images on, shadows asked for (they cost: see the benchmarks).
/// assert!(lighting.images > 1 && !lighting.shadows);
/// // As before light images: each light's copy in the domain only.
/// assert_eq!(Lighting::DOMAIN_COPY.images, 0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Lighting {
    /// The most images of each light in the cover that light a point,
    /// nearest the domain first: the light's range is cut (smoothly) to
    /// what they reach, so every point within it sees all of them and
    /// light is continuous across the faces. 0: each light's copy in the
    /// domain only, seen along the chart's straight line, with no range
    /// or fog on its way: light seams at the faces (the lighting before
    /// light images, kept for comparison).
    pub images: u32,
    /// A light image lights a point only if the geodesic between them is
    /// free: shadow rays cross the faces as camera rays do. Glowing balls
    /// (lamps) cast none. Off by default: a shadow ray per light image per
    /// hit costs from about as much again as the frame (Seifert–Weber) to
    /// many times it (the Poincaré space's 240 arcs; see `BENCHMARKS.md`).
    pub shadows: bool,
}

impl Lighting {
    /// Each light's copy in the domain, no shadows.
    pub const DOMAIN_COPY: Lighting = Lighting {
        images: 0,
        shadows: false,
    };
}

impl Default for Lighting {
    fn default() -> Self {
        Lighting {
            images: 64,
            shadows: false,
        }
    }
}

/// Exponential fog on the distance travelled.
#[derive(Clone, Debug, PartialEq)]
pub struct Fog {
    /// Extinction per unit distance.
    pub density: f64,
    /// The colour light fades to.
    pub color: [f32; 3],
}

/// Everything the tracer draws.
///
/// ```
/// use bevy_manifold_core::prelude::*;
/// let space = catalog::torus(1.0);
/// let scene = Scene::default_for(&space);
/// assert_eq!(scene.balls.len(), 1);
/// assert!(scene.edge_radius.is_some());
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// The camera.
    pub camera: Camera,
    /// Balls; ids 1, 2, ... in this order.
    pub balls: Vec<Ball>,
    /// Point lights.
    pub lights: Vec<Light>,
    /// Triangle meshes; ids follow the balls'.
    pub meshes: Vec<SceneMesh>,
    /// Radius of the tubes drawn along the domain's edges, if drawn.
    pub edge_radius: Option<f64>,
    /// Fog, if any.
    pub fog: Option<Fog>,
    /// How the lights reach what they light.
    pub lighting: Lighting,
    /// What a scene file asked for that was left out, and why (a mesh
    /// file that failed to load); empty for scenes made in code.
    pub skipped: Vec<String>,
}

impl Scene {
    /// A scene with nothing in it, the camera at the origin: rays only
    /// cross faces (used to follow geodesics and in tests).
    #[must_use]
    pub fn empty() -> Scene {
        Scene {
            camera: Camera {
                isometry: DMat4::IDENTITY,
                fov_y_degrees: 60.0,
                frustum: None,
                cell: Vec::new(),
            },
            balls: Vec::new(),
            lights: Vec::new(),
            meshes: Vec::new(),
            edge_radius: None,
            fog: None,
            lighting: Lighting::default(),
            skipped: Vec::new(),
        }
    }
}
