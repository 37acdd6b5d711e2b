//! The catalog spaces against exact invariants from geometry, and broken
//! spaces against the specific errors they must give.

use bevy_manifold_core::geometry::{Geometry, isometry};
use bevy_manifold_core::prelude::*;
use bevy_manifold_core::space::{SpaceDesc, SpaceError, SpaceFileErrorKind, catalog};
use glam::{DMat4, DVec3, DVec4};
use std::f64::consts::{PI, TAU};
use std::path::Path;

fn trace(m: &DMat4) -> f64 {
    m.x_axis.x + m.y_axis.y + m.z_axis.z + m.w_axis.w
}

fn all_dihedrals(s: &Space, degrees: f64) {
    for (i, e) in s.edges().iter().enumerate() {
        assert!(
            (e.dihedral.to_degrees() - degrees).abs() < 1e-9,
            "{}: edge {i} has dihedral {} deg",
            s.name(),
            e.dihedral.to_degrees()
        );
    }
}

fn seifert_weber() {
    let s = catalog::seifert_weber();
    assert_eq!(s.geometry(), Geometry::Hyperbolic);
    assert_eq!(s.faces().len(), 12);
    assert_eq!(s.vertices().len(), 20);
    assert_eq!(s.edges().len(), 30);
    all_dihedrals(&s, 72.0);
    assert_eq!(s.edge_cycles().len(), 6);
    for c in s.edge_cycles() {
        assert_eq!(c.distinct_edges(), 5);
        assert!((c.angle_sum - TAU).abs() < 1e-9);
        assert_eq!(c.order, 1);
    }
    assert!(s.is_manifold());
    assert!((s.volume() - 11.199065).abs() < 1e-5, "volume {}", s.volume());
    let h = s.first_homology().expect("homology");
    assert_eq!((h.rank, h.torsion.clone()), (0, vec![5, 5, 5]), "H1 = {h}");
    // Every pairing is a screw motion of length 2 r (r = inradius) turning by
    // 3 pi / 5: trace 2 cosh 2r + 2 cos(3 pi / 5) = phi^4.
    let phi: f64 = (1.0 + 5f64.sqrt()) / 2.0;
    assert!(
        (2.0 * s.inradius() - 1.992769).abs() < 1e-6,
        "2r = {}",
        2.0 * s.inradius()
    );
    for (i, f) in s.faces().iter().enumerate() {
        let t = trace(&f.pairing);
        assert!((t - phi.powi(4)).abs() < 1e-9, "face {i}: trace {t}");
        assert!((t - 6.854102).abs() < 1e-6);
        let length = Geometry::Hyperbolic.distance::<f64>(DVec4::W, f.pairing * DVec4::W);
        assert!((length - 2.0 * s.inradius()).abs() < 1e-12);
        let turn = ((t - 2.0 * length.cosh()) / 2.0).acos();
        assert!(
            (turn - 3.0 * PI / 5.0).abs() < 1e-7,
            "face {i}: turn {} deg",
            turn.to_degrees()
        );
    }
}

fn the_papers_seifert_weber_twist_of_3pi_over_10_is_a_misprint() {
    // The paper says "a clockwise rotation of 3 pi/10" (54 deg). That does not
    // carry the pentagon's vertices onto the opposite face's, so it glues
    // nothing: the geometry says the twist is 3/10 of a turn (108 deg).
    let result = std::panic::catch_unwind(|| {
        catalog::twisted_dodecahedron("paper-text", Geometry::Hyperbolic, TAU / 5.0, 3.0 * PI / 10.0)
    });
    assert!(result.is_err(), "a 54 degree twist must fail validation");
    let faces: Vec<Face> = catalog::seifert_weber()
        .faces()
        .iter()
        .map(|f| {
            let u = f.plane.truncate().normalize();
            Face {
                pairing: isometry::screw(Geometry::Hyperbolic, u, -2.0 * 0.996384498, 3.0 * PI / 10.0),
                ..f.clone()
            }
        })
        .collect();
    match Space::new("paper-text", Geometry::Hyperbolic, faces) {
        Err(SpaceError::FaceNotMapped {
            face: 0, partner: 6, ..
        }) => {}
        other => panic!("expected face 0 not mapped onto face 6, got {other:?}"),
    }
    // With 1/10 of a turn in H3 the pentagons match but the edge cycles have
    // three 72 degree angles: 216 degrees, no manifold and no orbifold.
    match std::panic::catch_unwind(|| {
        catalog::twisted_dodecahedron("wrong", Geometry::Hyperbolic, TAU / 5.0, TAU / 10.0)
    }) {
        Err(_) => {}
        Ok(_) => panic!("the 1/10-turn hyperbolic dodecahedron is not a valid space"),
    }
}

