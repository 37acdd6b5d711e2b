//! The manifold's light: every image of a light in the cover, each along
//! its own geodesic, against sums written here from the geometry alone
//! (the lattice of the 3-torus, the 120 elements of the binary
//! icosahedral group found by closing the Poincare sphere's pairings),
//! continuity across every face, and shadows where the right-triangle
//! formulas of each geometry put them.

use bevy_manifold_core::geometry::{Geometry, isometry};
use bevy_manifold_core::prelude::*;
use bevy_manifold_core::trace::shadow::{aim_at_light, light_blocked};
use bevy_manifold_core::trace::{FlatLight, FlatScene, Spot, image_irradiance, light_images, spot_factor};
use glam::{DMat4, DVec3, DVec4};
use std::f64::consts::{PI, TAU};

/// The irradiance the tracer's images give at `x`: each image, each arc
/// (two in S3), as `shade` sums them (no normal: the full irradiance).
fn irradiance(g: Geometry, images: &[FlatLight<f64>], x: DVec4, density: f64) -> f64 {
    images
        .iter()
        .map(|l| {
            let d = g.distance::<f64>(x, l.position);
            let from = g.log::<f64>(l.position, x).map_or(DVec4::ZERO, |(v, _)| v);
            let mut e = image_irradiance::<f64>(g, l, d, density) * spot_factor::<f64>(g, l, from);
            if g == Geometry::Spherical {
                e += image_irradiance::<f64>(g, l, TAU - d, density) * spot_factor::<f64>(g, l, -from);
            }
            e
        })
        .sum()
}

/// The irradiance vector at `x`: each image's irradiance times the unit
/// tangent towards it (both arcs in S3), so that directions are checked
/// as well as amounts.
fn irradiance_vector(g: Geometry, images: &[FlatLight<f64>], x: DVec4) -> DVec4 {
    let mut v = DVec4::ZERO;
    for l in images {
        let (Some((dir, d)), Some((from, _))) = (g.log::<f64>(x, l.position), g.log::<f64>(l.position, x)) else {
            continue;
        };
        v += dir * image_irradiance::<f64>(g, l, d, 0.0) * spot_factor::<f64>(g, l, from);
        if g == Geometry::Spherical {
            v -= dir * image_irradiance::<f64>(g, l, TAU - d, 0.0) * spot_factor::<f64>(g, l, -from);
        }
    }
    v
}

/// Bevy's window on a range, written out.
fn window(s: f64, range: f64) -> f64 {
    let f = (s / range).powi(4);
    (1.0 - f).clamp(0.0, 1.0).powi(2)
}

fn light_at(p: DVec4, range: Option<f64>) -> Light {
    Light {
        range,
        ..Light::point(p, 1.0, [1.0; 3])
    }
}

fn range_of(images: &[FlatLight<f64>]) -> f64 {
    1.0 / images[0].inv_range_sq.sqrt()
}

#[test]
fn the_torus_is_lit_by_the_lattice_sum_of_its_light() {
    // The cube of edge 2: the light's images are p + 2 (i, j, k).
    let space = catalog::torus(2.0);
    let g = space.geometry();
    let p = DVec4::new(0.3, -0.2, 0.45, 1.0);
    let density = 0.1;
    let lattice = |x: DVec4, range: f64| {
        let mut e = 0.0;
        for i in -5..=5 {
            for j in -5..=5 {
                for k in -5..=5 {
                    let image = p.truncate() + 2.0 * DVec3::new(f64::from(i), f64::from(j), f64::from(k));
                    let s = (x.truncate() - image).length();
                    e += window(s, range) / (4.0 * PI * s * s) * (-density * s).exp();
                }
            }
        }
        e
    };
    let points = [
        DVec4::new(0.9, 0.9, -0.9, 1.0),
        DVec4::new(-0.7, 0.1, 0.2, 1.0),
        DVec4::new(0.0, -0.99, 0.5, 1.0),
        DVec4::new(0.31, -0.2, 0.4, 1.0),
    ];
    // A range of its own, within the budget: the sum is whole.
    let lighting = Lighting {
        images: 256,
        shadows: false,
    };
    let images = light_images::<f64>(&space, &[light_at(p, Some(3.5))], lighting);
    assert!((range_of(&images) - 3.5).abs() < 1e-12);
    for x in points {
        let want = lattice(x, 3.5);
        let got = irradiance(g, &images, x, density);
        assert!(
            (got - want).abs() <= 1e-12 * want,
            "at {x}: {got} against the lattice's {want}"
        );
    }
    // No range of its own: the budget cuts it, and the images kept are
    // every one within the cut range of any point.
    let lighting = Lighting {
        images: 32,
        shadows: false,
    };
    let images = light_images::<f64>(&space, &[light_at(p, None)], lighting);
    let range = range_of(&images);
    assert!(
        images.len() <= 32 && range > 1.0,
        "{} images, range {range}",
        images.len()
    );
    for x in points {
        let want = lattice(x, range);
        let got = irradiance(g, &images, x, density);
        assert!(
            (got - want).abs() <= 1e-12 * want,
            "at {x}: {got} against the lattice's {want}"
        );
    }
}

