//! Culling (`TraceSettings::cull`): a segment tests only the objects near
//! the faces it comes near. Checked against brute force: every object a
//! segment really hits passes the test, and whole images are identical
//! with culling on and off.

use bevy_manifold_core::geometry::Real;
use bevy_manifold_core::prelude::*;
use bevy_manifold_core::trace::step::{ALL_FACES, Ray, hit_ball, hit_tube, may_hit, near_faces};
use bevy_manifold_core::trace::{Candidate, FaceGroups, FlatScene, Walker, chart_segment, each_candidate, tree_leaves};
use bevy_manifold_test_support::Rng;
use bevy_manifold_test_support::stress::{self, face_middle};
use glam::DVec4;

/// The spaces: the catalog, generator spaces up to 20 faces, and
/// Seifert-Weber's 52-face domain, whose faces fold onto the masks' 32 bits.
fn spaces() -> Vec<(String, Space)> {
    let mut out: Vec<(String, Space)> = catalog::NAMES
        .iter()
        .map(|n| (n.to_string(), catalog::by_name(n).expect("catalog")))
        .collect();
    for name in ["weeks", "lens-5-2", "torus-bcc", "binary-octahedral"] {
        out.push((name.to_string(), catalog::resolve(name).expect("library")));
    }
    let (x, y, z) = stress::FIFTY_TWO_FACES;
    let sw52 = stress::seifert_weber_about(x, y, z).expect("builds");
    assert_eq!(sw52.faces().len(), 52, "the off-centre domain");
    out.push(("seifert-weber/52".into(), sw52));
    out
}

/// The default scene (a ball, the edges, a light), and one without edges
/// where small balls straddle faces (their ghosts carry masks).
fn scenes(space: &Space) -> Vec<(&'static str, Scene)> {
    let mut ghosts = Scene::default_for(space);
    ghosts.edge_radius = None;
    let r = space.inradius();
    for f in 0..space.faces().len().min(6) {
        ghosts.balls.push(Ball {
            center: space
                .geometry()
                .normalize_point::<f64>(face_middle(space, f) * 0.97 + DVec4::W * 0.03),
            radius: 0.08 * r,
            color: [0.2, 0.8, 0.4],
            glow: 0.0,
            pbr: None,
        });
    }
    vec![
        ("default", Scene::default_for(space)),
        ("ghosts", ghosts),
        ("swarm", stress::swarm(space, 120, 7)),
    ]
}

/// Counts over many segments: object tests made, culled, and hits on
/// objects that carry a mask (so the check below is not vacuous); balls
/// with no mask, those the ball tree skips, and hits on them.
#[derive(Default)]
struct Counts {
    tests: usize,
    culled: usize,
    masked_hits: usize,
    interior: usize,
    interior_skipped: usize,
    interior_hits: usize,
}

