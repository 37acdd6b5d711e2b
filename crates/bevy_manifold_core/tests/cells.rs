//! Cell ids depend on the group element only: different words for the same
//! element get the same id, different elements different ids.

use bevy_manifold_core::geometry::isometry;
use bevy_manifold_core::prelude::*;
use bevy_manifold_core::space::cells::{CellId, CellScheme};
use bevy_manifold_test_support::Rng;
use glam::{DMat4, IVec3};

/// The element of a word of face crossings (as a ray accumulates it).
fn word(space: &Space, faces: &[usize]) -> DMat4 {
    faces.iter().fold(DMat4::IDENTITY, |g, &f| g * space.crossing(f))
}

/// A relator of the group: the faces crossed walking once around an edge
/// cycle (their product is the identity, or of order k).
fn cycle_relator(space: &Space, cycle: usize) -> Vec<usize> {
    let c = &space.edge_cycles()[cycle];
    // The walk's holonomy is T_{a_m} ... T_{a_1}; crossing a_1, ..., a_m
    // multiplies by T_{a_1}^-1 ... T_{a_m}^-1, its inverse.
    let once: Vec<usize> = c.faces.clone();
    once.iter()
        .copied()
        .cycle()
        .take(once.len() * c.order as usize)
        .collect()
}

#[test]
fn torus_ids_are_the_lattice_triple() {
    let t = catalog::torus(1.0);
    // Faces: 0 = +x, 1 = +y, 2 = +z, 3..5 the opposites.
    assert_eq!(t.cell_id(&word(&t, &[0, 1, 0])).lattice(), Some(IVec3::new(2, 1, 0)));
    assert_eq!(t.cell_id(&word(&t, &[0, 1, 0])), t.cell_id(&word(&t, &[1, 0, 0])));
    assert_eq!(t.cell_id(&word(&t, &[0, 3])), CellId(0));
    assert_eq!(
        t.cell_id(&word(&t, &[5, 5, 4, 3])).lattice(),
        Some(IVec3::new(-1, -1, -2))
    );
    for c in [IVec3::new(-5, 7, 1000), IVec3::new(1 << 19, -(1 << 19), 3)] {
        assert_eq!(CellId::from_lattice(c).lattice(), Some(c));
    }
    // A mirrored cube's copies sit on the same lattice; two reflections in
    // opposite faces are a translation by 2.
    let m = catalog::mirrored_cube(1.0);
    // Across +x into the mirrored copy, whose "-x" face is on the far side.
    assert_eq!(m.cell_id(&word(&m, &[0, 3])).lattice(), Some(IVec3::new(2, 0, 0)));
    assert_eq!(m.cell_id(&word(&m, &[0, 0])), CellId(0));
    assert_eq!(m.cell_id(&word(&m, &[0, 1])), m.cell_id(&word(&m, &[1, 0])));
}

#[test]
fn different_words_for_one_element_share_an_id_in_every_space() {
    let mut rng = Rng(42);
    for name in catalog::NAMES {
        let s = catalog::by_name(name).expect("catalog");
        let n = s.faces().len();
        for trial in 0..300 {
            let len = 1 + rng.below(6);
            let w: Vec<usize> = (0..len).map(|_| rng.below(n)).collect();
            // Insert a relator (an edge cycle's word), or a face and its
            // partner back to back, at a random place.
            let relator = if trial % 2 == 0 {
                cycle_relator(&s, rng.below(s.edge_cycles().len()))
            } else {
                let f = rng.below(n);
                vec![f, s.faces()[f].partner]
            };
            let at = rng.below(w.len() + 1);
            let mut w2 = w.clone();
            w2.splice(at..at, relator.iter().copied());
            let (g1, g2) = (word(&s, &w), word(&s, &w2));
            assert!(
                g1.abs_diff_eq(g2, 1e-6 * g1.w_axis.length()),
                "{name}: the relator is not trivial"
            );
            assert_eq!(s.cell_id(&g1), s.cell_id(&g2), "{name}: words {w:?} and {w2:?}");
        }
    }
}

