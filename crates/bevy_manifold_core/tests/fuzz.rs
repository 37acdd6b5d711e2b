//! Every input format, fuzzed: space files, generator files (`.gen` and
//! JSON lists), scene files and glTF, each mutated from valid seeds (see
//! `bevy_manifold_test_support::fuzz`). The rule for each: an answer
//! (a space, or an error naming the file) in bounded time, never a panic.
//! A bounded run here; `FUZZ_CASES=100000 cargo test --release -p
//! bevy_manifold_core --test fuzz` for a long one. Inputs that once failed
//! live in `tests/fuzz/<format>/` and are replayed first.

use bevy_manifold_core::mesh::gltf;
use bevy_manifold_core::prelude::*;
use bevy_manifold_core::space::library;
use bevy_manifold_test_support::Rng;
use bevy_manifold_test_support::fuzz::{Target, cases, mutate_bytes, mutate_json, mutate_text, run};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::time::Duration;

/// The kept inputs of one format (empty when none ever failed).
fn kept(format: &str) -> Vec<(PathBuf, Vec<u8>)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz").join(format);
    let mut out: Vec<(PathBuf, Vec<u8>)> = std::fs::read_dir(&dir)
        .into_iter()
        .flatten()
        .filter_map(|e| {
            let p = e.ok()?.path();
            let bytes = std::fs::read(&p).ok()?;
            Some((p, bytes))
        })
        .collect();
    out.sort();
    out
}

fn space_file(text: &str, name: &str) -> bool {
    Space::parse_file(text, Path::new(name)).is_ok()
}

#[test]
fn space_files() {
    for (path, bytes) in kept("space") {
        let _ = space_file(&String::from_utf8_lossy(&bytes), &path.display().to_string());
    }
    let seeds: Vec<Value> = catalog::NAMES
        .iter()
        .map(|n| serde_json::from_str(&catalog::by_name(n).expect("catalog").to_json()).expect("json"))
        .collect();
    let target = Target {
        format: "space files",
        mutate: mutate_json,
        run: |v: &Value| space_file(&v.to_string(), "fuzz.json"),
        bytes: |v: &Value| v.to_string().into_bytes(),
    };
    run(&target, &seeds, cases(1500), 1, Duration::from_secs(5));
}

#[test]
fn generator_files() {
    for (path, bytes) in kept("gen") {
        let _ = space_file(&String::from_utf8_lossy(&bytes), &path.display().to_string());
    }
    // Each as written, and as a Windows editor saves it (a byte-order
    // mark, CRLF line ends).
    let seeds: Vec<String> = library::names()
        .iter()
        .map(|n| library::by_name(n).expect("library").to_gen("seed"))
        .flat_map(|t| [format!("\u{feff}{}", t.replace('\n', "\r\n")), t])
        .collect();
    assert!(
        seeds.iter().all(|t| space_file(t, "seed.gen")),
        "every seed, BOM or not, is a space"
    );
    let target = Target {
        format: "gen files",
        mutate: |t: &mut String, rng: &mut Rng| *t = mutate_text(t, rng),
        run: |t: &String| space_file(t, "fuzz.gen"),
        bytes: |t: &String| t.clone().into_bytes(),
    };
    run(&target, &seeds, cases(600), 1_000_000, Duration::from_secs(10));
    let seeds: Vec<Value> = ["quaternionic", "hantzsche-wendt", "weeks", "lens-8-3"]
        .iter()
        .map(|n| serde_json::to_value(library::by_name(n).expect("library").to_desc()).expect("json"))
        .collect();
    let target = Target {
        format: "generator lists",
        mutate: mutate_json,
        run: |v: &Value| space_file(&v.to_string(), "fuzz.gens.json"),
        bytes: |v: &Value| v.to_string().into_bytes(),
    };
    run(&target, &seeds, cases(600), 2_000_000, Duration::from_secs(10));
}

#[test]
fn scene_files() {
    let spaces: Vec<Space> = catalog::NAMES
        .iter()
        .map(|n| catalog::by_name(n).expect("catalog"))
        .collect();
    for (path, bytes) in kept("scene") {
        for s in &spaces {
            let _ = Scene::parse(&String::from_utf8_lossy(&bytes), &path.display().to_string(), s);
        }
    }
    let seeds: Vec<(usize, Value)> = spaces
        .iter()
        .enumerate()
        .map(|(i, s)| (i, serde_json::from_str(&Scene::default_for(s).to_json()).expect("json")))
        .collect();
    let target = Target {
        format: "scene files",
        mutate: |(_, v): &mut (usize, Value), rng: &mut Rng| mutate_json(v, rng),
        run: |(i, v): &(usize, Value)| Scene::parse(&v.to_string(), "fuzz.json", &spaces[*i]).is_ok(),
        bytes: |(_, v): &(usize, Value)| v.to_string().into_bytes(),
    };
    run(&target, &seeds, cases(1500), 3_000_000, Duration::from_secs(5));
}