fn poincare() {
    let s = catalog::poincare();
    assert_eq!(s.geometry(), Geometry::Spherical);
    all_dihedrals(&s, 120.0);
    assert!((s.inradius() - PI / 10.0).abs() < 1e-12, "inradius {}", s.inradius());
    assert_eq!(s.edge_cycles().len(), 10);
    for c in s.edge_cycles() {
        assert_eq!(c.distinct_edges(), 3);
        assert_eq!(c.order, 1);
    }
    assert!(
        (s.volume() - 2.0 * PI * PI / 120.0).abs() < 1e-9,
        "volume {}",
        s.volume()
    );
    assert_eq!(s.group_order(), Some(120));
    let h = s.first_homology().expect("homology");
    assert_eq!((h.rank, h.torsion.len()), (0, 0), "a homology sphere: H1 = {h}");
    // The group acts freely: no element but the identity has a fixed point
    // on S3 (an eigenvalue 1, so det(g - I) = 0).
    let CellScheme::Finite { elements, .. } = s.cells() else {
        panic!("Poincaré has a finite cell table")
    };
    for (k, g) in elements.iter().enumerate().skip(1) {
        let det = (*g - DMat4::IDENTITY).determinant();
        assert!(det.abs() > 1e-6, "element {k} fixes a point (det(g - I) = {det})");
    }
    // It contains -I (the binary icosahedral group's centre).
    assert!(
        elements
            .iter()
            .any(|g| (*g + DMat4::IDENTITY).abs_diff_eq(DMat4::ZERO, 1e-9))
    );
}

use bevy_manifold_core::space::cells::CellScheme;

fn mirrored_dodecahedron() {
    let s = catalog::mirrored_dodecahedron();
    all_dihedrals(&s, 90.0);
    assert!((s.inradius() - 0.808461).abs() < 1e-6, "inradius {}", s.inradius());
    assert!((s.volume() - 4.306208).abs() < 1e-5, "volume {}", s.volume());
    assert!(!s.is_manifold());
    for c in s.edge_cycles() {
        assert_eq!(c.order, 2, "right-angled mirror edges are corner reflectors of order 2");
    }
    for f in s.faces() {
        assert_eq!(f.kind, FaceKind::Mirror);
        assert!(isometry::is_orientation_reversing(f.pairing));
    }
}

fn torus_and_mirrored_cube() {
    let t = catalog::torus(1.0);
    assert!((t.volume() - 1.0).abs() < 1e-12);
    for f in t.faces() {
        let shift = f.pairing * DVec4::W - DVec4::W;
        assert!((shift.length() - 1.0).abs() < 1e-15, "a translation by a unit vector");
        assert!(shift.truncate().abs().max_element() == 1.0);
        assert_eq!(
            DMat4::from_cols(f.pairing.x_axis, f.pairing.y_axis, f.pairing.z_axis, DVec4::W),
            DMat4::IDENTITY
        );
    }
    assert_eq!(t.first_homology().expect("homology").rank, 3);
    assert!((catalog::torus(2.0).volume() - 8.0).abs() < 1e-12);
    let c = catalog::mirrored_cube(1.0);
    assert!((c.volume() - 1.0).abs() < 1e-12);
    all_dihedrals(&c, 90.0);
    assert!(!c.is_manifold());
}

fn every_catalog_space_validates_and_round_trips_through_json() {
    for name in catalog::NAMES {
        let s = catalog::by_name(name).expect("catalog name");
        s.validate().unwrap_or_else(|e| panic!("{name}: {e}"));
        let json = s.to_json();
        let back = SpaceDesc::parse(&json, Path::new("export.json")).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(back.faces().len(), s.faces().len());
        for (a, b) in s.faces().iter().zip(back.faces()) {
            assert!((a.plane - b.plane).length() < 1e-15);
            assert!(a.pairing.abs_diff_eq(b.pairing, 1e-15));
        }
        assert!((back.volume() - s.volume()).abs() < 1e-12);
    }
}

/// The project's shared folder's Curved Spaces files (beside the
/// repository; never copied into it).
fn curved_spaces() -> Result<std::path::PathBuf, String> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/curved-spaces");
    if dir.join("poincare.gen").is_file() {
        Ok(dir)
    } else {
        Err(format!("{} has no poincare.gen", dir.display()))
    }
}

