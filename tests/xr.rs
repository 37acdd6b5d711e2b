//! VR without a headset: the eyes, hands and locomotion of
//! `bevy_manifold::xr` driven as bevy_mod_openxr drives them (one
//! `XrCamera` per eye under the tracking root, with the off-centre
//! `XrProjection` OpenXR gives, each eye's `Transform` its pose in the
//! room), the eyes drawing into images that are read back. The
//! predictions come from the geometry in closed form (right triangles in
//! E3 and H3), not from the tracer. The real runtime is tested by the
//! app's `tests/xr.rs` under Monado.

use bevy::camera::RenderTarget;
use bevy::prelude::*;
use bevy::render::RenderApp;
use bevy::time::TimeUpdateStrategy;
use bevy_manifold::geometry::product::{ProductPoint, ProductTangent};
use bevy_manifold::placement::{DomainCell, Placement};
use bevy_manifold::prelude::*;
use bevy_manifold::product::{ProductBody, ProductCamera, ProductSpaceRoot};
use bevy_manifold::render::{ManifoldBufferCache, ManifoldUploads, offscreen};
use bevy_manifold::space::Space;
use bevy_manifold::space::product::ProductSpace;
use bevy_manifold::trace::product::ProductView;
use bevy_manifold::xr::XrProductHead;
use bevy_manifold::xr::{
    ManifoldXrPlugin, XrBody, XrControllers, XrEye, XrHand, XrHandSide, XrHead, XrLocomotion, XrRecentre, XrTrigger,
};
use bevy_mod_xr::camera::{Fov, XrCamera, XrProjection, calculate_projection};
use bevy_mod_xr::session::XrTrackingRoot;
use glam::{DVec3, DVec4};
use std::sync::Arc;
use std::time::Duration;

/// A left eye's field of view as a headset reports it (radians: left,
/// right, down, up); the right eye's is its mirror image.
const LEFT_FOV: [f32; 4] = [-0.87, 0.70, -0.84, 0.77];
const W: u32 = 640;
const H: u32 = 560;
/// Half the distance between the eyes, in metres.
const HALF_IPD: f32 = 0.032;

fn fov(eye: usize) -> [f32; 4] {
    let [l, r, d, u] = LEFT_FOV;
    if eye == 0 { [l, r, d, u] } else { [-r, -l, d, u] }
}

/// `[half width, half height, centre x, centre y]` of an eye's frustum, in
/// slopes.
fn slopes(eye: usize) -> [f64; 4] {
    let [l, r, d, u] = fov(eye).map(|a| f64::from(a).tan());
    [(r - l) / 2.0, (u - d) / 2.0, (r + l) / 2.0, (u + d) / 2.0]
}

/// The slope of a pixel boundary (`i` from 0 to `W`) and of a row's centre.
fn column_slope(eye: usize, i: f64) -> f64 {
    let [hw, _, cx, _] = slopes(eye);
    (2.0 * i / f64::from(W) - 1.0) * hw + cx
}

fn row_slope(eye: usize, j: u32) -> f64 {
    let [_, hh, _, cy] = slopes(eye);
    (1.0 - 2.0 * (f64::from(j) + 0.5) / f64::from(H)) * hh + cy
}

/// One slope in pixels.
fn pixel(eye: usize) -> f64 {
    2.0 * slopes(eye)[0] / f64::from(W)
}

/// An offscreen app with the XR plugin, a space, the body at the origin,
/// and two eyes as bevy_mod_openxr makes them, drawing into images.
struct Rig {
    app: App,
    root: Entity,
    images: [Handle<Image>; 2],
}

/// One offscreen render app at a time in this process: the GPU tests
/// here hold it while their app lives (a lavapipe device per app; two
/// made and torn down side by side once left the heap corrupt at exit).
static ONE_RENDER_APP: std::sync::Mutex<()> = std::sync::Mutex::new(());

fn rig(space: &Space, world_scale: f64) -> Rig {
    rig_with(|world| {
        let root = world.spawn(ManifoldSpace::new(space.clone())).id();
        world.spawn((ChildOf(root), XrBody { world_scale }, Placement::default()));
        root
    })
}

/// An offscreen app with the XR plugin and two eyes drawing into images
/// ([`spawn_eyes`]), its space and body spawned by `body` (which returns
/// the space's root).
fn rig_with(body: impl FnOnce(&mut World) -> Entity) -> Rig {
    let mut app = App::new();
    app.add_plugins(offscreen::plugins().disable::<bevy::log::LogPlugin>())
        .add_plugins((ManifoldPlugins::default(), ManifoldXrPlugin));
    app.finish();
    app.cleanup();
    let images = [0, 1].map(|_| offscreen::target(&mut app, W, H));
    let world = app.world_mut();
    let root = body(world);
    spawn_eyes(world, &images);
    Rig { app, root, images }
}