/// A GLB of a JSON chunk and a binary chunk.
fn glb(json: &Value, bin: &[u8]) -> Vec<u8> {
    let mut j = json.to_string().into_bytes();
    while !j.len().is_multiple_of(4) {
        j.push(b' ');
    }
    let mut b = bin.to_vec();
    while !b.len().is_multiple_of(4) {
        b.push(0);
    }
    let total = 12 + 8 + j.len() + 8 + b.len();
    let mut out = Vec::with_capacity(total);
    out.extend(b"glTF");
    out.extend(2u32.to_le_bytes());
    out.extend((total as u32).to_le_bytes());
    out.extend((j.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(j);
    out.extend((b.len() as u32).to_le_bytes());
    out.extend(b"BIN\0");
    out.extend(b);
    out
}

/// A triangle with normals, uvs, indices and a node tree, as GLB parts.
fn triangle() -> (Value, Vec<u8>) {
    let floats: [f32; 24] = [
        0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, // positions
        0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, // normals
        0.0, 0.0, 1.0, 0.0, 0.0, 1.0, // uvs
    ];
    let mut bin: Vec<u8> = floats.iter().flat_map(|f| f.to_le_bytes()).collect();
    bin.extend([0u16, 1, 2, 0].iter().flat_map(|i| i.to_le_bytes()));
    let json = serde_json::json!({
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
        "nodes": [{"children": [1], "scale": [1, 1, 1]}, {"mesh": 0, "translation": [0, 0, 0]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [1, 0.5, 0.5, 1]}}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC2"},
            {"bufferView": 3, "componentType": 5123, "count": 3, "type": "SCALAR"}
        ],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 36},
            {"buffer": 0, "byteOffset": 36, "byteLength": 36},
            {"buffer": 0, "byteOffset": 72, "byteLength": 24},
            {"buffer": 0, "byteOffset": 96, "byteLength": 6}
        ],
        "buffers": [{"byteLength": 104}]
    });
    (json, bin)
}

#[test]
fn gltf_files() {
    let path = Path::new("fuzz.glb");
    for (p, bytes) in kept("gltf") {
        let _ = gltf::from_slice(&bytes, &p);
    }
    // The structure mutated, then packed.
    let (json, bin) = triangle();
    assert!(gltf::from_slice(&glb(&json, &bin), path).is_ok(), "the seed loads");
    let target = Target {
        format: "glTF structure",
        mutate: mutate_json,
        run: |j: &Value| gltf::from_slice(&glb(j, &bin), path).is_ok(),
        bytes: |j: &Value| glb(j, &bin),
    };
    run(&target, &[json], cases(1500), 4_000_000, Duration::from_secs(5));
    // The bytes of real models mutated.
    let models = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/models");
    let seeds: Vec<Vec<u8>> = ["suzanne.glb", "left.glb"]
        .iter()
        .map(|f| std::fs::read(models.join(f)).expect("model"))
        .collect();
    let target = Target {
        format: "glTF bytes",
        mutate: mutate_bytes,
        run: |b: &Vec<u8>| gltf::from_slice(b, path).is_ok(),
        bytes: |b: &Vec<u8>| b.clone(),
    };
    run(&target, &seeds, cases(150), 5_000_000, Duration::from_secs(10));
}

#[test]
fn mutators_change_their_input() {
    // The fuzzer is no fuzzer if its mutants equal the seeds.
    let (json, _) = triangle();
    let text = library::by_name("quaternionic").expect("library").to_gen("x");
    let (mut changed_json, mut changed_text) = (0, 0);
    for seed in 0..200 {
        let mut rng = Rng(seed);
        let mut j = json.clone();
        mutate_json(&mut j, &mut rng);
        changed_json += usize::from(j != json);
        changed_text += usize::from(mutate_text(&text, &mut rng) != text);
    }
    assert!(
        changed_json > 150 && changed_text > 150,
        "{changed_json} {changed_text}"
    );
}
