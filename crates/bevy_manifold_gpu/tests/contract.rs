//! The contract between the Rust and WGSL halves of the tracer, checked
//! through naga with no GPU: every `Gpu…` struct has its WGSL twin's size
//! and member offsets (naga's layouter, as the GPU lays them out), the
//! WGSL bindings are those of the one Rust table ([`BINDINGS`]) both
//! bind-group layouts are built from, and the shared constants are equal
//! on both sides. Every "WGSL twin" comment in the Rust names a WGSL item
//! that exists (in the file it names), every "Rust twin" comment in the
//! WGSL a Rust item that exists, and each stage of the tracer is a Rust
//! file and a WGSL file of the same name. Two tests break a copy on
//! purpose (a WGSL struct's fields swapped, a twin misnamed) and see the
//! checks fail, so the checks themselves are known to bite.

use bevy_manifold_core::geometry::Geometry;
use bevy_manifold_core::trace::step::ALL_FACES;
use bevy_manifold_core::trace::{EDGE_ID, FOG_CUT, LIGHT_AT_HIT};
use bevy_manifold_gpu::bindings::{BINDINGS, BindingKind};
use bevy_manifold_gpu::layout::{
    GpuBall, GpuFace, GpuInstance, GpuLight, GpuParams, GpuPixel, GpuTube, NO_INSTANCE_TREES, NO_JOINT,
};
use bevy_manifold_gpu::product::{
    GpuProductBall, GpuProductFace, GpuProductLight, GpuProductMesh, GpuProductParams, GpuProductPixel,
};
use bevy_manifold_gpu::{
    FLAG_NO_CULL, FLAG_NO_EARLY_STOP, FLAG_NO_RENORMALIZE, GpuCellScheme, GpuTracer, RENDER_WGSL, SHADER_IMPORTS,
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
            projection, eye_offset, near_reach, light_sample_u, ball_leaves, chart_stretch, footprint_cap, light_sample_v, frustum, cone, occupied, reflections, path_depth, seed, sample, instance_trees, pad_a, pad_b, pad_c,
        }),
        rust_layout!(GpuFace => "Face" { plane, pairing, crossing, partner, pad_a, pad_b, pad_c }),
        rust_layout!(GpuBall => "Ball" { center, color, k, id, face_mask, glow, pbr }),
        rust_layout!(GpuTube => "Tube" { a, e, b, e_b, color, face_mask, joint, pad_a, pad_b, pad_c }),
        rust_layout!(GpuInstance => "Instance" {
            to_local, center, color, k, nodes, vertices, triangles, id, textures, node_count, attached,
            face_mask, alpha_cutoff, emissive, metallic, roughness, alpha, pad, home,
        }),
        rust_layout!(GpuLight => "Light" { position, color, intensity, inv_range_sq, min_area, spot_scale, spot_offset, spot_dir, radius, pad_a, pad_b, pad_c }),
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

/// The product tracer's `Gpu…` structs with the names of their WGSL
/// twins (in `shaders/product.wgsl`).
fn product_layouts() -> Vec<RustLayout> {
    vec![
        rust_layout!(GpuProductParams => "ProductParams" {
            eye, forward, right, up, fog_color, frustum, edges, width, height, max_crossings, side_count, ball_count,
            curvature, half_height, max_distance, tan_half_fov, fog, origin_x, origin_y, tint_mode, tint_a,
            tint_b, cell_count, camera_steps, camera_flip, light_count, shadows, mesh_count, pad_a, pad_b, pad_c,
        }),
        rust_layout!(GpuProductMesh => "ProductMesh" {
            to_chart, placement, center, color, to_flip, to_shift, across, across_trig, tall, id, nodes, triangles,
        }),
        rust_layout!(GpuProductLight => "ProductLight" {
            position, color, inv_range_sq, min_area, spot_inner, spot_outer, spot_axis,
        }),
        rust_layout!(GpuProductFace => "ProductFace" { normal, corner, surface, flip, shift, partner, cross_steps }),
        rust_layout!(GpuProductBall => "ProductBall" { center, color, radius, id, reach_trig, pad }),
        rust_layout!(GpuProductPixel => "ProductPixel" { color, object, crossings, cell }),
    ]
}

/// Each mismatch between the Rust layouts and the module's structs.
fn layout_mismatches(module: &naga::Module) -> Vec<String> {
    layout_mismatches_of(module, rust_layouts())
}

