//! Exact cell ids of the product spaces (`space::product_cells`),
//! checked against geometry and group theory rather than against
//! themselves: among random words, two name one id exactly when the
//! copies they reach (computed in `f64` from the gluings) are one copy;
//! in the mirrored prism, exactly when the right-angled Coxeter group's
//! normal forms (a rewriting solution of the word problem) are equal;
//! the table the GPU walks names what the exact elements name.

use bevy_manifold_core::geometry::product::{ProductIsometry, ProductPoint};
use bevy_manifold_core::space::cells::CellId;
use bevy_manifold_core::space::exact::TooFar;
use bevy_manifold_core::space::product::ProductSpace;
use bevy_manifold_core::space::product_cells::{
    DEFAULT_PRODUCT_TABLE_CELLS, ProductCellTable, ProductCells, product_cell_id,
};
use bevy_manifold_test_support::Rng;
use bevy_manifold_test_support::coxeter::RightAngledCoxeter;

fn random_word(rng: &mut Rng, faces: usize, max_len: usize) -> Vec<usize> {
    let len = rng.below(max_len + 1);
    (0..len).map(|_| rng.below(faces)).collect()
}

/// The copy `word` reaches, in `f64`: the inverse gluings composed in
/// order (crossing face `f` from copy `e` reaches `e G_f^-1`), applied to
/// a point inside the prism that no symmetry of the polygon fixes.
fn copy_of(space: &ProductSpace, word: &[usize]) -> ProductPoint {
    let g = space.geometry;
    let e = word.iter().fold(ProductIsometry::IDENTITY, |e, &f| {
        e.compose(&space.gluings[f].isometry().inverse(g))
    });
    let (c, s) = g.trig(0.05);
    let inside = ProductPoint::new(glam::DVec3::new(s * 0.6, s * 0.8, c), 0.1 * space.height);
    g.normalize_point(e.apply(inside))
}

#[test]
fn every_catalog_space_has_exact_cells() {
    for name in ProductSpace::NAMES {
        for twist in [1, 3] {
            let space = ProductSpace::named(name, 1.5, twist).unwrap();
            let cells = ProductCells::of(&space).unwrap_or_else(|| panic!("{}: no exact cells", space.name));
            assert_eq!(cells.faces(), space.face_count(), "{}", space.name);
            // Each face's crossing undoes its partner's.
            for f in 0..space.face_count() {
                let back = cells.element(&[f, space.partner(f)]).unwrap();
                assert_eq!(cells.id(&back), CellId(0), "{} face {f}", space.name);
            }
        }
    }
    // Gluings that are not over the rings: no exact cells (and no panic).
    let mut odd = ProductSpace::genus_two_x_s1(1.0);
    for gluing in &mut odd.gluings[..8] {
        if let bevy_manifold_core::space::product::ProductGluing::Paired { pairing, .. } = gluing {
            pairing.surface.x_axis.x += 1e-4;
        }
    }
    assert!(ProductCells::of(&odd).is_none());
}

#[test]
fn equal_ids_are_exactly_equal_copies() {
    let mut rng = Rng(47);
    for (name, twist, words, len) in [
        ("genus2xs1", 0, 500, 7),
        ("twisted-genus2xs1", 3, 500, 7),
        ("s2xs1", 1, 200, 9),
        ("twisted-s2xs1", 3, 200, 9),
        ("mirrored-prism", 0, 500, 9),
    ] {
        let space = ProductSpace::named(name, 1.3, twist).unwrap();
        let g = space.geometry;
        let cells = ProductCells::of(&space).unwrap();
        let seen: Vec<(CellId, ProductPoint)> = (0..words)
            .map(|_| {
                let word = random_word(&mut rng, space.face_count(), len);
                (cells.id(&cells.element(&word).unwrap()), copy_of(&space, &word))
            })
            .collect();
        let (mut same, mut other) = (0, 0);
        for (i, a) in seen.iter().enumerate() {
            for b in &seen[..i] {
                // Copies of the prism are 0.1 height apart at the least
                // here, or a side's width on the surface; 1e-6 is rounding.
                let one = g.distance(a.1, b.1) < 1e-6;
                assert_eq!(
                    a.0 == b.0,
                    one,
                    "{}: ids {:?} {:?} at {:?} {:?}",
                    space.name,
                    a.0,
                    b.0,
                    a.1,
                    b.1
                );
                if one { same += 1 } else { other += 1 }
            }
        }
        // Both kinds of pair were met (short words reach a copy twice).
        assert!(
            same > 20 && other > 1000,
            "{}: {same} equal pairs, {other} others",
            space.name
        );
    }
}

