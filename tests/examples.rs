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
    ("torus", &["--mirror"], "torus_mirror"),
    ("seifert_weber", &[], "seifert_weber"),
    ("poincare", &[], "poincare"),
    ("mirrored_cube", &[], "mirrored_cube"),
    ("mirrored_dodecahedron", &[], "mirrored_dodecahedron"),
    (
        "mirrored_dodecahedron",
        &["--no-edges"],
        "mirrored_dodecahedron_no_edges",
    ),
    // A Bevy scene placed by its transforms alone.
    ("bevy_scene", &[], "bevy_scene"),
    // A game in progress (150 ticks of its demo script).
    ("shooter", &["--space", "torus"], "shooter_torus"),
    ("shooter", &["--space", "seifert-weber"], "shooter_seifert_weber"),
    // The billiards break, 0.7 s after the first stroke.
    ("billiards", &["--space", "torus"], "billiards_torus"),
    ("billiards", &["--space", "seifert-weber"], "billiards_seifert_weber"),
    // A level of 4,000 props, each with its own transform and material.
    ("instances", &[], "instances_torus"),
    // Animated glTF characters, each held at its phase of the sway.
    ("animated", &[], "animated_seifert_weber"),
    // The product geometries: a genus-2 surface times a circle, the
    // sphere times a circle, and the mirrored prism shaded by cell.
    ("product", &[], "product_example_genus2xs1"),
    ("product", &["--space", "s2xs1"], "product_example_s2xs1"),
    // Lit by two point lights, every image of each, with shadows.
    (
        "product",
        &["--space", "s2xs1", "--lights"],
        "product_example_s2xs1_lit",
    ),
    (
        "product",
        &["--space", "mirrored-prism", "--cells"],
        "product_example_mirrored_cells",
    ),
    // The tour through S2 x S1, held on its climb up the circle.
    (
        "product",
        &["--tour", "assets/tours/s2xs1.product-tour.json", "--at", "8"],
        "product_tour_s2xs1",
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

/// The shooter's bad arguments and scripts end in one line naming what
/// is wrong, exit 1, no panic; a script plays headless to its score.
fn the_shooter_refuses_bad_input_and_plays_a_script_headless() {
    let run = |args: &[&str]| {
        let out = Command::new(example("shooter"))
            .args(args)
            .env_remove("DISPLAY")
            .env_remove("WAYLAND_DISPLAY")
            .output()
            .expect("the shooter runs");
        (
            out.status.code(),
            String::from_utf8_lossy(&out.stdout).into_owned(),
            String::from_utf8_lossy(&out.stderr).into_owned(),
        )
    };
    // Unknown flags (a typo, another version's) and bad values are named,
    // and nothing is played.
    for (args, needle) in [
        (&["--server"][..], "unexpected argument '--server'"),
        (&["--join", "127.0.0.1:5000"][..], "unexpected argument '--join'"),
        (&["--levels", "0"][..], "invalid value '0' for '--levels <LEVELS>'"),
        (&["--seed", "x"][..], "invalid value 'x' for '--seed <SEED>'"),
        (&["--screenshot", "s.png", "--size", "0x10"][..], "--size: WIDTHxHEIGHT"),
    ] {
        let (code, out, err) = run(args);
        assert!(matches!(code, Some(1 | 2)), "{args:?}: {code:?} {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
        assert!(out.is_empty() && !err.contains("panicked"), "{args:?}: {out} {err}");
    }
    let (code, out, _) = run(&["--help"]);
    assert_eq!(code, Some(0));
    assert!(out.contains("--space") && out.contains("--headless"), "{out}");
    let (code, _, err) = run(&["--space", "klein-bottle"]);
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("error: --space: no catalog space \"klein-bottle\""),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
    let dir = std::env::temp_dir().join(format!("bevy_manifold_shooter_{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let bad = dir.join("bad.json");
    std::fs::write(&bad, r#"{"space": "torus", "seed": 1, "difficulty": "normal", "inputs": [{"at": 0, "turn": [0, 5, 0]}], "ticks": 10}"#).expect("writes");
    let (code, _, err) = run(&["--play", bad.to_str().unwrap(), "--headless"]);
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("bad.json: inputs[0].turn: each component in [-1, 1]"),
        "{err}"
    );
    // Fire straight ahead in the torus (period 1, inradius 0.5) for 2 s:
    // each shot (a ball of 0.03 of the inradius) comes back after one
    // period less its radius and the player's (0.12 of the inradius):
    // 1 - 0.015 - 0.06; 20 health a hit, and the fifth ends it.
    let good = dir.join("good.json");
    std::fs::write(
        &good,
        r#"{"space": "torus", "seed": 1, "difficulty": "easy", "inputs": [{"at": 0, "fire": true}], "ticks": 120}"#,
    )
    .expect("writes");
    let (code, out, err) = run(&["--play", good.to_str().unwrap(), "--headless"]);
    assert_eq!(code, Some(0), "{err}");
    let hits = out.matches("PlayerHit { own: true, distance: 0.92499999").count();
    assert_eq!(hits, 5, "{out}");
    assert!(out.contains("GameOver"), "{out}");
    assert!(out.contains("score 0 level 1 health 0 after"), "{out}");
    std::fs::remove_dir_all(&dir).ok();
}

/// The billiards' bad arguments end in one line naming what is wrong,
/// exit 1 or 2, no panic; `--help` lists the flags.
fn the_billiards_refuses_bad_input() {
    let run = |args: &[&str]| {
        let out = Command::new(example("billiards"))
            .args(args)
            .env_remove("DISPLAY")
            .env_remove("WAYLAND_DISPLAY")
            .output()
            .expect("the billiards runs");
        (
            out.status.code(),
            String::from_utf8_lossy(&out.stdout).into_owned(),
            String::from_utf8_lossy(&out.stderr).into_owned(),
        )
    };
    for (args, code_want, needle) in [
        (
            &["--space", "klein-bottle"][..],
            1,
            "error: --space: no catalog space \"klein-bottle\"",
        ),
        (&["--levels", "65"][..], 2, "invalid value '65' for '--levels <LEVELS>'"),
        (&["--size", "0x10"][..], 1, "--size: WIDTHxHEIGHT"),
        (
            &["--xr", "--world-scale", "0"][..],
            1,
            "--world-scale: a positive number",
        ),
        (&["--cue"][..], 2, "unexpected argument '--cue'"),
    ] {
        let (code, out, err) = run(args);
        assert_eq!(code, Some(code_want), "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
        assert!(out.is_empty() && !err.contains("panicked"), "{args:?}: {out} {err}");
    }
    let (code, out, _) = run(&["--help"]);
    assert_eq!(code, Some(0));
    assert!(
        out.contains("--space") && out.contains("--screenshot") && out.contains("--xr"),
        "{out}"
    );
}

/// Without a display the shooter says so in one line and renders its
/// opening view to `shooter.png` (as the explorer renders `explorer.png`)
/// instead of panicking in winit.
fn without_a_display_the_shooter_renders_shooter_png() {
    let dir = std::env::temp_dir().join(format!("bevy_manifold_shooter_nodisplay_{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let out = Command::new(example("shooter"))
        .args(["--size", "160x90"])
        .current_dir(&dir)
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("the shooter runs");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{err}");
    assert!(
        err.contains("no display (neither DISPLAY nor WAYLAND_DISPLAY is set)"),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
    let img = image::open(dir.join("shooter.png")).expect("shooter.png").to_rgba8();
    assert_eq!(img.dimensions(), (160, 90));
    let first = img.get_pixel(0, 0);
    assert!(img.pixels().any(|p| p != first), "not blank");
    std::fs::remove_dir_all(&dir).ok();
}

bevy_manifold_test_support::test_main! {
    cpu: [
        the_shooter_refuses_bad_input_and_plays_a_script_headless,
        the_billiards_refuses_bad_input,
    ],
    gpu: [
        every_example_renders_its_figure_headlessly,
        without_a_display_the_shooter_renders_shooter_png,
    ],
}
