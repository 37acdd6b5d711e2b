//! The `audio` and `gamepad` features (built and run by CI after it
//! installs ALSA's and udev's development packages): sounds heard from the
//! directions of their nearest images with the geometry's fall-off, and
//! a gamepad flying the fly camera. Expected values are closed forms: the
//! torus's images through its faces, `sinh` and `sin` of the distances.

use bevy::audio::{AudioPlayer, PlaybackSettings, Volume};
use bevy::prelude::*;
use bevy_manifold::audio::{
    EMITTER_DISTANCE, ManifoldAudioPlugin, ManifoldListener, ManifoldSound, heard_images, sound_gain, wav_source,
};
use bevy_manifold::prelude::*;
use glam::{DVec3, DVec4};

fn close(a: DVec3, b: DVec3) -> bool {
    (a - b).length() < 1e-9
}

/// The torus: a listener at x = -0.4 hears a source at x = 0.4 first from
/// its left, 0.2 away through the face x = -1/2, then from its right, 0.8
/// away across the cube; turned a quarter to the left, the first image is
/// straight ahead. Gains are `r / d`.
#[test]
fn a_sound_is_heard_from_its_nearest_images_through_the_faces() {
    let torus = catalog::torus(1.0);
    let listener = Placement::at(&torus, DVec3::X * -0.4);
    let source = DVec4::new(0.4, 0.0, 0.0, 1.0);
    let heard = heard_images(&torus, &listener, source, 2, 0.1);
    assert_eq!(heard.len(), 2);
    assert!(close(heard[0].direction, DVec3::NEG_X), "{:?}", heard[0]);
    assert!((heard[0].distance - 0.2).abs() < 1e-12);
    assert!((heard[0].gain - 0.5).abs() < 1e-12);
    assert!(close(heard[1].direction, DVec3::X), "{:?}", heard[1]);
    assert!((heard[1].gain - 0.125).abs() < 1e-12);
    // A quarter turn left (about +y): -x is now straight ahead.
    let turned = listener.rotated(glam::DMat4::from_rotation_y(core::f64::consts::FRAC_PI_2));
    let heard = heard_images(&torus, &turned, source, 1, 0.1);
    assert!(close(heard[0].direction, DVec3::NEG_Z), "{:?}", heard[0]);
}

/// In H3 and S3 the amplitude falls as `sinh r / sinh d` and
/// `sin r / sin d`: the area of the geodesic sphere, not `d^2`. Within the
/// reference distance a sound is at full volume.
#[test]
fn sounds_fall_off_with_the_area_of_the_geodesic_sphere() {
    let (r, d) = (0.1, 0.6);
    assert!((sound_gain(Geometry::Euclidean, d, r) - r / d).abs() < 1e-12);
    assert!((sound_gain(Geometry::Hyperbolic, d, r) - r.sinh() / d.sinh()).abs() < 1e-12);
    assert!((sound_gain(Geometry::Spherical, d, r) - r.sin() / d.sin()).abs() < 1e-12);
    assert_eq!(sound_gain(Geometry::Hyperbolic, 0.05, r), 1.0);
    // Past a quarter turn in S3 the sphere shrinks: louder again near the
    // antipode (2.8 is as loud as pi - 2.8).
    let far = sound_gain(Geometry::Spherical, 2.8, r);
    assert!((far - sound_gain(Geometry::Spherical, core::f64::consts::PI - 2.8, r)).abs() < 1e-12);
    assert!(far > sound_gain(Geometry::Spherical, 1.5, r));
    assert_eq!(sound_gain(Geometry::Euclidean, f64::NAN, r), 0.0);
    // Seifert-Weber, a source 0.6 up the y axis from the centre.
    let sw = catalog::seifert_weber();
    let source = Placement::at(&sw, DVec3::Y * d).position();
    let heard = heard_images(&sw, &Placement::default(), source, 1, r);
    assert!(close(heard[0].direction, DVec3::Y));
    assert!((heard[0].gain - r.sinh() / d.sinh()).abs() < 1e-9);
}

