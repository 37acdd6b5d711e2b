//! The product geometries H2xR and S2xR and their compact spaces, checked
//! against facts of geometry: volumes by integration and Gauss-Bonnet,
//! closed geodesics of known lengths, the copies of the circle and of the
//! octagon tiling where the Poincare disk puts them, and a million
//! crossings that keep the ray on the model.

use bevy_manifold_core::geometry::product::{ProductGeometry, ProductIsometry, ProductPoint, ProductTangent};
use bevy_manifold_core::space::product::{ProductGluing, ProductSpace, ProductSpaceError};
use bevy_manifold_core::space::product_cells::ProductElement;
use bevy_manifold_core::trace::product::{ProductBall, ProductRay, exit_face, flow, hits};
use glam::DVec3;
use std::f64::consts::{PI, TAU};

/// The unit tangent along the surface in direction `angle` at the
/// origin, tilted up by `up` radians.
fn direction(angle: f64, up: f64) -> ProductTangent {
    ProductTangent::new(DVec3::new(angle.cos(), angle.sin(), 0.0) * up.cos(), up.sin())
}

fn ray(origin: ProductPoint, dir: ProductTangent) -> ProductRay {
    ProductRay { origin, dir }
}

/// The point at surface distance `d` from the origin in direction
/// `angle`, at height `h`, built from its coordinates (hyperboloid or
/// sphere).
fn point(g: ProductGeometry, angle: f64, d: f64, h: f64) -> ProductPoint {
    let (c, s) = match g {
        ProductGeometry::H2xR => (d.cosh(), d.sinh()),
        ProductGeometry::S2xR => (d.cos(), d.sin()),
    };
    ProductPoint::new(DVec3::new(s * angle.cos(), s * angle.sin(), c), h)
}

fn catalog() -> Vec<ProductSpace> {
    vec![
        ProductSpace::s2_x_s1(1.5),
        ProductSpace::twisted_s2_x_s1(1.5, 3),
        ProductSpace::genus_two_x_s1(0.8),
        ProductSpace::twisted_genus_two_x_s1(0.8, 1),
        ProductSpace::mirrored_prism(5, 0.6),
    ]
}

#[test]
fn geodesics_are_exact_and_isometries_keep_distances() {
    for g in [ProductGeometry::H2xR, ProductGeometry::S2xR] {
        let p = point(g, 0.3, 0.7, -0.2);
        let v = g.normalize_tangent(p, ProductTangent::new(DVec3::new(0.4, -0.9, 0.1), 0.35));
        for s in [0.1, 0.9, 1.7] {
            let (q, w) = g.exp(p, v, s);
            assert!(g.point_error(q) < 1e-12 && (w.length(g) - 1.0).abs() < 1e-12);
            // Along a geodesic, short of the sphere's antipode, the
            // distance is the arc length.
            assert!((g.distance(p, q) - s).abs() < 1e-12, "{g:?} s = {s}");
            let (back, d) = g.log(p, q).expect("distinct points");
            assert!((d - s).abs() < 1e-12);
            assert!((back.surface - v.surface).length() < 1e-9 && (back.height - v.height).abs() < 1e-9);
        }
        // An isometry (a turn, a translation, a reflection, a flip of the
        // line) keeps distances.
        let m = ProductIsometry::new(
            g.rotation(1.1) * g.translation(0.4, 0.9) * g.reflection(DVec3::X),
            -1.0,
            2.5,
        );
        assert!(g.isometry_error(m.surface) < 1e-12);
        let q = point(g, 2.0, 0.4, 0.8);
        assert!((g.distance(m.apply(p), m.apply(q)) - g.distance(p, q)).abs() < 1e-12);
        let back = m.inverse(g).compose(&m);
        assert!(back.surface.abs_diff_eq(glam::DMat3::IDENTITY, 1e-12) && back.flip == 1.0 && back.shift.abs() < 1e-12);
    }
}

/// The geodesic sphere's area against a different algorithm: the area
/// element of the exponential map measured by finite differences of
/// distances on a grid of directions.
#[test]
fn the_geodesic_spheres_area_is_what_the_exponential_map_sweeps() {
    for g in [ProductGeometry::H2xR, ProductGeometry::S2xR] {
        for d in [0.05, 1.5, 2.5] {
            let at = |a: f64, t: f64| g.exp(ProductPoint::ORIGIN, direction(t, a), d).0;
            let (na, nt) = (400, 64);
            let (da, dt) = (PI / f64::from(na), TAU / f64::from(nt));
            let mut area = 0.0;
            for i in 0..na {
                let a = -PI / 2.0 + (f64::from(i) + 0.5) * da;
                // Rotation about the origin is an isometry, so every
                // theta sweeps the same: one column, times the turn.
                let h = 1e-6;
                let along_a = g.distance(at(a + h, 0.0), at(a - h, 0.0)) / (2.0 * h);
                let along_t = g.distance(at(a, h), at(a, -h)) / (2.0 * h);
                area += along_a * along_t * da * dt * f64::from(nt);
            }
            let want = g.sphere_area(d);
            assert!(
                (area - want).abs() < 2e-4 * want,
                "{g:?} d = {d}: swept {area}, sphere_area {want}"
            );
        }
        // Small spheres are Euclidean ones.
        assert!((g.sphere_area(1e-3) / (4.0 * PI * 1e-6) - 1.0).abs() < 1e-6);
    }
}

