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
use bevy_manifold_core::space::{Generators, Space};
use bevy_manifold_core::trace::step::Ray;
use bevy_manifold_core::trace::{Camera, FaceTables, FlatScene, RayDrift, Scene, TraceSettings, camera_ray, ray_drift};
use glam::{DMat4, DQuat, DVec3, DVec4};
use rayon::prelude::*;

/// Seifert-Weber's own face pairings taken as generators, and their
/// Dirichlet domain about the point of the hyperboloid over `(x, y, z)`:
/// the same manifold with another domain ([`domain_about`]). About the
/// origin it is the dodecahedron (12 faces); about `(0.2, 0.1, 0.05)` it
/// has 52 faces, more than the 32 bits of a face mask (`trace::cull`).
///
/// # Errors
/// When the domain does not build, with the reason.
pub fn seifert_weber_about(x: f64, y: f64, z: f64) -> Result<Space, String> {
    domain_about(&bevy_manifold_core::space::catalog::seifert_weber(), x, y, z)
}

/// A hyperbolic `space`'s own face pairings taken as generators, and
/// their Dirichlet domain about the point of the hyperboloid over
/// `(x, y, z)`, `(x, y, z, sqrt(1 + x^2 + y^2 + z^2))` (the origin's own
/// domain for the origin).
///
/// # Errors
/// When `space` is not hyperbolic, or the domain does not build, with
/// the reason.
pub fn domain_about(space: &Space, x: f64, y: f64, z: f64) -> Result<Space, String> {
    use bevy_manifold_core::geometry::Geometry;
    if space.geometry() != Geometry::Hyperbolic {
        return Err(format!("{} is not hyperbolic", space.name()));
    }
    let pairings = space.faces().iter().map(|f| f.pairing).collect();
    let mut gens = Generators::of_geometry(space.name(), Geometry::Hyperbolic, pairings).map_err(|e| e.to_string())?;
    let w = (1.0 + x * x + y * y + z * z).sqrt();
    let at = (x, y, z) != (0.0, 0.0, 0.0);
    gens.set_basepoint(at.then_some([x, y, z, w]))
        .map_err(|e| e.to_string())?;
    gens.dirichlet_domain().map_err(|e| e.to_string())
}

/// Where [`seifert_weber_about`] gives Seifert-Weber 52 faces.
pub const FIFTY_TWO_FACES: (f64, f64, f64) = (0.2, 0.1, 0.05);

/// A nonzero `v` with `r . v = 0 mod p` for every row `r` of `rows`
/// (`cols` entries each, `p` prime), by row reduction mod `p`: the first
/// free column set to 1. `None` when the rows have full rank.
fn kernel_vector(mut rows: Vec<Vec<i64>>, cols: usize, p: i64) -> Option<Vec<i64>> {
    let inverse = |a: i64| (1..p).find(|&b| (a * b).rem_euclid(p) == 1);
    let mut pivots: Vec<usize> = Vec::new();
    let mut r = 0;
    for c in 0..cols {
        let Some(k) = (r..rows.len()).find(|&k| rows[k][c].rem_euclid(p) != 0) else {
            continue;
        };
        rows.swap(r, k);
        let scale = inverse(rows[r][c].rem_euclid(p))?;
        for x in &mut rows[r] {
            *x = (*x * scale).rem_euclid(p);
        }
        let pivot = rows[r].clone();
        for (k, row) in rows.iter_mut().enumerate() {
            let f = row[c].rem_euclid(p);
            if k != r && f != 0 {
                for (x, y) in row.iter_mut().zip(&pivot) {
                    *x = (*x - f * y).rem_euclid(p);
                }
            }
        }
        pivots.push(c);
        r += 1;
    }
    let free = (0..cols).find(|c| !pivots.contains(c))?;
    let mut v = vec![0; cols];
    v[free] = 1;
    for (row, &c) in pivots.iter().enumerate() {
        v[c] = (-rows[row][free]).rem_euclid(p);
    }
    Some(v)
}

