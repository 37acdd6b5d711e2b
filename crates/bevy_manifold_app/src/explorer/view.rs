//! The explorer's world and view: the space root, the camera and the
//! paper's scene spawned from the [`ExplorerSettings`], re-spawned when the
//! space or the scene changes (the one code path the panel, the keys and
//! the tests use), the camera's components kept in step with the settings,
//! and the offscreen image the camera renders into at the render scale.
//! A product space (H2xR, S2xR) is shown by a `ProductCamera` among its
//! balls and lights instead ([`spawn_product_world`]).

use super::settings::ExplorerSettings;
use bevy::camera::RenderTarget;
use bevy::prelude::*;
use bevy_manifold::camera::ManifoldFog;
use bevy_manifold::camera::{
    AccumulationProgress, AdaptiveRenderScale, ManifoldAccumulation, ManifoldFootprint, ManifoldPathTracer,
    ManifoldRenderScale,
};
use bevy_manifold::camera::{FlyCamera, Vehicle};
use bevy_manifold::drawables::paper::{paper_camera, spawn_paper_scene};
use bevy_manifold::geometry::product::ProductTangent;
use bevy_manifold::placement::{DomainCell, FaceCrossed, ManifoldSpace, Placement};
use bevy_manifold::product::{
    ProductBody, ProductCamera, ProductMeshBody, ProductPointLight, ProductSpaceRoot, ProductVelocity,
};
use bevy_manifold::space::product::ProductSpace;
use bevy_manifold::space::{Space, catalog};
use bevy_manifold::tour::FaceWord;
use bevy_manifold::trace::product::{ProductEdges, ProductScene, ProductView};
use std::collections::VecDeque;
use std::sync::Arc;

/// Marks the explorer's camera.
#[derive(Component, Clone, Copy, Debug, Default)]
pub struct ExplorerCamera;

/// What the explorer spawned, and the settings it was spawned with.
#[derive(Resource, Clone, Debug)]
pub struct ExplorerWorld {
    /// The space root (despawned with everything below it on a switch).
    pub root: Entity,
    /// The camera.
    pub camera: Entity,
    /// The space shown; while a product space is shown, the last space
    /// of E3, H3 or S3 shown (what the tours and VR keep).
    pub space: Space,
    /// The product space shown, if one is.
    pub product: Option<Arc<ProductSpace>>,
    /// The settings the world and camera reflect.
    pub applied: ExplorerSettings,
}

impl ExplorerWorld {
    /// The name of the space shown.
    #[must_use]
    pub fn name(&self) -> &str {
        match &self.product {
            Some(p) => &p.name,
            None => self.space.name(),
        }
    }
}

/// The product space `name` names ([`ProductSpace::NAMES`]), with the
/// explorer's circle of 2 and twists of a third (S2xS1) or three eighths
/// (genus 2).
#[must_use]
pub fn product_space(name: &str) -> Option<ProductSpace> {
    ProductSpace::named(name, 2.0, 3)
}

/// Spawns the product space `space` with the balls of its lit scene
/// ([`ProductScene::lit_for`], one of them drifting through the faces),
/// the airplane and the box of [`ProductScene::furnished_for`],
/// its two lights when the settings light it, and the explorer's camera
/// (a `ProductCamera` flown by the fly camera) at `keep` when given, else
/// where the scene's view starts.
fn spawn_product_world(
    commands: &mut Commands,
    space: &Arc<ProductSpace>,
    settings: &ExplorerSettings,
    target: &Handle<Image>,
    keep: Option<ProductView>,
) -> (Entity, Entity) {
    let root = commands
        .spawn((
            Name::new(format!("space {}", space.name)),
            ProductSpaceRoot(space.clone()),
        ))
        .id();
    let scene = ProductScene::lit_for(space);
    for (k, ball) in scene.balls.iter().enumerate() {
        let body = commands
            .spawn((
                Name::new(format!("ball {}", ball.id)),
                ChildOf(root),
                ProductBody::from(*ball),
            ))
            .id();
        if k == 1 {
            let dir = ProductTangent::new(glam::DVec3::Y, 0.5);
            commands
                .entity(body)
                .insert(ProductVelocity::along(space.geometry, ball.center, dir, 0.3));
        }
    }
    if settings.lights {
        for light in &scene.lights {
            commands.spawn((Name::new("light"), ChildOf(root), ProductPointLight(*light)));
        }
    }
    for mesh in ProductScene::furnished_for(space).meshes {
        commands.spawn((
            Name::new(format!("mesh {}", mesh.id)),
            ChildOf(root),
            ProductMeshBody(mesh),
        ));
    }
    let mut camera = ProductCamera {
        space: space.clone(),
        balls: scene.balls,
        meshes: Vec::new(),
        lights: scene.lights,
        lighting: scene.lighting,
        edges: product_edges(settings),
        view: keep.unwrap_or(scene.view),
    };
    set_product_view(&mut camera.view, settings);
    let camera = commands
        .spawn((
            Name::new("explorer camera"),
            ChildOf(root),
            ExplorerCamera,
            Camera3d::default(),
            camera,
            FlyCamera {
                speed: 0.6,
                mouse_button: Some(MouseButton::Right),
                ..default()
            },
            RenderTarget::Image(target.clone().into()),
        ))
        .id();
    (root, camera)
}

