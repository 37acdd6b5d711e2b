//! Exact cell ids on the GPU (`CELLS_TABLE`: the table of cells around the
//! camera, `bevy_manifold_core::space::cell_table`) against the CPU f64
//! reference, which multiplies exact golden elements along each ray
//! (`space::exact`): per-cell colour on, fog off, 8 levels, in the
//! Seifert-Weber space and the mirrored dodecahedron, the camera in the
//! origin copy and 20 crossings away.

use bevy_manifold_core::prelude::*;
use bevy_manifold_core::space::cells::{CellId, CellTint};
use bevy_manifold_core::trace::TraceImage;
use bevy_manifold_test_support::tracer;
use glam::{DMat4, DVec3, DVec4};

/// Most of the pixels the GPU may mark beyond its table, at 8 levels:
/// measured 0 of 16,384 (SW, camera at home), with margin for the far
/// camera's view; the note gives the figures per space.
const MAX_BEYOND: f64 = 0.6;

/// A ball at the domain's centre (every copy shows its own, well inside
/// its cell, so the cell of a hit is the cell of the geodesic, not of a
/// rounding) and a light; the camera a little off centre, looking along a
/// slanted direction.
fn scene(space: &Space, cell: Vec<usize>) -> Scene {
    let g = space.geometry();
    let r = space.inradius();
    let mut scene = Scene::empty();
    scene.camera.isometry = bevy_manifold_core::geometry::isometry::translation(g, DVec3::new(0.1, 0.05, 0.3) * r)
        * DMat4::from_rotation_y(0.4)
        * DMat4::from_rotation_x(0.2);
    scene.camera.fov_y_degrees = 90.0;
    scene.camera.cell = cell;
    scene.balls.push(Ball {
        center: DVec4::W,
        radius: 0.6 * r,
        color: [0.9, 0.9, 0.9],
        glow: 0.0,
        pbr: None,
    });
    scene.lights.push(Light {
        position: g.normalize_point::<f64>(DVec4::new(0.0, 0.4 * r, 0.5 * r, 1.0)),
        intensity: 4.0,
        color: [1.0; 3],
        range: None,
        radius: 0.0,
        spot: None,
    });
    scene
}

/// Twenty crossings that lead away from the origin copy (each one out of
/// the face the camera's cell centre is most beyond... simply a fixed
/// word checked to end more than 6 away).
fn far_word(space: &Space) -> Vec<usize> {
    let word: Vec<usize> = (0..20).map(|k| (k * 5 + k / 3) % space.faces().len()).collect();
    let d = space.geometry().distance::<f64>(
        DVec4::W,
        space
            .geometry()
            .normalize_point::<f64>(space.cell_matrix(&space.cell_of_word(&word)) * DVec4::W),
    );
    assert!(d > 6.0, "{}: the far camera is only {d} away", space.name());
    word
}

struct Compared {
    hits: usize,
    beyond: usize,
    id_mismatch: usize,
    object_mismatch: usize,
}

fn compare(gpu: &TraceImage, cpu: &TraceImage) -> Compared {
    let mut c = Compared {
        hits: 0,
        beyond: 0,
        id_mismatch: 0,
        object_mismatch: 0,
    };
    for (p, q) in gpu.pixels.iter().zip(&cpu.pixels) {
        assert!(!q.cell.is_far(), "the CPU reference is exact everywhere: {:?}", q.cell);
        if q.object == 0 {
            continue;
        }
        c.hits += 1;
        if p.object != q.object {
            c.object_mismatch += 1;
        } else if p.cell == CellId::BEYOND_TABLE {
            c.beyond += 1;
        } else if p.cell != q.cell {
            c.id_mismatch += 1;
        }
    }
    c
}

