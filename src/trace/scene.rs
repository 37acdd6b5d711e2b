//! What the tracer draws: a camera, balls, the domain's edges as tubes,
//! point lights and fog. Read from JSON (validated field by field) or made
//! for a space by [`Scene::default_for`].
//!
//! ```text
//! {"camera": {"isometry": [[..4..],[..4..],[..4..],[..4..]], "fov_y_degrees": 60},
//!  "balls":  [{"center": [x,y,z,w], "radius": r, "color": [r,g,b]}, ...],
//!  "lights": [{"position": [x,y,z,w], "intensity": i, "color": [r,g,b]}, ...],
//!  "meshes": [{"file": "model.glb", "placement": [[..4..] x4], "scale": s,
//!              "color": [r,g,b], "attached": false}, ...],
//!  "edges": {"radius": r} | null,
//!  "fog": {"density": d, "color": [r,g,b]} | null}
//! ```
//! Mesh files are found relative to the scene file.
//! The camera isometry (row-major, acting on column vectors) carries the
//! origin to the eye and the origin's frame to the camera's; the camera
//! looks along its local -z with +y up.

use super::scene_mesh::{MeshDesc, SceneMesh, describe, read_meshes};
use crate::geometry::{Geometry, isometry};
use crate::space::Space;
use crate::space::file::{from_rows, to_rows};
use glam::{DMat4, DVec3, DVec4};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The camera: where it is and how wide it sees.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    /// Carries the origin to the eye, the origin's frame to the camera's.
    pub isometry: DMat4,
    /// Vertical field of view in degrees.
    pub fov_y_degrees: f64,
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
}

/// A point light.
#[derive(Clone, Debug, PartialEq)]
pub struct Light {
    /// Position: a normalised point inside the fundamental domain.
    pub position: DVec4,
    /// Power: the irradiance at distance `d` is `intensity / area(d)`.
    pub intensity: f64,
    /// Linear RGB colour.
    pub color: [f32; 3],
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
/// use bevy_manifold::prelude::*;
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
    /// What a scene file asked for that was left out, and why (a mesh
    /// file that failed to load); empty for scenes made in code.
    pub skipped: Vec<String>,
}

