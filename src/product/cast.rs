//! [`ProductRayCast`]: gameplay ray casts in the product spaces, along the
//! exact geodesics and through the faces as the tracer's rays go, against
//! the [`ProductBody`]s and [`ProductMeshBody`]s of a [`ProductSpaceRoot`].

use super::{ProductBody, ProductCamera, ProductMeshBody, ProductSpaceRoot};
use crate::placement::RayCastSettings;
use bevy::ecs::system::SystemParam;
use bevy::prelude::*;
use bevy_manifold_core::geometry::product::{ProductPoint, ProductTangent};
use bevy_manifold_core::trace::product::{ProductBall, ProductMesh, ProductObjects, ProductRay, hits_in};

/// One hit of a product cast, in the order of distance (the same body
/// may be hit again in another copy of the prism).
#[derive(Clone, Debug, PartialEq)]
pub struct ProductRayHit {
    /// The body (or mesh) hit.
    pub entity: Entity,
    /// Distance along the geodesic.
    pub distance: f64,
    /// Where the ray entered the body, in the prism.
    pub point: ProductPoint,
    /// The faces the ray crossed before the hit, in order: the word of
    /// the copy of the prism the hit is in, from the ray's
    /// (`ProductCells::element` names it exactly).
    pub faces: Vec<usize>,
}

/// Casts geodesic rays through a product space against its
/// [`ProductBody`]s (every hit, nearest first, at most 64) and its
/// [`ProductMeshBody`]s (each one's first hit in each copy of the prism).
///
/// ```
/// use bevy::prelude::*;
/// use bevy_manifold::placement::RayCastSettings;
/// use bevy_manifold::product::{ProductCamera, ProductRayCast};
/// fn look(cast: ProductRayCast, cameras: Query<Entity, With<ProductCamera>>) {
///     for camera in &cameras {
///         // Straight ahead: the first body it sees.
///         if let Some(hit) = cast.from_camera(camera, [1.0, 0.0, 0.0], &RayCastSettings::default()).first() {
///             info!("{} at {:.2} after {} faces", hit.entity, hit.distance, hit.faces.len());
///         }
///     }
/// }
/// # bevy::ecs::system::assert_is_system(look);
/// ```
#[derive(SystemParam)]
pub struct ProductRayCast<'w, 's> {
    roots: Query<'w, 's, (&'static ProductSpaceRoot, &'static Children)>,
    bodies: Query<'w, 's, (&'static ProductBody, &'static ChildOf)>,
    meshes: Query<'w, 's, &'static ProductMeshBody>,
    cameras: Query<'w, 's, (&'static ProductCamera, &'static ChildOf)>,
}

impl ProductRayCast<'_, '_> {
    /// Casts `ray` (a point in the prism and a tangent there, made unit)
    /// through the space of the root `root`, against its bodies and meshes but
    /// `settings.exclude`, for `settings.max_distance` and at most
    /// `settings.levels` faces. Empty for a root that is not one, a ray
    /// that is not finite or has no direction.
    #[must_use]
    pub fn cast(&self, root: Entity, ray: ProductRay, settings: &RayCastSettings) -> Vec<ProductRayHit> {
        let Ok((space, children)) = self.roots.get(root) else {
            return Vec::new();
        };
        let g = space.0.geometry;
        let numbers = [ray.origin.surface, ray.dir.surface].iter().all(|v| v.is_finite())
            && ray.origin.height.is_finite()
            && ray.dir.height.is_finite();
        if !numbers || ray.dir.length(g) == 0.0 || settings.max_distance.is_nan() || settings.max_distance < 0.0 {
            return Vec::new();
        }
        let origin = g.normalize_point(ray.origin);
        let ray = ProductRay {
            origin,
            dir: g.normalize_tangent(origin, ray.dir),
        };
        let others = || children.iter().filter(|c| Some(*c) != settings.exclude);
        let keys: Vec<(Entity, &ProductBody)> = others()
            .filter_map(|c| self.bodies.get(c).ok().map(|(b, _)| (c, b)))
            .collect();
        let mesh_keys: Vec<(Entity, &ProductMeshBody)> = others()
            .filter_map(|c| self.meshes.get(c).ok().map(|m| (c, m)))
            .collect();
        // Each body under its index, then each mesh, to name it again in
        // the hits.
        let balls: Vec<ProductBall> = keys
            .iter()
            .enumerate()
            .map(|(k, (_, b))| ProductBall {
                center: b.center,
                radius: b.radius,
                id: k as u32,
            })
            .collect();
        let meshes: Vec<ProductMesh> = mesh_keys
            .iter()
            .enumerate()
            .map(|(k, (_, m))| ProductMesh {
                id: (keys.len() + k) as u32,
                ..m.0.clone()
            })
            .collect();
        let entity = |id: u32| {
            let id = id as usize;
            keys.get(id).map_or_else(|| mesh_keys[id - keys.len()].0, |k| k.0)
        };
        let objects = ProductObjects::new(&space.0, &balls, None, &meshes);
        let levels = usize::try_from(settings.levels).unwrap_or(usize::MAX);
        hits_in(&space.0, &objects, ray, settings.max_distance, levels)
            .into_iter()
            .map(|h| ProductRayHit {
                entity: entity(h.object),
                distance: h.distance,
                point: h.point,
                faces: h.faces,
            })
            .collect()
    }

    /// Casts from the body `from` (excluded) in the direction `dir`, a
    /// tangent at its centre.
    #[must_use]
    pub fn from_body(&self, from: Entity, dir: ProductTangent, settings: &RayCastSettings) -> Vec<ProductRayHit> {
        let Ok((body, parent)) = self.bodies.get(from) else {
            return Vec::new();
        };
        let settings = RayCastSettings {
            exclude: Some(from),
            ..settings.clone()
        };
        self.cast(
            parent.parent(),
            ProductRay {
                origin: body.center,
                dir,
            },
            &settings,
        )
    }

    /// Casts from the eye of the product camera `camera` (a child of a
    /// root) in the direction `forward * d[0] + right * d[1] + up * d[2]`
    /// of its view's frame.
    #[must_use]
    pub fn from_camera(&self, camera: Entity, d: [f64; 3], settings: &RayCastSettings) -> Vec<ProductRayHit> {
        let Ok((camera, parent)) = self.cameras.get(camera) else {
            return Vec::new();
        };
        let [f, r, u] = camera.view.frame;
        let dir = ProductTangent::new(
            f.surface * d[0] + r.surface * d[1] + u.surface * d[2],
            f.height * d[0] + r.height * d[1] + u.height * d[2],
        );
        self.cast(
            parent.parent(),
            ProductRay {
                origin: camera.view.eye,
                dir,
            },
            settings,
        )
    }
}
