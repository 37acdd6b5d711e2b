//! Tours: the screw logarithm, the spline through the keyframes (through
//! every keyframe, in the group, velocity continuous), legs checked
//! against the geometry, and tour files' errors named by entry and field.

use bevy_manifold_core::geometry::{Geometry, isometry};
use bevy_manifold_core::space::{Space, catalog};
use bevy_manifold_core::tour::{PathKey, Segment, TourDesc, TourError, TourPath};
use bevy_manifold_test_support::Rng;
use glam::{DMat4, DVec3, DVec4};

const ALL: [Geometry; 3] = [Geometry::Euclidean, Geometry::Hyperbolic, Geometry::Spherical];

fn max_abs(m: DMat4) -> f64 {
    m.to_cols_array().iter().fold(0.0f64, |a, x| a.max(x.abs()))
}

#[test]
fn the_screw_of_a_screw_motion_is_its_axis_length_and_angle() {
    // Built from translation and rotation, read back by the logarithm.
    let mut rng = Rng(3);
    for g in ALL {
        for _ in 0..200 {
            let axis = rng.unit();
            let d = rng.next_f64() * 2.5;
            let a = (rng.next_f64() * 2.0 - 1.0) * 3.0;
            let m = isometry::screw(g, axis, d, a);
            let (v, w) = isometry::log_twist(g, m).expect("a screw has a logarithm");
            assert!((v - axis * d).length() < 1e-10, "{g}: v {v} for {}", axis * d);
            assert!((w - axis * a).length() < 1e-10, "{g}: w {w} for {}", axis * a);
        }
    }
}

#[test]
fn exp_of_log_is_the_motion_for_random_isometries() {
    let mut rng = Rng(5);
    for g in ALL {
        for _ in 0..300 {
            let m = rng.isometry(g, 2.0);
            let Some((v, w)) = isometry::log_twist(g, m) else {
                // Only a half turn has no unique screw; rare at random.
                continue;
            };
            assert!(max_abs(isometry::exp_twist(g, v, w) - m) < 1e-11, "{g}");
        }
    }
}

#[test]
fn a_half_turn_and_a_reflection_have_no_screw() {
    for g in ALL {
        let half = isometry::rotation(DVec3::Y, std::f64::consts::PI);
        assert_eq!(isometry::log_twist(g, half), None, "{g}");
        let mirror = isometry::reflection(g, DVec4::new(1.0, 0.0, 0.0, -0.2));
        assert_eq!(isometry::log_twist(g, mirror), None, "{g}");
    }
    assert_eq!(isometry::log_twist(Geometry::Hyperbolic, DMat4::NAN), None);
}

/// Keyframes that wander through several copies, turning as they go.
fn wandering_keys(space: &Space, rng: &mut Rng) -> Vec<PathKey> {
    let g = space.geometry();
    let r = space.inradius();
    let faces = space.faces().len();
    let mut word = Vec::new();
    let mut keys = Vec::new();
    let mut time = 0.0;
    for k in 0..7 {
        if k > 0 {
            word.push(rng.below(faces));
        }
        let p = isometry::translation(g, rng.unit() * r * 0.5 * rng.next_f64());
        let turn = isometry::rotation(rng.unit(), rng.next_f64() * 1.5);
        time += 0.5 + rng.next_f64() * 2.0;
        keys.push(PathKey {
            time,
            word: word.clone(),
            local: p * turn,
            stop: k == 3,
        });
    }
    keys
}

fn spaces() -> Vec<Space> {
    catalog::NAMES.iter().map(|n| catalog::by_name(n).unwrap()).collect()
}

