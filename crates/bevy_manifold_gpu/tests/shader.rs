//! The WGSL tracer, composed for every specialisation with Bevy's own
//! preprocessor (naga_oil), validated by naga and written as SPIR-V by
//! naga's writer, as wgpu's Vulkan backend writes it: no GPU needed.

use bevy_manifold_core::geometry::Geometry;
use bevy_manifold_core::prelude::*;
use bevy_manifold_gpu::{GpuTracer, TraceDefs};

/// Composed exactly as the GPU tracer composes it (naga_oil, Bevy's
/// preprocessor).
fn compose(defs: &TraceDefs) -> Result<naga::Module, String> {
    GpuTracer::compose(defs).map_err(|e| e.to_string())
}

fn validate(module: &naga::Module) -> Result<(), String> {
    validated(module).map(|_| ())
}

fn validated(module: &naga::Module) -> Result<naga::valid::ModuleInfo, String> {
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::default(),
    )
    .validate(module)
    .map_err(|e| format!("{e:?}"))
}

/// The module written as SPIR-V, as wgpu's Vulkan backend writes it
/// (lavapipe and every Vulkan driver take this): naga's writer can fail,
/// or panic, on a module that validates.
fn spirv(module: &naga::Module, info: &naga::valid::ModuleInfo) -> Result<Vec<u32>, String> {
    let options = naga::back::spv::Options::default();
    std::panic::catch_unwind(|| naga::back::spv::write_vec(module, info, &options, None))
        .map_err(|_| "naga's SPIR-V writer panicked".to_string())?
        .map_err(|e| format!("{e:?}"))
}

/// The product spaces' tracer, a module of its own: validated and written
/// as SPIR-V, with its one compute entry.
#[test]
fn the_product_tracer_composes_and_validates() {
    let module = GpuTracer::compose_modules(
        &[bevy_manifold_gpu::CELL_TINT_WGSL],
        bevy_manifold_gpu::PRODUCT_WGSL,
        &[],
        &[],
    )
    .expect("composes");
    let info = validated(&module).expect("validates");
    let words = spirv(&module, &info).expect("SPIR-V");
    assert_eq!(words.first(), Some(&0x0723_0203), "the SPIR-V magic number");
    let entries: Vec<&str> = module.entry_points.iter().map(|e| e.name.as_str()).collect();
    assert_eq!(entries, ["product_fragment", "product_trace"]);
    assert_eq!(module.entry_points[1].workgroup_size, [8, 8, 1]);
    // With the sRGB encoding the render pass asks for, too.
    let encoding = GpuTracer::compose_modules(
        &[bevy_manifold_gpu::CELL_TINT_WGSL],
        bevy_manifold_gpu::PRODUCT_WGSL,
        &["ENCODE_SRGB"],
        &[],
    )
    .expect("composes");
    let info = validated(&encoding).expect("validates");
    spirv(&encoding, &info).expect("SPIR-V");
    assert!(functions(&encoding).iter().any(|f| f == "encode_srgb"));
    assert!(!functions(&module).iter().any(|f| f == "encode_srgb"));
    // Each specialisation on what a scene needs (cells, lights), with
    // only its own code: the lights' walk to each light where there are
    // lights, the table walk where there is a table.
    for defs in bevy_manifold_gpu::product::ProductShaderDefs::all() {
        let module = GpuTracer::compose_modules(
            &[bevy_manifold_gpu::CELL_TINT_WGSL],
            bevy_manifold_gpu::PRODUCT_WGSL,
            &defs.names(),
            &[],
        )
        .expect("composes");
        let info = validated(&module).unwrap_or_else(|e| panic!("{defs:?}: {e}"));
        spirv(&module, &info).unwrap_or_else(|e| panic!("{defs:?}: {e}"));
        let has = |name: &str| functions(&module).iter().any(|f| f == name);
        assert_eq!((has("shadowed"), has("direct")), (defs.lights, defs.lights), "{defs:?}");
        assert_eq!(
            (has("cross_cell"), has("product_cell_id")),
            (defs.cells, defs.cells),
            "{defs:?}"
        );
        assert_eq!(
            (has("edge_entry"), has("mesh_entry")),
            (defs.edges, defs.meshes),
            "{defs:?}"
        );
    }
}

