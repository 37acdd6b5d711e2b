//! Panoramas: a pixel of the equirectangular and omni-directional stereo
//! projections sees what a perspective camera turned to look along the
//! same direction (from the same eye) sees in its centre.

use bevy_manifold_core::geometry::{Geometry, isometry};
use bevy_manifold_core::prelude::*;
use bevy_manifold_core::trace::{Projection, TracePixel};
use bevy_manifold_test_support::Rng;
use glam::{DMat4, DVec3, DVec4};

/// The direction of equirectangular pixel `(i, row)` of `w` x `rows`,
/// written from the definition (longitude 0 is -z, +x at three quarters).
fn direction(i: u32, row: u32, w: u32, rows: u32) -> DVec3 {
    let lon = std::f64::consts::TAU * ((f64::from(i) + 0.5) / f64::from(w) - 0.5);
    let lat = std::f64::consts::PI * (0.5 - (f64::from(row) + 0.5) / f64::from(rows));
    DVec3::new(lon.sin() * lat.cos(), lat.sin(), -lon.cos() * lat.cos())
}

/// A rotation carrying -z to `d`.
fn facing(d: DVec3) -> DMat4 {
    let up = if d.y.abs() > 0.9 { DVec3::X } else { DVec3::Y };
    let r = d.cross(up).normalize();
    let u = r.cross(d);
    DMat4::from_cols(r.extend(0.0), u.extend(0.0), (-d).extend(0.0), DVec4::W)
}

/// The centre pixel of a 1x1 perspective view from `camera`: its ray is
/// exactly the camera's -z.
fn centre(space: &Space, scene: &Scene, camera: DMat4, levels: u32) -> TracePixel {
    let mut scene = scene.clone();
    scene.camera.isometry = camera;
    let settings = TraceSettings {
        width: 1,
        height: 1,
        levels,
        ..TraceSettings::default()
    };
    render::<f64>(space, &scene, &settings).pixels[0]
}

fn same(a: &TracePixel, b: &TracePixel) -> bool {
    a.object == b.object
        && a.cell == b.cell
        && a.levels == b.levels
        && a.color.iter().zip(b.color).all(|(x, y)| (x - y).abs() < 1e-5)
}

fn check(space: &Space, projection: Projection, seed: u64) {
    let g: Geometry = space.geometry();
    let scene = Scene::default_for(space);
    let (w, h) = (48, 24);
    let levels = 4;
    let settings = TraceSettings {
        width: w,
        height: h,
        levels,
        projection,
        ..TraceSettings::default()
    };
    let pano = render::<f64>(space, &scene, &settings);
    let mut rng = Rng(seed);
    let (mut agree, mut hits) = (0, 0);
    let n = 120;
    for _ in 0..n {
        let (i, j) = (rng.below(w as usize) as u32, rng.below(h as usize) as u32);
        let (rows, row, side, s) = match projection {
            Projection::Ods { eye_separation } if j < h / 2 => (h / 2, j, -1.0, eye_separation / 2.0),
            Projection::Ods { eye_separation } => (h - h / 2, j - h / 2, 1.0, eye_separation / 2.0),
            _ => (h, j, 0.0, 0.0),
        };
        let d = direction(i, row, w, rows);
        // The eye sits off the camera along the geodesic to its right at
        // that longitude (perpendicular to d's horizontal part).
        let right = DVec3::new(d.x, 0.0, d.z).normalize().cross(DVec3::Y);
        let eye = isometry::translation(g, right * (side * s as f32 as f64));
        let want = centre(space, &scene, scene.camera.isometry * eye * facing(d), levels);
        let got = pano.at(i, j);
        agree += usize::from(same(got, &want));
        hits += usize::from(want.object != 0);
    }
    // Rounding may tip a ray grazing an edge; no more than that.
    assert!(agree >= n - 2, "{}: {agree} of {n} pixels agree", space.name());
    assert!(hits > n / 4, "{}: only {hits} rays hit something", space.name());
}

#[test]
fn an_equirect_pixel_sees_what_a_camera_turned_that_way_sees() {
    for (k, name) in catalog::NAMES.iter().enumerate() {
        check(&catalog::by_name(name).unwrap(), Projection::Equirect, 40 + k as u64);
    }
}

#[test]
fn an_ods_pixel_sees_what_that_eye_looking_that_way_sees() {
    for (k, name) in ["torus", "seifert-weber", "poincare"].iter().enumerate() {
        let space = catalog::by_name(name).unwrap();
        let s = space.inradius() * 0.3;
        check(&space, Projection::Ods { eye_separation: s }, 50 + k as u64);
    }
}

#[test]
fn the_two_eyes_of_an_ods_panorama_differ_and_a_zero_separation_does_not() {
    let space = catalog::seifert_weber();
    let scene = Scene::default_for(&space);
    let render_with = |projection| {
        let settings = TraceSettings {
            width: 48,
            height: 48,
            levels: 3,
            projection,
            ..TraceSettings::default()
        };
        render::<f64>(&space, &scene, &settings)
    };
    let halves = |img: &bevy_manifold_core::trace::TraceImage| {
        let half = img.pixels.len() / 2;
        img.pixels[..half]
            .iter()
            .zip(&img.pixels[half..])
            .filter(|(a, b)| a.object != b.object)
            .count()
    };
    let flat = render_with(Projection::Ods { eye_separation: 0.0 });
    assert_eq!(halves(&flat), 0, "one eye position: both halves alike");
    let stereo = render_with(Projection::Ods { eye_separation: 0.3 });
    assert!(halves(&stereo) > 20, "parallax: {}", halves(&stereo));
}
