//! Scene files: JSON, validated field by field, each error named by its
//! path in the file.
//!
//! ```text
//! {"camera": {"isometry": [[..4..],[..4..],[..4..],[..4..]], "fov_y_degrees": 60,
//!             "frustum": [left, right, down, up] (optional: an off-centre eye)},
//!  "balls":  [{"center": [x,y,z,w], "radius": r, "color": [r,g,b], "glow": 0,
//!              "metallic": m, "roughness": r (optional: the GGX lobe)}, ...],
//!  "lights": [{"position": [x,y,z,w], "intensity": i, "color": [r,g,b],
//!              "range": r (optional), "radius": r (optional, 0),
//!              "spot": {"direction": [x,y,z], "inner": a, "outer": b} (optional)}, ...],
//!  "meshes": [{"file": "model.glb", "placement": [[..4..] x4], "scale": s,
//!              "color": [r,g,b], "metallic": m, "roughness": r, "emission": [r,g,b]
//!              (optional: in place of the file's own), "attached": false}, ...],
//!  "edges": {"radius": r} | null,
//!  "fog": {"density": d, "color": [r,g,b]} | null,
//!  "lighting": {"images": n, "shadows": false} (optional: the default)}
//! Mesh files are found relative to the scene file.
//! The camera isometry (row-major, acting on column vectors) carries the
//! origin to the eye and the origin's frame to the camera's; the camera
//! looks along its local -z with +y up.

use super::mesh::SceneMesh;
#[cfg(feature = "gltf")]
use super::mesh::baked;
use super::{Ball, Camera, Fog, Frustum, Light, Lighting, Scene, Spot};
use crate::geometry::{Geometry, isometry};
#[cfg(feature = "gltf")]
use crate::mesh::gltf::GltfError;
use crate::mesh::{MeshData, MeshMaterial};
use crate::space::Space;
use crate::space::file::{from_rows, to_rows};
use crate::trace::light_images::MAX_LIGHT_IMAGES;
use glam::{DMat4, DVec4};
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::sync::Arc;

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

/// Most faces in a scene file's `camera.cell` (each is one exact product
/// when the scene is prepared).
pub const MAX_CAMERA_CELL_WORD: usize = 1 << 16;

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct CameraDesc {
    isometry: [[f64; 4]; 4],
    fov_y_degrees: f64,
    /// An off-centre frustum: the slopes of the left, right, bottom and
    /// top edges (`Frustum`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    frustum: Option<[f64; 4]>,
    /// The faces crossed from the origin copy to the camera's copy.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    cell: Vec<usize>,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct BallDesc {
    center: [f64; 4],
    radius: f64,
    color: [f32; 3],
    #[serde(default, skip_serializing_if = "is_zero")]
    glow: f32,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    metallic: Option<f32>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    roughness: Option<f32>,
}

/// The GGX lobe a file's `metallic` and `roughness` ask for (either alone
/// takes Bevy's default for the other), checked; `None` when neither is
/// given.
fn pbr_of(
    metallic: Option<f32>,
    roughness: Option<f32>,
    name: &dyn Fn(&str) -> String,
) -> Result<Option<crate::material::Pbr>, (String, String)> {
    if metallic.is_none() && roughness.is_none() {
        return Ok(None);
    }
    let d = crate::material::Pbr::default();
    for (v, f) in [(metallic, "metallic"), (roughness, "roughness")] {
        if let Some(v) = v
            && !(0.0..=1.0).contains(&v)
        {
            return Err((name(f), format!("must be in [0, 1], got {v}")));
        }
    }
    Ok(Some(crate::material::Pbr {
        metallic: metallic.unwrap_or(d.metallic),
        roughness: roughness.unwrap_or(d.roughness),
    }))
}