#[test]
fn the_path_passes_through_every_keyframe_and_stays_in_the_group() {
    let mut rng = Rng(17);
    for space in spaces() {
        let g = space.geometry();
        let keys = wandering_keys(&space, &mut rng);
        let path = TourPath::new(&space, keys.clone(), vec![Segment::Smooth; keys.len() - 1]).unwrap();
        let mut off_key = 0.0f64;
        for key in path.keys() {
            let at = path.frame(&space, key.time);
            // The same copy (by id, from the two words) and the same pose.
            let want = space.cell_id_of(&space.cell_of_word(&key.word));
            assert_eq!(
                space.cell_id_of(&space.cell_of_word(&at.word)),
                want,
                "{}",
                space.name()
            );
            let err = max_abs(at.placement - key.local);
            assert!(err < 1e-9, "{}: {err:.2e} off keyframe at {}", space.name(), key.time);
            off_key = off_key.max(err);
        }
        let (t0, t1) = path.span();
        let mut worst = 0.0f64;
        for k in 0..=400 {
            let t = t0 + (t1 - t0) * f64::from(k) / 400.0;
            let (_, pose) = path.local_pose(t);
            worst = worst.max(isometry::isometry_error(g, pose));
            let at = path.frame(&space, t);
            assert!(
                space.outside_face(at.placement.w_axis, 1e-9).is_none(),
                "{}",
                space.name()
            );
        }
        eprintln!(
            "{}: {} keyframes, worst {off_key:.2e} off a keyframe, form error {worst:.2e} along the path",
            space.name(),
            path.keys().len()
        );
        assert!(worst < 1e-12, "{}: form error {worst:.2e}", space.name());
    }
}

/// The largest jump of the body velocity at the interior keyframes,
/// from one-sided differences over `eps`, relative to the speed there.
fn velocity_jump(space: &Space, path: &TourPath, eps: f64) -> f64 {
    let g = space.geometry();
    let keys = path.keys();
    let mut worst = 0.0f64;
    for key in &keys[1..keys.len() - 1] {
        let t = key.time;
        let before = isometry::log_twist(g, path.relative(t - eps, t)).unwrap();
        let after = isometry::log_twist(g, path.relative(t, t + eps)).unwrap();
        let jump = ((before.0 - after.0).length() + (before.1 - after.1).length()) / eps;
        let speed = (after.0.length() + after.1.length()) / eps;
        if !key.stop {
            worst = worst.max(jump / speed.max(1e-3));
        } else {
            // At a stop the velocity is zero from both sides.
            worst = worst.max(speed);
        }
    }
    worst
}

#[test]
fn the_velocity_is_continuous_at_keyframes_and_a_piecewise_screw_path_is_not() {
    let mut rng = Rng(23);
    for space in spaces() {
        let keys = wandering_keys(&space, &mut rng);
        let n = keys.len() - 1;
        let smooth = TourPath::new(&space, keys.clone(), vec![Segment::Smooth; n]).unwrap();
        // One-sided differences differ by the acceleration jump times eps:
        // the jump shrinks tenfold with eps, to nothing.
        let (coarse, fine) = (
            velocity_jump(&space, &smooth, 1e-4),
            velocity_jump(&space, &smooth, 1e-5),
        );
        eprintln!(
            "{}: velocity jump at keyframes {coarse:.2e} (differences over 1e-4 s), {fine:.2e} (over 1e-5 s)",
            space.name()
        );
        assert!(
            fine < 1e-3,
            "{}: velocity jumps by {fine:.2e} of the speed",
            space.name()
        );
        assert!(
            fine < coarse * 0.3 || fine < 1e-6,
            "{}: {coarse:.2e} then {fine:.2e}",
            space.name()
        );
        // The same keyframes joined by plain screws turn corners.
        let mut corners = keys.clone();
        for k in &mut corners {
            k.stop = false;
        }
        let screws = TourPath::new(&space, corners, vec![Segment::Screw; n]).unwrap();
        let jump = velocity_jump(&space, &screws, 1e-5);
        assert!(
            jump > 0.05,
            "{}: the control case shows no corner ({jump:.2e})",
            space.name()
        );
    }
}

fn build(space: &Space, text: &str) -> Result<bevy_manifold_core::tour::Tour, TourError> {
    TourDesc::parse(text, "t.tour.json")?.build(space, "t.tour.json")
}

