//! The explorer: its settings file (kept between runs, a broken one
//! reported and replaced, never a crash), its headless fallback (no
//! display: `explorer.png` and exit 0), and switching spaces through the
//! code path the panel uses without leaking GPU buffers or pipelines;
//! tours played and recorded in it, and the vehicle it rides.

use bevy::prelude::*;
use bevy::render::renderer::RenderDevice;
use bevy_manifold::prelude::*;
use bevy_manifold::render::offscreen;
use bevy_manifold::tour::FaceWord;
use bevy_manifold::trace::SuzanneMode;
use bevy_manifold_app::explorer::settings::{self, ExplorerSettings};
use bevy_manifold_app::explorer::soak::GPU_COUNTERS;
use bevy_manifold_app::explorer::tour::ExplorerTour;
use bevy_manifold_app::explorer::{CellMode, ExplorerPlugin, ExplorerStatus, ExplorerView, ExplorerWorld};
use std::path::{Path, PathBuf};
use std::process::Command;

fn tmp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("bevy_manifold_explorer_{name}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

fn settings_round_trip_and_broken_files_are_replaced_not_lost() {
    let dir = tmp_dir("settings");
    let path = dir.join("explorer.json");
    // No file: the defaults, silently.
    let (s, warnings) = settings::load(&path);
    assert_eq!(s, ExplorerSettings::default());
    assert!(warnings.is_empty());
    // Everything the panel sets comes back.
    let mine = ExplorerSettings {
        space: "poincare".into(),
        levels: 12,
        max_distance: 30.0,
        fog: true,
        fog_density: 0.8,
        fog_color: [0.2, 0.3, 0.4],
        cells: true,
        cell_mode: CellMode::Pattern,
        pattern_on: 0.25,
        highlight: 7,
        hidden: true,
        hidden_on: 0.3,
        hidden_seed: 12,
        walls: true,
        wall_density: 0.6,
        wall_seed: 4,
        edges: false,
        suzanne: SuzanneMode::Free,
        hands: false,
        vehicle: true,
        mirror: true,
        reflections: 3,
        path_trace: true,
        path_depth: 12,
        path_samples: 64,
        render_scale: 0.5,
        hold_frame_rate: true,
        target_fps: 90.0,
        refine_still: false,
        still_samples: 64,
        smooth_detail: false,
        lights: false,
        panel: false,
    };
    mine.save(&path).expect("saved");
    assert_eq!(settings::load(&path), (mine.clone(), Vec::new()));
    // As a Windows editor saves it (a byte-order mark, CRLF): the same.
    let text = std::fs::read_to_string(&path).unwrap();
    std::fs::write(&path, format!("\u{feff}{}", text.replace('\n', "\r\n"))).unwrap();
    assert_eq!(settings::load(&path), (mine.clone(), Vec::new()));
    // A file cut short: reported, defaults used, the file kept aside.
    let text = std::fs::read_to_string(&path).unwrap();
    std::fs::write(&path, &text[..text.len() / 2]).unwrap();
    let (s, warnings) = settings::load(&path);
    assert_eq!(s, ExplorerSettings::default());
    assert_eq!(warnings.len(), 1);
    assert!(
        warnings[0].contains("is broken") && warnings[0].contains("explorer.json.broken"),
        "{warnings:?}"
    );
    assert_eq!(
        std::fs::read_to_string(dir.join("explorer.json.broken")).unwrap(),
        text[..text.len() / 2]
    );
    assert!(!path.exists());
    // Out-of-range values are clamped one by one, the rest kept; missing
    // fields take their defaults.
    std::fs::write(
        &path,
        r#"{"space": "nowhere", "levels": 1000, "fog_density": -1.0, "render_scale": 0.0, "pattern_on": 2.0, "edges": false, "target_fps": 1000, "still_samples": 0, "reflections": 99}"#,
    )
    .unwrap();
    let (s, warnings) = settings::load(&path);
    assert_eq!(warnings.len(), 8, "{warnings:?}");
    assert_eq!(s.target_fps, 144.0);
    assert_eq!(s.reflections, bevy_manifold::trace::MAX_REFLECTIONS);
    assert_eq!(s.still_samples, 2);
    assert_eq!(s.space, "torus");
    assert_eq!(s.levels, settings::MAX_LEVEL);
    assert_eq!(s.fog_density, ExplorerSettings::default().fog_density);
    assert_eq!(s.render_scale, settings::MIN_SCALE);
    assert_eq!(s.pattern_on, 0.5);
    assert!(!s.edges, "a good value next to bad ones is kept");
    // The camera follows the settings.
    let (camera, shading) = mine.camera();
    assert_eq!((camera.levels, camera.max_distance), (12, 30.0));
    assert_eq!(shading, CellShading::Pattern { on_fraction: 0.25 });
    assert_eq!(mine.fog().map(|f| f.density), Some(0.8));
    std::fs::remove_dir_all(&dir).ok();
}

fn without_a_display_the_explorer_renders_explorer_png_and_exits_0() {
    let dir = tmp_dir("fallback");
    let config = dir.join("config");
    let out = Command::new(env!("CARGO_BIN_EXE_bevy_manifold"))
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env("BEVY_MANIFOLD_CONFIG_DIR", &config)
        .current_dir(&dir)
        .output()
        .expect("the binary runs");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "exit {:?}\n{stdout}\n{stderr}", out.status);
    let lines: Vec<&str> = stdout.lines().collect();
    assert_eq!(lines.len(), 1, "one clear line: {stdout}");
    assert!(
        lines[0].starts_with("no display") && lines[0].contains("explorer.png") && lines[0].contains("torus"),
        "{stdout}"
    );
    let png = image::open(dir.join("explorer.png"))
        .expect("explorer.png is a PNG")
        .to_rgb8();
    let (w, h) = png.dimensions();
    assert!((w, h) == (1280, 720) || (w, h) == (640, 360), "{w}x{h}");
    // Not blank: the scene's edges and Suzanne's images give many colours.
    let mut colours: Vec<[u8; 3]> = png.pixels().map(|p| p.0).collect();
    colours.sort_unstable();
    colours.dedup();
    eprintln!("explorer.png: {w}x{h}, {} distinct colours; {stdout}", colours.len());
    assert!(colours.len() > 200, "{} colours", colours.len());
    std::fs::remove_dir_all(&dir).ok();
}

