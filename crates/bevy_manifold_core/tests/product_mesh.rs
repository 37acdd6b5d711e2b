//! Meshes in the product spaces (`ProductMesh`), against answers found
//! without the tracer's machinery (no BVH, no chart curve, no Newton):
//! the ray is sampled every 1e-3 along its exact geodesic, each sample
//! taken into the mesh's chart by the placement's inverse and tested
//! against the solid the mesh bounds (a box or an octahedron, in chart
//! coordinates), and the first sample inside is bisected to 1e-13. The
//! normals are checked against the geometry of the models: a wall over a
//! geodesic of the surface has the line's normal, and a slanted face's
//! normal is orthogonal, in the product metric, to its tangents pushed
//! forward by finite differences of the chart.

use bevy_manifold_core::geometry::product::{ProductGeometry, ProductIsometry, ProductPoint, ProductTangent};
use bevy_manifold_core::mesh::shapes::cuboid;
use bevy_manifold_core::mesh::{MeshData, TriMesh};
use bevy_manifold_core::space::product::ProductSpace;
use bevy_manifold_core::trace::product::mesh::{chart_of, chart_point};
use bevy_manifold_core::trace::product::{
    LightArc, ProductMesh, ProductMeshError, ProductObjects, ProductRay, ProductScene, hits_in, render, shadowed,
};
use glam::DVec3;
use std::sync::Arc;

/// The box `[-a, a]^3` of the chart, 12 triangles, flat-shaded.
fn cube(a: f32) -> Arc<MeshData> {
    MeshData::shared(cuboid([a; 3]))
}

/// The octahedron `|x| + |y| + |z| <= a` of the chart (slanted faces),
/// flat-shaded (no vertex normals of its own: one per face).
fn octahedron(a: f32) -> Arc<MeshData> {
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    for sx in [-1.0f32, 1.0] {
        for sy in [-1.0f32, 1.0] {
            for sz in [-1.0f32, 1.0] {
                let k = positions.len() as u32;
                positions.extend([[sx * a, 0.0, 0.0], [0.0, sy * a, 0.0], [0.0, 0.0, sz * a]]);
                triangles.push([k, k + 1, k + 2]);
            }
        }
    }
    MeshData::shared(TriMesh::new(positions, None, None, triangles).unwrap())
}

/// What rays meet in `space`: the one mesh, placed, with `id`.
fn alone(space: &ProductSpace, mesh: Arc<MeshData>, placement: ProductIsometry, id: u32) -> ProductObjects {
    ProductObjects::new(space, &[], None, &[ProductMesh { mesh, placement, id }])
}

/// A random generator (xorshift), in [0, 1).
fn rng(mut seed: u64) -> impl FnMut() -> f64 {
    move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The first distance in `[0, end]` at which the ray is inside the solid
/// (`inside`, of chart points), sampled every 1e-3 and bisected; `None`
/// where no sample is inside, and `Some(None)` where a sample comes within
/// 1e-5 of the surface without entering (too near a graze to say).
fn sampled_entry(
    g: ProductGeometry,
    to_chart: &ProductIsometry,
    ray: ProductRay,
    end: f64,
    inside: &dyn Fn(DVec3) -> f64,
) -> Option<Option<f64>> {
    // `inside(q)` is the solid's gauge minus its size: <= 0 inside.
    let gap = |s: f64| {
        inside(chart_of(
            g.normalize_point(to_chart.apply(g.exp(ray.origin, ray.dir, s).0)),
        ))
    };
    let steps = (end / 1e-3) as usize;
    let mut least = f64::INFINITY;
    for i in 1..=steps {
        let s = i as f64 * 1e-3;
        let f = gap(s);
        if f <= 0.0 {
            let (mut lo, mut hi) = (s - 1e-3, s);
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if gap(mid) <= 0.0 { hi = mid } else { lo = mid }
            }
            return Some(Some(hi));
        }
        least = least.min(f);
    }
    if least < 1e-5 { Some(None) } else { None }
}

/// A placement: the surface turned by `angle`, moved `d` along x, lifted
/// by `h`.
fn placed(g: ProductGeometry, d: f64, angle: f64, h: f64) -> ProductIsometry {
    ProductIsometry::new(g.translation(0.0, d) * g.rotation(angle), 1.0, h)
}

/// Random rays from points around the mesh, aimed near its centre: the
/// tracer's first entry against the sampled one, to 1e-9, in a space
/// large enough that the rays cross no face (an H2 prism's and S2's
/// whole sphere: no sides near).
fn entries_agree(mesh: Arc<MeshData>, inside: &dyn Fn(DVec3) -> f64, seed: u64) {
    for space in [ProductSpace::s2_x_s1(40.0), ProductSpace::genus_two_x_s1(40.0)] {
        let placement = placed(space.geometry, 0.2, 0.7, 0.3);
        entries_agree_in(&space, placement, (mesh.clone(), inside), seed);
    }
}

