//! `bench product`: the product spaces (H2xR, S2xR) against Seifert-Weber's
//! space at the same size and levels: the GPU frame time of the product
//! tracer (`shaders/product.wgsl`) over the main tracer's in
//! Seifert-Weber (the goal: within 1.5x), and the CPU f64 reference's.
//! Each product space shows its default scene
//! ([`ProductScene::default_for`]: three balls, fog, lit from the eye) and
//! its lit scene ([`ProductScene::lit_for`]: two point lights, 32 images
//! of each, shadows), with the prism's edges drawn as tubes
//! ([`ProductEdges::default`]) and with meshes
//! ([`ProductScene::furnished_for`]: the airplane and a box, 156
//! triangles), Seifert-Weber its own (edges, a ball, a light).

use crate::{best_ms, trace_ms};
use bevy_manifold::prelude::*;
use bevy_manifold::space::product::ProductSpace;
use bevy_manifold::trace::product::{ProductEdges, ProductScene, render as render_product};
use bevy_manifold_gpu::GpuTracer;

/// The product spaces timed, as the CLI names them.
fn spaces() -> Vec<(&'static str, ProductSpace)> {
    vec![
        ("s2xs1", ProductSpace::s2_x_s1(2.0)),
        ("twisted-s2xs1", ProductSpace::twisted_s2_x_s1(2.0, 3)),
        ("genus2xs1", ProductSpace::genus_two_x_s1(2.0)),
        ("twisted-genus2xs1", ProductSpace::twisted_genus_two_x_s1(2.0, 3)),
        ("mirrored-prism", ProductSpace::mirrored_prism(5, 2.0)),
    ]
}

/// Runs the comparison and prints its table.
///
/// # Errors
/// No GPU, or a trace that fails.
pub fn run(width: u32, height: u32, levels: u32, runs: u32) -> Result<(), String> {
    let mut tracer = GpuTracer::new().map_err(|e| e.to_string())?;
    println!(
        "The product spaces against Seifert-Weber, {width}x{height}, {levels} levels; GPU on {} (the trace alone, median of {runs}), CPU f64 reference on {} threads (best of {runs}); ms",
        tracer.adapter_name(),
        rayon::current_num_threads()
    );
    println!(
        "{:<18} {:>9} {:>8} {:>9} {:>7} {:>10} {:>9} {:>8} {:>10} {:>9} {:>9}",
        "space", "GPU", "GPU/SW", "CPU f64", "hits", "crossings", "GPU lit", "lit/SW", "no shadows", "edges", "meshes"
    );
    let sw = catalog::seifert_weber();
    let settings = TraceSettings {
        width,
        height,
        levels,
        ..TraceSettings::default()
    };
    let sw_scene = Scene::default_for(&sw);
    let sw_ms = trace_ms(&mut tracer, &sw, &sw_scene, &settings, runs)?;
    let sw_image = bevy_manifold::trace::render::<f64>(&sw, &sw_scene, &settings);
    let sw_cpu = best_ms(runs, || {
        Ok(bevy_manifold::trace::render::<f64>(&sw, &sw_scene, &settings))
    })?;
    let sw_hits = sw_image.pixels.iter().filter(|p| p.object != 0).count();
    println!(
        "{:<18} {sw_ms:>9.1} {:>7.2}x {sw_cpu:>9.1} {:>6.1}% {:>10.2}",
        "seifert-weber",
        1.0,
        100.0 * sw_hits as f64 / sw_image.pixels.len() as f64,
        sw_image.pixels.iter().map(|p| f64::from(p.levels)).sum::<f64>() / sw_image.pixels.len() as f64
    );
    let mut worst: f64 = 0.0;
    for (name, space) in spaces() {
        // The scene at the run's levels, and its GPU frame time.
        let mut timed = |mut scene: ProductScene| -> Result<(ProductScene, f64), String> {
            scene.view.max_crossings = levels as usize;
            let t = tracer
                .time_product(&space, &scene, (width, height), runs)
                .map_err(|e| e.to_string())?;
            Ok((scene, t.device_ms.unwrap_or(t.wall_ms)))
        };
        let (scene, gpu_ms) = timed(ProductScene::default_for(&space))?;
        let (lit, lit_ms) = timed(ProductScene::lit_for(&space))?;
        let mut unshadowed = lit;
        unshadowed.lighting.shadows = false;
        let (_, unshadowed_ms) = timed(unshadowed)?;
        let mut edged = ProductScene::default_for(&space);
        edged.edges = Some(ProductEdges::default());
        let (_, edges_ms) = timed(edged)?;
        let (_, meshes_ms) = timed(ProductScene::furnished_for(&space))?;
        let cpu = best_ms(runs, || Ok(render_product(&space, &scene, width, height)))?;
        let image = render_product(&space, &scene, width, height);
        let hits = image.iter().filter(|p| p.object != 0).count();
        let crossings = image.iter().map(|p| p.crossings as f64).sum::<f64>() / image.len() as f64;
        worst = worst.max(gpu_ms / sw_ms);
        println!(
            "{name:<18} {gpu_ms:>9.1} {:>7.2}x {cpu:>9.1} {:>6.1}% {crossings:>10.2} {lit_ms:>9.1} {:>7.2}x {unshadowed_ms:>10.1} {edges_ms:>9.1} {meshes_ms:>9.1}",
            gpu_ms / sw_ms,
            100.0 * hits as f64 / image.len() as f64,
            lit_ms / sw_ms
        );
    }
    println!("slowest product space / seifert-weber (GPU, lit from the eye): {worst:.2} x (goal: within 1.5x)");
    println!(
        "hits: pixels that see a ball (or an edge, in Seifert-Weber); crossings: faces crossed per pixel on the way to what it sees (0 where a product space's ray sees nothing); lit: the same view lit by two point lights, every image of each (32), with shadows (no shadows: the same without them); edges: the default view with the prism's edges drawn as tubes (S2 x S1 has none); meshes: the default view with the airplane and a box (156 triangles), lit from the eye"
    );
    Ok(())
}
