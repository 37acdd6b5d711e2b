//! Overlap, contact and shape-cast queries and contact messages between
//! colliders, through the face pairings, in a headless `App`. Expected
//! values are the geometry's: distances through a torus face in closed
//! form, and along a geodesic through two ball centres in H3.

use bevy::prelude::*;
use bevy_manifold::prelude::*;
use glam::{DVec3, DVec4};

fn app() -> App {
    let mut app = App::new();
    app.add_plugins((MinimalPlugins, ManifoldPlugins::default()));
    app
}

fn drain<M: Message>(app: &mut App) -> Vec<M> {
    app.world_mut().resource_mut::<Messages<M>>().drain().collect()
}

fn ball(radius: f64) -> ManifoldCollider {
    ManifoldCollider::Ball { radius }
}

/// Two balls of radius 0.15 at x = -0.4 and x = 0.4 of the unit torus are
/// 0.2 apart through the face x = 1/2: they touch once the second is
/// placed, stop when it moves to x = 0 (0.4 apart), touch again when it
/// comes back, and stop when it is despawned. A pair where neither asks
/// for messages sends none.
#[test]
fn contact_messages_start_and_end_through_a_face() {
    let mut app = app();
    let space = catalog::torus(1.0);
    let root = app.world_mut().spawn(ManifoldSpace::new(space.clone())).id();
    let at = |x: f64| Placement::at(&space, DVec3::X * x);
    let a = app
        .world_mut()
        .spawn((ChildOf(root), ball(0.15), ContactEvents, at(-0.4)))
        .id();
    let b = app.world_mut().spawn((ChildOf(root), ball(0.15), at(0.4))).id();
    // Two more that touch each other but nothing asks about.
    app.world_mut().spawn((ChildOf(root), ball(0.05), at(0.0)));
    app.world_mut().spawn((
        ChildOf(root),
        ball(0.05),
        Placement::at(&space, DVec3::new(0.05, 0.0, 0.0)),
    ));
    app.update();
    assert_eq!(drain::<ContactStarted>(&mut app), vec![ContactStarted { a, b }]);
    assert!(drain::<ContactEnded>(&mut app).is_empty());
    app.update();
    assert!(
        drain::<ContactStarted>(&mut app).is_empty(),
        "sent once, not every frame"
    );
    *app.world_mut().get_mut::<Placement>(b).unwrap() = Placement::at(&space, DVec3::new(0.2, 0.3, 0.0));
    app.update();
    assert_eq!(drain::<ContactEnded>(&mut app), vec![ContactEnded { a, b }]);
    *app.world_mut().get_mut::<Placement>(b).unwrap() = at(0.4);
    app.update();
    assert_eq!(drain::<ContactStarted>(&mut app), vec![ContactStarted { a, b }]);
    app.world_mut().entity_mut(b).despawn();
    app.update();
    assert_eq!(drain::<ContactEnded>(&mut app), vec![ContactEnded { a, b }]);
}

/// The queries: what overlaps a ball placed by hand, what an entity
/// touches, the contacts of a pair and the nearest image, each through
/// the face as the torus's closed form says.
#[test]
fn overlaps_and_contacts_are_seen_through_the_faces() {
    let mut app = app();
    let space = catalog::torus(1.0);
    let root = app.world_mut().spawn(ManifoldSpace::new(space.clone())).id();
    let near = app
        .world_mut()
        .spawn((
            ChildOf(root),
            ball(0.05),
            Placement::at(&space, DVec3::new(-0.45, 0.0, 0.0)),
        ))
        .id();
    let far = app
        .world_mut()
        .spawn((
            ChildOf(root),
            ball(0.05),
            Placement::at(&space, DVec3::new(-0.1, 0.0, 0.0)),
        ))
        .id();
    app.update();
    let query = |app: &mut App, f: fn(ManifoldContacts, Entity, Entity) -> Vec<f64>| {
        let mut state = bevy::ecs::system::SystemState::<ManifoldContacts>::new(app.world_mut());
        let contacts = state.get(app.world()).expect("the query");
        f(contacts, near, far)
    };
    // A ball of radius 0.1 at x = 0.45: `near` is 0.1 away through the
    // face (depth 0.05), `far` 0.45 away across the cube.
    let hits = {
        let mut state = bevy::ecs::system::SystemState::<ManifoldContacts>::new(app.world_mut());
        let contacts = state.get(app.world()).expect("the query");
        contacts.overlapping(root, ball(0.1), &Placement::at(&space, DVec3::X * 0.45))
    };
    assert_eq!(hits.len(), 1);
    assert_eq!(hits[0].entity, near);
    assert!((hits[0].contacts[0].depth - 0.05).abs() < 1e-12);
    assert!((hits[0].contacts[0].image.distance - 0.1).abs() < 1e-12);
    // `near` and `far` are 0.35 apart: no contact; `near` touches nothing.
    let got = query(&mut app, |c, a, b| c.contacts(a, b).iter().map(|c| c.depth).collect());
    assert!(got.is_empty(), "{got:?}");
    let got = query(&mut app, |c, a, _| {
        c.touching(a).iter().map(|o| o.contacts[0].depth).collect()
    });
    assert!(got.is_empty(), "{got:?}");
    // The nearest image of `far` from `near`: 0.35 along +x.
    let got = query(&mut app, |c, a, b| {
        c.nearest_image(a, b)
            .map(|i| vec![i.distance, i.direction.x])
            .unwrap_or_default()
    });
    assert!((got[0] - 0.35).abs() < 1e-12 && (got[1] - 1.0).abs() < 1e-12, "{got:?}");
    // Grown to 0.31, `near` touches `far`, 0.01 deep.
    app.world_mut().entity_mut(near).insert(ball(0.31));
    let got = query(&mut app, |c, a, b| c.contacts(a, b).iter().map(|c| c.depth).collect());
    assert_eq!(got.len(), 1);
    assert!((got[0] - 0.01).abs() < 1e-12, "{got:?}");
    // A ball of radius 0.55 touches its own six neighbouring images.
    app.world_mut().entity_mut(far).insert(ball(0.55));
    let got = query(&mut app, |c, _, b| {
        c.touching(b)
            .iter()
            .filter(|o| o.entity == b)
            .flat_map(|o| o.contacts.iter().map(|c| c.image.distance))
            .collect()
    });
    assert_eq!(got.len(), 6, "{got:?}");
    assert!(got.iter().all(|d| (d - 1.0).abs() < 1e-12));
}