#[test]
fn the_catalog_validates_and_broken_spaces_are_named() {
    for space in catalog() {
        space.validate().unwrap_or_else(|e| panic!("{}: {e}", space.name));
    }
    // A gluing that misses its partner side.
    let mut wrong = ProductSpace::genus_two_x_s1(1.0);
    let g = wrong.geometry;
    wrong.gluings[2] = ProductGluing::Paired {
        partner: 6,
        pairing: ProductIsometry::new(g.translation(PI / 2.0, -2.0), 1.0, 0.0),
    };
    assert!(matches!(
        wrong.validate(),
        Err(ProductSpaceError::Gluing { face: 2, .. })
    ));
    // Corners whose angles do not close up: the octagon with angles
    // pi/3, glued as the genus-2 surface (8 pi/3 round the one vertex).
    let mut cone = ProductSpace::genus_two_x_s1(1.0);
    let (sides, r) = ProductSpace::regular_polygon(g, 8, PI / 3.0);
    cone.sides = sides;
    cone.angles = vec![PI / 3.0; 8];
    for (i, gl) in cone.gluings.iter_mut().take(8).enumerate() {
        *gl = ProductGluing::Paired {
            partner: (i + 4) % 8,
            pairing: ProductIsometry::new(g.translation(TAU * i as f64 / 8.0, -2.0 * r), 1.0, 0.0),
        };
    }
    assert!(matches!(cone.validate(), Err(ProductSpaceError::VertexCycle { .. })));
    let mut flat = ProductSpace::s2_x_s1(1.0);
    flat.height = f64::NAN;
    let e = flat.validate().unwrap_err();
    assert!(e.to_string().contains("height"), "{e}");
}

/// Volumes: S2 x S1 of circle L is 4 pi L; a genus-2 surface has area
/// 4 pi (Gauss-Bonnet); the right-angled pentagon pi / 2. The polygons'
/// areas are also integrated in polar coordinates about the centre,
/// `integral of (cosh rho(theta) - 1) dtheta`, with `rho` the distance to
/// the boundary that `exit_face` finds.
#[test]
fn volumes_are_the_surfaces_areas_times_the_circle() {
    for (space, area) in [
        (ProductSpace::s2_x_s1(1.5), 4.0 * PI),
        (ProductSpace::twisted_s2_x_s1(1.5, 3), 4.0 * PI),
        (ProductSpace::genus_two_x_s1(0.8), 4.0 * PI),
        (ProductSpace::twisted_genus_two_x_s1(0.8, 1), 4.0 * PI),
        (ProductSpace::mirrored_prism(5, 0.6), PI / 2.0),
    ] {
        assert!((space.volume() - area * space.height).abs() < 1e-9, "{}", space.name);
        if space.sides.is_empty() {
            continue;
        }
        let n = 80_000;
        let integrated: f64 = (0..n)
            .map(|i| {
                let t = TAU * (f64::from(i) + 0.5) / f64::from(n);
                let (_, rho) = exit_face(&space, &ray(ProductPoint::ORIGIN, direction(t, 0.0)), None).unwrap();
                (rho.cosh() - 1.0) * TAU / f64::from(n)
            })
            .sum();
        assert!(
            (integrated - area).abs() < 1e-6,
            "{}: integrated {integrated}",
            space.name
        );
    }
    // The octagon's corners are pi / 4 by their sides' normals:
    // cos(angle) = -<n0, n1>.
    let octagon = ProductSpace::genus_two_x_s1(1.0);
    let g = octagon.geometry;
    let cos = -g.form(octagon.sides[0], octagon.sides[1]);
    assert!((cos - (PI / 4.0).cos()).abs() < 1e-12);
}

