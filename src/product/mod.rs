//! The product geometries (H2xR, S2xR) in a Bevy app: a [`ProductCamera`]
//! on a `Camera3d` looks into a product space, traced every frame by the
//! product tracer (`bevy_manifold_gpu`'s `shaders/product.wgsl`, its
//! `product_fragment` entry) over the camera's viewport; with a
//! `FlyCamera` (feature `fly_camera`) it flies through the space along
//! geodesics, wrapping through the faces.
//!
//! These spaces have their own types
//! ([`ProductSpace`](bevy_manifold_core::space::product::ProductSpace),
//! balls of the product metric), apart from the `ManifoldSpace` of E3, H3
//! and S3. Their entities are balls: a [`ProductSpaceRoot`] holds a space,
//! and the [`ProductBody`]s (balls, moved by a [`ProductVelocity`]
//! through the faces) and [`ProductMeshBody`]s (meshes; a `Mesh3d` with a
//! [`ProductMeshPlacement`] becomes one) among its children are what the
//! [`ProductCamera`]s among its children show, lit by the
//! [`ProductPointLight`]s among its children (every image of each, with
//! shadows); [`ProductRayCast`] casts rays against the bodies and meshes,
//! and [`ProductContacts`] says which bodies touch.
//! A [`ProductTourPlayer`] flies a camera through a product tour.
//!
//! ```no_run
//! use bevy::prelude::*;
//! use bevy_manifold::prelude::*;
//! use bevy_manifold::product::ProductCamera;
//! use bevy_manifold::space::product::ProductSpace;
//!
//! fn setup(mut commands: Commands) {
//!     let space = ProductSpace::genus_two_x_s1(2.0);
//!     // Add a `FlyCamera` (feature `fly_camera`, with `FlyCameraPlugin`)
//!     // to fly it.
//!     commands.spawn((Camera3d::default(), ProductCamera::default_for(space)));
//! }
//!
//! App::new()
//!     .add_plugins((DefaultPlugins, ManifoldPlugins::default()))
//!     .add_systems(Startup, setup)
//!     .run();
//! ```

pub mod cast;
pub mod contact;
#[cfg(feature = "render")]
pub mod render;

pub use cast::{ProductRayCast, ProductRayHit};
pub use contact::ProductContacts;

use crate::placement::{GeodesicVelocity, ManifoldSystems};
use bevy::prelude::*;
use bevy_manifold_core::geometry::product::ProductIsometry;
use bevy_manifold_core::geometry::product::{ProductGeometry, ProductPoint, ProductTangent};
#[cfg(feature = "render")]
use bevy_manifold_core::mesh::MeshData;
use bevy_manifold_core::space::product::ProductSpace;
use bevy_manifold_core::tour::product::ProductTour;
#[cfg(feature = "render")]
use bevy_manifold_core::trace::product::mesh::z_up;
use bevy_manifold_core::trace::product::{
    ProductBall, ProductEdges, ProductLight, ProductLighting, ProductMesh, ProductRay, ProductScene, ProductView, flow,
};
use std::sync::Arc;

/// A camera looking into a product space: the space, the balls and
/// lights in it and the view (the eye, its frame, how far and through how
/// many faces it sees, the fog). Put it on a `Camera3d`; the camera's own `Transform`
/// and projection are not used (the view's frame and field of view are).
#[derive(Component, Clone, Debug)]
pub struct ProductCamera {
    /// The space.
    pub space: Arc<ProductSpace>,
    /// The balls, in the space's prism.
    pub balls: Vec<ProductBall>,
    /// The meshes, placed in the space's prism.
    pub meshes: Vec<ProductMesh>,
    /// The lights, in the space's prism; none: the balls are lit from
    /// the eye.
    pub lights: Vec<ProductLight>,
    /// How the lights light the balls (their images, shadows).
    pub lighting: ProductLighting,
    /// The prism's edges drawn as tubes of the product metric; `None`
    /// for none.
    pub edges: Option<ProductEdges>,
    /// Where the eye is and how it sees.
    pub view: ProductView,
}

impl ProductCamera {
    /// `space` with its default scene ([`ProductScene::default_for`]:
    /// three balls, an eye looking across the prism, fog).
    #[must_use]
    pub fn default_for(space: ProductSpace) -> Self {
        let scene = ProductScene::default_for(&space);
        Self::of(space, scene)
    }

