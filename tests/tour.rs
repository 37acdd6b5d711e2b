//! `TourPlayer` in a headless app: the camera flies the tour through the
//! faces like any entity (one `FaceCrossed` per face of the route) and
//! arrives at the pose a direct placement gives.

use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use bevy_manifold::geometry::isometry;
use bevy_manifold::prelude::*;
use bevy_manifold::tour::TourDesc;
use glam::DMat4;
use std::time::Duration;

#[derive(Resource, Default)]
struct Crossings(Vec<FaceCrossed>);

fn collect(mut reader: MessageReader<FaceCrossed>, mut all: ResMut<Crossings>) {
    all.0.extend(reader.read().copied());
}

fn max_abs(m: DMat4) -> f64 {
    m.to_cols_array().iter().fold(0.0f64, |a, x| a.max(x.abs()))
}

/// A headless app at 60 frames a second that collects `FaceCrossed`.
fn app() -> App {
    let mut app = App::new();
    app.add_plugins((MinimalPlugins, ManifoldPlugins::default()))
        .insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_secs_f64(1.0 / 60.0)))
        .init_resource::<Crossings>()
        .add_systems(Last, collect);
    app
}

/// Plays `text` in `space` at 60 frames a second to its end; returns the
/// faces crossed, the camera's cell and placement.
fn play(space: &Space, text: &str) -> (Vec<usize>, DomainCell, Placement) {
    let tour = TourDesc::parse(text, "t").unwrap().build(space, "t").unwrap();
    let frames = (tour.duration() * 60.0).ceil() as usize + 3;
    let mut app = app();
    let root = app.world_mut().spawn(ManifoldSpace::new(space.clone())).id();
    let camera = app.world_mut().spawn((ChildOf(root), TourPlayer::new(tour))).id();
    for _ in 0..frames {
        app.update();
    }
    let world = app.world();
    let player = world.get::<TourPlayer>(camera).unwrap();
    assert!(player.finished());
    let faces = world
        .resource::<Crossings>()
        .0
        .iter()
        .filter(|m| m.entity == camera)
        .map(|m| m.face)
        .collect();
    (
        faces,
        world.get::<DomainCell>(camera).unwrap().clone(),
        *world.get::<Placement>(camera).unwrap(),
    )
}

#[test]
fn a_tour_to_a_keyframe_three_cells_away_crosses_those_faces_and_arrives_there() {
    // Seifert-Weber: from the centre, straight through face 0 along its
    // axis (a loop leg: the closed geodesic), then on to a keyframe given
    // by the word [0, 0, 0] at the centre of that copy.
    let sw = catalog::seifert_weber();
    let n = sw.faces()[0].plane.truncate().normalize();
    let text = format!(
        r#"{{"space": "seifert-weber", "keyframes": [
            {{"time": 0, "position": [0, 0, 0, 1], "look": [{}, {}, {}]}},
            {{"loop": {{"faces": [0], "laps": 2, "seconds": 3}}}},
            {{"time": 4.5, "cell": [0, 0, 0], "position": [0, 0, 0, 1], "look": [{}, {}, {}]}}]}}"#,
        n.x, n.y, n.z, n.x, n.y, n.z
    );
    let (faces, cell, placement) = play(&sw, &text);
    assert_eq!(faces, vec![0, 0, 0], "one crossing of face 0 per copy");
    let direct = sw.cell_of_word(&[0, 0, 0]);
    assert_eq!(cell.id, sw.cell_id_of(&direct), "the copy a direct placement names");
    assert_eq!(cell.cell, direct, "exactly the same element");
    // The keyframe's pose (its look is as given; the loops' twists are
    // absorbed by the spline into the arrival).
    let tour = TourDesc::parse(&text, "t").unwrap().build(&sw, "t").unwrap();
    let want = tour.path.keys().last().unwrap().local;
    assert!(max_abs(placement.isometry - want) < 1e-9, "{:?}", placement.isometry);
    assert!(isometry::isometry_error(sw.geometry(), placement.isometry) < 1e-12);
}

#[test]
fn a_torus_flight_crosses_one_face_per_period_and_seeking_crosses_none() {
    let torus = catalog::torus(1.0);
    let text = r#"{"space": "torus", "keyframes": [
        {"time": 0, "position": [0, 0, 0, 1], "look": [1, 0, 0]},
        {"fly": {"seconds": 2, "speed": 1.2}}]}"#;
    let (faces, cell, placement) = play(&torus, text);
    // 2.4 units along +x from the centre: through the faces at x = 0.5
    // and 1.5, face 0 twice, to x = 0.4 in the third copy.
    assert_eq!(faces, vec![0, 0]);
    assert!((placement.isometry.w_axis.x - 0.4).abs() < 1e-9);
    let x = placement.isometry.w_axis.x + cell.element.w_axis.x;
    assert!((x - 2.4).abs() < 1e-9, "at {x} in the cover");

    // A seek places the entity directly: no faces on the way.
    let tour = TourDesc::parse(text, "t").unwrap().build(&torus, "t").unwrap();
    let mut app = app();
    let root = app.world_mut().spawn(ManifoldSpace::new(torus.clone())).id();
    let mut player = TourPlayer::new(tour);
    player.playing = false;
    let camera = app.world_mut().spawn((ChildOf(root), player)).id();
    app.update();
    app.world_mut().get_mut::<TourPlayer>(camera).unwrap().seek(1.6);
    app.update();
    app.update();
    assert!(
        app.world().resource::<Crossings>().0.is_empty(),
        "a seek crosses nothing"
    );
    let cell = app.world().get::<DomainCell>(camera).unwrap();
    let p = app.world().get::<Placement>(camera).unwrap();
    let x = p.isometry.w_axis.x + cell.element.w_axis.x;
    assert!((x - 1.92).abs() < 1e-9, "at {x}");
}