/// A product camera's view as the settings ask: the levels (faces a ray
/// crosses), the distance, the fog's density (its colour is the product
/// tracer's own) and the per-cell shading.
pub fn set_product_view(view: &mut ProductView, settings: &ExplorerSettings) {
    view.max_crossings = settings.levels as usize;
    view.max_distance = f64::from(settings.max_distance);
    view.fog = if settings.fog { settings.fog_density } else { 0.0 };
    view.tint = settings.cell_shading().tint();
}

/// The product space's edges as the settings draw them (the domain's
/// edges: thin tubes).
#[must_use]
pub fn product_edges(settings: &ExplorerSettings) -> Option<ProductEdges> {
    settings.edges.then(ProductEdges::default)
}

/// The image the explorer's camera renders into, and the size asked for
/// (the view's pixels times the render scale, set by the panel or a test).
#[derive(Resource, Clone, Debug)]
pub struct ExplorerView {
    /// The current target.
    pub image: Handle<Image>,
    /// Its size.
    pub size: UVec2,
    /// The size wanted; the image is replaced when they differ.
    pub wanted: UVec2,
}

/// What the panel shows that is not a setting.
#[derive(Resource, Debug, Default)]
pub struct ExplorerStatus {
    /// The last face the camera crossed.
    pub last_face: Option<usize>,
    /// A message for the user and whether it is an error.
    pub message: Option<(String, bool)>,
    /// Frame times in milliseconds, oldest first, with the time they ended.
    pub frame_times: VecDeque<(f64, f32)>,
    /// Spaces switched to since start.
    pub switches: u64,
}

impl ExplorerStatus {
    /// Seconds of frame times kept.
    pub const HISTORY_SECS: f64 = 5.0;

    /// Shows `message` (an error when `error`).
    pub fn say(&mut self, message: impl Into<String>, error: bool) {
        let m = message.into();
        if error {
            warn!("{m}");
        } else {
            info!("{m}");
        }
        self.message = Some((m, error));
    }

    /// The mean of the kept frame times, in ms.
    #[must_use]
    pub fn mean_frame_ms(&self) -> Option<f32> {
        (!self.frame_times.is_empty())
            .then(|| self.frame_times.iter().map(|f| f.1).sum::<f32>() / self.frame_times.len() as f32)
    }
}

/// A render target image of `size` (at least 1x1).
fn view_image(images: &mut Assets<Image>, size: UVec2) -> Handle<Image> {
    bevy_manifold::render::offscreen::target_image(images, size.x.max(1), size.y.max(1))
}

/// Spawns `space` with the paper's scene and the explorer's camera as the
/// settings say, the camera at `keep` when given (a scene change in the
/// same space keeps the view) or where the paper's camera starts.
fn spawn_world(
    commands: &mut Commands,
    space: &Space,
    settings: &ExplorerSettings,
    target: &Handle<Image>,
    keep: Option<(Placement, DomainCell, FaceWord)>,
) -> (Entity, Entity) {
    let root = commands
        .spawn((
            Name::new(format!("space {}", space.name())),
            ManifoldSpace::new(space.clone()).with_rule(settings.rule()),
        ))
        .id();
    let (placement, projection) = paper_camera(space);
    let mut camera = commands.spawn((
        Name::new("explorer camera"),
        ChildOf(root),
        ExplorerCamera,
        settings.camera(),
        projection,
        RenderTarget::Image(target.clone().into()),
    ));
    insert_controller(&mut camera, space, settings.vehicle);
    insert_scale(&mut camera, settings);
    match keep {
        Some((p, cell, word)) => camera.insert((p, cell, word)),
        None => camera.insert((placement, FaceWord::default())),
    };
    if let Some(fog) = settings.fog() {
        camera.insert(fog);
    }
    let camera = camera.id();
    spawn_paper_scene(commands, root, camera, space, settings.paper());
    (root, camera)
}

