//! Lights in the product spaces, checked against independent facts: the
//! fall-off against the Jacobian of the geodesic flow taken by finite
//! differences, its mean over the directions against the sphere's area,
//! the light's images against the group's orbit enumerated by words, the
//! light straight above a ball against the sum over the circle's copies,
//! and shadows cast through the faces by the ball's own copies.

use bevy_manifold_core::geometry::product::{ProductGeometry, ProductIsometry, ProductPoint, ProductTangent};
use bevy_manifold_core::space::product::ProductSpace;
use bevy_manifold_core::trace::product::{
    DIM_LIGHT, ProductBall, ProductLight, ProductLightImage, ProductLighting, ProductObjects, ProductScene,
    arc_irradiance, direct, images, light_arcs, light_images, render, shadowed,
};
use glam::DVec3;
use std::f64::consts::PI;

fn point(g: ProductGeometry, angle: f64, d: f64, h: f64) -> ProductPoint {
    let (c, s) = g.trig(d);
    ProductPoint::new(DVec3::new(s * angle.cos(), s * angle.sin(), c), h)
}

/// The product metric's length of an ambient vector tangent at a point.
fn dot(g: ProductGeometry, a: (DVec3, f64), b: (DVec3, f64)) -> f64 {
    g.form(a.0, b.0) + a.1 * b.1
}

#[test]
fn the_fall_off_is_the_spread_of_the_geodesic_flow() {
    // From the origin, the direction at elevation a and azimuth t; the
    // area the end points at distance d sweep per unit of the unit
    // sphere's area (cos a da dt), by central differences of exp.
    for (g, distances) in [
        (ProductGeometry::H2xR, [0.5, 1.5, 3.0]),
        (ProductGeometry::S2xR, [0.5, 1.5, 2.8]),
    ] {
        for d in distances {
            for a in [0.0, 0.3, 0.9, 1.3] {
                let t = 0.7;
                let end = |a: f64, t: f64| {
                    let v = ProductTangent::new(DVec3::new(a.cos() * t.cos(), a.cos() * t.sin(), 0.0), a.sin());
                    let p = g.exp(ProductPoint::ORIGIN, v, d).0;
                    (p.surface, p.height)
                };
                let h = 1e-5;
                let diff = |p: (DVec3, f64), q: (DVec3, f64)| ((p.0 - q.0) / (2.0 * h), (p.1 - q.1) / (2.0 * h));
                let da = diff(end(a + h, t), end(a - h, t));
                let dt = diff(end(a, t + h), end(a, t - h));
                let gram = dot(g, da, da) * dot(g, dt, dt) - dot(g, da, dt).powi(2);
                let spread = gram.sqrt() / a.cos();
                let expected = g.light_area(d, d * a.cos()) / (4.0 * PI);
                assert!(
                    (spread - expected).abs() < 1e-6 * expected,
                    "{g:?} d {d} a {a}: flow {spread}, light_area {expected}"
                );
            }
        }
    }
}

#[test]
fn the_fall_off_averages_to_the_sphere_area() {
    // Uniform in z = sin a over the unit sphere (midpoint rule), against
    // the sphere's area integrated in a by Simpson's rule.
    for (g, d) in [
        (ProductGeometry::H2xR, 0.8),
        (ProductGeometry::H2xR, 4.0),
        (ProductGeometry::S2xR, 1.2),
        (ProductGeometry::S2xR, 2.5),
    ] {
        let n = 20_000;
        let mean: f64 = (0..n)
            .map(|i| {
                let z = -1.0 + (f64::from(i) + 0.5) * 2.0 / f64::from(n);
                g.light_area(d, d * (1.0 - z * z).sqrt())
            })
            .sum::<f64>()
            / f64::from(n);
        let area = g.sphere_area(d);
        assert!((mean - area).abs() < 1e-5 * area, "{g:?} {d}: {mean} against {area}");
    }
    // Near the light every direction spreads as in flat space.
    let g = ProductGeometry::H2xR;
    let flat = 4.0 * PI * 1e-6;
    assert!((g.light_area(1e-3, 1e-3) - flat).abs() < 1e-6 * flat);
}

