//! An animated glTF character made here, in code: a stalk (an eight-sided
//! tube of height 1 and radius 0.08, closed at both ends) skinned to two
//! bones, and one animation that sways it. `assets/models/stalk.gltf` is
//! what [`gltf`] writes; a test keeps the two equal.
//!
//! - Bone 0, `root`, stands at the origin; bone 1, `knee`, is its child at
//!   y = 0.5.
//! - A vertex at height y follows the knee with weight
//!   [`knee_weight`]`(y)` (0 below y = 0.25, 1 above y = 0.75, linear
//!   between) and the root with the rest.
//! - The animation `sway` ([`DURATION`] seconds, linear keys at 0, 1 and
//!   2 s) turns the root about +y by [`root_angle`]`(t)` and the knee about
//!   +z by [`knee_angle`]`(t)`: both angles piecewise linear in `t`, as a
//!   slerp between keys turns them.
//!
//! So the pose at a time is known by geometry alone ([`posed`]), without
//! matrices of joints: bend the upper part about the knee's z axis, then
//! turn everything about y.

use base64::Engine as _;
use glam::{Quat, Vec3};

/// Sides of the tube.
pub const SIDES: usize = 8;
/// Rings of the tube, evenly from y = 0 to y = 1.
pub const RINGS: usize = 9;
/// The tube's radius.
pub const RADIUS: f32 = 0.08;
/// Where the knee stands.
pub const KNEE: f32 = 0.5;
/// The animation's length, in seconds.
pub const DURATION: f32 = 2.0;
/// The keys' times.
const TIMES: [f32; 3] = [0.0, 1.0, 2.0];
/// The root's angle about +y at each key.
const ROOT_KEYS: [f32; 3] = [0.0, 0.4, 0.8];
/// The knee's angle about +z at each key.
const KNEE_KEYS: [f32; 3] = [0.0, 1.2, 0.0];

/// How much a vertex at height `y` follows the knee.
#[must_use]
pub fn knee_weight(y: f32) -> f32 {
    ((y - 0.25) / 0.5).clamp(0.0, 1.0)
}

/// The keys' values at `t` (clamped to the animation), linearly between.
fn keyed(keys: [f32; 3], t: f32) -> f32 {
    let t = t.clamp(0.0, DURATION);
    let i = if t < TIMES[1] { 0 } else { 1 };
    let f = (t - TIMES[i]) / (TIMES[i + 1] - TIMES[i]);
    keys[i] + (keys[i + 1] - keys[i]) * f
}

/// The root's angle about +y at time `t`.
#[must_use]
pub fn root_angle(t: f32) -> f32 {
    keyed(ROOT_KEYS, t)
}

/// The knee's angle about +z at time `t`.
#[must_use]
pub fn knee_angle(t: f32) -> f32 {
    keyed(KNEE_KEYS, t)
}

/// The tube's vertices at rest, as the file holds them: the side rings
/// (ring by ring, bottom up, radial normals), then the bottom cap (its
/// ring facing -y and its centre) and the top cap (the same, +y).
#[must_use]
pub fn rest() -> Vec<(Vec3, Vec3)> {
    let around = |s: usize| {
        let a = std::f32::consts::TAU * s as f32 / SIDES as f32;
        Vec3::new(a.cos(), 0.0, -a.sin())
    };
    let mut v = Vec::new();
    for r in 0..RINGS {
        let y = r as f32 / (RINGS - 1) as f32;
        v.extend((0..SIDES).map(|s| (around(s) * RADIUS + Vec3::Y * y, around(s))));
    }
    for (y, n) in [(0.0, -Vec3::Y), (1.0, Vec3::Y)] {
        v.extend((0..SIDES).map(|s| (around(s) * RADIUS + Vec3::Y * y, n)));
        v.push((Vec3::Y * y, n));
    }
    v
}