/// Every element of the group the pairings generate, by closing them
/// under products (the pairings' own matrices, not the tracer's walk).
fn closure(space: &Space, limit: usize) -> Vec<DMat4> {
    let gens: Vec<DMat4> = space.faces().iter().map(|f| f.pairing).collect();
    let mut all = vec![DMat4::IDENTITY];
    let mut next = 0;
    while next < all.len() && all.len() < limit {
        let m = all[next];
        next += 1;
        for t in &gens {
            let n = m * *t;
            if !all.iter().any(|a| a.abs_diff_eq(n, 1e-9)) {
                all.push(n);
            }
        }
    }
    all
}

#[test]
fn the_poincare_sphere_is_lit_by_all_120_images_both_ways_round() {
    let space = catalog::poincare();
    let g = space.geometry();
    let group = closure(&space, 200);
    assert_eq!(group.len(), 120, "the binary icosahedral group has 120 elements");
    // Its elements move every point by the angles of the unit
    // quaternions of the binary icosahedral group: 0, pi/5, pi/3, 2pi/5,
    // pi/2, ... with multiplicities 1, 12, 20, 12, 30, 12, 20, 12, 1.
    let mut spectrum = [0usize; 9];
    for m in &group {
        let d = g.distance::<f64>(DVec4::W, *m * DVec4::W);
        let k = [
            0.0,
            1.0 / 5.0,
            1.0 / 3.0,
            2.0 / 5.0,
            0.5,
            3.0 / 5.0,
            2.0 / 3.0,
            4.0 / 5.0,
            1.0,
        ]
        .iter()
        .position(|f| (d - f * PI).abs() < 1e-9)
        .expect("an angle of the binary icosahedral group");
        spectrum[k] += 1;
    }
    assert_eq!(spectrum, [1, 12, 20, 12, 30, 12, 20, 12, 1]);
    let p = g.normalize_point::<f64>(DVec4::new(0.1, 0.05, -0.12, 1.0));
    let lighting = Lighting {
        images: 128,
        shadows: false,
    };
    let images = light_images::<f64>(&space, &[light_at(p, None)], lighting);
    assert_eq!(images.len(), 120);
    assert_eq!(images[0].inv_range_sq, 0.0, "no cut-off: the whole group fits");
    for x in [
        DVec4::W,
        g.normalize_point::<f64>(DVec4::new(0.2, -0.15, 0.1, 1.0)),
        g.normalize_point::<f64>(DVec4::new(-0.25, 0.3, 0.05, 1.0)),
    ] {
        // Both arcs of each image: sin^2 is the same either way round.
        let want: f64 = group
            .iter()
            .map(|m| {
                let d = (x.dot(*m * p)).clamp(-1.0, 1.0).acos();
                2.0 / (4.0 * PI * d.sin().powi(2)).max(1e-4)
            })
            .sum();
        let got = irradiance(g, &images, x, 0.0);
        assert!((got - want).abs() <= 1e-9 * want, "at {x}: {got} against {want}");
    }
}

/// The spaces the continuity test walks: the catalog and four library
/// spaces of other kinds (a lens space, a small hyperbolic manifold, a
/// flat one with a twist, the quaternionic space).
fn spaces() -> Vec<Space> {
    let mut out: Vec<Space> = catalog::NAMES.iter().filter_map(|n| catalog::by_name(n)).collect();
    for n in ["lens-7-2", "weeks", "hantzsche-wendt", "quaternionic"] {
        out.push(catalog::resolve(n).expect("a library space"));
    }
    out
}

/// A point inside face `f`'s polygon: a tenth of the way from the face's
/// centre of vertices to its first vertex, on the plane.
fn point_on_face(space: &Space, f: usize) -> DVec4 {
    let g = space.geometry();
    let verts: Vec<DVec4> = space.polyhedron().face_vertices[f]
        .iter()
        .map(|&v| space.vertices()[v].point)
        .collect();
    let centre = verts.iter().copied().sum::<DVec4>() / verts.len() as f64;
    g.normalize_point::<f64>(centre * 0.9 + verts[0] * 0.1)
}

