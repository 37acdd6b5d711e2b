//! `bench lights`: what the manifold's light costs, and how near its sum
//! comes to the brute-force one.
//!
//! 1. Frame time of the paper's scene per catalog space, GPU (device
//!    clock, median) and CPU f32 (best), with each light's copy in the
//!    domain only (the lighting before light images), with its images,
//!    and with its images and shadows; the ratios over the first.
//! 2. Run time against error per space: the paper's light with a fixed
//!    range (twice the inradius; S3: no cut-off, both arcs), its images
//!    kept at budgets 1 to 256, against the brute-force sum over the
//!    group's elements found by closing the face pairings under products
//!    (not the tracer's cover walk), at points all over the domain. The
//!    error is the largest gap, over the points, as a share of the
//!    nearest image's irradiance there; the time is the GPU's frame with
//!    that budget (shadows off). Writes `lights.csv` and `lights.png`.

use crate::plot::{Panel, Series, draw, pareto_front};
use crate::{best_ms, times_and_ratios, trace_ms};
use bevy_manifold::prelude::*;
use bevy_manifold_core::geometry::Geometry;
use bevy_manifold_core::trace::{FlatLight, image_irradiance, light_images};
use bevy_manifold_gpu::GpuTracer;
use glam::{DMat4, DVec4};
use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;

/// The budgets the error table walks.
const BUDGETS: [u32; 9] = [1, 2, 4, 8, 16, 32, 64, 128, 256];

/// Points of the domain the error is taken at.
const POINTS: usize = 300;

/// Runs both parts for the catalog spaces whose name holds `only`,
/// writing the CSV and plot into `out`.
///
/// # Errors
/// No GPU adapter, a space that does not build, or a file not written.
pub fn run(width: u32, height: u32, runs: u32, only: &str, out: &Path) -> Result<(), String> {
    let mut tracer = GpuTracer::new().map_err(|e| e.to_string())?;
    println!(
        "Light images and shadows, the paper's scene, {width}x{height}, 8 levels; GPU on {} (median of {runs}), CPU f32 on {} threads (best of {runs}); ms",
        tracer.adapter_name(),
        rayon::current_num_threads()
    );
    println!(
        "{:<24} {:>9} {:>9} {:>9} {:>7} {:>7} {:>9} {:>9} {:>9} {:>7} {:>7}",
        "space", "GPU copy", "images", "+shadow", "ratio", "ratio", "CPU copy", "images", "+shadow", "ratio", "ratio"
    );
    let settings = TraceSettings {
        width,
        height,
        levels: 8,
        ..TraceSettings::default()
    };
    let names: Vec<&str> = catalog::NAMES.iter().copied().filter(|n| n.contains(only)).collect();
    for name in &names {
        let space = catalog::resolve(name)?;
        let base = Scene::paper_default(&space);
        let mut gpu = [0.0; 3];
        let mut cpu = [0.0; 3];
        for (k, lighting) in [
            Lighting::DOMAIN_COPY,
            Lighting {
                shadows: false,
                ..Lighting::default()
            },
            Lighting {
                shadows: true,
                ..Lighting::default()
            },
        ]
        .into_iter()
        .enumerate()
        {
            let scene = Scene {
                lighting,
                ..base.clone()
            };
            gpu[k] = trace_ms(&mut tracer, &space, &scene, &settings, runs)?;
            cpu[k] = best_ms(runs, || Ok(render::<f32>(&space, &scene, &settings)))?;
        }
        println!("{name:<24} {} {}", times_and_ratios(gpu, 1), times_and_ratios(cpu, 1));
    }
    errors(&mut tracer, &names, &settings, runs, out)
}