#[test]
fn a_loop_through_a_face_of_seifert_weber_flies_two_inradii_and_turns_three_fifths_of_pi() {
    let sw = catalog::seifert_weber();
    let g = sw.geometry();
    // Face 0's centre: the camera at the domain's centre looks at it.
    let n = sw.faces()[0].plane;
    let look = -n.truncate().normalize();
    let look = if n.truncate().dot(look) < 0.0 { -look } else { look };
    let text = format!(
        r#"{{"space": "seifert-weber", "keyframes": [
            {{"time": 0, "position": [0, 0, 0, 1], "look": [{}, {}, {}], "up": [0.3, 0.9, 0.1]}},
            {{"loop": {{"faces": [0], "seconds": 4}}}}]}}"#,
        look.x, look.y, look.z
    );
    let tour = build(&sw, &text).unwrap();
    let end = tour.frame(&sw, 4.0);
    assert_eq!(end.word, vec![0]);
    let start = tour.frame(&sw, 0.0);
    assert!(
        max_abs(end.placement - start.placement) < 1e-9,
        "the loop ends where it began"
    );
    let (v, w) = isometry::log_twist(g, tour.path.relative(0.0, 4.0)).unwrap();
    // 2r = 1.99277 (the Seifert-Weber dodecahedron's inradius is 0.996384)
    // and the gluing turns by 3 pi / 5 (108 degrees).
    assert!((v.length() - 1.99277).abs() < 1e-5, "length {}", v.length());
    assert!((v.length() - 2.0 * sw.inradius()).abs() < 1e-9);
    assert!(
        (w.length() - 0.6 * std::f64::consts::PI).abs() < 1e-9,
        "angle {}",
        w.length()
    );
    // Along the camera's view: a straight flight forward, no sideways drift.
    assert!(v.normalize().dot(DVec3::NEG_Z) > 1.0 - 1e-9, "{v}");
    // Halfway, the camera is on the face, a distance r from the centre.
    let mid = tour.path.local_pose(2.0).1;
    assert!((g.distance::<f64>(DVec4::W, mid.w_axis) - sw.inradius()).abs() < 1e-9);
}

#[test]
fn legs_fly_and_turn_as_the_geometry_says() {
    // In the torus, flying 2.4 units along -z from the centre crosses the
    // face -z twice and ends 0.4 short of the third copy's centre.
    let torus = catalog::torus(1.0);
    let tour = build(
        &torus,
        r#"{"space": "torus", "keyframes": [
            {"time": 0, "position": [0, 0, 0, 1]},
            {"fly": {"seconds": 2, "speed": 1.2}},
            {"turn": {"seconds": 1, "yaw_degrees": 90}},
            {"fly": {"seconds": 1, "speed": 1}}]}"#,
    )
    .unwrap();
    let after_fly = tour.frame(&torus, 2.0);
    let p = after_fly.placement.w_axis;
    assert!((p.truncate() - DVec3::new(0.0, 0.0, -0.4)).length() < 1e-9, "{p}");
    assert_eq!(after_fly.word.len(), 2, "two faces crossed: {:?}", after_fly.word);
    // Half way through the fly leg, constant speed: 1.2 units along.
    let half = tour.path.relative(0.0, 1.0);
    assert!(
        (half.w_axis.truncate() - DVec3::NEG_Z * 1.2).length() < 1e-9,
        "{}",
        half.w_axis
    );
    // The yaw of 90 degrees turns -z into -x; the last leg flies one
    // period along -x, through one more face, to the same point.
    let end = tour.frame(&torus, 4.0);
    assert!((end.placement.w_axis.truncate() - DVec3::new(0.0, 0.0, -0.4)).length() < 1e-9);
    assert_eq!(end.word.len(), 3, "{:?}", end.word);
    let forward = -end.placement.z_axis.truncate();
    assert!((forward - DVec3::NEG_X).length() < 1e-9, "{forward}");

    // In S3 a fly of 4 units (more than a half great circle) goes forward
    // all the way, cut into pieces: the distance from the start follows
    // the great circle, |sin|-like, back near zero at 2 pi.
    let poincare = catalog::poincare();
    let g = poincare.geometry();
    let tour = build(
        &poincare,
        r#"{"space": "poincare", "keyframes": [
            {"time": 0, "position": [0, 0, 0, 1]},
            {"fly": {"seconds": 6.283185307179586, "speed": 1}}]}"#,
    )
    .unwrap();
    for k in 1..10 {
        let t = std::f64::consts::TAU * f64::from(k) / 10.0;
        let m = tour.path.relative(0.0, t);
        let d = g.distance::<f64>(DVec4::W, m * DVec4::W);
        let want = t.min(std::f64::consts::TAU - t);
        assert!((d - want).abs() < 1e-9, "at {t}: {d} vs {want}");
    }
}