/// The explorer without a display in `dir`, with `args`, as in a shell
/// with no desktop login (no `XDG_RUNTIME_DIR` either).
fn explore_headless(dir: &std::path::Path, args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_bevy_manifold"))
        .arg("explore")
        .args(args)
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("XDG_RUNTIME_DIR")
        .env("BEVY_MANIFOLD_CONFIG_DIR", dir.join("config"))
        .current_dir(dir)
        .output()
        .expect("the binary runs")
}

/// `explore --space` opens a library space by name, a `.gen` file by
/// path and a product space by name (here in the headless fallback, which
/// says which space it drew),
/// and refuses a name that is no space and a broken file, naming them,
/// without drawing anything. Without a runtime directory it makes its
/// own, so the libraries do not complain of its absence.
fn explore_opens_the_space_it_is_given_and_names_a_bad_one() {
    let dir = tmp_dir("space");
    let run = |args: &[&str]| {
        std::fs::remove_file(dir.join("explorer.png")).ok();
        let out = explore_headless(&dir, args);
        let text = |b: &[u8]| String::from_utf8_lossy(b).into_owned();
        (
            out.status.success(),
            text(&out.stdout),
            text(&out.stderr),
            dir.join("explorer.png").exists(),
        )
    };
    let (ok, stdout, stderr, png) = run(&["--space", "weeks"]);
    assert!(ok && png, "{stdout}\n{stderr}");
    assert!(stdout.starts_with("no display") && stdout.contains("weeks"), "{stdout}");
    assert!(!stderr.contains("XDG_RUNTIME_DIR"), "{stderr}");
    let gen_file =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../bevy_manifold_core/assets/spaces/lens-7-2.gen");
    let gen_file = gen_file.canonicalize().expect("the library's lens-7-2.gen");
    let (ok, stdout, stderr, png) = run(&["--space", gen_file.to_str().expect("utf-8")]);
    assert!(ok && png, "{stdout}\n{stderr}");
    assert!(stdout.contains("view of lens-7-2 "), "{stdout}");
    // A product space by name, drawn by the product tracer.
    let (ok, stdout, stderr, png) = run(&["--space", "s2xs1"]);
    assert!(ok && png, "{stdout}\n{stderr}");
    assert!(stdout.contains("view of S2 x S1 "), "{stdout}");
    let (ok, stdout, stderr, png) = run(&["--space", "no-such-space"]);
    assert!(!ok && !png, "{stdout}\n{stderr}");
    assert!(
        stderr.contains("--space no-such-space") && stderr.contains("neither a catalog space"),
        "{stderr}"
    );
    let broken = dir.join("broken.gen");
    std::fs::write(&broken, "1 0 0 0\n0 1 0\n").expect("write");
    let (ok, stdout, stderr, png) = run(&["--space", broken.to_str().expect("utf-8")]);
    assert!(!ok && !png, "{stdout}\n{stderr}");
    assert!(stderr.contains("broken.gen") && stderr.contains("line 2"), "{stderr}");
    std::fs::remove_dir_all(&dir).ok();
}

