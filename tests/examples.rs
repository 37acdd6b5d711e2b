//! The examples, run as a user runs them with `--screenshot`: each renders
//! its paper figure headlessly on the GPU (lavapipe in CI) with wgpu
//! validation on, exits 0, and the pictures are neither blank nor the same
//! as one another. The README's pictures in `docs/images/` are these at
//! 640x360 (`docs/images/render.sh`); this regenerates them small.

use std::path::PathBuf;
use std::process::Command;

/// Each example and the arguments that make one of the paper's figures.
const FIGURES: &[(&str, &[&str], &str)] = &[
    ("torus", &[], "torus"),
    ("torus", &["--fog"], "torus_fog"),
    ("seifert_weber", &[], "seifert_weber"),
    ("poincare", &[], "poincare"),
    ("mirrored_cube", &[], "mirrored_cube"),
    ("mirrored_dodecahedron", &[], "mirrored_dodecahedron"),
    (
        "mirrored_dodecahedron",
        &["--no-edges"],
        "mirrored_dodecahedron_no_edges",
    ),
];

/// The example binaries cargo built next to this test's (`cargo test`
/// builds the examples); built here when they are not there.
fn example(name: &str) -> PathBuf {
    let exe = std::env::current_exe().expect("test binary");
    let profile_dir = exe.parent().and_then(|d| d.parent()).expect("target/<profile>");
    let path = profile_dir.join("examples").join(name);
    if !path.exists() {
        let release = profile_dir.ends_with("release");
        let mut cargo = Command::new(env!("CARGO"));
        cargo.args(["build", "-p", "bevy_manifold", "--examples"]);
        if release {
            cargo.arg("--release");
        }
        assert!(cargo.status().expect("cargo runs").success(), "cargo build --examples");
    }
    path
}

fn every_example_renders_its_figure_headlessly() {
    let dir = std::env::temp_dir().join(format!("bevy_manifold_examples_{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let (w, h) = (160u32, 90u32);
    let mut shots: Vec<(&str, Vec<u8>)> = Vec::new();
    for (name, args, figure) in FIGURES {
        let out = dir.join(format!("{figure}.png"));
        let run = Command::new(example(name))
            .args(*args)
            .arg("--screenshot")
            .arg(&out)
            .args(["--size", &format!("{w}x{h}")])
            .env("WGPU_VALIDATION", "1")
            .env_remove("DISPLAY")
            .env_remove("WAYLAND_DISPLAY")
            .output()
            .expect("the example runs");
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert!(run.status.success(), "{figure}: exit {:?}\n{stderr}", run.status);
        assert!(
            !stderr.contains("Validation Error") && !stderr.contains("RenderError"),
            "{figure}: wgpu reported an error\n{stderr}"
        );
        let png = image::open(&out).expect("a PNG").to_rgb8();
        assert_eq!(png.dimensions(), (w, h), "{figure}");
        let bytes = png.into_raw();
        // Not blank: the figure has structure, not one colour.
        let mean = bytes.iter().map(|&b| f64::from(b)).sum::<f64>() / bytes.len() as f64;
        let spread = (bytes.iter().map(|&b| (f64::from(b) - mean).powi(2)).sum::<f64>() / bytes.len() as f64).sqrt();
        eprintln!("{figure}: mean {mean:.1}, spread {spread:.1}");
        assert!(spread > 10.0, "{figure} is nearly blank (spread {spread:.1})");
        shots.push((figure, bytes));
    }
    // No two figures alike: each differs from every other in many pixels.
    for (i, (a, pa)) in shots.iter().enumerate() {
        for (b, pb) in &shots[i + 1..] {
            let differ = pa
                .chunks_exact(3)
                .zip(pb.chunks_exact(3))
                .filter(|(x, y)| x.iter().zip(y.iter()).any(|(p, q)| p.abs_diff(*q) > 8))
                .count();
            assert!(
                differ > (w * h / 20) as usize,
                "{a} and {b} differ in only {differ} pixels"
            );
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

bevy_manifold_test_support::test_main! {
    cpu: [],
    gpu: [
        every_example_renders_its_figure_headlessly,
    ],
}
