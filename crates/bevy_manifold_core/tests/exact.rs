//! Exact cell ids (`space::exact`, `space::element`), checked against the
//! group's relations (edge cycles and face pairs, from the polyhedron),
//! against geometry near the origin copy, and in the mirrored dodecahedron
//! against the right-angled Coxeter normal form (`bevy_manifold_test_support::coxeter`), an
//! independent solution of the same word problem.

use bevy_manifold_core::geometry::isometry;
use bevy_manifold_core::prelude::*;
use bevy_manifold_core::space::cells::CellId;
use bevy_manifold_core::space::element::CellElement;
use bevy_manifold_core::space::exact::ExactGroup;
use bevy_manifold_test_support::Rng;
use bevy_manifold_test_support::coxeter::RightAngledCoxeter;
use glam::{DMat4, DVec4};

fn random_word(rng: &mut Rng, faces: usize, max_len: usize) -> Vec<usize> {
    let len = rng.below(max_len + 1);
    (0..len).map(|_| rng.below(faces)).collect()
}

/// The crossings that walk `k` times around edge cycle `c`: its
/// transformation `T_{a_m} ... T_{a_1}` (`T_a` is the crossing of `a`'s
/// partner), to the cycle's order: a relation of the group.
fn cycle_relator(s: &Space, c: usize) -> Vec<usize> {
    let cycle = &s.edge_cycles()[c];
    let once: Vec<usize> = cycle.faces.iter().rev().map(|&a| s.faces()[a].partner).collect();
    once.repeat(cycle.order as usize)
}

/// A relator of `s` from its polyhedron: a face and its partner, an edge
/// cycle (rotated to start anywhere), or a short word and its inverse.
fn relator(rng: &mut Rng, s: &Space) -> Vec<usize> {
    let n = s.faces().len();
    match rng.below(3) {
        0 => {
            let a = rng.below(n);
            vec![a, s.faces()[a].partner]
        }
        1 => {
            let mut r = cycle_relator(s, rng.below(s.edge_cycles().len()));
            let k = rng.below(r.len());
            r.rotate_left(k);
            r
        }
        _ => {
            let u = random_word(rng, n, 6);
            let inverse = u.iter().rev().map(|&f| s.faces()[f].partner);
            u.iter().copied().chain(inverse).collect()
        }
    }
}

fn id(s: &Space, word: &[usize]) -> CellId {
    s.cell_id_of(&s.cell_of_word(word))
}

fn matrix(s: &Space, word: &[usize]) -> DMat4 {
    word.iter().fold(DMat4::IDENTITY, |m, &f| {
        isometry::orthonormalize(s.geometry(), m * s.crossing(f))
    })
}

#[test]
fn the_hyperbolic_catalog_spaces_are_exact_and_the_others_keep_their_schemes() {
    let kind = |name: &str| catalog::resolve(name).unwrap().cells().kind();
    assert_eq!(kind("seifert-weber"), "exact");
    assert_eq!(kind("mirrored-dodecahedron"), "exact");
    assert_eq!(kind("poincare"), "finite");
    assert_eq!(kind("torus"), "lattice");
    assert_eq!(kind("mirrored-cube"), "lattice");
    // The Weeks manifold's matrices live over a cubic field: not golden.
    assert_eq!(kind("weeks"), "hashed");
    assert!(ExactGroup::of(&catalog::resolve("weeks").unwrap()).is_none());
}

#[test]
fn the_exact_matrices_are_the_pairings() {
    // Rounded back to f64, the exact element of a short word is the
    // product of the f64 pairings.
    let mut rng = Rng(3);
    for name in ["seifert-weber", "mirrored-dodecahedron"] {
        let s = catalog::by_name(name).unwrap();
        for _ in 0..200 {
            let w = random_word(&mut rng, s.faces().len(), 4);
            let exact = s.cell_matrix(&s.cell_of_word(&w));
            let float = matrix(&s, &w);
            let err = (exact - float)
                .to_cols_array()
                .iter()
                .fold(0.0f64, |m, x| m.max(x.abs()));
            assert!(err < 1e-9 * float.w_axis.w, "{name} {w:?}: {err}");
        }
    }
}

