//! The instance tree (`FlatScene::instance_trees`): a level of thousands
//! of mesh instances traces exactly the hits of brute force (every
//! instance tested on every segment), while a segment tests only a few
//! of them.

use bevy_manifold_core::geometry::Real;
use bevy_manifold_core::mesh::bvh::hit_box;
use bevy_manifold_core::prelude::*;
use bevy_manifold_core::trace::step::{ALL_FACES, Ray, near_faces};
use bevy_manifold_core::trace::{
    Candidate, FlatScene, InstanceTree, MIN_INSTANCE_TREE, Walker, ball_box, chart_fraction, chart_segment,
    each_candidate, octant,
};
use bevy_manifold_test_support::Rng;
use bevy_manifold_test_support::stress::props;

/// 4,000 rays (80x50), in f64, with the tree and with every instance
/// tested: the same object in every pixel, at the same distance.
fn same_as_brute_force(name: &str, n: usize, size: f64) {
    let space = catalog::resolve(name).expect("catalog");
    let mut scene = props(&space, n, size, 5);
    scene.lights.clear();
    let flat = FlatScene::<f64>::new(&space, &scene);
    assert!(
        !flat.instance_trees[0].is_empty(),
        "{name}: the interior instances have a tree"
    );
    let settings = |cull| TraceSettings {
        width: 80,
        height: 50,
        levels: 4,
        cull,
        ..TraceSettings::default()
    };
    let tree = render::<f64>(&space, &scene, &settings(true));
    let brute = render::<f64>(&space, &scene, &settings(false));
    let first_mesh = scene.balls.len() as u32 + 1;
    let mut on_meshes = std::collections::HashSet::new();
    for (k, (a, b)) in tree.pixels.iter().zip(&brute.pixels).enumerate() {
        assert_eq!(a.object, b.object, "{name}: pixel {k} sees another object");
        assert!(
            (a.distance - b.distance).abs() <= 1e-6 * (1.0 + b.distance.abs()),
            "{name}: pixel {k} at {} against {}",
            a.distance,
            b.distance
        );
        if a.object >= first_mesh {
            on_meshes.insert(a.object);
        }
    }
    // Not vacuous: the rays see many different instances.
    assert!(on_meshes.len() > 100, "{name}: only {} instances seen", on_meshes.len());
}

#[test]
fn ten_thousand_instances_in_the_torus_trace_the_brute_force_hits() {
    same_as_brute_force("torus", 10_000, 0.03);
}

#[test]
fn instances_in_hyperbolic_and_spherical_spaces_trace_the_brute_force_hits() {
    same_as_brute_force("seifert-weber", 2_000, 0.05);
    same_as_brute_force("poincare", 2_000, 0.05);
}

/// Every segment of random rays: each instance it hits (brute force, by
/// its bounding ball's chart box) is handed out when nothing nearer was
/// found, and a segment is handed few of the 10,000.
#[test]
fn a_segment_is_handed_every_instance_it_meets_and_few_others() {
    for (name, n) in [("torus", 10_000), ("seifert-weber", 3_000), ("poincare", 3_000)] {
        let space = catalog::resolve(name).expect("catalog");
        let scene = props(&space, n, 0.03, 9);
        let flat = FlatScene::<f32>::new(&space, &scene);
        let g = space.geometry();
        let mut rng = Rng(3);
        let (mut handed_total, mut segments, mut met_total) = (0usize, 0usize, 0usize);
        for _ in 0..300 {
            let r = rng.ray_inside(&space);
            let ray = Ray {
                origin: f32::v4_of(r.origin),
                dir: f32::v4_of(r.dir),
            };
            let mut walk = Walker::new(ray, f32::m4_of(glam::DMat4::IDENTITY));
            for _ in 0..3 {
                let (face, t_end) = walk.segment_end(&flat.faces);
                let near = near_faces(
                    &flat.faces.planes,
                    flat.faces.near_scale,
                    flat.near_reach,
                    &walk.ray,
                    t_end,
                );
                let mut handed = std::collections::HashSet::new();
                each_candidate(&flat, &walk.ray, t_end, ([near; 2], true), 0.0, |c| {
                    if let Candidate::Instance(i) = c {
                        assert!(handed.insert(i), "{name}: instance {i} handed out twice");
                    }
                    t_end
                });
                // Brute force: the instances whose chart box the segment's
                // chart image meets, of the groups the segment walks.
                if let Some((a, d)) = chart_segment(&walk.ray, t_end) {
                    let inv = bevy_manifold_core::mesh::bvh::safe_inverse(d);
                    for (i, inst) in flat.instances.iter().enumerate() {
                        let (lo, hi) = ball_box(g, f32::v4_f64(inst.center), inst.k.f64());
                        let walked = inst.face_mask & !near == 0;
                        if walked && hit_box(a, inv, lo, hi, 1.0).is_some() {
                            met_total += 1;
                            assert!(
                                handed.contains(&i),
                                "{name}: instance {i} meets the segment but is not handed out"
                            );
                        }
                    }
                }
                handed_total += handed.len();
                segments += 1;
                let Some(f) = face else { break };
                let end = bevy_manifold_core::trace::step::advance(g, &walk.ray, t_end);
                walk.step(&flat.faces, Some(f), end, true);
            }
        }
        let mean = handed_total as f64 / segments as f64;
        assert!(met_total > segments, "{name}: segments meet instances ({met_total})");
        // A walk hands out the leaves it meets (up to four instances
        // each), not the level.
        assert!(
            mean < 0.02 * n as f64,
            "{name}: {mean:.1} of {n} instances handed to a segment on average"
        );
    }
}

