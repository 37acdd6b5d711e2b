//! Gathering each space's drawables into its [`ManifoldScene`]
//! ([`gather_scenes`]), and the other way, a tracer scene spawned as
//! entities ([`spawn_scene`]).

use super::components::{
    DomainEdges, ManifoldLight, ManifoldLighting, ManifoldMeshes, ManifoldScene, SpotCone, TracedBall,
};
use crate::geometry::isometry;
use crate::placement::{InSpace, ManifoldSpace, Placement, SpaceMembers};
use crate::trace::{Ball, Light, MAX_LIGHTS, MAX_MESHES, Scene, Spot, max_radius};
use bevy::color::{Color, LinearRgba};
use bevy::prelude::*;
use bevy_manifold_core::material::Pbr;
use std::sync::Arc;

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
    Option<&'a ManifoldLighting>,
);

/// Filter: a space root whose space, edges or meshes changed.
type ChangedRoot = Or<(
    Changed<ManifoldSpace>,
    Changed<DomainEdges>,
    Changed<ManifoldMeshes>,
    Changed<SpaceMembers>,
    Changed<ManifoldLighting>,
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
    for (root, ms, edges, old, meshes, members, lighting) in &roots {
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
                        pbr: b.pbr.filter(Pbr::is_valid),
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
                range: l.range.filter(|r| r.is_finite() && *r > 0.0),
                radius: if l.radius.is_finite() {
                    l.radius.clamp(0.0, max_radius(ms.space().geometry()))
                } else {
                    0.0
                },
                spot: l.cone.map(|c| Spot {
                    direction: p.forward(),
                    inner: c.inner,
                    outer: c.outer,
                }),
            })
            .collect();
        let (mut entities, mut balls): (Vec<Entity>, Vec<Ball>) = ball_list.into_iter().unzip();
        // 254 balls at most: with their ghost copies they stay within
        // the GPU's ball array (bevy_manifold_gpu::bindings::MAX_BALLS).
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
            let room = m.meshes.len().min(MAX_MESHES);
            if room < m.meshes.len() {
                warn!(
                    "bevy_manifold: {} meshes in space {}: only the first {MAX_MESHES} are drawn",
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
        scene.lighting = lighting.copied().unwrap_or_default().to_lighting();
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

/// Spawns a tracer [`Scene`]'s balls and lights under `root` (a
/// [`ManifoldSpace`] root) and gives the root [`DomainEdges`] when the scene
/// draws edges; the scene's camera and fog are per camera and left to the
/// caller. What a scene file or [`Scene::default_for`] describes, as
/// entities.
pub fn spawn_scene(commands: &mut Commands, root: Entity, space: &crate::space::Space, scene: &Scene) {
    let g = space.geometry();
    let at = |p: glam::DVec4| Placement::from_isometry(isometry::translation_to(g, p));
    let color = |c: [f32; 3]| Color::linear_rgb(c[0], c[1], c[2]);
    for b in &scene.balls {
        commands.spawn((
            ChildOf(root),
            at(b.center),
            TracedBall {
                pbr: b.pbr,
                ..TracedBall::new(b.radius, color(b.color)).glowing(b.glow)
            },
        ));
    }
    for l in &scene.lights {
        // A spot points along its placement's forward (local -z): the
        // placement at the light turned so that -z is the spot's tangent
        // there, carried back to the origin.
        let placed = match l.spot {
            Some(s) => {
                let to = isometry::translation_to(g, l.position);
                let axis = (isometry::inverse(g, to) * s.direction).truncate();
                let turn = glam::DQuat::from_rotation_arc(glam::DVec3::NEG_Z, axis.normalize_or(glam::DVec3::NEG_Z));
                Placement::from_isometry(to * glam::DMat4::from_quat(turn))
            }
            None => at(l.position),
        };
        commands.spawn((
            ChildOf(root),
            placed,
            ManifoldLight {
                intensity: l.intensity,
                color: color(l.color),
                range: l.range,
                radius: l.radius,
                cone: l.spot.map(|s| SpotCone {
                    inner: s.inner,
                    outer: s.outer,
                }),
            },
        ));
    }
    if let Some(radius) = scene.edge_radius {
        commands.entity(root).insert(DomainEdges { radius });
    }
    commands.entity(root).insert(ManifoldLighting::from(scene.lighting));
}