/// Walks random rays segment by segment; on each, every ball and tube the
/// segment hits (tested by brute force) must pass `may_hit` and be among
/// the objects `each_candidate` hands the tracer, each once.
fn check_segments<R: Real>(name: &str, space: &Space, flat: &FlatScene<R>, rng: &mut Rng, counts: &mut Counts) {
    let g = space.geometry();
    let zero = R::of(0.0);
    for _ in 0..800 {
        let ray = rng.ray_inside(space);
        let ray = Ray {
            origin: R::v4_of(ray.origin),
            dir: R::v4_of(ray.dir),
        };
        let mut walk = Walker::new(ray, R::m4_of(glam::DMat4::IDENTITY));
        for _ in 0..8 {
            let (face, t_end) = walk.segment_end(&flat.faces);
            let near = near_faces(
                &flat.faces.planes,
                flat.faces.near_scale,
                flat.near_reach,
                &walk.ray,
                t_end,
            );
            // What the tracer tests on this segment.
            let mut handed = std::collections::HashSet::new();
            each_candidate(flat, &walk.ray, t_end, ([near; 2], true), 0.0, |c| {
                assert!(handed.insert(c), "{name}: {c:?} handed out twice");
                t_end
            });
            let mut check = |mask: u32, hit: Option<R>, what: &str| {
                counts.tests += 1;
                let shown = may_hit(mask, near);
                counts.culled += usize::from(!shown);
                if let Some(t) = hit
                    && t <= t_end
                {
                    counts.masked_hits += usize::from(mask != 0);
                    assert!(
                        shown,
                        "{name}: {what} (mask {mask:#x}) hit at t {} but culled (near {near:#x})",
                        t.f64()
                    );
                }
            };
            for (i, b) in flat.balls.iter().enumerate() {
                let hit = hit_ball(g, &walk.ray, b.center, b.k, zero);
                check(b.face_mask, hit, "a ball");
                if hit.is_some_and(|t| t <= t_end) {
                    assert!(
                        handed.contains(&Candidate::Ball(i)),
                        "{name}: ball {i} is hit but not tested"
                    );
                }
            }
            // The ball tree: every ball with no mask that the segment
            // hits is in a leaf the walk visits.
            let interior = flat.groups.balls[0] as usize;
            let mut visited = vec![false; interior];
            match chart_segment(&walk.ray, t_end).filter(|_| !flat.ball_tree.is_empty()) {
                Some((a, d)) => tree_leaves(&flat.ball_tree, a, d, 0.0, |leaf| {
                    for i in leaf {
                        assert!(!visited[i], "{name}: ball {i} is in two leaves");
                        visited[i] = true;
                    }
                }),
                None => visited.fill(true),
            }
            for (i, b) in flat.balls[..interior].iter().enumerate() {
                counts.interior += 1;
                counts.interior_skipped += usize::from(!visited[i]);
                if let Some(t) = hit_ball(g, &walk.ray, b.center, b.k, zero)
                    && t <= t_end
                {
                    counts.interior_hits += 1;
                    assert!(
                        visited[i],
                        "{name}: ball {i} hit at t {} but its leaf is skipped",
                        t.f64()
                    );
                }
            }
            for (i, tube) in flat.tubes.iter().enumerate() {
                let hit = hit_tube(g, &walk.ray, &tube.segment, flat.tube_k, zero);
                check(tube.face_mask, hit, "a tube");
                if hit.is_some_and(|t| t <= t_end) {
                    assert!(
                        handed.contains(&Candidate::Tube(i)),
                        "{name}: tube {i} is hit but not tested"
                    );
                }
            }
            let Some(f) = face else { break };
            let end = bevy_manifold_core::trace::step::advance(g, &walk.ray, t_end);
            walk.step(&flat.faces, Some(f), end, true);
        }
    }
}

#[test]
fn no_object_a_segment_hits_is_culled() {
    let mut rng = Rng(19);
    for (name, space) in spaces() {
        for (what, scene) in scenes(&space) {
            let mut c64 = Counts::default();
            check_segments(
                &name,
                &space,
                &FlatScene::<f64>::new(&space, &scene),
                &mut rng,
                &mut c64,
            );
            let mut c32 = Counts::default();
            check_segments(
                &name,
                &space,
                &FlatScene::<f32>::new(&space, &scene),
                &mut rng,
                &mut c32,
            );
            let culled = c64.culled as f64 / c64.tests as f64;
            let skipped = c64.interior_skipped as f64 / c64.interior.max(1) as f64;
            eprintln!(
                "{name:<22} {what:<8} {} tests, {:.1}% culled (f32 {:.1}%), {} hits on masked objects; \
                 {:.1}% of {} interior ball tests skipped by the tree (f32 {:.1}%), {} hits on them",
                c64.tests,
                100.0 * culled,
                100.0 * c32.culled as f64 / c32.tests as f64,
                c64.masked_hits + c32.masked_hits,
                100.0 * skipped,
                c64.interior,
                100.0 * c32.interior_skipped as f64 / c32.interior.max(1) as f64,
                c64.interior_hits + c32.interior_hits,
            );
            // A swarm of small balls: a segment meets few of their boxes.
            if what == "swarm" {
                assert!(
                    c64.interior_hits > 100,
                    "{name}: the swarm is hit ({})",
                    c64.interior_hits
                );
                assert!(
                    skipped > 0.6,
                    "{name}: the tree skips only {:.1}% of the swarm",
                    100.0 * skipped
                );
            }
            assert!(
                c64.masked_hits > 10,
                "{name} {what}: masked objects are hit ({})",
                c64.masked_hits
            );
            // The default scene's objects are almost all edges and joints:
            // a segment near one or two faces skips most of them.
            if what == "default" {
                assert!(culled > 0.6, "{name}: only {:.1}% of tests culled", 100.0 * culled);
            }
        }
    }
}

