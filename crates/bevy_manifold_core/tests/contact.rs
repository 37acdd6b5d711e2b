//! Contacts through the face pairings against what the geometry says
//! independently: the torus's nearest images in closed form (each
//! coordinate of the difference reduced to `[-1/2, 1/2]`), and in the
//! Seifert-Weber and Poincaré spaces against the group enumerated here
//! from the face pairings (every word up to a length, or the whole finite
//! group).

use bevy_manifold_core::contact::{self, Image};
use bevy_manifold_core::geometry;
use bevy_manifold_core::prelude::*;
use bevy_manifold_test_support::Rng;
use glam::{DMat4, DVec4};

/// The group elements reached by words of at most `length` face
/// pairings, one per distinct matrix.
fn words(space: &Space, length: usize) -> Vec<DMat4> {
    let mut all = vec![DMat4::IDENTITY];
    let mut last = vec![DMat4::IDENTITY];
    for _ in 0..length {
        let mut next = Vec::new();
        for m in &last {
            for f in space.faces() {
                let w = *m * f.pairing;
                if !all.iter().chain(&next).any(|o: &DMat4| o.abs_diff_eq(w, 1e-6)) {
                    next.push(w);
                }
            }
        }
        all.extend(&next);
        last = next;
    }
    all
}

/// The distances from `p` of every image of `q` under `group`, sorted.
fn group_distances(space: &Space, group: &[DMat4], p: DVec4, q: DVec4) -> Vec<f64> {
    let g = space.geometry();
    let mut all: Vec<f64> = group
        .iter()
        .map(|w| g.distance::<f64>(p, g.normalize_point::<f64>(*w * q)))
        .collect();
    all.sort_by(f64::total_cmp);
    all
}

fn torus_nearest(p: DVec4, q: DVec4) -> f64 {
    let d = (q - p).truncate();
    (d - d.round()).length()
}

#[test]
fn the_nearest_image_is_the_shortest_route_through_the_faces() {
    let mut rng = Rng(5);
    let torus = catalog::torus(1.0);
    for _ in 0..200 {
        let p = rng.ray_inside(&torus).origin;
        let q = rng.ray_inside(&torus).origin;
        let near = contact::nearest_image(&torus, p, q).expect("finite");
        let want = torus_nearest(p, q);
        assert!(
            (near.distance - want).abs() < 1e-9,
            "{p:?} {q:?}: {} against {want}",
            near.distance
        );
        // The direction points at the image, the element makes it.
        let image = near.element * q;
        assert!((p + near.direction * near.distance - image).length() < 1e-9);
    }
    // Seifert-Weber: never longer than the best word of three pairings.
    let sw = catalog::seifert_weber();
    let group = words(&sw, 3);
    for _ in 0..30 {
        let p = rng.ray_inside(&sw).origin;
        let q = rng.ray_inside(&sw).origin;
        let near = contact::nearest_image(&sw, p, q).expect("finite");
        let best = group_distances(&sw, &group, p, q)[0];
        assert!(
            near.distance <= best + 1e-9,
            "{} is longer than a route of {best}",
            near.distance
        );
    }
}

/// In the Poincaré space (a group of 120) the images within a distance
/// are exactly those of the whole group, enumerated from the pairings.
#[test]
fn the_images_within_a_distance_are_all_the_groups() {
    let poincare = catalog::poincare();
    let group = words(&poincare, 12);
    assert_eq!(group.len(), 120, "the binary icosahedral group");
    let mut rng = Rng(11);
    for reach in [0.3, 0.8, 1.6] {
        for _ in 0..10 {
            let p = rng.ray_inside(&poincare).origin;
            let q = rng.ray_inside(&poincare).origin;
            let mut want = group_distances(&poincare, &group, p, q);
            want.retain(|d| *d <= reach);
            let got: Vec<f64> = contact::images_within(&poincare, p, q, reach)
                .iter()
                .map(|i: &Image| i.distance)
                .collect();
            assert_eq!(got.len(), want.len(), "reach {reach}: {got:?} against {want:?}");
            for (a, b) in got.iter().zip(&want) {
                assert!((a - b).abs() < 1e-9, "reach {reach}: {a} against {b}");
            }
        }
    }
}

