//! The soak run (`bevy_manifold soak`): the explorer, in its window, left
//! running for a long time (an hour by default) on a script that flies the
//! camera along a turning path, visits every catalog and library space in
//! turn, switches every setting the panel has, and loads and drops glTF
//! meshes through Bevy's asset server. Every few seconds it records the
//! process's resident memory and the GPU objects alive on the device
//! (wgpu's counters), as a CSV and a line on standard output, and ends with
//! the start, end and peak of each. Not part of CI: it is how a leak that
//! a short test cannot see would show.
//!
//! ```no_run
//! use bevy_manifold_app::explorer::soak::{SoakOptions, run_soak};
//! use std::time::Duration;
//! let options = SoakOptions {
//!     duration: Duration::from_secs(600),
//!     ..SoakOptions::default()
//! };
//! let exit = run_soak(&options);
//! ```

use super::settings::{CellMode, ExplorerSettings, MAX_LEVEL};
use super::view::{ExplorerCamera, ExplorerStatus, ExplorerWorld};
use bevy::prelude::*;
use bevy::render::renderer::RenderDevice;
use bevy_manifold::camera::fly_camera_input;
use bevy_manifold::placement::{GeodesicVelocity, ManifoldSystems, Placement};
use bevy_manifold::space::{catalog, library};
use bevy_manifold::trace::SuzanneMode;
use std::io::Write as _;
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// What a soak run does and for how long.
#[derive(Clone, Debug)]
pub struct SoakOptions {
    /// How long it runs.
    pub duration: Duration,
    /// How long each step of the script lasts (one space, one set of
    /// settings, one mesh).
    pub phase: Duration,
    /// How often memory and GPU objects are recorded.
    pub sample: Duration,
    /// The CSV written (one row per sample).
    pub out: PathBuf,
    /// The folder the glTF files are loaded from (Bevy's asset root).
    pub assets: PathBuf,
    /// The glTF files loaded and dropped in turn, relative to `assets`.
    pub meshes: Vec<String>,
}

impl Default for SoakOptions {
    fn default() -> Self {
        SoakOptions {
            duration: Duration::from_secs(3600),
            phase: Duration::from_secs(15),
            sample: Duration::from_secs(10),
            out: PathBuf::from("soak.csv"),
            assets: PathBuf::from("assets"),
            meshes: vec![
                "models/suzanne.glb".into(),
                "models/left.glb".into(),
                "models/right.glb".into(),
            ],
        }
    }
}

/// One record of a soak run.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SoakSample {
    /// Seconds since the start.
    pub secs: f64,
    /// Frames so far.
    pub frames: u64,
    /// Mean frame time over the explorer's history, in milliseconds.
    pub frame_ms: f32,
    /// Resident memory, in MiB (0 where `/proc/self/statm` is not there).
    pub rss_mib: f64,
    /// Live GPU objects, as [`live_gpu_objects`] counts them, in
    /// [`GPU_COUNTERS`]' order.
    pub gpu: [isize; GPU_COUNTERS.len()],
    /// Bevy's image and mesh assets alive in the main world.
    pub assets: [usize; 2],
    /// Space switches so far.
    pub switches: u64,
}

/// The CSV header, matching [`SoakSample::csv`].
pub const CSV_HEADER: &str = "secs,frames,frame_ms,rss_mib,buffers,texture_views,texture_kib,bind_groups,render_pipelines,compute_pipelines,shader_modules,images,meshes,switches";

/// What [`live_gpu_objects`] counts, in order.
///
/// Textures are counted by the memory they hold (KiB), not by number:
/// wgpu-hal 29's Vulkan backend takes one off its texture count for each
/// texture it destroys but adds one only for those handed to it from
/// outside (`create_texture_from_hal`), not for those it creates, so that
/// count runs below zero and says nothing. Its texture memory is added on
/// creation and taken off on destruction, so a leaked texture shows there
/// (a window's swapchain images are not in it).
pub const GPU_COUNTERS: [&str; 7] = [
    "buffers",
    "texture views",
    "texture KiB",
    "bind groups",
    "render pipelines",
    "compute pipelines",
    "shader modules",
];

impl SoakSample {
    /// The sample as a CSV row.
    #[must_use]
    pub fn csv(&self) -> String {
        let gpu: Vec<String> = self.gpu.iter().map(ToString::to_string).collect();
        format!(
            "{:.1},{},{:.1},{:.1},{},{},{},{}",
            self.secs,
            self.frames,
            self.frame_ms,
            self.rss_mib,
            gpu.join(","),
            self.assets[0],
            self.assets[1],
            self.switches
        )
    }
}

