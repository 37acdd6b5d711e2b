//! Entities that arrive under a manifold root with a Bevy `Transform` and
//! no placement, as an existing Bevy scene spawns them: each lands where
//! its transform says, read through the exponential map, checked against
//! closed forms of each geometry.

use bevy::prelude::*;
use bevy_manifold::placement::TrackedPose;
use bevy_manifold::prelude::*;
use glam::{DMat4, DVec4};

fn app() -> App {
    let mut app = App::new();
    app.add_plugins((MinimalPlugins, ManifoldPlugins::default()));
    app
}

fn placement(app: &App, e: Entity) -> Placement {
    *app.world().get::<Placement>(e).expect("a placement")
}

fn close(a: DVec4, b: DVec4) -> bool {
    (a - b).abs().max_element() < 1e-6
}

/// Bevy's own `3d_scene` example, its entities spawned under a torus root
/// as that example spawns them (a transform each, no placement): a cube
/// half a unit up, a light at (4, 8, 4) and a ball (which requires a
/// placement, the identity by default). In E3 the exponential map is the
/// translation itself; the wrap then brings each into the unit cube, in
/// the copy its integer part names.
#[test]
fn bevy_3d_scene_entities_land_where_their_transforms_say() {
    let mut app = app();
    let root = app.world_mut().spawn(ManifoldSpace::new(catalog::torus(1.0))).id();
    let plane = app.world_mut().spawn((ChildOf(root), Transform::default())).id();
    let cube = app
        .world_mut()
        .spawn((ChildOf(root), Transform::from_xyz(0.0, 0.5, 0.0)))
        .id();
    let light = app
        .world_mut()
        .spawn((ChildOf(root), Transform::from_xyz(4.0, 8.0, 4.0)))
        .id();
    let ball = app
        .world_mut()
        .spawn((
            ChildOf(root),
            TracedBall::new(0.1, Color::WHITE),
            Transform::from_xyz(0.25, -1.25, 0.0),
        ))
        .id();
    app.update();
    app.update();
    // An entity at the origin with no turn needs no placement.
    assert!(app.world().get::<Placement>(plane).is_none());
    assert!(close(placement(&app, cube).position(), DVec4::new(0.0, 0.5, 0.0, 1.0)));
    // (4, 8, 4) is the origin of the copy four, eight and four cubes over.
    let l = placement(&app, light);
    assert!(close(l.position(), DVec4::W), "{:?}", l.position());
    let cell = app.world().get::<DomainCell>(light).unwrap();
    assert!(
        close(cell.element.w_axis, DVec4::new(4.0, 8.0, 4.0, 1.0)),
        "{:?}",
        cell.element
    );
    // The required identity placement gives way to the transform.
    let b = placement(&app, ball);
    assert!(
        close(b.position(), DVec4::new(0.25, -0.25, 0.0, 1.0)),
        "{:?}",
        b.position()
    );
    let cell = app.world().get::<DomainCell>(ball).unwrap();
    assert!(close(cell.element.w_axis, DVec4::new(0.0, -1.0, 0.0, 1.0)));
    // The transform written back is the wrapped chart position.
    let t = app.world().get::<Transform>(light).unwrap();
    assert!(t.translation.length() < 1e-5, "{t:?}");
}