/// bevy_mod_openxr's tracking root and its two eyes (with the off-centre
/// projections of [`fov`], 2 `HALF_IPD` apart), drawing into `images`.
fn spawn_eyes(world: &mut World, images: &[Handle<Image>; 2]) {
    let tracking = world.spawn((XrTrackingRoot, Transform::default())).id();
    for (i, image) in images.iter().enumerate() {
        let [l, r, d, u] = fov(i);
        let x = if i == 0 { -HALF_IPD } else { HALF_IPD };
        world.spawn((
            ChildOf(tracking),
            XrCamera(i as u32),
            RenderTarget::Image(image.clone().into()),
            Projection::custom(XrProjection {
                projection_matrix: calculate_projection(
                    0.01,
                    Fov {
                        angle_left: l,
                        angle_right: r,
                        angle_down: d,
                        angle_up: u,
                    },
                ),
                near: 0.01,
            }),
            Transform::from_xyz(x, 0.0, 0.0),
        ));
    }
}

/// [`rig`] in a product space: its root, and the body a product camera
/// with `view` (the root's the `ProductSpaceRoot`).
fn product_rig(space: &ProductSpace, view: ProductView, world_scale: f64) -> Rig {
    rig_with(|world| {
        let root = world.spawn(ProductSpaceRoot(Arc::new(space.clone()))).id();
        let mut camera = ProductCamera::default_for(space.clone());
        camera.view = view;
        world.spawn((ChildOf(root), XrBody { world_scale }, camera));
        root
    })
}

/// A view from the surface's origin at height 0, looking along the
/// surface (its `x`), its right the surface's `-y`, its up the line's;
/// seeing only the prism about it, with no fog.
fn level_view() -> ProductView {
    ProductView {
        eye: ProductPoint::ORIGIN,
        frame: [
            ProductTangent::new(DVec3::X, 0.0),
            ProductTangent::new(DVec3::NEG_Y, 0.0),
            ProductTangent::new(DVec3::ZERO, 1.0),
        ],
        fov_y_degrees: 90.0,
        frustum: None,
        max_distance: 3.0,
        max_crossings: 0,
        fog: 0.0,
        cell: None,
        tint: None,
    }
}

impl Rig {
    fn capture(&mut self) -> [Vec<u8>; 2] {
        offscreen::wait_for_pipelines(&mut self.app).expect("pipelines");
        let images = self.images.clone();
        images.map(|image| offscreen::capture(&mut self.app, &image).expect("capture"))
    }
}

/// The widest run of pixels in row `j` whose colour `is` picks: the first
/// pixel and one past the last.
fn widest_run(rgba: &[u8], j: u32, is: impl Fn(&[u8]) -> bool) -> Option<(u32, u32)> {
    let mut best: Option<(u32, u32)> = None;
    let mut start = None;
    for i in 0..=W {
        let on = i < W && is(&rgba[((j * W + i) * 4) as usize..][..4]);
        match (on, start) {
            (true, None) => start = Some(i),
            (false, Some(s)) => {
                if best.is_none_or(|(a, b)| i - s > b - a) {
                    best = Some((s, i));
                }
                start = None;
            }
            _ => {}
        }
    }
    best
}

/// The largest 4-connected set of pixels whose colour `is` picks (the
/// nearest copy of an object; the others are smaller): its pixel count and
/// the sums of its pixel centres' columns and rows.
fn largest_blob(rgba: &[u8], is: impl Fn(&[u8]) -> bool) -> (f64, f64, f64) {
    let at = |i: u32, j: u32| is(&rgba[((j * W + i) * 4) as usize..][..4]);
    let mut seen = vec![false; (W * H) as usize];
    let mut best = (0.0, 0.0, 0.0);
    for start in 0..W * H {
        if seen[start as usize] || !at(start % W, start / W) {
            continue;
        }
        seen[start as usize] = true;
        let mut stack = vec![start];
        let mut blob = (0.0, 0.0, 0.0);
        while let Some(k) = stack.pop() {
            let (i, j) = (k % W, k / W);
            blob.0 += 1.0;
            blob.1 += f64::from(i) + 0.5;
            blob.2 += f64::from(j) + 0.5;
            let near = [
                (i > 0).then(|| k - 1),
                (i + 1 < W).then(|| k + 1),
                (j > 0).then(|| k - W),
                (j + 1 < H).then(|| k + W),
            ];
            for m in near.into_iter().flatten() {
                if !seen[m as usize] && at(m % W, m / W) {
                    seen[m as usize] = true;
                    stack.push(m);
                }
            }
        }
        if blob.0 > best.0 {
            best = blob;
        }
    }
    best
}

fn red(p: &[u8]) -> bool {
    p[0] > 150 && p[1] < 80 && p[2] < 80
}