#[test]
fn mirrored_prism_ids_are_the_coxeter_normal_forms() {
    // The pentagon's sides 0..5 (neighbours meet at right angles), the
    // bottom 5 and the top 6 (at right angles to every side, not to each
    // other: D-infinity).
    let space = ProductSpace::mirrored_prism(5, 1.0);
    let cells = ProductCells::of(&space).unwrap();
    let mut pairs: Vec<(usize, usize)> = (0..5).map(|i| (i, (i + 1) % 5)).collect();
    pairs.extend((0..5).flat_map(|i| [(i, 5), (i, 6)]));
    let coxeter = RightAngledCoxeter::from_commuting(7, &pairs);
    let mut rng = Rng(5);
    let words: Vec<Vec<usize>> = (0..600).map(|_| random_word(&mut rng, 7, 12)).collect();
    let ids: Vec<CellId> = words.iter().map(|w| cells.id(&cells.element(w).unwrap())).collect();
    let forms: Vec<Vec<u8>> = words.iter().map(|w| coxeter.normal_form(w)).collect();
    let mut same = 0;
    for i in 0..words.len() {
        for j in 0..i {
            assert_eq!(
                ids[i] == ids[j],
                forms[i] == forms[j],
                "{:?} and {:?}",
                words[i],
                words[j]
            );
            same += usize::from(forms[i] == forms[j]);
        }
        // A relation inserted anywhere names the same copy: s s, and the
        // commuting square s t s t of neighbouring sides.
        let at = rng.below(words[i].len() + 1);
        let s = rng.below(5);
        for relation in [vec![s, s], vec![s, (s + 1) % 5, s, (s + 1) % 5], vec![5, s, 5, s]] {
            let mut w = words[i].clone();
            w.splice(at..at, relation);
            assert_eq!(cells.id(&cells.element(&w).unwrap()), ids[i]);
        }
    }
    assert!(same > 50, "{same} equal pairs");
}

#[test]
fn the_table_names_what_the_elements_name() {
    let mut rng = Rng(11);
    for (name, twist) in [
        ("genus2xs1", 0),
        ("twisted-genus2xs1", 3),
        ("mirrored-prism", 0),
        ("twisted-s2xs1", 3),
    ] {
        let space = ProductSpace::named(name, 1.0, twist).unwrap();
        let cells = ProductCells::of(&space).unwrap();
        let table = ProductCellTable::grow(&cells, DEFAULT_PRODUCT_TABLE_CELLS);
        // The sphere's copies differ by their steps alone: one cell.
        let one = space.sides.is_empty();
        assert!(
            one == (table.len() == 1) && table.len() <= DEFAULT_PRODUCT_TABLE_CELLS,
            "{}: {}",
            space.name,
            table.len()
        );
        // A camera somewhere off the origin copy.
        let camera = cells.element(&random_word(&mut rng, space.face_count(), 5)).unwrap();
        let tiles = table.tiles_around(&cells, &camera);
        for _ in 0..300 {
            // Walk the table as the GPU does: an index for the surface
            // part, the line's flip and steps counted apart.
            let word = random_word(&mut rng, space.face_count(), 7);
            let (mut k, mut line) = (0u32, cells.identity());
            for &f in &word {
                k = table.neighbours[k as usize * table.faces() + f];
                line = cells.cross(&line, f).unwrap();
                if k == u32::MAX {
                    break;
                }
            }
            // The table holds every copy within 3 side crossings, with
            // any number of crossings up and down.
            let sides = word.iter().filter(|&&f| f < space.sides.len()).count();
            if k == u32::MAX {
                assert!(sides > 3, "{}: {word:?} left a table of {}", space.name, table.len());
                continue;
            }
            let steps = camera.steps() + line.steps() * if camera.flips() { -1 } else { 1 };
            let exact = cells.compose(&camera, &cells.element(&word).unwrap()).unwrap();
            assert_eq!(
                product_cell_id(tiles[k as usize], steps),
                cells.id(&exact),
                "{}: {word:?}",
                space.name
            );
        }
    }
}

#[test]
fn far_copies_are_refused_not_wrapped() {
    let space = ProductSpace::genus_two_x_s1(1.0);
    let cells = ProductCells::of(&space).unwrap();
    // Straight across the octagon again and again: each crossing moves
    // 2 arccosh(1 + sqrt 2) = 3.06 along one axis, past i128 by 200.
    assert_eq!(cells.element(&[0; 200]), Err(TooFar));
    // Near copies along that axis are all different.
    let ids: Vec<CellId> = (0..12)
        .map(|n| cells.id(&cells.element(&vec![0; n]).unwrap()))
        .collect();
    let distinct: std::collections::HashSet<_> = ids.iter().collect();
    assert_eq!(distinct.len(), 12);
    // Up the circle, any number of times.
    let up = cells.element(&vec![space.top(); 100_000]).unwrap();
    assert_eq!(up.steps(), 100_000);
}