#[test]
fn light_is_continuous_across_every_face() {
    for space in spaces() {
        let g = space.geometry();
        let p = g.normalize_point::<f64>(
            DVec4::new(0.11, -0.07, 0.05, 1.0) * space.inradius() + DVec4::W * (1.0 - space.inradius()),
        );
        let lighting = Lighting {
            images: 64,
            shadows: false,
        };
        // A lamp, and a wide spot pointing off along a skew axis: its
        // cone must turn with each image.
        let spot = Light {
            spot: Some(Spot {
                direction: DVec4::new(0.3, -0.8, 0.5, 0.0),
                inner: 0.6,
                outer: 1.4,
            }),
            ..light_at(p, None)
        };
        let images = light_images::<f64>(&space, &[light_at(p, None), spot], lighting);
        let seam = light_images::<f64>(&space, &[light_at(p, None)], Lighting::DOMAIN_COPY);
        let mut worst_seam = 0.0f64;
        for (f, face) in space.faces().iter().enumerate() {
            let x = point_on_face(&space, f);
            // The same point of the manifold, seen from the partner face.
            let y = g.normalize_point::<f64>(face.pairing * x);
            let (vx, vy) = (irradiance_vector(g, &images, x), irradiance_vector(g, &images, y));
            let scale = irradiance(g, &images, x, 0.0).max(1e-12);
            assert!(
                ((face.pairing * vx) - vy).length() <= 1e-9 * scale,
                "{}: face {f}: light {vx} on one side, {vy} on the other",
                space.name()
            );
            let (ex, ey) = (irradiance(g, &seam, x, 0.0), irradiance(g, &seam, y, 0.0));
            worst_seam = worst_seam.max((ex - ey).abs() / ex.max(ey));
        }
        // Each light's copy in the domain alone seams (this test would see
        // it), except in the mirrored spaces, whose faces map to themselves.
        if space.faces().iter().enumerate().any(|(i, f)| f.partner != i) {
            assert!(
                worst_seam > 0.01,
                "{}: the domain copy alone seams by {worst_seam}",
                space.name()
            );
        }
    }
}

/// The least distance from `c` to the geodesic segment from `x` to `p`:
/// the foot of the perpendicular from `c` to the geodesic through `x`
/// with unit tangent `u` is where `c` projects onto the plane of `x` and
/// `u` (R^4, with the form of the geometry), at distance `b` along it
/// with `tan b = <c,u> / <c,x>` (S3; `tanh`, H3; `b = (c - x).u`, E3)
/// and `cos h = |projection|` (`cosh`, H3; Pythagoras, E3): the
/// right-triangle formulas of each geometry. An end of the segment when
/// the foot is off it.
fn segment_distance(g: Geometry, x: DVec4, p: DVec4, c: DVec4) -> f64 {
    let Some((u, len)) = g.log::<f64>(x, p) else {
        return g.distance::<f64>(x, c);
    };
    let (b, h) = match g {
        Geometry::Euclidean => {
            let v = (c - x).truncate();
            let b = v.dot(u.truncate());
            (b, (v - u.truncate() * b).length())
        }
        Geometry::Hyperbolic => {
            let (cx, cu) = (-g.form::<f64>(c, x), g.form::<f64>(c, u));
            ((cu / cx).atanh(), (cx * cx - cu * cu).max(1.0).sqrt().acosh())
        }
        Geometry::Spherical => {
            let (cx, cu) = (c.dot(x), c.dot(u));
            (cu.atan2(cx), (cx * cx + cu * cu).sqrt().min(1.0).acos())
        }
    };
    if b > 0.0 && b < len {
        h
    } else {
        g.distance::<f64>(x, c).min(g.distance::<f64>(p, c))
    }
}