#[test]
fn every_specialisation_composes_and_validates() {
    let all = TraceDefs::all();
    // 6 switches per base, each way; then of balls and tubes: neither (1
    // way), tubes only (cone tracing on and off: 2), balls only (cone
    // tracing and the ball tree on and off: 4), both (4).
    assert_eq!(all.len(), 7 * 64 * (1 + 2 + 4 + 4));
    for defs in &all {
        let module = compose(defs).unwrap_or_else(|e| panic!("{:?}: {e}", defs.names()));
        let info = validated(&module).unwrap_or_else(|e| panic!("{:?}: {e}", defs.names()));
        let words = spirv(&module, &info).unwrap_or_else(|e| panic!("{:?}: SPIR-V: {e}", defs.names()));
        assert_eq!(words.first(), Some(&0x0723_0203), "the SPIR-V magic number");
        // The headless compute entry and the render pass's fragment entry.
        assert!(module.entry_points.iter().any(|e| e.name == "trace"));
        assert!(module.entry_points.iter().any(|e| e.name == "fragment"));
        assert!(module.entry_points.iter().any(|e| e.name == "drift"));
        // The BVH walk is compiled in only with meshes.
        let has_bvh = functions(&module).iter().any(|f| f == "hit_mesh");
        assert_eq!(has_bvh, defs.meshes, "{:?}", defs.names());
        // Cone tracing is compiled in only under FOOTPRINT.
        let has_cone = functions(&module).iter().any(|f| f == "cone_layer");
        assert_eq!(has_cone, defs.footprint, "{:?}", defs.names());
    }
}

#[test]
fn the_srgb_encoding_variant_composes_and_encodes() {
    let torus = catalog::torus(1.0);
    let defs = TraceDefs::for_scene(&torus, &Scene::default_for(&torus), false);
    let with = |extra: &[&'static str]| {
        let names: Vec<&'static str> = defs.names().into_iter().chain(extra.iter().copied()).collect();
        let module = GpuTracer::compose_with(&names, &defs.values()).expect("compose");
        validate(&module).expect("validate");
        functions(&module)
    };
    assert!(with(&["ENCODE_SRGB"]).iter().any(|f| f == "encode_srgb"));
    assert!(!with(&[]).iter().any(|f| f == "encode_srgb"));
}

/// The names of the functions a composed module kept, as the WGSL names
/// them (naga_oil suffixes an imported module's items with
/// `X_naga_oil_mod_X<its path>X`).
fn functions(module: &naga::Module) -> Vec<String> {
    module
        .functions
        .iter()
        .filter_map(|(_, f)| f.name.as_deref())
        .map(|n| bevy_manifold_gpu::undecorated(n).to_string())
        .collect()
}

/// True when the module calls a math function like `sinh` anywhere.
fn uses_math(module: &naga::Module, fun: naga::MathFunction) -> bool {
    let in_fn = |f: &naga::Function| {
        f.expressions
            .iter()
            .any(|(_, e)| matches!(e, naga::Expression::Math { fun: m, .. } if *m == fun))
    };
    module.functions.iter().any(|(_, f)| in_fn(f)) || module.entry_points.iter().any(|e| in_fn(&e.function))
}

#[test]
fn scenes_compile_only_what_they_use() {
    // A fog-free torus: no fog, no hyperbolic or spherical functions, no
    // general transport, no cell colours.
    let torus = catalog::torus(1.0);
    let mut scene = Scene::default_for(&torus);
    let defs = TraceDefs::for_scene(&torus, &scene, false);
    let names = defs.names();
    for absent in [
        "FOG",
        "MESHES",
        "GEOMETRY_HYPERBOLIC",
        "GEOMETRY_SPHERICAL",
        "CELL_COLORS",
        "CELLS_HASHED",
    ] {
        assert!(!names.contains(&absent), "{absent} in {names:?}");
    }
    for present in [
        "GEOMETRY_EUCLIDEAN",
        "TRANSLATIONS_ONLY",
        "CELLS_LATTICE",
        "BALLS",
        "TUBES",
        "LIGHTS",
    ] {
        assert!(names.contains(&present), "{present} missing from {names:?}");
    }
    let module = compose(&defs).expect("compose");
    for fun in [
        naga::MathFunction::Sinh,
        naga::MathFunction::Atanh,
        naga::MathFunction::Asinh,
        naga::MathFunction::Exp,
    ] {
        assert!(!uses_math(&module, fun), "the fog-free torus shader uses {fun:?}");
    }
    assert!(!functions(&module).iter().any(|f| f == "cell_color"));

    // Fog and cell colours switch their code on.
    scene.fog = Some(Fog {
        density: 0.3,
        color: [0.5; 3],
    });
    let fogged = compose(&TraceDefs::for_scene(&torus, &scene, true)).expect("compose");
    assert!(uses_math(&fogged, naga::MathFunction::Exp));
    assert!(functions(&fogged).iter().any(|f| f == "cell_color"));

    // Seifert-Weber: hyperbolic functions, general transport, the exact
    // table of cells; the Weeks manifold (not golden) hashes its cells.
    let sw = catalog::seifert_weber();
    let defs = TraceDefs::for_scene(&sw, &Scene::default_for(&sw), false);
    assert_eq!(defs.geometry, Geometry::Hyperbolic);
    assert!(!defs.translations_only);
    assert!(defs.names().contains(&"CELLS_TABLE"));
    let weeks = bevy_manifold_core::space::catalog::resolve("weeks").unwrap();
    assert!(
        TraceDefs::for_scene(&weeks, &Scene::empty(), false)
            .names()
            .contains(&"CELLS_HASHED")
    );
    assert!(uses_math(&compose(&defs).expect("compose"), naga::MathFunction::Atanh));
    // The mirrored cube is Euclidean but its pairings are reflections.
    let mc = catalog::mirrored_cube(1.0);
    assert!(!TraceDefs::for_scene(&mc, &Scene::default_for(&mc), false).translations_only);
    // Poincaré uses the Cayley table.
    let p = catalog::poincare();
    assert!(
        TraceDefs::for_scene(&p, &Scene::empty(), false)
            .names()
            .contains(&"CELLS_FINITE")
    );
    // An empty scene compiles no object code at all.
    let empty = TraceDefs::for_scene(&sw, &Scene::empty(), false);
    let names = empty.names();
    assert!(!names.contains(&"BALLS") && !names.contains(&"TUBES") && !names.contains(&"LIGHTS"));
    let module = compose(&empty).expect("compose");
    assert!(!functions(&module).iter().any(|f| f == "hit_ball" || f == "hit_tube"));
}