#[test]
fn images_are_the_same_with_culling_on_and_off() {
    for (name, space) in spaces() {
        let mut scenes = scenes(&space);
        scenes.push(("paper", Scene::paper_default(&space)));
        // Cone tracing too on the default scene: its balls, joints
        // included, are culled by wider near faces than its tubes.
        let cones = scenes
            .iter()
            .filter(|(what, _)| *what == "default")
            .map(|(_, s)| ("cones", s.clone()));
        let scenes: Vec<_> = scenes.iter().cloned().chain(cones.collect::<Vec<_>>()).collect();
        for (what, scene) in scenes {
            let on = TraceSettings {
                width: 96,
                height: 64,
                levels: 8,
                footprint: what == "cones",
                ..TraceSettings::default()
            };
            let off = TraceSettings {
                cull: false,
                ..on.clone()
            };
            for (precision, a, b) in [
                (
                    "f64",
                    render::<f64>(&space, &scene, &on),
                    render::<f64>(&space, &scene, &off),
                ),
                (
                    "f32",
                    render::<f32>(&space, &scene, &on),
                    render::<f32>(&space, &scene, &off),
                ),
            ] {
                let differ = a.pixels.iter().zip(&b.pixels).filter(|(p, q)| p != q).count();
                assert_eq!(
                    differ, 0,
                    "{name} {what} {precision}: {differ} pixels differ with culling"
                );
                let hit = a.pixels.iter().filter(|p| p.object != 0).count();
                assert!(hit > 100, "{name} {what}: the view sees objects ({hit})");
            }
        }
    }
}

#[test]
fn groups_hold_every_object_once_and_a_segment_walks_the_near_ones() {
    let space = catalog::seifert_weber();
    let flat = FlatScene::<f64>::new(&space, &Scene::default_for(&space));
    let g = &flat.groups;
    // 12 faces: 13 starts, the last the count; non-decreasing.
    assert_eq!(g.tubes.len(), 13);
    assert_eq!(*g.tubes.last().unwrap() as usize, flat.tubes.len());
    assert!(g.tubes.windows(2).all(|w| w[0] <= w[1]));
    // Each edge of the dodecahedron lies on two faces: every tube masked.
    assert_eq!(g.tubes[0], 0, "no tube is unmasked");
    assert!(flat.tubes.iter().all(|t| t.face_mask.count_ones() == 2));
    // Each vertex joint lies on three faces; the central ball on none.
    let joints = flat.balls.iter().filter(|b| b.id == bevy_manifold_core::trace::EDGE_ID);
    assert!(joints.clone().all(|b| b.face_mask.count_ones() == 3));
    assert_eq!(joints.count(), 20);
    assert_eq!(g.balls[0], 1, "the one unmasked ball comes first");
    // All faces near: every object walked once.
    let all: Vec<usize> = FaceGroups::ranges(&g.tubes, ALL_FACES).flatten().collect();
    assert_eq!(all, (0..flat.tubes.len()).collect::<Vec<_>>());
    // Near face 0 only: its group, each tube in it has face 0 as first face.
    let near0: Vec<usize> = FaceGroups::ranges(&g.tubes, 1).flatten().collect();
    assert!(!near0.is_empty());
    assert!(near0.iter().all(|&i| flat.tubes[i].face_mask.trailing_zeros() == 0));
    // The tubes along face 0's five edges are those with bit 0.
    assert_eq!(flat.tubes.iter().filter(|t| t.face_mask & 1 != 0).count(), 5);
}