/// Start, end and peak of each recorded quantity, as the closing lines of
/// a soak run print them.
#[must_use]
pub fn summary(samples: &[SoakSample]) -> String {
    let (Some(first), Some(last)) = (samples.first(), samples.last()) else {
        return "no samples".into();
    };
    let peak_rss = samples.iter().map(|s| s.rss_mib).fold(0.0, f64::max);
    let mut out = format!(
        "soak: {:.0} s, {} frames, {} space switches\nresident memory MiB: start {:.1}, end {:.1}, peak {:.1}\n",
        last.secs, last.frames, last.switches, first.rss_mib, last.rss_mib, peak_rss
    );
    for (k, name) in GPU_COUNTERS.iter().enumerate() {
        let peak = samples.iter().map(|s| s.gpu[k]).max().unwrap_or(0);
        out.push_str(&format!(
            "{name}: start {}, end {}, peak {peak}\n",
            first.gpu[k], last.gpu[k]
        ));
    }
    for (k, name) in ["image assets", "mesh assets"].iter().enumerate() {
        let peak = samples.iter().map(|s| s.assets[k]).max().unwrap_or(0);
        out.push_str(&format!(
            "{name}: start {}, end {}, peak {peak}\n",
            first.assets[k], last.assets[k]
        ));
    }
    out
}

/// Resident memory of this process in MiB, from `/proc/self/statm` (Linux);
/// 0 elsewhere.
#[must_use]
pub fn resident_mib() -> f64 {
    let Ok(statm) = std::fs::read_to_string("/proc/self/statm") else {
        return 0.0;
    };
    let pages: f64 = statm
        .split_whitespace()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(0.0);
    // The page size of every Linux target Bevy runs on.
    pages * 4096.0 / (1024.0 * 1024.0)
}

/// Live GPU objects on `device` (wgpu's `counters`), in [`GPU_COUNTERS`]'
/// order.
#[must_use]
pub fn live_gpu_objects(device: &RenderDevice) -> [isize; GPU_COUNTERS.len()] {
    let c = device.wgpu_device().get_internal_counters();
    [
        c.hal.buffers.read(),
        c.hal.texture_views.read(),
        c.hal.texture_memory.read() / 1024,
        c.hal.bind_groups.read(),
        c.hal.render_pipelines.read(),
        c.hal.compute_pipelines.read(),
        c.hal.shader_modules.read(),
    ]
}

/// The spaces a soak run visits: the catalog, then the library.
#[must_use]
pub fn soak_spaces() -> Vec<String> {
    let mut names: Vec<String> = catalog::NAMES.iter().map(|n| (*n).to_string()).collect();
    names.extend(library::names());
    names
}

/// The settings of script step `k`: the space `spaces[k mod n]`, and every
/// setting the panel has cycled with a different period so that, over a
/// run, each space meets each combination.
#[must_use]
pub fn step_settings(base: &ExplorerSettings, spaces: &[String], k: u64) -> ExplorerSettings {
    let pick = |n: u64| usize::try_from(k % n).unwrap_or(0);
    let mut s = base.clone();
    if !spaces.is_empty() {
        s.space = spaces[pick(spaces.len() as u64)].clone();
    }
    s.levels = 2 + (k % u64::from(MAX_LEVEL.min(6) - 1)) as u32;
    s.fog = k % 2 == 1;
    s.cells = !k.is_multiple_of(3);
    s.cell_mode = CellMode::ALL[pick(3)];
    s.highlight = k;
    s.edges = k % 4 != 2;
    s.suzanne = [SuzanneMode::Attached, SuzanneMode::Free, SuzanneMode::Hidden][pick(3)];
    s.mirror = k % 3 == 2;
    s.reflections = [0, 1, 2][pick(3)];
    s.path_trace = k % 7 == 3;
    s.render_scale = [0.25, 0.35, 0.5][pick(3)];
    s.hold_frame_rate = k % 4 == 3;
    s.target_fps = [10.0, 30.0, 90.0][pick(3)];
    s.refine_still = k % 3 != 1;
    s.still_samples = [4, 16, 64][pick(3)];
    s.smooth_detail = k % 5 != 1;
    s.panel = k % 5 != 4;
    s
}

/// The soak script and its records.
#[derive(Resource)]
struct Soak {
    options: SoakOptions,
    spaces: Vec<String>,
    base: ExplorerSettings,
    start: Instant,
    step: u64,
    next_step: Instant,
    mesh_due: Option<Instant>,
    next_sample: Instant,
    frames: u64,
    mesh: Option<Entity>,
    samples: Vec<SoakSample>,
    csv: Option<std::fs::File>,
}

