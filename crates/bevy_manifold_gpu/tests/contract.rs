//! The contract between the Rust and WGSL halves of the tracer, checked
//! through naga with no GPU: every `Gpu…` struct has its WGSL twin's size
//! and member offsets (naga's layouter, as the GPU lays them out), the
//! WGSL bindings are those of the one Rust table ([`BINDINGS`]) both
//! bind-group layouts are built from, and the shared constants are equal
//! on both sides. A last test swaps two fields of a WGSL struct and sees
//! the check fail, so the check itself is known to bite.

use bevy_manifold_core::geometry::Geometry;
use bevy_manifold_core::trace::step::ALL_FACES;
use bevy_manifold_core::trace::{EDGE_ID, FOG_CUT, LIGHT_AT_HIT};
use bevy_manifold_gpu::bindings::{BINDINGS, BindingKind};
use bevy_manifold_gpu::layout::{GpuBall, GpuFace, GpuInstance, GpuLight, GpuParams, GpuPixel, GpuTube, NO_JOINT};
use bevy_manifold_gpu::{
    FLAG_NO_CULL, FLAG_NO_EARLY_STOP, FLAG_NO_RENORMALIZE, GpuCellScheme, GpuTracer, SHADER_IMPORTS, TRACE_WGSL,
    TraceDefs, WgslModule, undecorated,
};
use naga::proc::Layouter;
use std::mem::{offset_of, size_of};