/// Each mismatch between `layouts` and the module's structs.
fn layout_mismatches_of(module: &naga::Module, layouts: Vec<RustLayout>) -> Vec<String> {
    let mut layouter = Layouter::default();
    layouter.update(module.to_ctx()).expect("layout");
    let mut out = Vec::new();
    for rust in layouts {
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
fn every_product_struct_has_its_wgsl_twins_size_and_offsets() {
    let module = GpuTracer::compose_modules(
        &[bevy_manifold_gpu::CELL_TINT_WGSL],
        bevy_manifold_gpu::PRODUCT_WGSL,
        &[],
        &[],
    )
    .expect("product.wgsl composes");
    let mismatches = layout_mismatches_of(&module, product_layouts());
    assert!(mismatches.is_empty(), "{mismatches:#?}");
    // The product tracer's bindings: params, faces, balls, pixels, cells,
    // lights, meshes and their data.
    let bound: Vec<(u32, String)> = module
        .global_variables
        .iter()
        .filter_map(|(_, v)| Some((v.binding.as_ref()?.binding, v.name.clone()?)))
        .collect();
    assert_eq!(
        bound,
        [
            (0, "params"),
            (1, "faces"),
            (2, "balls"),
            (3, "pixels"),
            (4, "cells"),
            (5, "lights"),
            (6, "meshes"),
            (7, "mesh_data")
        ]
        .map(|(b, n)| (b, n.to_owned()))
    );
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
    assert_eq!(
        constant(&module, "NO_INSTANCE_TREES"),
        naga::Literal::U32(NO_INSTANCE_TREES)
    );
    assert_eq!(constant(&module, "ALL_FACES"), naga::Literal::U32(ALL_FACES));
    assert_eq!(constant(&module, "FOG_CUT"), naga::Literal::F32(FOG_CUT as f32));
    assert_eq!(FOG_CUT, 255f64.ln(), "FOG_CUT is ln 255");
    assert_eq!(
        constant(&module, "LIGHT_AT_HIT"),
        naga::Literal::F32(LIGHT_AT_HIT as f32)
    );
    assert_eq!(
        constant(&module, "MIRROR_OFFSET"),
        naga::Literal::F32(bevy_manifold_core::trace::MIRROR_OFFSET as f32)
    );
    assert_eq!(
        constant(&module, "MAX_MIRROR_ROUGHNESS"),
        naga::Literal::F32(bevy_manifold_core::trace::MAX_MIRROR_ROUGHNESS)
    );
    assert_eq!(
        constant(&module, "MAX_REFLECTIONS"),
        naga::Literal::U32(bevy_manifold_core::trace::MAX_REFLECTIONS)
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
    GpuTracer::compose_modules(&imports, RENDER_WGSL, &defs.names(), &defs.values())
        .expect("the broken copy still composes")
}

/// The WGSL sources, by file name (`render.wgsl`, …).
fn wgsl_sources() -> Vec<(String, String)> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    let mut out: Vec<(String, String)> = std::fs::read_dir(&dir)
        .expect("shaders/")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "wgsl"))
        .map(|p| {
            let name = p.file_name().expect("name").to_string_lossy().into_owned();
            (name, std::fs::read_to_string(&p).expect("read"))
        })
        .collect();
    out.sort();
    out
}

/// Every Rust source of the tracer's crates (the core, this crate, the
/// plugin), by path from the repository root; empty outside the
/// repository (a packaged crate has no sibling crates).
fn rust_sources() -> Vec<(String, String)> {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut out = Vec::new();
    for dir in ["crates/bevy_manifold_core/src", "crates/bevy_manifold_gpu/src", "src"] {
        let mut stack = vec![root.join(dir)];
        while let Some(d) = stack.pop() {
            let Ok(entries) = std::fs::read_dir(&d) else { continue };
            for e in entries {
                let p = e.expect("entry").path();
                if p.is_dir() {
                    stack.push(p);
                } else if p.extension().is_some_and(|x| x == "rs") {
                    let name = p
                        .strip_prefix(&root)
                        .expect("under the root")
                        .to_string_lossy()
                        .into_owned();
                    out.push((name, std::fs::read_to_string(&p).expect("read")));
                }
            }
        }
    }
    out.sort();
    out
}