fn green(p: &[u8]) -> bool {
    p[1] > 150 && p[0] < 80 && p[2] < 80
}

/// A function of a distance.
type OfDistance = fn(f64) -> f64;

/// Distances of a right triangle: `sin`, `tan`, `cos` of a surface or
/// space of curvature `k` (1, or -1 for `sinh`, `tanh`, `cosh`), or their
/// flat limits (0).
fn trig(k: f64) -> (OfDistance, OfDistance, OfDistance) {
    if k < 0.0 {
        (f64::sinh, f64::tanh, f64::cosh)
    } else if k > 0.0 {
        (f64::sin, f64::tan, f64::cos)
    } else {
        (|x| x, |x| x, |_| 1.0)
    }
}

/// Where a ball of radius `r` straight ahead of the head at distance `d`
/// is seen by an eye `a` to the side of the head (left: `side` = -1), as
/// the slopes of its left and right edges in the plane of the eyes. The
/// head, the eye and the ball's centre make a right triangle at the
/// head; at the eye, the angle between the head and the ball has
/// `tan = tanh d / sinh a` (E3: `d / a`, S: `tan d / sin a`), so the ball
/// is off the eye's forward axis by the slope `sinh a / tanh d`; the eye
/// is at distance `cosh D = cosh a cosh d` (E3: Pythagoras, S: `cos D =
/// cos a cos d`) from the centre, where the ball subtends a half-angle
/// with `sin = sinh r / sinh D`. In curvature `k`.
fn predicted_edges(k: f64, a: f64, d: f64, r: f64, side: f64) -> (f64, f64) {
    let (sinh, tanh, cosh) = trig(k);
    let centre = (-side * sinh(a) / tanh(d)).atan();
    let far = if k < 0.0 {
        (cosh(a) * cosh(d)).acosh()
    } else if k > 0.0 {
        (cosh(a) * cosh(d)).acos()
    } else {
        a.hypot(d)
    };
    let half = (sinh(r) / sinh(far)).asin();
    ((centre - half).tan(), (centre + half).tan())
}

/// Checks that each eye sees the ball of radius `r` straight ahead of the
/// head at distance `d` (the eyes `a` to either side, in curvature `k`)
/// with its edges, in the row level with the eyes, where
/// [`predicted_edges`] puts them (within 0.75 px); returns the disparity
/// of its middle and the flat formula's, in pixels.
fn seen_disparity(
    name: &str,
    shots: &[Vec<u8>; 2],
    is: impl Fn(&[u8]) -> bool + Copy,
    (k, a, d, r): (f64, f64, f64, f64),
) -> (f64, f64) {
    let mut mids = [0.0; 2];
    let mut flat_mids = [0.0; 2];
    for eye in 0..2 {
        let j = (0..H)
            .min_by(|&p, &q| row_slope(eye, p).abs().total_cmp(&row_slope(eye, q).abs()))
            .expect("rows");
        let (i0, i1) = widest_run(&shots[eye], j, is).unwrap_or_else(|| panic!("{name}: eye {eye} sees no ball"));
        let seen = (column_slope(eye, f64::from(i0)), column_slope(eye, f64::from(i1)));
        let side = if eye == 0 { -1.0 } else { 1.0 };
        let want = predicted_edges(k, a, d, r, side);
        let px = pixel(eye);
        eprintln!(
            "{name}: eye {eye}: edges at slopes ({:.4}, {:.4}), predicted ({:.4}, {:.4}): off by {:.2} and {:.2} px",
            seen.0,
            seen.1,
            want.0,
            want.1,
            (seen.0 - want.0) / px,
            (seen.1 - want.1) / px
        );
        assert!((seen.0 - want.0).abs() < 0.75 * px, "{name}: eye {eye}: left edge");
        assert!((seen.1 - want.1).abs() < 0.75 * px, "{name}: eye {eye}: right edge");
        mids[eye] = (seen.0 + seen.1) / 2.0;
        let flat = predicted_edges(0.0, a, d, r, side);
        flat_mids[eye] = (flat.0 + flat.1) / 2.0;
    }
    let px = pixel(0);
    let disparity = (mids[0] - mids[1]) / px;
    let flat = (flat_mids[0] - flat_mids[1]) / px;
    eprintln!("{name}: disparity {disparity:.1} px; the flat formula says {flat:.1} px");
    (disparity, flat)
}