/// Every specialisation is no larger than the generic shader with the same
/// face count (a constant count loops over the faces in chunks, each
/// unrolled: more code, not more work).
#[test]
fn the_generic_shader_is_the_largest() {
    let count = |m: &naga::Module| m.functions.iter().map(|(_, f)| f.expressions.len()).sum::<usize>();
    for g in [Geometry::Euclidean, Geometry::Hyperbolic, Geometry::Spherical] {
        let generic = |face_count| {
            count(
                &compose(&TraceDefs {
                    face_count,
                    ..TraceDefs::generic(g)
                })
                .expect("compose"),
            )
        };
        let (counted, constant) = (generic(None), generic(Some(12)));
        for defs in TraceDefs::all().iter().filter(|d| d.geometry == g) {
            let largest = if defs.face_count.is_some() { constant } else { counted };
            assert!(count(&compose(defs).expect("compose")) <= largest, "{:?}", defs.names());
        }
    }
}

#[test]
fn the_upscale_shader_validates_and_binds_what_the_pass_binds() {
    use bevy_manifold_gpu::{SHADER_IMPORTS, UPSCALE_WGSL};
    // With and without the encoding, composed as Bevy composes it.
    let plain = GpuTracer::compose_modules(&SHADER_IMPORTS, UPSCALE_WGSL, &[], &[]).expect("composes");
    validate(&plain).expect("validates");
    assert!(!functions(&plain).iter().any(|f| f == "encode_srgb"));
    let module =
        GpuTracer::compose_modules(&SHADER_IMPORTS, UPSCALE_WGSL, &["ENCODE_SRGB"], &[]).expect("composes encoding");
    validate(&module).expect("validates encoding");
    assert!(functions(&module).iter().any(|f| f == "encode_srgb"));
    for name in ["upscale", "blend_in"] {
        let entry = module.entry_points.iter().find(|e| e.name == name).expect(name);
        assert_eq!(entry.stage, naga::ShaderStage::Fragment);
    }
    // Group 0: colour texture, sampler, depth texture (src/render/upscale.rs).
    let mut bound: Vec<(u32, String)> = module
        .global_variables
        .iter()
        .filter_map(|(_, g)| {
            let b = g.binding.as_ref()?;
            assert_eq!(b.group, 0);
            let kind = match &module.types[g.ty].inner {
                naga::TypeInner::Image { class, .. } => match class {
                    naga::ImageClass::Depth { .. } => "depth",
                    _ => "color",
                },
                naga::TypeInner::Sampler { comparison: false } => "sampler",
                other => panic!("unexpected binding {other:?}"),
            };
            Some((b.binding, kind.to_string()))
        })
        .collect();
    bound.sort();
    assert_eq!(
        bound,
        [
            (0, "color".to_string()),
            (1, "sampler".to_string()),
            (2, "depth".to_string())
        ]
    );
}
