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

/// Every group element whose copy of the domain has its centre within
/// `reach` of the domain's, by a breadth-first walk over the face
/// pairings that keeps to copies whose centres lie within `reach` plus
/// the circumradius (every copy the geodesic from the centre to such a
/// copy's centre passes through), each element once.
fn group_within(space: &Space, reach: f64) -> Vec<DMat4> {
    use std::collections::HashSet;
    let g = space.geometry();
    let centre = |m: &DMat4| g.distance::<f64>(DVec4::W, g.normalize_point::<f64>(*m * DVec4::W));
    let key = |m: &DMat4| m.to_cols_array().map(|x| (x * 1e6).round() as i64);
    let walk_limit = reach + space.circumradius();
    let mut seen = HashSet::from([key(&DMat4::IDENTITY)]);
    let mut all = vec![DMat4::IDENTITY];
    let mut next = 0;
    while next < all.len() {
        let m = all[next];
        next += 1;
        for f in space.faces() {
            let w = m * f.pairing;
            if centre(&w) <= walk_limit && seen.insert(key(&w)) {
                all.push(w);
            }
        }
    }
    all.retain(|m| centre(m) <= reach);
    all
}

/// A point anywhere in the domain: a random ray inside it followed
/// through the faces for up to twice the inradius.
fn anywhere(rng: &mut Rng, space: &Space, tables: &bevy_manifold_core::trace::FaceTables<f64>) -> DVec4 {
    let ray = rng.ray_inside(space);
    bevy_manifold_core::trace::flow(tables, ray, 2.0 * rng.next_f64() * space.inradius(), 64)
        .ray
        .origin
}

/// A point within `reach` of `p`, wrapped into the domain: `p` followed
/// in a random direction for a random distance up to `reach`.
fn near(
    rng: &mut Rng,
    space: &Space,
    tables: &bevy_manifold_core::trace::FaceTables<f64>,
    p: DVec4,
    reach: f64,
) -> DVec4 {
    let g = space.geometry();
    let dir = g.normalize_tangent::<f64>(p, rng.unit().extend(0.0));
    let ray = bevy_manifold_core::trace::step::Ray { origin: p, dir };
    bevy_manifold_core::trace::flow(tables, ray, rng.next_f64() * reach, 64)
        .ray
        .origin
}

/// Overlaps through the faces against brute force over the images, in
/// every space of the catalog: 2,000 random pairs of balls each (10^4 in
/// all), radii from 0.01 to 0.26 of the inradius, the first centre
/// anywhere in the domain and the second anywhere (half the cases) or
/// within 1.2 times the radii's sum of it (the rest, often through a
/// face). `ball_contacts` gives exactly the images of the second centre
/// within the radii's sum of the first among the whole group near the
/// domain ([`group_within`]), at the same distances.
#[test]
fn contacts_are_the_overlapping_images_of_brute_force_in_every_space() {
    use bevy_manifold_core::trace::FaceTables;
    let mut rng = Rng(29);
    let (mut cases, mut overlaps, mut through_faces) = (0, 0, 0);
    for name in catalog::NAMES {
        let space = catalog::resolve(name).expect("a catalog space");
        let g = space.geometry();
        let tables = FaceTables::<f64>::new(&space);
        let r = space.inradius();
        // Both centres within the circumradius of the domain's, the radii
        // adding up to at most 0.52 r.
        let group = group_within(&space, 2.0 * space.circumradius() + 0.52 * r);
        for case in 0..2000 {
            let ra = (0.01 + 0.25 * rng.next_f64()) * r;
            let rb = (0.01 + 0.25 * rng.next_f64()) * r;
            let p = anywhere(&mut rng, &space, &tables);
            let q = if case % 2 == 0 {
                anywhere(&mut rng, &space, &tables)
            } else {
                near(&mut rng, &space, &tables, p, 1.2 * (ra + rb))
            };
            let want: Vec<f64> = group_distances(&space, &group, p, q)
                .into_iter()
                .filter(|d| *d < ra + rb)
                .collect();
            let mut got: Vec<f64> = contact::ball_contacts(&space, (p, ra), (q, rb))
                .iter()
                .map(|c| c.image.distance)
                .collect();
            got.sort_by(f64::total_cmp);
            assert_eq!(got.len(), want.len(), "{name}: {got:?} against {want:?}");
            assert!(
                got.iter().zip(&want).all(|(a, b)| (a - b).abs() < 1e-9),
                "{name}: {got:?} against {want:?}"
            );
            cases += 1;
            overlaps += want.len();
            let direct = g.distance::<f64>(p, q);
            through_faces += usize::from(want.iter().any(|d| (d - direct).abs() > 1e-9));
        }
    }
    eprintln!("{cases} cases: {overlaps} overlapping images; {through_faces} cases touch through a face");
    assert_eq!(cases, 10_000);
    assert!(through_faces > 400, "the cases reach over the faces: {through_faces}");
}