/// The comment blocks of a source (runs of lines whose trimmed text starts
/// with `//`), each as one string with the comment markers taken off, with
/// the line it starts on.
fn comment_blocks(source: &str) -> Vec<(usize, String)> {
    let mut out: Vec<(usize, String)> = Vec::new();
    let mut open = false;
    for (i, line) in source.lines().enumerate() {
        let t = line.trim_start();
        if let Some(text) = t.strip_prefix("//") {
            let text = text.trim_start_matches(['/', '!']).trim();
            if open && let Some(last) = out.last_mut() {
                last.1.push(' ');
                last.1.push_str(text);
            } else {
                out.push((i + 1, text.to_owned()));
            }
            open = true;
        } else {
            open = false;
        }
    }
    out
}

/// The sentences of `block` that start with `marker` ("WGSL twin",
/// "Rust twin") followed by `:` or ` (` (or `s:`, `s (`): from the marker to
/// the end of its sentence (a full stop and a space, or the block's end).
/// Prose that only mentions twins ("the WGSL twin of a file") is not one.
fn twin_sentences<'a>(block: &'a str, marker: &str) -> Vec<&'a str> {
    let mut out = Vec::new();
    let mut rest = block;
    while let Some(at) = rest.find(marker) {
        let s = &rest[at..];
        let after = s[marker.len()..].trim_start_matches('s');
        if !(after.starts_with(':') || after.starts_with(" (")) {
            rest = &s[marker.len()..];
            continue;
        }
        let end = s.find(". ").map_or(s.len(), |e| e + 1);
        out.push(&s[..end]);
        rest = &s[end..];
    }
    out
}

/// The text between backticks in `s`, but for intra-doc links (``[`x`]``),
/// which name Rust items.
fn backticked(s: &str) -> Vec<&str> {
    let parts: Vec<&str> = s.split('`').collect();
    (1..parts.len())
        .step_by(2)
        .filter(|&i| !parts[i - 1].ends_with('['))
        .map(|i| parts[i])
        .collect()
}

/// The names a WGSL source defines: functions, structs, constants,
/// variables, struct members and shader defs.
fn wgsl_names(source: &str) -> std::collections::BTreeSet<String> {
    let mut names = std::collections::BTreeSet::new();
    let ident = |s: &str| -> String { s.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect() };
    let mut in_struct = false;
    for line in source.lines() {
        let t = line.trim();
        for (prefix, is_struct) in [("fn ", false), ("struct ", true), ("const ", false)] {
            if let Some(rest) = t.strip_prefix(prefix) {
                names.insert(ident(rest));
                in_struct |= is_struct;
            }
        }
        if let Some(at) = t.find("var") {
            let after = &t[at + 3..];
            let after = after.split_once('>').map_or(after, |(_, a)| a).trim_start();
            if t.starts_with("var") || t.starts_with('@') {
                names.insert(ident(after));
            }
        }
        for def in ["#ifdef ", "#ifndef ", "#else ifdef "] {
            if let Some(rest) = t.strip_prefix(def) {
                names.insert(ident(rest));
            }
        }
        if let Some(at) = t.find("#{") {
            names.insert(ident(&t[at + 2..]));
        }
        if in_struct {
            if t.starts_with('}') {
                in_struct = false;
            } else if let Some((member, _)) = t.split_once(':')
                && !member.contains(' ')
            {
                names.insert(member.to_owned());
            }
        }
    }
    names.remove("");
    names
}

/// The names a Rust source defines: functions, types, constants, struct
/// fields (`name:` at a line's start), enum variants and `let` bindings
/// (a closure a function's comment names).
fn rust_names(source: &str) -> std::collections::BTreeSet<String> {
    let mut names = std::collections::BTreeSet::new();
    let ident = |s: &str| -> String { s.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect() };
    for line in source.lines() {
        let mut t = line.trim();
        for vis in ["pub(crate) ", "pub(super) ", "pub "] {
            t = t.strip_prefix(vis).unwrap_or(t);
        }
        for prefix in [
            "fn ", "struct ", "enum ", "const ", "type ", "trait ", "mod ", "let mut ", "let ",
        ] {
            if let Some(rest) = t.strip_prefix(prefix) {
                names.insert(ident(rest));
            }
        }
        if let Some((field, _)) = t.split_once(':')
            && !field.is_empty()
            && field.chars().all(|c| c.is_alphanumeric() || c == '_')
        {
            names.insert(field.to_owned());
        }
        // Enum variants: `Name,` or `Name(…)` or `Name {` alone on a line.
        let v = ident(t);
        if !v.is_empty()
            && v.chars().next().is_some_and(char::is_uppercase)
            && t[v.len()..].trim_start().starts_with([',', '(', '{'])
        {
            names.insert(v);
        }
    }
    names.remove("");
    names
}