/// The triangles (counter-clockwise seen from outside).
#[must_use]
pub fn triangles() -> Vec<[u16; 3]> {
    let at = |r: usize, s: usize| (r * SIDES + s % SIDES) as u16;
    let mut t = Vec::new();
    for r in 0..RINGS - 1 {
        for s in 0..SIDES {
            t.push([at(r, s), at(r, s + 1), at(r + 1, s + 1)]);
            t.push([at(r, s), at(r + 1, s + 1), at(r + 1, s)]);
        }
    }
    let bottom = RINGS * SIDES;
    let top = bottom + SIDES + 1;
    for s in 0..SIDES {
        let (a, b) = (s, (s + 1) % SIDES);
        t.push([(bottom + SIDES) as u16, (bottom + b) as u16, (bottom + a) as u16]);
        t.push([(top + SIDES) as u16, (top + a) as u16, (top + b) as u16]);
    }
    t
}

/// Where the rest point `p` is at time `t`, by the geometry of the sway:
/// the point turned by the knee's angle about the line x = 0, y =
/// [`KNEE`] (along z) and the point left where it is are mixed by
/// [`knee_weight`], then the whole is turned about +y by the root's angle.
#[must_use]
pub fn posed(p: Vec3, t: f32) -> Vec3 {
    let knee = Vec3::Y * KNEE;
    let bent = knee + Quat::from_rotation_z(knee_angle(t)) * (p - knee);
    let w = knee_weight(p.y);
    Quat::from_rotation_y(root_angle(t)) * (p * (1.0 - w) + bent * w)
}

/// Little-endian bytes of `values`.
fn bytes(values: impl IntoIterator<Item = f32>) -> Vec<u8> {
    values.into_iter().flat_map(f32::to_le_bytes).collect()
}

