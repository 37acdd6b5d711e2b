//! What the pass's tests share: an offscreen app, a view of a space's
//! default scene, the tracers' own traces of what it gathered, and the
//! measures the tests compare by.

use bevy::camera::RenderTarget;
use bevy::prelude::*;
use bevy::render::RenderApp;
use bevy_manifold::prelude::*;
use bevy_manifold::render::{ManifoldUploads, offscreen};
use bevy_manifold::space::Space;
use bevy_manifold_gpu::GpuTracer;
use bevy_manifold_test_support::compare::rgba8_agreement;

pub const W: u32 = 160;
pub const H: u32 = 120;

pub fn headless_app(with_manifold: bool) -> App {
    offscreen::app(with_manifold)
}

pub fn target(app: &mut App, w: u32, h: u32) -> Handle<Image> {
    offscreen::target(app, w, h)
}

pub fn wait_for_pipelines(app: &mut App) {
    offscreen::wait_for_pipelines(app).expect("pipelines");
}

pub fn capture(app: &mut App, target: &Handle<Image>) -> Vec<u8> {
    offscreen::capture(app, target).expect("capture")
}

pub fn uploads(app: &App) -> ManifoldUploads {
    *app.sub_app(RenderApp).world().resource::<ManifoldUploads>()
}

/// A space's root with the default scene of that space (with fog when
/// asked) and a manifold camera rendering into `image`; returns the root
/// and the camera.
pub fn spawn_view(app: &mut App, space: &Space, image: &Handle<Image>, fog: bool, cells: bool) -> (Entity, Entity) {
    let mut scene = Scene::default_for(space);
    if fog {
        scene.fog = Some(fog_of(space));
    }
    let camera = (
        ManifoldCamera { levels: 8, ..default() },
        if cells { CellShading::ByCell } else { CellShading::Off },
    );
    offscreen::spawn_view(app, space, &scene, image, camera)
}

pub fn fog_of(space: &Space) -> Fog {
    Fog {
        density: 0.4 / space.inradius(),
        color: [0.7, 0.75, 0.8],
    }
}

/// A still view of `scene` in `space` through a camera of `camera`'s
/// components, drawn offscreen at W x H until its pipelines are in and
/// ten frames more (an accumulating view's eight samples): what it shows,
/// and the scene the plugin gathered.
pub fn settled_view(space: &Space, scene: &Scene, camera: impl Bundle) -> (Vec<u8>, Scene) {
    let mut app = headless_app(true);
    let image = target(&mut app, W, H);
    let (root, _) = offscreen::spawn_view(&mut app, space, scene, &image, camera);
    wait_for_pipelines(&mut app);
    for _ in 0..10 {
        app.update();
    }
    let shown = capture(&mut app, &image);
    (shown, gathered_scene(&app, space, root, false))
}

/// The scene the app gathered for `root`, with the camera and fog the test
/// gave it: what the CPU reference traces.
pub fn gathered_scene(app: &App, space: &Space, root: Entity, fog: bool) -> Scene {
    let mut scene = app
        .world()
        .get::<ManifoldScene>(root)
        .expect("gathered")
        .scene()
        .clone();
    scene.camera = Scene::default_for(space).camera;
    if fog {
        scene.fog = Some(fog_of(space));
    }
    scene
}

/// A new view of the default scene of `space` into `image` (with fog and
/// per-cell shading as asked): its root, what the pass shows, and the
/// scene the app gathered, which the tracers trace.
pub fn shown_default_scene(
    app: &mut App,
    space: &Space,
    image: &Handle<Image>,
    (fog, cells): (bool, bool),
) -> (Entity, Vec<u8>, Scene) {
    let (root, _) = spawn_view(app, space, image, fog, cells);
    wait_for_pipelines(app);
    let shown = capture(app, image);
    let scene = gathered_scene(app, space, root, fog);
    (root, shown, scene)
}