/// A `p`-fold cyclic cover of the manifold `space`: the kernel of a
/// homomorphism of its group onto `Z/p`, as generators (its elements that
/// move the origin least, one of each pair of inverses, at most
/// [`bevy_manifold_core::space::generators::MAX_GENERATORS`]), for
/// [`Generators::dirichlet_domain`]. `None` where the group has no such
/// homomorphism.
///
/// Worked out from the space alone: `phi` is any nonzero vector mod `p`
/// (`p` prime) that kills every row of its group's abelianisation
/// ([`Space::abelian_relations`]), found in the null space of those rows
/// mod `p`; the group is walked breadth-first through its elements within
/// `reach` of the origin, `phi` summed along each word, and those with
/// `phi = 0` kept, the nearest first. Whether they generate the whole
/// kernel is not checked here: the domain's volume, `p` times the
/// space's, says so.
#[must_use]
pub fn cyclic_cover(space: &Space, p: i64, reach: f64) -> Option<Generators> {
    use bevy_manifold_core::space::generators::MAX_GENERATORS;
    let g = space.geometry();
    let faces = space.faces();
    let relations = space.abelian_relations();
    // Each entry mod p, so it fits an i64.
    let rows = relations
        .rows
        .iter()
        .map(|r| r.iter().map(|&x| x.rem_euclid(i128::from(p)) as i64).collect())
        .collect();
    let phi = kernel_vector(rows, relations.generators, p)?;
    let phi_of = |f: usize| {
        let (k, sign) = relations.letters[f];
        if sign > 0 { phi[k] } else { (p - phi[k]) % p }
    };
    // Plain products: Gram-Schmidt on an element far from the origin
    // rounds it by far more than the product did.
    let key = |m: &DMat4| (m.w_axis.truncate() * 1e6).round().as_i64vec3().to_array();
    let mut found: Vec<(DMat4, i64, f64)> = vec![(DMat4::IDENTITY, 0, 0.0)];
    let mut seen: std::collections::HashSet<[i64; 3]> = std::iter::once(key(&DMat4::IDENTITY)).collect();
    let mut next = 0;
    while next < found.len() && found.len() < 200_000 {
        let (m, phi_m, _) = found[next];
        next += 1;
        for (f, face) in faces.iter().enumerate() {
            let n = m * face.pairing;
            let at = g.distance::<f64>(DVec4::W, n.w_axis);
            if at <= reach && seen.insert(key(&n)) {
                found.push((n, (phi_m + phi_of(f)) % p, at));
            }
        }
    }
    let mut kernel: Vec<(DMat4, f64)> = found
        .into_iter()
        .filter(|&(_, phi, at)| phi == 0 && at > 1e-6)
        .map(|(m, _, at)| (m, at))
        .collect();
    kernel.sort_by(|a, b| a.1.total_cmp(&b.1));
    let mut matrices: Vec<DMat4> = Vec::new();
    for (m, _) in kernel {
        let back = isometry::inverse(g, m).w_axis;
        let twin = |k: &DMat4| {
            g.distance::<f64>(k.w_axis, back)
                .min(g.distance::<f64>(k.w_axis, m.w_axis))
                < 1e-7
        };
        if matrices.len() < MAX_GENERATORS && !matrices.iter().any(twin) {
            matrices.push(m);
        }
    }
    Generators::of_geometry(format!("{}, a {p}-fold cyclic cover", space.name()), g, matrices).ok()
}

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

/// The twist of a [`face_axis_loop`]: each step brings the mover back to
/// its start point, facing the same way, turned about its view axis by this
/// angle (radians; 0 where two mirrors send it back). Found from the
/// geometry alone, without the motion code: the one element of the
/// pairings, of word length `crossings_per_step`, that carries the end of
/// one step in the cover back to the start point.
///
/// # Panics
/// When no such element exists or the return is not a pure turn about the
/// axis (the path is not a closed geodesic of the domain).
#[must_use]
pub fn loop_twist(space: &Space, path: &Path) -> f64 {
    let g = space.geometry();
    let end = path.start * path.step;
    let mut words = vec![DMat4::IDENTITY];
    for _ in 0..path.crossings_per_step {
        words = words
            .iter()
            .flat_map(|w| {
                space
                    .faces()
                    .iter()
                    .flat_map(move |f| [f.pairing * *w, isometry::inverse(g, f.pairing) * *w])
            })
            .collect();
    }
    let home = |m: &DMat4| (m.w_axis - path.start.w_axis).abs().max_element() < 1e-9;
    let back = words
        .into_iter()
        .map(|w| w * end)
        .find(home)
        .unwrap_or_else(|| panic!("{}: no pairing word brings the loop home", space.name()));
    // start^-1 * back fixes the point (e_w) and the view axis (e_z).
    let turn = isometry::inverse(g, path.start) * back;
    assert!(
        (turn.w_axis - DVec4::W).abs().max_element() < 1e-9 && (turn.z_axis - DVec4::Z).abs().max_element() < 1e-9,
        "{}: the loop's return is not a turn about its axis: {turn:?}",
        space.name()
    );
    turn.x_axis.y.atan2(turn.x_axis.x)
}