#[test]
fn a_lights_images_up_the_circle_turn_with_the_twist() {
    // S2 x S1 turned by a third as one goes up the circle of 2: the k-th
    // copy up is turned by k thirds about the pole and raised by 2 k.
    let space = ProductSpace::twisted_s2_x_s1(2.0, 3);
    let at = point(ProductGeometry::S2xR, 0.4, 0.9, 0.3);
    let light = ProductLight {
        range: Some(7.0),
        ..ProductLight::point(at, 5.0)
    };
    let found = light_images(&space, &[light], ProductLighting::default());
    // Heights 0.3 + 2 k nearer than 7 to the prism's [-1, 1]: k from -4
    // (-7.7) to 3 (6.3).
    assert_eq!(found.len(), 8);
    // The k-th copy turned by k thirds in the sense `sense` (the twist
    // turns one way or the other: either, but one sense for all).
    let copy = |k: i32, sense: f64| {
        let (s, c) = (sense * f64::from(k) * 2.0 * PI / 3.0).sin_cos();
        let p = at.surface;
        ProductPoint::new(
            DVec3::new(p.x * c - p.y * s, p.x * s + p.y * c, p.z),
            0.3 + 2.0 * f64::from(k),
        )
    };
    let has = |q: ProductPoint| {
        found
            .iter()
            .any(|i| ProductGeometry::S2xR.distance(i.position, q) < 1e-9)
    };
    let sense = if has(copy(1, 1.0)) { 1.0 } else { -1.0 };
    for k in -4i32..=3 {
        assert!(has(copy(k, sense)), "no image at k = {k} (turned {sense})");
    }
    assert!((found[0].inv_range_sq - 1.0 / 49.0).abs() < 1e-15);
}

/// The orbit of `p` under the gluings, every word of up to `length`
/// letters (left multiplication, breadth first; points merged by their
/// coordinates rounded to 1e-4, so a point may rarely appear twice),
/// short of 9 from the origin (farther, f64 can no longer keep them on
/// the hyperboloid).
fn orbit(space: &ProductSpace, p: ProductPoint, length: usize) -> Vec<ProductPoint> {
    let g = space.geometry;
    let gluings: Vec<ProductIsometry> = space.gluings.iter().map(|m| m.isometry()).collect();
    let key = |q: ProductPoint| {
        let r = |x: f64| (x * 1e4).round() as i64;
        (r(q.surface.x), r(q.surface.y), r(q.surface.z), r(q.height))
    };
    let mut seen = std::collections::HashSet::from([key(p)]);
    let mut all = vec![p];
    let mut frontier = vec![p];
    for _ in 0..length {
        let mut next = Vec::new();
        for q in &frontier {
            for m in &gluings {
                let r = g.normalize_point(m.apply(*q));
                if r.surface.z.abs() < 4000.0 && seen.insert(key(r)) {
                    all.push(r);
                    next.push(r);
                }
            }
        }
        frontier = next;
    }
    all
}

/// Points of the prism: its centre, corners, points on its sides and
/// inside.
fn prism_points(space: &ProductSpace) -> Vec<ProductPoint> {
    let g = space.geometry;
    let vertices = space.vertices();
    let mut out = Vec::new();
    for h in [-0.5, -0.2, 0.0, 0.35, 0.5] {
        let height = h * space.height;
        out.push(ProductPoint::new(DVec3::Z, height));
        for (i, v) in vertices.iter().enumerate() {
            let w = vertices[(i + 1) % vertices.len()];
            for (a, b) in [(1.0, 0.0), (0.5, 0.5), (0.8, 0.2), (0.45, 0.0)] {
                // On the segment v w (a + b = 1), or towards the centre.
                let c = 1.0 - a - b;
                let q = *v * a + w * b + DVec3::Z * c;
                out.push(g.normalize_point(ProductPoint::new(q, height)));
            }
        }
    }
    out
}

