//! The command line, run as a user runs it.

use std::path::PathBuf;
use std::process::{Command, Output};

fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_bevy_manifold"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("bevy_manifold_cli_{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir.join(name)
}

// No arguments opens the explorer (tests/explorer.rs runs its headless
// fallback).
fn help_prints_usage() {
    let o = run(&["--help"]);
    assert!(o.status.success());
    let out = stdout(&o);
    assert!(
        out.contains("Usage") && out.contains("render") && out.contains("space"),
        "{out}"
    );
}

fn space_list_prints_one_name_per_line() {
    let o = run(&["space", "list"]);
    assert!(o.status.success());
    assert_eq!(
        stdout(&o),
        "torus\nseifert-weber\npoincare\nmirrored-cube\nmirrored-dodecahedron\n"
    );
}

fn space_show_gives_the_invariants() {
    let out = stdout(&run(&["space", "show", "seifert-weber"]));
    for needle in [
        "geometry:      hyperbolic",
        "faces:         12",
        "vertices:      20",
        "dihedral angles (deg): 72.000000",
        "volume:        11.19906",
        "first homology: Z/5 + Z/5 + Z/5",
        "edge cycles:   6",
        "angle sum 360.000000 deg",
    ] {
        assert!(out.contains(needle), "missing '{needle}' in:\n{out}");
    }
    let out = stdout(&run(&["space", "show", "poincare"]));
    assert!(
        out.contains("group order:   120") && out.contains("inradius:      0.314159265"),
        "{out}"
    );
}

fn export_then_load_the_file_by_path() {
    let o = run(&["space", "export", "poincare"]);
    assert!(o.status.success());
    let json = stdout(&o);
    let v: serde_json::Value = serde_json::from_str(&json).expect("export is JSON");
    assert_eq!(v["geometry"], "spherical");
    assert_eq!(v["faces"].as_array().map(Vec::len), Some(12));
    assert_eq!(v["faces"][0]["kind"], "glue");
    assert_eq!(v["vertices"].as_array().map(Vec::len), Some(20));
    let path = tmp("poincare.json");
    std::fs::write(&path, &json).expect("write");
    let p = path.to_str().expect("utf-8 path");
    let shown = stdout(&run(&["space", "show", p]));
    assert!(shown.contains("group order:   120"), "{shown}");
    let again = stdout(&run(&["space", "export", p]));
    assert!(
        again == json,
        "export of the loaded file differs from the file (floats must round-trip exactly)"
    );
}