/// Where a mover on `path` is after `steps` steps, in closed form: the
/// start turned `steps` times by the [`loop_twist`] (the angle multiplied,
/// reduced mod 2 pi, nothing composed). The ground truth far travel is
/// checked against.
#[must_use]
pub fn loop_exact(space: &Space, path: &Path, steps: u64) -> DMat4 {
    let angle = (steps as f64 * loop_twist(space, path)).rem_euclid(std::f64::consts::TAU);
    path.start * DMat4::from_rotation_z(angle)
}

/// How far (the largest matrix entry of the difference) a travel ended
/// from the closed form [`loop_exact`] after the same number of steps.
#[must_use]
pub fn exact_gap(space: &Space, path: &Path, far: &FarTravel) -> f64 {
    (far.placement - loop_exact(space, path, far.steps))
        .abs()
        .to_cols_array()
        .into_iter()
        .fold(0.0, f64::max)
}

/// A scene with nothing in it, seen from `camera` (60 degrees): what the
/// drift walks look along.
#[must_use]
pub fn empty_view(camera: DMat4) -> Scene {
    Scene {
        camera: Camera {
            isometry: camera,
            fov_y_degrees: 60.0,
            frustum: None,
            cell: Vec::new(),
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
    let flat = FlatScene::<R>::new(space, scene);
    let (w, h) = (settings.width, settings.height);
    (0..w * h)
        .into_par_iter()
        .map(|k| ray_drift::<R>(space, camera_ray(&flat, k % w, k / w, w, h), settings))
        .collect()
}

/// The worst [`RayDrift::worst`] of a set of walks.
#[must_use]
pub fn worst(drifts: &[RayDrift]) -> f64 {
    drifts.iter().map(RayDrift::worst).fold(0.0, f64::max)
}

/// Transports of the long-ray stability check.
pub const LONG_WALK: u32 = 10_000;

/// The worst drift of 16x16 rays from `space`'s default camera after
/// [`LONG_WALK`] transports, with renormalisation on and off, as `drift`
/// (the CPU in some precision, or the GPU) walks them: the long-ray
/// stability check.
///
/// # Panics
/// When a renormalised ray did not cross [`LONG_WALK`] faces: a walk
/// that stops early would show a small drift it never earned (lavapipe
/// once cut every walk at 1638 transports; see
/// `bevy_manifold_gpu::TraceDefs::face_count`).
pub fn long_ray_drift(space: &Space, mut drift: impl FnMut(&Scene, &TraceSettings) -> Vec<RayDrift>) -> [f64; 2] {
    let scene = empty_view(Scene::default_for(space).camera.isometry);
    [true, false].map(|renormalize| {
        let walks = drift(&scene, &walk_settings(LONG_WALK, renormalize, 16));
        if renormalize {
            let short = walks.iter().filter(|d| d.levels != LONG_WALK).count();
            assert!(
                short == 0,
                "{}: {short} of {} rays crossed fewer than {LONG_WALK} faces",
                space.name(),
                walks.len()
            );
        }
        worst(&walks)
    })
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

/// In the torus of side 1, a camera 3/8 from the centre of a ball of
/// radius 1/8 (albedo `[0.5, 0.25, 1.0]`), looking at it, and a light of
/// intensity 0.3 on the ball's axis at height `z`: at `z = 1/8` the light
/// is exactly where the centre ray of a 3x3 image hits (the numbers are
/// exact in binary), where the direction to it is 0 / 0.
#[must_use]
pub fn light_on_the_hit(z: f64) -> (Space, Scene) {
    use bevy_manifold_core::trace::{Ball, Light};
    let s = bevy_manifold_core::space::catalog::torus(1.0);
    let scene = Scene {
        camera: Camera {
            isometry: isometry::translation(s.geometry(), DVec3::Z * 0.375),
            fov_y_degrees: 40.0,
            frustum: None,
            cell: Vec::new(),
        },
        balls: vec![Ball {
            center: DVec4::W,
            radius: 0.125,
            color: [0.5, 0.25, 1.0],
            glow: 0.0,
            pbr: None,
        }],
        lights: vec![Light {
            position: DVec4::new(0.0, 0.0, z, 1.0),
            intensity: 0.3,
            color: [1.0; 3],
            range: None,
            radius: 0.0,
            spot: None,
        }],
        ..Scene::empty()
    };
    (s, scene)
}

/// The default scene of `space` with `n` more balls (at most 254 in all,
/// ids 1..254) of radius `0.05` of the inradius at random points inside
/// the domain (within 0.95 of its inradius of the centre), glowing: a
/// swarm of shots, as the shooter fills a space, for culling's tests and
/// `bench balls`. The same `seed` gives the same swarm.
#[must_use]
pub fn swarm(space: &Space, n: usize, seed: u64) -> Scene {
    let mut scene = Scene::default_for(space);
    let mut rng = crate::Rng(seed);
    let room = 254usize.saturating_sub(scene.balls.len());
    for k in 0..n.min(room) {
        let hue = k as f32 / n.max(1) as f32;
        scene.balls.push(bevy_manifold_core::trace::Ball {
            center: rng.ray_inside(space).origin,
            radius: 0.05 * space.inradius(),
            color: [1.0 - hue, 0.4 + 0.5 * hue, 0.3],
            glow: 0.5,
            pbr: None,
        });
    }
    scene
}

/// Three small meshes made here, for [`props`]: a cube, an octahedron and
/// a tetrahedron, each within the unit ball of its own chart.
#[must_use]
pub fn prop_meshes() -> Vec<std::sync::Arc<bevy_manifold_core::mesh::MeshData>> {
    use bevy_manifold_core::mesh::{MeshData, TriMesh};
    let h = 1.0 / 3f32.sqrt();
    let cube: Vec<[f32; 3]> = (0..8)
        .map(|i| [0, 1, 2].map(|k| if i >> k & 1 == 1 { h } else { -h }))
        .collect();
    // Two triangles per face, outwards: each face's corners in order round it.
    let quads = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let cube_tris = quads
        .iter()
        .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
        .collect();
    let octa = vec![
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
    ];
    let octa_tris = vec![
        [0, 2, 4],
        [2, 1, 4],
        [1, 3, 4],
        [3, 0, 4],
        [2, 0, 5],
        [1, 2, 5],
        [3, 1, 5],
        [0, 3, 5],
    ];
    let tetra = vec![[h, h, h], [h, -h, -h], [-h, h, -h], [-h, -h, h]];
    let tetra_tris = vec![[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]];
    [(cube, cube_tris), (octa, octa_tris), (tetra, tetra_tris)]
        .into_iter()
        .map(|(p, t)| MeshData::shared(TriMesh::new(p, None, None, t).expect("a closed mesh")))
        .collect()
}

/// The default scene of `space` (its edges, ball and light) with `n` mesh
/// instances of the three [`prop_meshes`], each at a random point inside
/// the domain (within 0.95 of its inradius of the centre) and turned at
/// random, of bounding radius `size` times the inradius (times 0.7 to
/// 1.3) and a colour of its own: a level of props, for the instance
/// tree's tests and `bench instances`. The same `seed` gives the same
/// props.
#[must_use]
pub fn props(space: &Space, n: usize, size: f64, seed: u64) -> Scene {
    use bevy_manifold_core::mesh::MeshMaterial;
    use bevy_manifold_core::trace::SceneMesh;
    let mut scene = Scene::default_for(space);
    let mut rng = crate::Rng(seed);
    let meshes = prop_meshes();
    for k in 0..n {
        let place = rng.ray_inside(space);
        let g = space.geometry();
        let placement = isometry::translation_to(g, place.origin)
            * isometry::rotation(rng.unit(), rng.next_f64() * std::f64::consts::TAU);
        let hue = rng.next_f64() as f32;
        let material = MeshMaterial {
            base_color: [0.3 + 0.7 * hue, 0.9 - 0.6 * hue, 0.2 + 0.3 * (k % 3) as f32],
            ..MeshMaterial::default()
        };
        let scale = size * space.inradius() * (0.7 + 0.6 * rng.next_f64());
        scene
            .meshes
            .push(SceneMesh::new(meshes[k % 3].clone(), material, placement, scale));
    }
    scene
}