/// Matrices from one of Weeks' Curved Spaces `.gen` files, turned into our
/// column-vector convention (his act on row vectors from the right).
fn read_gen(name: &str) -> Option<Vec<DMat4>> {
    let text = std::fs::read_to_string(curved_spaces().ok()?.join(name)).ok()?;
    let nums: Vec<f64> = text
        .lines()
        .filter(|l| !l.trim_start().starts_with('#'))
        .flat_map(|l| l.split_whitespace().map(|t| t.parse::<f64>().expect("a number")))
        .collect();
    // Row-major rows of M for v' = v M: M's rows are our matrix's columns.
    Some(nums.chunks_exact(16).map(DMat4::from_cols_slice).collect())
}

/// All elements generated by `gens`, told apart by where they send the origin.
fn generate(gens: &[DMat4], limit: usize) -> Vec<DMat4> {
    let mut els = vec![DMat4::IDENTITY];
    let mut k = 0;
    while k < els.len() && els.len() < limit {
        for g in gens {
            let m = els[k] * *g;
            if !els.iter().any(|e| (e.w_axis - m.w_axis).length() < 1e-6) {
                els.push(m);
            }
        }
        k += 1;
    }
    els
}

fn the_curved_spaces_files_agree_with_the_catalog() {
    // An independent source: Weeks' Curved Spaces gives the same spaces as
    // matrix generators, in his own coordinates and chirality.
    // The harness runs this only when the files are there (or under CI).
    let theirs = read_gen("poincare.gen").expect("the shared Curved Spaces files");
    // Poincaré: his two generators give a group of 120 elements whose traces
    // (a conjugation invariant of the representation) match ours one for one.
    let mut their_traces: Vec<f64> = generate(&theirs, 1000).iter().map(trace).collect();
    let CellScheme::Finite { elements, .. } = catalog::poincare().cells().clone() else {
        panic!("finite")
    };
    let mut our_traces: Vec<f64> = elements.iter().map(trace).collect();
    assert_eq!(their_traces.len(), 120);
    their_traces.sort_by(f64::total_cmp);
    our_traces.sort_by(f64::total_cmp);
    for (a, b) in their_traces.iter().zip(&our_traces) {
        assert!((a - b).abs() < 1e-9, "traces differ: {a} vs {b}");
    }
    // Seifert-Weber and the mirrored dodecahedron: twelve generators each,
    // each moving the centre by twice the inradius with the same trace as ours.
    for (file, ours) in [
        ("seifert-weber.gen", catalog::seifert_weber()),
        ("mirrored-dodecahedron.gen", catalog::mirrored_dodecahedron()),
    ] {
        let theirs = read_gen(file).expect("file present");
        assert_eq!(theirs.len(), 12, "{file}");
        for m in &theirs {
            assert!(
                (trace(m) - trace(&ours.faces()[0].pairing)).abs() < 1e-9,
                "{file}: trace {}",
                trace(m)
            );
            let moved = Geometry::Hyperbolic.distance::<f64>(DVec4::W, *m * DVec4::W);
            assert!(
                (moved - 2.0 * ours.inradius()).abs() < 1e-9,
                "{file}: moves the centre by {moved}"
            );
        }
    }
}

fn torus_faces() -> Vec<Face> {
    catalog::torus(1.0).faces().to_vec()
}