/// A plain ball's glow is left out of the JSON.
fn is_zero(g: &f32) -> bool {
    *g == 0.0
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct LightDesc {
    position: [f64; 4],
    intensity: f64,
    color: [f32; 3],
    #[serde(default, skip_serializing_if = "Option::is_none")]
    range: Option<f64>,
    #[serde(default)]
    radius: f64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    spot: Option<SpotDesc>,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct SpotDesc {
    direction: [f64; 3],
    inner: f64,
    outer: f64,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct LightingDesc {
    images: u32,
    shadows: bool,
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
    #[serde(default)]
    lighting: Option<LightingDesc>,
}

/// How far off its model a point in a file may be before it is an error
/// (it is then normalised exactly).
const POINT_TOLERANCE: f64 = 1e-6;

impl Scene {
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
        let desc: SceneDesc = serde_json::from_str(crate::text::without_bom(text)).map_err(|e| SceneError::Json {
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
        let frustum = desc
            .camera
            .frustum
            .map(|[left, right, down, up]| Frustum { left, right, down, up });
        if let Some(f) = frustum
            && !f.is_valid()
        {
            return Err(field(
                "camera.frustum".into(),
                format!(
                    "must be finite slopes [left, right, down, up] with left < right and down < up, got {:?}",
                    [f.left, f.right, f.down, f.up]
                ),
            ));
        }
        if desc.camera.cell.len() > MAX_CAMERA_CELL_WORD {
            return Err(field(
                "camera.cell".into(),
                format!("has {} faces, more than {MAX_CAMERA_CELL_WORD}", desc.camera.cell.len()),
            ));
        }
        if let Some((i, f)) = desc
            .camera
            .cell
            .iter()
            .enumerate()
            .find(|(_, f)| **f >= space.faces().len())
        {
            return Err(field(
                format!("camera.cell[{i}]"),
                format!("is face {f}, but the space has {} faces", space.faces().len()),
            ));
        }
        let camera = Camera {
            isometry: isometry::orthonormalize(g, cam),
            fov_y_degrees: fov,
            frustum,
            cell: desc.camera.cell.clone(),
        };

        let mut balls = Vec::new();
        for (i, b) in desc.balls.iter().enumerate() {
            let center = point_field(space, b.center, &format!("balls[{i}].center")).map_err(|(f, m)| field(f, m))?;
            radius(g, b.radius, &format!("balls[{i}].radius")).map_err(|(f, m)| field(f, m))?;
            color(b.color, &format!("balls[{i}].color")).map_err(|(f, m)| field(f, m))?;
            glow(b.glow, &format!("balls[{i}].glow")).map_err(|(f, m)| field(f, m))?;
            let pbr = pbr_of(b.metallic, b.roughness, &|f| format!("balls[{i}].{f}")).map_err(|(f, m)| field(f, m))?;
            balls.push(Ball {
                center,
                radius: b.radius,
                color: b.color,
                glow: b.glow,
                pbr,
            });
        }
        if balls.len() > 254 {
            return Err(field("balls".into(), format!("at most 254 balls, got {}", balls.len())));
        }
        if desc.lights.len() > MAX_LIGHTS {
            return Err(field(
                "lights".into(),
                format!(
                    "at most {MAX_LIGHTS} lights (every hit is lit by each), got {}",
                    desc.lights.len()
                ),
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
            if let Some(r) = l.range
                && !(r > 0.0 && r.is_finite())
            {
                return Err(field(
                    format!("lights[{i}].range"),
                    format!("must be > 0 and finite, got {r}"),
                ));
            }
            if !(l.radius >= 0.0 && l.radius <= max_radius(g)) {
                return Err(field(
                    format!("lights[{i}].radius"),
                    format!("must be in [0, {}], got {}", max_radius(g), l.radius),
                ));
            }
            let spot = match &l.spot {
                None => None,
                Some(sp) => {
                    let [x, y, z] = sp.direction;
                    let v = glam::DVec4::new(x, y, z, 0.0);
                    let axis = g.project_tangent::<f64>(position, v);
                    if !(sp.direction.iter().all(|c| c.is_finite()) && g.form::<f64>(axis, axis).abs() > 1e-12) {
                        return Err(field(
                            format!("lights[{i}].spot.direction"),
                            format!(
                                "must be a finite, non-zero direction at the light, got {:?}",
                                sp.direction
                            ),
                        ));
                    }
                    if !(sp.inner >= 0.0 && sp.outer >= sp.inner && sp.outer <= core::f64::consts::PI) {
                        return Err(field(
                            format!("lights[{i}].spot"),
                            format!(
                                "needs 0 <= inner <= outer <= pi (radians), got inner {} and outer {}",
                                sp.inner, sp.outer
                            ),
                        ));
                    }
                    Some(Spot {
                        direction: axis,
                        inner: sp.inner,
                        outer: sp.outer,
                    })
                }
            };
            lights.push(Light {
                position,
                intensity: l.intensity,
                color: l.color,
                range: l.range,
                radius: l.radius,
                spot,
            });
        }
        let edge_radius = match desc.edges {
            Some(e) => {
                radius(g, e.radius, "edges.radius").map_err(|(f, m)| field(f, m))?;
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
        let (meshes, skipped) = read_meshes(&desc.meshes, dir, space).map_err(|(f, m)| field(f, m))?;
        if meshes.len() > MAX_MESHES {
            return Err(field(
                "meshes".into(),
                format!("at most {MAX_MESHES} mesh parts, got {}", meshes.len()),
            ));
        }
        let lighting = match desc.lighting {
            Some(l) if l.images as usize > MAX_LIGHT_IMAGES => {
                return Err(field(
                    "lighting.images".into(),
                    format!("at most {MAX_LIGHT_IMAGES} images of a light, got {}", l.images),
                ));
            }
            Some(l) => Lighting {
                images: l.images,
                shadows: l.shadows,
            },
            None => Lighting::default(),
        };
        Ok(Scene {
            camera,
            balls,
            lights,
            meshes,
            edge_radius,
            fog,
            lighting,
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
                frustum: self.camera.frustum.map(|f| [f.left, f.right, f.down, f.up]),
                cell: self.camera.cell.clone(),
            },
            balls: self
                .balls
                .iter()
                .map(|b| BallDesc {
                    center: b.center.to_array(),
                    radius: b.radius,
                    color: b.color,
                    glow: b.glow,
                    metallic: b.pbr.map(|p| p.metallic),
                    roughness: b.pbr.map(|p| p.roughness),
                })
                .collect(),
            lights: self
                .lights
                .iter()
                .map(|l| LightDesc {
                    position: l.position.to_array(),
                    intensity: l.intensity,
                    color: l.color,
                    range: l.range,
                    radius: l.radius,
                    spot: l.spot.map(|sp| SpotDesc {
                        // The chart's direction at the light whose tangent
                        // there is the spot's: `t - (t.w / p.w) p` has no
                        // `w`, and projects back onto `t` (reading
                        // projects it).
                        direction: (sp.direction - l.position * (sp.direction.w / l.position.w))
                            .truncate()
                            .to_array(),
                        inner: sp.inner,
                        outer: sp.outer,
                    }),
                })
                .collect(),
            meshes: describe(&self.meshes),
            edges: self.edge_radius.map(|radius| EdgesDesc { radius }),
            fog: self.fog.as_ref().map(|f| FogDesc {
                density: f.density,
                color: f.color,
            }),
            lighting: Some(LightingDesc {
                images: self.lighting.images,
                shadows: self.lighting.shadows,
            }),
        };
        serde_json::to_string_pretty(&desc).unwrap_or_default()
    }
}

/// Most lights a scene may have: every hit loops over all of them.
pub const MAX_LIGHTS: usize = 64;

/// Most meshes (instances, each with its own placement and material) a
/// scene may have: their instance trees make a segment's cost grow with
/// the log of their count, and on the GPU each takes 176 bytes, so this
/// many fit well within a storage binding.
pub const MAX_MESHES: usize = 100_000;

/// The largest ball or tube radius a geometry takes: in H3 `cosh r` must
/// stay far inside f32 (it overflows past r = 89), in S3 a ball of radius
/// pi is the whole sphere, in E3 a bound no scene needs.
#[must_use]
pub fn max_radius(g: Geometry) -> f64 {
    match g {
        Geometry::Hyperbolic => 40.0,
        Geometry::Spherical => core::f64::consts::PI,
        Geometry::Euclidean => 1.0e6,
    }
}

fn radius(g: Geometry, r: f64, name: &str) -> Result<(), (String, String)> {
    positive(r, name)?;
    if r > max_radius(g) {
        return Err((
            name.into(),
            format!("must be at most {} in {g} space, got {r}", max_radius(g)),
        ));
    }
    Ok(())
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

/// Most glow a ball may have (a lamp is a few; more only saturates).
pub const MAX_GLOW: f32 = 1000.0;

fn glow(g: f32, name: &str) -> Result<(), (String, String)> {
    if g.is_finite() && (0.0..=MAX_GLOW).contains(&g) {
        Ok(())
    } else {
        Err((name.into(), format!("glow must be finite, in [0, {MAX_GLOW}], got {g}")))
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

/// A mesh ready to place, with its surface.
pub type MeshPart = (Arc<MeshData>, MeshMaterial);

/// The meshes of a glTF file, each part baked, BVHs built, and the
/// loader's warnings.
///
/// # Errors
/// As [`crate::mesh::gltf::load`].
#[cfg(feature = "gltf")]
pub fn meshes_of(path: &Path) -> Result<(Vec<MeshPart>, Vec<String>), GltfError> {
    let loaded = crate::mesh::gltf::load(path)?;
    Ok(from_loaded(loaded))
}

#[cfg(feature = "gltf")]
pub(super) fn from_loaded(loaded: crate::mesh::gltf::Loaded) -> (Vec<MeshPart>, Vec<String>) {
    let parts = loaded
        .parts
        .into_iter()
        .map(|p| (MeshData::shared(baked(&p.mesh, p.transform)), p.material))
        .collect();
    (parts, loaded.warnings)
}

/// A mesh in a scene file.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct MeshDesc {
    pub file: String,
    pub placement: [[f64; 4]; 4],
    #[serde(default = "one")]
    pub scale: f64,
    #[serde(default)]
    pub color: Option<[f32; 3]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub metallic: Option<f32>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub roughness: Option<f32>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub emission: Option<[f32; 3]>,
    #[serde(default)]
    pub attached: bool,
}

fn one() -> f64 {
    1.0
}

/// Reads the meshes of a scene file, resolving files against `dir`: the
/// meshes, and one line for each that was left out.
pub(super) fn read_meshes(
    descs: &[MeshDesc],
    dir: &Path,
    domain: &Space,
) -> Result<(Vec<SceneMesh>, Vec<String>), (String, String)> {
    let g = domain.geometry();
    let mut meshes = Vec::new();
    let mut skipped = Vec::new();
    for (i, d) in descs.iter().enumerate() {
        let field = |f: &str| format!("meshes[{i}].{f}");
        let m = crate::space::file::from_rows(d.placement);
        if !m.is_finite() {
            return Err((field("placement"), "has a NaN or infinite entry".into()));
        }
        let err = isometry::isometry_error(g, m);
        if err > 1e-6 {
            return Err((
                field("placement"),
                format!("is not an isometry of {g} space (form error {err:.2e})"),
            ));
        }
        if !(d.scale > 0.0 && d.scale.is_finite()) {
            return Err((field("scale"), format!("must be positive and finite, got {}", d.scale)));
        }
        if let Some(c) = d.color {
            color(c, &field("color"))?;
        }
        let pbr = pbr_of(d.metallic, d.roughness, &field)?;
        if let Some(e) = d.emission
            && !e.iter().all(|c| (0.0..=crate::material::MAX_EMISSIVE).contains(c))
        {
            return Err((
                field("emission"),
                format!(
                    "must be linear RGB in [0, {}] per channel, got {e:?}",
                    crate::material::MAX_EMISSIVE
                ),
            ));
        }
        if let Some(f) = domain.outside_face(m.w_axis, 1e-9) {
            return Err((
                field("placement"),
                format!(
                    "puts the mesh at {:?}, outside the fundamental domain beyond face {f}",
                    m.w_axis.to_array()
                ),
            ));
        }
        let path = dir.join(&d.file);
        #[cfg(not(feature = "gltf"))]
        let _ = path;
        #[cfg(not(feature = "gltf"))]
        let loaded: Result<(Vec<MeshPart>, Vec<String>), &str> =
            Err("this build has no glTF support (bevy_manifold_core's `gltf` feature)");
        #[cfg(feature = "gltf")]
        let loaded = meshes_of(&path);
        match loaded {
            Ok((parts, warnings)) => {
                skipped.extend(warnings);
                for (data, mut material) in parts {
                    if let Some(c) = d.color {
                        material.base_color = c;
                    }
                    if let Some(p) = pbr {
                        // The file's numbers, not times its own texture's.
                        material.pbr = Some(p);
                        material.metallic_roughness = None;
                    }
                    if let Some(e) = d.emission {
                        material.emissive = e;
                        material.emissive_texture = None;
                    }
                    meshes.push(SceneMesh {
                        data,
                        material,
                        placement: isometry::orthonormalize(g, m),
                        scale: d.scale,
                        local: DMat4::IDENTITY,
                        attached: d.attached,
                        file: Some(d.file.clone()),
                    });
                }
            }
            Err(e) => skipped.push(format!("{}: left out: {e}", field("file"))),
        }
    }
    Ok((meshes, skipped))
}

/// Scene-file entries for `meshes` (those that came from a file).
pub(super) fn describe(meshes: &[SceneMesh]) -> Vec<MeshDesc> {
    let mut out: Vec<MeshDesc> = Vec::new();
    for m in meshes {
        let Some(file) = &m.file else { continue };
        // The parts of one file share one entry.
        if out
            .last()
            .is_some_and(|d| &d.file == file && crate::space::file::from_rows(d.placement) == m.placement)
        {
            continue;
        }
        out.push(MeshDesc {
            file: file.clone(),
            placement: crate::space::file::to_rows(m.placement),
            scale: m.scale,
            color: None,
            metallic: None,
            roughness: None,
            emission: None,
            attached: m.attached,
        });
    }
    out
}