    /// `scene` in `space`.
    #[must_use]
    pub fn of(space: ProductSpace, scene: ProductScene) -> Self {
        Self {
            space: Arc::new(space),
            balls: scene.balls,
            meshes: scene.meshes,
            lights: scene.lights,
            lighting: scene.lighting,
            edges: scene.edges,
            view: scene.view,
        }
    }

    /// The scene the camera shows.
    #[must_use]
    pub fn scene(&self) -> ProductScene {
        ProductScene {
            balls: self.balls.clone(),
            meshes: self.meshes.clone(),
            lights: self.lights.clone(),
            lighting: self.lighting,
            edges: self.edges,
            view: self.view,
        }
    }
}

/// The root of a product space: the [`ProductBody`]s among its children
/// are what the [`ProductCamera`]s among its children show (each frame,
/// by [`gather_product_bodies`]).
///
/// It has a `Transform` (and with `render` a `Visibility`): the identity,
/// visible, for the cameras among its children, as Bevy's hierarchy
/// wants.
#[derive(Component, Clone, Debug)]
#[cfg_attr(feature = "render", require(Transform, Visibility))]
#[cfg_attr(not(feature = "render"), require(Transform))]
pub struct ProductSpaceRoot(pub Arc<ProductSpace>);

/// A ball in a product space, a child of a [`ProductSpaceRoot`]: a
/// geodesic ball of the product metric about `center`, which stays in
/// the space's prism (a moving body is carried through the faces).
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct ProductBody {
    /// Its centre, in the prism.
    pub center: ProductPoint,
    /// Its radius.
    pub radius: f64,
    /// The object id the tracer reports (and its colour).
    pub id: u32,
}

impl From<ProductBall> for ProductBody {
    fn from(b: ProductBall) -> Self {
        Self {
            center: b.center,
            radius: b.radius,
            id: b.id,
        }
    }
}

impl From<ProductBody> for ProductBall {
    fn from(b: ProductBody) -> Self {
        Self {
            center: b.center,
            radius: b.radius,
            id: b.id,
        }
    }
}

/// A mesh in a product space, a child of a [`ProductSpaceRoot`]: its
/// triangles in its chart (the Klein or gnomonic chart of the surface
/// times the height, `trace::product::mesh`) and where that chart
/// stands. The [`ProductCamera`]s among the root's children show it, in
/// the product metric; [`ProductRayCast`] hits it. A `Mesh3d` with a
/// [`ProductMeshPlacement`] is made one (feature `render`).
///
/// ```
/// use bevy::prelude::*;
/// use bevy_manifold::prelude::*;
/// use bevy_manifold::geometry::product::ProductIsometry;
/// use bevy_manifold::mesh::{MeshData, shapes::cuboid};
/// use bevy_manifold::product::{ProductCamera, ProductMeshBody, ProductSpaceRoot};
/// use bevy_manifold::space::product::ProductSpace;
/// use bevy_manifold::trace::product::ProductMesh;
/// use std::sync::Arc;
///
/// let mut app = App::new();
/// app.add_plugins((MinimalPlugins, ManifoldPlugins::default()));
/// let space = ProductSpace::genus_two_x_s1(2.0);
/// let root = app.world_mut().spawn(ProductSpaceRoot(Arc::new(space.clone()))).id();
/// let block = ProductMesh {
///     mesh: MeshData::shared(cuboid([0.1, 0.1, 0.2])),
///     placement: ProductIsometry::vertical(0.3),
///     id: 4,
/// };
/// app.world_mut().spawn((ChildOf(root), ProductMeshBody(block.clone())));
/// let camera = app.world_mut().spawn((ChildOf(root), ProductCamera::default_for(space))).id();
/// app.update();
/// assert_eq!(app.world().get::<ProductCamera>(camera).unwrap().meshes, [block]);
/// ```
#[derive(Component, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "render", require(Transform, Visibility))]
#[cfg_attr(not(feature = "render"), require(Transform))]
pub struct ProductMeshBody(pub ProductMesh);

/// Puts a `Mesh3d` in a product space (feature `render`): on a child of
/// a [`ProductSpaceRoot`] with a `Mesh3d`, the Bevy mesh (y up, as Bevy's
/// and glTF's are; one unit of the space per unit of the mesh) is turned
/// into the product chart's axes (z up, `trace::product::mesh::z_up`) and
/// made the entity's [`ProductMeshBody`], placed by `placement`
/// ([`product_mesh_assets`]). Give it no material: the product cameras
/// trace it, Bevy does not draw it.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct ProductMeshPlacement {
    /// Where the mesh's chart stands in the prism.
    pub placement: ProductIsometry,
    /// The object id the tracer reports (and its colour).
    pub id: u32,
}

