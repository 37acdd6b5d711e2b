//! A glTF file written here, byte by byte, for the material tests: a
//! 2 x 2 quad in the xy plane facing +z (texture `u` along +x, `v` down
//! the image, so along -y), with every field of glTF's metallic-roughness
//! material set to a known value and four 2 x 2 PNG textures beside it.

use std::path::{Path, PathBuf};

/// The base colour factor written ([`write_material_quad`]).
pub const BASE: [f32; 4] = [0.5, 0.25, 1.0, 1.0];
/// The metallic factor written.
pub const METALLIC: f32 = 0.5;
/// The roughness factor written.
pub const ROUGHNESS: f32 = 0.8;
/// The emissive factor written.
pub const EMISSIVE: [f32; 3] = [1.0, 0.5, 0.25];
/// `KHR_materials_emissive_strength` written.
pub const STRENGTH: f32 = 4.0;
/// The alpha cutoff written.
pub const CUTOFF: f32 = 0.3;

/// The texels of each texture (RGBA8, row-major from the top, 2 x 2):
/// the base colour is white, opaque in its left column and transparent
/// in its right one (so the quad's half with `x > 0` is cut away); the
/// metallic-roughness texture has roughness (green) 255 and metallic
/// (blue) 255 (the factors alone); the emission is white; the normal map
/// tilts the normal fully along the tangent (+x).
pub const TEXELS: [(&str, [[u8; 4]; 4]); 4] = [
    (
        "base.png",
        [
            [255, 255, 255, 255],
            [255, 255, 255, 0],
            [255, 255, 255, 255],
            [255, 255, 255, 0],
        ],
    ),
    ("mr.png", [[0, 255, 255, 255]; 4]),
    ("emissive.png", [[255, 255, 255, 255]; 4]),
    ("normal.png", [[255, 128, 128, 255]; 4]),
];

/// Writes `quad.gltf`, `quad.bin` and the four PNGs into `dir`; the
/// path of the glTF file.
///
/// # Panics
/// When the files cannot be written.
#[must_use]
pub fn write_material_quad(dir: &Path) -> PathBuf {
    std::fs::create_dir_all(dir).expect("test directory");
    let positions: [[f32; 3]; 4] = [[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]];
    let normals = [[0.0f32, 0.0, 1.0]; 4];
    let uvs: [[f32; 2]; 4] = [[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]];
    let indices: [u16; 6] = [0, 1, 2, 0, 2, 3];
    let mut bin = Vec::new();
    for p in positions {
        p.iter().for_each(|c| bin.extend(c.to_le_bytes()));
    }
    for n in normals {
        n.iter().for_each(|c| bin.extend(c.to_le_bytes()));
    }
    for t in uvs {
        t.iter().for_each(|c| bin.extend(c.to_le_bytes()));
    }
    for i in indices {
        bin.extend(i.to_le_bytes());
    }
    std::fs::write(dir.join("quad.bin"), &bin).expect("quad.bin");
    for (name, texels) in TEXELS {
        let flat: Vec<u8> = texels.iter().flatten().copied().collect();
        image::save_buffer(dir.join(name), &flat, 2, 2, image::ExtendedColorType::Rgba8).expect("png");
    }
    let json = serde_json::json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_materials_emissive_strength"],
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"name": "quad", "primitives": [{
            "attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
            "indices": 3,
            "material": 0
        }]}],
        "materials": [{
            "pbrMetallicRoughness": {
                "baseColorFactor": BASE,
                "baseColorTexture": {"index": 0},
                "metallicFactor": METALLIC,
                "roughnessFactor": ROUGHNESS,
                "metallicRoughnessTexture": {"index": 1}
            },
            "emissiveFactor": EMISSIVE,
            "emissiveTexture": {"index": 2},
            "normalTexture": {"index": 3},
            "alphaMode": "MASK",
            "alphaCutoff": CUTOFF,
            "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": STRENGTH}}
        }],
        "textures": [{"source": 0}, {"source": 1}, {"source": 2}, {"source": 3}],
        "images": TEXELS.iter().map(|(n, _)| serde_json::json!({"uri": n})).collect::<Vec<_>>(),
        "buffers": [{"uri": "quad.bin", "byteLength": bin.len()}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 48},
            {"buffer": 0, "byteOffset": 96, "byteLength": 32},
            {"buffer": 0, "byteOffset": 128, "byteLength": 12}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [-1.0, -1.0, 0.0], "max": [1.0, 1.0, 0.0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"}
        ]
    });
    let path = dir.join("quad.gltf");
    std::fs::write(&path, serde_json::to_string_pretty(&json).expect("json")).expect("quad.gltf");
    path
}
