//! `bench cells`: what exact cell ids cost. On the CPU, the
//! exact product per face crossing against the `f64` matrix product it
//! replaces, the table's growth and recentring; on the GPU, the frame time
//! with the table of exact ids (`CELLS_TABLE`) against the hashed ids it
//! replaces (`CELLS_HASHED`), in one run, and the share of hit pixels the
//! table covers at 8 and 16 levels.

use crate::best_ms;
use bevy_manifold::prelude::*;
use bevy_manifold::space::cell_table::{CellTable, DEFAULT_TABLE_CELLS};
use bevy_manifold::space::cells::{CellId, CellScheme};
use bevy_manifold_gpu::{GpuCellScheme, GpuTracer, TraceDefs};
use glam::DMat4;
use std::time::Instant;

const SPACES: [&str; 2] = ["seifert-weber", "mirrored-dodecahedron"];

/// Prints the CPU costs, then the GPU frame times and coverage.
///
/// # Errors
/// No GPU, or a render that fails.
pub fn run(width: u32, height: u32, runs: u32) -> Result<(), String> {
    println!("Exact cell ids, CPU (one core), best of {runs}");
    println!(
        "{:<22} {:>12} {:>12} {:>8} {:>7} {:>10} {:>12}",
        "space", "exact ns/x", "f64 ns/x", "cells", "radius", "grow ms", "recentre ms"
    );
    for name in SPACES {
        let space = catalog::resolve(name)?;
        let CellScheme::Exact(exact) = space.cells() else {
            return Err(format!("{name} has no exact ids"));
        };
        let n = space.faces().len();
        // A walk of 64 crossings from the origin copy, repeated: the
        // distances a ray and a game reach.
        let word: Vec<usize> = (0..64).map(|k| (k * 7 + k / 5) % n).collect();
        let reps = 2000;
        let exact_ns = best_ms(runs, || {
            for _ in 0..reps {
                let mut c = space.origin_cell();
                for &f in &word {
                    c = space.cross_cell(&c, f);
                }
                std::hint::black_box(space.cell_id_of(&c));
            }
            Ok(())
        })? * 1e6
            / f64::from(reps * 64);
        let float_ns = best_ms(runs, || {
            for _ in 0..reps {
                let mut m = DMat4::IDENTITY;
                for &f in &word {
                    m = bevy_manifold::geometry::isometry::orthonormalize(space.geometry(), m * space.crossing(f));
                }
                std::hint::black_box(m);
            }
            Ok(())
        })? * 1e6
            / f64::from(reps * 64);
        let t = Instant::now();
        let table = CellTable::grow(&exact.group, DEFAULT_TABLE_CELLS);
        let grow = t.elapsed().as_secs_f64() * 1e3;
        let far = match space.cell_of_word(&word[..20]) {
            bevy_manifold::space::element::CellElement::Exact(e) => e,
            _ => return Err("not exact".into()),
        };
        let recentre = best_ms(runs, || Ok(table.ids_around(&exact.group, &far)))?;
        println!(
            "{name:<22} {exact_ns:>12.0} {float_ns:>12.0} {:>8} {:>7} {grow:>10.0} {recentre:>12.1}",
            table.len(),
            table.radius()
        );
    }
    let mut tracer = GpuTracer::new().map_err(|e| e.to_string())?;
    println!();
    println!(
        "GPU frame time (ms), {width}x{height}, paper scene with per-cell colour, no fog, best of {runs}, on {}",
        tracer.adapter_name()
    );
    println!(
        "{:<22} {:>6} {:>12} {:>12} {:>8} {:>16}",
        "space", "levels", "table ms", "hashed ms", "ratio", "hits in table"
    );
    for name in SPACES {
        let space = catalog::resolve(name)?;
        let scene = Scene::default_for(&space);
        for levels in [8, 16] {
            let settings = TraceSettings {
                width,
                height,
                levels,
                cell_colors: true,
                ..TraceSettings::default()
            };
            let defs = TraceDefs::for_scene(&space, &scene, true);
            let hashed = TraceDefs {
                cells: GpuCellScheme::Hashed,
                ..defs
            };
            let mut image = None;
            let table = best_ms(runs, || {
                image = Some(
                    tracer
                        .render_with(&space, &scene, &settings, defs)
                        .map_err(|e| e.to_string())?,
                );
                Ok(())
            })?;
            let hashed_ms = best_ms(runs, || {
                tracer
                    .render_with(&space, &scene, &settings, hashed)
                    .map_err(|e| e.to_string())
            })?;
            let image = image.ok_or("no image")?;
            let hits = image.pixels.iter().filter(|p| p.object != 0).count();
            let inside = image
                .pixels
                .iter()
                .filter(|p| p.object != 0 && p.cell != CellId::BEYOND_TABLE)
                .count();
            println!(
                "{name:<22} {levels:>6} {table:>12.1} {hashed_ms:>12.1} {:>8.3} {:>15.1}%",
                table / hashed_ms,
                100.0 * inside as f64 / hits.max(1) as f64
            );
        }
    }
    Ok(())
}