#[test]
fn a_word_with_a_relation_inserted_keeps_its_id_in_every_catalog_space() {
    let mut rng = Rng(7);
    for name in catalog::NAMES {
        let s = catalog::by_name(name).unwrap();
        let n = s.faces().len();
        for _ in 0..10_000 {
            let w = random_word(&mut rng, n, 64);
            let at = rng.below(w.len() + 1);
            let mut v = w.clone();
            v.splice(at..at, relator(&mut rng, &s));
            let (a, b) = (id(&s, &w), id(&s, &v));
            assert!(!a.is_far(), "{name}: {w:?} is far");
            assert_eq!(a, b, "{name}: {w:?} vs {v:?}");
        }
    }
}

#[test]
fn a_word_times_an_element_that_moves_the_domain_gets_another_id_in_every_catalog_space() {
    let mut rng = Rng(11);
    for name in catalog::NAMES {
        let s = catalog::by_name(name).unwrap();
        let n = s.faces().len();
        let mut pairs = 0;
        while pairs < 10_000 {
            let w = random_word(&mut rng, n, 64);
            let u = random_word(&mut rng, n, 6);
            // u moves the domain when the f64 matrix (a short word: exact
            // enough) carries the centre out of the domain.
            if s.outside_face(matrix(&s, &u) * DVec4::W, 1e-9).is_none() {
                continue;
            }
            pairs += 1;
            let wu: Vec<usize> = w.iter().chain(&u).copied().collect();
            assert_ne!(id(&s, &w), id(&s, &wu), "{name}: {w:?} and {u:?}");
        }
    }
}

#[test]
fn exact_ids_agree_with_the_coxeter_normal_form_at_length_64() {
    // Two independent solutions of the mirrored dodecahedron's word
    // problem: equal ids exactly when equal normal forms, over 10^4 pairs
    // of long words, half of them equal by construction.
    let s = catalog::mirrored_dodecahedron();
    let g = RightAngledCoxeter::of(&s).unwrap();
    let mut rng = Rng(19);
    let (mut same, mut differ) = (0, 0);
    for k in 0..10_000 {
        let w = random_word(&mut rng, 12, 64);
        let v = if k % 2 == 0 {
            let mut v = w.clone();
            let at = rng.below(w.len() + 1);
            v.splice(at..at, relator(&mut rng, &s));
            v
        } else {
            random_word(&mut rng, 12, 64)
        };
        let equal = g.normal_form(&w) == g.normal_form(&v);
        assert_eq!(id(&s, &w) == id(&s, &v), equal, "{w:?} vs {v:?}");
        if equal {
            same += 1;
        } else {
            differ += 1;
        }
    }
    assert!(same >= 5000 && differ > 4000, "{same} equal, {differ} distinct");
}

#[test]
fn among_short_words_equal_ids_are_equal_copies() {
    // Near the origin copy the f64 centres are exact enough to decide.
    let mut rng = Rng(13);
    for name in ["seifert-weber", "mirrored-dodecahedron"] {
        let s = catalog::by_name(name).unwrap();
        let geometry = s.geometry();
        let words: Vec<Vec<usize>> = (0..300).map(|_| random_word(&mut rng, 12, 5)).collect();
        let ids: Vec<CellId> = words.iter().map(|w| id(&s, w)).collect();
        let centres: Vec<DVec4> = words
            .iter()
            .map(|w| geometry.normalize_point::<f64>(matrix(&s, w) * DVec4::W))
            .collect();
        let mut same = 0;
        for i in 0..words.len() {
            for j in i + 1..words.len() {
                let d = geometry.distance::<f64>(centres[i], centres[j]);
                let equal_copy = d < 1e-6;
                assert!(equal_copy || d > 1.9 * s.inradius(), "{name}: {d}");
                assert_eq!(ids[i] == ids[j], equal_copy, "{name}: {:?} {:?}", words[i], words[j]);
                same += usize::from(equal_copy);
            }
        }
        assert!(same > 50, "{name}: {same} equal pairs");
    }
}