fn the_gpu_gives_the_cpu_references_exact_ids_near_and_far() {
    let mut gpu = tracer();
    for name in ["seifert-weber", "mirrored-dodecahedron"] {
        let space = catalog::by_name(name).unwrap();
        for (label, cell) in [("home", Vec::new()), ("20 crossings away", far_word(&space))] {
            let scene = scene(&space, cell);
            let settings = TraceSettings {
                width: 128,
                height: 128,
                levels: 8,
                cell_colors: true,
                ..TraceSettings::default()
            };
            let g = gpu
                .render(&space, &scene, &settings)
                .unwrap_or_else(|e| panic!("{name}: {e}"));
            let c = render::<f64>(&space, &scene, &settings);
            let r = compare(&g, &c);
            let n = (settings.width * settings.height) as usize;
            eprintln!(
                "{name:<22} {label:<18}: {} hit pixels of {n}; ids differ on {}, beyond the table {} ({:.2}%), objects differ {}",
                r.hits,
                r.id_mismatch,
                r.beyond,
                100.0 * r.beyond as f64 / r.hits.max(1) as f64,
                r.object_mismatch
            );
            assert!(r.hits > n / 4, "{name} {label}: only {} hits", r.hits);
            assert_eq!(r.id_mismatch, 0, "{name} {label}: exact ids differ");
            assert!(
                r.object_mismatch * 200 < r.hits,
                "{name} {label}: {} objects differ",
                r.object_mismatch
            );
            assert!(
                (r.beyond as f64) <= MAX_BEYOND * r.hits as f64,
                "{name} {label}: {} of {} hits beyond the table",
                r.beyond,
                r.hits
            );
        }
    }
}

/// Highlight one cell and the on/off pattern with the camera 20 crossings
/// away (more than 6 from the origin copy): the GPU lights the same pixels
/// as the CPU reference.
fn highlight_and_pattern_work_far_from_the_origin_copy() {
    let mut gpu = tracer();
    for name in ["seifert-weber", "mirrored-dodecahedron"] {
        let space = catalog::by_name(name).unwrap();
        let scene = scene(&space, far_word(&space));
        let base = TraceSettings {
            width: 96,
            height: 96,
            levels: 8,
            cell_colors: true,
            ..TraceSettings::default()
        };
        // The copy to highlight: a neighbour's, seen in the picture (the
        // most common hit cell other than the camera's own).
        let by_cell = render::<f64>(&space, &scene, &base);
        let mut counts = std::collections::HashMap::new();
        for p in by_cell.pixels.iter().filter(|p| p.object != 0) {
            *counts.entry(p.cell).or_insert(0usize) += 1;
        }
        let mut cells: Vec<(CellId, usize)> = counts.into_iter().collect();
        cells.sort_by_key(|(id, n)| (std::cmp::Reverse(*n), id.0));
        let target = cells[1].0;
        for tint in [CellTint::Highlight(target), CellTint::Pattern { on_fraction: 0.5 }] {
            let settings = TraceSettings {
                cell_tint: tint,
                ..base.clone()
            };
            let g = gpu.render(&space, &scene, &settings).unwrap();
            let c = render::<f64>(&space, &scene, &settings);
            let lit = |img: &TraceImage, p: usize| {
                let px = &img.pixels[p];
                px.object != 0 && tint.tint(px.cell) != [1.0; 3]
            };
            let mut both = 0;
            let mut differ = 0;
            for p in 0..g.pixels.len() {
                if g.pixels[p].object != c.pixels[p].object || g.pixels[p].cell == CellId::BEYOND_TABLE {
                    continue;
                }
                both += usize::from(lit(&g, p) && lit(&c, p));
                differ += usize::from(lit(&g, p) != lit(&c, p));
            }
            eprintln!("{name:<22} {tint:?}: {both} pixels tinted on both, {differ} on one only");
            assert!(both > 20, "{name} {tint:?}: only {both} tinted pixels");
            assert_eq!(differ, 0, "{name} {tint:?}");
        }
    }
}