/// A ball swept along a geodesic (the cast against the other ball grown
/// by its radius) never passes through another: 400 random sweeps in
/// each space, each sampled every 1/20 of the radii's sum along its path
/// through the faces. Where a sample overlaps an image of the other
/// ball (brute force over [`group_within`]), the sweep has reported a
/// touch no later; where it reports one, the balls just touch there.
#[test]
fn a_sweep_never_tunnels_through_a_ball() {
    use bevy_manifold_core::trace::{CastBall, FaceTables, cast_balls, flow};
    let mut rng = Rng(31);
    let mut touched = 0;
    for name in catalog::NAMES {
        let space = catalog::resolve(name).expect("a catalog space");
        let g = space.geometry();
        let tables = FaceTables::<f64>::new(&space);
        let r = space.inradius();
        let length = 1.5 * r;
        // Every sample and the other ball are within the circumradius of
        // the centre, and the radii add up to at most 0.22 r.
        let group = group_within(&space, 2.0 * space.circumradius() + 0.22 * r);
        for _ in 0..400 {
            let (ra, rb) = ((0.01 + 0.1 * rng.next_f64()) * r, (0.01 + 0.1 * rng.next_f64()) * r);
            let ray = rng.ray_inside(&space);
            // The other ball near the sweep's path, often over a face:
            // up to 1.5 times the radii's sum off a point of it.
            let on_path = flow(&tables, ray, (0.2 + 1.2 * rng.next_f64()) * r, 64).ray.origin;
            let q = near(&mut rng, &space, &tables, on_path, 1.5 * (ra + rb));
            let sweep = cast_balls(
                &space,
                &tables,
                ray,
                &[CastBall {
                    key: 0u8,
                    center: q,
                    radius: ra + rb,
                }],
                length,
                64,
            );
            let first = sweep.first().map(|h| h.distance);
            let step = (ra + rb) / 20.0;
            let nearest = |p: DVec4| {
                group
                    .iter()
                    .map(|w| g.distance::<f64>(p, g.normalize_point::<f64>(*w * q)))
                    .fold(f64::INFINITY, f64::min)
            };
            if nearest(ray.origin) < ra + rb {
                // Touching already: not a sweep towards the ball.
                continue;
            }
            let mut at = ray;
            let mut t = 0.0;
            while t <= length {
                if nearest(at.origin) < ra + rb {
                    assert!(
                        first.is_some_and(|f| f <= t + 1e-9),
                        "{name}: the balls overlap {t} along, the sweep says {first:?}"
                    );
                    break;
                }
                at = flow(&tables, at, step, 64).ray;
                t += step;
            }
            if let Some(f) = first {
                let there = flow(&tables, ray, f, 64).ray.origin;
                assert!(
                    (nearest(there) - (ra + rb)).abs() < 1e-7,
                    "{name}: at {f} the gap is {}",
                    nearest(there) - (ra + rb)
                );
                touched += 1;
            }
        }
    }
    eprintln!("{touched} of 2000 sweeps touch");
    assert!(touched > 800, "the sweeps touch: {touched}");
}
