//! Meshes in a tracer scene: a triangle mesh with its BVH, its surface,
//! and where it is placed. In scene files, `"meshes": [{"file": "x.glb",
//! "placement": [[..4..] x4], "scale": s, "color": [r,g,b]}]`; a mesh file
//! that fails to load is left out (the reason is kept in
//! [`super::Scene::skipped`]) and the rest of the scene still renders.

use crate::geometry::{Geometry, isometry};
use crate::mesh::gltf::GltfError;
use crate::mesh::{MeshData, MeshMaterial, TriMesh};
use glam::{DMat4, DVec4, Mat4, Vec3};
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::sync::{Arc, OnceLock};

/// A triangle mesh placed in the space, drawn through its BVH; copies are
/// seen in every copy of the domain like any object. Mesh `j` of a scene
/// with `n` balls has object id `n + 1 + j`.
#[derive(Clone, Debug)]
pub struct SceneMesh {
    /// Triangles and hierarchy (shared by every mesh that shows them).
    pub data: Arc<MeshData>,
    /// Base colour and texture.
    pub material: MeshMaterial,
    /// Carries the mesh's local chart to its place: an isometry inside the
    /// domain (orientation-reversing for a mirror image).
    pub placement: DMat4,
    /// The mesh's coordinates are multiplied by this in its local chart.
    pub scale: f64,
    /// The mesh's own transform inside its object, applied before the
    /// scale (a glTF node's; a Euclidean similarity of the local chart,
    /// which keeps triangles flat). The identity for most meshes.
    pub local: DMat4,
    /// Attached to the camera: its own copy is not drawn (the camera sits
    /// inside it), only its images in the other copies of the domain.
    pub attached: bool,
    /// The file it came from, for scene files.
    pub file: Option<String>,
}

impl PartialEq for SceneMesh {
    fn eq(&self, o: &Self) -> bool {
        Arc::ptr_eq(&self.data, &o.data)
            && self.material == o.material
            && self.placement == o.placement
            && self.scale == o.scale
            && self.local == o.local
            && self.attached == o.attached
            && self.file == o.file
    }
}

impl SceneMesh {
    /// `data` with `material` at `placement`, scaled by `scale`.
    #[must_use]
    pub fn new(data: Arc<MeshData>, material: MeshMaterial, placement: DMat4, scale: f64) -> Self {
        SceneMesh {
            data,
            material,
            placement,
            scale,
            local: DMat4::IDENTITY,
            attached: false,
            file: None,
        }
    }

    /// The bounding distance around the placement's point: the mesh's
    /// chart radius times the scale, as a distance of `g` (`None` when it
    /// reaches the sphere at infinity of H3 or past a quarter turn of S3).
    #[must_use]
    pub fn bounding_radius(&self, g: Geometry) -> Option<f64> {
        let l = &self.local;
        let stretch = [l.x_axis, l.y_axis, l.z_axis]
            .iter()
            .map(|c| c.truncate().length())
            .fold(0.0, f64::max);
        let reach = l.w_axis.truncate().length() + stretch * f64::from(self.data.mesh.bounding_radius());
        let r = reach * self.scale;
        match g {
            Geometry::Euclidean => Some(r),
            Geometry::Hyperbolic => (r < 1.0).then(|| r.atanh()),
            Geometry::Spherical => Some(r.atan()),
        }
    }

    /// The point the mesh is placed at (its local origin).
    #[must_use]
    pub fn center(&self, g: Geometry) -> DVec4 {
        g.normalize_point::<f64>(self.placement * DVec4::W)
    }
}

/// Bakes a glTF part's node transform into its vertices (positions and
/// normals), so the mesh is in the file's scene coordinates.
#[must_use]
pub fn baked(mesh: &TriMesh, transform: Mat4) -> TriMesh {
    if transform == Mat4::IDENTITY {
        return mesh.clone();
    }
    let normal = glam::Mat3::from_mat4(transform).inverse().transpose();
    let mut out = mesh.clone();
    for p in &mut out.positions {
        *p = transform.transform_point3(Vec3::from(*p)).to_array();
    }
    for n in &mut out.normals {
        *n = (normal * Vec3::from(*n)).normalize_or(Vec3::Z).to_array();
    }
    out
}

/// A mesh ready to place, with its surface.
pub type MeshPart = (Arc<MeshData>, MeshMaterial);

/// The meshes of a glTF file, each part baked, BVHs built, and the
/// loader's warnings.
///
/// # Errors
/// As [`crate::mesh::gltf::load`].
pub fn meshes_of(path: &Path) -> Result<(Vec<MeshPart>, Vec<String>), GltfError> {
    let loaded = crate::mesh::gltf::load(path)?;
    Ok(from_loaded(loaded))
}

fn from_loaded(loaded: crate::mesh::gltf::Loaded) -> (Vec<MeshPart>, Vec<String>) {
    let parts = loaded
        .parts
        .into_iter()
        .map(|p| (MeshData::shared(baked(&p.mesh, p.transform)), p.material))
        .collect();
    (parts, loaded.warnings)
}

/// The models the crate carries (`assets/models/`, embedded so an app
/// from crates.io has them): Suzanne and the two hands, parsed and
/// BVH-built once.
pub mod builtin {
    use super::*;

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
        M.get_or_init(|| parse(include_bytes!("../../assets/models/suzanne.glb"), "suzanne.glb"))
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
            L.get_or_init(|| parse(include_bytes!("../../assets/models/left.glb"), "left.glb"))
                .clone()
        } else {
            R.get_or_init(|| parse(include_bytes!("../../assets/models/right.glb"), "right.glb"))
                .clone()
        }
    }
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
    g: Geometry,
) -> Result<(Vec<SceneMesh>, Vec<String>), (String, String)> {
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
        let path = dir.join(&d.file);
        match meshes_of(&path) {
            Ok((parts, warnings)) => {
                skipped.extend(warnings);
                for (data, mut material) in parts {
                    if let Some(c) = d.color {
                        material.base_color = c;
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
            attached: m.attached,
        });
    }
    out
}
