//! HDR into Bevy: with `Hdr` on a manifold camera the pass writes linear
//! radiance into Bevy's HDR target, so Bevy's tonemapping, bloom and
//! exposure work on it; without it the output is the display colour.

use super::support::*;
use bevy::camera::Hdr;
use bevy::prelude::*;
use bevy_manifold::prelude::*;
use bevy_manifold::render::offscreen;

pub fn an_hdr_camera_gets_linear_radiance_above_one() {
    let space = catalog::torus(1.0);
    let mut scene = Scene::default_for(&space);
    // The ball in the middle of the view, white, glowing at three times
    // its albedo: it shows at least 3 (ambient and the light only add).
    scene.balls[0].color = [1.0; 3];
    scene.balls[0].glow = 3.0;
    let mut app = headless_app(true);
    let image = hdr_target(&mut app);
    let camera = (ManifoldCamera { levels: 8, ..default() }, CellShading::Off, Hdr);
    offscreen::spawn_view(&mut app, &space, &scene, &image, camera);
    wait_for_pipelines(&mut app);
    let bytes = capture(&mut app, &image);
    let at = |x: u32, y: u32| hdr_pixel(&bytes, (y * W + x) as usize);
    // The CPU reference of the same view, unclamped.
    let settings = TraceSettings {
        width: W,
        height: H,
        levels: 8,
        ..TraceSettings::default()
    };
    let reference = render::<f64>(&space, &scene, &settings);
    let (cx, cy) = (W / 2, H / 2);
    let want = reference.pixels[(cy * W + cx) as usize].color;
    let got = at(cx, cy);
    assert!(want.iter().all(|&c| c > 3.0), "the reference's centre: {want:?}");
    for c in 0..3 {
        assert!(
            (got[c] - want[c]).abs() <= 0.01 * want[c],
            "HDR centre {got:?} against the CPU reference's {want:?}"
        );
    }
    // Radiance above 1 wherever the glowing ball is, as the reference says.
    let mut above = 0;
    for (i, p) in reference.pixels.iter().enumerate() {
        let (x, y) = (i as u32 % W, i as u32 / W);
        if p.color.iter().all(|&c| c > 1.5) {
            above += 1;
            assert!(
                at(x, y).iter().all(|&c| c > 1.0),
                "pixel ({x}, {y}): {:?} against {:?}",
                at(x, y),
                p.color
            );
        }
    }
    assert!(above > 50, "{above} pixels of the glowing ball");
    // Without Hdr the same view into an sRGB image shows display colours:
    // the ball clamped to white.
    let mut app = headless_app(true);
    let srgb = target(&mut app, W, H);
    offscreen::spawn_view(
        &mut app,
        &space,
        &scene,
        &srgb,
        (ManifoldCamera { levels: 8, ..default() }, CellShading::Off),
    );
    wait_for_pipelines(&mut app);
    let shown = capture(&mut app, &srgb);
    let k = ((cy * W + cx) * 4) as usize;
    assert_eq!(&shown[k..k + 3], &[255, 255, 255]);
}