/// Closed geodesics: up the circle after L; round a great circle of the
/// sphere after 2 pi; along the axis of a genus-2 gluing after its
/// translation length, from the gluing's trace (an SO(2,1) translation
/// by l has trace 1 + 2 cosh l; in SL(2,R), 2 cosh(l/2), so l =
/// 2 acosh(|tr|/2)).
#[test]
fn closed_geodesics_close_after_their_lengths() {
    let closes = |space: &ProductSpace, r: ProductRay, length: f64| {
        let g = space.geometry;
        let end = flow(space, r, length, 1000).ray;
        g.distance(end.origin, r.origin) < 1e-9 && (end.dir.surface - r.dir.surface).length() < 1e-9
    };
    let s2 = ProductSpace::s2_x_s1(1.5);
    let up = direction(0.0, PI / 2.0);
    for p in [ProductPoint::ORIGIN, point(s2.geometry, 1.0, 1.2, 0.3)] {
        let dir = s2.geometry.normalize_tangent(p, up);
        assert!(closes(&s2, ray(p, dir), 1.5));
        assert!(!closes(&s2, ray(p, dir), 0.75));
    }
    assert!(closes(&s2, ray(ProductPoint::ORIGIN, direction(0.4, 0.0)), TAU));
    assert!(!closes(&s2, ray(ProductPoint::ORIGIN, direction(0.4, 0.0)), PI));

    // The octagon's inradius by trigonometry (right triangle centre,
    // side midpoint, corner: cos(pi/8) = cosh r sin(pi/8)).
    let r = (1.0 / (PI / 8.0).tan()).acosh();
    let genus2 = ProductSpace::genus_two_x_s1(0.8);
    for (i, gluing) in genus2.gluings.iter().take(8).enumerate() {
        // The gluing as an element of SO(2,1), the adjoint form of
        // PSL(2,R): its SL(2,R) trace squared is its trace plus 1.
        let m = gluing.isometry().surface;
        let tr = (m.x_axis.x + m.y_axis.y + m.z_axis.z + 1.0).sqrt();
        let l = 2.0 * (tr / 2.0).acosh();
        assert!(
            (l - 2.0 * r).abs() < 1e-9,
            "gluing {i}: length {l}, across the octagon {}",
            2.0 * r
        );
        let along = ray(ProductPoint::ORIGIN, direction(TAU * i as f64 / 8.0, 0.0));
        assert!(closes(&genus2, along, l), "gluing {i}'s axis");
        assert!(!closes(&genus2, along, l / 2.0));
    }
    // A twisted circle: the sphere turned by a third, the genus-2 surface
    // by an eighth, each time round. Vertical geodesics through the
    // centre of the turn close after L; the others after 3 L and 8 L.
    for (space, order) in [
        (ProductSpace::twisted_s2_x_s1(1.5, 3), 3),
        (ProductSpace::twisted_genus_two_x_s1(0.8, 1), 8),
    ] {
        let g = space.geometry;
        let l = space.height;
        assert!(closes(&space, ray(ProductPoint::ORIGIN, up), l), "{}", space.name);
        let off = point(g, 0.2, 0.5, 0.0);
        let dir = g.normalize_tangent(off, up);
        assert!(!closes(&space, ray(off, dir), l), "{}", space.name);
        assert!(closes(&space, ray(off, dir), l * f64::from(order)), "{}", space.name);
    }
}

/// Looking straight up in S2 x S1 of circle L: a ball above the eye and
/// its copies every L up the circle. In the sphere turned by a third each
/// time round, a ball off the poles comes back over the eye only every
/// 3 L.
#[test]
fn the_view_straight_up_repeats_the_scene_every_circle() {
    let (l, radius, above) = (1.7, 0.1, 0.45);
    for (space, every) in [
        (ProductSpace::s2_x_s1(l), 1.0),
        (ProductSpace::twisted_s2_x_s1(l, 3), 3.0),
    ] {
        let g = space.geometry;
        let eye = point(g, 0.7, 0.9, -0.3);
        let ball = ProductBall {
            center: ProductPoint::new(eye.surface, eye.height + above),
            radius,
            id: 7,
        };
        let up = g.normalize_tangent(eye, ProductTangent::new(DVec3::ZERO, 1.0));
        let seen = hits(&space, &[ball], ray(eye, up), 10.0 * l, 64);
        let want: Vec<f64> = (0..)
            .map(|k| above - radius + every * l * f64::from(k))
            .take_while(|d| *d < 10.0 * l)
            .collect();
        let got: Vec<f64> = seen.iter().map(|h| h.distance).collect();
        assert_eq!(got.len(), want.len(), "{}: {got:?} against {want:?}", space.name);
        for (a, b) in got.iter().zip(&want) {
            assert!((a - b).abs() < 1e-9, "{}: {got:?} against {want:?}", space.name);
        }
        assert!(seen.iter().all(|h| h.object == 7));
    }
}

/// The Poincare disk's Mobius map of the translation by `l` along the
/// direction `angle`: `z -> e^(i a) A(e^(-i a) z)`, `A(z) = (z + t) / (1 +
/// t z)` with `t = tanh(l / 2)`. Complex numbers as pairs.
fn disk_translation(angle: f64, l: f64) -> impl Fn((f64, f64)) -> (f64, f64) {
    let t = (l / 2.0).tanh();
    let (c, s) = (angle.cos(), angle.sin());
    move |(x, y)| {
        let (x, y) = (x * c + y * s, y * c - x * s);
        // (z + t) / (1 + t z)
        let (nx, ny) = (x + t, y);
        let (dx, dy) = (1.0 + t * x, t * y);
        let d = dx * dx + dy * dy;
        let (qx, qy) = ((nx * dx + ny * dy) / d, (ny * dx - nx * dy) / d);
        (qx * c - qy * s, qy * c + qx * s)
    }
}

