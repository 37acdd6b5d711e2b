//! Triangle meshes on the CPU: the BVH against brute force, glTF loading
//! and its failures, and mirror images in mirrored spaces. (The GPU
//! tracer with meshes is `bevy_manifold_gpu`'s `tests/meshes.rs`.)

use bevy_manifold_core::geometry::isometry;
use bevy_manifold_core::mesh::bvh::hit_brute_force;
use bevy_manifold_core::mesh::gltf::{GltfError, load};
use bevy_manifold_core::mesh::{MeshMaterial, TriMesh};
use bevy_manifold_core::prelude::*;
use bevy_manifold_core::trace::{SceneMesh, builtin};
use bevy_manifold_test_support::Rng;
use glam::{DMat4, DVec3};
use std::path::Path;

fn models() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/assets/models"))
}

#[test]
fn the_bvh_finds_exactly_the_brute_force_nearest_hit() {
    let suzanne = builtin::suzanne();
    assert_eq!(suzanne.mesh.triangles.len(), 3936);
    let mut rng = Rng(7);
    let (mut hits, mut misses) = (0, 0);
    for _ in 0..100_000 {
        // From a box around the head towards a point near it: most rays
        // hit, many graze, some start inside the head.
        let o = rng.in_box(2.5);
        let target = rng.in_box(1.0);
        let d = [target[0] - o[0], target[1] - o[1], target[2] - o[2]];
        let fast = suzanne.hit::<f64>(o, d, f64::INFINITY);
        let slow = hit_brute_force::<f64>(&suzanne, o, d, f64::INFINITY);
        match (fast, slow) {
            (Some(a), Some(b)) => {
                assert!((a.s - b.s).abs() <= 1e-6 * b.s.max(1.0), "distance {} vs {}", a.s, b.s);
                // The same triangle, unless two meet at exactly that s (an edge).
                assert!(
                    a.triangle == b.triangle || a.s == b.s,
                    "triangle {} vs {}",
                    a.triangle,
                    b.triangle
                );
                hits += 1;
            }
            (None, None) => misses += 1,
            (a, b) => panic!("BVH {a:?} against brute force {b:?} from {o:?} along {d:?}"),
        }
    }
    eprintln!(
        "100000 rays: {hits} hits, {misses} misses, BVH of {} nodes",
        suzanne.nodes.len()
    );
    assert!(hits > 30_000 && misses > 10_000, "the rays test both cases");
}

#[test]
fn the_shipped_models_load_with_their_triangles() {
    for (file, triangles) in [("suzanne.glb", 3936), ("left.glb", 2314), ("right.glb", 2314)] {
        let loaded = load(models().join(file)).expect(file);
        assert!(loaded.warnings.is_empty(), "{file}: {:?}", loaded.warnings);
        let n: usize = loaded.parts.iter().map(|p| p.mesh.triangles.len()).sum();
        assert_eq!(n, triangles, "{file}");
    }
}

/// A .gltf file with its buffer beside it: one triangle, positions as
/// given.
fn write_gltf(dir: &Path, name: &str, positions: [[f32; 3]; 3]) -> std::path::PathBuf {
    let bin: Vec<u8> = positions.iter().flatten().flat_map(|f| f.to_le_bytes()).collect();
    std::fs::write(dir.join(format!("{name}.bin")), &bin).unwrap();
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,1]}}],
        "bufferViews":[{{"buffer":0,"byteLength":36}}],
        "buffers":[{{"byteLength":36,"uri":"{name}.bin"}}]}}"#
    );
    let path = dir.join(format!("{name}.gltf"));
    std::fs::write(&path, json).unwrap();
    path
}