/// In an app: each heard image gets a Bevy emitter around the plugin's
/// listener, placed at its direction and started at its gain; moving the
/// listener moves the emitters; despawning the source silences them.
/// (No audio device is needed: Bevy plays nothing without one, and the
/// emitters are still kept.)
#[test]
fn emitters_follow_the_images_and_go_with_their_source() {
    let mut app = App::new();
    app.add_plugins((
        MinimalPlugins,
        bevy::asset::AssetPlugin::default(),
        bevy::audio::AudioPlugin::default(),
        ManifoldPlugins::default(),
        ManifoldAudioPlugin,
    ));
    let torus = catalog::torus(1.0);
    let tone: Vec<f32> = (0..4410).map(|i| (i as f32 * 0.05).sin() * 0.5).collect();
    let handle = app
        .world_mut()
        .resource_mut::<Assets<AudioSource>>()
        .add(wav_source(&tone, 44_100));
    let root = app.world_mut().spawn(ManifoldSpace::new(torus.clone())).id();
    let ear = app
        .world_mut()
        .spawn((ChildOf(root), ManifoldListener, Placement::at(&torus, DVec3::X * -0.4)))
        .id();
    let source = app
        .world_mut()
        .spawn((
            ChildOf(root),
            Placement::at(&torus, DVec3::X * 0.4),
            ManifoldSound {
                images: 2,
                ..ManifoldSound::looping(handle)
            },
        ))
        .id();
    app.update();
    let emitters = |app: &mut App| -> Vec<(Vec3, f32)> {
        let mut q = app.world_mut().query::<(&AudioPlayer, &Transform, &PlaybackSettings)>();
        let mut v: Vec<(Vec3, f32)> = q
            .iter(app.world())
            .map(|(_, t, s)| {
                let Volume::Linear(g) = s.volume else {
                    panic!("linear volume")
                };
                (t.translation, g)
            })
            .collect();
        v.sort_by(|a, b| b.1.total_cmp(&a.1));
        v
    };
    let got = emitters(&mut app);
    assert_eq!(got.len(), 2);
    assert!((got[0].0 - Vec3::NEG_X * EMITTER_DISTANCE).length() < 1e-6, "{got:?}");
    assert!((got[0].1 - 0.5).abs() < 1e-6);
    assert!((got[1].0 - Vec3::X * EMITTER_DISTANCE).length() < 1e-6);
    assert!((got[1].1 - 0.125).abs() < 1e-6);
    // The listener turns a quarter to the left: the near image ahead.
    let turned = app
        .world()
        .get::<Placement>(ear)
        .unwrap()
        .rotated(glam::DMat4::from_rotation_y(core::f64::consts::FRAC_PI_2));
    *app.world_mut().get_mut::<Placement>(ear).unwrap() = turned;
    app.update();
    let mut q = app.world_mut().query::<(&AudioPlayer, &Transform)>();
    let positions: Vec<Vec3> = q.iter(app.world()).map(|(_, t)| t.translation).collect();
    assert!(
        positions
            .iter()
            .any(|p| (*p - Vec3::NEG_Z * EMITTER_DISTANCE).length() < 1e-6),
        "{positions:?}"
    );
    app.world_mut().entity_mut(source).despawn();
    app.update();
    assert!(emitters(&mut app).is_empty());
    // A volume that is not a number is silence, not a NaN handed to Bevy.
    let handle = app
        .world_mut()
        .resource_mut::<Assets<AudioSource>>()
        .add(wav_source(&tone, 44_100));
    app.world_mut().spawn((
        ChildOf(root),
        Placement::at(&torus, DVec3::X * 0.4),
        ManifoldSound {
            volume: f32::NAN,
            ..ManifoldSound::looping(handle)
        },
    ));
    app.update();
    assert_eq!(emitters(&mut app).iter().map(|e| e.1).collect::<Vec<_>>(), vec![0.0]);
}

/// A gamepad flies the fly camera: the left stick pushed half way forward
/// is half speed ahead, the right stick full right is a full-rate yaw to
/// the right, the right trigger is up.
#[test]
fn a_gamepad_flies_the_fly_camera() {
    let mut app = App::new();
    app.add_plugins((MinimalPlugins, ManifoldPlugins::default(), FlyCameraPlugin));
    let torus = catalog::torus(1.0);
    let root = app.world_mut().spawn(ManifoldSpace::new(torus)).id();
    let fly = FlyCamera::default();
    let camera = app.world_mut().spawn((ChildOf(root), fly, Placement::default())).id();
    let mut pad = Gamepad::default();
    pad.analog_mut().set(GamepadAxis::LeftStickY, 0.5);
    pad.analog_mut().set(GamepadAxis::RightStickX, 1.0);
    pad.analog_mut().set(GamepadButton::RightTrigger2, 0.0);
    app.world_mut().spawn(pad);
    app.update();
    let v = *app.world().get::<GeodesicVelocity>(camera).unwrap();
    assert!(close(v.linear, DVec3::NEG_Z * 0.5 * fly.speed), "{v:?}");
    assert!(close(v.angular, DVec3::NEG_Y * fly.turn_rate), "{v:?}");
    // The right trigger all the way: up, with the half stick ahead.
    let mut pads = app.world_mut().query::<&mut Gamepad>();
    pads.single_mut(app.world_mut())
        .unwrap()
        .analog_mut()
        .set(GamepadButton::RightTrigger2, 1.0);
    app.update();
    let v = *app.world().get::<GeodesicVelocity>(camera).unwrap();
    let want = DVec3::new(0.0, 1.0, -0.5).normalize() * fly.speed;
    assert!(close(v.linear, want), "{v:?}");
}