/// The copies of the domain that a ball meets, and the ball's ghosts
/// (the elements whose copy of it reaches into the domain), against the
/// copies that hold its points: 400 points of each ball, each carried
/// into the domain by the pairings (`Space::wrap`, which names the copy
/// it was in). Every such copy must be walked, and its element's inverse
/// must be a ghost; and every copy walked must pass the walk's own
/// bound. In the Poincaré space (S3, a domain of inradius 0.31) the
/// largest balls meet a dozen copies and more.
#[test]
fn the_copies_a_ball_meets_and_its_ghosts_hold_all_its_points() {
    let poincare = catalog::poincare();
    let g = poincare.geometry();
    let outside = |q: DVec4| {
        poincare
            .faces()
            .iter()
            .map(|f| geometry::plane::signed_distance(g, f.plane, q))
            .fold(0.0f64, f64::max)
    };
    let mut rng = Rng(5);
    let mut most = 0;
    for r in [0.05, 0.2, 0.5] {
        for _ in 0..20 {
            let p = rng.ray_inside(&poincare).origin;
            let copies = contact::copies_within(&poincare, p, r);
            for (h, bound) in &copies {
                let seen = g.normalize_point::<f64>(geometry::isometry::inverse(g, *h) * p);
                assert!((outside(seen) - bound).abs() < 1e-9 && *bound <= r + 1e-9);
            }
            let walked: Vec<_> = copies.iter().map(|(h, _)| poincare.cell_id(h)).collect();
            let ghosts: Vec<_> = bevy_manifold_core::trace::ghost_elements(&poincare, p, r)
                .iter()
                .map(|h| poincare.cell_id(h))
                .collect();
            most = most.max(walked.len());
            let basis = geometry::isometry::tangent_basis(g, p);
            for _ in 0..400 {
                let d = rng.unit();
                let v = basis[0] * d.x + basis[1] * d.y + basis[2] * d.z;
                let s = r * rng.next_f64().cbrt() * (1.0 - 1e-9);
                let (q, _) = g.exp::<f64>(p, v, s);
                let (_, k) = poincare.wrap(geometry::isometry::translation_to(g, q), 64);
                assert!(
                    walked.contains(&poincare.cell_id(&k)),
                    "radius {r}: a point's copy not walked"
                );
                let ghost = poincare.cell_id(&geometry::isometry::inverse(g, k));
                assert!(ghosts.contains(&ghost), "radius {r}: a ghost missing");
            }
        }
    }
    assert!(most >= 12, "the largest balls met only {most} copies");
}

/// The `k` nearest images, against the whole Poincaré group and, in the
/// torus, against the lattice's nearest points in closed form (the 27
/// offsets of the difference's rounding, sorted).
#[test]
fn the_nearest_few_images_are_the_groups_nearest() {
    let poincare = catalog::poincare();
    let group = words(&poincare, 12);
    let mut rng = Rng(21);
    for _ in 0..10 {
        let p = rng.ray_inside(&poincare).origin;
        let q = rng.ray_inside(&poincare).origin;
        let want = group_distances(&poincare, &group, p, q);
        let got = contact::nearest_images(&poincare, p, q, 7);
        assert_eq!(got.len(), 7);
        for (a, b) in got.iter().zip(&want) {
            assert!((a.distance - b).abs() < 1e-9, "{} against {b}", a.distance);
        }
        // All of a finite group, when asked for more than it has.
        assert_eq!(contact::nearest_images(&poincare, p, q, 500).len(), 120);
    }
    let torus = catalog::torus(1.0);
    for _ in 0..50 {
        let p = rng.ray_inside(&torus).origin;
        let q = rng.ray_inside(&torus).origin;
        let d = (q - p).truncate();
        let base = d - d.round();
        let mut want: Vec<f64> = (-1..=1)
            .flat_map(|x| {
                (-1..=1).flat_map(move |y| (-1..=1).map(move |z| glam::DVec3::new(x as f64, y as f64, z as f64)))
            })
            .map(|o| (base + o).length())
            .collect();
        want.sort_by(f64::total_cmp);
        let got = contact::nearest_images(&torus, p, q, 4);
        for (a, b) in got.iter().zip(&want) {
            assert!((a.distance - b).abs() < 1e-9, "{} against {b}", a.distance);
        }
    }
}