/// A point light in a product space, a child of a [`ProductSpaceRoot`]:
/// the [`ProductCamera`]s among the root's children are lit by it (by
/// every image of it, as their `lighting` says).
///
/// ```
/// use bevy::prelude::*;
/// use bevy_manifold::prelude::*;
/// use bevy_manifold::product::{ProductCamera, ProductPointLight, ProductSpaceRoot};
/// use bevy_manifold::space::product::ProductSpace;
/// use bevy_manifold::trace::product::ProductLight;
/// use bevy_manifold::geometry::product::ProductPoint;
/// use std::sync::Arc;
///
/// let mut app = App::new();
/// app.add_plugins((MinimalPlugins, ManifoldPlugins::default()));
/// let space = ProductSpace::s2_x_s1(2.0);
/// let root = app.world_mut().spawn(ProductSpaceRoot(Arc::new(space.clone()))).id();
/// let light = ProductLight::point(ProductPoint::new(glam::DVec3::Z, 0.5), 5.0);
/// app.world_mut().spawn((ChildOf(root), ProductPointLight(light)));
/// let camera = app.world_mut().spawn((ChildOf(root), ProductCamera::default_for(space))).id();
/// app.update();
/// assert_eq!(app.world().get::<ProductCamera>(camera).unwrap().lights, [light]);
/// ```
#[derive(Component, Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "render", require(Transform, Visibility))]
#[cfg_attr(not(feature = "render"), require(Transform))]
pub struct ProductPointLight(pub ProductLight);

/// A [`ProductBody`]'s velocity: a tangent vector at its centre, in
/// distance per second. [`move_product_bodies`] moves the body along its
/// geodesic, through the faces, and turns the velocity as the geodesic
/// and the gluings turn it.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct ProductVelocity(pub ProductTangent);

impl ProductVelocity {
    /// `speed` at the point `at` of a `g` space, in the direction of `dir`
    /// (made tangent there and of unit length).
    #[must_use]
    pub fn along(g: ProductGeometry, at: ProductPoint, dir: ProductTangent, speed: f64) -> Self {
        let unit = g.normalize_tangent(at, dir);
        Self(ProductTangent::new(unit.surface * speed, unit.height * speed))
    }
}

/// Moves every [`ProductBody`] with a [`ProductVelocity`] along its
/// geodesic for the frame's time, through the faces of its root's space
/// ([`flow`]).
pub fn move_product_bodies(
    time: Res<Time>,
    roots: Query<&ProductSpaceRoot>,
    mut bodies: Query<(&mut ProductBody, &mut ProductVelocity, &ChildOf)>,
) {
    let dt = f64::from(time.delta_secs());
    for (mut body, mut velocity, parent) in &mut bodies {
        let Ok(root) = roots.get(parent.parent()) else {
            continue;
        };
        let g = root.0.geometry;
        // Its part tangent at the centre (all of it, for a velocity made
        // as the docs say).
        let (v, c) = (velocity.0, body.center.surface);
        let v = ProductTangent::new(v.surface - c * (g.form(v.surface, c) * g.curvature()), v.height);
        let speed = v.length(g);
        let moving = speed * dt > 0.0 && speed.is_finite();
        if !moving {
            continue;
        }
        let ray = ProductRay {
            origin: body.center,
            dir: v.unit(g),
        };
        let end = flow(&root.0, ray, speed * dt, 64).ray;
        body.center = end.origin;
        velocity.0 = ProductTangent::new(end.dir.surface * speed, end.dir.height * speed);
    }
}

