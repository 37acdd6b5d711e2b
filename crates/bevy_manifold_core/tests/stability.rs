//! Numerical stability under stress on the CPU, in f64 and in f32 (the
//! GPU's arithmetic): degenerate rays, long rays and their drift with and
//! without renormalisation, far travel through 10^7 faces, and antipodes
//! in S3. No GPU needed; the GPU side of each check is in
//! `bevy_manifold_gpu`'s `tests/stability.rs`. Bounded in time for CI;
//! `bench stability` runs longer versions.

use bevy_manifold_core::geometry::isometry;
use bevy_manifold_core::prelude::*;
use bevy_manifold_test_support::stress;
use bevy_manifold_test_support::stress::{cpu_drift, empty_view, walk_settings};
use glam::DVec4;

/// Drift bounds with renormalisation on, after 10^4 transports: f64 keeps
/// every ray on the model to 1e-12, f32 to 1e-5.
const F64_DRIFT: f64 = 1e-12;
const F32_DRIFT: f64 = 1e-5;

#[test]
fn rays_through_vertices_and_edges_and_along_faces_stay_sane_in_f32_on_the_cpu() {
    for name in catalog::NAMES {
        let space = catalog::by_name(name).expect("catalog");
        let settings = walk_settings(64, true, 1);
        let rays = stress::degenerate_rays(&space);
        for (k, ray) in rays.iter().enumerate() {
            let scene = empty_view(stress::camera_along(&space, ray));
            let d = cpu_drift::<f32>(&space, &scene, &settings)[0];
            stress::assert_sane_walk(&space, &d, 64, &format!("{name} ray {k} (CPU f32)"));
        }
        eprintln!(
            "{name}: {} degenerate rays, 64 transports each, sane on CPU f32",
            rays.len()
        );
    }
}

#[test]
fn long_rays_stay_on_the_model_only_with_renormalisation() {
    eprintln!(
        "worst drift after {} transports, 256 rays: renormalised / not",
        stress::LONG_WALK
    );
    for name in catalog::NAMES {
        let space = catalog::by_name(name).expect("catalog");
        let c32 = stress::long_ray_drift(&space, |scene, settings| cpu_drift::<f32>(&space, scene, settings));
        let c64 = stress::long_ray_drift(&space, |scene, settings| cpu_drift::<f64>(&space, scene, settings));
        eprintln!(
            "{name:<22} CPU f32 {:.2e} / {:.2e}   CPU f64 {:.2e} / {:.2e}",
            c32[0], c32[1], c64[0], c64[1]
        );
        assert!(c32[0] <= F32_DRIFT, "{name}: CPU f32 drift {:e}", c32[0]);
        assert!(c64[0] <= F64_DRIFT, "{name}: CPU f64 drift {:e}", c64[0]);
        // The protection is what keeps the bound: without renormalisation
        // the curved spaces' f32 walks leave it. The flat ones stay at one
        // rounding either way: their pairings are integer translations and
        // reflections, which add no error to carry on.
        if space.geometry() != Geometry::Euclidean {
            assert!(
                c32[1] > F32_DRIFT,
                "{name}: CPU f32 drift without renormalisation only {:e}",
                c32[1]
            );
            assert!(c64[1] > c64[0], "{name}: f64 without renormalisation drifts no more");
        }
    }
}

#[test]
fn ten_million_face_crossings_keep_the_placement_exact() {
    const CROSSINGS: u64 = 10_000_000;
    for (space, path, far) in stress::catalog_far_travels(CROSSINGS) {
        let name = space.name();
        let g = space.geometry();
        assert!(far.crossings >= CROSSINGS);
        assert!(
            far.isometry_error < 1e-12,
            "{name}: isometry error {:e}",
            far.isometry_error
        );
        assert!(
            space.outside_face(far.placement.w_axis, 1e-9).is_none(),
            "{name}: left the domain"
        );
        let gap = stress::exact_gap(&space, &path, &far);
        eprintln!(
            "{name}: {} crossings in {} steps, isometry error {:.1e}, {:.1e} from the closed form (twist {:.6} rad a step)",
            far.crossings,
            far.steps,
            far.isometry_error,
            gap,
            stress::loop_twist(&space, &path)
        );
        // The closed form (the start turned by the twist times the steps,
        // nothing composed) is where the mover is. In E3 and S3 the
        // composed placement stays on it.
        if g != Geometry::Hyperbolic {
            assert!(gap < 1e-6, "{name}: {gap:e} from the closed form after the loop");
        }
    }
}

