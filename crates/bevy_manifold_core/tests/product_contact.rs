//! Contacts between balls in the product spaces (`trace::product::contact`),
//! against distances worked out from the spaces' shape: up the circle of
//! S2 x S1, and across a side of the genus-2 octagon along the
//! perpendicular through the side's foot.

use bevy_manifold_core::geometry::product::{ProductPoint, ProductTangent};
use bevy_manifold_core::space::product::ProductSpace;
use bevy_manifold_core::trace::product::contact::contacts;
use bevy_manifold_core::trace::product::{ProductBall, ProductRay, flow};
use glam::DVec3;

fn ball(center: ProductPoint, radius: f64) -> ProductBall {
    ProductBall { center, radius, id: 1 }
}

/// In S2 x S1 of circle 2, balls of radius 0.3 at heights 0.9 and -0.9 on
/// the pole are 1.8 apart in the prism and 0.2 apart through its top: one
/// contact, 0.4 deep, its normal straight up; at heights 0.5 and -0.5
/// (1 apart both ways) none.
#[test]
fn balls_touch_up_the_circle_through_the_top() {
    let space = ProductSpace::s2_x_s1(2.0);
    let at = |h: f64| ball(ProductPoint::new(DVec3::Z, h), 0.3);
    let touch = contacts(&space, &at(0.9), &at(-0.9));
    assert_eq!(touch.len(), 1, "{touch:?}");
    assert!((touch[0].distance - 0.2).abs() < 1e-12);
    assert!((touch[0].depth - 0.4).abs() < 1e-12);
    let n = touch[0].normal.expect("apart");
    assert!((n.height - 1.0).abs() < 1e-12 && n.surface.length() < 1e-12, "{n:?}");
    assert!(contacts(&space, &at(0.5), &at(-0.5)).is_empty());
    // A radius that is not a number touches nothing.
    assert!(contacts(&space, &at(0.9), &ball(ProductPoint::new(DVec3::Z, -0.9), f64::NAN)).is_empty());
}

/// Across side 0 of the genus-2 octagon: a ball 0.1 inside the side's
/// foot (along the perpendicular from the origin) and one 0.1 beyond it
/// (carried back into the prism through the side) are 0.2 apart, and with
/// radii 0.15 they touch 0.1 deep, the first's normal pointing out
/// through the side; with radii 0.09, not at all.
#[test]
fn balls_touch_across_a_side_of_the_octagon() {
    let space = ProductSpace::genus_two_x_s1(2.0);
    let g = space.geometry;
    let n = space.sides[0];
    // The foot of the perpendicular from the origin: atanh(n_w / |n_xy|)
    // along n_xy.
    let across = n.truncate().length();
    let foot = (n.z / across).atanh();
    let out = ProductTangent::new(DVec3::new(n.x, n.y, 0.0) / across, 0.0);
    let along = |d: f64| {
        flow(
            &space,
            ProductRay {
                origin: ProductPoint::ORIGIN,
                dir: out,
            },
            d,
            4,
        )
    };
    let inside = along(foot - 0.1);
    let beyond = along(foot + 0.1);
    assert_eq!((inside.faces.len(), beyond.faces.len()), (0, 1));
    let touch = contacts(&space, &ball(inside.ray.origin, 0.15), &ball(beyond.ray.origin, 0.15));
    assert_eq!(touch.len(), 1, "{touch:?}");
    assert!((touch[0].distance - 0.2).abs() < 1e-9, "{}", touch[0].distance);
    assert!((touch[0].depth - 0.1).abs() < 1e-9);
    // Out through the side: along the ray that got there.
    let normal = touch[0].normal.expect("apart");
    assert!((g.dot(normal, inside.ray.dir) - 1.0).abs() < 1e-9, "{normal:?}");
    assert!(contacts(&space, &ball(inside.ray.origin, 0.09), &ball(beyond.ray.origin, 0.09)).is_empty());
}