/// Adds the soak script to an explorer app.
pub struct SoakPlugin(pub SoakOptions);

impl Plugin for SoakPlugin {
    fn build(&self, app: &mut App) {
        let now = Instant::now();
        let csv = match std::fs::File::create(&self.0.out) {
            Ok(mut f) => {
                let _ = writeln!(f, "{CSV_HEADER}");
                Some(f)
            }
            Err(e) => {
                eprintln!("warning: {}: {e}; samples only printed", self.0.out.display());
                None
            }
        };
        app.insert_resource(Soak {
            options: self.0.clone(),
            spaces: soak_spaces(),
            base: ExplorerSettings {
                levels: 3,
                ..ExplorerSettings::default()
            },
            start: now,
            step: 0,
            next_step: now,
            mesh_due: None,
            next_sample: now + self.0.sample,
            frames: 0,
            mesh: None,
            samples: Vec::new(),
            csv,
        })
        .add_systems(Update, script)
        .add_systems(
            PostUpdate,
            fly.after(fly_camera_input).before(ManifoldSystems::Integrate),
        )
        .add_systems(Last, record);
    }
}

/// Advances the script: a new step's settings, and half a step later (once
/// the world of a new space stands) a new mesh in place of the last.
fn script(
    mut commands: Commands,
    mut soak: ResMut<Soak>,
    mut settings: ResMut<ExplorerSettings>,
    world: Option<Res<ExplorerWorld>>,
    assets: Res<AssetServer>,
) {
    let now = Instant::now();
    if now >= soak.next_step {
        let step = soak.step;
        *settings = step_settings(&soak.base, &soak.spaces, step);
        soak.step += 1;
        soak.next_step = now + soak.options.phase;
        soak.mesh_due = Some(now + soak.options.phase / 2);
    }
    if soak.mesh_due.is_some_and(|d| now >= d)
        && let Some(world) = world
    {
        soak.mesh_due = None;
        if let Some(old) = soak.mesh.take() {
            commands.entity(old).try_despawn();
        }
        let files = &soak.options.meshes;
        if !files.is_empty() {
            let file = &files[usize::try_from(soak.step).unwrap_or(0) % files.len()];
            let r = world.space.inradius();
            let mesh: Handle<Mesh> = assets.load(format!("{file}#Mesh0/Primitive0"));
            let id = commands
                .spawn((
                    ChildOf(world.root),
                    Mesh3d(mesh),
                    Placement::at(&world.space, glam::DVec3::new(0.2, -0.1, -0.3) * r),
                    Transform::from_scale(Vec3::splat((0.2 * r) as f32)),
                ))
                .id();
            soak.mesh = Some(id);
        }
    }
}

/// Flies the camera along a path that turns a little differently every
/// moment, a third of the domain's circumradius a second.
fn fly(
    soak: Res<Soak>,
    world: Option<Res<ExplorerWorld>>,
    mut cameras: Query<&mut GeodesicVelocity, With<ExplorerCamera>>,
) {
    let Some(world) = world else { return };
    let t = soak.start.elapsed().as_secs_f64();
    let speed = world.space.circumradius() / 3.0;
    for mut v in &mut cameras {
        v.linear = glam::DVec3::new(0.2 * (0.3 * t).sin(), 0.1, -1.0) * speed;
        v.angular = glam::DVec3::new(0.25 * (0.21 * t).sin(), 0.3 * (0.13 * t).cos(), 0.1);
    }
}

/// Records a sample when one is due, and ends the run when its time is up.
fn record(
    mut soak: ResMut<Soak>,
    status: Res<ExplorerStatus>,
    device: Option<Res<RenderDevice>>,
    images: Res<Assets<Image>>,
    meshes: Res<Assets<Mesh>>,
    mut exit: MessageWriter<AppExit>,
) {
    soak.frames += 1;
    let now = Instant::now();
    let done = soak.start.elapsed() >= soak.options.duration;
    if now < soak.next_sample && !done {
        return;
    }
    soak.next_sample = now + soak.options.sample;
    let sample = SoakSample {
        secs: soak.start.elapsed().as_secs_f64(),
        frames: soak.frames,
        frame_ms: status.mean_frame_ms().unwrap_or(f32::NAN),
        rss_mib: resident_mib(),
        gpu: device.map_or([0; GPU_COUNTERS.len()], |d| live_gpu_objects(&d)),
        assets: [images.len(), meshes.len()],
        switches: status.switches,
    };
    println!("soak {}", sample.csv());
    if let Some(f) = soak.csv.as_mut() {
        let _ = writeln!(f, "{}", sample.csv());
    }
    soak.samples.push(sample);
    if done {
        print!("{}", summary(&soak.samples));
        println!("samples written to {}", soak.options.out.display());
        exit.write(AppExit::Success);
    }
}

