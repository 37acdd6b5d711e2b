//! What the tracer draws, as components: balls and lights placed in a
//! manifold, and the domain's edges. [`gather_scenes`] collects them per
//! space into a [`ManifoldScene`] on the space's root entity, rebuilt only
//! when one of them (or the space) changed. The scene is render-agnostic
//! (the CPU reference can trace it as it is); the render world's prepare
//! stage packs it for the GPU when its generation changes.
//!
//! ```
//! use bevy::prelude::*;
//! use bevy_manifold::prelude::*;
//! use glam::DVec3;
//!
//! let mut app = App::new();
//! app.add_plugins((MinimalPlugins, ManifoldPlugin::default()));
//! let space = catalog::torus(1.0);
//! let root = app.world_mut().spawn((ManifoldSpace::new(space.clone()), DomainEdges::default())).id();
//! app.world_mut().spawn((ChildOf(root), TracedBall::new(0.2, Color::srgb(0.9, 0.3, 0.2))));
//! app.world_mut().spawn((ChildOf(root), ManifoldLight::default(), Placement::at(&space, DVec3::Y * 0.3)));
//! app.update();
//! let scene = app.world().get::<ManifoldScene>(root).unwrap();
//! assert_eq!(scene.scene().balls.len(), 1);
//! assert_eq!(scene.scene().lights.len(), 1);
//! assert!(scene.scene().edge_radius.is_some());
//! ```

use crate::placement::{InSpace, ManifoldSpace, ManifoldSystems, Placement, SpaceMembers};
use crate::trace::{Ball, Light, MAX_LIGHTS, Scene, max_radius};
use bevy::color::{Color, LinearRgba};
use bevy::ecs::schedule::{InternedScheduleLabel, ScheduleLabel};
use bevy::prelude::*;
use std::sync::Arc;

/// A ball the tracer draws at the entity's [`Placement`]: an exact metric
/// ball of the space (a round sphere in E3, a hyperbolic or spherical one
/// elsewhere), seen in every copy of the domain.
///
/// ```
/// use bevy::prelude::*;
/// use bevy_manifold::prelude::*;
/// let ball = TracedBall::new(0.25, Color::WHITE);
/// assert_eq!(ball.radius, 0.25);
/// ```
#[derive(Component, Clone, Copy, Debug, PartialEq, Reflect)]
#[reflect(Component, Debug)]
#[require(Placement)]
pub struct TracedBall {
    /// Radius, in the space's own distance.
    pub radius: f64,
    /// Albedo.
    pub color: Color,
    /// Light it gives off, in units of its albedo ([`crate::trace::Ball::glow`]):
    /// 0 for a plain ball; a shot or a lamp glows at 1 or more.
    pub glow: f32,
}

impl TracedBall {
    /// A ball of `radius` and albedo `color`.
    #[must_use]
    pub fn new(radius: f64, color: Color) -> Self {
        TracedBall {
            radius,
            color,
            glow: 0.0,
        }
    }

    /// The same ball, glowing: it shows at least `color * glow` with no
    /// light on it.
    ///
    /// ```
    /// use bevy::prelude::*;
    /// use bevy_manifold::prelude::*;
    /// let shot = TracedBall::new(0.03, Color::srgb(1.0, 0.8, 0.3)).glowing(1.5);
    /// assert_eq!(shot.glow, 1.5);
    /// ```
    #[must_use]
    pub fn glowing(self, glow: f32) -> Self {
        TracedBall { glow, ..self }
    }
}

/// A point light at the entity's [`Placement`]. Its irradiance at distance
/// `d` is `intensity / area(d)`, the area of the geodesic sphere of radius
/// `d` (so light falls off faster in H3 and refocuses in S3).
#[derive(Component, Clone, Copy, Debug, PartialEq, Reflect)]
#[reflect(Component, Debug)]
#[require(Placement)]
pub struct ManifoldLight {
    /// Power.
    pub intensity: f64,
    /// Colour.
    pub color: Color,
}

impl Default for ManifoldLight {
    fn default() -> Self {
        ManifoldLight {
            intensity: 1.0,
            color: Color::WHITE,
        }
    }
}

/// On a [`ManifoldSpace`] root: draw the fundamental domain's edges as tubes
/// of this radius, coloured by edge cycle (edges the pairings glue together
/// share a colour), with a ball at each vertex.
#[derive(Component, Clone, Copy, Debug, PartialEq, Reflect)]
#[reflect(Component, Debug)]
pub struct DomainEdges {
    /// Tube radius, in the space's distance.
    pub radius: f64,
}

impl Default for DomainEdges {
    fn default() -> Self {
        DomainEdges { radius: 0.02 }
    }
}