/// Looking along the surface in genus 2 x S1: a ball's copies are where
/// the octagon tiling of the Poincare disk puts them. The tiling is made
/// here from Mobius maps (the translations across the octagon, by twice
/// the inradius of trigonometry), not from the space's matrices; a ray
/// aimed at each copy's disk position enters it at the copy's hyperbolic
/// distance less the radius.
#[test]
fn the_view_along_the_surface_shows_the_octagon_tiling() {
    let space = ProductSpace::genus_two_x_s1(0.8);
    let g = space.geometry;
    let r = (1.0 / (PI / 8.0).tan()).acosh();
    let (angle, d, radius) = (0.3, 0.5, 0.05);
    let ball = ProductBall {
        center: point(g, angle, d, 0.0),
        radius,
        id: 3,
    };
    let home = ((d / 2.0).tanh() * angle.cos(), (d / 2.0).tanh() * angle.sin());
    // Words of length 1 and 2 in the eight translations.
    let moves: Vec<_> = (0..8)
        .map(|i| disk_translation(TAU * f64::from(i) / 8.0, -2.0 * r))
        .collect();
    let mut copies = vec![];
    for a in &moves {
        copies.push(a(home));
        for b in &moves {
            copies.push(a(b(home)));
        }
    }
    let mut checked = 0;
    for (x, y) in copies {
        let rho = (x * x + y * y).sqrt();
        let distance = 2.0 * rho.atanh();
        if !(1e-6..=7.0).contains(&distance) {
            continue;
        }
        let aim = ray(ProductPoint::ORIGIN, direction(y.atan2(x), 0.0));
        let seen = hits(&space, &[ball], aim, distance + 1.0, 64);
        assert!(
            seen.iter().any(|h| (h.distance - (distance - radius)).abs() < 1e-7),
            "the copy at distance {distance} in direction {}: {:?}",
            y.atan2(x),
            seen.iter().map(|h| h.distance).collect::<Vec<_>>()
        );
        checked += 1;
    }
    assert!(checked >= 40, "{checked} copies checked");
}

/// A million crossings of the genus-2 prism: the ray stays on the model,
/// of unit speed and in the prism, its surface point renormalised at each
/// gluing.
#[test]
fn a_million_crossings_keep_the_ray_on_the_model() {
    let space = ProductSpace::genus_two_x_s1(0.37);
    let g = space.geometry;
    let start = point(g, 1.0, 0.2, 0.05);
    let dir = g.normalize_tangent(start, direction(0.123, 0.31));
    let walk = flow(&space, ray(start, dir), f64::INFINITY, 1_000_000);
    assert_eq!(walk.faces.len(), 1_000_000);
    let end = walk.ray;
    assert!(g.point_error(end.origin) < 1e-12, "{}", g.point_error(end.origin));
    assert!((end.dir.length(g) - 1.0).abs() < 1e-12);
    assert!(g.form(end.origin.surface, end.dir.surface).abs() < 1e-12);
    assert!(space.contains(end.origin, 1e-9));
    // Every side was crossed; the ray climbs, so it left through the
    // top and never the bottom.
    let mut count = vec![0; space.face_count()];
    walk.faces.iter().for_each(|f| count[*f] += 1);
    assert!(count[..8].iter().all(|c| *c > 10_000), "{count:?}");
    assert!(count[space.top()] > 10_000 && count[space.bottom()] == 0, "{count:?}");
}

/// The picture: looking straight up in S2 x S1 at a ball above the eye,
/// the middle pixel sees it at its distance, lit head-on; rays far from
/// the vertical miss it and its copies (the ball is small and the sphere
/// has nothing else).
#[test]
fn a_rendered_view_sees_what_the_rays_hit() {
    use bevy_manifold_core::trace::product::{ProductScene, ProductView, render};
    let space = ProductSpace::s2_x_s1(1.5);
    let ball = ProductBall {
        center: ProductPoint::new(DVec3::Z, 0.5),
        radius: 0.1,
        id: 1,
    };
    let view = ProductView {
        eye: ProductPoint::ORIGIN,
        frame: [
            ProductTangent::new(DVec3::ZERO, 1.0),
            ProductTangent::new(DVec3::X, 0.0),
            ProductTangent::new(DVec3::Y, 0.0),
        ],
        fov_y_degrees: 90.0,
        frustum: None,
        max_distance: 10.0,
        max_crossings: 16,
        fog: 0.0,
        cell: Some(ProductElement::IDENTITY),
        tint: None,
    };
    let image = render(&space, &ProductScene::new(vec![ball], view), 33, 33);
    let middle = image[16 * 33 + 16];
    assert_eq!(middle.object, 1);
    assert!((middle.distance - 0.4).abs() < 1e-9);
    // Lit from the eye: brightest head-on, darker towards the rim.
    let brightness = |c: [f32; 3]| c.iter().sum::<f32>();
    let rim = image
        .iter()
        .filter(|p| p.object == 1)
        .map(|p| brightness(p.color))
        .fold(f32::INFINITY, f32::min);
    assert!(
        image
            .iter()
            .all(|p| p.object != 1 || brightness(p.color) <= brightness(middle.color) + 1e-6)
    );
    assert!(
        rim < 0.8 * brightness(middle.color),
        "rim {rim}, middle {:?}",
        middle.color
    );
    assert_eq!(image[0].object, 0);
    // The ball subtends the same angle in every direction about the
    // vertical: the image is symmetric under a quarter turn.
    for j in 0..33 {
        for i in 0..33 {
            assert_eq!(image[j * 33 + i].object, image[i * 33 + (32 - j)].object, "({i}, {j})");
        }
    }
}