/// The glTF file (JSON, its one buffer embedded as a base64 data URI).
#[must_use]
pub fn gltf() -> String {
    let rest = rest();
    let tris = triangles();
    let n = rest.len();
    let positions = bytes(rest.iter().flat_map(|(p, _)| p.to_array()));
    let normals = bytes(rest.iter().flat_map(|(_, n)| n.to_array()));
    let joints: Vec<u8> = rest.iter().flat_map(|_| [0u8, 0, 1, 0, 0, 0, 0, 0]).collect();
    let weights = bytes(rest.iter().flat_map(|(p, _)| {
        let w = knee_weight(p.y);
        [1.0 - w, w, 0.0, 0.0]
    }));
    let mut indices: Vec<u8> = tris.iter().flatten().flat_map(|i| i.to_le_bytes()).collect();
    indices.resize(indices.len().next_multiple_of(4), 0);
    let inverse_binds = bytes(
        [glam::Mat4::IDENTITY, glam::Mat4::from_translation(-Vec3::Y * KNEE)]
            .iter()
            .flat_map(|m| m.to_cols_array()),
    );
    let times = bytes(TIMES);
    let turns =
        |keys: [f32; 3], axis: Vec3| bytes(keys.iter().flat_map(|&a| Quat::from_axis_angle(axis, a).to_array()));
    let root_turns = turns(ROOT_KEYS, Vec3::Y);
    let knee_turns = turns(KNEE_KEYS, Vec3::Z);
    let parts = [
        &positions,
        &normals,
        &joints,
        &weights,
        &indices,
        &inverse_binds,
        &times,
        &root_turns,
        &knee_turns,
    ];
    let mut buffer = Vec::new();
    let mut views = Vec::new();
    for part in parts {
        views.push(serde_json::json!({"buffer": 0, "byteOffset": buffer.len(), "byteLength": part.len()}));
        buffer.extend_from_slice(part);
    }
    let (lo, hi) = rest
        .iter()
        .fold((Vec3::MAX, Vec3::MIN), |(lo, hi), (p, _)| (lo.min(*p), hi.max(*p)));
    let json = serde_json::json!({
        "asset": {"version": "2.0", "generator": "bevy_manifold_test_support::stalk"},
        "scene": 0,
        "scenes": [{"name": "stalk", "nodes": [0, 2]}],
        "nodes": [
            {"name": "root", "children": [1]},
            {"name": "knee", "translation": [0.0, KNEE, 0.0]},
            {"name": "stalk", "mesh": 0, "skin": 0}
        ],
        "skins": [{"joints": [0, 1], "inverseBindMatrices": 5, "skeleton": 0}],
        "meshes": [{"name": "stalk", "primitives": [{
            "attributes": {"POSITION": 0, "NORMAL": 1, "JOINTS_0": 2, "WEIGHTS_0": 3},
            "indices": 4,
            "material": 0
        }]}],
        "materials": [{
            "name": "stalk",
            "pbrMetallicRoughness": {"baseColorFactor": [0.35, 0.8, 0.3, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.7}
        }],
        "animations": [{
            "name": "sway",
            "samplers": [
                {"input": 6, "output": 7, "interpolation": "LINEAR"},
                {"input": 6, "output": 8, "interpolation": "LINEAR"}
            ],
            "channels": [
                {"sampler": 0, "target": {"node": 0, "path": "rotation"}},
                {"sampler": 1, "target": {"node": 1, "path": "rotation"}}
            ]
        }],
        "buffers": [{
            "byteLength": buffer.len(),
            "uri": format!("data:application/octet-stream;base64,{}", base64::engine::general_purpose::STANDARD.encode(&buffer))
        }],
        "bufferViews": views,
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": n, "type": "VEC3", "min": lo.to_array(), "max": hi.to_array()},
            {"bufferView": 1, "componentType": 5126, "count": n, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5123, "count": n, "type": "VEC4"},
            {"bufferView": 3, "componentType": 5126, "count": n, "type": "VEC4"},
            {"bufferView": 4, "componentType": 5123, "count": tris.len() * 3, "type": "SCALAR"},
            {"bufferView": 5, "componentType": 5126, "count": 2, "type": "MAT4"},
            {"bufferView": 6, "componentType": 5126, "count": 3, "type": "SCALAR", "min": [TIMES[0]], "max": [TIMES[2]]},
            {"bufferView": 7, "componentType": 5126, "count": 3, "type": "VEC4"},
            {"bufferView": 8, "componentType": 5126, "count": 3, "type": "VEC4"}
        ]
    });
    let mut text = serde_json::to_string_pretty(&json).expect("a JSON value");
    text.push('\n');
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The committed model is the one written here (set
    /// `BEVY_MANIFOLD_WRITE_MODELS=1` to write it again after a change).
    #[test]
    fn the_committed_stalk_is_the_one_made_here() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/models/stalk.gltf");
        let made = gltf();
        if std::env::var_os("BEVY_MANIFOLD_WRITE_MODELS").is_some() {
            std::fs::write(&path, &made).expect("assets/models/stalk.gltf");
        }
        let committed = std::fs::read_to_string(&path).expect("assets/models/stalk.gltf");
        assert!(
            committed == made,
            "assets/models/stalk.gltf is not what stalk::gltf() writes"
        );
    }

    /// The pose by geometry, at known points: the knee's own point never
    /// moves but for the root's turn, the top of the tube swings on a
    /// circle of radius 0.5 about the knee.
    #[test]
    fn the_pose_by_geometry_moves_what_it_should() {
        let t = 1.5;
        let (root, knee) = (root_angle(t), knee_angle(t));
        assert!((root - 0.6).abs() < 1e-6 && (knee - 0.6).abs() < 1e-6);
        let top = posed(Vec3::Y, t);
        let (s, c) = knee.sin_cos();
        let want = Quat::from_rotation_y(root) * Vec3::new(-0.5 * s, 0.5 + 0.5 * c, 0.0);
        assert!((top - want).length() < 1e-6, "{top} against {want}");
        assert!((posed(Vec3::Y * 0.1, t) - Vec3::Y * 0.1).length() < 1e-6);
        assert_eq!(rest().len(), RINGS * SIDES + 2 * (SIDES + 1));
    }
}
