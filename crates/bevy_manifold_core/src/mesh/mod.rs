//! Triangle meshes for the tracer, free of the ECS: a mesh in an object's
//! local chart is made of flat (totally geodesic) triangles in every
//! geometry (see [`crate::geometry`]), so once a ray is carried into that chart the
//! test is an ordinary ray/triangle test, accelerated by a bounding-volume
//! hierarchy ([`bvh`]). [`gltf`] reads meshes and their base colour from
//! glTF files.
//!
//! ```
//! use bevy_manifold_core::mesh::{MeshData, TriMesh};
//! // One triangle in the z = 0 plane.
//! let tri = TriMesh::new(
//!     vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
//!     None,
//!     None,
//!     vec![[0, 1, 2]],
//! )
//! .unwrap();
//! let mesh = MeshData::build(tri);
//! // A ray from above, straight down through (0.25, 0.25).
//! let hit = mesh.hit::<f64>([0.25, 0.25, 1.0], [0.0, 0.0, -1.0], f64::INFINITY).unwrap();
//! assert!((hit.s - 1.0).abs() < 1e-12);
//! ```

pub mod bvh;
#[cfg(feature = "gltf")]
pub mod gltf;
pub mod shapes;
pub mod vehicle;

pub use bvh::{BvhNode, MeshHit};

use std::sync::Arc;

/// Why a mesh cannot be traced.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeshError {
    /// No triangles at all.
    #[error("the mesh has no triangles")]
    Empty,
    /// A position is NaN or infinite.
    #[error("vertex {0} has a non-finite position")]
    NonFinite(usize),
    /// An index points past the vertices.
    #[error("triangle {triangle} uses vertex {index}, but there are only {vertices}")]
    BadIndex {
        /// The triangle.
        triangle: usize,
        /// The index.
        index: u32,
        /// How many vertices there are.
        vertices: usize,
    },
    /// More vertices or triangles than a traced mesh may have.
    #[error("{count} {what}: more than the {max} a traced mesh may have")]
    TooLarge {
        /// "vertices" or "triangles".
        what: &'static str,
        /// How many.
        count: usize,
        /// The cap.
        max: usize,
    },
    /// Attribute arrays of different lengths.
    #[error("{what} has {got} entries for {vertices} vertices")]
    Attribute {
        /// Which attribute.
        what: &'static str,
        /// Its length.
        got: usize,
        /// The vertex count.
        vertices: usize,
    },
}

/// Most vertices a traced mesh may have.
pub const MAX_VERTICES: usize = 1 << 22;

/// Most triangles a traced mesh may have (two million: its GPU buffers
/// stay under the 128 MiB storage-binding size every adapter allows).
pub const MAX_TRIANGLES: usize = 1 << 21;

/// Most texels a traced texture may have (4096 x 4096).
pub const MAX_TEXELS: u64 = 1 << 24;

/// A triangle mesh in its object's local chart: positions, per-vertex
/// normals and texture coordinates, triangles by vertex index.
#[derive(Clone, Debug, PartialEq)]
pub struct TriMesh {
    /// Vertex positions.
    pub positions: Vec<[f32; 3]>,
    /// Unit vertex normals.
    pub normals: Vec<[f32; 3]>,
    /// Texture coordinates.
    pub uvs: Vec<[f32; 2]>,
    /// Triangles (counter-clockwise seen from the front).
    pub triangles: Vec<[u32; 3]>,
}