/// [`entries_agree`] for one space and placement: the rays cross at most
/// 8 faces (the sampled ray runs on in the universal cover, where the
/// mesh is where its placement puts it).
fn entries_agree_in(
    space: &ProductSpace,
    placement: ProductIsometry,
    (mesh, inside): (Arc<MeshData>, &dyn Fn(DVec3) -> f64),
    seed: u64,
) {
    let g = space.geometry;
    let objects = alone(space, mesh.clone(), placement, 5);
    let to_chart = placement.inverse(g);
    let center = placement.apply(ProductPoint::ORIGIN);
    let mut random = rng(seed);
    let (mut hits, mut misses, mut skipped) = (0, 0, 0);
    for k in 0..600 {
        let from = ProductPoint::new(
            chart_point(g, DVec3::new(0.8 * random() - 0.4, 0.8 * random() - 0.4, 0.0)).surface,
            0.3 + 1.2 * random() - 0.6,
        );
        let (toward, d) = g.log(from, center).unwrap();
        let side = g.normalize_tangent(
            from,
            ProductTangent::new(
                DVec3::new(random() - 0.5, random() - 0.5, random() - 0.5),
                random() - 0.5,
            ),
        );
        let off = 0.6 * random();
        let dir = g.normalize_tangent(
            from,
            ProductTangent::new(toward.surface + side.surface * off, toward.height + side.height * off),
        );
        let ray = ProductRay { origin: from, dir };
        if inside(chart_of(to_chart.apply(from))) <= 0.0 {
            continue;
        }
        let end = d + 0.5;
        let seen = hits_in(space, &objects, ray, end, 8);
        match sampled_entry(g, &to_chart, ray, end, inside) {
            Some(None) => skipped += 1,
            None => {
                assert!(
                    seen.is_empty(),
                    "{} ray {k}: sampled a miss, traced {:?}",
                    g.name(),
                    seen[0].distance
                );
                misses += 1;
            }
            Some(Some(s)) => {
                let hit = seen
                    .first()
                    .unwrap_or_else(|| panic!("{} ray {k}: sampled {s}", g.name()));
                assert_eq!(hit.object, 5);
                assert!(
                    (hit.distance - s).abs() < 1e-9,
                    "{} ray {k}: traced {}, sampled {s}",
                    g.name(),
                    hit.distance
                );
                // The normal faces the ray.
                assert!(g.dot(hit.normal, hit.dir) < 0.0);
                hits += 1;
            }
        }
    }
    eprintln!("{}: {hits} hits, {misses} misses, {skipped} too near a graze", g.name());
    assert!(hits > 150 && misses > 50 && skipped < 10, "{hits} {misses} {skipped}");
}

#[test]
fn a_box_is_entered_where_the_sampled_ray_first_enters_it() {
    let a = 0.15625;
    entries_agree(cube(a as f32), &|q| q.abs().max_element() - a, 1);
}

/// A box across a side of the genus-2 octagon, half in the prism and half
/// in the next copy: the tracer sees it as its image through the side's
/// gluing, the sampled ray (in the universal cover) as one box.
#[test]
fn a_box_across_a_face_is_entered_where_the_sampled_ray_enters_it() {
    let space = ProductSpace::genus_two_x_s1(40.0);
    let g = space.geometry;
    // The foot of the perpendicular from the origin to side 0's line
    // <n, p> = 0: at distance atanh(n_w / |n_xy|) along n_xy.
    let n = space.sides[0];
    let across = n.truncate().length();
    let placement = ProductIsometry::new(
        g.translation(n.y.atan2(n.x), (n.z / across).atanh()) * g.rotation(0.3),
        1.0,
        0.3,
    );
    let foot = placement.apply(ProductPoint::ORIGIN);
    assert!(g.form(n, foot.surface).abs() < 1e-12);
    let a = 0.15625;
    entries_agree_in(
        &space,
        placement,
        (cube(a as f32), &|q: DVec3| q.abs().max_element() - a),
        3,
    );
}

#[test]
fn an_octahedron_is_entered_where_the_sampled_ray_first_enters_it() {
    let a = 0.25;
    entries_agree(octahedron(a as f32), &|q| q.x.abs() + q.y.abs() + q.z.abs() - a, 2);
}