#[test]
fn the_octagons_light_images_light_the_prism_as_the_whole_orbit() {
    // Genus 2 x S1 (also turned by 3/8 round the circle) and the mirrored
    // prism: at every sample point of the prism the kept images give the
    // same light as every image of the orbit (enumerated by words,
    // independently of the walk of copies).
    for space in [
        ProductSpace::genus_two_x_s1(1.2),
        ProductSpace::twisted_genus_two_x_s1(1.2, 3),
        ProductSpace::mirrored_prism(5, 1.0),
    ] {
        let g = space.geometry;
        let at = point(g, 1.1, 0.2, 0.15);
        for (range, budget) in [(Some(1.4), 64), (None, 24)] {
            let light = ProductLight {
                range,
                ..ProductLight::point(at, 3.0)
            };
            let lighting = ProductLighting {
                images: budget,
                shadows: false,
            };
            let kept = light_images(&space, &[light], lighting);
            assert!(!kept.is_empty() && kept.len() <= budget as usize, "{}", space.name);
            let cut = 1.0 / kept[0].inv_range_sq.sqrt();
            if let Some(r) = range {
                assert!(cut <= r + 1e-12);
            }
            let all = orbit(&space, at, 6);
            // Every kept image is in the orbit.
            for k in &kept {
                assert!(all.iter().any(|a| g.distance(*a, k.position) < 1e-6), "{}", space.name);
            }
            // Every image of the orbit nearer than the cut to a point of
            // the prism is kept, so the sums agree there.
            let sum = |images: &mut dyn Iterator<Item = ProductPoint>, x: ProductPoint| -> f64 {
                images
                    .map(|p| {
                        let image = ProductLightImage { position: p, ..kept[0] };
                        let s = g.distance(x, p);
                        arc_irradiance(g, &image, (s, g.surface_distance(x.surface, p.surface)), 0.0)
                    })
                    .sum()
            };
            let mut lit = 0;
            for x in prism_points(&space) {
                for p in &all {
                    if g.distance(x, *p) < cut - 1e-9 {
                        assert!(
                            kept.iter().any(|k| g.distance(k.position, *p) < 1e-6),
                            "{}: an image {:.3} from the prism left out",
                            space.name,
                            g.distance(x, *p)
                        );
                    }
                }
                // The orbit's images that light x, each once.
                let mut near: Vec<ProductPoint> = Vec::new();
                for p in all.iter().filter(|p| g.distance(x, **p) < cut) {
                    if !near.iter().any(|n| g.distance(*n, *p) < 1e-6) {
                        near.push(*p);
                    }
                }
                let (a, b) = (
                    sum(&mut kept.iter().map(|k| k.position), x),
                    sum(&mut near.into_iter(), x),
                );

                assert!(
                    (a - b).abs() <= 1e-9 * b.max(1.0),
                    "{}: {a} against {b} at {x:?}",
                    space.name
                );
                lit += usize::from(a > 0.0);
            }
            assert!(lit > 20, "{}: lit at {lit} points", space.name);
        }
    }
}

#[test]
fn a_light_above_a_ball_lights_it_once_per_circle_and_its_copies_shade_it() {
    // S2 x S1 of circle 2: a ball of radius 0.2 on the pole at height 0
    // and a light on the pole at 0.6; their copies every 2 up the circle.
    // The ball's top, seen from straight above, faces every copy of the
    // light above it, each straight up the circle (a vertical geodesic:
    // area 4 pi s^2).
    let space = ProductSpace::s2_x_s1(2.0);
    let g = space.geometry;
    let ball = ProductBall {
        center: ProductPoint::new(DVec3::Z, 0.0),
        radius: 0.2,
        id: 1,
    };
    let range = 9.0;
    let light = ProductLight {
        range: Some(range),
        ..ProductLight::point(ProductPoint::new(DVec3::Z, 0.6), 2.0)
    };
    let balls = images(&space, &[ball]);
    let x = ProductPoint::new(DVec3::Z, 0.2);
    let up = ProductTangent::new(DVec3::ZERO, 1.0);
    let albedo = [0.5, 0.25, 1.0];
    let window = |s: f64| (1.0 - (s * s / (range * range)).powi(2)).powi(2);
    let falloff = |s: f64| 2.0 * window(s) / (4.0 * PI * s * s);
    for shadows in [false, true] {
        let lit = light_images(&space, &[light], ProductLighting { images: 64, shadows });
        let rgb = direct(
            &space,
            &ProductObjects {
                balls: balls.clone(),
                ..ProductObjects::default()
            },
            &lit,
            (x, up, up),
            albedo,
            0.0,
            shadows,
            32,
        );
        // Unshadowed: every copy above, at 0.4 + 2 k, within the range;
        // the copies below lie behind the surface. Shadowed: the ball's
        // copy at 2 hides every copy of the light past it, but for the
        // dim light: copies whose light (its brightest channel) fits in
        // what is left of `DIM_LIGHT`, nearest first, count at half.
        // Lambert head-on, and Blinn's lobe at its peak (0.35).
        let light = |s: f64| albedo.map(|a| (f64::from(a) + 0.35) * falloff(s));
        let copies = (0..5).map(|k| 0.4 + 2.0 * f64::from(k)).filter(|s| *s < range);
        let mut expected = [0.0; 3];
        let mut dim = f64::from(DIM_LIGHT);
        let mut halves = 0;
        for (k, s) in copies.enumerate() {
            let l = light(s);
            let share = if !shadows || k == 0 {
                1.0
            } else if l[2] < dim {
                dim -= l[2];
                halves += 1;
                0.5
            } else {
                0.0
            };
            for c in 0..3 {
                expected[c] += share * l[c];
            }
        }
        // Shadowed, the two farthest copies (6.4 and 8.4 on) are dim.
        assert_eq!(halves, if shadows { 2 } else { 0 });
        for c in 0..3 {
            assert!(
                (f64::from(rgb[c]) - expected[c]).abs() < 1e-6 * expected[c],
                "shadows {shadows}: {} against {}",
                rgb[c],
                expected[c]
            );
            // The dim light is off by at most half of `DIM_LIGHT`.
            let exact = if shadows { light(0.4)[c] } else { expected[c] };
            assert!((f64::from(rgb[c]) - exact).abs() <= f64::from(DIM_LIGHT) / 2.0);
        }
    }
    // The way up from the top meets the ball's copy at 2 (1.6 on), after
    // one crossing of the top face.
    let arcs = light_arcs(g, x, ProductPoint::new(DVec3::Z, 2.6));
    assert_eq!(arcs.len(), 1, "straight up: no way round the sphere");
    let objects = ProductObjects {
        balls: balls.clone(),
        ..ProductObjects::default()
    };
    assert!(shadowed(&space, &objects, (x, up), &arcs[0], 8));
    assert!(
        !shadowed(&space, &objects, (x, up), &arcs[0], 0),
        "the copy is past a face"
    );
}