/// A Rust struct's size and its fields' offsets, in declaration order.
struct RustLayout {
    name: &'static str,
    size: usize,
    fields: Vec<(&'static str, usize)>,
}

macro_rules! rust_layout {
    ($ty:ident => $wgsl:literal { $($field:ident),* $(,)? }) => {
        RustLayout {
            name: $wgsl,
            size: size_of::<$ty>(),
            fields: vec![$((stringify!($field), offset_of!($ty, $field))),*],
        }
    };
}

/// Every `Gpu…` struct with the name of its WGSL twin.
fn rust_layouts() -> Vec<RustLayout> {
    vec![
        rust_layout!(GpuParams => "Params" {
            camera, camera_cell, fog_color, width, height, levels, face_count, ball_count, tube_count,
            light_count, camera_cell_index, tan_half_fov, max_distance, fog_density, tube_k, origin_x,
            origin_y, near, flags, cell_scale, instance_count, cell_mode, cell_a, cell_b, rule_hidden, rule_hidden_seed, rule_walls, rule_walls_seed,
            projection, eye_offset, near_reach, pad_a, ball_leaves, chart_stretch, footprint_cap, pad_b, frustum, cone, occupied,
        }),
        rust_layout!(GpuFace => "Face" { plane, pairing, crossing, partner, pad_a, pad_b, pad_c }),
        rust_layout!(GpuBall => "Ball" { center, color, k, id, face_mask, glow, pad }),
        rust_layout!(GpuTube => "Tube" { a, e, b, e_b, color, face_mask, joint, pad_a, pad_b, pad_c }),
        rust_layout!(GpuInstance => "Instance" {
            to_local, center, color, k, nodes, vertices, triangles, id, texture, tex_width, tex_height,
            node_count, attached, face_mask, pad, home,
        }),
        rust_layout!(GpuLight => "Light" { position, color, intensity }),
        rust_layout!(GpuPixel => "Pixel" { color, object, levels, cell_lo, cell_hi }),
    ]
}

/// The shader with every def on, meshes and the Cayley table included
/// (naga_oil keeps only the bindings some entry uses, so this is a
/// specialisation that uses them all).
fn composed() -> naga::Module {
    let defs = TraceDefs {
        cells: GpuCellScheme::Finite,
        face_count: Some(12),
        ..TraceDefs::generic(Geometry::Spherical)
    };
    let mut names = defs.names();
    names.push("ENCODE_SRGB");
    assert!(names.contains(&"MESHES"), "{names:?}");
    GpuTracer::compose_with(&names, &defs.values()).expect("the tracer composes")
}

/// Each mismatch between the Rust layouts and the module's structs.
fn layout_mismatches(module: &naga::Module) -> Vec<String> {
    let mut layouter = Layouter::default();
    layouter.update(module.to_ctx()).expect("layout");
    let mut out = Vec::new();
    for rust in rust_layouts() {
        let found = module
            .types
            .iter()
            .find(|(_, t)| t.name.as_deref().map(undecorated) == Some(rust.name));
        let Some((handle, ty)) = found else {
            out.push(format!("{}: no such WGSL struct", rust.name));
            continue;
        };
        let naga::TypeInner::Struct { members, span } = &ty.inner else {
            out.push(format!("{}: not a struct", rust.name));
            continue;
        };
        if *span as usize != rust.size || layouter[handle].size as usize != rust.size {
            out.push(format!("{}: WGSL size {span}, Rust {}", rust.name, rust.size));
        }
        if members.len() != rust.fields.len() {
            out.push(format!(
                "{}: WGSL has {} members, Rust {} fields",
                rust.name,
                members.len(),
                rust.fields.len()
            ));
        }
        for (m, (field, offset)) in members.iter().zip(&rust.fields) {
            let name = m.name.as_deref().map(undecorated).unwrap_or("?");
            if name != *field || m.offset as usize != *offset {
                out.push(format!(
                    "{}: WGSL member {name} at {}, Rust field {field} at {offset}",
                    rust.name, m.offset
                ));
            }
        }
    }
    out
}

#[test]
fn every_gpu_struct_has_its_wgsl_twins_size_and_offsets() {
    let module = composed();
    let mismatches = layout_mismatches(&module);
    assert!(mismatches.is_empty(), "{mismatches:#?}");
}

#[test]
fn the_bindings_are_the_rust_tables() {
    let module = composed();
    let mut layouter = Layouter::default();
    layouter.update(module.to_ctx()).expect("layout");
    let mut seen = Vec::new();
    for (_, var) in module.global_variables.iter() {
        let Some(binding) = &var.binding else { continue };
        assert_eq!(binding.group, 0, "{:?}", var.name);
        let rust = BINDINGS
            .iter()
            .find(|b| b.binding == binding.binding)
            .unwrap_or_else(|| panic!("WGSL binding {} is not in BINDINGS", binding.binding));
        let name = var.name.as_deref().map(undecorated).unwrap_or("?");
        assert_eq!(name, rust.name, "binding {}", rust.binding);
        let kind = match var.space {
            naga::AddressSpace::Uniform => BindingKind::Uniform,
            naga::AddressSpace::Storage { access } if access.contains(naga::StorageAccess::STORE) => {
                BindingKind::StorageReadWrite
            }
            naga::AddressSpace::Storage { .. } => BindingKind::Storage,
            other => panic!("{name}: unexpected address space {other:?}"),
        };
        assert_eq!(kind, rust.kind, "{name}");
        // The uniform's size, or one element of a storage array.
        let element = match &module.types[var.ty].inner {
            naga::TypeInner::Array { base, .. } => layouter[*base].size,
            _ => layouter[var.ty].size,
        };
        assert_eq!(element as usize, rust.element_size, "{name}: element size");
        // A uniform array's declared length is the buffer's capacity.
        let length = match &module.types[var.ty].inner {
            naga::TypeInner::Array {
                size: naga::ArraySize::Constant(n),
                ..
            } => n.get() as usize,
            _ => 0,
        };
        assert_eq!(length, rust.capacity, "{name}: uniform array length");
        seen.push(rust.binding);
    }
    seen.sort_unstable();
    let all: Vec<u32> = BINDINGS.iter().map(|b| b.binding).collect();
    assert_eq!(seen, all, "every binding of the table is declared in the WGSL");
}

/// The value of a WGSL `const` (decorated name or not).
fn constant(module: &naga::Module, name: &str) -> naga::Literal {
    let (_, c) = module
        .constants
        .iter()
        .find(|(_, c)| c.name.as_deref().map(undecorated) == Some(name))
        .unwrap_or_else(|| panic!("no WGSL constant {name}"));
    match module.global_expressions[c.init] {
        naga::Expression::Literal(l) => l,
        ref e => panic!("{name} is not a literal: {e:?}"),
    }
}

#[test]
fn the_shared_constants_are_equal_on_both_sides() {
    let module = composed();
    assert_eq!(constant(&module, "EDGE_ID"), naga::Literal::U32(EDGE_ID));
    assert_eq!(
        constant(&module, "FLAG_NO_EARLY_STOP"),
        naga::Literal::U32(FLAG_NO_EARLY_STOP)
    );
    assert_eq!(
        constant(&module, "FLAG_NO_RENORMALIZE"),
        naga::Literal::U32(FLAG_NO_RENORMALIZE)
    );
    assert_eq!(constant(&module, "FLAG_NO_CULL"), naga::Literal::U32(FLAG_NO_CULL));
    assert_eq!(constant(&module, "NO_JOINT"), naga::Literal::U32(NO_JOINT));
    assert_eq!(constant(&module, "ALL_FACES"), naga::Literal::U32(ALL_FACES));
    assert_eq!(constant(&module, "FOG_CUT"), naga::Literal::F32(FOG_CUT as f32));
    assert_eq!(FOG_CUT, 255f64.ln(), "FOG_CUT is ln 255");
    assert_eq!(
        constant(&module, "LIGHT_AT_HIT"),
        naga::Literal::F32(LIGHT_AT_HIT as f32)
    );
}

#[test]
fn the_contract_catches_a_swapped_field() {
    // The same shader, but `Ball`'s `k` and `id` (both 4 bytes) swapped:
    // sizes stay equal, so only the member check can see it.
    let bindings = SHADER_IMPORTS
        .iter()
        .find(|m| m.path.ends_with("/bindings.wgsl"))
        .expect("bindings");
    let original = bindings.source;
    let ball = original.find("struct Ball {").expect("Ball");
    let k = ball + original[ball..].find("    k: f32,\n").expect("k");
    let id = ball + original[ball..].find("    id: u32,\n").expect("id");
    assert!(k < id);
    let swapped = format!(
        "{}    id: u32,\n{}    k: f32,\n{}",
        &original[..k],
        &original[k + "    k: f32,\n".len()..id],
        &original[id + "    id: u32,\n".len()..]
    );
    let module = compose_with_bindings(&swapped);
    let mismatches = layout_mismatches(&module);
    assert!(
        mismatches.iter().any(|m| m.starts_with("Ball: WGSL member id")),
        "{mismatches:#?}"
    );
    assert!(mismatches.iter().all(|m| m.starts_with("Ball:")), "{mismatches:#?}");
}

/// The entry module composed with `bindings` replaced by `source`.
fn compose_with_bindings(source: &str) -> naga::Module {
    let source: &'static str = Box::leak(source.to_owned().into_boxed_str());
    let imports = SHADER_IMPORTS.map(|m| {
        if m.path.ends_with("/bindings.wgsl") {
            WgslModule { source, ..m }
        } else {
            m
        }
    });
    let defs = TraceDefs::generic(Geometry::Hyperbolic);
    GpuTracer::compose_modules(&imports, TRACE_WGSL, &defs.names(), &defs.values())
        .expect("the broken copy still composes")
}
