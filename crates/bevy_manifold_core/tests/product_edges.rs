//! The prism's edges as tubes of the product metric (`ProductTubes`),
//! against distances worked out by hand from the models: a ray aimed at
//! a corner of the polygon enters the vertical edge's tube where its
//! surface part comes within the radius of the corner; a ray aimed at the
//! point of a side at the top nearest it enters that edge's tube at its
//! distance less the radius; and the tubes cast shadows.

use bevy_manifold_core::geometry::product::{ProductPoint, ProductTangent};
use bevy_manifold_core::space::product::ProductSpace;
use bevy_manifold_core::trace::product::{
    EDGE_ID, LightArc, ProductEdges, ProductObjects, ProductRay, ProductScene, ProductTubes, render, shadowed,
};
use glam::DVec3;

const R: f64 = 0.05;

fn spaces() -> [ProductSpace; 2] {
    [ProductSpace::genus_two_x_s1(2.0), ProductSpace::mirrored_prism(5, 2.0)]
}

fn tubes(space: &ProductSpace) -> ProductTubes {
    ProductTubes::of(
        space,
        Some(ProductEdges {
            radius: R,
            ..ProductEdges::default()
        }),
    )
}

/// The unit tangent at the hyperbolic plane's origin `(0, 0, 1)` towards
/// the point `q`, and the distance to it: the tangent plane there is the
/// `xy` plane, where the form is Euclidean, and `cosh d = q.z`.
fn towards(q: DVec3) -> (DVec3, f64) {
    (DVec3::new(q.x, q.y, 0.0).normalize(), q.z.acosh())
}

/// From the origin at height 0, the ray whose surface part heads at `q`
/// at the angle `alpha` above the surface.
fn ray_at(q: DVec3, alpha: f64) -> (ProductRay, f64) {
    let (u, d) = towards(q);
    let ray = ProductRay {
        origin: ProductPoint::ORIGIN,
        dir: ProductTangent::new(u * alpha.cos(), alpha.sin()),
    };
    (ray, d)
}

/// A ray heading at a corner at angle `alpha` above the surface comes
/// within `R` of it on the surface after `(d - R) / cos alpha` (its
/// surface part moves straight at the corner at speed `cos alpha`), and
/// the nearest point of the edge there is the corner at the ray's height.
#[test]
fn a_ray_at_a_corner_enters_its_vertical_tube_where_the_surface_says() {
    for space in spaces() {
        let g = space.geometry;
        let tubes = tubes(&space);
        for corner in space.vertices() {
            // Shallow enough to meet the corner between the bottom and the
            // top (the octagon's corners are 2.45 from its centre).
            for alpha in [0.0, 0.3, -0.25] {
                let (ray, d) = ray_at(corner, alpha);
                let (s, near) = tubes.entry(g, &ray, 10.0).expect("a tube");
                let want = (d - R) / alpha.cos();
                assert!((s - want).abs() < 1e-9, "{}: {s} vs {want}", space.name);
                assert!((near.surface - corner).length() < 1e-9, "{}: {near:?}", space.name);
                assert!((near.height - want * alpha.sin()).abs() < 1e-9, "{}", space.name);
            }
        }
    }
}

/// The point of a side nearest the centre of the (regular) polygon is
/// the foot of the perpendicular, `o - <o, n> n` put on the model; at the
/// top of the prism, `H / 2` up, it is `D = sqrt(d^2 + (H/2)^2)` from the
/// origin, and the ray straight at it enters the tube about that side at
/// `D - R` (the ray's distance to the edge falls as it moves: `D - s`).
#[test]
fn a_ray_at_a_side_at_the_top_enters_its_tube_at_its_distance_less_the_radius() {
    for space in spaces() {
        let g = space.geometry;
        let tubes = tubes(&space);
        let half = space.height / 2.0;
        let corners = space.vertices();
        let n = corners.len();
        for (i, side) in space.sides.iter().enumerate() {
            let normal = *side / g.form(*side, *side).sqrt();
            let o = DVec3::Z;
            let foot = o - normal * g.form(o, normal);
            let foot = foot / (-g.form(foot, foot)).sqrt();
            // The foot is the side's midpoint: it lies between its corners.
            let (a, b) = (corners[(i + n - 1) % n], corners[i]);
            let (da, db) = (g.surface_distance(foot, a), g.surface_distance(foot, b));
            assert!((da - db).abs() < 1e-9, "{}: side {i}: {da} {db}", space.name);
            for height in [half, -half] {
                let (u, d) = towards(foot);
                let big = d.hypot(height);
                let ray = ProductRay {
                    origin: ProductPoint::ORIGIN,
                    dir: ProductTangent::new(u * (d / big), height / big),
                };
                let (s, near) = tubes.entry(g, &ray, 10.0).expect("a tube");
                assert!(
                    (s - (big - R)).abs() < 1e-9,
                    "{}: side {i} at {height}: {s} vs {}",
                    space.name,
                    big - R
                );
                assert!(g.distance(near, ProductPoint::new(foot, height)) < 1e-6, "{near:?}");
            }
        }
    }
}

/// A way to a light past a corner is blocked by the corner's tube, and
/// not without the tubes; a view of the prism with its edges sees them
/// (the edge's id, its colour lit from the eye) and without them does
/// not.
#[test]
fn the_tubes_cast_shadows_and_are_seen() {
    let space = ProductSpace::genus_two_x_s1(2.0);
    let tubes = tubes(&space);
    let corner = space.vertices()[0];
    let (ray, d) = ray_at(corner, 0.0);
    let arc = LightArc {
        dir: ray.dir,
        length: d + 0.5,
        surface: d + 0.5,
    };
    let x = (ProductPoint::ORIGIN, ray.dir);
    assert!(shadowed(
        &space,
        &ProductObjects {
            tubes: tubes.clone(),
            ..ProductObjects::default()
        },
        x,
        &arc,
        8
    ));
    assert!(!shadowed(&space, &ProductObjects::default(), x, &arc, 8));
    // Short of the tube: free.
    let short = LightArc {
        length: d - R - 0.01,
        ..arc
    };
    assert!(!shadowed(
        &space,
        &ProductObjects {
            tubes: tubes.clone(),
            ..ProductObjects::default()
        },
        x,
        &short,
        8
    ));

    let mut scene = ProductScene::default_for(&space);
    let plain = render(&space, &scene, 64, 36);
    assert!(plain.iter().all(|p| p.object != EDGE_ID));
    scene.edges = Some(ProductEdges {
        radius: R,
        color: [0.1, 0.9, 0.1],
    });
    let edged = render(&space, &scene, 64, 36);
    let seen: Vec<_> = edged.iter().filter(|p| p.object == EDGE_ID).collect();
    assert!(seen.len() > 20, "{} edge pixels", seen.len());
    // Green, shaded from the eye (0.25 to 1 of it), fogged towards grey.
    for p in &seen {
        assert!(p.color[1] > p.color[0] && p.color[1] > p.color[2], "{:?}", p.color);
    }
}