/// A ball's chart box holds every point of the ball and is tight: points
/// on its sphere, reached by the exponential map from its centre (an
/// independent route to the ball), lie inside, and on each side some come
/// within 1% of the box's width of it. In the three geometries, for balls
/// of many sizes and places.
#[test]
fn a_balls_chart_box_holds_it_and_touches_it() {
    let mut rng = Rng(23);
    for name in ["torus", "seifert-weber", "poincare"] {
        let space = catalog::by_name(name).expect("catalog");
        let g = space.geometry();
        for _ in 0..40 {
            let c = rng.ray_inside(&space).origin;
            let r = (0.02 + 0.6 * rng.next_f64()) * space.inradius();
            let k = bevy_manifold_core::trace::step::radius_param(g, r);
            let (lo, hi) = bevy_manifold_core::trace::ball_box(g, c, k);
            let mut reach = [
                f64::INFINITY,
                f64::INFINITY,
                f64::INFINITY,
                f64::NEG_INFINITY,
                f64::NEG_INFINITY,
                f64::NEG_INFINITY,
            ];
            for _ in 0..4000 {
                let v = rng.unit().extend(rng.next_f64() - 0.5);
                let u = g.normalize_tangent::<f64>(c, v);
                let q = g.exp::<f64>(c, u, r).0;
                let x = q.truncate() / q.w;
                for i in 0..3 {
                    assert!(
                        f64::from(lo[i]) <= x[i] && x[i] <= f64::from(hi[i]),
                        "{name}: point {x:?} of the ball (r {r}) outside its box {lo:?}..{hi:?}"
                    );
                    reach[i] = reach[i].min(x[i]);
                    reach[3 + i] = reach[3 + i].max(x[i]);
                }
            }
            for i in 0..3 {
                let width = f64::from(hi[i] - lo[i]);
                assert!(
                    reach[i] - f64::from(lo[i]) < 0.01 * width && f64::from(hi[i]) - reach[3 + i] < 0.01 * width,
                    "{name}: box {lo:?}..{hi:?} is loose on axis {i} (points reach {} to {})",
                    reach[i],
                    reach[3 + i]
                );
            }
        }
    }
}

/// The edge walk hands out, for any near faces, exactly the tubes whose
/// edge's two faces are near (and those with no edge bits), once each and
/// in their sorted order: checked against a scan of every tube, whose
/// edge bits are checked against the domain's own edge list. Every tube a
/// segment may hit (its whole mask near) is among them. In every space,
/// the 52-face domain included, whose faces fold onto 32 bits.
#[test]
fn the_edge_walk_finds_the_tubes_of_the_near_edges() {
    let mut rng = Rng(41);
    for (name, space) in spaces() {
        let flat = FlatScene::<f64>::new(&space, &Scene::default_for(&space));
        let g = &flat.groups;
        let bit = |f: usize| 1u32 << (f % 32);
        // Each tube's edge bits are those of the polyhedron edge it runs
        // along (found by its ends), or for a folded repeat one of them,
        // or 0.
        let mut keys = std::collections::HashSet::new();
        for t in flat.tubes.iter().filter(|t| t.edge != 0) {
            assert!(keys.insert(t.edge), "{name}: two tubes with edge bits {:b}", t.edge);
        }
        for t in &flat.tubes {
            let edge = space
                .edges()
                .iter()
                .find(|e| {
                    let [a, b] = e.vertices.map(|v| space.vertices()[v].point);
                    (a - t.segment.a).length() < 1e-9 && (b - t.segment.b).length() < 1e-9
                })
                .unwrap_or_else(|| panic!("{name}: a tube is on no edge"));
            let faces = bit(edge.faces[0]) | bit(edge.faces[1]);
            let alone = [bit(edge.faces[0]), bit(edge.faces[1])];
            assert!(
                t.edge == faces || alone.contains(&t.edge) || t.edge == 0,
                "{name}: edge bits {:b}, faces {faces:b}",
                t.edge
            );
            assert_eq!(t.edge & !t.face_mask, 0, "{name}: edge bits outside the mask");
            if t.edge != faces {
                assert!(
                    keys.contains(&faces) || t.face_mask & faces != faces,
                    "{name}: a tube lost its key"
                );
            }
        }
        if space.faces().len() <= 32 {
            assert!(
                flat.tubes.iter().all(|t| t.edge.count_ones() == 2),
                "{name}: every edge has its own two bits"
            );
        }
        let mut nears = near_sets(&mut rng, 200);
        for f in 0..space.faces().len().min(32) {
            nears.push(1 << f);
            nears.push(!(1 << f));
        }
        for near in nears {
            let walked: Vec<usize> = FaceGroups::edge_walk(&g.tubes, &g.edges, near).collect();
            let scanned: Vec<usize> = (0..flat.tubes.len())
                .filter(|&i| flat.tubes[i].edge & !near == 0)
                .collect();
            assert_eq!(walked, scanned, "{name}: near {near:032b}");
            for (i, t) in flat.tubes.iter().enumerate() {
                if may_hit(t.face_mask, near) {
                    assert!(walked.contains(&i), "{name}: tube {i} may be hit but is not walked");
                }
            }
        }
    }
}