/// The last name of a path-like token (`Nearest::limit`, `params.cone`,
/// `FaceTables::planes[i]`), and whether the token names a name at all
/// (not a file, a crate or a command).
fn name_of(token: &str) -> Option<&str> {
    if token.contains('/') || token.contains(' ') || token.ends_with(".rs") || token.ends_with(".wgsl") {
        return None;
    }
    if token.starts_with("bevy_manifold") {
        return None;
    }
    let token = token.split('[').next().unwrap_or(token).trim_end_matches("()");
    let last = token.rsplit(['.', ':']).next().unwrap_or(token);
    (!last.is_empty() && last.chars().all(|c| c.is_alphanumeric() || c == '_')).then_some(last)
}

/// Every "WGSL twin" sentence of `rust` (a file's name and source) and
/// the names it gives that no WGSL source defines (or, where the
/// sentence names WGSL files, that none of them defines); and the pairs
/// it holds: (Rust file, WGSL name).
fn check_wgsl_twins(rust: &[(String, String)], wgsl: &[(String, String)]) -> (Vec<String>, Vec<(String, String)>) {
    let all: std::collections::BTreeSet<String> = wgsl.iter().flat_map(|(_, s)| wgsl_names(s)).collect();
    let by_file: std::collections::BTreeMap<&str, std::collections::BTreeSet<String>> =
        wgsl.iter().map(|(f, s)| (f.as_str(), wgsl_names(s))).collect();
    let (mut missing, mut pairs) = (Vec::new(), Vec::new());
    for (file, source) in rust {
        for (line, block) in comment_blocks(source) {
            for sentence in twin_sentences(&block, "WGSL twin") {
                let tokens = backticked(sentence);
                let named: Vec<&str> = tokens
                    .iter()
                    .filter(|t| t.ends_with(".wgsl"))
                    .map(|t| t.rsplit('/').next().unwrap_or(t))
                    .collect();
                for f in named.iter().filter(|f| !by_file.contains_key(**f)) {
                    missing.push(format!("{file}:{line}: no shader {f}"));
                }
                for name in tokens.iter().filter_map(|t| name_of(t)) {
                    let known = if named.is_empty() {
                        all.contains(name)
                    } else {
                        named
                            .iter()
                            .any(|f| by_file.get(f).is_some_and(|names| names.contains(name)))
                    };
                    if known {
                        pairs.push((file.clone(), name.to_owned()));
                    } else {
                        let place = if named.is_empty() {
                            "the WGSL".to_owned()
                        } else {
                            named.join(" or ")
                        };
                        missing.push(format!("{file}:{line}: `{name}` is not in {place}"));
                    }
                }
            }
        }
    }
    (missing, pairs)
}

/// The same the other way: every "Rust twin" sentence of the WGSL, its
/// first name (the twin: the first word after the colon that is a
/// `….rs` file or a code name, with `_`, `::` or a capital) and every name
/// in backticks; the files that do not exist and the names no Rust source
/// defines; and how many it held.
fn check_rust_twins(wgsl: &[(String, String)], rust: &[(String, String)]) -> (Vec<String>, usize) {
    let all: std::collections::BTreeSet<String> = rust.iter().flat_map(|(_, s)| rust_names(s)).collect();
    let (mut missing, mut held) = (Vec::new(), 0);
    for (file, source) in wgsl {
        for (line, block) in comment_blocks(source) {
            for sentence in twin_sentences(&block, "Rust twin") {
                let body = sentence.split_once(':').map_or("", |(_, b)| b);
                let words = body.split(|c: char| {
                    !(c.is_alphanumeric()
                        || c == '_'
                        || c == ':'
                        || c == '/'
                        || c == '.'
                        || c == '`'
                        || c == '['
                        || c == ']')
                });
                let mut first = true;
                for word in words.filter(|w| !w.is_empty()) {
                    let quoted = word.starts_with('`');
                    let word = word.trim_matches(['`', '.', ':']);
                    if first && word.ends_with(".rs") {
                        first = false;
                        let exists = rust
                            .iter()
                            .any(|(f, _)| f.ends_with(word.rsplit("src/").next().unwrap_or(word)));
                        if exists {
                            held += 1;
                        } else {
                            missing.push(format!("{file}:{line}: no Rust file {word}"));
                        }
                        continue;
                    }
                    let code = word.contains('_')
                        || word.contains("::")
                        || word.chars().next().is_some_and(char::is_uppercase);
                    if !(quoted || (first && code)) {
                        continue;
                    }
                    first = false;
                    let Some(name) = name_of(word) else { continue };
                    if all.contains(name) {
                        held += 1;
                    } else {
                        missing.push(format!("{file}:{line}: `{name}` is not in the Rust sources"));
                    }
                }
            }
        }
    }
    (missing, held)
}