/// Per-cell shading: looking straight up in S2 x S1, the ball is seen in
/// the copy above the eye's (one step up the circle); after the eye flies
/// once round the circle it is in the next copy up, and so is what it
/// sees. A highlighted copy tints the ball in it, and only there.
#[test]
fn cells_are_named_along_the_circle_and_tint_the_balls_in_them() {
    use bevy_manifold_core::space::cells::CellTint;
    use bevy_manifold_core::space::product_cells::product_cell_id;
    use bevy_manifold_core::trace::product::{ProductScene, ProductView, palette, render};
    let space = ProductSpace::s2_x_s1(1.5);
    let ball = ProductBall {
        center: ProductPoint::new(DVec3::Z, -0.6),
        radius: 0.1,
        id: 1,
    };
    let view = ProductView {
        eye: ProductPoint::new(DVec3::Z, 0.2),
        frame: [
            ProductTangent::new(DVec3::ZERO, 1.0),
            ProductTangent::new(DVec3::X, 0.0),
            ProductTangent::new(DVec3::Y, 0.0),
        ],
        fov_y_degrees: 30.0,
        frustum: None,
        max_distance: 10.0,
        max_crossings: 16,
        fog: 0.0,
        cell: Some(ProductElement::IDENTITY),
        tint: None,
    };
    let middle = |v: &ProductView| render(&space, &ProductScene::new(vec![ball], *v), 9, 9)[4 * 9 + 4];
    let seen = middle(&view);
    // Up 0.55 to the top face, then from -0.75 to the ball's bottom at
    // -0.7 in the next copy.
    assert_eq!(seen.object, 1);
    assert!((seen.distance - 0.6).abs() < 1e-9, "{}", seen.distance);
    assert_eq!(seen.cell, product_cell_id([0, 0], 1));
    // Once round the circle, straight up: one copy up, through one face.
    let round = view.moved(&space, [1.0, 0.0, 0.0], 1.5);
    assert!((round.eye.height - 0.2).abs() < 1e-9);
    assert_eq!(round.cell.map(|c| c.steps()), Some(1));
    let after = middle(&round);
    assert_eq!(after.cell, product_cell_id([0, 0], 2));
    assert!((after.distance - seen.distance).abs() < 1e-9);
    // Highlighting the copy it is seen in tints it; another copy does not.
    let lit = middle(&ProductView {
        tint: Some(CellTint::Highlight(after.cell)),
        ..round
    });
    let other = middle(&ProductView {
        tint: Some(CellTint::Highlight(seen.cell)),
        ..round
    });
    let base = palette(1);
    for (c, b) in base.iter().enumerate() {
        assert!((lit.color[c] - after.color[c] * CellTint::HIGHLIGHT[c]).abs() < 1e-6);
        assert!((other.color[c] - after.color[c]).abs() < 1e-6);
        assert!(after.color[c] <= b + 1e-6);
    }
}

/// Product space files: every catalog space written and read back is the
/// same space; broken files name the file and the field.
#[test]
fn product_space_files_round_trip_and_name_what_is_broken() {
    for space in catalog() {
        let back = ProductSpace::from_json(&space.to_json(), "x.json").unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(back.name, space.name);
        assert_eq!(back.geometry, space.geometry);
        assert_eq!(back.gluings, space.gluings);
        assert_eq!(back.sides, space.sides);
        assert_eq!(back.height, space.height);
    }
    let genus2 = ProductSpace::genus_two_x_s1(1.0).to_json();
    let broken = |edit: &dyn Fn(&mut serde_json::Value)| {
        let mut v: serde_json::Value = serde_json::from_str(&genus2).unwrap();
        edit(&mut v);
        ProductSpace::from_json(&v.to_string(), "g2.json").expect_err("a broken file")
    };
    for (edit, field) in [
        (
            Box::new(|v: &mut serde_json::Value| v["height"] = serde_json::json!(-1.0))
                as Box<dyn Fn(&mut serde_json::Value)>,
            "height",
        ),
        (
            Box::new(|v| v["gluings"][3]["surface"][0][0] = serde_json::json!(2.0)),
            "gluings[3]",
        ),
        (
            Box::new(|v| v["gluings"][5]["partner"] = serde_json::json!(40)),
            "gluings[5]",
        ),
        (
            Box::new(|v| v["gluings"][8]["kind"] = serde_json::json!("mirror")),
            "gluings[8].partner",
        ),
        (Box::new(|v| v["sides"][2][0] = serde_json::json!(0.5)), "sides"),
        (Box::new(|v| v["angles"] = serde_json::json!(vec![0.7; 8])), "angles"),
        (Box::new(|v| v["geometry"] = serde_json::json!("nil")), "json"),
        (Box::new(|v| v["colour"] = serde_json::json!(1)), "json"),
    ] {
        let e = broken(&edit);
        assert!(e.file == "g2.json" && e.field == field, "{field}: {e}");
    }
    // The file says its geometry: the same prism in S2xR is another space
    // (its octagon's normals are not unit normals of S2's form there).
    let e = broken(&|v| v["geometry"] = serde_json::json!("s2xr"));
    assert_eq!(e.field, "sides", "{e}");
}

