//! `bench skinning`: what a skinned mesh's new pose costs per triangle,
//! the three steps side by side on meshes of 8,192 to 51,200 triangles:
//! skinning its vertices on the CPU (`drawables::skinned_tri_mesh`, as
//! Bevy's vertex shader skins them), refitting the last pose's BVH to them
//! (`MeshData::refit`), and building a new BVH (`MeshData::build`), which a
//! refit replaces until its boxes' area passes `REFIT_GROWTH` times the
//! built one's. The last column is that area ratio after a bend of 60
//! degrees: how much looser the refitted tree is than a new one.

use crate::best_ms;
use bevy::asset::RenderAssetUsages;
use bevy::math::{Mat4, Quat, Vec3};
use bevy::mesh::{Indices, Mesh, PrimitiveTopology, VertexAttributeValues};
use bevy_manifold::drawables::skinned_tri_mesh;
use bevy_manifold::mesh::MeshData;
use bevy_manifold::mesh::bvh::surface_area;

/// Grid sides timed: `2 n^2` triangles each.
pub const SIDES: [u32; 3] = [64, 100, 160];

/// A sheet of `n x n` quads in the x-y plane (side 1, from y = 0 to 1),
/// skinned to two joints: the bottom half to the root joint, the top half
/// to a joint at y = 0.5, blended linearly across a band around it.
fn sheet(n: u32) -> Mesh {
    let mut positions = Vec::new();
    let mut joints = Vec::new();
    let mut weights = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (i as f32 / n as f32 - 0.5, j as f32 / n as f32);
            positions.push([x, y, 0.0]);
            let top = ((y - 0.4) / 0.2).clamp(0.0, 1.0);
            joints.push([0u16, 1, 0, 0]);
            weights.push([1.0 - top, top, 0.0f32, 0.0]);
        }
    }
    let mut indices = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let a = j * (n + 1) + i;
            indices.extend([a, a + 1, a + n + 2, a, a + n + 2, a + n + 1]);
        }
    }
    let mut mesh = Mesh::new(PrimitiveTopology::TriangleList, RenderAssetUsages::all());
    mesh.insert_attribute(Mesh::ATTRIBUTE_POSITION, positions);
    mesh.insert_attribute(Mesh::ATTRIBUTE_JOINT_INDEX, VertexAttributeValues::Uint16x4(joints));
    mesh.insert_attribute(Mesh::ATTRIBUTE_JOINT_WEIGHT, weights);
    mesh.insert_indices(Indices::U32(indices));
    mesh
}

/// The second joint turned by `angle` about x at y = 0.5 (its inverse
/// bind pose the move back from there).
fn joints(angle: f32) -> [Mat4; 2] {
    let at = Mat4::from_translation(Vec3::Y * 0.5);
    [
        Mat4::IDENTITY,
        at * Mat4::from_quat(Quat::from_rotation_x(angle)) * at.inverse(),
    ]
}

/// Prints, per mesh size, the microseconds per triangle of skinning,
/// refitting and building, best of `runs`, and the refit's area ratio.
///
/// # Errors
/// A mesh that does not skin (never, for these).
pub fn run(runs: u32) -> Result<(), String> {
    println!(
        "A skinned mesh's new pose, CPU, one thread; microseconds per triangle, best of {runs}; area: the refitted BVH's box area over a new one's after a 60-degree bend"
    );
    println!(
        "{:>9} {:>9} {:>9} {:>9} {:>7}",
        "triangles", "skin", "refit", "build", "area"
    );
    for n in SIDES {
        let mesh = sheet(n);
        let rest = MeshData::build(skinned_tri_mesh(&mesh, &joints(0.0))?);
        let bent = joints(std::f32::consts::FRAC_PI_3);
        let triangles = rest.mesh.triangles.len() as f64;
        let skin_ms = best_ms(runs, || skinned_tri_mesh(&mesh, &bent))?;
        let posed = skinned_tri_mesh(&mesh, &bent)?;
        let refit_ms = best_ms(runs, || {
            rest.refit(posed.positions.clone(), posed.normals.clone())
                .map_err(|e| e.to_string())
        })?;
        let build_ms = best_ms(runs, || Ok(MeshData::build(posed.clone())))?;
        let refit = rest
            .refit(posed.positions.clone(), posed.normals.clone())
            .map_err(|e| e.to_string())?;
        let area = surface_area(&refit.nodes) / surface_area(&MeshData::build(posed.clone()).nodes);
        let per = |ms: f64| ms * 1e3 / triangles;
        println!(
            "{:>9} {:>9.3} {:>9.3} {:>9.3} {:>6.2}x",
            triangles,
            per(skin_ms),
            per(refit_ms),
            per(build_ms),
            area
        );
    }
    Ok(())
}