#[test]
fn an_f64_element_is_located_in_its_exact_copy() {
    // The f64 path (walking the centre home) names the same copy as the
    // exact element while the f64 product is good, about distance 12.
    let mut rng = Rng(23);
    for name in ["seifert-weber", "mirrored-dodecahedron"] {
        let s = catalog::by_name(name).unwrap();
        let mut checked = 0;
        for _ in 0..2000 {
            let w = random_word(&mut rng, 12, 12);
            let m = matrix(&s, &w);
            if !m.is_finite() || m.w_axis.w >= 1e5 {
                continue;
            }
            checked += 1;
            assert_eq!(s.cell_id(&m), id(&s, &w), "{name} {w:?}");
            assert_eq!(s.cell_of_matrix(&m), s.cell_of_word(&w), "{name} {w:?}");
        }
        assert!(checked > 500, "{name}: {checked}");
    }
}

#[test]
fn a_million_crossings_out_and_back_by_another_route_come_home() {
    // Out 30 random crossings (about distance 30), back by the inverse
    // route with a relator spliced in at every step: 10^6 crossings, and
    // the exact element is the identity after each trip.
    let mut rng = Rng(29);
    for name in ["seifert-weber", "mirrored-dodecahedron"] {
        let s = catalog::by_name(name).unwrap();
        let mut crossings = 0;
        let mut farthest = 0.0f64;
        while crossings < 1_000_000 {
            let out = random_word(&mut rng, 12, 30);
            let mut cell = s.cell_of_word(&out);
            farthest = farthest.max(s.cell_matrix(&cell).w_axis.w);
            for &f in out.iter().rev() {
                for r in relator(&mut rng, &s) {
                    cell = s.cross_cell(&cell, r);
                }
                cell = s.cross_cell(&cell, s.faces()[f].partner);
                crossings += 1;
            }
            crossings += out.len();
            assert!(matches!(cell, CellElement::Exact(_)), "{name}");
            assert_eq!(s.cell_id_of(&cell), CellId(0), "{name}: {out:?}");
        }
        assert!(farthest > 1e9, "{name}: only w = {farthest} out");
    }
}

#[test]
fn far_out_the_integers_grow_and_stay_exact() {
    // Straight out through one face 300 times (about distance 600) and
    // back: past i128 (about 40 steps on this axis) the element is held in
    // integers of any size, and coming home gives the identity again.
    let s = catalog::seifert_weber();
    let p = s.faces()[0].partner;
    let mut cell = s.origin_cell();
    for _ in 0..300 {
        cell = s.cross_cell(&cell, 0);
    }
    let CellElement::Exact(far) = &cell else {
        panic!("not exact: {cell:?}")
    };
    assert!(!far.is_small());
    assert!(!s.cell_id_of(&cell).is_far());
    for _ in 0..300 {
        cell = s.cross_cell(&cell, p);
    }
    assert_eq!(s.cell_id_of(&cell), CellId(0));
    let CellElement::Exact(home) = &cell else { panic!() };
    assert!(home.is_small());
}