/// A ball swept along a geodesic first touches another when their
/// centres are the radii's sum apart: in the Seifert-Weber space (H3) a
/// ball of 0.1 swept from the centre towards a ball of 0.2 at distance 0.9
/// touches it after 0.6; in the torus, one swept from x = 0.3 along +x
/// touches a ball at x = -0.3 through the face after 0.4 - 0.1, where the
/// ray (no radius) goes 0.05 further.
#[test]
fn shape_casts_stop_where_the_swept_ball_first_touches() {
    let mut app = app();
    let sw = catalog::seifert_weber();
    let root = app.world_mut().spawn(ManifoldSpace::new(sw.clone())).id();
    let caster = app.world_mut().spawn((ChildOf(root), Placement::default())).id();
    let target = app
        .world_mut()
        .spawn((ChildOf(root), ball(0.2), Placement::at(&sw, DVec3::NEG_Z * 0.9)))
        .id();
    let torus = catalog::torus(1.0);
    let root2 = app.world_mut().spawn(ManifoldSpace::new(torus.clone())).id();
    let caster2 = app
        .world_mut()
        .spawn((ChildOf(root2), Placement::at(&torus, DVec3::X * 0.3)))
        .id();
    let target2 = app
        .world_mut()
        .spawn((ChildOf(root2), ball(0.05), Placement::at(&torus, DVec3::X * -0.3)))
        .id();
    app.update();
    let mut state = bevy::ecs::system::SystemState::<ManifoldRayCast>::new(app.world_mut());
    let cast = state.get(app.world()).expect("the query");
    let settings = RayCastSettings::default();
    let hits = cast.shape_cast(caster, ball(0.1), DVec3::NEG_Z, &settings);
    assert_eq!(hits[0].entity, target);
    assert!((hits[0].distance - 0.6).abs() < 1e-9, "{}", hits[0].distance);
    // The swept ball's centre at the touch: 0.6 down the z axis.
    let want = DVec4::new(0.0, 0.0, -(0.6f64.sinh()), 0.6f64.cosh());
    let p = hits[0].point;
    assert!((p / p.w - want / want.w).length() < 1e-9, "{p:?}");
    let hits = cast.shape_cast(caster2, ball(0.05), DVec3::X, &settings);
    assert_eq!(hits[0].entity, target2);
    assert!((hits[0].distance - 0.3).abs() < 1e-12, "{}", hits[0].distance);
    assert_eq!(hits[0].faces.len(), 1);
    let ray = cast.cast(caster2, DVec3::X, &settings);
    assert!((ray[0].distance - 0.35).abs() < 1e-12);
    // A shape with no size or a NaN one: a ray, and nothing.
    let zero = cast.shape_cast(caster2, ball(0.0), DVec3::X, &settings);
    assert!((zero[0].distance - 0.35).abs() < 1e-12);
    assert!(cast.shape_cast(caster2, ball(f64::NAN), DVec3::X, &settings).is_empty());
}