/// Part 2: the error table, CSV and plot.
fn errors(
    tracer: &mut GpuTracer,
    names: &[&str],
    settings: &TraceSettings,
    runs: u32,
    out: &Path,
) -> Result<(), String> {
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    println!(
        "\nThe light sum against brute force: the paper's light, range 2 inradii (S3: none); error = the largest gap over {POINTS} points of the domain, as a share of the nearest image's irradiance there; GPU ms of the paper's scene at that budget, shadows off"
    );
    println!(
        "{:<24} {:>7} {:>7} {:>8} {:>12} {:>9}",
        "space", "budget", "images", "range", "max error", "GPU ms"
    );
    let mut csv = String::from("space,budget,images,range,max_error,gpu_ms\n");
    let mut panels = Vec::new();
    let mut all_points = Vec::new();
    let mut series = Vec::new();
    for (k, name) in names.iter().enumerate() {
        let space = catalog::resolve(name)?;
        let g = space.geometry();
        let scene = Scene::paper_default(&space);
        let Some(light) = scene.lights.first().cloned() else {
            continue;
        };
        let range = (g != Geometry::Spherical).then(|| 2.0 * space.inradius());
        let light = Light { range, ..light };
        // Every image within the range of a point of the domain lies
        // within range + circumradius of the origin, and its cell's
        // centre within that plus the light's own distance.
        let reach = range.map_or(std::f64::consts::TAU, |r| {
            r + space.circumradius() + g.distance::<f64>(DVec4::W, light.position)
        });
        let brute = brute_force_images(&space, light.position, reach);
        let points = domain_points(&space);
        let mut pts = Vec::new();
        for budget in BUDGETS {
            let lighting = Lighting {
                images: budget,
                shadows: false,
            };
            let images = light_images::<f64>(&space, std::slice::from_ref(&light), lighting);
            let cut = images.first().map_or(0.0, |l| {
                if l.inv_range_sq > 0.0 {
                    1.0 / l.inv_range_sq.sqrt()
                } else {
                    f64::INFINITY
                }
            });
            let mut worst = 0.0f64;
            for &x in &points {
                let (got, _) = sum(g, &images, x);
                let (want, nearest) = brute_sum(g, &light, &brute, x);
                if nearest > 0.0 {
                    worst = worst.max((got - want).abs() / nearest);
                }
            }
            let lit = Scene {
                lighting,
                lights: vec![light.clone()],
                ..scene.clone()
            };
            let ms = trace_ms(tracer, &space, &lit, settings, runs)?;
            println!(
                "{:<24} {:>7} {:>7} {:>8.3} {:>11.4}% {:>9.1}",
                name,
                budget,
                images.len(),
                cut,
                worst * 100.0,
                ms
            );
            let _ = writeln!(csv, "{name},{budget},{},{cut},{worst},{ms}", images.len());
            pts.push((ms, worst * 100.0));
        }
        all_points.extend(pts.iter().copied());
        series.push(Series {
            label: (*name).to_string(),
            color: crate::plot::PALETTE[k % crate::plot::PALETTE.len()],
            points: pts,
            line: true,
        });
    }
    panels.push(Panel {
        title: "Light images: GPU frame time against the error of the light sum".into(),
        x: "GPU ms (paper's scene, 8 levels)".into(),
        y: "max error, % of the nearest image".into(),
        series,
        front: pareto_front(&all_points),
    });
    let csv_path = out.join("lights.csv");
    std::fs::write(&csv_path, csv).map_err(|e| format!("{}: {e}", csv_path.display()))?;
    let png = out.join("lights.png");
    match draw(&png, &panels, 1, 1e-4) {
        Ok(()) => println!("\nwrote {} and {}", csv_path.display(), png.display()),
        Err(e) => println!("\nwrote {} ({e})", csv_path.display()),
    }
    Ok(())
}

/// The irradiance of the tracer's images at `x` (both arcs in S3).
fn sum(g: Geometry, images: &[FlatLight<f64>], x: DVec4) -> (f64, f64) {
    let mut total = 0.0;
    let mut nearest = 0.0f64;
    for l in images {
        let d = g.distance::<f64>(x, l.position);
        let mut arcs = vec![d];
        if g == Geometry::Spherical {
            arcs.push(std::f64::consts::TAU - d);
        }
        for s in arcs {
            let e = image_irradiance::<f64>(g, l, s, 0.0);
            total += e;
            nearest = nearest.max(e);
        }
    }
    (total, nearest)
}

