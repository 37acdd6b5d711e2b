//! The GPU's walk of a mesh's hierarchy (`hit_mesh` in `shaders/bvh.wgsl`,
//! over `mesh_data` as the tracer packs it) against the CPU's brute force
//! over every triangle, in `f64`: each ray at Suzanne gets the same
//! nearest triangle at the same distance, or a miss where the CPU finds
//! none. An image comparison is not enough here: a leaf the walk skips
//! leaves the triangle behind it to be hit, shaded almost alike.
//!
//! Without a GPU adapter this test is listed as ignored; under CI (`CI`
//! set) a missing adapter is a failure.

use bevy_manifold_core::mesh::bvh::{hit_brute_force, hit_triangle};
use bevy_manifold_core::prelude::*;
use bevy_manifold_core::trace::{FlatScene, PaperOptions};
use bevy_manifold_gpu::GpuScene;
use bevy_manifold_gpu::WgslModule;
use bevy_manifold_test_support::Rng;

mod probe;

/// One ray per invocation: `rays` holds origin and direction, two words a
/// ray; `mesh` the mesh's offsets in `mesh_data` and its node count.
const PROBE: WgslModule = WgslModule {
    path: "bevy_manifold/tests/mesh_walk_probe.wgsl",
    source: "
#import bevy_manifold::bindings::Instance
#import bevy_manifold::bvh::hit_mesh

@group(0) @binding(20) var<storage, read> rays: array<vec4<f32>>;
@group(0) @binding(21) var<storage, read> mesh: array<u32, 4>;
@group(0) @binding(22) var<storage, read_write> hits: array<vec4<f32>>;

@compute @workgroup_size(64, 1, 1)
fn walk(@builtin(global_invocation_id) id: vec3<u32>) {
    if 2u * id.x + 1u >= arrayLength(&rays) {
        return;
    }
    var inst: Instance;
    inst.nodes = mesh[0];
    inst.vertices = mesh[1];
    inst.triangles = mesh[2];
    inst.node_count = mesh[3];
    let h = hit_mesh(inst, rays[2u * id.x].xyz, rays[2u * id.x + 1u].xyz, 1.0e30);
    hits[id.x] = vec4<f32>(h.s, bitcast<f32>(h.triangle), h.u, h.v);
}
",
};

fn the_gpu_walk_finds_the_brute_force_nearest_triangle() {
    let space = catalog::by_name("torus").expect("catalog");
    let scene = Scene::paper(&space, &PaperOptions::default());
    let flat = FlatScene::<f32>::new(&space, &scene);
    let packed = GpuScene::pack(&space, &flat, &TraceSettings::default());
    // The first mesh is packed first: its instances start at word 0.
    let mesh = &flat.meshes[0];
    let inst = packed
        .objects
        .instances
        .iter()
        .find(|i| i.nodes == 0)
        .expect("an instance of the first mesh");
    assert_eq!(inst.node_count as usize, mesh.nodes.len());
    let (lo, hi) = mesh
        .mesh
        .positions
        .iter()
        .fold(([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]), |(lo, hi), p| {
            (
                [0, 1, 2].map(|k| lo[k].min(f64::from(p[k]))),
                [0, 1, 2].map(|k| hi[k].max(f64::from(p[k]))),
            )
        });
    let centre = [0, 1, 2].map(|k| 0.5 * (lo[k] + hi[k]));
    let reach = (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>().sqrt();
    let mut rng = Rng(59);
    let rays: Vec<([f64; 3], [f64; 3])> = (0..4000)
        .map(|_| {
            let u = rng.unit();
            let o = [0, 1, 2].map(|k| centre[k] + 1.5 * reach * u[k]);
            let target = [0, 1, 2].map(|k| lo[k] + (hi[k] - lo[k]) * rng.next_f64());
            // Rounded to f32 first, so both sides trace the same ray.
            let o = o.map(|x| f64::from(x as f32));
            let d = [0, 1, 2].map(|k| f64::from((target[k] - o[k]) as f32));
            (o, d)
        })
        .collect();
    let words: Vec<[f32; 4]> = rays
        .iter()
        .flat_map(|(o, d)| [o, d].map(|v| [v[0] as f32, v[1] as f32, v[2] as f32, 0.0]))
        .collect();
    let bytes = probe::run(
        PROBE,
        &["MESHES"],
        "walk",
        &[
            (7, bytemuck::cast_slice(&packed.objects.mesh_data)),
            (20, bytemuck::cast_slice(&words)),
            (
                21,
                bytemuck::cast_slice(&[inst.nodes, inst.vertices, inst.triangles, inst.node_count]),
            ),
        ],
        (22, (rays.len() * 16) as u64),
        rays.len() as u32,
    );
    let hits: Vec<[f32; 4]> = bytemuck::pod_collect_to_vec(&bytes);
    let mut hit = 0;
    for (k, ((o, d), gpu)) in rays.iter().zip(&hits).enumerate() {
        let cpu = hit_brute_force::<f64>(mesh, *o, *d, f64::INFINITY);
        let s = f64::from(gpu[0]);
        let Some(cpu) = cpu else {
            assert!(s < 0.0, "ray {k}: the GPU hits at {s}, brute force nothing");
            continue;
        };
        hit += 1;
        assert!(
            (s - cpu.s).abs() <= 1e-4 * (1.0 + cpu.s),
            "ray {k}: the GPU hits at {s}, brute force at {} (triangle {})",
            cpu.s,
            cpu.triangle
        );
        // The same triangle, or one the ray meets as near (a shared edge).
        let triangle = gpu[1].to_bits();
        if triangle != cpu.triangle {
            let corners =
                mesh.mesh.triangles[triangle as usize].map(|i| mesh.mesh.positions[i as usize].map(f64::from));
            let there = hit_triangle(*o, *d, corners[0], corners[1], corners[2]).map(|h| h.0);
            assert!(
                there.is_some_and(|t| (t - cpu.s).abs() <= 1e-4 * (1.0 + cpu.s)),
                "ray {k}: the GPU's triangle {triangle} is not the nearest ({}, at {})",
                cpu.triangle,
                cpu.s
            );
        }
    }
    assert!(hit > 1000, "only {hit} of {} rays hit the mesh", rays.len());
}

bevy_manifold_test_support::test_main! {
    cpu: [],
    gpu: [the_gpu_walk_finds_the_brute_force_nearest_triangle],
}