/// The two eyes see a ball ahead at the slopes the geometry predicts, so
/// their disparity is the geometry's: in Seifert-Weber (H3) larger than
/// the flat formula by `tanh d / d`, a difference of many pixels the test
/// tells apart. Both eyes bind one upload of the scene.
fn the_eyes_see_a_ball_with_the_disparity_the_geometry_predicts() {
    let _one = ONE_RENDER_APP.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    for (space, k, d) in [(catalog::torus(1.0), 0.0, 0.35), (catalog::seifert_weber(), -1.0, 0.6)] {
        let name = space.name().to_string();
        // 64 mm between the eyes is 0.2 of the space apart.
        let world_scale = f64::from(2.0 * HALF_IPD) / 0.2;
        let a = 0.1;
        let r = 0.05;
        let mut rig = rig(&space, world_scale);
        let root = rig.root;
        rig.app.world_mut().spawn((
            ChildOf(root),
            TracedBall::new(r, Color::srgb(1.0, 0.0, 0.0)).glowing(2.0),
            Placement::at(&space, DVec3::new(0.0, 0.0, -d)),
        ));
        let shots = rig.capture();
        // Two eyes, one scene on the GPU: uploaded once, not once an eye.
        let render = rig.app.sub_app(RenderApp).world();
        let cache = render.resource::<ManifoldBufferCache>();
        assert_eq!((cache.len(), cache.scenes()), (2, 1), "{name}: views and scenes held");
        let uploads = render.resource::<ManifoldUploads>();
        eprintln!("{name}: uploads with two eyes: {uploads:?}");
        if k == 0.0 {
            // (Seifert-Weber's table of exact ids is repacked once grown.)
            assert_eq!((uploads.space, uploads.objects), (1, 1), "{name}: one upload of each");
        }
        let (disparity, flat) = seen_disparity(&name, &shots, red, (k, a, d, r));
        if k < 0.0 {
            assert!(disparity - flat > 8.0, "{name}: {disparity} vs the flat {flat}");
        }
    }
}

/// A body that holds a render scale hands it to both eyes, and each eye,
/// traced at half its pixels and upscaled, still shows the ball's edges
/// where the geometry puts them through its own off-centre frustum
/// (within 1.5 pixels: half the resolution, then a bilinear edge).
/// A frustum taken as symmetric would move them by tens of pixels. The
/// ball glows at exactly 1: the traced texture keeps linear colour
/// unclamped, and a brighter ball would bleed over the edge when the
/// upscale interpolates it.
fn both_eyes_trace_at_the_bodys_render_scale_through_their_own_frusta() {
    let _one = ONE_RENDER_APP.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    let space = catalog::torus(1.0);
    let (a, r, d) = (0.1, 0.05, 0.35);
    let mut rig = rig(&space, f64::from(2.0 * HALF_IPD) / 0.2);
    let root = rig.root;
    let world = rig.app.world_mut();
    let body = world
        .query_filtered::<Entity, With<XrBody>>()
        .single(world)
        .expect("a body");
    world.entity_mut(body).insert(ManifoldRenderScale(0.5));
    world.spawn((
        ChildOf(root),
        TracedBall::new(r, Color::srgb(1.0, 0.0, 0.0)).glowing(1.0),
        Placement::at(&space, DVec3::new(0.0, 0.0, -d)),
    ));
    let shots = rig.capture();
    let world = rig.app.world_mut();
    let scales: Vec<f32> = world
        .query_filtered::<&ManifoldRenderScale, With<XrEye>>()
        .iter(world)
        .map(|s| s.0)
        .collect();
    assert_eq!(scales, [0.5, 0.5], "both eyes take the body's scale");
    for (eye, shot) in shots.iter().enumerate() {
        // The column through the ellipse's centre, and the ball's top and
        // bottom there: the cone of half-angle asin(r / D) about the
        // direction to the ball (E3), cut by the image plane: at column
        // x, (axis . (x, y, -1))^2 = cos^2(half) (x^2 + y^2 + 1). (Along
        // the row the blur of half resolution joins the ball to a small
        // copy beside it, so the edges are taken up and down.)
        let side = if eye == 0 { -1.0 } else { 1.0 };
        let centre = (-side * a / d).atan();
        let half = (r / a.hypot(d)).asin();
        let x = ((centre - half).tan() + (centre + half).tan()) / 2.0;
        let along = x * centre.sin() + centre.cos();
        let y = (along * along / (half.cos() * half.cos()) - x * x - 1.0).sqrt();
        let px = pixel(eye);
        let i = (0..W)
            .min_by(|&p, &q| {
                let at = |i: u32| (column_slope(eye, f64::from(i) + 0.5) - x).abs();
                at(p).total_cmp(&at(q))
            })
            .expect("columns");
        let j = (0..H)
            .min_by(|&p, &q| row_slope(eye, p).abs().total_cmp(&row_slope(eye, q).abs()))
            .expect("rows");
        let at = |j: u32| red(&shot[((j * W + i) * 4) as usize..][..4]);
        assert!(at(j), "eye {eye}: no ball at its predicted centre");
        let top = (0..=j).rev().take_while(|&j| at(j)).last().expect("a run");
        let bottom = (j..H).take_while(|&j| at(j)).last().expect("a run") + 1;
        // Slopes of the rows' outer edges.
        let [_, hh, _, cy] = slopes(eye);
        let edge = |j: u32| (1.0 - 2.0 * f64::from(j) / f64::from(H)) * hh + cy;
        let seen = (edge(top), edge(bottom));
        eprintln!(
            "half scale: eye {eye}: top and bottom off by {:.2} and {:.2} px",
            (seen.0 - y) / px,
            (seen.1 + y) / px
        );
        assert!((seen.0 - y).abs() < 1.5 * px, "eye {eye}: top edge");
        assert!((seen.1 + y).abs() < 1.5 * px, "eye {eye}: bottom edge");
    }
    // Cone tracing on the body reaches both eyes, and leaves with it.
    let cones = |rig: &mut Rig| {
        let world = rig.app.world_mut();
        world
            .query_filtered::<Has<ManifoldFootprint>, With<XrEye>>()
            .iter(world)
            .collect::<Vec<_>>()
    };
    rig.app.world_mut().entity_mut(body).insert(ManifoldFootprint);
    rig.app.update();
    rig.app.update();
    assert_eq!(cones(&mut rig), [true, true]);
    rig.app.world_mut().entity_mut(body).remove::<ManifoldFootprint>();
    rig.app.update();
    rig.app.update();
    assert_eq!(cones(&mut rig), [false, false]);
}

