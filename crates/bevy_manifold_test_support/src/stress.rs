//! Stress cases for numerical stability, shared by the stability tests and
//! `bench stability`: rays aimed at the degenerate places of a domain, a
//! camera looking along a given ray, and far travel (a placement carried
//! through millions of faces, composed in f64 and re-orthonormalised at
//! every wrap, as the ECS layer moves entities).
//!
//! ```
//! use bevy_manifold_core::space::catalog;
//! use bevy_manifold_test_support::stress;
//! let torus = catalog::torus(1.0);
//! let path = stress::face_axis_loop(&torus);
//! let far = stress::far_travel(&torus, &path, 1000);
//! assert_eq!(far.crossings, 1000);
//! // The torus loop is exact: after any number of laps it is back.
//! let moved = (far.placement - path.start).to_cols_array();
//! assert!(moved.iter().all(|x| x.abs() < 1e-9));
//! ```

use bevy_manifold_core::geometry::{Real, isometry};
use bevy_manifold_core::motion::move_placement;
use bevy_manifold_core::space::Space;
use bevy_manifold_core::trace::step::Ray;
use bevy_manifold_core::trace::{Camera, FaceTables, FlatScene, RayDrift, Scene, TraceSettings, camera_ray, ray_drift};
use glam::{DMat3, DMat4, DQuat, DVec3, DVec4};
use rayon::prelude::*;

/// The middle of face `i`: the normalised mean of its vertices.
#[must_use]
pub fn face_middle(space: &Space, i: usize) -> DVec4 {
    let sum = space.polyhedron().face_vertices[i]
        .iter()
        .map(|&v| space.vertices()[v].point)
        .sum::<DVec4>();
    space.geometry().normalize_point::<f64>(sum)
}

/// The rays where the face test degenerates: from the domain's centre
/// through every vertex (several faces at once) and every edge's middle
/// (two faces at once), along every edge from one end, and from the middle
/// of every face sliding along it towards one of its vertices (tangent to
/// the face).
#[must_use]
pub fn degenerate_rays(space: &Space) -> Vec<Ray<f64>> {
    let g = space.geometry();
    let o = DVec4::W;
    let from = |p: DVec4, towards: DVec4| Ray {
        origin: p,
        dir: g.normalize_tangent::<f64>(p, towards),
    };
    let mut rays: Vec<_> = space.vertices().iter().map(|v| from(o, v.point)).collect();
    for e in space.edges() {
        let [a, b] = e.vertices.map(|i| space.vertices()[i].point);
        rays.push(from(o, g.normalize_point::<f64>(a + b)));
        rays.push(from(a, b));
    }
    for (i, ring) in space.polyhedron().face_vertices.iter().enumerate() {
        rays.push(from(face_middle(space, i), space.vertices()[ring[0]].point));
    }
    rays
}

/// A camera isometry at `ray.origin` whose view axis (`-z`) is `ray.dir`,
/// so the centre of a 1x1 image traces exactly that ray.
#[must_use]
pub fn camera_along(space: &Space, ray: &Ray<f64>) -> DMat4 {
    let g = space.geometry();
    let t = isometry::translation_to(g, ray.origin);
    let local = isometry::inverse(g, t) * ray.dir;
    let q = DQuat::from_rotation_arc(DVec3::NEG_Z, local.truncate().normalize());
    t * DMat4::from_quat(q)
}

/// A periodic motion: from `start`, right-multiplying by `step` (a motion
/// in the mover's own frame) crosses `crossings_per_step` faces.
#[derive(Clone, Copy, Debug)]
pub struct Path {
    /// Where the mover starts (inside the domain).
    pub start: DMat4,
    /// One step of the motion.
    pub step: DMat4,
    /// Faces one step crosses when the motion is exact.
    pub crossings_per_step: usize,
}