#[test]
fn a_ball_casts_its_umbra_where_the_geometry_puts_it_in_each_geometry() {
    for space in [catalog::torus(2.0), catalog::seifert_weber(), catalog::poincare()] {
        let g = space.geometry();
        let r_in = space.inradius();
        let c = g.normalize_point::<f64>(DVec4::new(0.1, 0.0, 0.0, 1.0) * r_in + DVec4::W * (1.0 - r_in));
        let c = if g == Geometry::Euclidean {
            DVec4::new(0.1, 0.0, 0.0, 1.0)
        } else {
            c
        };
        let radius = 0.25 * r_in;
        let mut scene = Scene::empty();
        scene.balls.push(Ball {
            center: c,
            radius,
            color: [1.0; 3],
            glow: 0.0,
            pbr: None,
        });
        let flat = FlatScene::<f64>::new(&space, &scene);
        // Every copy of the ball a shadow ray can meet: the group's
        // images of its centre (closed from the pairings, as far as
        // three products in H3).
        let copies: Vec<DVec4> = closure(&space, 2000).iter().map(|m| *m * c).collect();
        let light = isometry::translation(g, DVec3::new(0.7, 0.2, -0.1) * r_in) * DVec4::W;
        let (mut shadowed, mut lit) = (0, 0);
        for i in 0..400 {
            // Points on a sphere about the light's far side, some through
            // faces: the light's image across the +x face for half.
            let t = f64::from(i) * 0.618_034;
            let dir = DVec3::new((t * TAU).cos(), (t * 3.7).sin(), (t * 5.3).cos()).normalize();
            let x =
                g.normalize_point::<f64>(isometry::translation(g, dir * 0.4 * r_in - DVec3::X * 0.4 * r_in) * DVec4::W);
            let target = if i % 2 == 0 {
                light
            } else {
                // Across the face the +x axis leaves by: the copy of the
                // light there.
                let f = (0..space.faces().len())
                    .max_by(|&a, &b| space.faces()[a].plane.x.total_cmp(&space.faces()[b].plane.x))
                    .unwrap_or(0);
                space.crossing(f) * light
            };
            let Some((dir, len)) = g.log::<f64>(x, target) else {
                continue;
            };
            let want = copies
                .iter()
                .map(|&cc| segment_distance(g, x, target, cc))
                .fold(f64::INFINITY, f64::min);
            if (want - radius).abs() < 1e-3 || copies.iter().any(|&cc| g.distance::<f64>(x, cc) < radius + 1e-3) {
                continue;
            }
            let normal = dir;
            let got = light_blocked(&flat, (x, normal), dir, len, (DMat4::IDENTITY, true));
            assert_eq!(
                got,
                want < radius,
                "{}: x {x}, to {target}: {want} from the ball of radius {radius}",
                space.name()
            );
            if got {
                shadowed += 1;
            } else {
                lit += 1;
            }
        }
        assert!(
            shadowed > 20 && lit > 20,
            "{}: {shadowed} shadowed, {lit} lit",
            space.name()
        );
    }
}

#[test]
fn a_spot_lights_by_bevys_cone_from_every_image() {
    // The torus of edge 2, a spot pointing along +x: each image p + 2k
    // points along +x too (the pairings are translations), and lights x
    // by Bevy's fall-off at the angle between +x and x - (p + 2k).
    let space = catalog::torus(2.0);
    let g = space.geometry();
    let p = DVec4::new(-0.2, 0.1, 0.0, 1.0);
    let (inner, outer) = (0.25f64, 0.6f64);
    let light = Light {
        spot: Some(Spot {
            direction: DVec4::new(2.0, 0.0, 0.0, 0.0),
            inner,
            outer,
        }),
        ..light_at(p, Some(3.0))
    };
    let lighting = Lighting {
        images: 256,
        shadows: false,
    };
    let images = light_images::<f64>(&space, &[light], lighting);
    for x in [
        DVec4::new(0.8, 0.15, -0.1, 1.0),
        DVec4::new(0.5, 0.4, 0.2, 1.0),
        DVec4::new(-0.6, 0.05, 0.1, 1.0),
    ] {
        let mut want = 0.0;
        for i in -3..=3 {
            for j in -3..=3 {
                for k in -3..=3 {
                    let image = p.truncate() + 2.0 * DVec3::new(f64::from(i), f64::from(j), f64::from(k));
                    let v = x.truncate() - image;
                    let s = v.length();
                    let cos_a = v.x / s;
                    let cone = ((cos_a - outer.cos()) / (inner.cos() - outer.cos()))
                        .clamp(0.0, 1.0)
                        .powi(2);
                    want += cone * window(s, 3.0) / (4.0 * PI * s * s);
                }
            }
        }
        let got = irradiance(g, &images, x, 0.0);
        assert!(
            want > 0.0 && (got - want).abs() <= 1e-12 * want,
            "at {x}: {got} against {want}"
        );
    }
}