#[test]
fn the_view_from_a_far_cell_is_the_view_from_home() {
    // The cover looks the same from every copy of the domain (the group
    // acts by isometries), so with per-cell colour off a camera 20
    // crossings away sees what it sees at home: Suzanne attached to it
    // (never seen from inside), the hands, the edges.
    let space = catalog::seifert_weber();
    let settings = TraceSettings {
        width: 96,
        height: 64,
        levels: 4,
        ..TraceSettings::default()
    };
    let home = Scene::paper_default(&space);
    assert!(!home.meshes.is_empty());
    let mut far = home.clone();
    far.camera.cell = (0..20).map(|k| (k * 5 + k / 3) % 12).collect();
    let a = render::<f64>(&space, &home, &settings);
    let b = render::<f64>(&space, &far, &settings);
    let same = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .filter(|(p, q)| p.object == q.object && p.color.iter().zip(&q.color).all(|(x, y)| (x - y).abs() < 2e-3))
        .count();
    assert!(same * 1000 >= 999 * a.pixels.len(), "{same} of {}", a.pixels.len());
    assert_ne!(a.pixels[0].cell, b.pixels[0].cell, "the ids are the far cell's");
}

/// Walks through a table of cells around a far copy name each cell as
/// the exact product of the crossings does (the arithmetic it replaces),
/// inside the table and, once a walk leaves it, never again by index.
#[test]
fn a_walk_through_the_table_around_a_copy_names_the_exact_products_cells() {
    use bevy_manifold_core::space::cell_table::{CellTable, CentredTable, OUTSIDE};
    use bevy_manifold_core::space::cells::CellScheme;
    use std::sync::Arc;
    let s = catalog::seifert_weber();
    let CellScheme::Exact(exact) = s.cells() else {
        panic!("exact ids")
    };
    let g = &exact.group;
    // A small table (radius 2 or 3), so that walks of 8 leave it.
    let table = Arc::new(CellTable::grow(g, 2000));
    let mut rng = Rng(41);
    let (mut inside, mut left) = (0, 0);
    for _ in 0..40 {
        let centre = g.element(&random_word(&mut rng, 12, 12)).unwrap();
        let around = CentredTable::new(table.clone(), centre.clone());
        assert_eq!(around.id(g, 0), centre.cell_id());
        for _ in 0..20 {
            let (mut e, mut k) = (centre.clone(), 0u32);
            for _ in 0..8 {
                let f = rng.below(12);
                e = g.cross(&e, f).unwrap();
                if k != OUTSIDE {
                    k = table.neighbour(k, s.faces()[f].partner);
                }
                if k == OUTSIDE {
                    left += 1;
                    continue;
                }
                inside += 1;
                assert_eq!(around.id(g, k), e.cell_id(), "cell {k}");
                // Asked again, from the kept id.
                assert_eq!(around.id(g, k), e.cell_id(), "cell {k}, again");
                assert_eq!(around.element(g, k).unwrap(), e);
            }
        }
    }
    assert!(inside > 1000 && left > 1000, "{inside} steps inside, {left} outside");
}