/// On a [`ManifoldSpace`] root: the space's traced meshes and the entity
/// each belongs to, as [`gather_scenes`] reads them. Kept by the mesh
/// gathering (feature `render`, see `crate::traced_meshes`), replaced only
/// when a mesh, material or placement changed; or inserted by hand, which
/// lasts only until the gathering runs again (any placed entity moving,
/// a mesh added): with the `render` feature, give meshes entities.
#[derive(Component, Clone, Debug, Default, PartialEq)]
pub struct ManifoldMeshes {
    /// The entity of each mesh.
    pub entities: Vec<Entity>,
    /// The meshes, in the tracer's terms.
    pub meshes: Vec<crate::trace::SceneMesh>,
}

/// What the tracer draws in one space, kept on the space's root entity by
/// [`gather_scenes`]: the scene (without a camera), shared. Ball `i` of the
/// scene has object id `i + 1` in the id buffer and belongs to
/// `entities()[i]`; the meshes follow the balls, in ids and in
/// `entities()`. The render world packs it for the GPU when
/// [`ManifoldScene::generation`] changes.
#[derive(Component, Clone, Debug)]
pub struct ManifoldScene {
    scene: Arc<Scene>,
    entities: Arc<Vec<Entity>>,
    generation: u64,
}

impl ManifoldScene {
    /// The scene, for [`crate::trace::render`] (its camera is the identity).
    #[must_use]
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The entity each ball and mesh belongs to, in object-id order (id 1
    /// first).
    #[must_use]
    pub fn entities(&self) -> &[Entity] {
        &self.entities
    }

    /// Bumped each time the objects are rebuilt.
    #[must_use]
    pub fn generation(&self) -> u64 {
        self.generation
    }
}

fn rgb(c: Color) -> [f32; 3] {
    let LinearRgba { red, green, blue, .. } = c.to_linear();
    [red, green, blue]
}

/// Filter: a drawable whose placement, shape, light or parent changed.
type ChangedDrawable = (
    Or<(With<TracedBall>, With<ManifoldLight>)>,
    Or<(
        Changed<Placement>,
        Changed<TracedBall>,
        Changed<ManifoldLight>,
        Changed<InSpace>,
    )>,
);

/// A space root and what the tracer draws there.
type RootData<'a> = (
    Entity,
    &'a ManifoldSpace,
    Option<&'a DomainEdges>,
    Option<&'a ManifoldScene>,
    Option<&'a ManifoldMeshes>,
    Option<&'a SpaceMembers>,
);

/// Filter: a space root whose space, edges or meshes changed.
type ChangedRoot = Or<(
    Changed<ManifoldSpace>,
    Changed<DomainEdges>,
    Changed<ManifoldMeshes>,
    Changed<SpaceMembers>,
)>;