/// A spot's direction is a tangent at the light; a scene file holds it as
/// a direction of the chart there. Written and read back, the cone points
/// the same way, in every geometry and away from the origin (where the
/// tangent's `w` is not 0 in H3 and S3); a ball's material comes back too.
#[test]
fn a_spot_and_a_material_keep_through_a_scene_file() {
    for space in [catalog::torus(1.0), catalog::seifert_weber(), catalog::poincare()] {
        let g = space.geometry();
        let mut scene = Scene::default_for(&space);
        let p = scene.lights[0].position;
        assert!(
            (p.w - 1.0).abs() > 1e-3 || g == Geometry::Euclidean,
            "{g}: the light is off the origin"
        );
        let dir = g.normalize_tangent::<f64>(p, g.project_tangent::<f64>(p, DVec4::new(0.3, -0.8, 0.5, 0.4)));
        scene.lights[0].spot = Some(Spot {
            direction: dir,
            inner: 0.2,
            outer: 0.5,
        });
        let pbr = bevy_manifold_core::material::Pbr {
            metallic: 0.25,
            roughness: 0.75,
        };
        scene.balls[0].pbr = Some(pbr);
        let read = Scene::parse(&scene.to_json(), "spot.scene.json", &space).expect("parses");
        let spot = read.lights[0].spot.expect("a spot");
        let back = g.normalize_tangent::<f64>(p, spot.direction);
        assert!((back - dir).length() < 1e-9, "{g}: {back} against {dir}");
        assert_eq!((spot.inner, spot.outer), (0.2, 0.5));
        assert_eq!(read.balls[0].pbr, Some(pbr), "{g}");
    }
}

/// `sin_k(d)`: `d`, `sinh d`, `sin d`, the geometry's sine.
fn sin_k(g: Geometry, d: f64) -> f64 {
    match g {
        Geometry::Euclidean => d,
        Geometry::Hyperbolic => d.sinh(),
        Geometry::Spherical => d.sin(),
    }
}

#[test]
fn the_shadow_ray_stops_at_the_near_surface_of_a_light_ball() {
    // Along each direction of the cone, the arc the tracer gives ends on
    // the light's sphere (distance to its centre = its radius, found by
    // the exponential map here), and a little before it the point is
    // still outside: the nearer root. In S3 the long way round too.
    for space in [catalog::torus(2.0), catalog::seifert_weber(), catalog::poincare()] {
        let g = space.geometry();
        let x = g.origin::<f64>();
        let dir = DVec4::new(0.6, 0.8, 0.0, 0.0);
        let other = DVec4::new(0.0, 0.0, 1.0, 0.0);
        for (s, radius) in [(0.5, 0.1), (1.0, 0.3), (0.2, 0.15)] {
            let arcs: &[(f64, DVec4)] = if g == Geometry::Spherical {
                &[(s, dir), (TAU - s, -dir)]
            } else {
                &[(s, dir)]
            };
            for &(s, dir) in arcs {
                let centre = g.exp::<f64>(x, dir, s).0;
                let sin_a = sin_k(g, radius) / sin_k(g, s);
                for k in 0..=8 {
                    let t = sin_a.asin() * f64::from(k) / 8.0;
                    let d = dir * t.cos() + other * t.sin();
                    let u = bevy_manifold_core::trace::shadow::arc_to_sphere::<f64>(g, s, t.cos(), radius);
                    let on = g.distance::<f64>(g.exp::<f64>(x, d, u).0, centre);
                    assert!(
                        (on - radius).abs() < 1e-9,
                        "{}: s {s}, t {t}: the arc {u} ends {on} from the centre, not {radius}",
                        space.name()
                    );
                    if k < 8 {
                        let before = g.distance::<f64>(g.exp::<f64>(x, d, u - 1e-3).0, centre);
                        assert!(before > radius, "{}: s {s}, t {t}: {before}", space.name());
                    }
                }
            }
        }
    }
}