fn broken_spaces_each_give_their_own_error() {
    let e = Geometry::Euclidean;
    // A wrong matrix: translation by 0.9 does not carry x = 1/2 onto x = -1/2.
    let mut f = torus_faces();
    f[0].pairing = isometry::translation(e, DVec3::new(-0.9, 0.0, 0.0));
    f[3].pairing = isometry::translation(e, DVec3::new(0.9, 0.0, 0.0));
    assert!(matches!(
        Space::new("t", e, f),
        Err(SpaceError::FaceNotMapped {
            face: 0,
            partner: 3,
            ..
        })
    ));

    // A matrix that is no isometry.
    let mut f = torus_faces();
    f[1].pairing = DMat4::from_scale(DVec3::splat(1.1)) * f[1].pairing;
    assert!(matches!(
        Space::new("t", e, f),
        Err(SpaceError::NotIsometry { face: 1, .. })
    ));

    // Swapped partner: face 0 says 4, but 4 says 1.
    let mut f = torus_faces();
    f[0].partner = 4;
    assert!(matches!(
        Space::new("t", e, f),
        Err(SpaceError::PartnerNotMutual {
            face: 0,
            partner: 4,
            back: 1
        })
    ));

    // T_partner * T_i != I: face 6 glued back with an extra fifth of a turn
    // (it still maps pentagon onto pentagon).
    let sw = catalog::seifert_weber();
    let mut f = sw.faces().to_vec();
    let axis = f[6].plane.truncate().normalize();
    f[6].pairing = isometry::rotation(-axis, TAU / 5.0) * f[6].pairing;
    match Space::new("sw", Geometry::Hyperbolic, f) {
        Err(SpaceError::NotInverse {
            face: 0, partner: 6, ..
        }) => {}
        other => panic!("expected T_6 T_0 != I, got {other:?}"),
    }

    // A mirror whose matrix is a translation.
    let mut f = catalog::mirrored_cube(1.0).faces().to_vec();
    f[2].pairing = isometry::translation(e, DVec3::new(0.0, 0.0, -1.0));
    assert!(matches!(
        Space::new("m", e, f),
        Err(SpaceError::FaceNotMapped { face: 2, .. } | SpaceError::NotReflection { face: 2, .. })
    ));

    // A mirror that names another face as partner.
    let mut f = catalog::mirrored_cube(1.0).faces().to_vec();
    f[0].partner = 3;
    f[3].partner = 0;
    assert!(matches!(
        Space::new("m", e, f),
        Err(SpaceError::KindPartner { face: 0, .. })
    ));

    // NaN entries.
    let mut f = torus_faces();
    f[5].pairing.w_axis.z = f64::NAN;
    assert_eq!(
        Space::new("t", e, f).unwrap_err(),
        SpaceError::NonFinite {
            face: 5,
            what: "pairing"
        }
    );
    let mut f = torus_faces();
    f[2].plane.x = f64::NAN;
    assert_eq!(
        Space::new("t", e, f).unwrap_err(),
        SpaceError::NonFinite { face: 2, what: "plane" }
    );

    // A face turned inside out (the origin on its outer side).
    let mut f = torus_faces();
    f[4].plane = -f[4].plane;
    assert!(matches!(
        Space::new("t", e, f),
        Err(SpaceError::OriginOutside { face: 4, .. })
    ));

    // Missing a face: the polyhedron does not close.
    let mut f = torus_faces();
    f.truncate(5);
    f[0].partner = 3;
    let r = Space::new("t", e, f);
    assert!(
        matches!(
            r,
            Err(SpaceError::NotCompact { .. } | SpaceError::PartnerOutOfRange { .. })
        ),
        "got {r:?}"
    );

    // A face that cuts nothing off (redundant).
    let mut f = torus_faces();
    f.push(Face {
        plane: DVec4::new(1.0, 1.0, 1.0, -5.0),
        partner: 6,
        kind: FaceKind::Mirror,
        pairing: isometry::reflection(e, DVec4::new(1.0, 1.0, 1.0, -5.0)),
    });
    assert!(matches!(
        Space::new("t", e, f),
        Err(SpaceError::RedundantFace { face: 6, vertices: 0 })
    ));

    // Too few faces.
    assert!(matches!(
        Space::new("t", e, torus_faces()[..3].to_vec()),
        Err(SpaceError::TooFewFaces { count: 3 })
    ));
}

/// S3 points on the far hemisphere (w <= 0) are outside the domain, which
/// lies in w > 0: a chart test dividing by w saw the antipode of a point
/// inside as inside, and wrap left it there. -1 is in the binary
/// icosahedral group, so the antipode of the origin wraps home to the
/// origin; and a spread of placements over the whole sphere (both
/// hemispheres) all wrap into the domain by a group element.
fn far_hemisphere_points_are_outside_and_wrap_home() {
    let space = catalog::poincare();
    let g = space.geometry();
    assert!(
        space.outside_face(-DVec4::W, 1e-9).is_some(),
        "the antipode of the centre is outside"
    );
    let (wrapped, element) = space.wrap(-DMat4::IDENTITY, 100);
    assert!((wrapped.w_axis - DVec4::W).length() < 1e-12, "{:?}", wrapped.w_axis);
    let close = |a: DMat4, b: DMat4, tol: f64| (a - b).abs().to_cols_array().iter().all(|x| *x < tol);
    assert!(close(element * wrapped, -DMat4::IDENTITY, 1e-12));
    let mut far = 0;
    for k in 0..400 {
        // Placements along great circles through the centre, past the
        // equator (distance pi / 2) towards the antipode.
        let t = f64::from(k) * 0.0075 + 0.1;
        let s = f64::from(k);
        let dir = DVec3::new((s * 3.1).sin(), (s * 1.7).cos(), (s * 0.7).sin()).normalize();
        let m = isometry::translation(g, dir * t);
        far += usize::from(m.w_axis.w <= 0.0);
        let (wrapped, element) = space.wrap(m, 1000);
        assert!(
            space.outside_face(wrapped.w_axis, 1e-9).is_none(),
            "distance {t}: left outside"
        );
        assert!(close(element * wrapped, m, 1e-9), "distance {t}");
    }
    assert!(far > 100, "{far} of the placements were on the far hemisphere");
}

