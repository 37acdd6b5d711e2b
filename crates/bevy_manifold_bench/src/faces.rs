//! `bench faces`: frame time against the number of faces of the domain,
//! on spaces built from generators (lens, prism and binary polyhedral
//! spaces in S3, lattices and screw spaces in E3, Seifert-Weber and the
//! Weeks manifold in H3), and Seifert-Weber's own pairings as generators,
//! their Dirichlet domain about the centre (12 faces) and about a point off
//! it (52 faces): one manifold and one volume, 4.3 times the faces (and
//! more edges, so a larger default scene). The tracer tests every face at
//! every level, so a level costs in proportion to the face count; this
//! measures how much.

use crate::{best_ms, trace_ms};
use bevy_manifold::prelude::*;
use bevy_manifold_gpu::GpuTracer;
use bevy_manifold_test_support::stress;

/// The spaces, by geometry and face count.
pub(crate) const SPACES: [&str; 13] = [
    "lens-5-2",
    "quaternionic",
    "binary-tetrahedral",
    "prism-4",
    "poincare",
    "binary-octahedral",
    "torus",
    "torus-hexagonal",
    "hantzsche-wendt",
    "torus-bcc",
    "seifert-weber",
    "mirrored-dodecahedron",
    "weeks",
];

/// [`SPACES`] by name, then Seifert-Weber's Dirichlet domains from its
/// pairings as generators, about the centre and about a point off it
/// ([`stress::seifert_weber_about`]).
///
/// # Errors
/// A space that does not build.
pub(crate) fn spaces() -> Result<Vec<(String, Space)>, String> {
    let mut out = Vec::new();
    for name in SPACES {
        out.push((name.to_string(), catalog::resolve(name)?));
    }
    let (x, y, z) = stress::FIFTY_TWO_FACES;
    out.push((
        "seifert-weber/centre".into(),
        stress::seifert_weber_about(0.0, 0.0, 0.0)?,
    ));
    out.push(("seifert-weber/off-centre".into(), stress::seifert_weber_about(x, y, z)?));
    Ok(out)
}

/// GPU and CPU f32 frame times at 8 levels, with nothing to hit (the
/// transport alone) and with the default scene (a ball, the edges and a
/// light), per space whose name holds `only`.
///
/// # Errors
/// No GPU, or a space that does not build.
pub fn run(width: u32, height: u32, runs: u32, only: &str) -> Result<(), String> {
    let mut tracer = GpuTracer::new().map_err(|e| e.to_string())?;
    println!(
        "Frame time against face count, {width}x{height}, 8 levels; GPU on {} (the trace alone by the device's clock, median of {runs}), CPU f32 reference (best of {runs})",
        tracer.adapter_name()
    );
    println!(
        "{:<26} {:<10} {:>5} {:>12} {:>12} {:>12} {:>12} {:>14}",
        "space", "geometry", "faces", "GPU empty", "GPU scene", "CPU empty", "CPU scene", "GPU empty/face"
    );
    for (name, space) in spaces()? {
        if !name.contains(only) {
            continue;
        }
        let settings = TraceSettings {
            width,
            height,
            levels: 8,
            ..TraceSettings::default()
        };
        let scenes = [Scene::empty(), Scene::default_for(&space)];
        let mut gpu = [0.0; 2];
        let mut cpu = [0.0; 2];
        for (k, scene) in scenes.iter().enumerate() {
            gpu[k] = trace_ms(&mut tracer, &space, scene, &settings, runs)?;
            cpu[k] = best_ms(runs, || Ok(render::<f32>(&space, scene, &settings)))?;
        }
        let faces = space.faces().len();
        println!(
            "{name:<26} {:<10} {faces:>5} {:>12.2} {:>12.2} {:>12.1} {:>12.1} {:>14.3}",
            space.geometry().name(),
            gpu[0],
            gpu[1],
            cpu[0],
            cpu[1],
            gpu[0] / faces as f64
        );
    }
    Ok(())
}