/// The pixels of an RGBA8 image brighter than 8 in some channel.
pub fn lit_pixels(shown: &[u8]) -> usize {
    shown
        .chunks_exact(4)
        .filter(|p| p[0] > 8 || p[1] > 8 || p[2] > 8)
        .count()
}

/// The views' size at 8 levels, as the tracers take it.
pub fn view_settings() -> TraceSettings {
    TraceSettings {
        width: W,
        height: H,
        levels: 8,
        ..TraceSettings::default()
    }
}

/// The headless compute trace of `scene` at [`view_settings`].
pub fn headless_trace(space: &Space, scene: &Scene) -> bevy_manifold::trace::TraceImage {
    GpuTracer::new()
        .expect("adapter")
        .render(space, scene, &view_settings())
        .expect("headless trace")
}

/// What the pass showed (`shown`) of a scene with a ball and two meshes
/// (object ids 2 and 3) against the headless compute trace (within 1/255)
/// and the CPU f64 reference (within 2/255), at 8 levels: the meshes'
/// pixel count on the CPU and the two agreements.
pub fn mesh_agreement(space: &Space, scene: &Scene, shown: &[u8]) -> (usize, f64, f64) {
    let compute = headless_trace(space, scene);
    let cpu = render::<f64>(space, scene, &view_settings());
    let mesh_pixels = cpu.pixels.iter().filter(|p| (2..=3).contains(&p.object)).count();
    (
        mesh_pixels,
        rgba8_agreement(shown, &compute, 1),
        rgba8_agreement(shown, &cpu, 2),
    )
}

/// A posed mesh (`what`) drawn by the pass in `root`'s view into `image`
/// as the headless tracer and the CPU f64 reference draw the gathered
/// scene (at least 99.5% and 99% of the pixels), in view (over 100
/// pixels), and seen by the CPU trace in at least three copies of the
/// domain.
pub fn assert_drawn_in_copies(app: &mut App, space: &Space, root: Entity, image: &Handle<Image>, what: &str) {
    wait_for_pipelines(app);
    let shown = capture(app, image);
    let scene = gathered_scene(app, space, root, false);
    let (mesh_pixels, vs_compute, vs_cpu) = mesh_agreement(space, &scene, &shown);
    eprintln!(
        "{what}: {mesh_pixels} mesh pixels; pass vs compute {:.3}%, vs CPU f64 {:.3}%",
        vs_compute * 100.0,
        vs_cpu * 100.0
    );
    assert!(mesh_pixels > 100, "{what} is in view");
    assert!(vs_compute >= 0.995 && vs_cpu >= 0.99);
    let cpu = render::<f64>(space, &scene, &view_settings());
    let mut cells: Vec<_> = cpu
        .pixels
        .iter()
        .filter(|p| (2..=3).contains(&p.object))
        .map(|p| p.cell)
        .collect();
    cells.sort();
    cells.dedup();
    assert!(cells.len() >= 3, "{what} is seen in {} copies", cells.len());
}

/// The fraction of `shown` (RGBA8, sRGB) within `tol` of linear `colors`.
pub fn close_to(shown: &[u8], colors: &[[f32; 3]], tol: u8) -> f64 {
    let close = shown
        .chunks_exact(4)
        .zip(colors)
        .filter(|(px, c)| (0..3).all(|k| px[k].abs_diff(bevy_manifold::trace::srgb8(c[k])) <= tol))
        .count();
    close as f64 / colors.len() as f64
}

/// PSNR (dB) of an RGBA8 sRGB image against linear reference colours,
/// both compared as sRGB bytes.
pub fn psnr(shown: &[u8], reference: &[[f32; 3]]) -> f64 {
    let mut sq = 0.0;
    for (px, c) in shown.chunks_exact(4).zip(reference) {
        for k in 0..3 {
            let d = f64::from(px[k]) - f64::from(bevy_manifold::trace::srgb8(c[k]));
            sq += d * d;
        }
    }
    let rmse = (sq / (3 * reference.len()) as f64).sqrt() / 255.0;
    -20.0 * rmse.log10()
}