#[test]
fn distinct_elements_get_distinct_ids_with_a_safe_rounding_margin() {
    for name in catalog::NAMES {
        let s = catalog::by_name(name).expect("catalog");
        let g = s.geometry();
        // Every element of word length <= 4 (deduplicated by matrix).
        let mut elements = vec![DMat4::IDENTITY];
        let mut frontier = vec![DMat4::IDENTITY];
        for _ in 0..4 {
            let mut next = Vec::new();
            for m in &frontier {
                for f in 0..s.faces().len() {
                    let h = isometry::orthonormalize(g, *m * s.crossing(f));
                    if !elements
                        .iter()
                        .any(|e| (e.w_axis - h.w_axis).length() < 1e-7 * h.w_axis.length())
                    {
                        elements.push(h);
                        next.push(h);
                    }
                }
            }
            frontier = next;
        }
        let mut ids: Vec<CellId> = elements.iter().map(|e| s.cell_id(e)).collect();
        ids.sort_unstable();
        let before = ids.len();
        ids.dedup();
        assert_eq!(ids.len(), before, "{name}: two different elements share an id");
        // The rounding behind hashed ids is far from its boundaries: f64
        // error after a few hundred steps is ~1e-12 of a grid step.
        let margin = elements
            .iter()
            .map(|e| s.cells().rounding_margin(e))
            .fold(0.5, f64::min);
        assert!(margin > 1e-4, "{name}: rounding margin {margin}");
        if name == "poincare" {
            assert!(ids.iter().all(|id| id.0 < 120), "Poincaré ids index its 120 elements");
        }
    }
}

#[test]
fn the_poincare_cayley_table_is_the_group_law() {
    let s = catalog::poincare();
    let CellScheme::Finite { elements, table } = s.cells() else {
        panic!("finite")
    };
    assert_eq!(elements.len(), 120);
    for (k, row) in table.iter().enumerate() {
        for (f, &j) in row.iter().enumerate() {
            let product = elements[k] * s.faces()[f].pairing;
            assert!(product.abs_diff_eq(elements[j as usize], 1e-9), "table[{k}][{f}]");
            // The group law from the other side: T_partner = T_f^-1, so
            // stepping back through the partner returns to k.
            let back = table[j as usize][s.faces()[f].partner];
            assert_eq!(back as usize, k, "table[table[{k}][{f}]][partner] is not {k}");
        }
    }
    // Words of 40 pairings: the table's walk lands on the element that the
    // matrix product names, found by a search over all 120 (not the table).
    let mut rng = Rng(7);
    for _ in 0..200 {
        let (mut k, mut m) = (0usize, DMat4::IDENTITY);
        for _ in 0..40 {
            let f = rng.below(s.faces().len());
            k = table[k][f] as usize;
            m *= s.faces()[f].pairing;
        }
        let nearest = (0..elements.len())
            .min_by(|&a, &b| {
                let d = |i: usize| {
                    (elements[i] - m)
                        .to_cols_array()
                        .iter()
                        .map(|x| x.abs())
                        .fold(0.0, f64::max)
                };
                d(a).total_cmp(&d(b))
            })
            .expect("elements");
        assert_eq!(nearest, k);
    }
}

#[test]
fn hashed_keys_round_half_to_even_and_never_saturate_like_the_gpu() {
    use bevy_manifold_core::space::cells::{HASH_KEY_LIMIT, hash_key_of};
    use glam::DVec4;
    // Ties go to the even neighbour, as WGSL's round does (Rust's round
    // would take 2.5 to 3 and -0.5 to -1).
    assert_eq!(hash_key_of(DVec4::new(2.5, -0.5, 1.5, 3.5), 1.0), [2, 0, 2, 4]);
    assert_eq!(hash_key_of(DVec4::new(0.25, 0.75, -1.25, 1.0), 2.0), [0, 2, -2, 2]);
    // Past the limit every coordinate is clamped, not saturated at i32::MAX.
    let limit = HASH_KEY_LIMIT as i32;
    assert_eq!(
        hash_key_of(DVec4::new(1e300, -1e300, 0.0, 1.0), 1.0),
        [limit, -limit, 0, 1]
    );
    // A centre with NaN (an overflowed element) is FAR, never a real cell.
    let sw = catalog::seifert_weber();
    let mut broken = glam::DMat4::IDENTITY;
    broken.w_axis = DVec4::new(f64::NAN, 0.0, 0.0, 1.0);
    let id = sw.cell_id(&broken);
    assert!(id.is_far() && id.0 != 0, "{id:?}");
    // A centre past the horizon is FAR too, with a key that stayed exact.
    let far = sw.crossing(0) * sw.crossing(5) * sw.crossing(0) * sw.crossing(5) * sw.crossing(0);
    let mut far_id = far;
    for _ in 0..6 {
        far_id = far_id * sw.crossing(0) * sw.crossing(5);
    }
    assert!(sw.cell_id(&far_id).is_far());
    assert!(!sw.cell_id(&far).is_far());
}