/// The nearest hit so far prunes the walk: a visitor that reports a hit
/// at the very start is handed, per group, the first leaf it meets and
/// then only leaves whose boxes hold the segment's start; and `chart_fraction` maps the ends of the segment to
/// 0 (plus its margin) and 1.
#[test]
fn the_nearest_hit_so_far_ends_the_walk_of_boxes_beyond_it() {
    let space = catalog::torus(1.0);
    let scene = props(&space, 5_000, 0.03, 4);
    let flat = FlatScene::<f64>::new(&space, &scene);
    let mut rng = Rng(8);
    let (mut pruned, mut whole, mut bound) = (0usize, 0usize, 0usize);
    for _ in 0..200 {
        let ray = rng.ray_inside(&space);
        let walk = Walker::new(ray, glam::DMat4::IDENTITY);
        let (_, t_end) = walk.segment_end(&flat.faces);
        let count = |limit: f64| {
            let mut n = 0;
            each_candidate(&flat, &walk.ray, t_end, ([ALL_FACES; 2], true), 0.0, |c| {
                n += usize::from(matches!(c, Candidate::Instance(_)));
                limit
            });
            n
        };
        pruned += count(0.0);
        whole += count(t_end);
        // Reporting a hit at the start, a group's walk is handed its first
        // met leaf (before any report) and then only leaves whose boxes
        // hold the first millionth of the segment.
        let (a, d) = chart_segment(&walk.ray, t_end).expect("E3");
        let inv = bevy_manifold_core::mesh::bvh::safe_inverse(d);
        let at_start = flat
            .instances
            .iter()
            .filter(|i| {
                let (lo, hi) = ball_box(space.geometry(), i.center, i.k);
                hit_box(a, inv, lo, hi, 1e-5).is_some()
            })
            .count();
        bound += 4 * flat.instance_trees.len() + 4 * at_start;
        assert_eq!(chart_fraction(&walk.ray, t_end, t_end), 1.0);
        let s0 = chart_fraction(&walk.ray, t_end, 0.0);
        assert!(s0 > 0.0 && s0 < 1e-5);
        // Halfway in E3 is halfway along the chart segment.
        let half = chart_fraction(&walk.ray, t_end, 0.5 * t_end);
        assert!((half - 0.5).abs() < 1e-3, "{half}");
    }
    assert!(pruned <= bound, "pruned {pruned} against a bound of {bound}");
    assert!(whole > 3 * pruned, "pruned {pruned} against {whole}");
}

/// The tree's structure: in each of the eight orders every instance of
/// the group is in exactly one leaf, every node's box holds its leaves'
/// instances' boxes, and the skip links lead past each subtree.
#[test]
fn every_order_holds_each_instance_once_inside_its_boxes() {
    let mut rng = Rng(12);
    let boxes: Vec<([f32; 3], [f32; 3])> = (0..500)
        .map(|_| {
            let c = rng.in_box(10.0).map(|x| x as f32);
            let r = 0.05 + 0.2 * rng.next_f64() as f32;
            (c.map(|x| x - r), c.map(|x| x + r))
        })
        .collect();
    let start = 40;
    let (tree, order) = InstanceTree::over(&boxes, start);
    assert_eq!(tree.orders.len(), 8);
    let mut sorted = order.clone();
    sorted.sort_unstable();
    assert_eq!(sorted, (0..500).collect::<Vec<u32>>());
    for (o, t) in tree.orders.iter().enumerate() {
        let mut seen = vec![0u32; 500];
        for (i, n) in t.nodes.iter().enumerate() {
            let past = t.skip[i] as usize;
            assert!(past > i && past <= t.nodes.len(), "order {o}: skip of node {i}");
            if n.count > 0 {
                for j in n.first..n.first + n.count {
                    let k = (j - start) as usize;
                    seen[k] += 1;
                    let (lo, hi) = boxes[order[k] as usize];
                    // Every node whose subtree holds this leaf holds its box.
                    for (a, up) in t.nodes[..=i].iter().enumerate() {
                        if (t.skip[a] as usize) > i {
                            assert!((0..3).all(|c| up.min[c] <= lo[c] && up.max[c] >= hi[c]), "order {o}");
                        }
                    }
                }
            }
        }
        assert!(seen.iter().all(|&s| s == 1), "order {o}: each instance once");
    }
    // A small group gets no tree and keeps its order.
    let (small, kept) = InstanceTree::over(&boxes[..MIN_INSTANCE_TREE - 1], 0);
    assert!(small.is_empty());
    assert_eq!(kept, (0..MIN_INSTANCE_TREE as u32 - 1).collect::<Vec<_>>());
    assert_eq!(octant([1.0f32, -2.0, 0.0]), 2);
    assert_eq!(octant([-1.0f32, -2.0, -3.0]), 7);
}