/// A box's wall at chart `x = a` lies over the surface's geodesic
/// `x - a w = 0`: its normal is that line's, the form's gradient `(1, 0,
/// -a / k)`, with no height. Its top's is straight up. Both met from the
/// chart's origin in closed form: the wall after `atanh a` (`atan a`) of
/// surface, the top where the height reaches `a`.
#[test]
fn a_boxs_walls_and_top_have_the_models_normals_and_distances() {
    let a = 0.3125f64;
    for space in [ProductSpace::s2_x_s1(40.0), ProductSpace::genus_two_x_s1(40.0)] {
        let g = space.geometry;
        let k = g.curvature();
        let objects = alone(&space, cube(a as f32), ProductIsometry::IDENTITY, 1);
        let across = match g {
            ProductGeometry::H2xR => a.atanh(),
            ProductGeometry::S2xR => a.atan(),
        };
        // From the origin, inside the box: out through the wall at 10
        // degrees up, and through the top at 80.
        for (degrees, wall) in [(10.0f64, true), (80.0, false)] {
            let t = degrees.to_radians();
            let dir = ProductTangent::new(DVec3::X * t.cos(), t.sin());
            let ray = ProductRay {
                origin: ProductPoint::ORIGIN,
                dir,
            };
            let hit = &hits_in(&space, &objects, ray, 2.0, 0)[0];
            if wall {
                assert!((hit.distance - across / t.cos()).abs() < 1e-9, "{}", hit.distance);
                let m = DVec3::new(1.0, 0.0, -a / k);
                let expected = g.normalize_tangent(hit.point, ProductTangent::new(m, 0.0));
                let cos = g.dot(hit.normal, expected);
                assert!((cos.abs() - 1.0).abs() < 1e-9, "{} wall: cos {cos}", g.name());
            } else {
                assert!((hit.distance - a / t.sin()).abs() < 1e-9, "{}", hit.distance);
                assert!((hit.normal.height.abs() - 1.0).abs() < 1e-9);
            }
            // From inside, the wall faces back at the ray.
            assert!(g.dot(hit.normal, hit.dir) < 0.0);
        }
    }
}

/// An octahedron's face `x + y + z = a` (in the positive octant): the
/// hit's normal is orthogonal, in the product metric, to the face's two
/// edge directions pushed forward by the chart (central differences).
#[test]
fn a_slanted_faces_normal_is_orthogonal_to_the_face() {
    let a = 0.375;
    for g in [ProductGeometry::H2xR, ProductGeometry::S2xR] {
        let space = match g {
            ProductGeometry::H2xR => ProductSpace::genus_two_x_s1(40.0),
            ProductGeometry::S2xR => ProductSpace::s2_x_s1(40.0),
        };
        let objects = alone(&space, octahedron(a as f32), ProductIsometry::IDENTITY, 1);
        // From the chart's point (0.3, 0.3, 0.3) (outside) back towards
        // the origin.
        let from = chart_point(g, DVec3::splat(0.3));
        let (dir, _) = g.log(from, ProductPoint::ORIGIN).unwrap();
        let hit = &hits_in(&space, &objects, ProductRay { origin: from, dir }, 2.0, 0)[0];
        let q = chart_of(hit.point);
        assert!((q.x + q.y + q.z - a).abs() < 1e-9, "{q}");
        let push = |e: DVec3| {
            let h = 1e-6;
            let (p, m) = (chart_point(g, q + e * h), chart_point(g, q - e * h));
            ProductTangent::new((p.surface - m.surface) / (2.0 * h), (p.height - m.height) / (2.0 * h))
        };
        for e in [DVec3::new(1.0, -1.0, 0.0), DVec3::new(0.0, 1.0, -1.0)] {
            let t = push(e);
            let cos = g.dot(hit.normal, t) / t.length(g);
            assert!(cos.abs() < 1e-8, "{}: {cos}", g.name());
        }
        assert!((hit.normal.length(g) - 1.0).abs() < 1e-12);
    }
}