#[test]
fn settings_and_captions_hold_from_their_entry_until_changed() {
    let torus = catalog::torus(1.0);
    let tour = build(
        &torus,
        r#"{"space": "torus", "keyframes": [
            {"time": 0, "position": [0, 0, 0, 1], "caption": "one", "levels": 4},
            {"fly": {"seconds": 0.75, "speed": 0.5}},
            {"fly": {"seconds": 1.25, "speed": 0.5}, "caption": "two", "fog": {"density": 0.5}},
            {"time": 3, "position": [0.1, 0, 0, 1], "caption": "", "suzanne": "Hidden", "walls": {"density": 0.3, "seed": 4}}]}"#,
    )
    .unwrap();
    assert_eq!(tour.caption_at(0.5), Some("one"));
    assert_eq!(tour.settings_at(0.5).levels, 4);
    assert!(tour.settings_at(0.5).fog.is_none());
    assert_eq!(tour.caption_at(1.0), Some("two"), "a leg's caption starts with the leg");
    assert_eq!(tour.settings_at(1.0).fog.as_ref().map(|f| f.density), Some(0.5));
    assert_eq!(tour.settings_at(1.0).levels, 4, "levels hold");
    assert_eq!(tour.caption_at(3.5), None);
    assert!(tour.settings_at(3.0).rule.walls.is_some());
    assert_eq!(
        tour.settings_at(3.0).suzanne,
        bevy_manifold_core::trace::SuzanneMode::Hidden
    );
}

fn field_error(space: &Space, text: &str) -> (String, String) {
    match build(space, text) {
        Err(TourError::Field { path, field, message }) => {
            assert_eq!(path, "t.tour.json");
            (field, message)
        }
        other => panic!("expected a field error, got {other:?}"),
    }
}