fn a_broken_space_file_is_reported_with_its_name() {
    let path = tmp("broken.json");
    std::fs::write(
        &path,
        r#"{"name": "x", "geometry": "hyperbolic", "faces": [{"plane": [1, 0, 0, -0.5]}]}"#,
    )
    .expect("write");
    let p = path.to_str().expect("utf-8 path");
    let o = run(&["space", "show", p]);
    assert_eq!(o.status.code(), Some(1));
    let err = stderr(&o);
    assert!(err.contains("broken.json") && err.contains("missing field"), "{err}");
    assert!(!err.contains("panicked"));
    let o = run(&["space", "show", "no-such-space"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("neither a catalog space"), "{}", stderr(&o));
}

fn gen_files_import_show_and_render() {
    // A .gen file of our own (the library's Hantzsche-Wendt space, row
    // vectors as Curved Spaces writes them).
    let gen_path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../bevy_manifold_core/assets/spaces/hantzsche-wendt.gen");
    let g = gen_path.to_str().expect("utf-8 path");
    let shown = stdout(&run(&["space", "show", g]));
    for needle in [
        "geometry:      euclidean",
        "faces:         12",
        "volume:        0.250000000",
        "first homology: Z/4 + Z/4",
    ] {
        assert!(shown.contains(needle), "missing '{needle}' in:\n{shown}");
    }
    // Import writes the space file, which loads like any other.
    let out = tmp("hw.json");
    let o = run(&["space", "import", g, "--out", out.to_str().expect("utf-8")]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("12 faces, volume 0.250000000"), "{}", stderr(&o));
    let again = stdout(&run(&["space", "show", out.to_str().expect("utf-8")]));
    assert!(again.contains("faces:         12"), "{again}");
    // A basepoint on request: the 3-torus centred elsewhere is the same cube.
    let bcc = gen_path.with_file_name("torus-bcc.gen");
    let o = run(&[
        "space",
        "import",
        bcc.to_str().expect("utf-8"),
        "--basepoint",
        "0.1,-0.2,0.3,1",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("14 faces, volume 0.500000000"), "{}", stderr(&o));
    // Render takes it too.
    let png = tmp("hw.png");
    let o = run(&[
        "render",
        "--space",
        g,
        "--cpu",
        "--width",
        "64",
        "--height",
        "36",
        "--out",
        png.to_str().expect("utf-8"),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(image::open(&png).is_ok());
    // The library listing: one line per space, with its invariants.
    let listing = stdout(&run(&["space", "library"]));
    assert!(
        listing
            .lines()
            .any(|l| l.starts_with("binary-octahedral") && l.contains("14 faces") && l.contains("group 48")),
        "{listing}"
    );
    // A broken .gen names the file and the line.
    let bad = tmp("bad.gen");
    std::fs::write(&bad, "1 0 0 0\n0 1 x 0\n").expect("write");
    let o = run(&["space", "import", bad.to_str().expect("utf-8")]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        stderr(&o).contains("bad.gen") && stderr(&o).contains("line 2: 'x' is not a number"),
        "{}",
        stderr(&o)
    );
}

fn render_mirror_adds_the_mirror_ball_and_one_reflection() {
    // The paper's scene with the mirror ball (id 1, ahead of the camera)
    // seen once with the default reflection and once with none: the
    // mirror's pixels differ; the edges and the background do not.
    let (a, b, ids) = (tmp("mirror.png"), tmp("mirror_plain.png"), tmp("mirror_ids.png"));
    let common = [
        "render", "--space", "torus", "--mirror", "--cpu", "--width", "64", "--height", "36",
    ];
    let mut with = common.to_vec();
    with.extend([
        "--out",
        a.to_str().expect("utf-8"),
        "--ids",
        ids.to_str().expect("utf-8"),
    ]);
    let o = run(&with);
    assert!(o.status.success(), "{}", stderr(&o));
    let mut without = common.to_vec();
    without.extend(["--reflections", "0", "--out", b.to_str().expect("utf-8")]);
    let o = run(&without);
    assert!(o.status.success(), "{}", stderr(&o));
    let (a, b) = (image::open(&a).unwrap().to_rgba8(), image::open(&b).unwrap().to_rgba8());
    let ids = image::open(&ids).unwrap().to_rgba8();
    assert_eq!(ids.get_pixel(32, 18).0[0], 1, "the mirror ball ahead");
    let (mut mirror, mut changed, mut plain_changed) = (0, 0, 0);
    for (x, y, id) in ids.enumerate_pixels() {
        let differs = a.get_pixel(x, y) != b.get_pixel(x, y);
        match id.0[0] {
            1 => {
                mirror += 1;
                changed += usize::from(differs);
            }
            // Edges (no material) and the background reflect nothing;
            // Suzanne and the hands (roughness 0.5) neither, but what
            // they show through the mirror's reflection may change.
            0 | 255 => plain_changed += usize::from(differs),
            _ => {}
        }
    }
    assert!(
        mirror > 100 && changed * 5 > mirror,
        "{changed} of {mirror} mirror pixels changed"
    );
    assert_eq!(plain_changed, 0, "edges and background are the same");
}

fn render_refuses_sizes_and_levels_no_tracer_takes() {
    let out = tmp("never.png");
    let out = out.to_str().expect("utf-8");
    // 70000 x 70000 overflows u32 when multiplied: checked in 64 bits.
    for (args, needle) in [
        (vec!["--width", "70000", "--height", "70000"], "70000x70000"),
        (vec!["--width", "0"], "0x360"),
        (vec!["--levels", "20000"], "20000 levels"),
        (vec!["--reflections", "9"], "9 reflections: at most 8"),
        (vec!["--path-trace", "--depth", "65"], "a path depth of 65: at most 64"),
        (vec!["--path-trace", "--depth", "0"], "--depth must be at least 1"),
        (vec!["--walls", "1.5"], "--walls must be a fraction"),
        (vec!["--hidden", "NaN"], "--hidden must be a fraction"),
    ] {
        let mut all = vec!["render", "--space", "torus", "--cpu", "--out", out];
        all.extend(args);
        let o = run(&all);
        assert_eq!(o.status.code(), Some(1), "{all:?}");
        let err = stderr(&o);
        assert!(err.contains(needle) && !err.contains("panicked"), "{err}");
    }
}

/// `product` renders each product space on the CPU: a PNG of the size
/// asked for, with the balls and the fog in it (several colours); with
/// `--cells` the balls seen in other copies of the prism change colour,
/// and with `--lights` the balls are lit otherwise; bad lengths and sizes
/// are refused by name.
fn product_renders_each_space_and_refuses_bad_numbers() {
    for space in [
        "s2xs1",
        "twisted-s2xs1",
        "genus2xs1",
        "twisted-genus2xs1",
        "mirrored-prism",
    ] {
        // The space drawn at 40x24, with `extra` arguments.
        let draw = |name: &str, extra: &[&str]| {
            let out = tmp(&format!("product_{space}{name}.png"));
            let mut all = vec!["product", "--space", space, "--width", "40", "--height", "24"];
            all.extend(extra);
            all.extend(["--out", out.to_str().expect("utf-8")]);
            let o = run(&all);
            assert!(o.status.success(), "{space}: {}", stderr(&o));
            image::open(&out).expect("a PNG").to_rgb8()
        };
        let png = draw("", &[]);
        assert_eq!(png.dimensions(), (40, 24));
        let mut colours: Vec<[u8; 3]> = png.pixels().map(|p| p.0).collect();
        colours.sort_unstable();
        colours.dedup();
        assert!(colours.len() > 20, "{space}: {} colours", colours.len());
        let by_cell = draw("_cells", &["--cells"]);
        let changed = png.pixels().zip(by_cell.pixels()).filter(|(a, b)| a != b).count();
        assert!(changed > 40, "{space}: {changed} pixels changed by cell");
        let lit = draw("_lights", &["--lights"]);
        let changed = png.pixels().zip(lit.pixels()).filter(|(a, b)| a != b).count();
        assert!(changed > 40, "{space}: {changed} pixels changed by the lights");
    }
    // A space's file, exported, edited and drawn from the file; a broken
    // one is named with its field.
    let o = run(&["product", "--space", "genus2xs1", "--length", "1.5", "--export"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let file = tmp("genus2.json");
    std::fs::write(&file, stdout(&o)).expect("write");
    let out = tmp("from_file.png");
    let o = run(&[
        "product",
        "--space",
        file.to_str().expect("utf-8"),
        "--width",
        "16",
        "--height",
        "9",
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    assert!(
        o.status.success() && stdout(&o).contains("genus 2 x S1"),
        "{}",
        stderr(&o)
    );
    let broken = tmp("broken.json");
    std::fs::write(
        &broken,
        stdout(&run(&["product", "--space", "s2xs1", "--export"])).replace("\"flip\": 1.0", "\"flip\": 2.0"),
    )
    .expect("write");
    let o = run(&[
        "product",
        "--space",
        broken.to_str().expect("utf-8"),
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    let err = stderr(&o);
    assert!(
        !o.status.success() && err.contains("broken.json: gluings[0]") && !err.contains("panicked"),
        "{err}"
    );
    // The tour through S2 x S1: one moment, then every frame at 1 fps.
    let tour = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../assets/tours/s2xs1.product-tour.json"
    );
    let moment = tmp("product_tour_moment.png");
    let o = run(&[
        "product",
        "--tour",
        tour,
        "--time",
        "8",
        "--width",
        "24",
        "--height",
        "16",
        "--out",
        moment.to_str().expect("utf-8"),
    ]);
    assert!(
        o.status.success() && stdout(&o).contains("S2 x S1, 8 s of"),
        "{}",
        stderr(&o)
    );
    assert_eq!(image::open(&moment).expect("a PNG").to_rgb8().dimensions(), (24, 16));
    let frames = tmp("product_tour_frames");
    let o = run(&[
        "product",
        "--tour",
        tour,
        "--fps",
        "1",
        "--width",
        "8",
        "--height",
        "6",
        "--out",
        frames.to_str().expect("utf-8"),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    // 25.85 s at 1 fps: frames at 0, 1, ..., 26.
    let written = std::fs::read_dir(&frames).expect("the frames").count();
    assert_eq!(written, 27, "{}", stdout(&o));
    let bad = tmp("bad.product-tour.json");
    std::fs::write(
        &bad,
        r#"{"product_space": "s2xs1", "legs": [{"fly": {"seconds": -1, "speed": 1}}]}"#,
    )
    .expect("write");
    let o = run(&[
        "product",
        "--tour",
        bad.to_str().expect("utf-8"),
        "--out",
        moment.to_str().expect("utf-8"),
    ]);
    let err = stderr(&o);
    assert!(
        !o.status.success()
            && err.contains("bad.product-tour.json: legs[0].fly.seconds: must be positive")
            && !err.contains("panicked"),
        "{err}"
    );
    let out = tmp("never_product.png");
    for (args, needle) in [
        (vec!["--length", "-1"], "between 0.01 and 100"),
        (vec!["--length", "NaN"], "between 0.01 and 100"),
        (vec!["--width", "0"], "--width"),
        (vec!["--twist", "0"], "--twist"),
    ] {
        let mut all = vec!["product", "--space", "genus2xs1", "--out", out.to_str().expect("utf-8")];
        all.extend(args);
        let o = run(&all);
        assert!(!o.status.success(), "{all:?}");
        let err = stderr(&o);
        assert!(err.contains(needle) && !err.contains("panicked"), "{all:?}: {err}");
    }
}

fn render_writes_the_image_and_the_id_buffer() {
    let (out, ids) = (tmp("torus.png"), tmp("torus_ids.png"));
    let o = run(&[
        "render",
        "--space",
        "torus",
        "--width",
        "48",
        "--height",
        "32",
        "--out",
        out.to_str().expect("utf-8"),
        "--ids",
        ids.to_str().expect("utf-8"),
        "--bounces",
        "3",
        "--fog",
        "0.5",
        "--cells",
        "--cpu",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let img = image::open(&out).expect("colour PNG").to_rgba8();
    assert_eq!(img.dimensions(), (48, 32));
    let idimg = image::open(&ids).expect("id PNG").to_rgba8();
    assert_eq!(idimg.dimensions(), (48, 32));
    // The default scene is the paper's: Suzanne (id 1) attached to the
    // camera, seen only in other copies (levels > 0), the hands (2, 3) in
    // front of it in its own copy, and the edges (255).
    assert!(idimg.pixels().any(|p| p.0[0] == 1 && p.0[1] > 0), "Suzanne's images");
    assert!(!idimg.pixels().any(|p| p.0[0] == 1 && p.0[1] == 0), "not her own copy");
    assert!(
        idimg.pixels().any(|p| (p.0[0] == 2 || p.0[0] == 3) && p.0[1] == 0),
        "the hands"
    );
    // Some pixels see edges (255) and other copies (levels > 0), none more than 3.
    assert!(idimg.pixels().any(|p| p.0[0] == 255));
    assert!(idimg.pixels().any(|p| p.0[1] > 0));
    assert!(idimg.pixels().all(|p| p.0[1] <= 3));
    // Not a blank image.
    let first = img.get_pixel(0, 0).0;
    assert!(img.pixels().any(|p| p.0 != first));
}

/// `render --hdr` and `--exr` write the linear colour, unclamped: a ball
/// glowing at three times its white albedo reads above 3 in the Radiance
/// file, as the CPU reference traces it (RGBE keeps about 1%), and in the
/// OpenEXR file exactly (32-bit floats, found through the file's line
/// offset table), where the PNG shows white.
fn render_writes_linear_hdr() {
    use bevy_manifold_core::prelude::*;
    let space = catalog::torus(1.0);
    let mut scene = Scene::default_for(&space);
    scene.balls[0].color = [1.0; 3];
    scene.balls[0].glow = 3.0;
    let scene_path = tmp("glow.scene.json");
    std::fs::write(&scene_path, scene.to_json()).expect("scene file");
    let (png, hdr, exr) = (tmp("glow.png"), tmp("glow.hdr"), tmp("glow.exr"));
    let o = run(&[
        "render",
        "--space",
        "torus",
        "--scene",
        scene_path.to_str().expect("utf-8"),
        "--width",
        "48",
        "--height",
        "32",
        "--out",
        png.to_str().expect("utf-8"),
        "--hdr",
        hdr.to_str().expect("utf-8"),
        "--exr",
        exr.to_str().expect("utf-8"),
        "--cpu",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let linear = image::open(&hdr).expect("a Radiance HDR file").to_rgb32f();
    assert_eq!(linear.dimensions(), (48, 32));
    let settings = TraceSettings {
        width: 48,
        height: 32,
        ..TraceSettings::default()
    };
    let reference = render::<f64>(&space, &Scene::load(&scene_path, &space).expect("the scene"), &settings);
    let centre = (16 * 48 + 24) as usize;
    let want = reference.pixels[centre].color;
    let got = linear.get_pixel(24, 16).0;
    assert!(want.iter().all(|&c| c > 3.0), "the reference's centre {want:?}");
    for c in 0..3 {
        assert!((got[c] - want[c]).abs() <= 0.02 * want[c], "{got:?} against {want:?}");
    }
    // OpenEXR: magic number, then line 16's block through the offset
    // table (after the header's closing zero byte), its y, and the
    // channels B, G, R of 48 floats each.
    let bytes = std::fs::read(&exr).expect("the OpenEXR file");
    assert_eq!(bytes[..4], [0x76, 0x2f, 0x31, 0x01]);
    let word = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().expect("4 bytes"));
    let header_end = bytes.len() - 32 * (8 + 8 + 12 * 48);
    assert_eq!(bytes[header_end - 1], 0, "the header ends in a zero byte");
    let entry = header_end + 8 * 16;
    let block = u64::from_le_bytes(bytes[entry..entry + 8].try_into().expect("8 bytes")) as usize;
    assert_eq!(word(block), 16);
    assert_eq!(word(block + 4), 12 * 48);
    for (c, channel) in [2, 1, 0].into_iter().enumerate() {
        let v = f32::from_bits(word(block + 8 + 4 * (48 * c + 24)));
        assert!(
            (v - want[channel]).abs() <= 1e-6 * want[channel],
            "channel {channel}: {v} against {want:?}"
        );
    }
    let shown = image::open(&png).expect("PNG").to_rgba8();
    assert_eq!(&shown.get_pixel(24, 16).0[..3], &[255, 255, 255]);
}

/// `render --samples N` averages N traces (a still view's accumulation):
/// the mean of the CPU reference's `trace::accumulate`, and a count out
/// of range is refused by name.
fn render_samples_average_the_accumulated_traces() {
    use bevy_manifold_core::prelude::*;
    let png = tmp("samples.png");
    let render_samples = |samples: &str, cpu: &[&str]| {
        let size = ["--width", "40", "--height", "24"];
        let out = png.to_str().expect("utf-8");
        let args: Vec<&str> = ["render", "--space", "torus", "--samples", samples]
            .into_iter()
            .chain(size)
            .chain(cpu.iter().copied())
            .chain(["--out", out])
            .collect();
        run(&args)
    };
    let o = render_samples("0", &[]);
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("--samples must be between 1 and 256, got 0"),
        "{}",
        stderr(&o)
    );
    let o = render_samples("4", &["--cpu"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains(", 4 samples,"), "{}", stderr(&o));
    let space = catalog::torus(1.0);
    let settings = TraceSettings {
        width: 40,
        height: 24,
        ..TraceSettings::default()
    };
    let mean = bevy_manifold_core::trace::accumulate::<f64>(&space, &Scene::paper_default(&space), &settings, 4);
    let plain = render::<f64>(&space, &Scene::paper_default(&space), &settings);
    let shown = image::open(&png).expect("PNG").to_rgba8();
    let within = |colors: &mut dyn Iterator<Item = [f32; 3]>| {
        colors
            .zip(shown.pixels())
            .filter(|(c, p)| (0..3).all(|i| bevy_manifold_core::trace::srgb8(c[i]).abs_diff(p.0[i]) <= 1))
            .count()
    };
    let (to_mean, to_plain) = (
        within(&mut mean.iter().copied()),
        within(&mut plain.pixels.iter().map(|p| p.color)),
    );
    assert_eq!(to_mean, 40 * 24, "{to_mean} pixels are the mean's");
    assert!(to_plain < to_mean, "{to_plain} pixels are also the plain trace's");
}

/// `render --path-trace` averages path samples: the PNG is the mean of
/// the core's accumulated path samples of the same depth and seed.
fn render_path_trace_averages_path_samples() {
    use bevy_manifold_core::prelude::*;
    let png = tmp("paths.png");
    let o = run(&[
        "render",
        "--space",
        "poincare",
        "--width",
        "32",
        "--height",
        "20",
        "--path-trace",
        "--depth",
        "4",
        "--seed",
        "5",
        "--samples",
        "3",
        "--cpu",
        "--out",
        png.to_str().expect("utf-8"),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let space = catalog::poincare();
    let settings = TraceSettings {
        width: 32,
        height: 20,
        path_depth: 4,
        seed: 5,
        ..TraceSettings::default()
    };
    let mean = bevy_manifold_core::trace::accumulate::<f64>(&space, &Scene::paper_default(&space), &settings, 3);
    let shown = image::open(&png).expect("PNG").to_rgba8();
    let same = mean
        .iter()
        .zip(shown.pixels())
        .filter(|(c, p)| (0..3).all(|i| bevy_manifold_core::trace::srgb8(c[i]).abs_diff(p.0[i]) <= 1))
        .count();
    assert_eq!(same, 32 * 20, "{same} pixels are the mean of the path samples");
}

/// `render --cones` traces cones: far edges fade to a haze of their
/// average colour instead of sparkling (Seifert-Weber, 8 levels, where
/// most pixels see far copies), while what is hit in the camera's own copy
/// (the hands) stays as the plain trace draws it.
fn render_cones_trace_cones() {
    let (ids, pair) = (tmp("sw_ids.png"), [tmp("sw_plain.png"), tmp("sw_cones.png")]);
    for (path, cones) in pair.iter().zip([false, true]) {
        let mut args = vec![
            "render",
            "--space",
            "seifert-weber",
            "--width",
            "96",
            "--height",
            "54",
            "--cpu",
            "--out",
        ];
        args.push(path.to_str().expect("utf-8"));
        args.extend(if cones {
            vec!["--cones"]
        } else {
            vec!["--ids", ids.to_str().expect("utf-8")]
        });
        let o = run(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        assert_eq!(stderr(&o).contains(", cones,"), cones, "{}", stderr(&o));
    }
    let [plain, cones] = pair.map(|p| image::open(p).expect("PNG").to_rgba8());
    let ids = image::open(&ids).expect("ids").to_rgba8();
    let close = |p: &image::Rgba<u8>, q: &image::Rgba<u8>| p.0.iter().zip(q.0).all(|(a, b)| a.abs_diff(b) <= 2);
    let (mut near, mut near_same, mut same) = (0, 0, 0);
    for ((p, q), id) in plain.pixels().zip(cones.pixels()).zip(ids.pixels()) {
        // The hands (ids 2 and 3) in the camera's own copy.
        let here = (id.0[0] == 2 || id.0[0] == 3) && id.0[1] == 0;
        near += usize::from(here);
        near_same += usize::from(here && close(p, q));
        same += usize::from(close(p, q));
    }
    let n = plain.pixels().len();
    eprintln!(
        "cones: {same} of {n} pixels within 2/255 of the plain trace; {near_same} of {near} in the camera's copy"
    );
    assert!(near > n / 50, "the hands are in view ({near} pixels)");
    assert!(
        near_same * 10 >= near * 9,
        "near hits changed: {near_same} of {near} the same"
    );
    assert!(same * 2 < n, "the far haze is missing: {same} of {n} the same");
}

fn render_reports_a_bad_scene_field() {
    let scene = tmp("bad_scene.json");
    std::fs::write(
        &scene,
        r#"{"camera": {"isometry": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]], "fov_y_degrees": 60},
            "balls": [{"center": [0,0,0,1], "radius": 0, "color": [1,1,1]}]}"#,
    )
    .expect("write");
    let out = tmp("never.png");
    let o = run(&[
        "render",
        "--space",
        "torus",
        "--width",
        "8",
        "--height",
        "8",
        "--out",
        out.to_str().expect("utf-8"),
        "--scene",
        scene.to_str().expect("utf-8"),
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        stderr(&o).contains("balls[0].radius: must be positive"),
        "{}",
        stderr(&o)
    );
    assert!(!out.exists(), "no image is written for a bad scene");
}

fn render_defaults_to_the_gpu_and_matches_the_cpu_ids() {
    let (gpu_ids, cpu_ids, out) = (tmp("gpu_ids.png"), tmp("cpu_ids.png"), tmp("gpu.png"));
    let args = |ids: &PathBuf, extra: &[&str]| {
        let mut a: Vec<String> = [
            "render", "--space", "poincare", "--width", "64", "--height", "48", "--out",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        a.push(out.to_str().expect("utf-8").into());
        a.push("--ids".into());
        a.push(ids.to_str().expect("utf-8").into());
        a.extend(extra.iter().map(|s| s.to_string()));
        a
    };
    let g = Command::new(env!("CARGO_BIN_EXE_bevy_manifold"))
        .args(args(&gpu_ids, &[]))
        .output()
        .expect("runs");
    assert!(g.status.success(), "{}", stderr(&g));
    let said = stderr(&g);
    assert!(said.contains("GPU: "), "{said}");
    let c = Command::new(env!("CARGO_BIN_EXE_bevy_manifold"))
        .args(args(&cpu_ids, &["--cpu"]))
        .output()
        .expect("runs");
    assert!(c.status.success(), "{}", stderr(&c));
    let (a, b) = (
        image::open(&gpu_ids).expect("gpu ids").to_rgba8(),
        image::open(&cpu_ids).expect("cpu ids").to_rgba8(),
    );
    let same = a.pixels().zip(b.pixels()).filter(|(p, q)| p == q).count();
    assert!(
        same * 1000 >= 995 * a.pixels().len(),
        "only {same} of {} id pixels agree",
        a.pixels().len()
    );
}

/// `space cell --words`: ten thousand words in one process per catalog
/// space. Pairs equal in the group (a relator from the polyhedron spliced
/// in: a face and its partner, or an edge cycle to its order) print the
/// same id; a word and the same word with one more crossing (never the
/// identity) print different ids; every id is exact and unique per class.
fn space_cell_reads_ten_thousand_words_in_one_process() {
    use bevy_manifold::prelude::*;
    use bevy_manifold_test_support::Rng;
    for name in catalog::NAMES {
        let space = catalog::by_name(name).unwrap();
        let n = space.faces().len();
        let mut rng = Rng(41);
        let mut lines = Vec::new();
        for k in 0..5000 {
            let w: Vec<usize> = (0..rng.below(64)).map(|_| rng.below(n)).collect();
            let v = if k % 2 == 0 {
                let relator = if rng.below(2) == 0 {
                    let a = rng.below(n);
                    vec![a, space.faces()[a].partner]
                } else {
                    let c = &space.edge_cycles()[rng.below(space.edge_cycles().len())];
                    let once: Vec<usize> = c.faces.iter().rev().map(|&a| space.faces()[a].partner).collect();
                    once.repeat(c.order as usize)
                };
                let mut v = w.clone();
                let at = rng.below(w.len() + 1);
                v.splice(at..at, relator);
                v
            } else {
                let mut v = w.clone();
                v.push(rng.below(n));
                v
            };
            let text = |w: &[usize]| w.iter().map(ToString::to_string).collect::<Vec<_>>().join(",");
            lines.push(text(&w));
            lines.push(text(&v));
        }
        let file = tmp(&format!("{name}-words.txt"));
        std::fs::write(&file, lines.join("\n")).unwrap();
        let o = run(&["space", "cell", name, "--words", file.to_str().unwrap()]);
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        let out = stdout(&o);
        let ids: Vec<(u64, bool)> = out
            .lines()
            .map(|l| {
                let v: serde_json::Value = serde_json::from_str(l).unwrap();
                (v["id"].as_u64().unwrap(), v["exact"].as_bool().unwrap())
            })
            .collect();
        assert_eq!(ids.len(), 10_000, "{name}");
        for (k, pair) in ids.chunks(2).enumerate() {
            assert!(pair[0].1 && pair[1].1, "{name}: line {} not exact", 2 * k + 1);
            assert_eq!(
                pair[0].0 == pair[1].0,
                k % 2 == 0,
                "{name}: lines {} and {}",
                2 * k + 1,
                2 * k + 2
            );
        }
    }
    // A bad face names the file, the line and the face.
    let file = tmp("bad-words.txt");
    std::fs::write(&file, "1,2\n3,12,4\n").unwrap();
    let o = run(&["space", "cell", "seifert-weber", "--words", file.to_str().unwrap()]);
    assert!(!o.status.success());
    let err = stderr(&o);
    assert!(
        err.contains("bad-words.txt line 2") && err.contains("face 1 is 12"),
        "{err}"
    );
    // One word, as a person asks: the origin copy's neighbour through
    // face 0 and back through its partner is home, id 0.
    let o = run(&["space", "cell", "seifert-weber", "--faces", "0,6", "--json"]);
    let v: serde_json::Value = serde_json::from_str(stdout(&o).trim()).unwrap();
    assert_eq!(v["id"], 0);
    assert_eq!(v["exact"], true);
}

/// The repository's shipped tour `name`.
fn shipped_tour(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("../../assets/tours/{name}.tour.json"))
}

/// `tour render`: frame k is the tour's camera at k / fps, traced; its
/// colours and ids are those of a render of that pose made here.
fn tour_render_frame_k_is_the_camera_at_k_over_fps() {
    use bevy_manifold_core::tour::Tour;
    use bevy_manifold_core::trace::{id_pixel, render, srgb8};
    let tour_file = shipped_tour("seifert-weber");
    let out = tmp("tour_frames");
    let o = run(&[
        "tour",
        "render",
        tour_file.to_str().unwrap(),
        "--fps",
        "2",
        "--size",
        "64x36",
        "--out",
        out.to_str().unwrap(),
        "--frames",
        "27..30",
        "--ids",
        "--cpu",
        "--no-video",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("3 frames of 64x36"), "{}", stderr(&o));
    let (space, tour) = Tour::load(&tour_file).expect("the shipped tour loads");
    for k in 27..30u32 {
        let (scene, settings) = tour.scene_at(&space, f64::from(k) / 2.0, 64, 36);
        let want = render::<f64>(&space, &scene, &settings);
        let got = image::open(out.join(format!("frame_{k:05}.png")))
            .expect("frame")
            .to_rgb8();
        let ids = image::open(out.join(format!("ids_{k:05}.png")))
            .expect("ids")
            .to_rgba8();
        for (n, p) in want.pixels.iter().enumerate() {
            let (i, j) = (n as u32 % 64, n as u32 / 64);
            assert_eq!(ids.get_pixel(i, j).0, id_pixel(p), "frame {k} pixel ({i}, {j}): ids");
            let c = got.get_pixel(i, j).0;
            for ch in 0..3 {
                let d = (i16::from(c[ch]) - i16::from(srgb8(p.color[ch]))).abs();
                assert!(d <= 1, "frame {k} pixel ({i}, {j}): colour {c:?} vs {:?}", p.color);
            }
        }
    }
    // Frames follow the camera: the first and the last differ.
    let (a, b) = (
        std::fs::read(out.join("ids_00027.png")).unwrap(),
        std::fs::read(out.join("ids_00029.png")).unwrap(),
    );
    assert_ne!(a, b, "the camera moved");
    let vtt = std::fs::read_to_string(out.join("captions.vtt")).expect("captions");
    assert!(vtt.starts_with("WEBVTT") && vtt.contains("00:00:00.000 --> "), "{vtt}");
}

/// Every shipped tour checks, one to two minutes long; a broken one is
/// named by file and field on the command line.
fn tour_check_reads_the_shipped_tours_and_names_a_broken_field() {
    for name in [
        "torus",
        "seifert-weber",
        "poincare",
        "mirrored-cube",
        "mirrored-dodecahedron",
        "torus-flight",
    ] {
        let o = run(&["tour", "check", shipped_tour(name).to_str().unwrap()]);
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        let first = stdout(&o).lines().next().unwrap_or_default().to_owned();
        let secs: f64 = first
            .rsplit(", ")
            .next()
            .unwrap()
            .trim_end_matches(" s")
            .parse()
            .unwrap();
        assert!((60.0..=120.0).contains(&secs), "{name}: one to two minutes, {secs} s");
        assert!(stdout(&o).lines().count() > 5, "{name}: captions listed");
    }
    let broken = tmp("broken.tour.json");
    std::fs::write(
        &broken,
        r#"{"space": "torus", "keyframes": [{"time": 0, "position": [0, 0, 0, 1]}, {"time": 1, "position": [0.7, 0, 0, 1]}]}"#,
    )
    .unwrap();
    let o = run(&[
        "tour",
        "render",
        broken.to_str().unwrap(),
        "--out",
        tmp("never").to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    let err = stderr(&o);
    assert!(
        err.contains("broken.tour.json: keyframes[1].position: outside the fundamental domain"),
        "{err}"
    );
    assert!(!tmp("never").exists(), "nothing rendered");
}

/// `product --gpu` traces on the GPU (it says so) and draws the picture
/// the CPU draws: 99% of the pixels within 3/255 of the CPU's, in the
/// genus-2 space and in S2 x S1.
fn product_gpu_draws_what_the_cpu_draws() {
    for space in ["genus2xs1", "s2xs1"] {
        let (cpu, gpu) = (tmp(&format!("cpu_{space}.png")), tmp(&format!("gpu_{space}.png")));
        for (out, extra) in [(&cpu, None), (&gpu, Some("--gpu"))] {
            let mut args = vec!["product", "--space", space, "--width", "64", "--height", "36"];
            args.extend(extra);
            args.extend(["--out", out.to_str().expect("utf-8")]);
            let o = run(&args);
            assert!(o.status.success(), "{space}: {}", stderr(&o));
            let on = if extra.is_some() { "GPU" } else { "CPU" };
            assert!(stdout(&o).contains(&format!("traced on the {on}")), "{}", stdout(&o));
        }
        let (a, b) = (
            image::open(&cpu).expect("PNG").to_rgb8(),
            image::open(&gpu).expect("PNG").to_rgb8(),
        );
        let close = a
            .pixels()
            .zip(b.pixels())
            .filter(|(p, q)| (0..3).all(|c| p.0[c].abs_diff(q.0[c]) <= 3))
            .count();
        assert!(
            close * 100 >= 99 * 64 * 36,
            "{space}: {close} of {} pixels agree",
            64 * 36
        );
    }
}

bevy_manifold_test_support::test_main! {
    cpu: [
        tour_render_frame_k_is_the_camera_at_k_over_fps,
        tour_check_reads_the_shipped_tours_and_names_a_broken_field,
        help_prints_usage,
        product_renders_each_space_and_refuses_bad_numbers,
        space_list_prints_one_name_per_line,
        gen_files_import_show_and_render,
        render_refuses_sizes_and_levels_no_tracer_takes,
        render_mirror_adds_the_mirror_ball_and_one_reflection,
        render_path_trace_averages_path_samples,
        space_show_gives_the_invariants,
        export_then_load_the_file_by_path,
        a_broken_space_file_is_reported_with_its_name,
        render_writes_the_image_and_the_id_buffer,
        render_writes_linear_hdr,
        render_samples_average_the_accumulated_traces,
        render_cones_trace_cones,
        render_reports_a_bad_scene_field,
        space_cell_reads_ten_thousand_words_in_one_process,
    ],
    gpu: [
        render_defaults_to_the_gpu_and_matches_the_cpu_ids,
        product_gpu_draws_what_the_cpu_draws,
    ],
}
