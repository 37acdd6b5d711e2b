//! Culling: which objects a segment of a ray can hit
//! ([`each_candidate`]): of the objects near the domain's faces, only
//! those whose faces the segment comes near, walked by their groups
//! ([`super::face_groups`]), each edge tube only where both its edge's
//! faces are near ([`FaceGroups::edge_walk`]), with the vertex joint it
//! carries ([`super::FlatTube::joint`]); of the balls inside the domain,
//! only those in the leaves of the ball tree the segment meets
//! ([`super::ball_tree`]); of a group of many mesh instances, only those
//! in the leaves of its tree the segment meets before the nearest hit
//! ([`super::instance_tree`]).
//!
//! WGSL twin: `shaders/cull.wgsl` in `bevy_manifold_gpu` (`each_candidate`,
//! which walks the same groups from the groups uniform); `near_faces` and
//! `may_hit` are in `shaders/step.wgsl`.

use super::ball_tree::{chart_segment, tree_leaves};
use super::face_groups::FaceGroups;
use super::flat::FlatScene;
use super::instance_tree::tree_instances;
use super::step::{Ray, may_hit};
use crate::geometry::Real;

/// One object a segment may meet, as [`each_candidate`] hands them out.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Candidate {
    /// An index into [`FlatScene::balls`].
    Ball(usize),
    /// An index into [`FlatScene::tubes`].
    Tube(usize),
    /// An index into [`FlatScene::instances`].
    Instance(usize),
}

/// Hands `visit` each object a segment of `ray` ending at `t_end` may
/// meet, in a fixed order: balls, tubes, mesh instances. With `cull`,
/// objects whose faces the segment does not come near (`near_balls` for
/// balls, `near` for the others, from [`super::step::near_faces`]: a cone grows balls
/// further) are left out: only the groups of near faces are walked
/// ([`FaceGroups`]), of the tubes only those whose edge's two faces are
/// near ([`FaceGroups::edge_walk`]), each with the vertex joint it
/// carries ([`super::FlatTube::joint`]), so walked by `near_balls`; and
/// of the balls with no face mask
/// only those in the leaves of [`FlatScene::ball_tree`] whose boxes,
/// padded by `pad`, the segment's chart image meets ([`tree_leaves`]), or
/// all of them where there is no tree (fewer than
/// [`super::MIN_BALL_TREE`]); and of each walked group of instances
/// that has a tree ([`FlatScene::instance_trees`]) only those in the
/// leaves whose boxes the segment's chart image meets before the chart
/// parameter `visit` last returned ([`tree_instances`]): `visit` returns
/// how far along the ray a hit still matters (the nearest hit so far, or
/// `t_end`; 0 once nothing more is wanted). Without `cull` (and with
/// `near_balls` and `near` all faces) every object is handed out once. The tracer
/// (`trace_ray`) tests exactly these; whoever visits them still checks
/// each one's face mask ([`super::step::may_hit`]). WGSL twin:
/// `each_candidate` in `shaders/cull.wgsl`.
pub fn each_candidate<R: Real>(
    flat: &FlatScene<R>,
    ray: &Ray<R>,
    t_end: R,
    ([near_balls, near], cull): ([u32; 2], bool),
    pad: f32,
    mut visit: impl FnMut(Candidate) -> R,
) {
    let groups = &flat.groups;
    // The segment in the chart, once for the ball tree and the instance
    // trees; none with culling off or an end past the chart's horizon.
    let chart = chart_segment(ray, t_end).filter(|_| cull);
    let mut ranges = FaceGroups::ranges(&groups.balls, near_balls);
    let interior = ranges.next().unwrap_or_default();
    match chart.filter(|_| pad.is_finite() && !flat.ball_tree.is_empty()) {
        Some((a, d)) => tree_leaves(&flat.ball_tree, a, d, pad, |leaf| {
            leaf.for_each(|i| {
                visit(Candidate::Ball(i));
            })
        }),
        None => interior.for_each(|i| {
            visit(Candidate::Ball(i));
        }),
    }
    ranges.flatten().for_each(|i| {
        visit(Candidate::Ball(i));
    });
    // The tubes a segment near the faces `near_balls` walks: those near
    // `near` among them (near_balls holds near), each followed by the
    // vertex joint it carries. Of the tubes with no edge bits, only those
    // whose faces are all near (the GPU, of the first 32 only).
    let unkeyed = groups.tubes.first().map_or(0, |&s| s as usize);
    let walked = FaceGroups::edge_walk(&groups.tubes, &groups.edges, near_balls)
        .filter(|&i| i >= unkeyed || may_hit(flat.tubes[i].face_mask, near_balls));
    for i in walked {
        visit(Candidate::Tube(i));
        if let Some(j) = flat.tubes[i].joint {
            visit(Candidate::Ball(j));
        }
    }
    // The instances: of a group with a tree, those of the leaves the
    // segment meets before the nearest hit so far, nearest leaves first.
    for (group, range) in FaceGroups::groups(&groups.instances, near) {
        match (chart, flat.instance_trees.get(group)) {
            (Some(ad), Some(tree)) if !tree.is_empty() => tree_instances(tree, (ray, t_end), ad, |leaf| {
                leaf.fold(t_end, |_, i| visit(Candidate::Instance(i)))
            }),
            _ => range.for_each(|i| {
                visit(Candidate::Instance(i));
            }),
        }
    }
}