#[test]
fn broken_tour_files_name_the_keyframe_and_field() {
    let sw = catalog::seifert_weber();
    let head = r#"{"space": "seifert-weber", "keyframes": [{"time": 0, "position": [0, 0, 0, 1]}, "#;
    let cases: &[(&str, &str, &str)] = &[
        // A keyframe outside the domain.
        (
            r#"{"time": 1, "position": [2.06474160483506, 0, 0, 2.29415733870562]}]}"#,
            "keyframes[1].position",
            "outside",
        ),
        // Not on the hyperboloid.
        (
            r#"{"time": 1, "position": [0.5, 0, 0, 1]}]}"#,
            "keyframes[1].position",
            "normalised",
        ),
        // Times out of order.
        (
            r#"{"time": 2, "position": [0, 0, 0, 1]}, {"time": 1, "position": [0, 0, 0, 1]}]}"#,
            "keyframes[2].time",
            "increase",
        ),
        // A face the space does not have.
        (
            r#"{"time": 1, "position": [0, 0, 0, 1], "cell": [3, 12]}]}"#,
            "keyframes[1].cell[1]",
            "12",
        ),
        // An isometry that is not one.
        (
            r#"{"time": 1, "isometry": [[2,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}]}"#,
            "keyframes[1].isometry",
            "not an isometry",
        ),
        // Look and up together.
        (
            r#"{"time": 1, "position": [0, 0, 0, 1], "look": [0, 1, 0]}]}"#,
            "keyframes[1].up",
            "parallel",
        ),
        // A leg without time.
        (
            r#"{"fly": {"seconds": -1, "speed": 1}}]}"#,
            "keyframes[1].fly.seconds",
            "positive",
        ),
        // A half turn between keyframes.
        (
            r#"{"time": 1, "position": [0, 0, 0, 1], "look": [0, 0, 1]}]}"#,
            "keyframes[1]",
            "half turn",
        ),
        // Both kinds in one entry.
        (
            r#"{"time": 1, "position": [0, 0, 0, 1], "turn": {"seconds": 1}}]}"#,
            "keyframes[1]",
            "one keyframe",
        ),
        // A negative fog density.
        (
            r#"{"time": 1, "position": [0, 0, 0, 1], "fog": {"density": -2}}]}"#,
            "keyframes[1].fog.density",
            ">= 0",
        ),
    ];
    for (tail, want_field, want_message) in cases {
        let (field, message) = field_error(&sw, &format!("{head}{tail}"));
        assert_eq!(&field, want_field, "{tail}: {message}");
        assert!(message.contains(want_message), "{tail}: {message}");
    }
    // A missing field and a NaN (not JSON): the file is named.
    for text in [
        r#"{"keyframes": []}"#,
        r#"{"space": "torus", "keyframes": [{"time": NaN}]}"#,
    ] {
        let e = TourDesc::parse(text, "t.tour.json").unwrap_err();
        assert!(
            matches!(e, TourError::Json { .. }) && e.to_string().starts_with("t.tour.json: "),
            "{e}"
        );
    }
    // Huge and infinite numbers.
    let (field, _) = field_error(
        &sw,
        &format!("{head}{}", r#"{"time": 1e300, "position": [0, 0, 0, 1]}]}"#),
    );
    assert_eq!(field, "keyframes[1].time");
    // An odd number of mirrors in a loop.
    let cube = catalog::by_name("mirrored-cube").unwrap();
    let (field, message) = field_error(
        &cube,
        r#"{"space": "mirrored-cube", "keyframes": [{"time": 0, "position": [0, 0, 0, 1]}, {"loop": {"faces": [1], "seconds": 2}}]}"#,
    );
    assert_eq!(field, "keyframes[1].loop.faces", "{message}");
    // An unknown space is named as the space field.
    let desc = TourDesc::parse(r#"{"space": "no-such-space", "keyframes": []}"#, "t").unwrap();
    let e = desc
        .resolve_space(Some(std::path::Path::new("dir/t.tour.json")))
        .unwrap_err();
    assert!(e.to_string().starts_with("dir/t.tour.json: space: "), "{e}");
}

#[test]
fn a_saved_tour_reads_back_the_same() {
    let sw = catalog::seifert_weber();
    let mut desc = TourDesc::parse(
        r#"{"space": "seifert-weber", "keyframes": [{"time": 0, "position": [0, 0, 0, 1], "caption": "hi"}]}"#,
        "t",
    )
    .unwrap();
    let pose = isometry::translation(sw.geometry(), DVec3::new(0.1, 0.2, -0.3)) * isometry::rotation(DVec3::Y, 0.4);
    desc.keyframes.push(TourDesc::keyframe(2.5, vec![3, 7], pose));
    let back = TourDesc::parse(&desc.to_json(), "t").unwrap();
    assert_eq!(back, desc);
    let tour = back.build(&sw, "t").unwrap();
    let at = tour.frame(&sw, 2.5);
    assert_eq!(
        sw.cell_id_of(&sw.cell_of_word(&at.word)),
        sw.cell_id_of(&sw.cell_of_word(&[3, 7]))
    );
    assert!(max_abs(at.placement - pose) < 1e-9);
}

#[test]
fn the_faces_a_tour_names_are_bounded_in_all_and_so_is_its_file() {
    // Four keyframes of 4,096 faces each are the most the cells may name
    // in all; a fifth is refused by name before any product of its word
    // is taken (each face word is a product of exact elements).
    let sw = catalog::seifert_weber();
    let mut rng = Rng(5);
    let keyframe = |i: usize, rng: &mut Rng| {
        let word: Vec<String> = (0..4096).map(|_| (rng.below(12)).to_string()).collect();
        format!(
            r#"{{"time": {i}, "position": [0, 0, 0, 1], "cell": [{}]}}"#,
            word.join(",")
        )
    };
    let tour = |n: usize, rng: &mut Rng| {
        let keys: Vec<String> = (0..n).map(|i| keyframe(i, rng)).collect();
        format!(r#"{{"space": "seifert-weber", "keyframes": [{}]}}"#, keys.join(","))
    };
    let Err(TourError::Field { field, message, .. }) = build(&sw, &tour(5, &mut rng)) else {
        panic!("5 keyframes of 4096 faces are refused");
    };
    assert_eq!(field, "keyframes[4].cell");
    assert!(message.contains("20480 faces in all, more than 16384"), "{message}");
    // A file past the cap is refused unread, by its size.
    let dir = std::env::temp_dir().join(format!("bevy_manifold_tour_cap_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let big = dir.join("big.tour.json");
    let file = std::fs::File::create(&big).unwrap();
    file.set_len(bevy_manifold_core::tour::MAX_TOUR_BYTES + 1).unwrap();
    let e = TourDesc::load(&big).unwrap_err().to_string();
    assert!(
        e.contains("big.tour.json") && e.contains("33554433 bytes, more than the 33554432"),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).ok();
}
