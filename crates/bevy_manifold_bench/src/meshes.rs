//! `bench meshes`: frame time against triangle count. Suzanne as shipped
//! (3,936 triangles), and cut into 9 and 100 pieces per triangle (35k and
//! 394k), each in the middle of the domain of the torus and of the
//! Seifert-Weber space, traced at 3 and 8 levels; and each BVH's build
//! time. With a BVH the cost of a hit should grow about with the log of
//! the triangle count.

use crate::best_ms;
use bevy_manifold::mesh::{MeshData, MeshMaterial, TriMesh};
use bevy_manifold::prelude::*;
use bevy_manifold::trace::builtin;
use bevy_manifold_gpu::GpuTracer;
use std::sync::Arc;
use std::time::Instant;

/// `mesh` with every triangle cut into `k * k` by a barycentric grid.
#[must_use]
pub fn subdivide(mesh: &TriMesh, k: u32) -> TriMesh {
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    let mut triangles = Vec::new();
    let lerp3 = |a: [f32; 3], b: [f32; 3], c: [f32; 3], (u, v): (f32, f32)| {
        [0, 1, 2].map(|i| a[i] * (1.0 - u - v) + b[i] * u + c[i] * v)
    };
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
        let [na, nb, nc] = t.map(|i| mesh.normals[i as usize]);
        let base = positions.len() as u32;
        // Grid points (i, j), i + j <= k, row by row.
        let index = |i: u32, j: u32| base + i * (k + 1) - i * (i.saturating_sub(1)) / 2 + j;
        for i in 0..=k {
            for j in 0..=k - i {
                let uv = (j as f32 / k as f32, i as f32 / k as f32);
                positions.push(lerp3(a, b, c, uv));
                normals.push(lerp3(na, nb, nc, uv));
            }
        }
        for i in 0..k {
            for j in 0..k - i {
                triangles.push([index(i, j), index(i, j + 1), index(i + 1, j)]);
                if j + 1 < k - i {
                    triangles.push([index(i, j + 1), index(i + 1, j + 1), index(i + 1, j)]);
                }
            }
        }
    }
    TriMesh::new(positions, Some(normals), None, triangles).expect("a subdivided mesh is a mesh")
}

pub fn run(width: u32, height: u32, runs: u32) -> Result<(), String> {
    let mut gpu = GpuTracer::new().map_err(|e| e.to_string())?;
    let suzanne = builtin::suzanne();
    println!(
        "meshes: BVH build and GPU frame time (trace + readback, best of {runs}) at {width}x{height}, on {}",
        gpu.adapter_name()
    );
    println!(
        "{:>10} {:>8} {:>9} {:<16} {:>10} {:>10}",
        "triangles", "nodes", "build ms", "space", "3 lv ms", "8 lv ms"
    );
    for k in [1, 3, 10] {
        let mesh = if k == 1 {
            suzanne.mesh.clone()
        } else {
            subdivide(&suzanne.mesh, k)
        };
        let n = mesh.triangles.len();
        let t = Instant::now();
        let data = Arc::new(MeshData::build(mesh));
        let build = t.elapsed().as_secs_f64() * 1e3;
        for name in ["torus", "seifert-weber"] {
            let space = catalog::by_name(name).ok_or("catalog")?;
            let mut scene = Scene::default_for(&space);
            scene.balls.clear();
            let facing = isometry::rotation(glam::DVec3::Y, 0.4);
            scene.meshes.push(SceneMesh::new(
                data.clone(),
                MeshMaterial::default(),
                facing,
                0.12 * space.inradius(),
            ));
            let mut ms = [0.0; 2];
            for (slot, levels) in [3, 8].into_iter().enumerate() {
                let settings = TraceSettings {
                    width,
                    height,
                    levels,
                    ..TraceSettings::default()
                };
                ms[slot] = best_ms(runs, || {
                    gpu.render(&space, &scene, &settings).map_err(|e| e.to_string())
                })?;
            }
            println!(
                "{n:>10} {:>8} {build:>9.1} {name:<16} {:>10.1} {:>10.1}",
                data.nodes.len(),
                ms[0],
                ms[1]
            );
        }
    }
    Ok(())
}