/// `Ok` when every one of `meshes` is a file under `assets`; otherwise
/// the first that is not, with the folder looked in: a soak that loaded
/// no mesh would measure nothing of what meshes hold, and Bevy only logs
/// a missing asset and goes on.
pub fn check_meshes(assets: &std::path::Path, meshes: &[String]) -> Result<(), String> {
    match meshes.iter().find(|m| !assets.join(m).is_file()) {
        None => Ok(()),
        Some(m) => Err(format!(
            "soak: the mesh {m} is not in {} (--assets names the folder that holds models/)",
            assets.display()
        )),
    }
}

/// Runs the explorer in its window under the soak script (settings are
/// not saved). Without a display or a GPU adapter it says so and exits
/// with an error: a soak needs the real thing.
pub fn run_soak(options: &SoakOptions) -> AppExit {
    if let Err(why) = super::fallback::window_adapter() {
        eprintln!("error: a soak run needs a display and a GPU adapter: {why}");
        return AppExit::error();
    }
    let assets = std::path::absolute(&options.assets).unwrap_or_else(|_| options.assets.clone());
    if let Err(why) = check_meshes(&assets, &options.meshes) {
        eprintln!("error: {why}");
        return AppExit::error();
    }
    println!(
        "soak: {} s, a step every {} s, a sample every {} s, meshes from {}; writing {}",
        options.duration.as_secs(),
        options.phase.as_secs(),
        options.sample.as_secs(),
        assets.display(),
        options.out.display()
    );
    println!("soak {CSV_HEADER}");
    let mut app = super::window_app(
        ExplorerSettings::default(),
        None,
        Some(assets.to_string_lossy().into_owned()),
    );
    app.add_plugins(SoakPlugin(options.clone()));
    app.run()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_soak_names_a_mesh_its_asset_folder_lacks() {
        let meshes = SoakOptions::default().meshes;
        let repo_assets = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets");
        assert_eq!(check_meshes(&repo_assets, &meshes), Ok(()));
        let empty = std::env::temp_dir().join(format!("bevy_manifold_soak_{}", std::process::id()));
        std::fs::create_dir_all(&empty).unwrap();
        let why = check_meshes(&empty, &meshes).unwrap_err();
        assert!(why.contains("models/suzanne.glb"), "{why}");
        assert!(why.contains(&empty.display().to_string()), "{why}");
        // A folder, not a file, by the mesh's name is not a mesh either.
        std::fs::create_dir_all(empty.join("models/suzanne.glb")).unwrap();
        let why = check_meshes(&empty, &meshes).unwrap_err();
        assert!(why.contains("models/suzanne.glb"), "{why}");
        std::fs::remove_dir_all(&empty).unwrap();
    }

    #[test]
    fn the_script_visits_every_space_with_every_cell_mode_in_range() {
        let spaces = soak_spaces();
        assert!(spaces.len() > catalog::NAMES.len(), "the library is visited too");
        let base = ExplorerSettings::default();
        let steps: Vec<ExplorerSettings> = (0..3 * spaces.len() as u64)
            .map(|k| step_settings(&base, &spaces, k))
            .collect();
        for name in &spaces {
            let modes: Vec<CellMode> = steps.iter().filter(|s| &s.space == name).map(|s| s.cell_mode).collect();
            assert_eq!(modes.len(), 3, "{name}");
        }
        for s in &steps {
            assert!((2..=MAX_LEVEL).contains(&s.levels), "{}", s.levels);
            assert!(s.render_scale > 0.0 && s.render_scale <= 1.0);
        }
        // Consecutive steps differ in the space and in some setting.
        assert!(
            steps
                .windows(2)
                .all(|w| w[0].space != w[1].space && w[0].fog != w[1].fog)
        );
    }

    #[test]
    fn the_summary_gives_start_end_and_peak() {
        let at = |secs: f64, rss: f64, buffers: isize| SoakSample {
            secs,
            rss_mib: rss,
            gpu: [buffers, 0, 0, 0, 0, 0, 0],
            ..SoakSample::default()
        };
        let text = summary(&[at(0.0, 100.0, 7), at(10.0, 250.5, 40), at(20.0, 180.0, 9)]);
        assert!(text.contains("start 100.0, end 180.0, peak 250.5"), "{text}");
        assert!(text.contains("buffers: start 7, end 9, peak 40"), "{text}");
        assert_eq!(at(1.0, 2.0, 3).csv(), "1.0,0,0.0,2.0,3,0,0,0,0,0,0,0,0,0");
    }
}