#[test]
fn the_sphere_lights_the_long_way_round_too() {
    // On S2 x R a light is also seen the other way round the great
    // circle, arriving from the opposite side, 2 pi - d along it.
    let g = ProductGeometry::S2xR;
    let x = point(g, 0.0, 0.0, 0.0);
    let l = point(g, 0.0, 1.0, 0.5);
    let arcs = light_arcs(g, x, l);
    assert_eq!(arcs.len(), 2);
    assert!((arcs[0].length - 1.0f64.hypot(0.5)).abs() < 1e-12);
    assert!((arcs[1].length - (2.0 * PI - 1.0).hypot(0.5)).abs() < 1e-12);
    assert!((arcs[0].dir.surface.x - 1.0 / 1.0f64.hypot(0.5)).abs() < 1e-12);
    assert!(arcs[1].dir.surface.x < 0.0 && arcs[1].dir.height > 0.0);
    // Each is a geodesic that reaches the light.
    for a in &arcs {
        let end = g.exp(x, a.dir, a.length).0;
        assert!(g.distance(end, l) < 1e-9, "{a:?}");
    }
}

#[test]
fn a_ball_between_shades_and_beside_does_not() {
    // H2 x S1 of the octagon: a light across the prism, a ball on the way
    // and then moved off it.
    let space = ProductSpace::genus_two_x_s1(2.0);
    let g = space.geometry;
    let x = point(g, PI, 0.3, 0.0);
    let light = point(g, 0.0, 0.3, 0.2);
    let arc = light_arcs(g, x, light)[0];
    let normal = arc.dir;
    let on_the_way = g.exp(x, arc.dir, arc.length / 2.0).0;
    for (center, blocked) in [(on_the_way, true), (ProductPoint::new(on_the_way.surface, 0.7), false)] {
        let ball = ProductBall {
            center,
            radius: 0.1,
            id: 1,
        };
        let balls = images(&space, &[ball]);
        assert_eq!(
            shadowed(
                &space,
                &ProductObjects {
                    balls: balls.clone(),
                    ..ProductObjects::default()
                },
                (x, normal),
                &arc,
                8
            ),
            blocked,
            "{center:?}"
        );
    }
}

#[test]
fn a_lit_scene_is_lit_and_shaded() {
    // The lit default scene of each space: never NaN, shadows only take
    // light away, and some points are in shadow (the warm light stands
    // beyond the ball on the axis from the smallest ball).
    for space in [
        ProductSpace::s2_x_s1(2.0),
        ProductSpace::genus_two_x_s1(2.0),
        ProductSpace::mirrored_prism(5, 1.0),
    ] {
        let scene = ProductScene::lit_for(&space);
        let lit = render(&space, &scene, 40, 24);
        let mut dark = scene.clone();
        dark.lighting.shadows = false;
        let unshadowed = render(&space, &dark, 40, 24);
        let mut brighter = 0;
        for (a, b) in lit.iter().zip(&unshadowed) {
            assert!(a.color.iter().all(|c| c.is_finite()), "{}", space.name);
            assert_eq!(a.object, b.object);
            // Shadows only take light away.
            assert!(
                a.color.iter().zip(&b.color).all(|(x, y)| *x <= *y + 1e-6),
                "{}",
                space.name
            );
            brighter += usize::from(b.color.iter().sum::<f32>() > a.color.iter().sum::<f32>() + 1e-3);
        }
        let hits = lit.iter().filter(|p| p.object != 0).count();
        eprintln!("{}: {hits} hits, {brighter} in shadow", space.name);
        assert!(hits > 100, "{}", space.name);
        assert!(brighter > 0, "{}: no shadow anywhere", space.name);
    }
}

