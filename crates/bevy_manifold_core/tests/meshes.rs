//! Triangle meshes on the CPU: the BVH against brute force, glTF loading
//! and its failures, mirror images in mirrored spaces, and the vehicle
//! against a plain ray caster. (The GPU
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

/// A refitted BVH (the shape built for Suzanne at rest, its boxes fitted
/// to her vertices twisted about the vertical and stretched, as a pose
/// moves a skinned mesh) finds exactly the brute-force nearest hit of the
/// moved triangles; its boxes' area grows, and a BVH built for the moved
/// mesh is tighter.
#[test]
fn a_refitted_bvh_finds_exactly_the_brute_force_nearest_hit() {
    let rest = builtin::suzanne();
    // Each vertex turned about y by an angle growing with its height, and
    // moved up in proportion to its distance from the axis.
    let moved: Vec<[f32; 3]> = rest
        .mesh
        .positions
        .iter()
        .map(|&[x, y, z]| {
            let (s, c) = (0.8 * y).sin_cos();
            [x * c + z * s, y + 0.3 * (x * x + z * z).sqrt(), z * c - x * s]
        })
        .collect();
    let refit = rest.refit(moved.clone(), rest.mesh.normals.clone()).unwrap();
    assert_eq!(refit.nodes.len(), rest.nodes.len(), "the shape is kept");
    let rebuilt = bevy_manifold_core::mesh::MeshData::build(
        TriMesh::new(moved, None, None, rest.mesh.triangles.clone()).unwrap(),
    );
    let area = bevy_manifold_core::mesh::bvh::surface_area;
    eprintln!(
        "box areas: at rest {:.1}, refitted {:.1}, rebuilt {:.1}",
        area(&rest.nodes),
        area(&refit.nodes),
        area(&rebuilt.nodes)
    );
    assert!(area(&refit.nodes) > area(&rebuilt.nodes));
    let mut rng = Rng(9);
    let mut hits = 0;
    for _ in 0..20_000 {
        let o = rng.in_box(2.5);
        let target = rng.in_box(1.0);
        let d = [target[0] - o[0], target[1] - o[1], target[2] - o[2]];
        let fast = refit.hit::<f64>(o, d, f64::INFINITY);
        let slow = hit_brute_force::<f64>(&refit, o, d, f64::INFINITY);
        match (fast, slow) {
            (Some(a), Some(b)) => {
                assert!((a.s - b.s).abs() <= 1e-6 * b.s.max(1.0), "distance {} vs {}", a.s, b.s);
                hits += 1;
            }
            (None, None) => {}
            (a, b) => panic!("refitted BVH {a:?} against brute force {b:?} from {o:?} along {d:?}"),
        }
    }
    assert!(hits > 5_000, "only {hits} hits");
    // A pose with a vertex count of another mesh is refused by name.
    let err = rest.refit(vec![[0.0; 3]; 3], vec![[0.0, 1.0, 0.0]; 3]).unwrap_err();
    assert!(err.to_string().contains("positions has 3 entries"), "{err}");
}

/// Items far apart leave most of the SAH sweep's bins empty; an empty
/// bin once made every box joined after it infinite, so no split beat a
/// leaf and 128 small balls went into 8 leaves of up to 25. Here 64 small
/// boxes on a 4x4x4 lattice with wide gaps (most of the 12 bins per axis
/// hold none): the hierarchy must split them down to leaves of at most
/// LEAF_SIZE, and every item must be in exactly one leaf.
#[test]
fn a_hierarchy_over_scattered_items_splits_them_into_small_leaves() {
    use bevy_manifold_core::mesh::bvh::{LEAF_SIZE, build_over};
    let items: Vec<([f32; 3], [f32; 3])> = (0..64)
        .map(|i| {
            let c = [i % 4, (i / 4) % 4, i / 16].map(|k| k as f32 * 10.0);
            (c.map(|x| x - 0.1), c.map(|x| x + 0.1))
        })
        .collect();
    let (nodes, order) = build_over(&items);
    let leaves: Vec<_> = nodes.iter().filter(|n| n.count > 0).collect();
    assert!(
        leaves.iter().all(|n| n.count as usize <= LEAF_SIZE),
        "leaf sizes {:?}",
        leaves.iter().map(|n| n.count).collect::<Vec<_>>()
    );
    assert!(leaves.len() >= 64 / LEAF_SIZE, "{} leaves", leaves.len());
    let mut seen: Vec<u32> = leaves
        .iter()
        .flat_map(|n| order[n.first as usize..(n.first + n.count) as usize].to_vec())
        .collect();
    seen.sort_unstable();
    assert_eq!(seen, (0..64).collect::<Vec<u32>>());
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

/// Writes a one-triangle `.gltf` whose JSON is `json` (with the triangle's
/// buffer beside it as `tri.bin`), and loads it.
fn load_json(
    dir: &Path,
    name: &str,
    json: &serde_json::Value,
) -> Result<bevy_manifold_core::mesh::gltf::Loaded, GltfError> {
    let bin: Vec<u8> = [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
        .iter()
        .flatten()
        .flat_map(|f| f.to_le_bytes())
        .collect();
    std::fs::write(dir.join("tri.bin"), &bin).unwrap();
    let path = dir.join(format!("{name}.gltf"));
    std::fs::write(&path, json.to_string()).unwrap();
    load(&path)
}

/// A glTF with one triangle mesh and the given nodes.
fn with_nodes(nodes: serde_json::Value) -> serde_json::Value {
    serde_json::json!({
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
        "nodes": nodes,
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 1]}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "buffers": [{"byteLength": 36, "uri": "tri.bin"}]
    })
}