impl TriMesh {
    /// A mesh from its arrays, checked: at least one triangle, finite
    /// positions, indices in range, attributes as long as the positions.
    /// Missing normals are computed (area-weighted face normals); missing
    /// texture coordinates are zero.
    ///
    /// # Errors
    /// [`MeshError`], naming the first bad vertex or triangle.
    pub fn new(
        positions: Vec<[f32; 3]>,
        normals: Option<Vec<[f32; 3]>>,
        uvs: Option<Vec<[f32; 2]>>,
        triangles: Vec<[u32; 3]>,
    ) -> Result<Self, MeshError> {
        let n = positions.len();
        if triangles.is_empty() {
            return Err(MeshError::Empty);
        }
        for (what, count, max) in [
            ("vertices", n, MAX_VERTICES),
            ("triangles", triangles.len(), MAX_TRIANGLES),
        ] {
            if count > max {
                return Err(MeshError::TooLarge { what, count, max });
            }
        }
        if let Some(i) = positions.iter().position(|p| p.iter().any(|c| !c.is_finite())) {
            return Err(MeshError::NonFinite(i));
        }
        for (t, tri) in triangles.iter().enumerate() {
            if let Some(&index) = tri.iter().find(|&&i| i as usize >= n) {
                return Err(MeshError::BadIndex {
                    triangle: t,
                    index,
                    vertices: n,
                });
            }
        }
        let check = |what, got| {
            if got == n {
                Ok(())
            } else {
                Err(MeshError::Attribute { what, got, vertices: n })
            }
        };
        let normals = match normals {
            Some(mut v) => {
                check("NORMAL", v.len())?;
                // A zero, tiny or non-finite normal would give NaN shading:
                // such vertices take the normal of their faces instead.
                let usable = |x: &[f32; 3]| {
                    let l2 = x[0] * x[0] + x[1] * x[1] + x[2] * x[2];
                    l2.is_finite() && l2 > 1e-12
                };
                if !v.iter().all(usable) {
                    let fallback = face_normals(&positions, &triangles);
                    for (x, f) in v.iter_mut().zip(fallback) {
                        if !usable(x) {
                            *x = f;
                        }
                    }
                }
                v
            }
            None => face_normals(&positions, &triangles),
        };
        let uvs = match uvs {
            Some(mut v) => {
                check("TEXCOORD_0", v.len())?;
                for uv in &mut v {
                    if !(uv[0].is_finite() && uv[1].is_finite()) {
                        *uv = [0.0; 2];
                    }
                }
                v
            }
            None => vec![[0.0; 2]; n],
        };
        Ok(TriMesh {
            positions,
            normals,
            uvs,
            triangles,
        })
    }

    /// The largest distance of a vertex from the local origin (chart
    /// units).
    #[must_use]
    pub fn bounding_radius(&self) -> f32 {
        self.positions
            .iter()
            .map(|p| (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt())
            .fold(0.0, f32::max)
    }
}

fn face_normals(positions: &[[f32; 3]], triangles: &[[u32; 3]]) -> Vec<[f32; 3]> {
    let mut acc = vec![glam::Vec3::ZERO; positions.len()];
    for t in triangles {
        let [a, b, c] = t.map(|i| glam::Vec3::from(positions[i as usize]));
        let n = (b - a).cross(c - a);
        for &i in t {
            acc[i as usize] += n;
        }
    }
    acc.into_iter()
        .map(|n| n.normalize_or(glam::Vec3::Z).to_array())
        .collect()
}

/// A mesh ready to trace: its triangles reordered so every BVH leaf holds
/// a contiguous run, and the flattened BVH ([`bvh::build`]). Shared by
/// every instance that shows it.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshData {
    /// The mesh, triangles in BVH order.
    pub mesh: TriMesh,
    /// The hierarchy, root first.
    pub nodes: Vec<BvhNode>,
    /// Per node, the index past its subtree ([`bvh::skip_links`]), where
    /// the walk goes on when the node's box is missed.
    pub skip: Vec<u32>,
}

impl MeshData {
    /// Builds the BVH of `mesh` (surface-area heuristic).
    #[must_use]
    pub fn build(mut mesh: TriMesh) -> Self {
        let (nodes, order) = bvh::build(&mesh);
        mesh.triangles = order.iter().map(|&i| mesh.triangles[i as usize]).collect();
        let skip = bvh::skip_links(&nodes);
        MeshData { mesh, nodes, skip }
    }