/// The pixel at the centre of the image of a ball of radius `r` whose
/// centre, offset from the head by `h` (in the head's frame, in units of
/// the space), an eye `a` to the side of the head sees. In E3 the eye
/// sees the centre along `h` less the eye's offset; in H3 the centre is
/// `exp(h)` on the hyperboloid, carried by the boost that takes the eye to
/// the origin, where the projective chart shows true directions. The
/// ball is a circular cone of half-angle `asin(sinh r / sinh D)` (E3:
/// `asin(r / D)`) about that direction, cut by the image plane in an
/// ellipse centred, along the radial line, halfway between
/// `tan(theta - rho)` and `tan(theta + rho)`.
fn predicted_pixel(hyperbolic: bool, eye: usize, a: f64, h: DVec3, r: f64) -> (f64, f64) {
    let x = if eye == 0 { -a } else { a };
    let (q, rho) = if hyperbolic {
        let n = h.length();
        let (p, w) = (h / n * n.sinh(), n.cosh());
        let (c, s) = (x.cosh(), x.sinh());
        let q = DVec3::new(c * p.x - s * w, p.y, p.z);
        let far = (c * w - s * p.x).acosh();
        (q, (r.sinh() / far.sinh()).asin())
    } else {
        let q = h - DVec3::X * x;
        (q, (r / q.length()).asin())
    };
    let radial = q.truncate().length();
    let theta = (radial / -q.z).atan();
    let mid = ((theta + rho).tan() + (theta - rho).tan()) / 2.0;
    let (sx, sy) = (q.x / radial * mid, q.y / radial * mid);
    let [hw, hh, cx, cy] = slopes(eye);
    let i = ((sx - cx) / hw + 1.0) / 2.0 * f64::from(W);
    let j = (1.0 - (sy - cy) / hh) / 2.0 * f64::from(H);
    (i, j)
}

/// A hand (a ball held in it) at a known controller pose appears, to each
/// eye, at the pixel the geometry predicts (within half a pixel), in E3
/// and H3; the nearest copy of it, as other copies of the torus show it
/// too.
fn a_hand_at_a_controller_pose_appears_where_the_geometry_predicts() {
    let _one = ONE_RENDER_APP.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    for (space, hyperbolic) in [(catalog::torus(1.0), false), (catalog::seifert_weber(), true)] {
        let name = space.name().to_string();
        let world_scale = f64::from(2.0 * HALF_IPD) / 0.2;
        let grip = Vec3::new(0.05, -0.03, -0.12);
        let mut rig = rig(&space, world_scale);
        let root = rig.root;
        rig.app.world_mut().spawn((
            ChildOf(root),
            XrHand(XrHandSide::Right),
            TracedBall::new(0.02, Color::srgb(0.0, 1.0, 0.0)).glowing(2.0),
        ));
        rig.app.world_mut().resource_mut::<XrControllers>().hands[1].grip = Some((grip, Quat::IDENTITY));
        let shots = rig.capture();
        let h = grip.as_dvec3() / world_scale;
        for (eye, shot) in shots.iter().enumerate() {
            let (n, si, sj) = largest_blob(shot, green);
            assert!(n > 20.0, "{name}: eye {eye}: {n} hand pixels");
            let seen = (si / n, sj / n);
            let want = predicted_pixel(hyperbolic, eye, 0.1, h, 0.02);
            eprintln!(
                "{name}: eye {eye}: hand at pixel ({:.2}, {:.2}), predicted ({:.2}, {:.2}), {n} pixels",
                seen.0, seen.1, want.0, want.1
            );
            assert!(
                (seen.0 - want.0).abs() < 0.5 && (seen.1 - want.1).abs() < 0.5,
                "{name}: eye {eye}"
            );
        }
    }
}