/// A 16-samples-per-pixel reference: the CPU f64 trace at 4x the size,
/// each pixel the mean of its 4x4 block (a box filter over the pixel).
pub fn supersampled(space: &Space, scene: &Scene, levels: u32) -> Vec<[f32; 3]> {
    let settings = TraceSettings {
        width: W,
        height: H,
        levels,
        ..TraceSettings::default()
    };
    bevy_manifold_test_support::compare::supersampled(space, scene, &settings, 4)
}

/// Linear colours as the RGBA8 sRGB bytes a target stores.
pub fn plain_bytes(colors: &[[f32; 3]]) -> Vec<u8> {
    colors
        .iter()
        .flat_map(|c| {
            let [r, g, b] = c.map(bevy_manifold::trace::srgb8);
            [r, g, b, 255]
        })
        .collect()
}

/// A plain Bevy scene: a lit cube seen by an ordinary `Camera3d`.
pub fn plain_scene(app: &mut App, image: &Handle<Image>) {
    let world = app.world_mut();
    let mesh = world.resource_mut::<Assets<Mesh>>().add(Cuboid::new(1.0, 1.0, 1.0));
    let material = world
        .resource_mut::<Assets<StandardMaterial>>()
        .add(Color::srgb(0.8, 0.5, 0.3));
    world.spawn((Mesh3d(mesh), MeshMaterial3d(material)));
    world.spawn((
        DirectionalLight::default(),
        Transform::from_xyz(1.0, 2.0, 3.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    world.spawn((
        Camera3d::default(),
        RenderTarget::Image(image.clone().into()),
        Transform::from_xyz(2.0, 1.5, 3.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
}

/// Balls in `space` at `n` points inside its domain (seeded), each a
/// tenth of the inradius, as entities under `root`; the scene's balls.
pub fn spawn_balls(app: &mut App, space: &Space, root: Entity, n: usize, seed: u64) -> Vec<Entity> {
    let mut rng = bevy_manifold_test_support::Rng(seed);
    let g = space.geometry();
    (0..n)
        .map(|k| {
            let centre = rng.ray_inside(space).origin;
            let hue = k as f32 / n as f32;
            app.world_mut()
                .spawn((
                    ChildOf(root),
                    Placement::from_isometry(bevy_manifold::geometry::isometry::translation_to(g, centre)),
                    TracedBall::new(
                        0.1 * space.inradius(),
                        Color::linear_rgb(1.0 - hue, 0.3 + 0.6 * hue, 0.4),
                    ),
                ))
                .id()
        })
        .collect()
}

/// An f16's value (IEEE 754 half precision).
pub fn f16_value(bits: u16) -> f32 {
    let sign = if bits & 0x8000 != 0 { -1.0 } else { 1.0 };
    let exp = i32::from((bits >> 10) & 0x1f);
    let frac = f32::from(bits & 0x3ff);
    sign * match exp {
        0 => frac * 2f32.powi(-24),
        31 => f32::INFINITY,
        _ => (1.0 + frac / 1024.0) * 2f32.powi(exp - 15),
    }
}

/// A W x H `Rgba16Float` target, readable back: what an `Hdr` manifold
/// camera writes linear radiance into.
pub fn hdr_target(app: &mut App) -> Handle<Image> {
    use bevy::render::render_resource::{TextureFormat, TextureUsages};
    let mut images = app.world_mut().resource_mut::<Assets<Image>>();
    let mut image = Image::new_target_texture(W, H, TextureFormat::Rgba16Float, None);
    image.texture_descriptor.usage |= TextureUsages::COPY_SRC;
    images.add(image)
}

/// The linear RGB of pixel `i` (row-major) of an [`hdr_target`]'s
/// [`capture`] (8 bytes a pixel).
pub fn hdr_pixel(bytes: &[u8], i: usize) -> [f32; 3] {
    let k = i * 8;
    [0, 1, 2].map(|c| f16_value(u16::from_le_bytes([bytes[k + 2 * c], bytes[k + 2 * c + 1]])))
}
