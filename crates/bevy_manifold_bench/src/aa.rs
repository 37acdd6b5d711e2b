//! `bench aa`: what cone tracing (`ManifoldFootprint`, CPU twin
//! `TraceSettings::footprint`) and accumulating jittered samples while
//! the view is still (`ManifoldAccumulation`, CPU twin
//! `trace::accumulate`) buy, against a reference of 16 samples per pixel
//! (the trace at 4x the size, box-filtered over each pixel), per space at
//! 8 and 16 levels: PSNR of the plain trace, of the cone trace, and of 4,
//! 8 and 16 accumulated samples. And flicker: the mean frame-to-frame
//! change of each pixel while the camera moves slowly forward, for the
//! plain trace, the cone trace and the 16-sample reference; what a trace
//! adds over the reference is aliasing. All on the CPU f64 reference (the
//! pass matches it: tests/pass.rs); then what each costs in the pass.

use crate::pass::frame_ms;
use bevy_manifold::prelude::*;
use bevy_manifold::render::offscreen;
use bevy_manifold::trace::accumulate;
use bevy_manifold_test_support::compare::{ConeComparison, compare_cones, psnr_of as psnr};

/// What anti-aliasing costs in the pass (a headless Bevy app, 320x180,
/// the default scene, 8 levels, ms a frame, best of `runs`): the plain
/// pass; cone tracing (`ManifoldFootprint`, every frame); accumulating
/// (256 samples wanted, so every frame traces, blends and copies: what a
/// moving view pays); and converged (2 samples, long in: no trace, one
/// copy).
fn pass_cost(runs: u32) -> Result<(), String> {
    println!("\nthe pass, 320x180, default scene, 8 levels, ms a frame (best of {runs}):");
    println!(
        "{:<22} {:>8} {:>8} {:>13} {:>10}",
        "space", "plain", "cone", "accumulating", "converged"
    );
    for name in ["torus", "seifert-weber", "mirrored-dodecahedron"] {
        let space = catalog::resolve(name)?;
        let scene = Scene::default_for(&space);
        let mut ms = [0.0; 4];
        for (slot, (cone, samples)) in [(false, None), (true, None), (false, Some(256)), (false, Some(2))]
            .into_iter()
            .enumerate()
        {
            let mut app = offscreen::app(true);
            let image = offscreen::target(&mut app, 320, 180);
            let camera = ManifoldCamera {
                levels: 8,
                ..ManifoldCamera::default()
            };
            let (_, id) = offscreen::spawn_view(&mut app, &space, &scene, &image, camera);
            if let Some(samples) = samples {
                app.world_mut().entity_mut(id).insert(ManifoldAccumulation { samples });
            }
            if cone {
                app.world_mut().entity_mut(id).insert(ManifoldFootprint);
            }
            ms[slot] = frame_ms(&mut app, &image, runs)?;
        }
        println!(
            "{name:<22} {:>8.1} {:>8.1} {:>13.1} {:>10.1}",
            ms[0], ms[1], ms[2], ms[3]
        );
    }
    Ok(())
}

/// Prints the PSNR and flicker table for every catalog space.
///
/// # Errors
/// A space that does not build.
pub fn run(width: u32, height: u32, frames: u32) -> Result<(), String> {
    println!(
        "Anti-aliasing, {width}x{height}, CPU f64; PSNR (dB) against 16 samples per pixel (4x4 box), flicker = mean frame-to-frame change (sRGB bytes) over {frames} frames moving forward 0.002 a frame"
    );
    println!(
        "{:<22} {:>6} {:>8} {:>8} {:>8} {:>8} {:>8} {:>10} {:>10} {:>10}",
        "space", "levels", "1 spp", "cone", "4", "8", "16", "flick 1", "flick cone", "flick 16"
    );
    for name in catalog::NAMES {
        let space = catalog::resolve(name)?;
        let scene = Scene::default_for(&space);
        for levels in [8, 16] {
            let settings = TraceSettings {
                width,
                height,
                levels,
                ..TraceSettings::default()
            };
            let ConeComparison {
                plain,
                cone,
                reference,
                flicker: [f_plain, f_cone, f_ref],
            } = compare_cones(&space, &scene, &settings, 4, (0.002, frames));
            let acc: Vec<f64> = [4, 8, 16]
                .iter()
                .map(|&n| psnr(&accumulate::<f64>(&space, &scene, &settings, n), &reference))
                .collect();
            println!(
                "{name:<22} {levels:>6} {:>8.2} {:>8.2} {:>8.2} {:>8.2} {:>8.2} {f_plain:>10.2} {f_cone:>10.2} {f_ref:>10.2}",
                psnr(&plain, &reference),
                psnr(&cone, &reference),
                acc[0],
                acc[1],
                acc[2]
            );
        }
    }
    pass_cost(3)
}