/// Every [`XrTrigger`] sent, in order.
#[derive(Resource, Default)]
struct TriggerLog(Vec<XrTrigger>);

/// A plain app (no renderer) with the XR plugin and two eyes whose room
/// poses a test sets, as bevy_mod_openxr's `update_views` does.
fn body_app(space: &Space) -> (App, Entity) {
    let mut app = App::new();
    app.add_plugins((MinimalPlugins, ManifoldPlugins::default(), ManifoldXrPlugin))
        .insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_millis(100)))
        .init_resource::<TriggerLog>()
        .add_systems(
            Last,
            |mut sent: MessageReader<XrTrigger>, mut log: ResMut<TriggerLog>| {
                log.0.extend(sent.read().copied());
            },
        );
    let world = app.world_mut();
    let root = world.spawn(ManifoldSpace::new(space.clone())).id();
    let body = world.spawn((ChildOf(root), XrBody { world_scale: 1.0 })).id();
    for i in 0..2u32 {
        let x = if i == 0 { -HALF_IPD } else { HALF_IPD };
        world.spawn((
            ChildOf(root),
            XrEye(i),
            bevy_manifold::placement::TrackedPose,
            Placement::default(),
            Transform::from_xyz(x, 0.0, 0.0),
        ));
    }
    app.update();
    (app, body)
}

/// Holds a control (`press` sets it) for `updates` updates, then lets go
/// (`release`) for two.
fn hold(app: &mut App, updates: usize, press: impl Fn(&mut XrControllers), release: impl Fn(&mut XrControllers)) {
    press(&mut app.world_mut().resource_mut::<XrControllers>());
    for _ in 0..updates {
        app.update();
    }
    release(&mut app.world_mut().resource_mut::<XrControllers>());
    app.update();
    app.update();
}

fn head(app: &App, body: Entity) -> XrHead {
    app.world().get::<XrHead>(body).expect("a head").clone()
}

/// The left stick flies the head forward along its geodesic at the set
/// speed, through the faces (the torus has period 1: 3 s at 0.3 units/s
/// is 0.9, so the head comes back 0.1 short of where it started); the
/// right stick snap-turns by 30 degrees about the head, once per push;
/// the secondary button puts the room back at the start; the trigger is
/// an action with two edges.
fn the_sticks_fly_and_turn_the_room_and_the_trigger_is_an_action() {
    let space = catalog::torus(1.0);
    let (mut app, body) = body_app(&space);
    let set = |app: &mut App, f: &dyn Fn(&mut XrControllers)| f(&mut app.world_mut().resource_mut::<XrControllers>());
    hold(
        &mut app,
        30,
        |c| c.hands[0].stick = Vec2::Y,
        |c| c.hands[0].stick = Vec2::ZERO,
    );
    let h = head(&app, body);
    let z = h.placement.position().z / h.placement.position().w;
    // 30 updates of 0.1 s, the first with no head yet... counted exactly:
    // the stick moved the room on each update where the head existed.
    assert!((z - 0.1).abs() < 0.031, "head at z {z}");
    assert_ne!(h.cell.id, DomainCell::default().id, "the head crossed a face");
    let speed = app.world().get::<XrLocomotion>(body).expect("locomotion").speed;
    assert!((speed - 0.3).abs() < 1e-12);

    // A snap turn: the head's forward turns 30 degrees to the right.
    let before = head(&app, body).placement.forward();
    hold(
        &mut app,
        5,
        |c| c.hands[1].stick = Vec2::X,
        |c| c.hands[1].stick = Vec2::ZERO,
    );
    let after = head(&app, body).placement.forward();
    let angle = before.truncate().angle_between(after.truncate()).to_degrees();
    assert!((angle - 30.0).abs() < 1e-6, "one snap of {angle} degrees");
    assert!(after.x > 0.0, "turned right: {after}");

    // Reset: back at the start of the origin copy.
    set(&mut app, &|c| c.hands[0].secondary = true);
    app.update();
    app.update();
    let h = head(&app, body);
    assert!(
        h.placement.position().truncate().length() < 1e-9,
        "{}",
        h.placement.position()
    );
    assert_eq!(h.cell.id, DomainCell::default().id);

    // The trigger: one pull and one release, however long it is held.
    set(&mut app, &|c| c.hands[1].trigger = 0.9);
    for _ in 0..3 {
        app.update();
    }
    set(&mut app, &|c| c.hands[1].trigger = 0.5);
    app.update();
    set(&mut app, &|c| c.hands[1].trigger = 0.0);
    app.update();
    assert_eq!(
        app.world().resource::<TriggerLog>().0,
        [
            XrTrigger {
                hand: XrHandSide::Right,
                pulled: true
            },
            XrTrigger {
                hand: XrHandSide::Right,
                pulled: false
            }
        ]
    );
}