/// Two balls near opposite faces of the torus touch through the face, one
/// contact, its depth the radii less the closed-form distance, its point
/// on the face; a ball wider than half the cube touches its own images
/// (six of them, one through each face); in H3 the contact point is at
/// the distance the depth puts it.
#[test]
fn balls_touch_through_the_faces_as_deep_as_the_geometry_says() {
    let torus = catalog::torus(1.0);
    let a = DVec4::new(-0.45, 0.1, 0.0, 1.0);
    let b = DVec4::new(0.42, 0.1, 0.0, 1.0);
    // 0.13 apart through x = 1/2 (0.87 across the cube).
    let touches = contact::ball_contacts(&torus, (a, 0.1), (b, 0.05));
    assert_eq!(touches.len(), 1);
    let c = touches[0];
    assert!((c.image.distance - 0.13).abs() < 1e-12, "{}", c.image.distance);
    assert!((c.depth - 0.02).abs() < 1e-12, "{}", c.depth);
    assert!((c.image.point - DVec4::new(-0.58, 0.1, 0.0, 1.0)).length() < 1e-12);
    // Midway through the overlap: 0.1 - 0.01 from a, through x = -1/2.
    assert!(
        (c.point - DVec4::new(-0.54, 0.1, 0.0, 1.0)).length() < 1e-12,
        "{:?}",
        c.point
    );
    // Radii 0.05 + 0.05 do not reach across 0.13.
    assert!(contact::ball_contacts(&torus, (a, 0.05), (b, 0.05)).is_empty());
    // A ball of radius 0.55 about the centre overlaps its six neighbours.
    let o = DVec4::W;
    let own = contact::ball_contacts(&torus, (o, 0.55), (o, 0.55));
    // Itself (distance 0) and the six copies one edge away (distance 1).
    assert_eq!(own.len(), 7);
    assert!(
        own[1..]
            .iter()
            .all(|c| (c.image.distance - 1.0).abs() < 1e-12 && (c.depth - 0.1).abs() < 1e-12)
    );
    // Seifert-Weber: centre and a point 0.5 up the z axis, radii 0.3 and
    // 0.4: depth 0.2, the contact 0.2 from the centre (cosh of it the
    // point's w).
    let sw = catalog::seifert_weber();
    let g = sw.geometry();
    let up = g.normalize_point::<f64>(DVec4::new(0.0, 0.0, 0.5f64.tanh(), 1.0));
    let hit = contact::ball_contacts(&sw, (DVec4::W, 0.3), (up, 0.4));
    let c = hit.first().expect("they overlap");
    assert!((c.depth - 0.2).abs() < 1e-9);
    assert!(
        (c.point - DVec4::new(0.0, 0.0, 0.2f64.sinh(), 0.2f64.cosh())).length() < 1e-9,
        "{:?}",
        c.point
    );
}

/// Bad input gives nothing, never a panic.
#[test]
fn non_finite_points_and_negative_reaches_give_no_images() {
    let torus = catalog::torus(1.0);
    assert!(contact::nearest_image(&torus, DVec4::NAN, DVec4::W).is_none());
    assert!(contact::images_within(&torus, DVec4::W, DVec4::W, -1.0).is_empty());
    assert!(contact::images_within(&torus, DVec4::W, DVec4::W, f64::NAN).is_empty());
}
