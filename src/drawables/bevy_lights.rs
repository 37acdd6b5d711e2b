//! Bevy's own lights in a manifold: a [`PointLight`] or [`SpotLight`] on
//! an entity with a [`Placement`] (under a
//! [`crate::placement::ManifoldSpace`] root) is a manifold light (a spot
//! points along the placement's forward). Its [`ManifoldLight`] is kept in step with it, so it
//! is gathered, imaged through the faces and shadowed like any other.
//!
//! Units: Bevy's luminous power in lumens, seen through Bevy's default
//! camera exposure (EV100 9.7, [`BEVY_EXPOSURE`]), so that a light lights
//! a surface at distance `d` of the space as Bevy's lights a surface `d`
//! metres away; `range` and `radius` are distances of the space.
//!
//! ```
//! use bevy::prelude::*;
//! use bevy_manifold::prelude::*;
//! use glam::DVec3;
//!
//! let mut app = App::new();
//! app.add_plugins((MinimalPlugins, ManifoldPlugins::default()));
//! let space = catalog::torus(1.0);
//! let root = app.world_mut().spawn(ManifoldSpace::new(space.clone())).id();
//! app.world_mut().spawn((
//!     ChildOf(root),
//!     PointLight { intensity: 1000.0, range: 2.0, ..default() },
//!     Placement::at(&space, DVec3::Y * 0.3),
//! ));
//! app.update();
//! let scene = app.world().get::<ManifoldScene>(root).unwrap();
//! let light = &scene.scene().lights[0];
//! assert_eq!(light.range, Some(2.0));
//! assert!((light.intensity - 1000.0 * bevy_manifold::drawables::BEVY_EXPOSURE).abs() < 1e-9);
//! ```

use super::components::ManifoldLight;
use super::components::SpotCone;
use crate::placement::Placement;
use bevy::light::{PointLight, SpotLight};
use bevy::prelude::*;

/// Bevy's default camera exposure, `1 / (1.2 * 2^9.7)` (EV100 9.7, its
/// `Exposure::default()`): what one lumen of a Bevy light is worth in
/// the tracer's units.
pub const BEVY_EXPOSURE: f64 = 1.0 / (1.2 * 831.746_454_093_805);

/// Marks a [`ManifoldLight`] kept from a Bevy light on the same entity,
/// removed with it.
#[derive(Component, Clone, Copy, Debug, Default)]
pub struct FromBevyLight;

/// The manifold light of a Bevy [`PointLight`].
#[must_use]
pub fn from_point_light(l: &PointLight) -> ManifoldLight {
    let LinearRgba { red, green, blue, .. } = l.color.to_linear();
    ManifoldLight {
        intensity: f64::from(l.intensity.max(0.0)) * BEVY_EXPOSURE,
        color: Color::linear_rgb(red, green, blue),
        range: (l.range.is_finite() && l.range > 0.0).then_some(f64::from(l.range)),
        radius: f64::from(l.radius.max(0.0)),
        cone: None,
    }
}

/// The manifold light of a Bevy [`SpotLight`]: as a point light's, with
/// its cone.
///
/// ```
/// use bevy::light::SpotLight;
/// use bevy_manifold::drawables::{BEVY_EXPOSURE, from_spot_light};
/// let spot = SpotLight { intensity: 2000.0, inner_angle: 0.2, outer_angle: 0.5, ..Default::default() };
/// let light = from_spot_light(&spot);
/// let cone = light.cone.unwrap();
/// assert!((cone.inner - 0.2).abs() < 1e-7 && (cone.outer - 0.5).abs() < 1e-7);
/// assert!((light.intensity - 2000.0 * BEVY_EXPOSURE).abs() < 1e-9);
/// ```
#[must_use]
pub fn from_spot_light(l: &SpotLight) -> ManifoldLight {
    let point = PointLight {
        color: l.color,
        intensity: l.intensity,
        range: l.range,
        radius: l.radius,
        ..PointLight::default()
    };
    ManifoldLight {
        cone: Some(SpotCone {
            inner: f64::from(l.inner_angle),
            outer: f64::from(l.outer_angle),
        }),
        ..from_point_light(&point)
    }
}

/// A placed Bevy light that changed, or was just placed.
type ChangedOrPlaced<L> = (With<Placement>, Or<(Changed<L>, Added<Placement>)>);

/// Keeps the [`ManifoldLight`] of each placed [`PointLight`] and
/// [`SpotLight`] in step, and removes it when the Bevy light goes.
pub fn sync_bevy_lights(
    mut commands: Commands,
    points: Query<(Entity, &PointLight), ChangedOrPlaced<PointLight>>,
    spots: Query<(Entity, &SpotLight), ChangedOrPlaced<SpotLight>>,
    mut removed_points: RemovedComponents<PointLight>,
    mut removed_spots: RemovedComponents<SpotLight>,
    kept: Query<(), With<FromBevyLight>>,
) {
    for (e, l) in &points {
        commands.entity(e).insert((from_point_light(l), FromBevyLight));
    }
    for (e, l) in &spots {
        commands.entity(e).insert((from_spot_light(l), FromBevyLight));
    }
    for e in removed_points.read().chain(removed_spots.read()) {
        if kept.contains(e)
            && let Ok(mut entity) = commands.get_entity(e)
        {
            entity.remove::<(ManifoldLight, FromBevyLight)>();
        }
    }
}