/// With `XrRecentre` the head, where it was first tracked (standing, 1.6 m
/// up and 0.2 m forward of the room's centre), is the body's origin; a
/// step of 0.1 m to the right then moves it 0.1 / scale from there, and a
/// grip 0.3 m in front of the head puts the hand 0.3 / scale ahead of the
/// body. `XrHead::eyes` are the eyes from the body: 32 mm / scale to
/// either side.
fn recentring_puts_the_first_head_pose_at_the_body() {
    let space = catalog::seifert_weber();
    let (mut app, body) = body_app(&space);
    let g = space.geometry();
    app.world_mut().entity_mut(body).insert(XrRecentre::default());
    let root = app.world().get::<ChildOf>(body).expect("root").parent();
    let hand = app.world_mut().spawn((ChildOf(root), XrHand(XrHandSide::Right))).id();
    let place = |app: &mut App, shift: Vec3| {
        let mut q = app.world_mut().query::<(&XrEye, &mut Transform)>();
        for (eye, mut t) in q.iter_mut(app.world_mut()) {
            let x = if eye.0 == 0 { -HALF_IPD } else { HALF_IPD };
            t.translation = Vec3::new(x, 1.6, -0.2) + shift;
        }
    };
    place(&mut app, Vec3::ZERO);
    app.world_mut().resource_mut::<XrControllers>().hands[1].grip = Some((Vec3::new(0.0, 1.6, -0.5), Quat::IDENTITY));
    app.update();
    app.update();
    let h = head(&app, body);
    let d = |p: DVec4| g.distance::<f64>(p, DVec4::W);
    assert!(d(h.placement.position()) < 1e-9, "head {}", h.placement.position());
    assert!(
        (h.recentred - Vec3::new(0.0, 1.6, -0.2)).length() < 1e-6,
        "{}",
        h.recentred
    );
    let half = f64::from(HALF_IPD);
    for e in h.eyes {
        assert!((d(e.w_axis) - half).abs() < 1e-9, "eye {}", e.w_axis);
    }
    let hand_at = app.world().get::<Placement>(hand).expect("hand").position();
    assert!((d(hand_at) - f64::from(0.3f32)).abs() < 1e-6, "hand {hand_at}");
    assert!(hand_at.z < 0.0, "ahead: {hand_at}");
    place(&mut app, Vec3::X * 0.1);
    app.update();
    app.update();
    let moved = d(head(&app, body).placement.position());
    assert!((moved - f64::from(0.1f32)).abs() < 1e-6, "moved {moved}");
}

/// In a product space each eye is the body's view moved along the
/// geodesic of its offset. Looking along the surface with the eyes apart
/// along it, the level surface through the eyes and the ball is totally
/// geodesic (a copy of H2 or of S2), so the row level with the eyes sees
/// the ball's edges where that surface's right triangles put them,
/// through each eye's off-centre frustum: in H2 (the genus-2 surface) the
/// disparity exceeds the flat formula's, on S2 it falls short of it, by
/// more than 8 pixels either way.
fn the_eyes_in_a_product_space_see_a_ball_where_its_surface_puts_it() {
    let _one = ONE_RENDER_APP.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    for space in [ProductSpace::genus_two_x_s1(2.0), ProductSpace::s2_x_s1(2.0)] {
        let g = space.geometry;
        let k = g.curvature();
        let (d, a, r) = (0.6, 0.1, 0.05);
        let world_scale = f64::from(2.0 * HALF_IPD) / (2.0 * a);
        let mut rig = product_rig(&space, level_view(), world_scale);
        let (c, sn) = g.trig(d);
        let center = ProductPoint::new(DVec3::new(sn, 0.0, c), 0.0);
        let root = rig.root;
        rig.app.world_mut().spawn((
            ChildOf(root),
            ProductBody {
                center,
                radius: r,
                id: 0,
            },
        ));
        let shots = rig.capture();
        let mut eyes = rig.app.world_mut().query::<(&XrEye, &ProductCamera)>();
        for (eye, camera) in eyes.iter(rig.app.world()) {
            let f = camera.view.frustum.expect("the eye's own frustum");
            let [l, r, d, u] = fov(eye.0 as usize).map(|x| f64::from(x).tan());
            let off = (f.left - l)
                .abs()
                .max((f.right - r).abs())
                .max((f.down - d).abs())
                .max((f.up - u).abs());
            assert!(off < 1e-5, "eye {}: frustum {f:?}", eye.0);
            assert_eq!(camera.balls.len(), 1, "the body's ball");
        }
        // The ball's colour (orange, lit from the eye), not the fog's
        // pale blue-grey.
        let ball = |p: &[u8]| p[2] < 160;
        let (disparity, flat) = seen_disparity(&format!("k {k}"), &shots, ball, (k, a, d, r));
        assert!(-k * (disparity - flat) > 8.0, "k {k}: {disparity} vs the flat {flat}");
    }
}