/// A spot light shines by the angle at the light between its axis and the
/// geodesic leaving it towards the lit point: points reached by shooting
/// from the light at angles 0 to 80 degrees from its axis (straight
/// down) get `smoothstep(cos 40, cos 20, cos angle)` of its light, in
/// H2xR and S2xR; in H2xR `direct` gives the point light's light times
/// that share, and an image of the spot through a face has its axis
/// turned with it.
#[test]
fn a_spot_shines_by_the_angle_at_the_light() {
    use bevy_manifold_core::trace::product::{ProductSpot, light_arcs, spot_share};
    let smoothstep = |e0: f64, e1: f64, x: f64| {
        let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
        t * t * (3.0 - 2.0 * t)
    };
    let (inner, outer) = (20f64.to_radians(), 40f64.to_radians());
    for space in [ProductSpace::genus_two_x_s1(40.0), ProductSpace::s2_x_s1(40.0)] {
        let g = space.geometry;
        let at = ProductPoint::new(DVec3::Z, 0.5);
        let down = ProductTangent::new(DVec3::ZERO, -1.0);
        let spot = ProductLight {
            spot: Some(ProductSpot {
                axis: down,
                inner,
                outer,
            }),
            ..ProductLight::point(at, 3.0)
        };
        let plain = ProductLight::point(at, 3.0);
        let lighting = ProductLighting {
            images: 0,
            shadows: false,
        };
        let (spot_image, point_image) = (
            light_images(&space, &[spot], lighting),
            light_images(&space, &[plain], lighting),
        );
        for degrees in [0.0f64, 10.0, 25.0, 30.0, 35.0, 45.0, 80.0] {
            let a = degrees.to_radians();
            let leaving = ProductTangent::new(DVec3::X * a.sin(), -a.cos());
            let (x, _) = g.exp(at, leaving, 0.7);
            let expected = smoothstep(outer.cos(), inner.cos(), a.cos());
            let arc = light_arcs(g, x, at)[0];
            let share = spot_share(g, x, &arc, spot_image[0].spot.expect("a spot"));
            assert!(
                (share - expected).abs() < 1e-9,
                "{} at {degrees}: {share} against {expected}",
                g.name()
            );
            if g.curvature() < 0.0 {
                // Facing the light: the point light's light, times the share.
                let normal = arc.dir;
                let lit = |images: &[bevy_manifold_core::trace::product::ProductLightImage]| {
                    direct(
                        &space,
                        &ProductObjects::default(),
                        images,
                        (x, normal, normal),
                        [1.0; 3],
                        0.0,
                        false,
                        0,
                    )
                };
                let (with, without) = (lit(&spot_image), lit(&point_image));
                assert!(
                    (f64::from(with[0]) - f64::from(without[0]) * expected).abs() < 1e-6 * f64::from(without[0]),
                    "at {degrees}: {with:?} against {without:?} x {expected}"
                );
            }
        }
    }
    // Through the top of S2 x S1 (circle 2), the image 2 above is the
    // light lifted: its axis is still straight down, and a point straight
    // below that image (above the prism's top) gets all its light.
    let space = ProductSpace::s2_x_s1(2.0);
    let spot = ProductLight {
        spot: Some(ProductSpot {
            axis: ProductTangent::new(DVec3::ZERO, -1.0),
            inner,
            outer,
        }),
        range: Some(3.0),
        ..ProductLight::point(ProductPoint::new(DVec3::Z, 0.5), 3.0)
    };
    let found = light_images(&space, &[spot], ProductLighting::default());
    let lifted = found
        .iter()
        .find(|i| (i.position.height - 2.5).abs() < 1e-9)
        .expect("the image 2 up");
    let (axis, _, _) = lifted.spot.expect("a spot");
    assert!((axis.height + 1.0).abs() < 1e-12, "{axis:?}");
}