/// The brute-force irradiance at `x` of `light` over the points `images`
/// of the group's orbit, written out: Bevy's window on the light's range,
/// over the area of the geodesic sphere; and the largest single term.
fn brute_sum(g: Geometry, light: &Light, images: &[DVec4], x: DVec4) -> (f64, f64) {
    let mut total = 0.0;
    let mut nearest = 0.0f64;
    for &p in images {
        let d = g.distance::<f64>(x, p);
        let mut arcs = vec![d];
        if g == Geometry::Spherical {
            arcs.push(std::f64::consts::TAU - d);
        }
        for s in arcs {
            let window = light
                .range
                .map_or(1.0, |r| (1.0 - (s / r).powi(4)).clamp(0.0, 1.0).powi(2));
            let e = light.intensity * window / g.sphere_area::<f64>(s).max(bevy_manifold_core::trace::MIN_AREA);
            total += e;
            nearest = nearest.max(e);
        }
    }
    (total, nearest)
}

/// The orbit of `p` under every group element whose cell's centre lies
/// within `radius` of the origin, found by closing the face pairings
/// under products, breadth first, pruned by that distance plus the
/// circumradius (the cells a geodesic to a near cell passes through come
/// that near).
fn brute_force_images(space: &Space, p: DVec4, radius: f64) -> Vec<DVec4> {
    let g = space.geometry();
    let o = DVec4::W;
    let gens: Vec<DMat4> = space.faces().iter().map(|f| f.pairing).collect();
    let prune = radius + space.circumradius();
    let mut seen: HashMap<[i64; 4], Vec<DVec4>> = HashMap::new();
    let quantum = space.inradius();
    let key = |c: DVec4| (c / quantum).to_array().map(|v| v.round() as i64);
    let mut frontier = vec![DMat4::IDENTITY];
    let mut out = Vec::new();
    seen.entry(key(o)).or_default().push(o);
    while !frontier.is_empty() && out.len() < 200_000 {
        let mut next = Vec::new();
        for m in frontier {
            let c = g.normalize_point::<f64>(m * o);
            if g.distance::<f64>(o, c) <= radius {
                out.push(g.normalize_point::<f64>(m * p));
            }
            for t in &gens {
                let n = m * *t;
                let c = g.normalize_point::<f64>(n * o);
                if g.distance::<f64>(o, c) > prune {
                    continue;
                }
                // Rounding to the key's grid may split one centre over two
                // keys: look in the neighbours too.
                let k = key(c);
                let mut known = false;
                'look: for dx in -1..=1 {
                    for dy in -1..=1 {
                        for dz in -1..=1 {
                            for dw in -1..=1 {
                                let kk = [k[0] + dx, k[1] + dy, k[2] + dz, k[3] + dw];
                                if seen
                                    .get(&kk)
                                    .is_some_and(|v| v.iter().any(|q| (*q - c).length() < 1e-6))
                                {
                                    known = true;
                                    break 'look;
                                }
                            }
                        }
                    }
                }
                if !known {
                    seen.entry(k).or_default().push(c);
                    next.push(n);
                }
            }
        }
        frontier = next;
    }
    out
}

/// Points spread over the domain: a golden spiral of directions at
/// radii out to the circumradius, kept where inside the domain.
fn domain_points(space: &Space) -> Vec<DVec4> {
    let g = space.geometry();
    let mut out = Vec::new();
    let mut i = 0u32;
    while out.len() < POINTS && i < 100 * POINTS as u32 {
        i += 1;
        let t = f64::from(i);
        let z = 1.0 - 2.0 * ((t * 0.618_034) % 1.0);
        let phi = t * 2.399_963;
        let rho = (1.0 - z * z).sqrt();
        let dir = glam::DVec3::new(rho * phi.cos(), rho * phi.sin(), z);
        let r = space.circumradius() * ((t * 0.754_877) % 1.0).cbrt();
        let x = bevy_manifold_core::geometry::isometry::translation(g, dir * r) * DVec4::W;
        if space.outside_face(x, 0.0).is_none() {
            out.push(g.normalize_point::<f64>(x));
        }
    }
    out
}