/// The share of the disc a light of radius `rho` at `l` shows `x` that
/// a ball (`c`, `r`) hides, integrated here on an `m` x `m` grid even in
/// solid angle (cos t and the angle around), in a frame of our own, each
/// direction followed to the light's sphere by the exponential map
/// (stepping, then bisection) and tested by the right-triangle distance
/// from the ball's centre to the segment.
fn hidden_share(g: Geometry, x: DVec4, l: DVec4, rho: f64, (c, r): (DVec4, f64), m: u32) -> f64 {
    let (a, s) = g.log::<f64>(x, l).expect("apart");
    let perp = |v: DVec4, keep: &[DVec4]| {
        let mut t = g.project_tangent::<f64>(x, v);
        for &k in keep {
            t -= k * g.form::<f64>(t, k);
        }
        t / g.form::<f64>(t, t).sqrt()
    };
    let b = perp(DVec4::new(1.0, 1.0, 1.0, 0.0), &[a]);
    let e = perp(DVec4::new(1.0, -2.0, 0.5, 0.0), &[a, b]);
    let cos_a = (1.0 - (sin_k(g, rho) / sin_k(g, s)).powi(2)).sqrt();
    let outside = |d: DVec4, u: f64| g.distance::<f64>(g.exp::<f64>(x, d, u).0, l) > rho;
    let mut hidden = 0;
    for i in 0..m {
        for j in 0..m {
            let cos_t = 1.0 - (f64::from(i) + 0.5) / f64::from(m) * (1.0 - cos_a);
            let sin_t = (1.0 - cos_t * cos_t).sqrt();
            let phi = TAU * (f64::from(j) + 0.5) / f64::from(m);
            let d = a * cos_t + (b * phi.cos() + e * phi.sin()) * sin_t;
            let (mut lo, step) = (0.0, rho / 64.0);
            while outside(d, lo + step) {
                lo += step;
            }
            let mut hi = lo + step;
            for _ in 0..50 {
                let mid = 0.5 * (lo + hi);
                if outside(d, mid) {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            if segment_distance(g, x, g.exp::<f64>(x, d, lo).0, c) < r {
                hidden += 1;
            }
        }
    }
    f64::from(hidden) / f64::from(m * m)
}

#[test]
fn a_light_with_a_radius_casts_the_penumbra_the_geometry_predicts() {
    // A ball between a point and a light ball, in each geometry: the
    // share of 256 shadow rays (the samples a still view accumulates)
    // that it stops is the share of the light's disc it hides. On the
    // axis, the discs are concentric: (1 - cos b) / (1 - cos a), with
    // sin a = sin_k(rho) / sin_k(s) and sin b = sin_k(r) / sin_k(d);
    // off the axis, the integral of [`hidden_share`].
    const SAMPLES: u32 = 256;
    for space in [catalog::torus(2.0), catalog::seifert_weber(), catalog::poincare()] {
        let g = space.geometry();
        let r_in = space.inradius();
        let at = |v: DVec3| g.normalize_point::<f64>(isometry::translation(g, v * r_in) * DVec4::W);
        let x = at(DVec3::new(-0.6, 0.0, 0.0));
        let l = at(DVec3::new(0.6, 0.0, 0.0));
        let (rho, r) = (0.2 * r_in, 0.06 * r_in);
        let (a, s) = g.log::<f64>(x, l).expect("apart");
        for (offset, name) in [(0.0, "on the axis"), (0.1, "off the axis")] {
            let c = at(DVec3::new(0.0, offset, 0.0));
            let mut scene = Scene::empty();
            scene.balls.push(Ball {
                center: c,
                radius: r,
                color: [1.0; 3],
                glow: 0.0,
                pbr: None,
            });
            let flat = FlatScene::<f64>::new(&space, &scene);
            let blocked = (0..SAMPLES)
                .filter(|&k| {
                    let u = bevy_manifold_core::trace::light_sample_point(k);
                    let (aim, len) = aim_at_light::<f64>(g, x, (a, s), rho, u);
                    light_blocked(&flat, (x, a), aim, len, (DMat4::IDENTITY, true))
                })
                .count();
            let got = blocked as f64 / f64::from(SAMPLES);
            let want = hidden_share(g, x, l, rho, (c, r), 96);
            if offset == 0.0 {
                let d = g.distance::<f64>(x, c);
                let cos_a = (1.0 - (sin_k(g, rho) / sin_k(g, s)).powi(2)).sqrt();
                let cos_b = (1.0 - (sin_k(g, r) / sin_k(g, d)).powi(2)).sqrt();
                let closed = (1.0 - cos_b) / (1.0 - cos_a);
                assert!(
                    (want - closed).abs() < 0.01,
                    "{}: the integral {want} is not the closed form {closed}",
                    space.name()
                );
            }
            eprintln!(
                "{} {name}: {got:.4} of the light hidden, the geometry says {want:.4}",
                space.name()
            );
            assert!(
                want > 0.05 && want < 0.95,
                "{}: {name}: a penumbra, not {want}",
                space.name()
            );
            assert!(
                (got - want).abs() < 0.02,
                "{} {name}: {got} of the shadow rays stopped, the geometry says {want}",
                space.name()
            );
        }
    }
}
