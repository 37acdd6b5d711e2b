//! `explore --xr` against a real OpenXR runtime: Monado with its null
//! compositor and a simulated headset, on lavapipe, in the Debian trixie
//! root `.ci/run` builds (`BEVY_MANIFOLD_XR_ROOT`; see
//! `../shared/openxr-headless.md`). The binary runs inside that root
//! (Monado's client library needs its newer glibc). Without the root the
//! runtime test is ignored, and fails under CI; the fallback test runs
//! everywhere.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

fn binary() -> PathBuf {
    PathBuf::from(env!("CARGO_BIN_EXE_bevy_manifold"))
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("bevy_manifold_xr_{}_{name}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("scratch dir");
    dir
}

/// With no OpenXR runtime (this machine has no loader, or none answers)
/// and no display, `explore --xr` says so in one line, renders the
/// desktop view to `explorer.png` as plain `explore` does, and exits 0.
fn without_a_runtime_the_xr_explorer_stays_on_the_desktop() {
    let dir = scratch("fallback");
    let out = Command::new(binary())
        .args(["explore", "--xr", "--frames", "3"])
        .current_dir(&dir)
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        // A runtime manifest that does not exist: the loader finds none.
        .env("XR_RUNTIME_JSON", dir.join("no-such-runtime.json"))
        .env("BEVY_MANIFOLD_CONFIG_DIR", dir.join("config"))
        .output()
        .expect("the binary runs");
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.status.success(), "exit {:?}:\n{text}", out.status);
    assert!(text.contains("no OpenXR runtime"), "{text}");
    assert!(!text.contains("panicked"), "{text}");
    let png = std::fs::read(dir.join("explorer.png")).expect("explorer.png written");
    assert_eq!(&png[1..4], b"PNG");
}

/// The trixie root with Monado, from `BEVY_MANIFOLD_XR_ROOT`.
fn xr_root() -> Result<String, String> {
    let root = std::env::var("BEVY_MANIFOLD_XR_ROOT").map_err(|_| "BEVY_MANIFOLD_XR_ROOT is not set".to_string())?;
    let service = Path::new(&root).join("usr/bin/monado-service");
    if !service.exists() {
        return Err(format!("{} is missing", service.display()));
    }
    Ok(root)
}

/// Monado, running in the root until dropped.
struct Monado {
    child: Child,
    log: PathBuf,
}

impl Monado {
    fn start(root: &Path) -> Monado {
        let xdg = root.join("tmp/xdg");
        let _ = std::fs::remove_dir_all(&xdg);
        std::fs::create_dir_all(&xdg).expect("runtime dir");
        std::fs::set_permissions(&xdg, std::os::unix::fs::PermissionsExt::from_mode(0o700)).expect("chmod");
        let log = root.join("tmp/monado.log");
        let file = std::fs::File::create(&log).expect("log");
        let child = Command::new("setpriv")
            .args(["--bounding-set", "-sys_nice", "--inh-caps", "-sys_nice", "chroot"])
            .arg(root)
            .args([
                "env",
                "HOME=/root",
                "XDG_RUNTIME_DIR=/tmp/xdg",
                "XRT_COMPOSITOR_NULL=1",
                "SIMULATED_ENABLE=1",
                "XRT_NO_STDIN=1",
                "IPC_EXIT_ON_DISCONNECT=1",
                "monado-service",
            ])
            .stdin(Stdio::null())
            .stdout(file.try_clone().expect("log"))
            .stderr(file)
            .spawn()
            .expect("monado-service starts");
        let monado = Monado { child, log };
        let start = Instant::now();
        while !monado.log_text().contains("The Monado service has started") {
            assert!(
                start.elapsed() < Duration::from_secs(30),
                "Monado did not start:\n{}",
                monado.log_text()
            );
            std::thread::sleep(Duration::from_millis(100));
        }
        monado
    }

    fn log_text(&self) -> String {
        std::fs::read_to_string(&self.log).unwrap_or_default()
    }
}