#[test]
fn hostile_gltf_files_end_quickly_with_a_named_reason() {
    let dir = std::env::temp_dir().join(format!("bevy_manifold_hostile_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // A node that lists itself, and a longer loop 0 -> 1 -> 2 -> 0: the
    // mesh still loads (once per path), the cycle is named.
    for (name, nodes) in [
        ("self", serde_json::json!([{"mesh": 0, "children": [0]}])),
        (
            "loop",
            serde_json::json!([{"children": [1]}, {"children": [2], "mesh": 0}, {"children": [0]}]),
        ),
    ] {
        let loaded = load_json(&dir, name, &with_nodes(nodes)).expect("the rest of the file loads");
        assert_eq!(loaded.parts.len(), 1, "{name}");
        assert!(
            loaded.warnings.iter().any(|w| w.contains("cycle") && w.contains(name)),
            "{name}: {:?}",
            loaded.warnings
        );
    }
    // A graph that reuses children: 2^40 paths to the mesh. Walked at most
    // MAX_NODE_VISITS times, with a warning.
    let mut nodes: Vec<serde_json::Value> = (0..40)
        .map(|i| serde_json::json!({"children": [i + 1, i + 1]}))
        .collect();
    nodes.push(serde_json::json!({"mesh": 0}));
    let start = std::time::Instant::now();
    let loaded = load_json(&dir, "reuse", &with_nodes(serde_json::Value::Array(nodes))).expect("loads");
    assert!(
        loaded.warnings.iter().any(|w| w.contains("node instances")),
        "{:?}",
        loaded.warnings
    );
    assert!(loaded.parts.len() <= bevy_manifold_core::mesh::gltf::MAX_NODE_VISITS);
    assert!(start.elapsed().as_secs() < 60, "bounded work");
    // A sparse accessor claiming three billion positions in a few bytes:
    // refused before anything is allocated, naming the attribute.
    let mut json = with_nodes(serde_json::json!([{"mesh": 0}]));
    json["accessors"] = serde_json::json!([{
        "componentType": 5126, "count": 3_000_000_000u64, "type": "VEC3",
        "min": [0, 0, 0], "max": [1, 1, 1],
        "sparse": {"count": 1, "indices": {"bufferView": 0, "componentType": 5125}, "values": {"bufferView": 0}}
    }]);
    let e = load_json(&dir, "sparse", &json).unwrap_err();
    assert!(
        e.to_string().contains("sparse") && e.to_string().contains("3000000000"),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn degenerate_normals_uvs_and_textures_are_repaired_or_refused() {
    use bevy_manifold_core::mesh::{MAX_TRIANGLES, MeshError, Texture, texel_index};
    // A zero normal and a NaN one are replaced by the face's normal (+z
    // for this triangle in the xy-plane); good ones are kept.
    let positions = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let normals = vec![[0.0, 0.0, 0.0], [f32::NAN, 0.0, 0.0], [1.0, 0.0, 0.0]];
    let uvs = vec![[f32::INFINITY, 0.5], [0.25, 0.5], [0.0, f32::NAN]];
    let m = TriMesh::new(positions.clone(), Some(normals), Some(uvs), vec![[0, 1, 2]]).unwrap();
    assert_eq!(m.normals, vec![[0.0, 0.0, 1.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]]);
    assert_eq!(m.uvs, vec![[0.0, 0.0], [0.25, 0.5], [0.0, 0.0]]);
    // Too many triangles: refused by count, not by running out of memory.
    let many = vec![[0u32, 1, 2]; MAX_TRIANGLES + 1];
    assert!(matches!(
        TriMesh::new(positions, None, None, many),
        Err(MeshError::TooLarge { what: "triangles", .. })
    ));
    // Textures: an empty one, a size that overflows u32, too few texels.
    assert!(Texture::new(0, 4, vec![]).unwrap_err().contains("empty"));
    assert!(Texture::new(1 << 16, 1 << 16, vec![]).is_err());
    assert!(Texture::new(2, 2, vec![0; 3]).unwrap_err().contains("3 texels"));
    assert_eq!(Texture::new(2, 1, vec![1, 2, 3]).unwrap().texels, vec![1, 2]);
    // The texel index of an empty axis is 0, never an underflow.
    assert_eq!(texel_index(0.7, 0), 0);
    assert_eq!(texel_index(0.7, 10), 7);
    assert_eq!(texel_index(-0.25, 4), 3);
}

#[test]
fn a_gltf_that_crashed_the_gltf_crate_is_an_error_naming_the_file() {
    // Found by the fuzzer (tests/fuzz.rs): a primitive whose POSITION names
    // accessor 0 in a file with no accessors panics inside gltf-json's
    // validation. It is this file's error now.
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz/gltf/no-accessors.glb");
    let e = load(&path).unwrap_err();
    assert!(
        matches!(e, GltfError::Parse { .. }) && e.to_string().contains("no-accessors.glb"),
        "{e}"
    );
}

/// The nearest of `mesh`'s triangles (vertices scaled by `scale`, moved
/// by `at`) the ray `o + s d` meets, by Möller–Trumbore over every
/// triangle: a plain ray caster, no BVH, no charts.
fn brute_force_hit(mesh: &TriMesh, scale: f64, at: DVec3, o: DVec3, d: DVec3) -> Option<f64> {
    let p = |i: u32| DVec3::from(mesh.positions[i as usize].map(f64::from)) * scale + at;
    mesh.triangles
        .iter()
        .filter_map(|t| {
            let (a, b, c) = (p(t[0]), p(t[1]), p(t[2]));
            let (e1, e2) = (b - a, c - a);
            let q = d.cross(e2);
            let det = e1.dot(q);
            if det.abs() < 1e-14 {
                return None;
            }
            let s = o - a;
            let u = s.dot(q) / det;
            let r = s.cross(e1);
            let v = d.dot(r) / det;
            let t = e2.dot(r) / det;
            (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t > 0.0).then_some(t)
        })
        .min_by(f64::total_cmp)
}

#[test]
fn the_vehicle_is_traced_where_a_plain_ray_caster_sees_it_and_in_the_other_copies() {
    use bevy_manifold_core::mesh::vehicle;
    use bevy_manifold_core::trace::{PaperOptions, SuzanneMode, vehicle_offset};
    // In the 3-torus the camera's chart is Euclidean: the home copy of the
    // vehicle must cover exactly the pixels whose rays a brute-force
    // caster finds on its triangles, placed by the offset the scene says,
    // at the same distances; its other copies are seen through the faces.
    let space = catalog::torus(1.0);
    let options = PaperOptions {
        edges: false,
        suzanne: SuzanneMode::Hidden,
        hands: false,
        vehicle: true,
        mirror: false,
    };
    let scene = Scene::paper(&space, &options);
    assert_eq!(scene.meshes.len(), 1);
    let (w, h) = (96u32, 64u32);
    let settings = TraceSettings {
        width: w,
        height: h,
        levels: 4,
        ..TraceSettings::default()
    };
    let img = render::<f64>(&space, &scene, &settings);
    let (offset, scale) = vehicle_offset(&space);
    let at = (offset * glam::DVec4::W).truncate();
    let plane = vehicle::airplane();
    let tan = (scene.camera.fov_y_degrees.to_radians() / 2.0).tan();
    let (mut both, mut only_traced, mut only_cast, mut far_off) = (0, 0, 0, 0.0f64);
    for j in 0..h {
        for i in 0..w {
            let x = 2.0 * (f64::from(i) + 0.5) / f64::from(w) - 1.0;
            let y = 1.0 - 2.0 * (f64::from(j) + 0.5) / f64::from(h);
            let d = DVec3::new(x * tan * f64::from(w) / f64::from(h), y * tan, -1.0).normalize();
            let cast = brute_force_hit(&plane.mesh, scale, at, DVec3::ZERO, d);
            let p = &img.pixels[(j * w + i) as usize];
            let traced = p.object == 1 && p.levels == 0;
            match (traced, cast) {
                (true, Some(s)) => {
                    both += 1;
                    far_off = far_off.max((f64::from(p.distance) - s).abs());
                }
                (true, None) => only_traced += 1,
                (false, Some(_)) => only_cast += 1,
                (false, None) => {}
            }
        }
    }
    let copies = img.pixels.iter().filter(|p| p.object == 1 && p.levels > 0).count();
    eprintln!(
        "vehicle pixels: {both} both, {only_traced} traced only, {only_cast} cast only; distance off by {far_off:.2e}; {copies} in other copies"
    );
    assert!(both > 150, "the vehicle fills part of the view below its centre");
    assert_eq!(only_traced + only_cast, 0, "the same pixels");
    assert!(far_off < 1e-4, "at the same distances");
    assert!(copies > 20, "its images in the other copies");
}

/// Base64 (RFC 4648, with padding), written here to embed files.
fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in bytes.chunks(3) {
        let n = chunk
            .iter()
            .enumerate()
            .fold(0u32, |n, (i, &b)| n | u32::from(b) << (16 - 8 * i));
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(char::from(ALPHABET[(n >> (18 - 6 * k) & 63) as usize]));
            } else {
                out.push('=');
            }
        }
    }
    out
}

#[test]
fn a_gltf_with_its_buffer_and_images_embedded_loads_as_with_them_beside_it() {
    // The material quad (a buffer and four PNG textures in files beside
    // it), then the same glTF with each file embedded as a base64 data URI
    // (Blender's "glTF Embedded"), alone in a folder of its own.
    let root = std::env::temp_dir().join(format!("embedded-gltf-{}", std::process::id()));
    let beside = bevy_manifold_test_support::materials::write_material_quad(&root.join("beside"));
    let dir = beside.parent().expect("its folder").to_path_buf();
    let mut json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&beside).expect("the .gltf")).expect("JSON");
    let embed = |uri: &serde_json::Value, media: &str| {
        let bytes = std::fs::read(dir.join(uri.as_str().expect("a file name"))).expect("the file");
        serde_json::Value::String(format!("data:{media};base64,{}", base64(&bytes)))
    };
    json["buffers"][0]["uri"] = embed(&json["buffers"][0]["uri"], "application/octet-stream");
    for i in 0..4 {
        json["images"][i]["uri"] = embed(&json["images"][i]["uri"], "image/png");
    }
    let alone = root.join("alone");
    std::fs::create_dir_all(&alone).expect("a folder");
    let embedded = alone.join("quad.gltf");
    std::fs::write(&embedded, json.to_string()).expect("written");
    let (a, b) = (
        load(&beside).expect("with its files"),
        load(&embedded).unwrap_or_else(|e| panic!("embedded: {e}")),
    );
    assert_eq!(a.parts.len(), 1);
    assert_eq!(b.parts.len(), 1);
    assert_eq!(a.parts[0].mesh, b.parts[0].mesh);
    assert_eq!(a.parts[0].material, b.parts[0].material);
    assert!(b.parts[0].material.texture.is_some() && b.parts[0].material.normal_map.is_some());
    assert!(b.warnings.is_empty(), "{:?}", b.warnings);
    // A data URI that is not base64, and one whose base64 is broken: named.
    for (uri, says) in [
        ("data:application/octet-stream,%00%01", "not base64"),
        ("data:application/octet-stream;base64,AB$=", "base64 is broken"),
    ] {
        json["buffers"][0]["uri"] = serde_json::Value::String(uri.into());
        std::fs::write(&embedded, json.to_string()).expect("written");
        let e = load(&embedded).expect_err(uri).to_string();
        assert!(
            e.contains("quad.gltf") && e.contains("buffers[0]") && e.contains(says),
            "{e}"
        );
    }
    let _ = std::fs::remove_dir_all(&root);
}