/// Vertex joints ride on tubes (`FlatTube::joint`): each joint at most
/// once, on a tube along an edge that ends at it (found by geometry, the
/// tube's end points), after every face group; and for any faces a
/// segment comes near, every ball that may be hit there is in a walked
/// group or carried by a walked tube. In Seifert-Weber's dodecahedron
/// (20 vertices, 30 edges) every joint rides on a tube, so no ball is
/// left in a face group.
#[test]
fn every_joint_a_segment_may_hit_is_walked_with_a_tube() {
    let mut rng = Rng(43);
    for (name, space) in spaces() {
        let flat = FlatScene::<f64>::new(&space, &Scene::default_for(&space));
        let g = &flat.groups;
        let grouped = *g.balls.last().expect("starts") as usize;
        let mut carried = vec![false; flat.balls.len()];
        for t in &flat.tubes {
            let Some(j) = t.joint else { continue };
            assert!(
                j >= grouped && j < flat.balls.len(),
                "{name}: joint {j} inside the groups"
            );
            assert!(!carried[j], "{name}: joint {j} on two tubes");
            carried[j] = true;
            let joint = &flat.balls[j];
            assert_eq!(
                joint.id,
                bevy_manifold_core::trace::EDGE_ID,
                "{name}: a carried ball is not a joint"
            );
            let at_end = [t.segment.a, t.segment.b]
                .iter()
                .any(|&end| (end - joint.center).length() < 1e-9);
            assert!(at_end, "{name}: joint {j} is not at an end of its tube");
            // So that a segment near all of the joint's faces walks the
            // tube, keyed (its edge bits) or not (its mask).
            assert_eq!(
                t.face_mask & !joint.face_mask,
                0,
                "{name}: the tube's faces outside the joint's mask"
            );
        }
        assert!(
            carried[grouped..].iter().all(|&c| c),
            "{name}: a ball after the groups that no tube carries"
        );
        let unkeyed = flat.tubes.iter().filter(|t| t.edge == 0).count();
        // The tubes before the first group, which the GPU's
        // MANY_UNKEYED_TUBES is decided by (TraceDefs::for_objects).
        assert_eq!(g.tubes[0] as usize, unkeyed, "{name}");
        assert!(
            space.faces().len() > 32 || unkeyed == 0,
            "{name}: an unkeyed tube in 32 faces or fewer"
        );
        let mut nears = near_sets(&mut rng, 300);
        for v in space.vertices() {
            // The faces at a vertex, as the segments passing it see them.
            let at: u32 = space
                .faces()
                .iter()
                .enumerate()
                .filter(|(_, f)| {
                    bevy_manifold_core::geometry::plane::signed_distance(space.geometry(), f.plane, v.point).abs()
                        < 1e-9
                })
                .fold(0, |m, (i, _)| m | 1 << (i % 32));
            nears.push(at);
        }
        for near in nears {
            let mut walked: Vec<usize> = FaceGroups::ranges(&g.balls, near).flatten().collect();
            // The tubes with no edge bits are walked where their faces are
            // near (each_candidate).
            walked.extend(
                FaceGroups::edge_walk(&g.tubes, &g.edges, near)
                    .filter(|&t| flat.tubes[t].edge != 0 || may_hit(flat.tubes[t].face_mask, near))
                    .filter_map(|t| flat.tubes[t].joint),
            );
            for (i, b) in flat.balls.iter().enumerate() {
                if may_hit(b.face_mask, near) {
                    assert!(
                        walked.contains(&i),
                        "{name}: ball {i} may be hit near {near:032b} but is not walked"
                    );
                }
            }
        }
        if name == "seifert-weber" {
            assert_eq!(flat.balls.len(), 21, "{name}: the ball and 20 joints");
            assert_eq!(grouped, 1, "{name}: only the central ball in the groups");
            assert!(g.balls.iter().all(|&s| s == 1), "{name}: {:?}", g.balls);
        }
    }
}

/// Sets of near faces to walk with: all, none, and `n` random ones (each
/// bit set with probability 3/4).
fn near_sets(rng: &mut Rng, n: usize) -> Vec<u32> {
    let mut nears = vec![ALL_FACES, 0];
    nears.extend((0..n).map(|_| (rng.next_f64() * 2f64.powi(32)) as u32 | (rng.next_f64() * 2f64.powi(32)) as u32));
    nears
}