#[test]
fn a_broken_gltf_is_reported_and_the_rest_of_the_scene_still_renders() {
    let dir = std::env::temp_dir().join(format!("bevy_manifold_meshes_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // Not glTF at all.
    let junk = dir.join("junk.glb");
    std::fs::write(&junk, b"not a model").unwrap();
    let e = load(&junk).unwrap_err();
    assert!(
        matches!(e, GltfError::Parse { .. }) && e.to_string().contains("junk.glb"),
        "{e}"
    );
    // Missing.
    let e = load(dir.join("missing.glb")).unwrap_err();
    assert!(matches!(e, GltfError::Io { .. }), "{e}");
    // NaN positions: nothing traceable, and the reason says so.
    let nan = write_gltf(&dir, "nan", [[0.0, 0.0, 0.0], [f32::NAN, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let e = load(&nan).unwrap_err();
    assert!(e.to_string().contains("non-finite"), "{e}");
    // A good one loads.
    let good = write_gltf(&dir, "good", [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    assert_eq!(load(&good).unwrap().parts[0].mesh.triangles.len(), 1);
    // No triangles at all.
    assert_eq!(
        TriMesh::new(vec![[0.0; 3]; 3], None, None, vec![]),
        Err(bevy_manifold_core::mesh::MeshError::Empty)
    );

    // In a scene file: the broken meshes are left out, with a reason, and
    // the ball still renders.
    let space = catalog::torus(1.0);
    let mut scene = Scene::default_for(&space);
    scene.meshes.clear();
    let mut json: serde_json::Value = serde_json::from_str(&scene.to_json()).unwrap();
    let rows = [
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ];
    json["meshes"] = serde_json::json!([
        {"file": "junk.glb", "placement": rows, "scale": 0.1},
        {"file": "nan.gltf", "placement": rows, "scale": 0.1},
        {"file": "good.gltf", "placement": rows, "scale": 0.1},
    ]);
    let path = dir.join("scene.json");
    std::fs::write(&path, json.to_string()).unwrap();
    let scene = Scene::load(&path, &space).expect("the scene loads without its broken meshes");
    assert_eq!(scene.meshes.len(), 1);
    assert_eq!(scene.skipped.len(), 2, "{:?}", scene.skipped);
    assert!(scene.skipped[0].contains("meshes[0].file") && scene.skipped[1].contains("meshes[1].file"));
    let settings = TraceSettings {
        width: 48,
        height: 48,
        ..TraceSettings::default()
    };
    let img = render::<f64>(&space, &scene, &settings);
    assert!(img.pixels.iter().any(|p| p.object == 1), "the ball");
    std::fs::remove_dir_all(&dir).ok();
}

/// The object id mask of a CPU render.
fn mask(space: &Space, scene: &Scene, id: u32, levels: Option<u32>) -> Vec<bool> {
    let settings = TraceSettings {
        width: 128,
        height: 128,
        levels: 4,
        ..TraceSettings::default()
    };
    render::<f64>(space, scene, &settings)
        .pixels
        .iter()
        .map(|p| p.object == id && levels.is_none_or(|l| p.levels == l))
        .collect()
}

#[test]
fn copies_seen_in_a_mirror_are_mirror_images() {
    // In the mirrored cube, a camera at the centre looks at the mirror
    // x = 1/2; a left hand behind it faces the mirror. What the camera sees
    // one reflection away must be the hand's mirror image, as drawn
    // directly (no faces in reach) in a large torus with a reflecting
    // placement; the unreflected hand in the same place looks different.
    let cube = catalog::mirrored_cube(1.0);
    let big = catalog::torus(20.0);
    let look = isometry::rotation(DVec3::Y, -std::f64::consts::FRAC_PI_2); // -z to +x
    let hand = |space: &Space, placement: DMat4| {
        let mut s = Scene::empty();
        s.camera.isometry = look;
        s.camera.fov_y_degrees = 40.0;
        s.meshes.push(SceneMesh::new(
            builtin::hand(true),
            MeshMaterial::default(),
            placement,
            1.5,
        ));
        let _ = space;
        s
    };
    // Behind the camera, fingers up, palm towards +x.
    let at = DMat4::from_translation(DVec3::new(-0.3, -0.1, 0.05)) * isometry::rotation(DVec3::X, -1.2);
    let mirror = DMat4::from_diagonal(glam::DVec4::new(-1.0, 1.0, 1.0, 1.0));
    let reflect = DMat4::from_translation(DVec3::X * 0.5) * mirror * DMat4::from_translation(DVec3::X * -0.5);
    let seen = mask(&cube, &hand(&cube, at), 1, Some(1));
    let imaged = mask(&big, &hand(&big, reflect * at), 1, None);
    let unreflected = mask(&big, &hand(&big, reflect * at * mirror), 1, None);
    let count = |m: &[bool]| m.iter().filter(|&&b| b).count();
    let differ = |a: &[bool], b: &[bool]| a.iter().zip(b).filter(|(x, y)| x != y).count();
    eprintln!(
        "hand pixels: through the mirror {}, mirror image drawn directly {}, unreflected {}; differences {} and {}",
        count(&seen),
        count(&imaged),
        count(&unreflected),
        differ(&seen, &imaged),
        differ(&seen, &unreflected)
    );
    assert!(count(&seen) > 300, "the hand is in view through the mirror");
    assert!(
        differ(&seen, &imaged) <= count(&seen) / 40,
        "the copy is the mirror image"
    );
    assert!(
        differ(&seen, &unreflected) > count(&seen) / 10,
        "and not the hand itself"
    );
}