impl Drop for Monado {
    fn drop(&mut self) {
        // It exits by itself once the client disconnects; wait a little.
        for _ in 0..50 {
            if matches!(self.child.try_wait(), Ok(Some(_))) {
                return;
            }
            std::thread::sleep(Duration::from_millis(100));
        }
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// The explorer in Monado's simulated headset, in its first space (the
/// paper's scene) and in a product space (the genus-2 surface times a
/// circle, whose eyes are traced by the product pass): the session goes
/// IDLE -> READY -> SYNCHRONIZED -> VISIBLE -> FOCUSED, 60 frames are
/// traced with both eyes, the app exits 0 and the session ends; no wgpu
/// validation error on the way.
fn the_xr_explorer_reaches_focused_and_traces_both_eyes_under_monado() {
    let root = PathBuf::from(xr_root().expect("the XR root"));
    for space in [None, Some("genus2xs1")] {
        explore_under_monado(&root, space);
    }
}

/// One run of [`the_xr_explorer_reaches_focused_and_traces_both_eyes_under_monado`],
/// in `space` (`None`: the explorer's first).
fn explore_under_monado(root: &Path, space: Option<&str>) {
    let name = space.unwrap_or("the first space");
    let bin_dir = root.join("opt/bevy_manifold");
    std::fs::create_dir_all(&bin_dir).expect("bin dir");
    std::fs::copy(binary(), bin_dir.join("bevy_manifold")).expect("binary copied in");
    for i in 0..2 {
        let _ = std::fs::remove_file(root.join(format!("tmp/eyes/eye{i}.png")));
    }
    let monado = Monado::start(root);
    let start = Instant::now();
    let space_args = space.map(|s| ["--space", s]);
    let out = Command::new("chroot")
        .arg(root)
        .args([
            "env",
            "HOME=/root",
            "XDG_RUNTIME_DIR=/tmp/xdg",
            "XR_RUNTIME_JSON=/usr/share/openxr/1/openxr_monado.json",
            "BEVY_MANIFOLD_CONFIG_DIR=/tmp/bevy_manifold_config",
            "RUST_LOG=warn,bevy_mod_openxr=info,wgpu_core=error,wgpu_hal=error",
            "timeout",
            "400",
            "/opt/bevy_manifold/bevy_manifold",
            "explore",
            "--xr",
            "--frames",
            "60",
            "--xr-capture",
            "/tmp/eyes",
        ])
        .args(space_args.iter().flatten())
        .output()
        .expect("the client runs");
    let secs = start.elapsed().as_secs_f64();
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    drop(monado);
    let all = format!("stdout:\n{stdout}\nstderr:\n{stderr}");
    eprintln!("{all}");
    assert!(out.status.success(), "{name}: exit {:?} after {secs:.1} s", out.status);
    let states: Vec<&str> = stdout
        .lines()
        .filter_map(|l| l.strip_prefix("xr: session state "))
        .collect();
    let wanted = ["IDLE", "READY", "SYNCHRONIZED", "VISIBLE", "FOCUSED"];
    let mut at = 0;
    for s in &states {
        if at < wanted.len() && *s == wanted[at] {
            at += 1;
        }
    }
    assert_eq!(at, wanted.len(), "{name}: states seen: {states:?}");
    let traced: u64 = stdout
        .lines()
        .find_map(|l| l.strip_prefix("xr: focused true, "))
        .and_then(|l| l.split_whitespace().next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no summary line:\n{all}"));
    assert!(traced >= 60, "{name}: {traced} frames with both eyes traced");
    assert!(!all.contains("Validation Error"), "{name}: a wgpu validation error");
    assert!(!all.contains("panicked"), "{name}: a panic");
    // Each eye's image, read back from its view target: a real picture
    // (many colours, not all black), and
    // the two differ by a horizontal shift (parallax), not by noise.
    let eyes = [0, 1].map(|i| {
        let path = root.join(format!("tmp/eyes/eye{i}.png"));
        image::open(&path)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
            .to_rgba8()
    });
    for (i, eye) in eyes.iter().enumerate() {
        let colours: std::collections::HashSet<[u8; 4]> = eye.pixels().map(|p| p.0).collect();
        let dark = eye.pixels().filter(|p| p.0[..3].iter().all(|&c| c < 8)).count();
        eprintln!(
            "xr: {name}: eye {i}: {}x{}, {} colours, {:.1}% black",
            eye.width(),
            eye.height(),
            colours.len(),
            100.0 * dark as f64 / f64::from(eye.width() * eye.height())
        );
        assert!(colours.len() > 200, "{name}: eye {i}: {} colours", colours.len());
        // The torus's space between the tubes is dark, about half the
        // picture, the product space's fog pale; a blank or failed eye
        // would be all black.
        assert!(
            dark * 10 < 9 * (eye.width() * eye.height()) as usize,
            "{name}: eye {i}: black"
        );
    }
    let (shift, at_shift, at_zero) = best_shift(&eyes[0], &eyes[1]);
    eprintln!(
        "xr: {name}: the right eye's image matches the left's best shifted {shift} px (mean difference {at_shift:.2}, unshifted {at_zero:.2})"
    );
    assert!(at_zero > 1.0, "{name}: the two eyes see the same picture");
    assert!(at_shift < at_zero, "{name}: no shift explains the eyes' difference");
    eprintln!("xr: {name}: {traced} frames with both eyes in {secs:.1} s under Monado (states {states:?})");
}

/// The horizontal shift (right image against left, -40 to 40 px) that
/// makes the two eyes' images most alike, with the mean absolute channel
/// difference there and unshifted, over the columns both cover.
fn best_shift(left: &image::RgbaImage, right: &image::RgbaImage) -> (i32, f64, f64) {
    let (w, h) = (left.width() as i32, left.height() as i32);
    let diff = |s: i32| {
        let (mut sum, mut n) = (0.0, 0.0);
        for y in 0..h {
            for x in 40..w - 40 {
                let a = left.get_pixel(x as u32, y as u32).0;
                let b = right.get_pixel((x + s) as u32, y as u32).0;
                sum += (0..3).map(|c| f64::from(a[c].abs_diff(b[c]))).sum::<f64>();
                n += 3.0;
            }
        }
        sum / n
    };
    let (shift, best) = (-40..=40)
        .map(|s| (s, diff(s)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .expect("shifts");
    (shift, best, diff(0))
}

bevy_manifold_test_support::test_main_requiring! {
    cpu: [without_a_runtime_the_xr_explorer_stays_on_the_desktop],
    requiring("OpenXR runtime root (Monado)", xr_root()): [
        the_xr_explorer_reaches_focused_and_traces_both_eyes_under_monado,
    ],
}