/// The closed geodesic along the axis from the domain's centre through the
/// middle of face 0, for domains where that axis is perpendicular to face 0
/// and to its partner (the catalog's cube and dodecahedra): a mover
/// starting 0.3 inradii along it, facing face 0. Through a glued face it
/// comes back in at the partner's middle and one step of twice the
/// inradius brings it round (twisted by the pairing); through a mirror it
/// bounces, and a step of four inradii crosses two faces.
#[must_use]
pub fn face_axis_loop(space: &Space) -> Path {
    let g = space.geometry();
    let axis = g.normalize_tangent::<f64>(DVec4::W, face_middle(space, 0)).truncate();
    let facing = DMat4::from_quat(DQuat::from_rotation_arc(DVec3::NEG_Z, axis));
    let start = isometry::translation(g, axis * (0.3 * space.inradius())) * facing;
    let mirror = space.faces()[0].partner == 0;
    let laps = if mirror { 4.0 } else { 2.0 };
    Path {
        start,
        step: isometry::translation(g, DVec3::NEG_Z * (laps * space.inradius())),
        crossings_per_step: if mirror { 2 } else { 1 },
    }
}

/// The end of [`far_travel`].
#[derive(Clone, Copy, Debug)]
pub struct FarTravel {
    /// The placement after the last step, inside the domain.
    pub placement: DMat4,
    /// Faces crossed.
    pub crossings: u64,
    /// Steps taken.
    pub steps: u64,
    /// The largest [`isometry::isometry_error`] seen (checked every 1024
    /// steps and at the end).
    pub isometry_error: f64,
}

/// Moves along `path` step by step, wrapping after each step with
/// [`move_placement`] (composition in f64, re-orthonormalised), until at
/// least `crossings` faces have been crossed.
#[must_use]
pub fn far_travel(space: &Space, path: &Path, crossings: u64) -> FarTravel {
    let g = space.geometry();
    let tables = FaceTables::<f64>::new(space);
    let mut out = FarTravel {
        placement: path.start,
        crossings: 0,
        steps: 0,
        isometry_error: 0.0,
    };
    while out.crossings < crossings {
        let m = out.placement;
        let moved = move_placement(space, &tables, m, m * path.step, 64);
        out.placement = moved.placement;
        out.crossings += moved.faces.len() as u64;
        out.steps += 1;
        if out.steps.is_multiple_of(1024) {
            out.isometry_error = out.isometry_error.max(isometry::isometry_error(g, out.placement));
        }
    }
    out.isometry_error = out.isometry_error.max(isometry::isometry_error(g, out.placement));
    out
}

/// Every catalog space with its [`face_axis_loop`] travelled through at
/// least `crossings` faces (the spaces in parallel): where the far-travel
/// checks, on the CPU and on the GPU, start from.
#[must_use]
pub fn catalog_far_travels(crossings: u64) -> Vec<(Space, Path, FarTravel)> {
    use rayon::prelude::*;
    bevy_manifold_core::space::catalog::NAMES
        .par_iter()
        .map(|n| {
            let space = bevy_manifold_core::space::catalog::by_name(n).expect("catalog");
            let path = face_axis_loop(&space);
            let far = far_travel(&space, &path, crossings);
            (space, path, far)
        })
        .collect()
}

/// How far (the largest matrix entry of the difference) a travel ended
/// from where its path began.
#[must_use]
pub fn start_gap(path: &Path, far: &FarTravel) -> f64 {
    (far.placement - path.start)
        .abs()
        .to_cols_array()
        .into_iter()
        .fold(0.0, f64::max)
}

/// The placement a user would make directly at the position and facing of
/// `m`: the translation to its point composed with the rotation of its
/// frame, rebuilt from a unit quaternion (a mirror image keeps its
/// parity as a reflection of x). Used to check that a long-composed
/// placement carries no hidden skew.
#[must_use]
pub fn placed_directly(space: &Space, m: DMat4) -> DMat4 {
    let g = space.geometry();
    let t = isometry::translation_to(g, g.normalize_point::<f64>(m.w_axis));
    let mut r = DMat3::from_mat4(isometry::inverse(g, t) * m);
    let flip = DMat4::from_diagonal(DVec4::new(-1.0, 1.0, 1.0, 1.0));
    let mirrored = r.determinant() < 0.0;
    if mirrored {
        r *= DMat3::from_diagonal(DVec3::new(-1.0, 1.0, 1.0));
    }
    let q = DQuat::from_mat3(&r).normalize();
    let placed = t * DMat4::from_quat(q);
    if mirrored { placed * flip } else { placed }
}

/// A scene with nothing in it, seen from `camera` (60 degrees): what the
/// drift walks look along.
#[must_use]
pub fn empty_view(camera: DMat4) -> Scene {
    Scene {
        camera: Camera {
            isometry: camera,
            fov_y_degrees: 60.0,
        },
        ..Scene::empty()
    }
}

