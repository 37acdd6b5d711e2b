//! The product geometries (H2xR, S2xR) in a Bevy app: a [`ProductCamera`]
//! on a `Camera3d` looks into a product space, traced every frame by the
//! product tracer (`bevy_manifold_gpu`'s `shaders/product.wgsl`, its
//! `product_fragment` entry) over the camera's viewport; with a
//! [`crate::camera::FlyCamera`] it flies through the space along
//! geodesics, wrapping through the faces.
//!
//! These spaces have their own types
//! ([`ProductSpace`](bevy_manifold_core::space::product::ProductSpace),
//! balls of the product metric), apart from the `ManifoldSpace` of E3, H3
//! and S3: their entities, placements, meshes and lights are not traced
//! yet, only the camera's scene of balls.
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

#[cfg(feature = "render")]
pub mod render;

use crate::placement::{GeodesicVelocity, ManifoldSystems};
use bevy::prelude::*;
use bevy_manifold_core::space::product::ProductSpace;
use bevy_manifold_core::trace::product::{ProductBall, ProductScene, ProductView};
use std::sync::Arc;

/// A camera looking into a product space: the space, the balls in it and
/// the view (the eye, its frame, how far and through how many faces it
/// sees, the fog). Put it on a `Camera3d`; the camera's own `Transform`
/// and projection are not used (the view's frame and field of view are).
#[derive(Component, Clone, Debug)]
pub struct ProductCamera {
    /// The space.
    pub space: Arc<ProductSpace>,
    /// The balls, in the space's prism.
    pub balls: Vec<ProductBall>,
    /// Where the eye is and how it sees.
    pub view: ProductView,
}

impl ProductCamera {
    /// `space` with its default scene ([`ProductScene::default_for`]:
    /// three balls, an eye looking across the prism, fog).
    #[must_use]
    pub fn default_for(space: ProductSpace) -> Self {
        let scene = ProductScene::default_for(&space);
        Self {
            space: Arc::new(space),
            balls: scene.balls,
            view: scene.view,
        }
    }

    /// The scene the camera shows.
    #[must_use]
    pub fn scene(&self) -> ProductScene {
        ProductScene {
            balls: self.balls.clone(),
            view: self.view,
        }
    }
}

/// Flies every [`ProductCamera`] that has a [`GeodesicVelocity`] (a
/// [`crate::camera::FlyCamera`] sets it from the keys and the mouse):
/// the eye moves along its geodesic through the faces
/// ([`ProductView::moved`]) and the frame turns ([`ProductView::turned`];
/// roll is not applied). The velocity is in the camera's frame, `-z`
/// forward, as for the other cameras.
pub fn fly_product_cameras(time: Res<Time>, mut cameras: Query<(&mut ProductCamera, &GeodesicVelocity)>) {
    let dt = f64::from(time.delta_secs());
    for (mut camera, velocity) in &mut cameras {
        if velocity.linear == glam::DVec3::ZERO && velocity.angular == glam::DVec3::ZERO {
            continue;
        }
        let g = camera.space.geometry;
        let v = velocity.linear;
        let mut view = camera.view.turned(g, -velocity.angular.y * dt, velocity.angular.x * dt);
        let speed = v.length();
        if speed > 0.0 {
            view = view.moved(&camera.space, [-v.z / speed, v.x / speed, v.y / speed], speed * dt);
        }
        camera.view = view;
    }
}

/// The product cameras: [`fly_product_cameras`], and with feature
/// `render` their pass ([`render::ProductRenderPlugin`]). Part of
/// [`crate::ManifoldPlugins`].
#[derive(Debug, Clone, Copy, Default)]
pub struct ProductPlugin;

impl Plugin for ProductPlugin {
    fn build(&self, app: &mut App) {
        // In the integration set: after the fly camera's input, which sets
        // the velocity before it.
        app.add_systems(PostUpdate, fly_product_cameras.in_set(ManifoldSystems::Integrate));
        #[cfg(feature = "render")]
        app.add_plugins(render::ProductRenderPlugin);
    }
}