/// `reach` bounds where a segment may be within a ball: on 4,000 random
/// segments and balls in both geometries (half the balls placed near the
/// segment), every point sampled along the
/// segment (every 1/2000 of it) that is within the radius, by the
/// distance itself, lies in the span `reach` gives; and where no sampled
/// point is near, the span is usually empty (it is a box about the ball,
/// not the ball).
#[test]
fn reach_holds_every_point_of_a_segment_within_a_ball() {
    use bevy_manifold_core::trace::product::reach;
    let mut seed = 0x2545_f491_4f6c_dd1du64;
    let mut random = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let (mut near, mut empty_when_far, mut far) = (0, 0, 0);
    for g in [ProductGeometry::H2xR, ProductGeometry::S2xR] {
        for _ in 0..2000 {
            let origin = point(g, TAU * random(), 1.5 * random(), random() - 0.5);
            let dir = g.normalize_tangent(
                origin,
                ProductTangent::new(
                    DVec3::new(random() - 0.5, random() - 0.5, random() - 0.5),
                    random() - 0.5,
                ),
            );
            let radius = 0.05 + 0.4 * random();
            let length = 0.2 + 8.0 * random();
            // Half the balls anywhere, half near a point of the segment.
            let center = if random() < 0.5 {
                point(g, TAU * random(), 1.5 * random(), random() - 0.5)
            } else {
                let (p, _) = g.exp(origin, dir, length * random());
                let aside = g.normalize_tangent(
                    p,
                    ProductTangent::new(
                        DVec3::new(random() - 0.5, random() - 0.5, random() - 0.5),
                        random() - 0.5,
                    ),
                );
                g.exp(p, aside, 1.5 * radius * random()).0
            };
            let r = ray(origin, dir);
            let span = reach(g, &r, center, radius, length);
            let mut any = false;
            for i in 0..=2000 {
                let s = length * f64::from(i) / 2000.0;
                let (p, _) = g.exp(origin, dir, s);
                if g.distance(p, center) <= radius {
                    any = true;
                    let (lo, hi) = span.unwrap_or_else(|| panic!("{g:?}: s = {s} is within but no span"));
                    assert!(lo - 1e-9 <= s && s <= hi + 1e-9, "{g:?}: s = {s} outside [{lo}, {hi}]");
                }
            }
            if any {
                near += 1;
            } else {
                far += 1;
                empty_when_far += usize::from(span.is_none());
            }
        }
    }
    eprintln!("{near} segments meet their ball; of the {far} others, {empty_when_far} have no span");
    assert!(near > 1000, "{near}");
    assert!(empty_when_far as f64 > 0.5 * far as f64, "{empty_when_far} of {far}");
}

/// A ball at a vertex of the octagon is seen in every copy of the prism
/// round the vertex: eight octagons of angle pi/4 meet there, and the
/// genus-2 gluing makes all eight vertices one, so `images` gives eight
/// balls, one at each vertex. On the top face too, eight more above.
#[test]
fn a_ball_at_a_vertex_is_seen_in_every_copy_round_it() {
    use bevy_manifold_core::trace::product::images;
    let space = ProductSpace::genus_two_x_s1(2.0);
    let g = space.geometry;
    let vertices = space.vertices();
    let at = |center: ProductPoint| ProductBall {
        center,
        radius: 0.1,
        id: 1,
    };
    let seen = images(&space, &[at(ProductPoint::new(vertices[3], 0.0))]);
    assert_eq!(seen.len(), 8);
    for v in &vertices {
        let n = seen
            .iter()
            .filter(|b| g.distance(b.center, ProductPoint::new(*v, 0.0)) < 1e-9)
            .count();
        assert_eq!(n, 1, "{v}");
    }
    let on_top = images(&space, &[at(ProductPoint::new(vertices[0], 1.0))]);
    assert_eq!(on_top.len(), 16);
    assert_eq!(
        on_top.iter().filter(|b| (b.center.height + 1.0).abs() < 1e-9).count(),
        8
    );
    // Well inside, a ball is seen only as itself.
    assert_eq!(images(&space, &[at(ProductPoint::ORIGIN)]).len(), 1);
}

