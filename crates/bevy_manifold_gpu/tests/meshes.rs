//! Triangle meshes in the GPU tracer: against the CPU reference with
//! Suzanne and the hands in every space, and what the shader compiles for
//! scenes with and without meshes. (The CPU side: `bevy_manifold_core`'s
//! `tests/meshes.rs`.)

use bevy_manifold_core::geometry::isometry;
use bevy_manifold_core::mesh::{MeshData, MeshMaterial, TriMesh};
use bevy_manifold_core::prelude::*;
use bevy_manifold_core::trace::SceneMesh;
use bevy_manifold_test_support::{agreement, tracer};
use glam::{DMat4, DVec3};

fn gpu_and_cpu_agree_on_suzanne_and_the_hands_in_every_space() {
    let mut gpu = tracer();
    for name in catalog::NAMES {
        let space = catalog::by_name(name).expect("catalog");
        let scene = Scene::paper_default(&space);
        assert_eq!(scene.meshes.len(), 3);
        let settings = TraceSettings {
            width: 256,
            height: 256,
            levels: 8,
            ..TraceSettings::default()
        };
        let g = gpu.render(&space, &scene, &settings).expect("render");
        let c = render::<f64>(&space, &scene, &settings);
        let (ids, colors) = agreement(&g, &c);
        let meshes = c.pixels.iter().filter(|p| (1..=3).contains(&p.object)).count();
        eprintln!(
            "{name}: ids {:.3}%, colours {:.3}% ({meshes} mesh pixels of {})",
            ids * 100.0,
            colors * 100.0,
            c.pixels.len()
        );
        assert!(meshes > 2000, "{name}: the meshes are in view");
        assert!(ids >= 0.995, "{name}: ids agree on {:.3}%", ids * 100.0);
        assert!(colors >= 0.99, "{name}: colours agree on {:.3}%", colors * 100.0);
    }
}

/// The camera beside a face wearing its body: the GPU skips the home body
/// through the face as the CPU does (the same rule, `same_cell_point`).
fn the_gpu_never_sees_the_cameras_own_body_from_inside() {
    let mut gpu = tracer();
    for space in [catalog::torus(1.0), catalog::seifert_weber()] {
        let (scene, radius) = bevy_manifold_test_support::stress::body_beside_a_face(&space);
        let settings = TraceSettings {
            width: 96,
            height: 96,
            levels: 6,
            ..TraceSettings::default()
        };
        let g = gpu.render(&space, &scene, &settings).expect("render");
        let c = render::<f64>(&space, &scene, &settings);
        let nearest = g
            .pixels
            .iter()
            .filter(|p| p.object == 1)
            .map(|p| p.distance)
            .fold(f32::INFINITY, f32::min);
        assert!(
            f64::from(nearest) > radius,
            "{}: GPU hit on the body at {nearest}",
            space.name()
        );
        let (ids, _) = agreement(&g, &c);
        assert!(ids >= 0.995, "{}: ids agree on {:.3}%", space.name(), ids * 100.0);
    }
}

fn meshes_share_one_bvh_and_scenes_without_them_compile_none() {
    let space = catalog::torus(1.0);
    let mut scene = Scene::empty();
    let data = MeshData::shared(
        TriMesh::new(
            vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            None,
            None,
            vec![[0, 1, 2]],
        )
        .unwrap(),
    );
    for i in 0..10 {
        let at = DMat4::from_translation(DVec3::new(-0.4 + 0.08 * f64::from(i), 0.0, 0.0));
        scene
            .meshes
            .push(SceneMesh::new(data.clone(), MeshMaterial::default(), at, 0.05));
    }
    let flat = bevy_manifold_core::trace::FlatScene::<f32>::new(&space, &scene);
    assert_eq!(flat.meshes.len(), 1, "ten instances, one mesh");
    assert_eq!(flat.instances.len(), 10);
    let defs = bevy_manifold_gpu::TraceDefs::for_scene(&space, &scene, false);
    assert!(defs.meshes);
    assert!(!bevy_manifold_gpu::TraceDefs::for_scene(&space, &Scene::default_for(&space), false).meshes);
}