    /// The same triangles with their vertices moved (a skinned mesh's
    /// next pose: `positions` and `normals` one per vertex, as this mesh
    /// has them): the BVH's shape kept and its boxes fitted to the new
    /// positions ([`bvh::refit`]), far cheaper than building it again.
    ///
    /// # Errors
    /// [`MeshError`] when the arrays are not one per vertex or a position
    /// is not finite.
    pub fn refit(&self, positions: Vec<[f32; 3]>, normals: Vec<[f32; 3]>) -> Result<Self, MeshError> {
        if positions.len() != self.mesh.positions.len() {
            return Err(MeshError::Attribute {
                what: "positions",
                got: positions.len(),
                vertices: self.mesh.positions.len(),
            });
        }
        let mesh = TriMesh::new(
            positions,
            Some(normals),
            Some(self.mesh.uvs.clone()),
            self.mesh.triangles.clone(),
        )?;
        let mut nodes = self.nodes.clone();
        bvh::refit(&mut nodes, &mesh);
        Ok(MeshData {
            mesh,
            nodes,
            skip: self.skip.clone(),
        })
    }

    /// [`MeshData::build`] behind an `Arc`, as scenes hold meshes.
    #[must_use]
    pub fn shared(mesh: TriMesh) -> Arc<Self> {
        Arc::new(Self::build(mesh))
    }

    /// The nearest triangle the affine ray `o + s d` (local chart) hits
    /// with `0 <= s <= s_max`, through the BVH.
    #[must_use]
    pub fn hit<R: crate::geometry::Real>(&self, o: [R; 3], d: [R; 3], s_max: R) -> Option<MeshHit<R>> {
        bvh::hit_mesh(self, o, d, s_max)
    }
}

pub use crate::material::MeshMaterial;

/// An RGBA8 texture (sRGB-encoded colour), sampled nearest with repeat by
/// both tracers alike.
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// Texels, row-major from the top, as packed RGBA8 (R in the low byte).
    pub texels: Vec<u32>,
}

impl Texture {
    /// A texture of `width x height` packed RGBA8 texels, checked: at least
    /// one texel, at most [`MAX_TEXELS`], and as many texels as the size
    /// says (extra ones are dropped).
    ///
    /// # Errors
    /// A zero or oversized size, or too few texels, said in words.
    pub fn new(width: u32, height: u32, mut texels: Vec<u32>) -> Result<Texture, String> {
        let count = u64::from(width) * u64::from(height);
        if count == 0 {
            return Err(format!("an empty {width}x{height} image"));
        }
        if count > MAX_TEXELS {
            return Err(format!(
                "{width}x{height} texels, more than the {MAX_TEXELS} a traced texture may have"
            ));
        }
        if (texels.len() as u64) < count {
            return Err(format!("{} texels for a {width}x{height} image", texels.len()));
        }
        texels.truncate(count as usize);
        Ok(Texture { width, height, texels })
    }

    /// The packed RGBA8 texel at `uv`, nearest, repeating. WGSL twin: its
    /// part of `texel_unorm` in `shaders/texture.wgsl`.
    #[must_use]
    pub fn texel(&self, uv: [f32; 2]) -> u32 {
        let i = texel_index(uv[0], self.width);
        let j = texel_index(uv[1], self.height);
        self.texels[(j * self.width + i) as usize]
    }

    /// The linear RGB colour at `uv` of an sRGB-encoded texture (a base
    /// colour, an emission), nearest texel, repeating. WGSL twin:
    /// `texture_rgb` in `shaders/texture.wgsl`.
    #[must_use]
    pub fn sample(&self, uv: [f32; 2]) -> [f32; 3] {
        let c = self.texel(uv);
        [0, 8, 16].map(|s| srgb_to_linear(((c >> s) & 0xff) as f32 / 255.0))
    }

    /// The texel at `uv` as four numbers in `[0, 1]`, undecoded (a linear
    /// texture: metallic-roughness, a normal map; or the alpha in `[3]`).
    /// WGSL twin: `texel_unorm` in `shaders/texture.wgsl`.
    #[must_use]
    pub fn sample_unorm(&self, uv: [f32; 2]) -> [f32; 4] {
        let c = self.texel(uv);
        [0, 8, 16, 24].map(|s| ((c >> s) & 0xff) as f32 / 255.0)
    }
}

/// The texel column (or row) of coordinate `x` in a texture `n` wide,
/// repeating: the same arithmetic as the shader's `texel_index`.
#[must_use]
pub fn texel_index(x: f32, n: u32) -> u32 {
    let f = x - x.floor();
    ((f * n as f32) as u32).min(n.max(1) - 1)
}

/// sRGB-encoded to linear: the same formula as the shader's.
#[must_use]
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}