/// The camera's render scale: held by an [`AdaptiveRenderScale`] when
/// the settings hold a frame rate (starting from the scale it has), else
/// full (the image's size is the render scale); the refinement of a
/// still view ([`ManifoldAccumulation`]) and cone tracing
/// ([`ManifoldFootprint`]) when asked for.
pub fn insert_scale(camera: &mut EntityCommands, settings: &ExplorerSettings) {
    match settings.adaptive_scale() {
        Some(adaptive) => camera.insert(adaptive),
        None => camera.remove::<(AdaptiveRenderScale, ManifoldRenderScale)>(),
    };
    match settings.accumulation() {
        Some(a) => camera.insert(a).insert_if_new(AccumulationProgress::default()),
        None => camera.remove::<(ManifoldAccumulation, AccumulationProgress)>(),
    };
    match settings.footprint() {
        Some(f) => camera.insert(f),
        None => camera.remove::<ManifoldFootprint>(),
    };
    match settings.path_tracer() {
        Some(p) => camera.insert(p),
        None => camera.remove::<ManifoldPathTracer>(),
    };
}

/// The camera's controller: the vehicle it rides (`vehicle`) or the fly
/// camera, at a speed for `space`'s size; the mouse steers while its right
/// button is held.
pub fn insert_controller(camera: &mut EntityCommands, space: &Space, vehicle: bool) {
    let speed = 0.5 * space.inradius().max(0.2);
    camera.remove::<(FlyCamera, Vehicle)>();
    if vehicle {
        camera.insert(Vehicle {
            mouse_button: Some(MouseButton::Right),
            ..Vehicle::cruising(0.6 * speed)
        });
    } else {
        camera.insert(FlyCamera {
            speed,
            mouse_button: Some(MouseButton::Right),
            ..default()
        });
    }
}

/// Spawns the first world (startup).
pub fn setup(
    mut commands: Commands,
    mut settings: ResMut<ExplorerSettings>,
    mut images: ResMut<Assets<Image>>,
    mut status: ResMut<ExplorerStatus>,
) {
    let size = UVec2::new(640, 360);
    let image = view_image(&mut images, size);
    let world = match product_space(&settings.space) {
        Some(product) => {
            let product = Arc::new(product);
            let (root, camera) = spawn_product_world(&mut commands, &product, &settings, &image, None);
            ExplorerWorld {
                root,
                camera,
                space: catalog::torus(1.0),
                product: Some(product),
                applied: settings.clone(),
            }
        }
        None => {
            let space = catalog::resolve(&settings.space).unwrap_or_else(|e| {
                status.say(format!("{e}; showing the 3-torus"), true);
                settings.space = "torus".into();
                catalog::torus(1.0)
            });
            let (root, camera) = spawn_world(&mut commands, &space, &settings, &image, None);
            ExplorerWorld {
                root,
                camera,
                space,
                product: None,
                applied: settings.clone(),
            }
        }
    };
    commands.insert_resource(world);
    commands.insert_resource(ExplorerView {
        image,
        size,
        wanted: size,
    });
}