/// Each [`ProductCamera`] that is a child of a [`ProductSpaceRoot`] shows
/// that root's space and the [`ProductBody`]s and [`ProductMeshBody`]s
/// among its children, lit by the [`ProductPointLight`]s among them (its
/// own `balls`, `meshes` and `lights` are replaced); other cameras keep
/// theirs. A mesh that cannot stand in the space (`ProductMesh::check`) is
/// left out, with a warning.
pub fn gather_product_bodies(
    roots: Query<(&ProductSpaceRoot, &Children)>,
    bodies: Query<&ProductBody>,
    meshes: Query<&ProductMeshBody>,
    lights: Query<&ProductPointLight>,
    mut cameras: Query<(&mut ProductCamera, &ChildOf)>,
    mut warned: Local<bevy::platform::collections::HashSet<Entity>>,
) {
    for (mut camera, parent) in &mut cameras {
        let Ok((root, children)) = roots.get(parent.parent()) else {
            continue;
        };
        let balls: Vec<ProductBall> = children
            .iter()
            .filter_map(|c| bodies.get(c).ok())
            .map(|b| ProductBall::from(*b))
            .collect();
        if !Arc::ptr_eq(&camera.space, &root.0) {
            camera.space = root.0.clone();
        }
        if camera.balls != balls {
            camera.balls = balls;
        }
        let g = root.0.geometry;
        let placed: Vec<ProductMesh> = children
            .iter()
            .filter_map(|c| meshes.get(c).ok().map(|m| (c, m)))
            .filter(|(c, m)| match m.0.check(g) {
                Ok(()) => true,
                Err(e) => {
                    if warned.insert(*c) {
                        warn!("bevy_manifold: the product mesh of entity {c} is not traced: {e}");
                    }
                    false
                }
            })
            .map(|(_, m)| m.0.clone())
            .collect();
        if camera.meshes != placed {
            camera.meshes = placed;
        }
        let lit: Vec<ProductLight> = children
            .iter()
            .filter_map(|c| lights.get(c).ok())
            .map(|l| l.0)
            .collect();
        if camera.lights != lit {
            camera.lights = lit;
        }
    }
}

/// Flies every [`ProductCamera`] that has a [`GeodesicVelocity`] (a
/// `FlyCamera` (feature `fly_camera`) sets it from the keys and the mouse):
/// the eye moves along its geodesic through the faces
/// ([`ProductView::moved`]) and the frame turns and rolls
/// ([`ProductView::turned`], [`ProductView::rolled`]). The velocity is in
/// the camera's frame, `-z` forward, as for the other cameras.
pub fn fly_product_cameras(time: Res<Time>, mut cameras: Query<(&mut ProductCamera, &GeodesicVelocity)>) {
    let dt = f64::from(time.delta_secs());
    for (mut camera, velocity) in &mut cameras {
        if velocity.linear == glam::DVec3::ZERO && velocity.angular == glam::DVec3::ZERO {
            continue;
        }
        let g = camera.space.geometry;
        let v = velocity.linear;
        let mut view = camera
            .view
            .turned(g, -velocity.angular.y * dt, velocity.angular.x * dt)
            .rolled(g, velocity.angular.z * dt);
        let speed = v.length();
        if speed > 0.0 {
            view = view.moved(&camera.space, [-v.z / speed, v.x / speed, v.y / speed], speed * dt);
        }
        camera.view = view;
    }
}

/// Plays a product tour on its entity's [`ProductCamera`]: each frame the
/// camera's view (eye, frame, field of view, per-cell shading) is the
/// tour's at the player's time, which runs while `playing` (round again
/// at the end where `looping`, else it stops there).
///
/// ```no_run
/// use bevy::prelude::*;
/// use bevy_manifold::product::ProductTourPlayer;
/// use bevy_manifold::tour::product::ProductTour;
///
/// fn setup(mut commands: Commands) {
///     let tour = ProductTour::load("assets/tours/s2xs1.product-tour.json").expect("the tour");
///     let player = ProductTourPlayer::new(tour);
///     commands.spawn((Camera3d::default(), player.camera(), player));
/// }
/// ```
#[derive(Component, Clone, Debug)]
pub struct ProductTourPlayer {
    /// The tour.
    pub tour: Arc<ProductTour>,
    /// Seconds into it.
    pub time: f64,
    /// Whether the time runs.
    pub playing: bool,
    /// Whether it starts again at the end.
    pub looping: bool,
}

impl ProductTourPlayer {
    /// A player at the tour's start, playing, not looping.
    #[must_use]
    pub fn new(tour: ProductTour) -> Self {
        Self {
            tour: Arc::new(tour),
            time: 0.0,
            playing: true,
            looping: false,
        }
    }

    /// The camera the tour is seen by: its space, its balls and its view
    /// at the player's time.
    #[must_use]
    pub fn camera(&self) -> ProductCamera {
        ProductCamera::of(self.tour.space.clone(), self.tour.scene_at(self.time))
    }
}