/// Live GPU objects on the app's device (as the soak run counts them),
/// once the GPU has finished the frames submitted: the staging buffers of
/// a frame's buffer writes (a dozen or so, freed when its submission is
/// done) would otherwise be counted or not as the GPU's timing falls.
fn live(app: &App) -> [isize; GPU_COUNTERS.len()] {
    let device = app.world().resource::<RenderDevice>();
    let wait = bevy::render::render_resource::PollType::Wait {
        submission_index: None,
        timeout: Some(std::time::Duration::from_secs(10)),
    };
    device.poll(wait).expect("the GPU finishes the frames submitted");
    bevy_manifold_app::explorer::soak::live_gpu_objects(device)
}

/// Updates until the counts have not changed for 5 frames (freed objects
/// go once the GPU is done with them).
fn settle(app: &mut App) -> [isize; GPU_COUNTERS.len()] {
    let mut last = live(app);
    let mut same = 0;
    for _ in 0..200 {
        app.update();
        let now = live(app);
        same = if now == last { same + 1 } else { 0 };
        last = now;
        if same >= 5 {
            break;
        }
    }
    last
}

fn switching_spaces_100_times_leaks_no_buffers_or_pipelines() {
    let mut app = App::new();
    app.add_plugins(offscreen::plugins().disable::<bevy::log::LogPlugin>())
        .insert_resource(ExplorerSettings {
            levels: 2,
            ..ExplorerSettings::default()
        })
        .add_plugins(ExplorerPlugin::default());
    app.finish();
    app.cleanup();
    app.update();
    app.world_mut().resource_mut::<ExplorerView>().wanted = UVec2::new(48, 27);
    // The catalog's five and three product spaces (a product camera and
    // its own pass between them).
    let names: Vec<&str> = catalog::NAMES
        .iter()
        .copied()
        .chain(["s2xs1", "genus2xs1", "mirrored-prism"])
        .collect();
    // Each count is taken in the space the switches began in, as what a
    // space keeps on the GPU differs by a buffer or so between spaces.
    let hundred_or_so = 100 - 100 % names.len();
    let switch = |app: &mut App, i: usize| {
        app.world_mut().resource_mut::<ExplorerSettings>().space = names[i % names.len()].to_string();
        app.update();
        app.update();
    };
    // Every space once, so each specialisation is compiled and cached
    // (Bevy keeps compiled pipelines for the app's lifetime, as it should).
    for i in 0..=2 * names.len() {
        switch(&mut app, i);
        offscreen::wait_for_pipelines(&mut app).expect("pipelines");
    }
    // A hundred switches or so (whole rounds of the spaces) to reach the
    // steady state (under load, objects made lazily, an exact-cell table
    // grown off the frame, can still be arriving after the warm-up), then
    // as many more: a leak grows with the switches, so the second count
    // is no higher than the first. Each count is taken once the GPU has
    // finished the frames submitted (`live`).
    // Freed objects go once the GPU is done with them, which under load
    // (the other tests of this binary run beside it) can take longer than
    // five quiet frames: settle again while counts are above. A leak never
    // comes back down.
    // Buffers, texture views, texture memory and bind groups: freed when
    // the GPU is done with them; pipelines and shader modules from here on.
    const FREED: usize = 4;
    // Two openings of the same space can differ by a buffer (seen under
    // load, one way or the other, and steady for hundreds of frames); not
    // one of the space's own, which are one per binding (`SceneBuffers`).
    const SLACK: [isize; FREED] = [2, 0, 0, 0];
    let hundred = |app: &mut App, from: usize, floor: Option<[isize; GPU_COUNTERS.len()]>| {
        for i in from..from + hundred_or_so {
            switch(app, i);
        }
        let mut now = settle(app);
        let Some(floor) = floor else {
            return now;
        };
        for _ in 0..20 {
            if (0..FREED).all(|k| now[k] <= floor[k] + SLACK[k]) {
                break;
            }
            now = settle(app);
        }
        now
    };
    let before = hundred(&mut app, 1, None);
    let after = hundred(&mut app, 1 + hundred_or_so, Some(before));
    let status = app.world().resource::<ExplorerStatus>();
    let world = app.world().resource::<ExplorerWorld>();
    eprintln!(
        "after {} switches: live {GPU_COUNTERS:?} {before:?} before, {after:?} after",
        status.switches
    );
    assert_eq!(status.switches, (2 * names.len() + 2 * hundred_or_so) as u64);
    assert_eq!(
        world.space.name(),
        catalog::torus(1.0).name(),
        "whole rounds of the 8 spaces end where they began"
    );
    // Every counter counts: the explorer's view is a texture with a view,
    // and it has buffers, bind groups and a render pipeline.
    assert!(
        before[..FREED + 1].iter().all(|&n| n > 0),
        "the counters count ({before:?})"
    );
    // Pipelines and shader modules: exactly where they were (each
    // specialisation compiled once). Buffers, texture views, texture
    // memory and bind groups: no more than before (give or take Bevy's
    // `SLACK`); Bevy may have freed some of its own since (a leak of one
    // per switch would add 96).
    assert_eq!(after[FREED..], before[FREED..], "pipelines and shader modules");
    for (k, what) in GPU_COUNTERS[..FREED].iter().enumerate() {
        assert!(
            after[k] <= before[k] + SLACK[k],
            "{what}: {} before, {} after",
            before[k],
            after[k]
        );
    }
    // One space root is left, with its camera, and no product space.
    let w = app.world_mut();
    assert_eq!(w.query::<&ManifoldSpace>().iter(w).count(), 1);
    assert_eq!(w.query::<&ManifoldCamera>().iter(w).count(), 1);
    let products = w.query::<&bevy_manifold::product::ProductSpaceRoot>().iter(w).count();
    let cameras = w.query::<&bevy_manifold::product::ProductCamera>().iter(w).count();
    assert_eq!((products, cameras), (0, 0));
}