/// Every material feature at once, GPU against the CPU f64 reference in
/// each geometry: a PBR ball (the GGX lobe), Suzanne in a metallic PBR
/// material with emission, and the material quad written by the test
/// support (its metallic-roughness, emission and normal textures and its
/// alpha mask), under light images and shadows.
fn gpu_and_cpu_agree_on_materials_in_every_geometry() {
    let mut gpu = tracer();
    let dir = std::env::temp_dir().join(format!("bevy_manifold_gpu_materials_{}", std::process::id()));
    let quad = bevy_manifold_core::mesh::gltf::load(bevy_manifold_test_support::materials::write_material_quad(&dir))
        .expect("the quad loads");
    let part = quad.parts.into_iter().next().expect("one part");
    let quad_data = MeshData::shared(part.mesh);
    for space in [catalog::torus(1.0), catalog::seifert_weber(), catalog::poincare()] {
        let g = space.geometry();
        let mut scene = Scene::paper_default(&space);
        let r = space.inradius();
        scene.balls.push(Ball {
            center: isometry::translation(g, DVec3::new(-0.3 * r, 0.2 * r, -0.2 * r)) * glam::DVec4::W,
            radius: 0.15 * r,
            color: [0.9, 0.7, 0.3],
            glow: 0.0,
            pbr: Some(bevy_manifold_core::material::Pbr {
                metallic: 0.7,
                roughness: 0.35,
            }),
        });
        scene.meshes[0].material.pbr = Some(bevy_manifold_core::material::Pbr {
            metallic: 1.0,
            roughness: 0.5,
        });
        scene.meshes[0].material.emissive = [0.1, 0.05, 0.0];
        let mut material = part.material.clone();
        // Emission within [0, 1], where colours are compared.
        material.emissive = material.emissive.map(|c| c * 0.05);
        let at = scene.camera.isometry * isometry::translation(g, DVec3::new(0.15 * r, 0.0, -0.45 * r));
        scene
            .meshes
            .push(SceneMesh::new(quad_data.clone(), material, at, 0.2 * r));
        scene.lighting.shadows = true;
        let defs = bevy_manifold_gpu::TraceDefs::for_scene(&space, &scene, false);
        assert!(defs.materials && defs.alpha_mask && defs.shadows, "{defs:?}");
        let settings = TraceSettings {
            width: 160,
            height: 160,
            levels: 6,
            ..TraceSettings::default()
        };
        let gi = gpu.render(&space, &scene, &settings).expect("render");
        let c = render::<f64>(&space, &scene, &settings);
        let (ids, colors) = agreement(&gi, &c);
        let quad_id = scene.balls.len() as u32 + 1 + 3;
        let quad_pixels = c.pixels.iter().filter(|p| p.object == quad_id).count();
        eprintln!(
            "{g}: ids {:.3}%, colours {:.3}% ({quad_pixels} quad pixels)",
            ids * 100.0,
            colors * 100.0
        );
        assert!(quad_pixels > 200, "{g}: the quad is in view");
        assert!(ids >= 0.995, "{g}: ids agree on {:.3}%", ids * 100.0);
        assert!(colors >= 0.99, "{g}: colours agree on {:.3}%", colors * 100.0);
    }
}

/// A level of props (`stress::props`, thousands of instances of three
/// meshes): traced through their instance trees, the GPU sees what the
/// CPU f64 reference sees, and what it sees itself with every instance
/// tested on every segment; in each geometry. (Not against its own brute
/// force at 10,000 instances: lavapipe ends an invocation's loops once
/// they have taken 65,535 iterations between them, which a few segments
/// testing 10,000 instances each pass, so there the brute force is cut
/// short in some pixels and the tree is not.)
fn gpu_instance_trees_trace_the_cpu_and_the_brute_force_hits() {
    use bevy_manifold_gpu::layout::NO_INSTANCE_TREES;
    use bevy_manifold_gpu::pack::GpuObjects;
    let mut gpu = tracer();
    for (name, n) in [("torus", 10_000), ("seifert-weber", 2_000), ("poincare", 2_000)] {
        let space = catalog::resolve(name).expect("catalog");
        let scene = bevy_manifold_test_support::stress::props(&space, n, 0.03, 5);
        let objects = GpuObjects::pack(&bevy_manifold_core::trace::FlatScene::<f32>::new(&space, &scene));
        assert_ne!(objects.instance_trees, NO_INSTANCE_TREES, "{name}: trees packed");
        let defs = bevy_manifold_gpu::TraceDefs::for_scene(&space, &scene, false).for_objects(&objects);
        assert!(defs.names().contains(&"INSTANCE_TREE"), "{name}: {defs:?}");
        let settings = |cull| TraceSettings {
            width: 160,
            height: 100,
            levels: 4,
            cull,
            ..TraceSettings::default()
        };
        let tree = gpu.render(&space, &scene, &settings(true)).expect("render");
        let c = render::<f64>(&space, &scene, &settings(true));
        let (ids, colors) = agreement(&tree, &c);
        let same =
            (n <= 2_000).then(|| agreement(&tree, &gpu.render(&space, &scene, &settings(false)).expect("render")).0);
        let first = scene.balls.len() as u32 + 1;
        let seen: std::collections::HashSet<u32> = c
            .pixels
            .iter()
            .map(|p| p.object)
            .filter(|&o| o >= first && o < first + n as u32)
            .collect();
        eprintln!(
            "{name}, {n} instances: against the CPU ids {:.3}%, colours {:.3}%; ids against every instance tested {}; {} instances seen",
            ids * 100.0,
            colors * 100.0,
            same.map_or("not traced".into(), |s| format!("{:.3}%", s * 100.0)),
            seen.len()
        );
        assert!(seen.len() > 100, "{name}: many instances in view");
        assert!(ids >= 0.995, "{name}: ids agree on {:.3}%", ids * 100.0);
        assert!(colors >= 0.99, "{name}: colours agree on {:.3}%", colors * 100.0);
        if let Some(same) = same {
            assert!(
                same >= 0.999,
                "{name}: the tree changes {:.3}% of ids",
                (1.0 - same) * 100.0
            );
        }
    }
}

bevy_manifold_test_support::test_main! {
    cpu: [meshes_share_one_bvh_and_scenes_without_them_compile_none],
    gpu: [
        the_gpu_never_sees_the_cameras_own_body_from_inside,
        gpu_and_cpu_agree_on_suzanne_and_the_hands_in_every_space,
        gpu_and_cpu_agree_on_materials_in_every_geometry,
        gpu_instance_trees_trace_the_cpu_and_the_brute_force_hits,
    ],
}