/// Collects the drawables of every space into its [`ManifoldScene`], when
/// anything they are made of changed (a drawable added, removed, moved,
/// restyled or re-parented; the space or its edges changed). A frame where
/// nothing changed costs a few change-detection checks; a frame where
/// something changed reads each space's members ([`SpaceMembers`]), not
/// every drawable in the world.
#[expect(clippy::too_many_arguments, reason = "a system's parameters")]
pub fn gather_scenes(
    mut commands: Commands,
    roots: Query<RootData>,
    changed_roots: Query<(), ChangedRoot>,
    changed: Query<(), ChangedDrawable>,
    balls: Query<(&Placement, &TracedBall)>,
    lights: Query<(&Placement, &ManifoldLight)>,
    mut removed_balls: RemovedComponents<TracedBall>,
    mut removed_lights: RemovedComponents<ManifoldLight>,
    mut removed_edges: RemovedComponents<DomainEdges>,
    mut left_spaces: RemovedComponents<InSpace>,
) {
    let removed = removed_balls.read().count()
        + removed_lights.read().count()
        + removed_edges.read().count()
        + left_spaces.read().count()
        > 0;
    let any_missing = roots.iter().any(|(_, _, _, s, ..)| s.is_none());
    let dirty = removed || any_missing || !changed.is_empty() || !changed_roots.is_empty();
    if !dirty {
        return;
    }
    for (root, ms, edges, old, meshes, members) in &roots {
        let members: Vec<Entity> = members.map(|m| m.iter().collect()).unwrap_or_default();
        let ball_list: Vec<(Entity, Ball)> = members
            .iter()
            .filter_map(|&e| balls.get(e).ok().map(|found| (e, found)))
            .map(|(e, (p, b))| {
                (
                    e,
                    Ball {
                        center: p.position(),
                        // Past the geometry's largest radius (H3: cosh r
                        // overflows f32) the ball is drawn at that radius.
                        radius: b.radius.min(max_radius(ms.space().geometry())),
                        color: rgb(b.color),
                        glow: if b.glow.is_finite() {
                            b.glow.clamp(0.0, crate::trace::MAX_GLOW)
                        } else {
                            0.0
                        },
                    },
                )
            })
            .collect();
        let light_list: Vec<Light> = members
            .iter()
            .filter_map(|&e| lights.get(e).ok())
            .map(|(p, l)| Light {
                position: p.position(),
                intensity: l.intensity,
                color: rgb(l.color),
            })
            .collect();
        let (mut entities, mut balls): (Vec<Entity>, Vec<Ball>) = ball_list.into_iter().unzip();
        // Object ids are bytes: 254 objects at most, balls first.
        if balls.len() > 254 {
            warn!(
                "bevy_manifold: {} traced balls in space {}: only the first 254 are drawn",
                balls.len(),
                ms.space().name()
            );
            balls.truncate(254);
            entities.truncate(254);
        }
        let light_list = if light_list.len() > MAX_LIGHTS {
            warn!(
                "bevy_manifold: {} lights in space {}: only the first {MAX_LIGHTS} light the scene",
                light_list.len(),
                ms.space().name()
            );
            light_list[..MAX_LIGHTS].to_vec()
        } else {
            light_list
        };
        let mut scene = Scene::empty();
        if let Some(m) = meshes {
            // Object ids are bytes: 254 objects at most.
            let room = 254usize.saturating_sub(balls.len()).min(m.meshes.len());
            if room < m.meshes.len() {
                warn!(
                    "bevy_manifold: {} balls and {} meshes in space {}: only 254 objects are drawn",
                    balls.len(),
                    m.meshes.len(),
                    ms.space().name()
                );
            }
            scene.meshes = m.meshes[..room].to_vec();
            entities.extend(&m.entities[..room]);
        }
        scene.balls = balls;
        scene.lights = light_list;
        scene.edge_radius = edges.map(|e| e.radius);
        // An unchanged scene keeps its generation, so nothing downstream
        // repacks or uploads it.
        if let Some(o) = old
            && *o.scene == scene
            && *o.entities == entities
        {
            continue;
        }
        commands.entity(root).insert(ManifoldScene {
            scene: Arc::new(scene),
            entities: Arc::new(entities),
            generation: old.map_or(0, |o| o.generation + 1),
        });
    }
}

/// Runs [`gather_scenes`] after the placement systems, so it sees the
/// frame's final placements. Part of [`crate::ManifoldPlugin`].
#[derive(Debug, Clone)]
pub struct DrawablesPlugin {
    schedule: InternedScheduleLabel,
}

impl Default for DrawablesPlugin {
    fn default() -> Self {
        Self::in_schedule(PostUpdate)
    }
}

impl DrawablesPlugin {
    /// The plugin with its system in `schedule` (the placement systems'
    /// schedule).
    #[must_use]
    pub fn in_schedule(schedule: impl ScheduleLabel) -> Self {
        DrawablesPlugin {
            schedule: schedule.intern(),
        }
    }
}

impl Plugin for DrawablesPlugin {
    fn build(&self, app: &mut App) {
        app.register_type::<TracedBall>()
            .register_type::<ManifoldLight>()
            .register_type::<DomainEdges>()
            .add_systems(self.schedule, gather_scenes.after(ManifoldSystems::Sync));
    }

    fn finish(&self, app: &mut App) {
        // Bevy meshes are traced where the app has them.
        #[cfg(feature = "render")]
        crate::traced_meshes::build(app, self.schedule);
        #[cfg(not(feature = "render"))]
        let _ = app;
    }
}

/// Spawns a tracer [`Scene`]'s balls and lights under `root` (a
/// [`ManifoldSpace`] root) and gives the root [`DomainEdges`] when the scene
/// draws edges; the scene's camera and fog are per camera and left to the
/// caller. What a scene file or [`Scene::default_for`] describes, as
/// entities.
pub fn spawn_scene(commands: &mut Commands, root: Entity, space: &crate::space::Space, scene: &Scene) {
    let g = space.geometry();
    let at = |p: glam::DVec4| Placement::from_isometry(crate::geometry::isometry::translation_to(g, p));
    let color = |c: [f32; 3]| Color::linear_rgb(c[0], c[1], c[2]);
    for b in &scene.balls {
        commands.spawn((ChildOf(root), at(b.center), TracedBall::new(b.radius, color(b.color))));
    }
    for l in &scene.lights {
        commands.spawn((
            ChildOf(root),
            at(l.position),
            ManifoldLight {
                intensity: l.intensity,
                color: color(l.color),
            },
        ));
    }
    if let Some(radius) = scene.edge_radius {
        commands.entity(root).insert(DomainEdges { radius });
    }
}