/// A view flying through the space: up the circle of S2 x S1 by its
/// length, or round a great circle of the sphere (2 pi), it comes back to
/// where it was, looking the same way (parallel transport round a closed
/// geodesic of a product is the identity here); in genus 2 x S1, moving
/// and moving back through the faces comes back too; turning and rolling
/// keep the frame orthonormal, and a whole turn or roll is none.
#[test]
fn a_flying_view_comes_back_round_closed_geodesics() {
    use bevy_manifold_core::trace::product::{ProductScene, ProductView};
    let same = |g: ProductGeometry, a: &ProductView, b: &ProductView, tol: f64| {
        assert!(g.distance(a.eye, b.eye) < tol, "{:?} vs {:?}", a.eye, b.eye);
        for (x, y) in a.frame.iter().zip(&b.frame) {
            let d = ProductTangent::new(x.surface - y.surface, x.height - y.height);
            assert!(d.length(g) < tol, "{x:?} vs {y:?}");
        }
    };
    let orthonormal = |g: ProductGeometry, v: &ProductView| {
        for i in 0..3 {
            for j in 0..3 {
                let (a, b) = (v.frame[i], v.frame[j]);
                let dot = g.form(a.surface, b.surface) + a.height * b.height;
                assert!((dot - f64::from(u8::from(i == j))).abs() < 1e-12, "{i} {j}: {dot}");
            }
            assert!(g.form(v.frame[i].surface, v.eye.surface).abs() < 1e-12);
        }
    };
    let s2 = ProductSpace::s2_x_s1(2.0);
    let g = s2.geometry;
    let view = ProductScene::default_for(&s2).view;
    // Straight up the circle: the frame's up is not vertical, so fly along
    // the vertical itself (forward tilted 0.25 up: the vertical is
    // forward sin + up cos).
    let (c, s) = (0.25f64.cos(), 0.25f64.sin());
    let up_the_circle = view.moved(&s2, [s, 0.0, c], 2.0);
    same(g, &up_the_circle, &view, 1e-9);
    let half = view.moved(&s2, [s, 0.0, c], 1.0);
    assert!((g.distance(half.eye, view.eye) - 1.0).abs() < 1e-9);
    // Round the sphere: along the frame's horizontal right.
    let round = view.moved(&s2, [0.0, 1.0, 0.0], std::f64::consts::TAU);
    same(g, &round, &view, 1e-9);
    let halfway = view.moved(&s2, [0.0, 1.0, 0.0], std::f64::consts::PI);
    assert!((g.surface_distance(halfway.eye.surface, view.eye.surface) - std::f64::consts::PI).abs() < 1e-6);
    orthonormal(g, &halfway);
    // Genus 2 x S1: there and back through the faces.
    let g2 = ProductSpace::genus_two_x_s1(2.0);
    let h = g2.geometry;
    let view = ProductScene::default_for(&g2).view;
    let there = view.moved(&g2, [1.0, 0.3, 0.2], 5.0);
    assert!(g2.contains(there.eye, 1e-9));
    orthonormal(h, &there);
    let turned_back = there.turned(h, std::f64::consts::PI, 0.0);
    let back = turned_back
        .moved(&g2, [1.0, 0.3, -0.2], 5.0)
        .turned(h, std::f64::consts::PI, 0.0);
    same(h, &back, &view, 1e-7);
    // Turning: a whole turn, and a turn and back.
    same(h, &view.turned(h, std::f64::consts::TAU, 0.0), &view, 1e-12);
    same(
        h,
        &view.turned(h, 0.7, 0.3).turned(h, 0.0, -0.3).turned(h, -0.7, 0.0),
        &view,
        1e-12,
    );
    orthonormal(h, &view.turned(h, 0.7, 0.3));
    // Rolling: a whole roll, a roll and back; where it looks stays.
    same(h, &view.rolled(h, std::f64::consts::TAU), &view, 1e-12);
    same(h, &view.rolled(h, 0.9).rolled(h, -0.9), &view, 1e-12);
    let rolled = view.rolled(h, std::f64::consts::FRAC_PI_2);
    orthonormal(h, &rolled);
    let d = ProductTangent::new(
        rolled.frame[0].surface - view.frame[0].surface,
        rolled.frame[0].height - view.frame[0].height,
    );
    assert!(d.length(h) < 1e-12);
    // A quarter roll turns the right into the up.
    let d = ProductTangent::new(
        rolled.frame[1].surface - view.frame[2].surface,
        rolled.frame[1].height - view.frame[2].height,
    );
    assert!(d.length(h) < 1e-12);
}

/// The tour through S2 x S1 (`assets/tours/s2xs1.product-tour.json`):
/// looking straight up the circle, the view one circle (2) later is the
/// same picture, one copy up (every pixel's copy one step higher); round
/// the sphere, a great circle closes after 2 pi: the eye is back where it
/// started, looking the same way, in the same copy.
#[test]
fn the_tour_through_s2xs1_repeats_up_the_circle_and_closes_round_the_sphere() {
    use bevy_manifold_core::space::product_cells::product_cell_id;
    use bevy_manifold_core::tour::product::ProductTour;
    use bevy_manifold_core::trace::product::{ProductScene, ProductView, render};
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../assets/tours/s2xs1.product-tour.json"
    );
    let tour = ProductTour::load(path).expect("the tour");
    let g = tour.space.geometry;
    let close = |a: &ProductView, b: &ProductView| {
        g.distance(a.eye, b.eye) < 1e-9
            && a.frame
                .iter()
                .zip(&b.frame)
                .all(|(u, v)| (u.surface - v.surface).length() < 1e-9 && (u.height - v.height).abs() < 1e-9)
    };
    // The climb: 6.5 s in, 6 s at speed 1, straight up.
    let (a, b) = (tour.view_at(7.0), tour.view_at(9.0));
    assert!(a.frame[0].height > 1.0 - 1e-9, "not straight up: {:?}", a.frame[0]);
    assert!(close(&a, &b), "{a:?} {b:?}");
    let steps = |v: &ProductView| v.cell.expect("a copy").steps();
    assert_eq!(steps(&b), steps(&a) + 1);
    let (pa, pb) = (
        render(&tour.space, &ProductScene::new(tour.balls.clone(), a), 24, 16),
        render(&tour.space, &ProductScene::new(tour.balls.clone(), b), 24, 16),
    );
    assert!(pa.iter().filter(|p| p.object != 0).count() > 20);
    for (p, q) in pa.iter().zip(&pb) {
        assert_eq!((p.object, p.crossings), (q.object, q.crossings));
        assert!((p.distance - q.distance).abs() < 1e-9 || p.object == 0);
        if p.object != 0 {
            let up = |c| {
                (0..100)
                    .find(|k| product_cell_id([0, 0], *k) == c)
                    .expect("a copy up the circle")
            };
            assert_eq!(up(q.cell), up(p.cell) + 1);
        }
    }
    // Round the sphere: from 15 s, 2 pi at speed 0.8.
    let (start, end) = (tour.view_at(15.0), tour.view_at(15.0 + std::f64::consts::TAU / 0.8));
    assert!(start.frame[0].height.abs() < 1e-9, "not level: {:?}", start.frame[0]);
    assert!(close(&start, &end), "{start:?} {end:?}");
    assert_eq!(start.cell, end.cell);
    let halfway = tour.view_at(15.0 + std::f64::consts::PI / 0.8);
    assert!((g.distance(start.eye, halfway.eye) - std::f64::consts::PI).abs() < 1e-9);
    assert_eq!(
        tour.caption_at(16.0),
        Some("Level again, then round the sphere: a great circle closes after 2 pi")
    );
}