/// Straight up S2 x S1 of circle 2 from under a box: its bottom, then its
/// copies every 2 (the mesh's images through the top and bottom); round
/// the sphere the other way, the box's far wall after `2 pi - atan` of
/// its chart coordinate.
#[test]
fn a_mesh_repeats_up_the_circle_and_round_the_sphere() {
    let space = ProductSpace::s2_x_s1(2.0);
    let g = space.geometry;
    let box_at = |x: f64, h: f64| ProductMesh {
        mesh: cube(0.125),
        placement: ProductIsometry::new(g.translation(0.0, x.atan()), 1.0, h),
        id: 1,
    };
    let objects = ProductObjects::new(&space, &[], None, &[box_at(0.0, 0.85)]);
    let up = ProductRay {
        origin: ProductPoint::ORIGIN,
        dir: ProductTangent::new(DVec3::ZERO, 1.0),
    };
    let at: Vec<f64> = hits_in(&space, &objects, up, 5.0, 8)
        .iter()
        .map(|h| h.distance)
        .collect();
    assert_eq!(at.len(), 3, "{at:?}");
    for (k, d) in at.iter().enumerate() {
        assert!((d - (0.725 + 2.0 * k as f64)).abs() < 1e-9, "{at:?}");
    }
    // Round the sphere along -x, the ray meets the box's far wall: at
    // its chart's x = 0.125, surface angle atan(0.5) + atan(0.125) from
    // the origin (the box's centre is atan(0.5) along x).
    let objects = ProductObjects::new(&space, &[], None, &[box_at(0.5, 0.0)]);
    let back = ProductRay {
        origin: ProductPoint::ORIGIN,
        dir: ProductTangent::new(DVec3::NEG_X, 0.0),
    };
    let hit = &hits_in(&space, &objects, back, 7.0, 8)[0];
    let wall = 0.5f64.atan() + 0.125f64.atan();
    assert!(
        (hit.distance - (std::f64::consts::TAU - wall)).abs() < 1e-9,
        "{}",
        hit.distance
    );
}

/// A mesh casts shadows: a box between a point and its light blocks the
/// way, and the way beside it is free.
#[test]
fn a_mesh_shadows_a_light() {
    let space = ProductSpace::genus_two_x_s1(4.0);
    let g = space.geometry;
    let objects = alone(
        &space,
        cube(0.125),
        ProductIsometry::new(g.translation(0.0, 0.3), 1.0, 0.0),
        1,
    );
    let up = ProductTangent::new(DVec3::ZERO, 1.0);
    let arc = |surface: DVec3| LightArc {
        dir: ProductTangent::new(surface, 0.0),
        length: 0.6,
        surface: 0.6,
    };
    let x = (ProductPoint::ORIGIN, up);
    assert!(shadowed(&space, &objects, x, &arc(DVec3::X), 8));
    assert!(!shadowed(&space, &objects, x, &arc(DVec3::Y), 8));
}

/// The view sees a mesh in its colour and lights it from the eye: the
/// centre pixel of a view looking at a box shows it, at the box's
/// distance.
#[test]
fn a_view_sees_a_mesh() {
    let space = ProductSpace::genus_two_x_s1(2.0);
    let g = space.geometry;
    let mut scene = ProductScene::default_for(&space);
    scene.balls.clear();
    let view = scene.view;
    // A box 0.5 ahead of the eye (its face about 0.375 ahead).
    let center = g.exp(view.eye, view.frame[0], 0.5).0;
    let (toward, _) = g
        .log(ProductPoint::ORIGIN, ProductPoint::new(center.surface, 0.0))
        .unwrap();
    let d = g.surface_distance(DVec3::Z, center.surface);
    let angle = toward.surface.y.atan2(toward.surface.x);
    scene.meshes.push(ProductMesh {
        mesh: cube(0.125),
        placement: ProductIsometry::new(g.translation(angle, d), 1.0, center.height),
        id: 4,
    });
    let pixels = render(&space, &scene, 9, 9);
    let mid = pixels[4 * 9 + 4];
    assert_eq!(mid.object, 4);
    assert!(mid.distance > 0.3 && mid.distance < 0.42, "{}", mid.distance);
    assert!(pixels[0].object == 0);
}

/// A mesh that cannot stand in H2xR (a vertex outside the Klein disc) or
/// whose placement is not an isometry is refused by name, and left out of
/// what rays meet.
#[test]
fn a_mesh_outside_the_chart_or_badly_placed_is_refused() {
    let space = ProductSpace::genus_two_x_s1(2.0);
    let g = space.geometry;
    let wide = ProductMesh {
        mesh: cube(0.75),
        placement: ProductIsometry::IDENTITY,
        id: 1,
    };
    // (0.75, 0.75) is outside the unit disc.
    match wide.check(g) {
        Err(ProductMeshError::OutsideChart { rho2, .. }) => assert_eq!(rho2, 1.125),
        other => panic!("{other:?}"),
    }
    // In S2xR the gnomonic chart takes it.
    assert!(wide.check(ProductGeometry::S2xR).is_ok());
    let nan = ProductMesh {
        placement: ProductIsometry::new(g.translation(0.0, f64::NAN), 1.0, 0.0),
        ..wide.clone()
    };
    assert!(matches!(nan.check(g), Err(ProductMeshError::Placement(_))));
    let up = ProductRay {
        origin: ProductPoint::ORIGIN,
        dir: ProductTangent::new(DVec3::X, 0.0),
    };
    assert!(
        hits_in(
            &space,
            &ProductObjects::new(&space, &[], None, &[wide, nan]),
            up,
            3.0,
            8
        )
        .is_empty()
    );
}