/// Settings for drift walks: `side` x `side` rays, `transports` of them
/// each with no distance limit to speak of, renormalising or not.
#[must_use]
pub fn walk_settings(transports: u32, renormalize: bool, side: u32) -> TraceSettings {
    TraceSettings {
        width: side,
        height: side,
        levels: transports,
        max_distance: 1e9,
        renormalize,
        ..TraceSettings::default()
    }
}

/// [`ray_drift`] of every camera ray of `scene` in precision `R`, in
/// parallel: the CPU side of `GpuTracer::drift`.
#[must_use]
pub fn cpu_drift<R: Real>(space: &Space, scene: &Scene, settings: &TraceSettings) -> Vec<RayDrift> {
    let prep = FlatScene::<R>::new(space, scene);
    let (w, h) = (settings.width, settings.height);
    (0..w * h)
        .into_par_iter()
        .map(|k| ray_drift::<R>(space, camera_ray(&prep, k % w, k / w, w, h), settings))
        .collect()
}

/// The worst [`RayDrift::worst`] of a set of walks.
#[must_use]
pub fn worst(drifts: &[RayDrift]) -> f64 {
    drifts.iter().map(RayDrift::worst).fold(0.0, f64::max)
}

/// The worst drift of 16x16 rays from `space`'s default camera after 1000
/// transports, with renormalisation on and off, as `drift` (the CPU in
/// some precision, or the GPU) walks them: the long-ray stability check.
pub fn long_ray_drift(space: &Space, mut drift: impl FnMut(&Scene, &TraceSettings) -> Vec<RayDrift>) -> [f64; 2] {
    let scene = empty_view(Scene::default_for(space).camera.isometry);
    [true, false].map(|renormalize| worst(&drift(&scene, &walk_settings(1000, renormalize, 16))))
}

/// Asserts what a degenerate ray's walk of `levels` transports must be,
/// whoever traced it (`what` names the ray and the tracer in the message):
/// finite, on the model and inside the domain to 1e-4, every transport
/// made, and not stalled (a stall would burn the transports at one place,
/// so the walk must cover more than 8 inradii).
///
/// # Panics
/// When the walk is not sane.
pub fn assert_sane_walk(space: &Space, d: &RayDrift, levels: u32, what: &str) {
    assert!(d.worst().is_finite(), "{what}: NaN");
    assert!(d.worst() < 1e-4, "{what}: off the model by {:e}", d.worst());
    assert!(d.outside < 1e-4, "{what}: {:e} outside the domain", d.outside);
    assert_eq!(d.levels, levels, "{what}: stopped early");
    assert!(
        d.distance > 8.0 * space.inradius(),
        "{what}: only {} in {levels} transports",
        d.distance
    );
}

/// The camera 0.05 inradius from face 0, looking at it with a 90 degree
/// field of view, wearing a body (Suzanne centred on the eye, attached)
/// of radius a fifth of the inradius, which reaches across the face; and
/// that radius. A hit on the body nearer than the radius is the home body
/// met from inside (every other copy is a translation away).
#[must_use]
pub fn body_beside_a_face(space: &Space) -> (bevy_manifold_core::trace::Scene, f64) {
    use bevy_manifold_core::trace::{Scene, SceneMesh, builtin};
    let g = space.geometry();
    let r = space.inradius();
    let n = bevy_manifold_core::geometry::plane::normal_at(g, space.faces()[0].plane, DVec4::W).truncate();
    let dir = n.normalize();
    let look = glam::DQuat::from_rotation_arc(-glam::DVec3::Z, dir);
    let camera = isometry::translation(g, dir * (0.95 * r)) * DMat4::from_quat(look);
    let mut scene = Scene::default_for(space);
    scene.balls.clear();
    scene.camera.isometry = camera;
    scene.camera.fov_y_degrees = 90.0;
    let suzanne = builtin::suzanne();
    let radius = 0.2 * r;
    let scale = radius / f64::from(suzanne.mesh.bounding_radius());
    let mut body = SceneMesh::new(
        suzanne,
        bevy_manifold_core::mesh::MeshMaterial::default(),
        camera,
        scale,
    );
    body.attached = true;
    scene.meshes = vec![body];
    (scene, radius)
}