fn oversized_spaces_are_refused_before_any_quartic_work() {
    // 200 faces (the torus's six repeated): refused by count at once, where
    // building the polyhedron would take 200^4 / 6 plane tests.
    let faces: Vec<Face> = (0..200).map(|i| torus_faces()[i % 6].clone()).collect();
    let start = std::time::Instant::now();
    let err = Space::new("big", Geometry::Euclidean, faces).unwrap_err();
    assert_eq!(
        err,
        SpaceError::TooManyFaces {
            count: 200,
            max: bevy_manifold_core::space::MAX_FACES
        }
    );
    assert!(start.elapsed().as_millis() < 1000);
}

fn broken_space_files_name_the_file_and_the_problem() {
    let good = catalog::torus(1.0).to_desc();
    let parse = |text: &str| SpaceDesc::parse(text, Path::new("broken.json")).unwrap_err();

    // Missing field.
    let err = parse(
        r#"{"name": "x", "geometry": "euclidean", "faces": [{"plane": [1,0,0,-0.5], "kind": "glue", "pairing": [[1,0,0,-1],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}]}"#,
    );
    let msg = err.to_string();
    assert!(
        msg.starts_with("broken.json:") && msg.contains("missing field `partner`"),
        "{msg}"
    );
    assert!(matches!(err.kind, SpaceFileErrorKind::Json(_)));

    // Unknown geometry.
    let msg = parse(r#"{"name": "x", "geometry": "elliptic", "faces": []}"#).to_string();
    assert!(msg.contains("elliptic"), "{msg}");

    // Not JSON at all.
    assert!(matches!(parse("dodecahedron please").kind, SpaceFileErrorKind::Json(_)));

    // A listed vertex that is no corner of the faces' polyhedron (a dent:
    // the file describes a non-convex shape).
    let mut d = good.clone();
    d.vertices.as_mut().expect("export lists vertices")[0] = [0.7, 0.5, 0.5, 1.0];
    let err = parse(&serde_json::to_string(&d).expect("serialise"));
    assert!(
        matches!(
            err.kind,
            SpaceFileErrorKind::Invalid(SpaceError::VertexMismatch { index: 0, .. })
        ),
        "{err}"
    );
    assert!(err.to_string().contains("outside face 0"), "{err}");

    // A wrong volume.
    let mut d = good.clone();
    d.volume = Some(1.5);
    let err = parse(&serde_json::to_string(&d).expect("serialise"));
    assert!(
        matches!(err.kind, SpaceFileErrorKind::Invalid(SpaceError::VolumeMismatch { .. })),
        "{err}"
    );

    // NaN survives JSON only as a non-number: serde rejects it by name.
    let text = serde_json::to_string(&good)
        .expect("serialise")
        .replacen("-0.5", "NaN", 1);
    assert!(matches!(parse(&text).kind, SpaceFileErrorKind::Json(_)));

    // A file that is not there.
    let err = Space::load("no/such/space.json").unwrap_err();
    assert!(err.to_string().starts_with("no/such/space.json: cannot read"), "{err}");
}

bevy_manifold_test_support::test_main_requiring! {
    cpu: [
        seifert_weber,
        the_papers_seifert_weber_twist_of_3pi_over_10_is_a_misprint,
        poincare,
        mirrored_dodecahedron,
        torus_and_mirrored_cube,
        every_catalog_space_validates_and_round_trips_through_json,
        broken_spaces_each_give_their_own_error,
        broken_space_files_name_the_file_and_the_problem,
        oversized_spaces_are_refused_before_any_quartic_work,
        far_hemisphere_points_are_outside_and_wrap_home,
    ],
    requiring(
        "the shared Curved Spaces files",
        curved_spaces().map(|d| d.display().to_string())
    ): [the_curved_spaces_files_agree_with_the_catalog],
}
