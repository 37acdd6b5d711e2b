//! A mesh in a tracer scene: a triangle mesh with its BVH, its surface,
//! its surface, and where it is placed (scene files name them by file; see
//! [`super::file`]).

use crate::geometry::Geometry;
use crate::mesh::{MeshData, MeshMaterial, TriMesh};
use glam::{DMat4, DVec4, Mat4, Vec3};
use std::sync::Arc;

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
