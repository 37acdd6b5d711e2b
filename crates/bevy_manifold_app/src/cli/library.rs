//! `space import` and `space library`: spaces from their generators.

use bevy_manifold::prelude::*;
use bevy_manifold::space::{Generators, generators::GeneratorError, library};
use glam::DVec4;
use std::path::Path;

/// Builds the Dirichlet domain of a generator file and writes the space.
pub fn import(file: &Path, out: Option<&Path>, basepoint: Option<&[f64]>, manifold: bool) -> Result<(), String> {
    let mut gens = Generators::load(file).map_err(|e| e.to_string())?;
    let named = |e: GeneratorError| format!("{}: {e}", file.display());
    if let Some(p) = basepoint {
        let [x, y, z, w] = p else {
            return Err(format!("--basepoint takes four numbers x,y,z,w, got {}", p.len()));
        };
        // Lifted onto the model first (the user need not normalise); in H3
        // only a time-like vector lifts. The check is the generators' own.
        let point = DVec4::new(*x, *y, *z, *w);
        let g = gens.geometry;
        let lifts = g != Geometry::Hyperbolic || g.form::<f64>(point, point) < 0.0;
        let lifted = if lifts { g.normalize_point::<f64>(point) } else { point };
        // The error names the point as the user wrote it.
        gens.set_basepoint(Some(lifted.to_array())).map_err(|_| {
            named(GeneratorError::BadBasepoint {
                point: point.to_array(),
                geometry: g.name(),
            })
        })?;
    }
    gens.manifold |= manifold;
    let start = std::time::Instant::now();
    let (space, moved) = gens.dirichlet_domain_and_basepoint().map_err(named)?;
    if let Some(p) = moved {
        eprintln!(
            "{}: an element fixes the origin, so the domain is built about the generic point ({:.6}, {:.6}, {:.6}, {:.6}), the chart origin; the space keeps that move as its file frame (\"file_frame\"), through which its pairings are the file's own elements (--basepoint picks another point)",
            file.display(),
            p.x,
            p.y,
            p.z,
            p.w
        );
    }
    eprintln!(
        "{}: {} geometry, {} faces, volume {:.9}, group order {}, built in {:.3} s",
        space.name(),
        space.geometry(),
        space.faces().len(),
        space.volume(),
        space.group_order().map_or("infinite".into(), |n| n.to_string()),
        start.elapsed().as_secs_f64()
    );
    match out {
        Some(path) => space.save(path).map_err(|e| format!("{}: {e}", path.display())),
        None => {
            println!("{}", space.to_json());
            Ok(())
        }
    }
}

/// Lists the library, or writes its generator files into `out`.
pub fn library(out: Option<&Path>) -> Result<(), String> {
    if let Some(dir) = out {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    for name in library::names() {
        let gens = library::by_name(&name).ok_or_else(|| format!("library space {name} is missing"))?;
        let start = std::time::Instant::now();
        let space = gens
            .dirichlet_domain()
            .map_err(|e| format!("library space {name}: {e}"))?;
        let ms = start.elapsed().as_secs_f64() * 1e3;
        match out {
            Some(dir) => {
                let path = dir.join(format!("{name}.gen"));
                std::fs::write(&path, gens.to_gen(&library::header(&name)))
                    .map_err(|e| format!("{}: {e}", path.display()))?;
                println!("{}", path.display());
            }
            None => println!(
                "{name:<22} {:<10} {:>3} faces  volume {:<12.9} group {:<9} H1 {:<14} built in {ms:.1} ms",
                space.geometry().name(),
                space.faces().len(),
                space.volume(),
                space.group_order().map_or("infinite".into(), |n| n.to_string()),
                space
                    .first_homology()
                    .map_or("too large to compute".into(), |h| h.to_string())
            ),
        }
    }
    Ok(())
}