/// Advances each [`ProductTourPlayer`] and sets its camera's view to the
/// tour's ([`ProductTour::view_at`]).
pub fn play_product_tours(time: Res<Time>, mut players: Query<(&mut ProductTourPlayer, &mut ProductCamera)>) {
    for (mut player, mut camera) in &mut players {
        if player.playing {
            let duration = player.tour.duration();
            let mut t = player.time + f64::from(time.delta_secs());
            if t > duration {
                if player.looping && duration > 0.0 {
                    t %= duration;
                } else {
                    t = duration;
                    player.playing = false;
                }
            }
            player.time = t;
        }
        let view = player.tour.view_at(player.time);
        if camera.view != view {
            camera.view = view;
        }
    }
}

/// The product spaces' systems: [`play_product_tours`],
/// [`fly_product_cameras`], [`move_product_bodies`],
/// [`product_mesh_assets`] (feature `render`) and
/// [`gather_product_bodies`], and with feature
/// `render` the cameras' pass ([`render::ProductRenderPlugin`]). Part of
/// [`crate::ManifoldPlugins`].
#[derive(Debug, Clone, Copy, Default)]
pub struct ProductPlugin;

impl Plugin for ProductPlugin {
    fn build(&self, app: &mut App) {
        // In the integration set: after the fly camera's input, which sets
        // the velocity before it.
        app.add_systems(
            PostUpdate,
            (
                play_product_tours,
                fly_product_cameras,
                move_product_bodies,
                gather_product_bodies,
            )
                .chain()
                .in_set(ManifoldSystems::Integrate),
        );
        #[cfg(feature = "render")]
        app.add_plugins(render::ProductRenderPlugin);
    }

    /// With feature `render`, in apps that have Bevy's meshes:
    /// [`product_mesh_assets`], before the bodies are gathered.
    fn finish(&self, app: &mut App) {
        #[cfg(feature = "render")]
        if app.world().contains_resource::<Assets<Mesh>>() {
            app.init_resource::<ProductMeshAssets>().add_systems(
                PostUpdate,
                product_mesh_assets
                    .before(gather_product_bodies)
                    .after(move_product_bodies)
                    .in_set(ManifoldSystems::Integrate),
            );
        }
        #[cfg(not(feature = "render"))]
        let _ = app;
    }
}

/// The Bevy meshes made [`ProductMeshBody`]s, by asset: each one's
/// triangles turned into the product chart's axes with their BVH, made
/// once (again when the asset changes); `None` for one that cannot be
/// traced.
#[cfg(feature = "render")]
#[derive(Resource, Default)]
pub struct ProductMeshAssets {
    meshes: bevy::platform::collections::HashMap<AssetId<Mesh>, Option<Arc<MeshData>>>,
}

/// Makes each `Mesh3d` with a [`ProductMeshPlacement`] its entity's
/// [`ProductMeshBody`] ([`ProductMeshPlacement`]): when its asset has
/// loaded, and again when the asset or the placement changes. A mesh
/// Bevy cannot give as triangles is warned of once and left out.
#[cfg(feature = "render")]
pub fn product_mesh_assets(
    mut commands: Commands,
    mut events: MessageReader<AssetEvent<Mesh>>,
    assets: Res<Assets<Mesh>>,
    mut cache: ResMut<ProductMeshAssets>,
    placed: Query<(
        Entity,
        &bevy::mesh::Mesh3d,
        &ProductMeshPlacement,
        Option<&ProductMeshBody>,
    )>,
) {
    for event in events.read() {
        if let AssetEvent::Modified { id } | AssetEvent::Removed { id } = event {
            cache.meshes.remove(id);
        }
    }
    for (entity, mesh, at, body) in &placed {
        let id = mesh.0.id();
        let data = match cache.meshes.get(&id) {
            Some(data) => data.clone(),
            None => {
                let Some(asset) = assets.get(id) else { continue };
                let built = match crate::drawables::tri_mesh(asset) {
                    Ok(m) => Some(MeshData::shared(z_up(&m, 1.0))),
                    Err(e) => {
                        warn!("bevy_manifold: mesh {id} of entity {entity} is not traced in the product space: {e}");
                        None
                    }
                };
                cache.meshes.insert(id, built.clone());
                built
            }
        };
        let Some(data) = data else { continue };
        let wanted = ProductMesh {
            mesh: data,
            placement: at.placement,
            id: at.id,
        };
        let same = body.is_some_and(|b| {
            Arc::ptr_eq(&b.0.mesh, &wanted.mesh) && b.0.placement == wanted.placement && b.0.id == wanted.id
        });
        if !same {
            commands.entity(entity).insert(ProductMeshBody(wanted));
        }
    }
}