/// In H3 neighbouring geodesics part like e^d, so the rounding of the
/// first steps grows until the long path above wanders off its closed
/// form (it stays in the group and the domain, checked there). Within the
/// horizon where e^d times the rounding is small, the composed placement
/// is the closed form: bounded by 100 roundings amplified by e^d, checked
/// wherever that bound is under 1e-3.
#[test]
fn hyperbolic_travel_follows_the_closed_form_within_its_horizon() {
    for name in ["seifert-weber", "mirrored-dodecahedron"] {
        let space = catalog::by_name(name).expect("catalog");
        let path = stress::face_axis_loop(&space);
        let step_length = space
            .geometry()
            .distance::<f64>(path.start.w_axis, (path.start * path.step).w_axis);
        let mut checked = 0;
        for steps in 1u64.. {
            let bound = 100.0 * f64::EPSILON * (steps as f64 * step_length).exp();
            if bound >= 1e-3 {
                break;
            }
            let far = stress::far_travel(&space, &path, steps * path.crossings_per_step as u64);
            assert_eq!(
                far.steps, steps,
                "{name}: one step crosses {} faces",
                path.crossings_per_step
            );
            let gap = stress::exact_gap(&space, &path, &far);
            eprintln!("{name}: {steps} steps: {gap:.1e} from the closed form (bound {bound:.1e})");
            assert!(gap <= bound, "{name}: {gap:e} from the closed form after {steps} steps");
            checked += 1;
        }
        assert!(checked >= 4, "{name}: only {checked} steps inside the horizon");
    }
}

/// The loop's twist is a fact of each space's gluing: none in the torus
/// and the mirrored spaces (reflections through the two faces the axis
/// meets compose to a translation along it), a tenth of a turn in the
/// Poincare dodecahedral space and three tenths in Seifert-Weber (each
/// glues opposite faces with that turn).
#[test]
fn the_loop_twists_as_each_gluing_turns() {
    use std::f64::consts::PI;
    for (name, turn) in [
        ("torus", 0.0),
        ("mirrored-cube", 0.0),
        ("mirrored-dodecahedron", 0.0),
        ("poincare", PI / 5.0),
        ("seifert-weber", 3.0 * PI / 5.0),
    ] {
        let space = catalog::by_name(name).expect("catalog");
        let twist = stress::loop_twist(&space, &stress::face_axis_loop(&space));
        assert!(
            (twist.abs() - turn).abs() < 1e-12,
            "{name}: twist {twist}, not +-{turn}"
        );
    }
}

#[test]
fn spherical_antipodes_stay_exact() {
    let space = catalog::poincare();
    let g = space.geometry();
    // Antipodal points: distance exactly pi, no direction between them,
    // and the exponential map reaches the antipode at pi and home at 2 pi.
    let p = isometry::translation(g, glam::DVec3::new(0.1, -0.2, 0.05)) * DVec4::W;
    let v = g.normalize_tangent::<f64>(p, DVec4::new(0.3, 0.1, -0.9, 0.0));
    assert!((g.distance::<f64>(p, -p) - std::f64::consts::PI).abs() < 1e-15);
    assert!(g.log::<f64>(p, -p).is_none());
    assert!((g.exp::<f64>(p, v, std::f64::consts::PI).0 + p).length() < 1e-15);
    assert!((g.exp::<f64>(p, v, std::f64::consts::TAU).0 - p).length() < 1e-15);
    let (q, _) = g.exp::<f64>(p, v, std::f64::consts::PI - 1e-6);
    assert!(
        (g.distance::<f64>(p, q) - (std::f64::consts::PI - 1e-6)).abs() < 1e-12,
        "stable just short of the antipode"
    );
}