/// The CPU tracer steps through the table of cells around the camera
/// once a space's table is grown, and multiplies exact elements at every
/// crossing before: the two name every pixel's cell alike, and so hide
/// the same cells and stop at the same walls, with the camera far from
/// the origin copy and rays reaching past the table (radius 4).
#[test]
fn rays_through_the_grown_table_see_what_exact_products_see() {
    use bevy_manifold_core::space::cells::CellScheme;
    use bevy_manifold_core::space::rule::{CellRule, OnOff, WALL_OBJECT, Walls};
    let plain = catalog::seifert_weber();
    let tabled = catalog::seifert_weber();
    let (CellScheme::Exact(p), CellScheme::Exact(t)) = (plain.cells(), tabled.cells()) else {
        panic!("exact ids")
    };
    let radius = t.table().radius();
    assert!(p.grown_table().is_none(), "a space of its own");
    let mut scene = Scene::paper_default(&plain);
    scene.camera.cell = vec![3, 7, 7, 1, 10];
    // One walks the table, the other multiplies.
    let flat = |s: &Space| bevy_manifold_core::trace::FlatScene::<f64>::new(s, &scene);
    assert!(flat(&tabled).centred_table(&tabled).is_some());
    assert!(flat(&plain).centred_table(&plain).is_none());
    for (rule, levels) in [
        (CellRule::default(), 8),
        (
            CellRule {
                hidden: Some(OnOff {
                    on_fraction: 0.5,
                    seed: 3,
                }),
                walls: Some(Walls { density: 0.2, seed: 5 }),
            },
            8,
        ),
    ] {
        let settings = TraceSettings {
            width: 64,
            height: 48,
            levels,
            cell_rule: rule,
            ..TraceSettings::default()
        };
        let a = render::<f64>(&plain, &scene, &settings);
        let b = render::<f64>(&tabled, &scene, &settings);
        for (i, (x, y)) in a.pixels.iter().zip(&b.pixels).enumerate() {
            assert_eq!(x.cell, y.cell, "pixel {i}: cell");
            assert_eq!((x.object, x.levels), (y.object, y.levels), "pixel {i}");
            assert_eq!(x.color, y.color, "pixel {i}: colour");
        }
        let past = a.pixels.iter().filter(|p| p.levels > u32::from(radius)).count();
        let within = a
            .pixels
            .iter()
            .filter(|p| (1..=u32::from(radius)).contains(&p.levels))
            .count();
        let walls = a.pixels.iter().filter(|p| p.object == WALL_OBJECT).count();
        eprintln!("{within} pixels within the table's radius {radius}, {past} past it, {walls} on walls");
        assert!(
            past > 100 && within > 100,
            "{within} pixels within the table, {past} past"
        );
        if rule.walls.is_some() {
            assert!(walls > 100, "{walls} wall pixels");
        }
    }
}

/// A scene's table is its own space's, around its own camera: traced with
/// another space (whose table has the same size), or with the camera
/// moved by hand, it hands out no table and the rays multiply exactly.
#[test]
fn a_scene_hands_out_its_table_only_for_its_space_and_camera() {
    use bevy_manifold_core::space::cells::CellScheme;
    use bevy_manifold_core::trace::{FlatScene, camera_ray, trace_ray};
    let sw = catalog::seifert_weber();
    let other = catalog::seifert_weber();
    for s in [&sw, &other] {
        let CellScheme::Exact(e) = s.cells() else {
            panic!("exact ids")
        };
        e.table();
    }
    let scene = Scene::paper_default(&sw);
    let mut flat = FlatScene::<f64>::new(&sw, &scene);
    assert!(flat.centred_table(&sw).is_some());
    assert!(flat.centred_table(&other).is_none(), "another space's table");
    let settings = TraceSettings {
        width: 16,
        height: 16,
        ..TraceSettings::default()
    };
    let rays: Vec<_> = (0..16 * 16)
        .map(|p| camera_ray(&flat, p % 16, p / 16, 16, 16))
        .collect();
    let mine: Vec<_> = rays
        .iter()
        .map(|&ray| trace_ray(&sw, &flat, ray, &settings, &mut |_| {}).0.cell)
        .collect();
    // The rays walked the table: the ids of the cells they ended in
    // within it were made there.
    let made = flat.centred_table(&sw).expect("the table").made();
    assert!(made >= 1, "{made} ids made");
    let theirs: Vec<_> = rays
        .iter()
        .map(|&ray| trace_ray(&other, &flat, ray, &settings, &mut |_| {}).0.cell)
        .collect();
    assert_eq!(mine, theirs, "the same group, multiplied");
    // The other space's traces made none in this table.
    assert_eq!(flat.centred_table(&sw).expect("the table").made(), made);
    flat.camera_element = sw.cell_of_word(&[2, 9]);
    assert!(flat.centred_table(&sw).is_none(), "a camera moved by hand");
    let moved = flat.clone().in_cell(&sw, &sw.cell_of_word(&[4]));
    assert!(moved.centred_table(&sw).is_some(), "in_cell makes a new table");
}
