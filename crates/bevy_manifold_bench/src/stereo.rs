//! `bench stereo`: what a headset asks of the tracer. Two eyes, each with
//! its own off-centre frustum (a Vive Pro's left eye and its mirror: 49.8
//! and 40.1 degrees out and in, 48.1 down, 44.1 up) and its own placement,
//! 64 mm apart at 4 m of the room per unit of the space
//! (`placement::tracked::head_and_eyes`, as the XR plugin places them),
//! traced one after the other by the headless GPU tracer: the frame time
//! is both eyes'. At the paper's 2x1512x1680 and at per-eye render scales,
//! in each catalog space with the paper's scene (edges, Suzanne on the
//! head, the hands), 1, 3 and 8 levels; the CPU f32 reference's rays/s
//! on the same scene in the same run, for scale.

use crate::{best_ms, trace_ms};
use bevy::math::{Quat, Vec3};
use bevy_manifold::placement::tracked;
use bevy_manifold::prelude::*;
use bevy_manifold::trace::{Frustum, PaperOptions};
use bevy_manifold_gpu::GpuTracer;

/// The left eye's field of view (radians: left, right, down, up).
const LEFT_FOV: [f64; 4] = [-0.87, 0.70, -0.84, 0.77];
/// The paper's per-eye resolution (HTC Vive Pro).
const EYE: (u32, u32) = (1512, 1680);

/// The two eyes' scenes: the paper's scene seen from each eye.
fn eyes(space: &Space) -> [Scene; 2] {
    let scene = Scene::paper(space, &PaperOptions::default());
    let room = [
        (Vec3::new(-0.032, 0.0, 0.0), Quat::IDENTITY),
        (Vec3::new(0.032, 0.0, 0.0), Quat::IDENTITY),
    ];
    let (_, placed) = tracked::head_and_eyes(space.geometry(), scene.camera.isometry, room, 4.0);
    let [l, r, d, u] = LEFT_FOV;
    let fov = [Frustum::from_angles(l, r, d, u), Frustum::from_angles(-r, -l, d, u)];
    [0, 1].map(|i| {
        let mut eye = scene.clone();
        eye.camera.isometry = placed[i];
        eye.camera.frustum = Some(fov[i]);
        eye
    })
}

/// Prints the table: per space and levels, both eyes' trace time at each
/// per-eye scale in `scales` (1 is 1512x1680 an eye), as the device times
/// it ([`GpuTracer::time_trace`]: its timestamps where it has them, else
/// the wall time to idle; the median of `runs` traces of one upload), the
/// same with cone tracing (`footprint`) and the whole headless render
/// (packing, upload, trace, read-back) at the first scale, and the CPU
/// reference's rays/s at the last scale.
///
/// # Errors
/// No GPU adapter, or a space that does not build.
pub fn run(scales: &[f64], runs: u32, only: &str) -> Result<(), String> {
    let mut tracer = GpuTracer::new().map_err(|e| e.to_string())?;
    println!(
        "Stereo: both eyes, off-centre frusta, paper scene; GPU on {}, CPU f32 reference on {} threads; median of {runs} traces; ms for both eyes",
        tracer.adapter_name(),
        rayon::current_num_threads()
    );
    let sizes: Vec<(f64, u32, u32)> = scales
        .iter()
        .map(|&s| {
            let px = |n: u32| ((f64::from(n) * s).round() as u32).max(1);
            (s, px(EYE.0), px(EYE.1))
        })
        .collect();
    let &(_, first_w, first_h) = sizes.first().ok_or("no scale")?;
    let &(_, last_w, last_h) = sizes.last().ok_or("no scale")?;
    print!("{:<22} {:>6}", "space", "levels");
    for (s, w, h) in &sizes {
        print!(" {:>18}", format!("2x{w}x{h} ({s})"));
    }
    println!(" {:>18} {:>14} {:>12}", "cone (first)", "render (first)", "CPU Mrays/s");
    for name in catalog::NAMES.iter().filter(|n| n.contains(only)) {
        let space = catalog::resolve(name)?;
        let eyes = eyes(&space);
        for levels in [1, 3, 8] {
            print!("{name:<22} {levels:>6}");
            let at = |width, height, footprint| TraceSettings {
                width,
                height,
                levels,
                footprint,
                ..TraceSettings::default()
            };
            let mut both = |settings: &TraceSettings| -> Result<f64, String> {
                let mut ms = 0.0;
                for eye in &eyes {
                    ms += trace_ms(&mut tracer, &space, eye, settings, runs)?;
                }
                Ok(ms)
            };
            for &(_, width, height) in &sizes {
                let ms = both(&at(width, height, false))?;
                print!(" {:>12.2} ({:>3.0}fps)", ms, 1e3 / ms);
            }
            let cone = both(&at(first_w, first_h, true))?;
            print!(" {:>12.2} ({:>3.0}fps)", cone, 1e3 / cone);
            let settings = at(first_w, first_h, false);
            let whole = best_ms(1, || {
                for eye in &eyes {
                    tracer.render(&space, eye, &settings).map_err(|e| e.to_string())?;
                }
                Ok(())
            })?;
            print!(" {whole:>14.1}");
            let settings = at(last_w, last_h, false);
            let ms = best_ms(1, || Ok(render::<f32>(&space, &eyes[0], &settings)))?;
            println!(" {:>12.2}", f64::from(last_w * last_h) / ms / 1e3);
        }
    }
    let clock = if tracer.has_timestamps() { "device" } else { "wall" };
    println!("(trace times by the {clock} clock)");
    Ok(())
}