/// The cell rules (hidden cells, walls) drawn by the GPU as by the CPU
/// f64 reference, near and far: the same objects (walls included) on the
/// same pixels, and colours within 2/255.
fn cell_rules_draw_the_same_on_the_gpu() {
    use bevy_manifold_core::space::rule::{CellRule, OnOff, WALL_OBJECT, Walls};
    let rule = CellRule {
        hidden: Some(OnOff {
            on_fraction: 0.5,
            seed: 4,
        }),
        walls: Some(Walls { density: 0.35, seed: 8 }),
    };
    let mut gpu = tracer();
    for name in ["torus", "poincare", "seifert-weber", "mirrored-dodecahedron"] {
        let space = catalog::by_name(name).unwrap();
        let far = if space.geometry() == Geometry::Hyperbolic {
            far_word(&space)
        } else {
            vec![0, 1, 2]
        };
        for cell in [Vec::new(), far] {
            let scene = scene(&space, cell);
            let settings = TraceSettings {
                width: 96,
                height: 96,
                levels: 8,
                cell_rule: rule,
                ..TraceSettings::default()
            };
            let g = gpu.render(&space, &scene, &settings).unwrap();
            let c = render::<f64>(&space, &scene, &settings);
            // Where a ray would leave the GPU's table of exact ids the
            // rules are unknown there: it stops grey, the cell says so.
            // Everywhere else the two agree.
            let known: Vec<usize> = (0..g.pixels.len())
                .filter(|&k| g.pixels[k].cell != CellId::BEYOND_TABLE)
                .collect();
            let pick = |img: &TraceImage| TraceImage {
                width: known.len() as u32,
                height: 1,
                pixels: known.iter().map(|&k| img.pixels[k]).collect(),
            };
            let (ids, colours) = bevy_manifold_test_support::agreement(&pick(&g), &pick(&c));
            let walls = c.pixels.iter().filter(|p| p.object == WALL_OBJECT).count();
            let gpu_walls = g.pixels.iter().filter(|p| p.object == WALL_OBJECT).count();
            let unknown = g.pixels.len() - known.len();
            eprintln!(
                "{name:<22} rules: ids {:.2}%, colours {:.2}% where known; {unknown} pixels past the table; wall pixels CPU {walls} GPU {gpu_walls}",
                100.0 * ids,
                100.0 * colours
            );
            assert!(unknown * 2 < g.pixels.len(), "{name}: {unknown} pixels past the table");
            assert!(walls > 300, "{name}: {walls} wall pixels");
            assert!(ids >= 0.99 && colours >= 0.99, "{name}: ids {ids}, colours {colours}");
        }
    }
}

/// Before its table of cells is grown (the render pass grows it on a
/// task), a golden space packs one cell, the camera's, with its exact id
/// and every neighbour outside: grey, never wrong. Once grown, the whole
/// table.
fn a_space_packs_one_exact_cell_until_its_table_is_grown() {
    use bevy_manifold_core::space::cell_table::OUTSIDE;
    use bevy_manifold_core::space::cells::CellScheme;
    use bevy_manifold_gpu::GpuSpace;
    let space = catalog::seifert_weber();
    let CellScheme::Exact(exact) = space.cells() else {
        panic!()
    };
    assert!(exact.grown_table().is_none());
    let camera = space.cell_of_word(&[3, 7, 1]);
    let mut packed = GpuSpace::pack(&space);
    assert!(packed.table_pending(&space));
    packed.centre_on(&space, &camera);
    assert_eq!(packed.index_of(space.cell_id_of(&camera)), Some(0));
    assert!(packed.cell_table[..12].iter().all(|&n| n == OUTSIDE));
    let table = exact.table();
    let mut grown = GpuSpace::pack(&space);
    assert!(!grown.table_pending(&space));
    grown.centre_on(&space, &camera);
    assert_eq!(grown.cell_table.len(), table.len() * 14);
    // The camera's neighbour through face 0 is in the table, with its id.
    let next = space.cross_cell(&camera, 0);
    let k = grown.cell_table[space.faces()[0].partner];
    assert_eq!(grown.index_of(space.cell_id_of(&next)), Some(k));
}

bevy_manifold_test_support::test_main! {
    cpu: [a_space_packs_one_exact_cell_until_its_table_is_grown],
    gpu: [
        cell_rules_draw_the_same_on_the_gpu,
        the_gpu_gives_the_cpu_references_exact_ids_near_and_far,
        highlight_and_pattern_work_far_from_the_origin_copy,
    ],
}