/// Broken product tours name the file and the field.
#[test]
fn broken_product_tours_name_the_field() {
    use bevy_manifold_core::tour::product::ProductTourDesc;
    for (text, needle) in [
        (
            r#"{"product_space": "torus", "legs": []}"#,
            "t.json: product_space: \"torus\" is not one of",
        ),
        (
            r#"{"product_space": "s2xs1", "length": -1, "legs": []}"#,
            "t.json: length: must be in (0.01, 100]",
        ),
        (
            r#"{"product_space": "s2xs1", "legs": [{"fly": {"seconds": 0, "speed": 1}}]}"#,
            "t.json: legs[0].fly.seconds: must be positive",
        ),
        (
            r#"{"product_space": "s2xs1", "legs": [{"turn": {"seconds": 1}}, {"fly": {"seconds": 1, "speed": 1e9}}]}"#,
            "t.json: legs[1].fly.speed",
        ),
        (
            r#"{"product_space": "s2xs1", "legs": [{"caption": "both", "fly": {"seconds": 1, "speed": 1}, "turn": {"seconds": 1}}]}"#,
            "t.json: legs[0]: must be one leg",
        ),
        (
            r#"{"product_space": "s2xs1", "legs": [{"turn": {"seconds": 1, "yaw_degrees": 1e300}}]}"#,
            "t.json: legs[0].turn: angles",
        ),
        (
            r#"{"product_space": "s2xs1", "legs": [{"fly": {"seconds": 1e5, "speed": 1}}]}"#,
            "t.json: legs[0].fly: flies 100000 units: too far for one leg",
        ),
        (
            r#"{"product_space": "s2xs1", "legs": [{"turn": {"seconds": 1e5}}]}"#,
            "t.json: legs[0]: the tour passes",
        ),
    ] {
        let e = ProductTourDesc::parse(text, "t.json")
            .and_then(|d| d.build("t.json"))
            .unwrap_err()
            .to_string();
        assert!(e.contains(needle), "{e}");
    }
    let e = ProductTourDesc::parse(r#"{"product_space": "s2xs1", "legs": [], "speed": 2}"#, "t.json").unwrap_err();
    assert!(
        e.to_string().contains("t.json: not a tour file: unknown field `speed`"),
        "{e}"
    );
}

#[test]
fn a_product_tour_can_be_lit() {
    // `lights` in the file: the scene at every moment has the lit
    // scene's two lights (and its lighting); without it, none.
    use bevy_manifold_core::tour::product::ProductTourDesc;
    use bevy_manifold_core::trace::product::ProductScene;
    let text = |lights: &str| {
        format!(r#"{{"product_space": "genus2xs1", {lights} "legs": [{{"fly": {{"seconds": 2, "speed": 0.5}}}}]}}"#)
    };
    let lit = ProductTourDesc::parse(&text(r#""lights": true,"#), "lit")
        .unwrap()
        .build("lit")
        .unwrap();
    let space = ProductSpace::genus_two_x_s1(2.0);
    let expected = ProductScene::lit_for(&space);
    for t in [0.0, 1.0, 2.0] {
        let scene = lit.scene_at(t);
        assert_eq!(scene.lights, expected.lights);
        assert_eq!(scene.lighting, expected.lighting);
        assert_eq!(scene.balls, expected.balls);
    }
    let plain = ProductTourDesc::parse(&text(""), "plain")
        .unwrap()
        .build("plain")
        .unwrap();
    assert!(plain.scene_at(1.0).lights.is_empty());
    // The same flight either way.
    assert_eq!(lit.view_at(1.5), plain.view_at(1.5));
    // A wrong type is refused, naming the file and what was expected.
    let e = ProductTourDesc::parse(&text(r#""lights": 3,"#), "bad")
        .unwrap_err()
        .to_string();
    assert!(e.contains("bad") && e.contains("boolean"), "{e}");
}