/// Brings the world in line with the settings when they changed: a new
/// space (or a new scene) despawns the old root with everything under it
/// and spawns the new one; camera settings only update its components.
/// A space that cannot be loaded is reported and the settings go back to
/// the space shown. A product space is shown as [`spawn_product_world`]
/// spawns it, and spawned again (keeping the view) when its lights are
/// turned on or off.
#[expect(clippy::too_many_arguments, reason = "a system's parameters")]
pub fn apply_settings(
    mut commands: Commands,
    mut settings: ResMut<ExplorerSettings>,
    mut world: ResMut<ExplorerWorld>,
    view: Res<ExplorerView>,
    mut status: ResMut<ExplorerStatus>,
    cameras: Query<(&Placement, &DomainCell, &FaceWord), With<ExplorerCamera>>,
    mut product_cameras: Query<&mut ProductCamera, With<ExplorerCamera>>,
    mut spaces: Query<&mut ManifoldSpace>,
) {
    if !settings.is_changed() || *settings == world.applied {
        return;
    }
    let space_changed = settings.space != world.applied.space;
    let product = if space_changed {
        product_space(&settings.space).map(Arc::new)
    } else {
        world.product.clone()
    };
    if let Some(product) = product {
        let respawn = space_changed || settings.lights != world.applied.lights;
        if respawn {
            let keep = (!space_changed)
                .then(|| product_cameras.get(world.camera).ok().map(|c| c.view))
                .flatten();
            #[cfg(feature = "xr")]
            bevy_manifold::xr::keep_tracking_root(&mut commands);
            commands.entity(world.root).despawn();
            let (root, camera) = spawn_product_world(&mut commands, &product, &settings, &view.image, keep);
            if space_changed {
                status.switches += 1;
                status.last_face = None;
                status.say(format!("showing {}", product.name), false);
            }
            world.root = root;
            world.camera = camera;
            world.product = Some(product);
        } else if let Ok(mut camera) = product_cameras.get_mut(world.camera) {
            set_product_view(&mut camera.view, &settings);
            camera.edges = product_edges(&settings);
        }
        world.applied = settings.clone();
        return;
    }
    if settings.rule() != world.applied.rule()
        && let Ok(mut ms) = spaces.get_mut(world.root)
    {
        ms.set_rule(settings.rule());
    }
    if space_changed || settings.paper() != world.applied.paper() {
        let space = if space_changed {
            match catalog::resolve(&settings.space) {
                Ok(s) => s,
                Err(e) => {
                    status.say(e, true);
                    settings.space = world.applied.space.clone();
                    return;
                }
            }
        } else {
            world.space.clone()
        };
        let keep = if space_changed {
            None
        } else {
            cameras
                .get(world.camera)
                .ok()
                .map(|(p, c, w)| (*p, c.clone(), w.clone()))
        };
        // The headset's tracking root hangs under the camera: keep it.
        #[cfg(feature = "xr")]
        bevy_manifold::xr::keep_tracking_root(&mut commands);
        commands.entity(world.root).despawn();
        let (root, camera) = spawn_world(&mut commands, &space, &settings, &view.image, keep);
        if space_changed {
            status.switches += 1;
            status.last_face = None;
            status.say(format!("showing {}", space.name()), false);
        }
        *world = ExplorerWorld {
            root,
            camera,
            space,
            product: None,
            applied: settings.clone(),
        };
        return;
    }
    let mut camera = commands.entity(world.camera);
    camera.insert(settings.camera());
    if settings.adaptive_scale() != world.applied.adaptive_scale()
        || settings.accumulation() != world.applied.accumulation()
        || settings.footprint() != world.applied.footprint()
        || settings.path_tracer() != world.applied.path_tracer()
    {
        insert_scale(&mut camera, &settings);
    }
    match settings.fog() {
        Some(fog) => camera.insert(fog),
        None => camera.remove::<ManifoldFog>(),
    };
    world.applied = settings.clone();
}

/// Replaces the view image when the wanted size changed, and points the
/// camera at the new one.
pub fn resize_view(
    mut commands: Commands,
    mut view: ResMut<ExplorerView>,
    mut images: ResMut<Assets<Image>>,
    world: Res<ExplorerWorld>,
) {
    if view.wanted == view.size || view.wanted.min_element() == 0 {
        return;
    }
    let image = view_image(&mut images, view.wanted);
    commands
        .entity(world.camera)
        .insert(RenderTarget::Image(image.clone().into()));
    view.image = image;
    view.size = view.wanted;
}

/// Notes the faces the camera crosses and the frame times.
pub fn track(
    mut crossed: MessageReader<FaceCrossed>,
    world: Res<ExplorerWorld>,
    time: Res<Time<bevy::time::Real>>,
    mut status: ResMut<ExplorerStatus>,
) {
    if let Some(c) = crossed.read().filter(|c| c.entity == world.camera).last() {
        status.last_face = Some(c.face);
    }
    let now = time.elapsed_secs_f64();
    let dt = time.delta_secs() * 1000.0;
    if dt > 0.0 {
        status.frame_times.push_back((now, dt));
    }
    while status
        .frame_times
        .front()
        .is_some_and(|f| f.0 < now - ExplorerStatus::HISTORY_SECS)
    {
        status.frame_times.pop_front();
    }
}

/// The camera's cell in words: the lattice triple of a box domain, the
/// element's index in a finite group, the exact id, or the hashed id
/// (marked "far" beyond the precision horizon).
#[must_use]
pub fn describe_cell(space: &Space, cell: &DomainCell) -> String {
    if let Some(l) = cell.id.lattice() {
        return format!("({}, {}, {})", l.x, l.y, l.z);
    }
    if let bevy_manifold::space::cells::CellScheme::Finite { elements, .. } = space.cells() {
        return format!("element {} of {}", cell.id.0, elements.len());
    }
    if matches!(cell.cell, bevy_manifold::space::element::CellElement::Exact(_)) {
        return format!("{:016x} (exact)", cell.id.0);
    }
    let far = if cell.id.is_far() { " (far: best effort)" } else { "" };
    format!("{:013x}{far}", cell.id.0 & !bevy_manifold::space::cells::CellId::FAR)
}