#[test]
fn every_twin_comment_names_a_twin_that_exists() {
    let (wgsl, rust) = (wgsl_sources(), rust_sources());
    if rust.is_empty() {
        eprintln!("not in the repository: the Rust twins are not here to check");
        return;
    }
    let (missing, pairs) = check_wgsl_twins(&rust, &wgsl);
    assert!(
        missing.is_empty(),
        "WGSL twins that do not exist:\n{}",
        missing.join("\n")
    );
    let (missing, held) = check_rust_twins(&wgsl, &rust);
    assert!(
        missing.is_empty(),
        "Rust twins that do not exist:\n{}",
        missing.join("\n")
    );
    eprintln!(
        "{} WGSL twins named in Rust, {held} Rust twins named in WGSL",
        pairs.len()
    );
    for (file, name) in &pairs {
        eprintln!("  {file} -> {name}");
    }
    // The tracer's stages: each Rust file has its WGSL twin of the same
    // name, and names it.
    for stage in [
        "camera",
        "trace",
        "cull",
        "nearest",
        "cone",
        "footprint",
        "shade",
        "render",
        "step",
        "walk",
    ] {
        let rs = format!("crates/bevy_manifold_core/src/trace/{stage}.rs");
        let source = &rust.iter().find(|(f, _)| *f == rs).unwrap_or_else(|| panic!("{rs}")).1;
        assert!(
            wgsl.iter().any(|(f, _)| *f == format!("{stage}.wgsl")),
            "{stage}.wgsl, the twin of {rs}"
        );
        assert!(
            source.contains(&format!("`shaders/{stage}.wgsl`")),
            "{rs} names its twin"
        );
    }
    assert!(pairs.len() > 60, "only {} pairs", pairs.len());
}

#[test]
fn the_twin_check_catches_a_name_that_is_not_there() {
    let wgsl = vec![(
        "step.wgsl".to_owned(),
        "fn exit_face(ray: Ray) -> u32 {\n    return 0u;\n}\n".to_owned(),
    )];
    let good = vec![(
        "a.rs".to_owned(),
        "/// Where a ray leaves. WGSL twin: `exit_face` in\n/// `shaders/step.wgsl`.\nfn exit_face() {}\n".to_owned(),
    )];
    let bad = vec![(
        "a.rs".to_owned(),
        "/// WGSL twin: `exit_faces` in `shaders/step.wgsl`.\nfn exit_face() {}\n".to_owned(),
    )];
    let elsewhere = vec![(
        "a.rs".to_owned(),
        "/// WGSL twin: `exit_face` in `shaders/walk.wgsl`.\nfn exit_face() {}\n".to_owned(),
    )];
    assert!(check_wgsl_twins(&good, &wgsl).0.is_empty());
    assert_eq!(check_wgsl_twins(&bad, &wgsl).0.len(), 1);
    assert_eq!(
        check_wgsl_twins(&elsewhere, &wgsl).0.len(),
        2,
        "no walk.wgsl, and the name not in it"
    );
    let wgsl_bad = vec![(
        "step.wgsl".to_owned(),
        "// Rust twin: `exit_faces`.\nfn exit_face() {}\n".to_owned(),
    )];
    assert_eq!(check_rust_twins(&wgsl_bad, &good).0.len(), 1);
    let wgsl_good = vec![(
        "step.wgsl".to_owned(),
        "// Rust twin: exit_face.\nfn exit_face() {}\n".to_owned(),
    )];
    assert_eq!(check_rust_twins(&wgsl_good, &good), (vec![], 1));
}