/// In H3 and S3 a translation is a tangent vector: the entity lands at
/// that geodesic distance (`cosh d`, `cos d` in the model's last
/// coordinate), and its frame is the transform's rotation carried along
/// the geodesic. A quarter turn about y takes x to -z; -z carried along
/// the z geodesic to distance d is `-(0, 0, cosh d, sinh d)` in H3 and
/// `-(0, 0, cos d, -sin d)` in S3.
#[test]
fn in_curved_spaces_a_translation_is_a_geodesic_distance() {
    // Inside both domains (the Poincare space's inradius is pi / 10).
    let d = 0.25f32;
    let dd = f64::from(d);
    for (space, along, tangent) in [
        (
            catalog::seifert_weber(),
            DVec4::new(0.0, 0.0, dd.sinh(), dd.cosh()),
            DVec4::new(0.0, 0.0, -dd.cosh(), -dd.sinh()),
        ),
        (
            catalog::poincare(),
            DVec4::new(0.0, 0.0, dd.sin(), dd.cos()),
            DVec4::new(0.0, 0.0, -dd.cos(), dd.sin()),
        ),
    ] {
        let name = space.name().to_string();
        let mut app = app();
        let root = app.world_mut().spawn(ManifoldSpace::new(space)).id();
        let turned =
            Transform::from_xyz(0.0, 0.0, d).with_rotation(Quat::from_rotation_y(core::f32::consts::FRAC_PI_2));
        let e = app.world_mut().spawn((ChildOf(root), turned)).id();
        app.update();
        let p = placement(&app, e);
        assert!(close(p.position(), along), "{name}: {:?}", p.position());
        assert!(close(p.isometry.x_axis, tangent), "{name}: {:?}", p.isometry.x_axis);
        assert!(close(p.isometry.y_axis, DVec4::Y), "{name}: {:?}", p.isometry.y_axis);
        assert!(!p.mirrored);
    }
}

/// What keeps its own position: an entity with a placement of its own, a
/// child of a placed entity (positioned relative to it), a tracked one.
/// A scale with one negative axis is a mirror image, as the placement
/// systems write one.
#[test]
fn placements_given_children_and_tracked_entities_are_left_alone() {
    let mut app = app();
    let space = catalog::torus(2.0);
    let given = Placement::at(&space, glam::DVec3::new(0.1, 0.2, 0.3));
    let root = app.world_mut().spawn(ManifoldSpace::new(space.clone())).id();
    let placed = app
        .world_mut()
        .spawn((ChildOf(root), given, Transform::from_xyz(0.7, 0.0, 0.0)))
        .id();
    let child = app
        .world_mut()
        .spawn((ChildOf(placed), Transform::from_xyz(0.0, 0.3, 0.0)))
        .id();
    let tracked = app
        .world_mut()
        .spawn((ChildOf(root), TrackedPose, Transform::from_xyz(0.0, 0.0, 0.4)))
        .id();
    let mirrored = app
        .world_mut()
        .spawn((
            ChildOf(root),
            Transform::from_xyz(0.2, 0.0, 0.0).with_scale(Vec3::new(-1.0, 1.0, 1.0)),
        ))
        .id();
    app.update();
    assert_eq!(placement(&app, placed).isometry, given.isometry);
    assert!(app.world().get::<Placement>(child).is_none());
    assert_eq!(
        *app.world().get::<Transform>(child).unwrap(),
        Transform::from_xyz(0.0, 0.3, 0.0)
    );
    assert!(
        app.world()
            .get::<Placement>(tracked)
            .is_none_or(|p| p.isometry == DMat4::IDENTITY)
    );
    let m = placement(&app, mirrored);
    assert!(m.mirrored);
    assert!(close(m.position(), DVec4::new(0.2, 0.0, 0.0, 1.0)));
    assert!(close(m.isometry.x_axis, -DVec4::X));
    // The mirror image written back: the same negative x scale.
    assert!(app.world().get::<Transform>(mirrored).unwrap().scale.x < 0.0);
    // A transform that is not finite places nothing (a warning says so).
    let broken = app
        .world_mut()
        .spawn((ChildOf(root), Transform::from_xyz(f32::NAN, 0.0, 0.0)))
        .id();
    app.update();
    assert!(app.world().get::<Placement>(broken).is_none());
    // By hand, the same placement.
    let by_hand = Placement::from_transform(
        &space,
        &Transform::from_xyz(0.2, 0.0, 0.0).with_scale(Vec3::new(-1.0, 1.0, 1.0)),
    );
    assert_eq!(by_hand, m);
}