/// The settings file, fuzzed (the `fuzz` module of the test support):
/// every mutant loads without a panic, and what it loads is in range (a
/// second clean-up finds nothing to fix).
fn fuzzed_settings_files_load_in_range() {
    use bevy_manifold_test_support::fuzz::{Target, cases, mutate_json, run};
    let dir = tmp_dir("fuzz");
    let path = dir.join("explorer.json");
    let seed: serde_json::Value = serde_json::to_value(ExplorerSettings::default()).expect("json");
    let target = Target {
        format: "explorer settings",
        mutate: mutate_json,
        run: |v: &serde_json::Value| {
            std::fs::write(&path, v.to_string()).expect("write");
            let (s, _) = settings::load(&path);
            let mut again = s.clone();
            assert!(again.sanitize().is_empty(), "loaded settings out of range: {s:?}");
            assert_eq!(again, s);
            let broken = path.with_extension("json.broken");
            let refused = broken.exists();
            let _ = std::fs::remove_file(&broken);
            !refused
        },
        bytes: |v: &serde_json::Value| v.to_string().into_bytes(),
    };
    run(
        &target,
        &[seed],
        cases(1500),
        6_000_000,
        std::time::Duration::from_secs(5),
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// The explorer's plugin in an app with no renderer, one frame run.
fn headless_explorer() -> App {
    let mut app = App::new();
    app.add_plugins((MinimalPlugins, AssetPlugin::default(), ImagePlugin::default()))
        .init_asset::<Mesh>()
        .init_asset::<StandardMaterial>()
        .add_plugins(ExplorerPlugin::default());
    app.update();
    app
}

fn a_space_that_cannot_be_loaded_is_reported_and_the_view_stays() {
    let mut app = headless_explorer();
    let dir = tmp_dir("badspace");
    let bad = dir.join("broken.json");
    std::fs::write(&bad, "{ \"geometry\": ").unwrap();
    app.world_mut().resource_mut::<ExplorerSettings>().space = bad.display().to_string();
    app.update();
    let status = app.world().resource::<ExplorerStatus>();
    let (message, error) = status.message.clone().expect("a message");
    assert!(error && message.contains("broken.json"), "{message}");
    assert_eq!(app.world().resource::<ExplorerSettings>().space, "torus");
    assert_eq!(
        app.world().resource::<ExplorerWorld>().space.name(),
        catalog::torus(1.0).name()
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// The panel's "hold a frame rate" puts a controller on the camera that
/// moves its render scale: frames here take 1/60 s of (manual) time
/// whatever the scale, so 144 fps drives it to its least and 30 fps back
/// to full; off takes both away.
fn holding_a_frame_rate_moves_the_cameras_render_scale() {
    let mut app = timed_explorer();
    let camera = app.world().resource::<ExplorerWorld>().camera;
    let scale = |app: &App| app.world().get::<ManifoldRenderScale>(camera).map(|s| s.0);
    assert_eq!(scale(&app), None);
    {
        let mut s = app.world_mut().resource_mut::<ExplorerSettings>();
        s.hold_frame_rate = true;
        s.target_fps = 144.0;
    }
    let mut seen = Vec::new();
    for _ in 0..60 {
        app.update();
        seen.push(scale(&app));
    }
    let adaptive = app.world().get::<AdaptiveRenderScale>(camera).expect("a controller");
    assert!((adaptive.target_frame_ms - 1000.0 / 144.0).abs() < 1e-4);
    assert_eq!(seen.last().copied().flatten(), Some(settings::MIN_SCALE), "{seen:?}");
    // The first change is the square root of 6.94 / 16.67 ms, on the grid.
    assert!(seen.contains(&Some(0.64)), "{seen:?}");
    app.world_mut().resource_mut::<ExplorerSettings>().target_fps = 30.0;
    for _ in 0..200 {
        app.update();
    }
    assert_eq!(scale(&app), Some(1.0));
    app.world_mut().resource_mut::<ExplorerSettings>().hold_frame_rate = false;
    app.update();
    app.update();
    assert_eq!(scale(&app), None);
    assert!(app.world().get::<AdaptiveRenderScale>(camera).is_none());
    // Refining a still view: on by default at 16 samples, off and back at
    // another count.
    let refine = |app: &App| app.world().get::<ManifoldAccumulation>(camera).copied();
    assert_eq!(refine(&app), Some(ManifoldAccumulation { samples: 16 }));
    app.world_mut().resource_mut::<ExplorerSettings>().refine_still = false;
    app.update();
    assert_eq!(refine(&app), None);
    {
        let mut s = app.world_mut().resource_mut::<ExplorerSettings>();
        s.refine_still = true;
        s.still_samples = 32;
    }
    app.update();
    assert_eq!(refine(&app), Some(ManifoldAccumulation { samples: 32 }));
    // Cone tracing: on by default, off and back.
    let cones = |app: &App| app.world().get::<ManifoldFootprint>(camera).is_some();
    assert!(cones(&app));
    app.world_mut().resource_mut::<ExplorerSettings>().smooth_detail = false;
    app.update();
    assert!(!cones(&app));
    app.world_mut().resource_mut::<ExplorerSettings>().smooth_detail = true;
    app.update();
    assert!(cones(&app));
}

/// The panel's cell rules reach the space the world shows (what the render
/// pass, the ray casts and the movers read), and survive a space switch.
fn the_panels_cell_rules_reach_the_space() {
    use bevy_manifold::placement::ManifoldSpace;
    use bevy_manifold::space::rule::{CellRule, Walls};
    let mut app = headless_explorer();
    let rule_of = |app: &App| {
        let root = app.world().resource::<ExplorerWorld>().root;
        *app.world().get::<ManifoldSpace>(root).unwrap().rule()
    };
    assert_eq!(rule_of(&app), CellRule::default());
    {
        let mut s = app.world_mut().resource_mut::<ExplorerSettings>();
        s.walls = true;
        s.wall_density = 0.25;
        s.wall_seed = 7;
    }
    app.update();
    let maze = CellRule {
        hidden: None,
        walls: Some(Walls { density: 0.25, seed: 7 }),
    };
    assert_eq!(rule_of(&app), maze);
    app.world_mut().resource_mut::<ExplorerSettings>().space = "seifert-weber".into();
    app.update();
    assert_eq!(rule_of(&app), maze);
    app.world_mut().resource_mut::<ExplorerSettings>().walls = false;
    app.update();
    assert_eq!(rule_of(&app), CellRule::default());
}

fn library_spaces_and_gen_files_open_in_the_explorer() {
    let mut app = headless_explorer();
    // A library space by name: its Dirichlet domain, a truncated cube.
    app.world_mut().resource_mut::<ExplorerSettings>().space = "binary-octahedral".into();
    app.update();
    let world = app.world().resource::<ExplorerWorld>();
    assert_eq!(world.space.name(), "binary-octahedral");
    assert_eq!(world.space.faces().len(), 14);
    assert_eq!(world.space.group_order(), Some(48));
    // A generator file by path, as "Open a space file" passes it.
    let dir = tmp_dir("genfile");
    let path = dir.join("quarter.gen");
    let gens = bevy_manifold::space::library::by_name("quarter-turn").unwrap();
    std::fs::write(&path, gens.to_gen("quarter-turn space")).unwrap();
    app.world_mut().resource_mut::<ExplorerSettings>().space = path.display().to_string();
    app.update();
    let world = app.world().resource::<ExplorerWorld>();
    assert_eq!(world.space.name(), "quarter");
    assert!((world.space.volume() - 1.0).abs() < 1e-12);
    let status = app.world().resource::<ExplorerStatus>();
    assert!(
        status
            .message
            .as_ref()
            .is_some_and(|(m, e)| !e && m.contains("quarter")),
        "{:?}",
        status.message
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// The headless explorer at 60 frames a second of game time.
fn timed_explorer() -> App {
    let mut app = headless_explorer();
    app.insert_resource(bevy::time::TimeUpdateStrategy::ManualDuration(
        std::time::Duration::from_secs_f64(1.0 / 60.0),
    ));
    app.update();
    app
}

fn shipped_tour(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../bevy_manifold_core/assets/tours/{name}.tour.json"))
}

/// The camera's placement, cell and face word.
fn camera_state(app: &App) -> (glam::DMat4, DomainCell, Vec<usize>) {
    let camera = app.world().resource::<ExplorerWorld>().camera;
    let w = app.world();
    (
        w.get::<Placement>(camera).unwrap().isometry,
        w.get::<DomainCell>(camera).unwrap().clone(),
        w.get::<FaceWord>(camera).unwrap().0.clone(),
    )
}

fn max_abs(m: glam::DMat4) -> f64 {
    m.to_cols_array().iter().fold(0.0f64, |a, x| a.max(x.abs()))
}

/// Opening a shipped tour switches the explorer to its space and the
/// camera flies it: after each stretch of play the camera is at the pose
/// the tour file gives for the time played (loaded here on its own), in
/// the copy it names, the face word the explorer tracked names that copy
/// too, the panel shows the tour's levels and caption; a seek jumps.
fn a_tour_opened_in_the_explorer_flies_the_camera_along_it() {
    let shipped = bevy_manifold_app::explorer::tour::shipped_tours();
    assert_eq!(shipped.len(), 6, "the panel lists the six shipped tours: {shipped:?}");
    let mut app = timed_explorer();
    let path = shipped_tour("seifert-weber");
    let (space, tour) = Tour::load(&path).unwrap();
    {
        let w = app.world_mut();
        let mut settings = w.resource::<ExplorerSettings>().clone();
        w.resource_mut::<ExplorerTour>().open(&path, &mut settings).unwrap();
        *w.resource_mut::<ExplorerSettings>() = settings;
    }
    let mut crossed_some = false;
    for stretch in [90, 600, 900] {
        for _ in 0..stretch {
            app.update();
        }
        let t = app.world().resource::<ExplorerTour>().time;
        assert_eq!(app.world().resource::<ExplorerWorld>().space.name(), space.name());
        let (placement, cell, word) = camera_state(&app);
        let frame = tour.frame(&space, t);
        assert_eq!(cell.id, space.cell_id_of(&space.cell_of_word(&frame.word)), "t = {t}");
        assert_eq!(
            cell.id,
            space.cell_id_of(&space.cell_of_word(&word)),
            "the tracked word, t = {t}"
        );
        assert!(max_abs(placement - frame.placement) < 1e-9, "t = {t}");
        crossed_some |= !word.is_empty();
        let settings = app.world().resource::<ExplorerSettings>();
        assert_eq!(settings.levels, tour.settings_at(t).levels, "t = {t}");
        assert_eq!(app.world().resource::<ExplorerTour>().caption(), tour.caption_at(t));
    }
    let t = app.world().resource::<ExplorerTour>().time;
    assert!((t - 1590.0 / 60.0).abs() < 0.05, "played 1590 frames at speed 1: {t}");
    // A tour that rides the vehicle: the scene has it, and the camera
    // follows the tour, not the vehicle's controls.
    {
        let w = app.world_mut();
        let mut settings = w.resource::<ExplorerSettings>().clone();
        let mut flight = ExplorerTour::default();
        flight.open(shipped_tour("torus-flight"), &mut settings).unwrap();
        flight.follow = true;
        *w.resource_mut::<ExplorerSettings>() = settings;
        *w.resource_mut::<ExplorerTour>() = flight;
    }
    let (flight_space, flight) = Tour::load(shipped_tour("torus-flight")).unwrap();
    for _ in 0..120 {
        app.update();
    }
    let s = app.world().resource::<ExplorerSettings>();
    assert!(s.vehicle && !s.hands, "the tour's scene");
    let ft = app.world().resource::<ExplorerTour>().time;
    let (placement, cell, _) = camera_state(&app);
    let frame = flight.frame(&flight_space, ft);
    assert_eq!(
        cell.id,
        flight_space.cell_id_of(&flight_space.cell_of_word(&frame.word))
    );
    assert!(max_abs(placement - frame.placement) < 1e-9, "on the flight at {ft}");
    let camera = app.world().resource::<ExplorerWorld>().camera;
    assert!(
        app.world().get::<Vehicle>(camera).is_none(),
        "no vehicle controls while on the tour"
    );
    // Back to the Seifert-Weber tour where it was.
    {
        let w = app.world_mut();
        let mut settings = w.resource::<ExplorerSettings>().clone();
        w.resource_mut::<ExplorerTour>().open(&path, &mut settings).unwrap();
        *w.resource_mut::<ExplorerSettings>() = settings;
    }
    app.update();
    app.update();
    assert!(crossed_some, "the tour left the home copy");
    app.world_mut().resource_mut::<ExplorerTour>().seek(5.0);
    app.update();
    let (placement, _, _) = camera_state(&app);
    let t = app.world().resource::<ExplorerTour>().time;
    assert!((t - 5.0).abs() < 0.02, "{t}");
    assert!(max_abs(placement - tour.frame(&space, t).placement) < 1e-9);
    // Following off: the fly camera is back, the tour player gone.
    app.world_mut().resource_mut::<ExplorerTour>().follow = false;
    app.update();
    app.update();
    let camera = app.world().resource::<ExplorerWorld>().camera;
    assert!(app.world().get::<TourPlayer>(camera).is_none());
    assert!(app.world().get::<FlyCamera>(camera).is_some());
}

/// Recording: fly the camera out through faces, add its view as a
/// keyframe, fly on, add another, save; the saved file, opened again,
/// puts the camera back at each recorded pose in the recorded copy.
fn views_recorded_as_keyframes_are_where_the_saved_tour_goes() {
    let mut app = timed_explorer();
    app.world_mut().resource_mut::<ExplorerSettings>().space = "seifert-weber".into();
    app.update();
    let camera = app.world().resource::<ExplorerWorld>().camera;
    app.world_mut().entity_mut(camera).remove::<FlyCamera>();
    let settings = app.world().resource::<ExplorerSettings>().clone();
    app.world_mut()
        .resource_mut::<ExplorerTour>()
        .start_new(&settings, 60.0);
    let mut recorded = Vec::new();
    for (k, (linear, angular)) in [
        (glam::DVec3::ZERO, glam::DVec3::ZERO),
        (glam::DVec3::new(0.2, 0.1, -1.0) * 0.6, glam::DVec3::new(0.0, 0.4, 0.1)),
        (
            glam::DVec3::new(-0.3, 0.5, -1.0) * 0.6,
            glam::DVec3::new(0.3, 0.0, -0.2),
        ),
    ]
    .into_iter()
    .enumerate()
    {
        app.world_mut()
            .entity_mut(camera)
            .insert(GeodesicVelocity { linear, angular });
        for _ in 0..120 {
            app.update();
        }
        app.world_mut().entity_mut(camera).insert(GeodesicVelocity::default());
        app.update();
        let (placement, cell, word) = camera_state(&app);
        let space = app.world().resource::<ExplorerWorld>().space.clone();
        assert_eq!(
            cell.id,
            space.cell_id_of(&space.cell_of_word(&word)),
            "the tracked word names the cell"
        );
        let time = 4.0 * k as f64;
        let i = app
            .world_mut()
            .resource_mut::<ExplorerTour>()
            .record(&space, time, &word, placement)
            .unwrap();
        assert_eq!(i, k);
        recorded.push((time, placement, cell.id, word));
    }
    assert!(recorded.iter().any(|r| !r.3.is_empty()), "the flights crossed faces");
    let dir = tmp_dir("recorded-tour");
    let file = dir.join("mine.tour.json");
    {
        let mut tour = app.world_mut().resource_mut::<ExplorerTour>();
        tour.path = file.display().to_string();
        tour.save().unwrap();
    }
    // Played back from the file: each recorded view at its time.
    let mut app = timed_explorer();
    {
        let w = app.world_mut();
        let mut settings = w.resource::<ExplorerSettings>().clone();
        w.resource_mut::<ExplorerTour>().open(&file, &mut settings).unwrap();
        *w.resource_mut::<ExplorerSettings>() = settings;
    }
    app.update();
    for (time, placement, id, _) in &recorded {
        app.world_mut().resource_mut::<ExplorerTour>().playing = false;
        app.world_mut().resource_mut::<ExplorerTour>().seek(*time);
        app.update();
        let (p, cell, _) = camera_state(&app);
        assert_eq!(cell.id, *id, "t = {time}");
        assert!(
            max_abs(p - *placement) < 1e-9,
            "t = {time}: {}",
            max_abs(p - *placement)
        );
    }
    // An edit that breaks the tour (times out of order) is refused by name.
    let space = app.world().resource::<ExplorerWorld>().space.clone();
    let mut tour = app.world_mut().resource_mut::<ExplorerTour>();
    tour.desc.as_mut().unwrap().keyframes[2].time = Some(1.0);
    let e = tour.rebuild(&space).unwrap_err();
    assert!(e.contains("keyframes[2].time"), "{e}");
    std::fs::remove_dir_all(&dir).ok();
}

/// The vehicle: on, the camera rides it (a child mesh spawned with the
/// camera) and flies forward along its geodesic at the vehicle's speed.
fn the_camera_rides_the_vehicle_forward_along_the_geodesic() {
    use bevy_manifold::geometry::Geometry;
    let mut app = timed_explorer();
    app.world_mut().resource_mut::<ExplorerSettings>().space = "poincare".into();
    app.update();
    app.world_mut().resource_mut::<ExplorerSettings>().vehicle = true;
    app.update();
    app.update();
    let camera = app.world().resource::<ExplorerWorld>().camera;
    let speed = app
        .world()
        .get::<Vehicle>(camera)
        .expect("the camera rides the vehicle")
        .speed;
    assert!(app.world().get::<FlyCamera>(camera).is_none());
    let children = app.world().get::<Children>(camera).unwrap();
    assert!(
        children
            .iter()
            .any(|c| app.world().get::<Name>(c).is_some_and(|n| n.as_str() == "vehicle")
                && app.world().get::<Mesh3d>(c).is_some()),
        "the vehicle's mesh under the camera"
    );
    let (start, cell0, _) = camera_state(&app);
    for _ in 0..30 {
        app.update();
    }
    let (end, cell1, _) = camera_state(&app);
    assert_eq!(cell0.id, cell1.id, "short enough to stay in the copy");
    let g = Geometry::Spherical;
    let travelled = g.distance::<f64>(start * glam::DVec4::W, end * glam::DVec4::W);
    assert!((travelled - speed * 0.5).abs() < 1e-9, "{travelled} vs {}", speed * 0.5);
    // Along the start frame's -z: the end point is exp of that direction.
    let ahead = start * bevy_manifold::geometry::isometry::translation(g, glam::DVec3::NEG_Z * speed * 0.5);
    assert!(max_abs(end - ahead) < 1e-9);
}

/// A product space picked in the panel (its name in the settings) is
/// shown by a `ProductCamera` among its balls and lights; the levels, the
/// distance, the fog and the per-cell shading reach its view; lights off
/// takes them away and keeps the view; a space of E3 picked after it
/// brings back a `ManifoldSpace`, and nothing of the product is left.
fn product_spaces_open_in_the_explorer() {
    use bevy_manifold::placement::ManifoldSpace;
    use bevy_manifold::product::{ProductBody, ProductCamera, ProductPointLight, ProductSpaceRoot};
    use bevy_manifold::space::cells::CellTint;
    let mut app = headless_explorer();
    app.world_mut().resource_mut::<ExplorerSettings>().space = "genus2xs1".into();
    app.update();
    app.update();
    let world = app.world().resource::<ExplorerWorld>().clone();
    let product = world.product.clone().expect("a product space shown");
    assert_eq!((product.name.as_str(), world.name()), ("genus 2 x S1", "genus 2 x S1"));
    assert!(app.world().get::<ProductSpaceRoot>(world.root).is_some());
    assert!(app.world().get::<ManifoldSpace>(world.root).is_none());
    let count = |app: &mut App| {
        let lights = app.world_mut().query::<&ProductPointLight>().iter(app.world()).count();
        let balls = app.world_mut().query::<&ProductBody>().iter(app.world()).count();
        (lights, balls)
    };
    assert_eq!(count(&mut app), (2, 3));
    {
        let mut s = app.world_mut().resource_mut::<ExplorerSettings>();
        s.levels = 7;
        s.max_distance = 9.0;
        s.fog = true;
        s.fog_density = 0.2;
        s.cells = true;
        s.cell_mode = CellMode::ByCell;
    }
    app.update();
    let camera = app
        .world()
        .get::<ProductCamera>(world.camera)
        .expect("the product camera");
    assert_eq!(camera.view.max_crossings, 7);
    assert!((camera.view.max_distance - 9.0).abs() < 1e-12 && (camera.view.fog - 0.2).abs() < 1e-12);
    assert_eq!(camera.view.tint, Some(CellTint::ByCell));
    assert_eq!(camera.lights.len(), 2, "lit by the root's lights");
    assert_eq!(camera.balls.len(), 3);
    // Moved, then the lights turned off: the view stays where it was.
    let moved = camera.view.moved(&product, [1.0, 0.0, 0.0], 0.3);
    app.world_mut().get_mut::<ProductCamera>(world.camera).unwrap().view = moved;
    app.world_mut().resource_mut::<ExplorerSettings>().lights = false;
    app.update();
    app.update();
    let now = app.world().resource::<ExplorerWorld>().clone();
    let camera = app
        .world()
        .get::<ProductCamera>(now.camera)
        .expect("the product camera");
    assert_eq!(camera.view.eye, moved.eye);
    assert!(camera.lights.is_empty());
    assert_eq!(count(&mut app), (0, 3));
    // Back to the 3-torus.
    app.world_mut().resource_mut::<ExplorerSettings>().space = "torus".into();
    app.update();
    let back = app.world().resource::<ExplorerWorld>().clone();
    assert!(back.product.is_none());
    assert!(app.world().get::<ManifoldSpace>(back.root).is_some());
    let roots = app.world_mut().query::<&ProductSpaceRoot>().iter(app.world()).count();
    assert_eq!((roots, count(&mut app)), (0, (0, 0)));
}

bevy_manifold_test_support::test_main! {
    cpu: [
        product_spaces_open_in_the_explorer,
        a_tour_opened_in_the_explorer_flies_the_camera_along_it,
        views_recorded_as_keyframes_are_where_the_saved_tour_goes,
        the_camera_rides_the_vehicle_forward_along_the_geodesic,
        fuzzed_settings_files_load_in_range,
        library_spaces_and_gen_files_open_in_the_explorer,
        the_panels_cell_rules_reach_the_space,
        holding_a_frame_rate_moves_the_cameras_render_scale,
        settings_round_trip_and_broken_files_are_replaced_not_lost,
        without_a_display_the_explorer_renders_explorer_png_and_exits_0,
        explore_opens_the_space_it_is_given_and_names_a_bad_one,
        a_space_that_cannot_be_loaded_is_reported_and_the_view_stays,
    ],
    gpu: [
        switching_spaces_100_times_leaks_no_buffers_or_pipelines,
    ],
}
