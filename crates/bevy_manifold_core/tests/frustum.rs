//! Off-centre frustums (a headset's eyes): every pixel's ray lands where
//! an independent projection matrix (OpenGL's `glFrustum`) puts it, in
//! every geometry and from a camera anywhere; a symmetric frustum is the
//! perspective; scene files carry it and refuse broken ones.

use bevy_manifold_core::geometry::isometry;
use bevy_manifold_core::prelude::*;
use bevy_manifold_core::trace::{FlatScene, Frustum, camera_ray};
use glam::{DMat4, DVec3, DVec4};

/// `glFrustum(l, r, b, t, n, f)` with `n = 1` (the edges at slopes
/// `l..r`, `b..t`), as the OpenGL reference pages write it.
fn gl_frustum(f: &Frustum) -> DMat4 {
    let (l, r, b, t, n, far) = (f.left, f.right, f.down, f.up, 1.0, 100.0);
    DMat4::from_cols(
        DVec4::new(2.0 * n / (r - l), 0.0, 0.0, 0.0),
        DVec4::new(0.0, 2.0 * n / (t - b), 0.0, 0.0),
        DVec4::new((r + l) / (r - l), (t + b) / (t - b), -(far + n) / (far - n), -1.0),
        DVec4::new(0.0, 0.0, -2.0 * far * n / (far - n), 0.0),
    )
}

#[test]
fn every_pixel_of_an_off_centre_frustum_lands_where_its_projection_puts_it() {
    // Monado's simulated headset and a Vive-like left eye: wider outward.
    let frustums = [
        Frustum::from_angles(-0.87, 0.70, -0.84, 0.77),
        Frustum::from_angles(-0.96, 0.76, -0.96, 0.84),
    ];
    let (w, h) = (37u32, 23u32);
    for name in ["torus", "seifert-weber", "poincare"] {
        let space = catalog::by_name(name).expect("catalog");
        let g = space.geometry();
        // A camera off the origin and turned: the frustum is in its frame.
        let camera = isometry::translation(g, DVec3::new(0.1, -0.05, 0.08)) * DMat4::from_rotation_y(0.4);
        for f in frustums {
            let mut scene = Scene::empty();
            scene.camera.isometry = camera;
            scene.camera.frustum = Some(f);
            let flat = FlatScene::<f64>::new(&space, &scene);
            let p = gl_frustum(&f);
            let back = isometry::inverse(g, flat.camera);
            for j in 0..h {
                for i in 0..w {
                    let ray = camera_ray(&flat, i, j, w, h);
                    // The direction in the camera's own frame, at its eye.
                    let d = back * ray.dir;
                    let clip = p * DVec4::new(d.x, d.y, d.z, 1.0) - p * DVec4::W;
                    let ndc = (clip.x / clip.w, clip.y / clip.w);
                    let want = (
                        2.0 * (f64::from(i) + 0.5) / f64::from(w) - 1.0,
                        1.0 - 2.0 * (f64::from(j) + 0.5) / f64::from(h),
                    );
                    assert!(
                        (ndc.0 - want.0).abs() < 1e-9 && (ndc.1 - want.1).abs() < 1e-9,
                        "{name} {f:?} pixel ({i}, {j}): lands at {ndc:?}, not {want:?}"
                    );
                    assert!(
                        d.z < 0.0 && d.w.abs() < 1e-12,
                        "{name}: looks forward, tangent at the eye"
                    );
                }
            }
        }
    }
}

#[test]
fn a_symmetric_frustum_traces_the_perspective_of_its_fov() {
    let space = catalog::seifert_weber();
    let mut scene = Scene::default_for(&space);
    let settings = TraceSettings {
        width: 48,
        height: 32,
        levels: 4,
        ..TraceSettings::default()
    };
    let plain = render::<f64>(&space, &scene, &settings);
    let t = (scene.camera.fov_y_degrees.to_radians() / 2.0).tan();
    let a = 48.0 / 32.0;
    scene.camera.frustum = Some(Frustum {
        left: -t * a,
        right: t * a,
        down: -t,
        up: t,
    });
    let framed = render::<f64>(&space, &scene, &settings);
    for (k, (p, q)) in plain.pixels.iter().zip(&framed.pixels).enumerate() {
        assert_eq!((p.object, p.levels, p.cell), (q.object, q.levels, q.cell), "pixel {k}");
        assert!((p.distance - q.distance).abs() < 1e-5, "pixel {k}");
    }
}

#[test]
fn scene_files_carry_a_frustum_and_name_a_broken_one() {
    let space = catalog::torus(1.0);
    let mut scene = Scene::default_for(&space);
    scene.camera.frustum = Some(Frustum::from_angles(-0.9, 0.7, -0.8, 0.75));
    let parse = |t: &str| Scene::parse(t, "eye.json", &space);
    let back = parse(&scene.to_json()).expect("reads back");
    assert_eq!(back.camera.frustum, scene.camera.frustum);
    let mut v: serde_json::Value = serde_json::from_str(&scene.to_json()).expect("json");
    for bad in [
        serde_json::json!([0.5, -0.5, -1.0, 1.0]),
        serde_json::json!([-1.0, 1.0, 1.0, 1.0]),
        serde_json::json!([0.3, 0.3, -1.0, 1.0]),
    ] {
        v["camera"]["frustum"] = bad.clone();
        let e = parse(&v.to_string()).expect_err("refused").to_string();
        assert!(e.starts_with("eye.json: camera.frustum: "), "{bad}: {e}");
    }
    v["camera"]["frustum"] = serde_json::json!([-1.0, 1.0, -1.0]);
    let e = parse(&v.to_string()).expect_err("three slopes").to_string();
    assert!(e.contains("eye.json"), "{e}");
}
