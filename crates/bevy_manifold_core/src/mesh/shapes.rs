//! Simple meshes made in code.
//!
//! ```
//! use bevy_manifold_core::mesh::shapes::cuboid;
//! let b = cuboid([0.5, 0.25, 0.125]);
//! assert_eq!(b.triangles.len(), 12);
//! // Flat-shaded: each face has corners of its own.
//! assert_eq!(b.positions.len(), 24);
//! ```

use super::TriMesh;

/// The box `[-h.x, h.x] x [-h.y, h.y] x [-h.z, h.z]`, flat-shaded (four
/// corners of its own to each face), every face wound outward.
///
/// # Panics
/// Never: its arrays are consistent by construction.
#[must_use]
pub fn cuboid(h: [f32; 3]) -> TriMesh {
    let corner = |i: u32| {
        [
            if i & 1 == 0 { -h[0] } else { h[0] },
            if i & 2 == 0 { -h[1] } else { h[1] },
            if i & 4 == 0 { -h[2] } else { h[2] },
        ]
    };
    // Each face's corners counter-clockwise seen from outside.
    let quads = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    for quad in quads {
        let k = positions.len() as u32;
        positions.extend(quad.map(corner));
        triangles.extend([[k, k + 1, k + 2], [k, k + 2, k + 3]]);
    }
    TriMesh::new(positions, None, None, triangles).expect("a box's arrays are consistent")
}