/// A scene file field that is wrong, named by its JSON path.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SceneError {
    /// Malformed JSON or a missing field.
    #[error("{path}: not a scene file: {message}")]
    Json {
        /// The file.
        path: String,
        /// serde's message, with line and column.
        message: String,
    },
    /// A field with a bad value.
    #[error("{path}: {field}: {message}")]
    Field {
        /// The file.
        path: String,
        /// The field, e.g. `balls[2].radius`.
        field: String,
        /// What is wrong with it.
        message: String,
    },
    /// The file could not be read.
    #[error("{path}: cannot read: {message}")]
    Io {
        /// The file.
        path: String,
        /// The OS error.
        message: String,
    },
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct CameraDesc {
    isometry: [[f64; 4]; 4],
    fov_y_degrees: f64,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct BallDesc {
    center: [f64; 4],
    radius: f64,
    color: [f32; 3],
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct LightDesc {
    position: [f64; 4],
    intensity: f64,
    color: [f32; 3],
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct EdgesDesc {
    radius: f64,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct FogDesc {
    density: f64,
    color: [f32; 3],
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneDesc {
    camera: CameraDesc,
    #[serde(default)]
    balls: Vec<BallDesc>,
    #[serde(default)]
    lights: Vec<LightDesc>,
    #[serde(default)]
    meshes: Vec<MeshDesc>,
    #[serde(default)]
    edges: Option<EdgesDesc>,
    #[serde(default)]
    fog: Option<FogDesc>,
}

/// How far off its model a point in a file may be before it is an error
/// (it is then normalised exactly).
const POINT_TOLERANCE: f64 = 1e-6;

impl Scene {
    /// A scene with nothing in it, the camera at the origin: rays only
    /// cross faces (used to follow geodesics and in tests).
    #[must_use]
    pub fn empty() -> Scene {
        Scene {
            camera: Camera {
                isometry: DMat4::IDENTITY,
                fov_y_degrees: 60.0,
            },
            balls: Vec::new(),
            lights: Vec::new(),
            meshes: Vec::new(),
            edge_radius: None,
            fog: None,
            skipped: Vec::new(),
        }
    }

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
            },
            balls: vec![Ball {
                center: DVec4::W,
                radius: ball_radius,
                color: [0.95, 0.55, 0.2],
            }],
            lights: vec![Light {
                position: eye,
                // Irradiance 0.8 on the near side of the ball: lit, with
                // room left for the highlight.
                intensity: 0.8 * g.sphere_area::<f64>(to_ball),
                color: [1.0, 1.0, 1.0],
            }],
            meshes: Vec::new(),
            edge_radius: Some(0.035 * r),
            fog: None,
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
        Scene::paper(space, &super::PaperOptions::default())
    }

    /// Reads and validates a scene file for `space`.
    ///
    /// # Errors
    /// Unreadable file, malformed JSON, or a field with a bad value, named
    /// by its path in the JSON (`balls[1].center`).
    pub fn load(path: impl AsRef<Path>, space: &Space) -> Result<Scene, SceneError> {
        let p = path.as_ref().display().to_string();
        let text = std::fs::read_to_string(path.as_ref()).map_err(|e| SceneError::Io {
            path: p.clone(),
            message: e.to_string(),
        })?;
        Self::parse(&text, &p, space)
    }

    /// Parses and validates scene JSON; `path` names it in errors.
    ///
    /// # Errors
    /// As [`Scene::load`].
    pub fn parse(text: &str, path: &str, space: &Space) -> Result<Scene, SceneError> {
        let desc: SceneDesc = serde_json::from_str(text).map_err(|e| SceneError::Json {
            path: path.into(),
            message: e.to_string(),
        })?;
        let field = |field: String, message: String| SceneError::Field {
            path: path.into(),
            field,
            message,
        };
        let g = space.geometry();

        let cam = from_rows(desc.camera.isometry);
        if !cam.is_finite() {
            return Err(field("camera.isometry".into(), "has a NaN or infinite entry".into()));
        }
        let err = isometry::isometry_error(g, cam);
        if err > 1e-6 {
            return Err(field(
                "camera.isometry".into(),
                format!("is not an isometry of {g} space (form error {err:.2e})"),
            ));
        }
        let fov = desc.camera.fov_y_degrees;
        if !(fov > 0.0 && fov < 180.0) {
            return Err(field(
                "camera.fov_y_degrees".into(),
                format!("must be in (0, 180), got {fov}"),
            ));
        }
        let camera = Camera {
            isometry: isometry::orthonormalize(g, cam),
            fov_y_degrees: fov,
        };

        let mut balls = Vec::new();
        for (i, b) in desc.balls.iter().enumerate() {
            let center = point_field(space, b.center, &format!("balls[{i}].center")).map_err(|(f, m)| field(f, m))?;
            positive(b.radius, &format!("balls[{i}].radius")).map_err(|(f, m)| field(f, m))?;
            color(b.color, &format!("balls[{i}].color")).map_err(|(f, m)| field(f, m))?;
            balls.push(Ball {
                center,
                radius: b.radius,
                color: b.color,
            });
        }
        if balls.len() > 254 {
            return Err(field(
                "balls".into(),
                format!("at most 254 balls (ids 1..254), got {}", balls.len()),
            ));
        }
        let mut lights = Vec::new();
        for (i, l) in desc.lights.iter().enumerate() {
            let position =
                point_field(space, l.position, &format!("lights[{i}].position")).map_err(|(f, m)| field(f, m))?;
            if !(l.intensity >= 0.0 && l.intensity.is_finite()) {
                return Err(field(
                    format!("lights[{i}].intensity"),
                    format!("must be >= 0 and finite, got {}", l.intensity),
                ));
            }
            color(l.color, &format!("lights[{i}].color")).map_err(|(f, m)| field(f, m))?;
            lights.push(Light {
                position,
                intensity: l.intensity,
                color: l.color,
            });
        }
        let edge_radius = match desc.edges {
            Some(e) => {
                positive(e.radius, "edges.radius").map_err(|(f, m)| field(f, m))?;
                Some(e.radius)
            }
            None => None,
        };
        let fog = match desc.fog {
            Some(f) => {
                if !(f.density >= 0.0 && f.density.is_finite()) {
                    return Err(field(
                        "fog.density".into(),
                        format!("must be >= 0 and finite, got {}", f.density),
                    ));
                }
                color(f.color, "fog.color").map_err(|(a, m)| field(a, m))?;
                Some(Fog {
                    density: f.density,
                    color: f.color,
                })
            }
            None => None,
        };
        let dir = Path::new(path).parent().unwrap_or(Path::new("."));
        let (meshes, skipped) = read_meshes(&desc.meshes, dir, g).map_err(|(f, m)| field(f, m))?;
        if balls.len() + meshes.len() > 254 {
            return Err(field(
                "meshes".into(),
                format!(
                    "at most 254 balls and mesh parts together (ids 1..254), got {}",
                    balls.len() + meshes.len()
                ),
            ));
        }
        Ok(Scene {
            camera,
            balls,
            lights,
            meshes,
            edge_radius,
            fog,
            skipped,
        })
    }

    /// The scene as JSON, in the scene-file format.
    #[must_use]
    pub fn to_json(&self) -> String {
        let desc = SceneDesc {
            camera: CameraDesc {
                isometry: to_rows(self.camera.isometry),
                fov_y_degrees: self.camera.fov_y_degrees,
            },
            balls: self
                .balls
                .iter()
                .map(|b| BallDesc {
                    center: b.center.to_array(),
                    radius: b.radius,
                    color: b.color,
                })
                .collect(),
            lights: self
                .lights
                .iter()
                .map(|l| LightDesc {
                    position: l.position.to_array(),
                    intensity: l.intensity,
                    color: l.color,
                })
                .collect(),
            meshes: describe(&self.meshes),
            edges: self.edge_radius.map(|radius| EdgesDesc { radius }),
            fog: self.fog.as_ref().map(|f| FogDesc {
                density: f.density,
                color: f.color,
            }),
        };
        serde_json::to_string_pretty(&desc).unwrap_or_default()
    }
}

fn positive(x: f64, name: &str) -> Result<(), (String, String)> {
    if x > 0.0 && x.is_finite() {
        Ok(())
    } else {
        Err((name.into(), format!("must be positive and finite, got {x}")))
    }
}

fn color(c: [f32; 3], name: &str) -> Result<(), (String, String)> {
    if c.iter().all(|x| x.is_finite() && *x >= 0.0) {
        Ok(())
    } else {
        Err((
            name.into(),
            format!("colour components must be finite and >= 0, got {c:?}"),
        ))
    }
}

fn point_field(space: &Space, p: [f64; 4], name: &str) -> Result<DVec4, (String, String)> {
    let g: Geometry = space.geometry();
    let v = DVec4::from_array(p);
    if !g.is_point(v) {
        return Err((name.into(), format!("{p:?} is not a point of {g} space")));
    }
    let err = g.point_error::<f64>(v);
    if err > POINT_TOLERANCE {
        return Err((
            name.into(),
            format!("{p:?} is not normalised (error {err:.2e}; {})", normal_form(g)),
        ));
    }
    if let Some(f) = space.outside_face(v, 1e-9) {
        return Err((
            name.into(),
            format!("{p:?} lies outside the fundamental domain, beyond face {f}"),
        ));
    }
    Ok(g.normalize_point::<f64>(v))
}

fn normal_form(g: Geometry) -> &'static str {
    match g {
        Geometry::Euclidean => "E3 points have w = 1",
        Geometry::Hyperbolic => "H3 points have <p,p> = -1",
        Geometry::Spherical => "S3 points have |p| = 1",
    }
}