/// An app with the XR plugin, a product space and a body whose camera
/// looks along the surface ([`level_view`]), and two eyes 2 `HALF_IPD`
/// apart, as [`body_app`] makes them.
fn product_body_app(space: &ProductSpace) -> (App, Entity) {
    let mut app = App::new();
    app.add_plugins((MinimalPlugins, ManifoldPlugins::default(), ManifoldXrPlugin))
        .insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_millis(100)));
    let mut camera = ProductCamera::default_for(space.clone());
    camera.view = level_view();
    let world = app.world_mut();
    let root = world.spawn(ProductSpaceRoot(Arc::new(space.clone()))).id();
    let body = world
        .spawn((ChildOf(root), XrBody { world_scale: 1.0 }, camera.clone()))
        .id();
    for i in 0..2u32 {
        let x = if i == 0 { -HALF_IPD } else { HALF_IPD };
        world.spawn((XrEye(i), camera.clone(), Transform::from_xyz(x, 0.0, 0.0)));
    }
    app.update();
    (app, body)
}

/// In a product space the left stick flies the body along the head's
/// level geodesic at the set speed (S2 x S1: 3 s at 0.3 units/s is 0.9
/// along a great circle of the sphere, the height kept); the right stick
/// snap-turns the head by 30 degrees to the right about its own point;
/// the secondary button brings the body back where it started. The eyes
/// stay 64 mm apart (at 1 m per unit) along the surface.
fn the_sticks_fly_a_product_body_along_its_geodesics() {
    let space = ProductSpace::s2_x_s1(2.0);
    let g = space.geometry;
    let (mut app, body) = product_body_app(&space);
    let head = |app: &App| *app.world().get::<XrProductHead>(body).expect("a head");
    let set = |app: &mut App, f: &dyn Fn(&mut XrControllers)| f(&mut app.world_mut().resource_mut::<XrControllers>());
    hold(
        &mut app,
        30,
        |c| c.hands[0].stick = Vec2::Y,
        |c| c.hands[0].stick = Vec2::ZERO,
    );
    let h = head(&app).view;
    let flown = g.distance(ProductPoint::ORIGIN, h.eye);
    assert!((flown - 0.9).abs() < 0.031, "flew {flown}");
    assert!(
        h.eye.height.abs() < 1e-9 && h.eye.surface.y.abs() < 1e-9,
        "level, straight ahead: {:?}",
        h.eye
    );
    assert!(h.eye.surface.x > 0.0, "forward: {:?}", h.eye);
    let mut eyes = app.world_mut().query::<(&XrEye, &ProductCamera)>();
    let views: Vec<ProductView> = eyes.iter(app.world()).map(|(_, c)| c.view).collect();
    let apart = g.distance(views[0].eye, views[1].eye);
    assert!((apart - f64::from(2.0 * HALF_IPD)).abs() < 1e-6, "eyes {apart} apart");

    // A snap turn to the right, about the head.
    let before = head(&app).view;
    hold(
        &mut app,
        5,
        |c| c.hands[1].stick = Vec2::X,
        |c| c.hands[1].stick = Vec2::ZERO,
    );
    let after = head(&app).view;
    assert!(g.distance(before.eye, after.eye) < 1e-9, "the head stays put");
    let angle = g
        .dot(before.frame[0], after.frame[0])
        .clamp(-1.0, 1.0)
        .acos()
        .to_degrees();
    assert!((angle - 30.0).abs() < 1e-6, "one snap of {angle} degrees");
    assert!(g.dot(before.frame[1], after.frame[0]) > 0.0, "turned right");

    // Reset: back where it started.
    set(&mut app, &|c| c.hands[0].secondary = true);
    app.update();
    app.update();
    let back = g.distance(ProductPoint::ORIGIN, head(&app).view.eye);
    assert!(back < 1e-9, "reset to {back} from the start");
}

bevy_manifold_test_support::test_main! {
    cpu: [
        the_sticks_fly_and_turn_the_room_and_the_trigger_is_an_action,
        recentring_puts_the_first_head_pose_at_the_body,
        the_sticks_fly_a_product_body_along_its_geodesics,
    ],
    gpu: [
        the_eyes_see_a_ball_with_the_disparity_the_geometry_predicts,
        a_hand_at_a_controller_pose_appears_where_the_geometry_predicts,
        both_eyes_trace_at_the_bodys_render_scale_through_their_own_frusta,
        the_eyes_in_a_product_space_see_a_ball_where_its_surface_puts_it,
    ],
}
