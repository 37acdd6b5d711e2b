//! Spaces from their generators: the library against volumes, group orders,
//! face counts and homology known from the mathematics; Weeks' Curved
//! Spaces files against the catalog; convention traps and broken lists
//! against the errors they must give.

use bevy_manifold_core::geometry::{Geometry, isometry};
use bevy_manifold_core::prelude::*;
use bevy_manifold_core::space::generators::{self, GeneratorError, Generators};
use bevy_manifold_core::space::{SpaceFileErrorKind, catalog, library};
use bevy_manifold_test_support::stress;
use glam::{DMat4, DVec3, DVec4};
use std::f64::consts::{PI, TAU};
use std::path::{Path, PathBuf};

/// Volume of S3 over the group order.
fn spherical_volume(order: usize) -> f64 {
    2.0 * PI * PI / order as f64
}

fn build(name: &str) -> Space {
    library::by_name(name)
        .unwrap_or_else(|| panic!("{name} is in the library"))
        .dirichlet_domain()
        .unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// Checks volume (1e-9), face count, group order and H1 of one space.
fn expect(s: &Space, volume: f64, faces: usize, order: Option<usize>, h1: &str) {
    let name = s.name();
    assert!(
        (s.volume() - volume).abs() < 1e-9,
        "{name}: volume {} against {volume}",
        s.volume()
    );
    assert_eq!(s.faces().len(), faces, "{name}: face count");
    assert_eq!(s.group_order(), order, "{name}: group order");
    assert_eq!(s.first_homology().expect("homology").to_string(), h1, "{name}: H1");
    assert!(s.is_manifold(), "{name} is a manifold");
    if s.lens().is_some() {
        // A lens or hemisphere: no vertices, no edges.
        assert!(s.vertices().is_empty() && s.edges().is_empty(), "{name}");
        return;
    }
    // Euler: V - E + F = 2 for the polyhedron's boundary sphere.
    assert_eq!(
        s.vertices().len() + faces,
        s.edges().len() + 2,
        "{name}: Euler characteristic"
    );
}

fn the_spherical_library_has_the_right_volumes_orders_and_homology() {
    // Lens spaces L(p, q): order p, volume 2 pi^2 / p, H1 = Z/p.
    for (p, q) in library::LENS {
        let s = build(&format!("lens-{p}-{q}"));
        let p = p as usize;
        assert_eq!(s.group_order(), Some(p));
        expect(&s, spherical_volume(p), s.faces().len(), Some(p), &format!("Z/{p}"));
        assert!(s.faces().len() >= 4 && s.faces().len().is_multiple_of(2), "{q}");
    }
    // L(p, 1): every orbit a great circle, so the domain is a lens of two
    // faces at a dihedral angle of 2 pi / p, a quarter turn across (its
    // inradius pi / p); RP3 = L(2, 1) a hemisphere, its one face glued to
    // itself by the antipodal map.
    for p in library::LENS_ROUND {
        let name = if p == 2 {
            "rp3".to_string()
        } else {
            format!("lens-{p}-1")
        };
        let s = build(&name);
        let faces = if p == 2 { 1 } else { 2 };
        let order = p as usize;
        expect(&s, spherical_volume(order), faces, Some(order), &format!("Z/{p}"));
        let shape = s.lens().expect("a lens");
        assert!((shape.dihedral - TAU / f64::from(p)).abs() < 1e-9, "{name}: {shape:?}");
        assert!(
            (s.inradius() - PI / f64::from(p)).abs() < 1e-9,
            "{name}: {}",
            s.inradius()
        );
        assert!((s.circumradius() - PI / 2.0).abs() < 1e-12, "{name}");
        assert!((s.surface_area() - 4.0 * PI).abs() < 1e-9, "{name}");
    }
    // S3/Q8: the Voronoi cell of 1 among {+-1, +-i, +-j, +-k} is a cube.
    expect(&build("quaternionic"), spherical_volume(8), 6, Some(8), "Z/2 + Z/2");
    // Prism manifolds S3/D*_4m: the orbit of 1 is 2m points on the circle
    // through 1 and i (two faces, from e^(+-i pi/m)) and 2m points on the
    // circle through j, all at distance pi/2 (2m side faces): a prism.
    // H1 is Z/4 for odd m, Z/2 + Z/2 for even m.
    for m in library::PRISM {
        let h1 = if m % 2 == 1 { "Z/4" } else { "Z/2 + Z/2" };
        let order = 4 * m as usize;
        expect(
            &build(&format!("prism-{m}")),
            spherical_volume(order),
            2 * m as usize + 2,
            Some(order),
            h1,
        );
    }
    // Binary tetrahedral: the 24-cell's vertices, each with 8 nearest
    // neighbours: an octahedron. H1 = Z/3.
    expect(&build("binary-tetrahedral"), spherical_volume(24), 8, Some(24), "Z/3");
    // Binary octahedral: a truncated cube (6 octagons, 8 triangles). H1 = Z/2.
    expect(&build("binary-octahedral"), spherical_volume(48), 14, Some(48), "Z/2");
    // Binary icosahedral: the Poincare dodecahedron. H1 = 0.
    expect(&build("poincare-generators"), spherical_volume(120), 12, Some(120), "0");
}

fn sorted_dihedrals(s: &Space) -> Vec<f64> {
    let mut d: Vec<f64> = s.edges().iter().map(|e| e.dihedral).collect();
    d.sort_by(f64::total_cmp);
    d
}

fn same_shape(a: &Space, b: &Space) {
    assert_eq!(a.faces().len(), b.faces().len(), "{} vs {}", a.name(), b.name());
    assert_eq!(a.vertices().len(), b.vertices().len());
    assert!((a.volume() - b.volume()).abs() < 1e-9);
    assert!((a.inradius() - b.inradius()).abs() < 1e-9);
    assert!((a.circumradius() - b.circumradius()).abs() < 1e-9);
    for (x, y) in sorted_dihedrals(a).iter().zip(sorted_dihedrals(b)) {
        assert!((x - y).abs() < 1e-9, "{}: dihedral {x} vs {y}", a.name());
    }
}

fn lens_spaces_that_are_the_same_manifold_give_the_same_domain() {
    // L(7,2) and L(7,3) are homeomorphic (2 * 3 = -1 mod 7), indeed
    // isometric: the domains at a Clifford-torus point are congruent.
    same_shape(
        &library::lens(7, 2).dirichlet_domain().unwrap(),
        &library::lens(7, 3).dirichlet_domain().unwrap(),
    );
    // L(8,3) and L(8,5) likewise (3 * 5 = -1 mod 8... 15 = -1 mod 8).
    same_shape(
        &library::lens(8, 3).dirichlet_domain().unwrap(),
        &library::lens(8, 5).dirichlet_domain().unwrap(),
    );
}

fn the_poincare_space_from_two_generators_is_the_catalog_one() {
    let ours = catalog::poincare();
    let built = build("poincare-generators");
    same_shape(&built, &ours);
    for e in built.edges() {
        assert!((e.dihedral.to_degrees() - 120.0).abs() < 1e-9);
    }
}

/// The point of the hyperboloid above `(x, y, z)`, as
/// `stress::seifert_weber_about` lifts its basepoint.
fn on_hyperboloid(x: f64, y: f64, z: f64) -> [f64; 4] {
    [x, y, z, (1.0 + x * x + y * y + z * z).sqrt()]
}

/// A generator list far longer than it needs to be builds the same
/// domain: Seifert-Weber's 12 face pairings and 52 products of two of them
/// (64 generators, the most a list may have; the products move the
/// origin up to 4.0, twice a pairing). The search once kept every product
/// of the elements it expanded, so 128 letters filled it past
/// `MAX_ELEMENTS` with elements outside its radius, and this discrete
/// group was refused as "not discrete". Both domains are checked against
/// the same group given by its pairings alone: the catalog's dodecahedron
/// about the origin, and the 52-face domain about another point.
fn redundant_generators_give_the_same_domain() {
    let sw = catalog::seifert_weber();
    let pairings: Vec<DMat4> = sw.faces().iter().map(|f| f.pairing).collect();
    let mut matrices = pairings.clone();
    for a in 0..12 {
        for b in 0..12 {
            if sw.faces()[a].partner != b && matrices.len() < 64 {
                matrices.push(pairings[a] * pairings[b]);
            }
        }
    }
    assert_eq!(matrices.len(), generators::MAX_GENERATORS);
    let (x, y, z) = bevy_manifold_test_support::stress::FIFTY_TWO_FACES;
    let about = bevy_manifold_test_support::stress::seifert_weber_about(x, y, z).expect("52 faces");
    for (point, reference) in [(None, &sw), (Some(on_hyperboloid(x, y, z)), &about)] {
        let mut gens = Generators::of_geometry("seifert-weber, 64 generators", Geometry::Hyperbolic, matrices.clone())
            .expect("isometries");
        gens.set_basepoint(point).expect("a point");
        let built = gens
            .dirichlet_domain()
            .unwrap_or_else(|e| panic!("about {point:?}: {e}"));
        same_shape(&built, reference);
        assert_eq!(built.first_homology().expect("homology").to_string(), "Z/5 + Z/5 + Z/5");
    }
    assert_eq!(about.faces().len(), 52);
}

/// A 5-fold cyclic cover of the Weeks manifold (H1 = Z/5 + Z/5, so its
/// group maps onto Z/5), built from the kernel's shortest elements
/// (`stress::cyclic_cover`: 64 generators, computed here from the edge
/// cycles, not taken from a table) has five times the Weeks manifold's volume, about the origin and about
/// another point: the kernel is the whole kernel, the domain a
/// fundamental domain of it, and the volume integration right over 36 or
/// more faces. A cover is a manifold whatever the basepoint.
fn a_five_fold_cover_has_five_times_the_volume() {
    let weeks = build("weeks");
    let mut cover = bevy_manifold_test_support::stress::cyclic_cover(&weeks, 5, 3.0).expect("H1 maps onto Z/5");
    assert_eq!(cover.matrices.len(), generators::MAX_GENERATORS);
    for point in [None, Some(on_hyperboloid(0.1, 0.05, 0.02))] {
        cover.set_basepoint(point).expect("a point");
        let s = cover
            .dirichlet_domain()
            .unwrap_or_else(|e| panic!("about {point:?}: {e}"));
        assert!(
            (s.volume() - 5.0 * weeks.volume()).abs() < 1e-9,
            "about {point:?}: volume {} against 5 x {}",
            s.volume(),
            weeks.volume()
        );
        assert!(s.is_manifold());
        assert!(s.faces().len() > 32, "about {point:?}: {} faces", s.faces().len());
    }
}

/// Seifert-Weber about points near the centre of its dodecahedron, five
/// that the search once refused as not discrete: the first cut, from the
/// 12 pairings alone, is a polytope with a circumradius of 2.4-3.7, and
/// the search jumped its radius to twice that (5-7.5), where f64 products
/// lose the identity ("an element moves the basepoint by only 4.7e-7:
/// images of it pile up") or fill the search ("more than 60000
/// elements"). The radius now grows at most 1.5 times a round, and the
/// polytope shrinks as elements are added (to a circumradius of about
/// 1.85). Each domain is one of the same manifold: the dodecahedron's
/// volume and homology, a closed manifold, 52-56 faces.
fn seifert_weber_builds_about_points_near_its_centre() {
    let sw = catalog::seifert_weber();
    for (x, y, z) in [
        (0.02, 0.06, 0.014),
        (0.0671, -0.0349, 0.0121),
        (-0.0487, -0.0414, -0.0094),
        (-0.0028, -0.0573, -0.0631),
        (0.0517, -0.0567, 0.012),
    ] {
        let s = stress::domain_about(&sw, x, y, z).unwrap_or_else(|e| panic!("about ({x}, {y}, {z}): {e}"));
        assert!(
            (s.volume() - sw.volume()).abs() < 1e-9,
            "about ({x}, {y}, {z}): volume {} against {}",
            s.volume(),
            sw.volume()
        );
        assert!(s.is_manifold());
        assert!(
            (52..=56).contains(&s.faces().len()),
            "about ({x}, {y}, {z}): {} faces",
            s.faces().len()
        );
        assert_eq!(s.first_homology().expect("homology").to_string(), "Z/5 + Z/5 + Z/5");
    }
}

/// The Weeks manifold from its domain's face pairings, about basepoints
/// far from that domain's centre (1.9 and 2.1 from it), where the words
/// to the elements are long and their matrices' entries large. The search once
/// re-orthonormalised every product, which rounds such an element by far
/// more than the product does, and refused both points: "an element
/// moves the basepoint by only 1.172e-7" and "2.447e-7". Each domain is
/// one of the same manifold: the published volume and H1 = Z/5 + Z/5.
fn the_weeks_manifold_builds_about_far_basepoints() {
    let weeks = build("weeks");
    for (x, y, z) in [
        (
            -1.706_374_949_671_634_5,
            -1.872_605_655_408_364,
            2.064_597_997_701_417_5,
        ),
        (2.249_794_827_398_045, -2.334_625_139_932_584_6, -2.253_919_203_950_801),
    ] {
        let s = stress::domain_about(&weeks, x, y, z).unwrap_or_else(|e| panic!("about ({x}, {y}, {z}): {e}"));
        assert!(
            (s.volume() - 0.942_707_362_776_927_7).abs() < 1e-9,
            "about ({x}, {y}, {z}): volume {}",
            s.volume()
        );
        assert!(s.is_manifold());
        assert_eq!(s.first_homology().expect("homology").to_string(), "Z/5 + Z/5");
    }
}

fn the_flat_library_has_the_right_volumes_and_homology() {
    let hex = 3f64.sqrt() / 2.0;
    // 3-tori: the lattice covolume; the Voronoi cell of the hexagonal
    // lattice is a hexagonal prism, of the body-centred one a truncated
    // octahedron (8 hexagons, 6 squares).
    expect(&build("torus-hexagonal"), hex, 8, None, "Z^3");
    expect(&build("torus-bcc"), 0.5, 14, None, "Z^3");
    // Screw spaces: translations a, b and c = (turn by 2 pi / k) + 1 along z.
    // The translation subgroup has c^k (length k) and a, b: covolume
    // k * area, over the point group of order k: the volume is the area.
    expect(&build("half-turn"), 1.0, 6, None, "Z + Z/2 + Z/2");
    expect(&build("quarter-turn"), 1.0, 6, None, "Z + Z/2");
    expect(&build("third-turn"), hex, 8, None, "Z + Z/3");
    expect(&build("sixth-turn"), hex, 8, None, "Z");
    // Hantzsche-Wendt: translations Z^3 (the squares of the generators),
    // point group Z/2 x Z/2: volume 1/4; H1 = Z/4 + Z/4. Its Dirichlet
    // domain at a point off the axes is a rhombic dodecahedron.
    expect(&build("hantzsche-wendt"), 0.25, 12, None, "Z/4 + Z/4");
    // First amphicosm: translations (2,0,0), y, z over Z/2: volume 1.
    expect(&build("amphicosm"), 1.0, 6, None, "Z^2 + Z/2");
    let s = build("amphicosm");
    assert!(
        s.faces().iter().any(|f| isometry::is_orientation_reversing(f.pairing)),
        "the amphicosm glues by a glide reflection"
    );
}

fn the_weeks_manifold_has_the_published_volume_and_homology() {
    let gens = library::weeks();
    assert_eq!(gens.geometry, Geometry::Hyperbolic);
    // The generators satisfy the relators, as Lorentz matrices.
    let [a, b] = [gens.matrices[0], gens.matrices[1]];
    let inv = |m: DMat4| isometry::inverse(Geometry::Hyperbolic, m);
    for r in library::WEEKS_RELATORS {
        let m = r.chars().fold(DMat4::IDENTITY, |m, c| {
            m * match c {
                'a' => a,
                'b' => b,
                'A' => inv(a),
                _ => inv(b),
            }
        });
        assert!(m.abs_diff_eq(DMat4::IDENTITY, 1e-9), "relator {r}");
    }
    // tr a in SL(2,C) is the complex root theta of t^3 - t + 1 (the trace
    // field's generator); a Lorentz matrix's trace is |tr A|^2. The root by
    // Newton's method, in complex arithmetic written out here.
    let (mut x, mut y) = (0.6, 0.5);
    for _ in 0..50 {
        // f = t^3 - t + 1, f' = 3 t^2 - 1, t = x + i y.
        let (t2r, t2i) = (x * x - y * y, 2.0 * x * y);
        let (t3r, t3i) = (t2r * x - t2i * y, t2r * y + t2i * x);
        let (fr, fi) = (t3r - x + 1.0, t3i - y);
        let (dr, di) = (3.0 * t2r - 1.0, 3.0 * t2i);
        let d = dr * dr + di * di;
        x -= (fr * dr + fi * di) / d;
        y -= (fi * dr - fr * di) / d;
    }
    let trace = a.x_axis.x + a.y_axis.y + a.z_axis.z + a.w_axis.w;
    assert!(
        (trace - (x * x + y * y)).abs() < 1e-9,
        "trace {trace} vs |theta|^2 {}",
        x * x + y * y
    );
    // Its Dirichlet domain: the published volume 0.9427073627769277 (the
    // least of any closed orientable hyperbolic 3-manifold; Gabai,
    // Meyerhoff and Milley 2009; OEIS A126774) and H1 = Z/5 + Z/5.
    let s = gens.dirichlet_domain().unwrap();
    expect(&s, 0.942_707_362_776_927_7, s.faces().len(), None, "Z/5 + Z/5");
    // At another basepoint the domain differs, the volume does not.
    let mut moved = gens.clone();
    moved.basepoint = Some(isometry::translation(Geometry::Hyperbolic, DVec3::new(0.1, -0.07, 0.03)).w_axis);
    let t = moved.dirichlet_domain().unwrap();
    assert!((t.volume() - s.volume()).abs() < 1e-9);
    assert_ne!(t.faces().len(), s.faces().len(), "a different domain, the same space");
    // Basepoints where the words to some elements within the search radius
    // pass outside it: the first domain cut leaves faces that do not pair,
    // and the search expands one step further (these were refused before).
    for p in [[0.1, 0.05, 0.02], [0.2, 0.1, 0.05], [0.15, 0.1, 0.03]] {
        let mut moved = gens.clone();
        moved.basepoint = Some(Geometry::Hyperbolic.normalize_point::<f64>(DVec4::new(p[0], p[1], p[2], 1.0)));
        let t = moved.dirichlet_domain().unwrap_or_else(|e| panic!("about {p:?}: {e}"));
        assert!(
            (t.volume() - 0.942_707_362_776_927_7).abs() < 1e-9,
            "about {p:?}: volume {}",
            t.volume()
        );
    }
}

/// The shipped files are the library's generators, written out; each
/// loads as a space through the file path a user would take.
fn the_shipped_library_files_are_the_library() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/spaces");
    let mut files: Vec<String> = std::fs::read_dir(&dir)
        .expect("assets/spaces")
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter(|n| n.ends_with(".gen"))
        .collect();
    files.sort();
    let mut names: Vec<String> = library::names().iter().map(|n| format!("{n}.gen")).collect();
    names.sort();
    assert_eq!(files, names, "assets/spaces holds one file per library space");
    for name in library::names() {
        let path = dir.join(format!("{name}.gen"));
        let read = Generators::load(&path).unwrap_or_else(|e| panic!("{e}"));
        let ours = library::by_name(&name).unwrap();
        assert_eq!(read.geometry, ours.geometry, "{name}");
        assert_eq!(read.manifold, ours.manifold, "{name}");
        assert_eq!(read.basepoint.is_some(), ours.basepoint.is_some(), "{name}");
        if let (Some(a), Some(b)) = (read.basepoint, ours.basepoint) {
            assert!((a - b).length() < 1e-15, "{name}: basepoint");
        }
        assert_eq!(read.matrices.len(), ours.matrices.len(), "{name}");
        for (a, b) in read.matrices.iter().zip(&ours.matrices) {
            assert!(a.abs_diff_eq(*b, 1e-15), "{name}: the file's matrices differ");
        }
        let space = Space::load(&path).unwrap_or_else(|e| panic!("{e}"));
        assert!((space.volume() - build(&name).volume()).abs() < 1e-12, "{name}");
    }
}

fn generator_lists_round_trip_through_json_and_gen() {
    for name in library::names() {
        let gens = library::by_name(&name).unwrap();
        let json = serde_json::to_string(&gens.to_desc()).unwrap();
        let back = Generators::parse_json(&json).unwrap();
        assert_eq!(back, gens, "{name} through JSON");
        let text = gens.to_gen("a comment\nover two lines");
        let back = Generators::parse_gen(&text, name.clone()).unwrap();
        for (a, b) in back.matrices.iter().zip(&gens.matrices) {
            assert!(a.abs_diff_eq(*b, 1e-16), "{name} through .gen");
        }
        assert_eq!(back.basepoint.is_some(), gens.basepoint.is_some());
    }
}

/// The project's shared folder's Curved Spaces files (beside the
/// repository; never copied into it).
fn curved_spaces() -> Result<PathBuf, String> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/curved-spaces");
    if dir.join("poincare.gen").is_file() {
        Ok(dir)
    } else {
        Err(format!("{} has no poincare.gen", dir.display()))
    }
}

fn weeks(name: &str) -> PathBuf {
    curved_spaces().expect("the shared Curved Spaces files").join(name)
}

fn every_curved_spaces_file_loads_and_matches() {
    // Poincare from Weeks' two generators: the catalog's dodecahedron.
    let poincare = Space::load(weeks("poincare.gen")).unwrap();
    same_shape(&poincare, &catalog::poincare());
    assert_eq!(poincare.group_order(), Some(120));
    // Seifert-Weber from his twelve generators: the catalog's space.
    let sw = Space::load(weeks("seifert-weber.gen")).unwrap();
    same_shape(&sw, &catalog::seifert_weber());
    assert_eq!(sw.first_homology().expect("homology").to_string(), "Z/5 + Z/5 + Z/5");
    assert!(sw.is_manifold());
    // The mirrored right-angled dodecahedron: twelve mirrors at 90 degrees.
    let md = Space::load(weeks("mirrored-dodecahedron.gen")).unwrap();
    same_shape(&md, &catalog::mirrored_dodecahedron());
    assert!(md.faces().iter().all(|f| f.kind == FaceKind::Mirror));
    assert!(!md.is_manifold());
    // The flat ones: unit cube, volume 1.
    for (file, h1) in [("3-torus.gen", "Z^3"), ("half-turn.gen", "Z + Z/2 + Z/2")] {
        let s = Space::load(weeks(file)).unwrap();
        assert_eq!(s.faces().len(), 6, "{file}");
        assert!((s.volume() - 1.0).abs() < 1e-12, "{file}");
        assert_eq!(s.first_homology().expect("homology").to_string(), h1, "{file}");
    }
    // L(5,1): a rotation of order 5 whose orbit of the basepoint is one
    // great circle, so the domain about it is a lens: two faces meeting at
    // 72 degrees in the great circle a quarter turn away, volume 2 pi^2 / 5.
    // The pairings are the file's own generator and its inverse, in the
    // file's coordinates: the basepoint stays where the file puts it.
    let gens = Generators::load(weeks("lens-5-1.gen")).unwrap();
    assert_eq!(gens.geometry, Geometry::Spherical);
    let m = gens.matrices[0];
    let fifth = m * m * m * m * m;
    assert!(fifth.abs_diff_eq(DMat4::IDENTITY, 1e-12), "order 5");
    let lens = Space::load(weeks("lens-5-1.gen")).unwrap();
    expect(&lens, spherical_volume(5), 2, Some(5), "Z/5");
    assert!((lens.lens().expect("a lens").dihedral - TAU / 5.0).abs() < 1e-9);
    let inverse = isometry::inverse(Geometry::Spherical, m);
    for f in lens.faces() {
        assert!(
            f.pairing.abs_diff_eq(m, 1e-12) || f.pairing.abs_diff_eq(inverse, 1e-12),
            "a pairing that is not the file's generator or its inverse: {:?}",
            f.pairing
        );
    }
}

/// A matrix's text in `.gen` rows (row-vector convention: rows are our
/// columns).
fn gen_text(ms: &[DMat4]) -> String {
    let mut t = String::from("# test\n");
    for m in ms {
        for c in m.to_cols_array_2d() {
            t.push_str(&format!("{} {} {} {}\n", c[0], c[1], c[2], c[3]));
        }
        t.push('\n');
    }
    t
}

fn transposed_files_are_caught_or_harmless() {
    let e = Geometry::Euclidean;
    let cube: Vec<DMat4> = [DVec3::X, DVec3::Y, DVec3::Z]
        .map(|v| isometry::translation(e, v))
        .to_vec();
    assert!(Generators::parse_gen(&gen_text(&cube), "cube").is_ok());
    // Written with the translation in the last column: caught.
    let transposed: Vec<DMat4> = cube.iter().map(|m| m.transpose()).collect();
    let err = Generators::parse_gen(&gen_text(&transposed), "cube").unwrap_err();
    assert_eq!(err, GeneratorError::Transposed { matrix: 0 });
    // S3 and H3: the transposed list generates the same group (S3) or its
    // mirror image (H3): the same domain, never a wrong space.
    for space in [catalog::poincare(), catalog::seifert_weber()] {
        let ms: Vec<DMat4> = space.faces().iter().map(|f| f.pairing.transpose()).collect();
        let built = Generators::parse_gen(&gen_text(&ms), "t")
            .unwrap()
            .dirichlet_domain()
            .unwrap();
        same_shape(&built, &space);
    }
}

fn broken_generator_lists_give_their_own_errors() {
    let e = Geometry::Euclidean;
    let t = |v: DVec3| isometry::translation(e, v);
    let parse = |text: &str| Generators::parse_gen(text, "x");
    // Text problems name the line.
    assert_eq!(
        parse("1 0 0 0\n0 1 0 0\n0 zero 1 0\n").unwrap_err(),
        GeneratorError::NotANumber {
            line: 3,
            token: "zero".into()
        }
    );
    assert_eq!(
        parse("1 0 0\n").unwrap_err(),
        GeneratorError::RowLength { line: 1, count: 3 }
    );
    assert_eq!(
        parse("1 0 0 0\n0 1 0 0\n").unwrap_err(),
        GeneratorError::Incomplete { matrix: 0, rows: 2 }
    );
    assert_eq!(parse("# nothing\n").unwrap_err(), GeneratorError::Count { count: 0 });
    assert!(matches!(
        parse("NaN 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n").unwrap_err(),
        GeneratorError::NonFinite {
            matrix: 0,
            row: 0,
            col: 0
        }
    ));
    // A scaling is an isometry of nothing.
    let scale = DMat4::from_scale(DVec3::splat(1.5));
    assert!(matches!(
        Generators::new("x", vec![t(DVec3::X), scale]),
        Err(GeneratorError::NotIsometry { matrix: 1, .. })
    ));
    // Mixed: a flat translation with an S3 rotation of the xw-plane.
    let s3 = isometry::translation(Geometry::Spherical, DVec3::X * 0.3);
    assert!(matches!(
        Generators::new("x", vec![t(DVec3::X), s3]),
        Err(GeneratorError::MixedGeometries {
            matrix: 1,
            other: 0,
            ..
        })
    ));
    // Only rotations about the origin: no geometry, no compact quotient.
    assert_eq!(
        Generators::new("x", vec![isometry::rotation(DVec3::Z, 1.0)]).unwrap_err(),
        GeneratorError::AllFixOrigin
    );
    // Not discrete: translations by 1 and sqrt 2 along x pile up.
    let dense = Generators::new(
        "x",
        vec![t(DVec3::X), t(DVec3::X * 2f64.sqrt()), t(DVec3::Y), t(DVec3::Z)],
    )
    .unwrap();
    assert!(
        matches!(dense.dirichlet_domain(), Err(GeneratorError::NotDiscrete { .. })),
        "{:?}",
        dense.dirichlet_domain().err()
    );
    // An S3 rotation by an irrational angle: infinite order, not discrete.
    let irrational = Generators::new("x", vec![isometry::translation(Geometry::Spherical, DVec3::X)]).unwrap();
    assert!(matches!(
        irrational.dirichlet_domain(),
        Err(GeneratorError::NotDiscrete { .. })
    ));
    // Unbounded: two translations only.
    let slab = Generators::new("x", vec![t(DVec3::X), t(DVec3::Y)]).unwrap();
    assert!(matches!(
        slab.dirichlet_domain(),
        Err(GeneratorError::NotCompact { .. })
    ));
    // Half-turns about the lines x = +-1/2, z = 0 (along y) pair the faces
    // x = +-1/2 with themselves by rotation: refused with a named face.
    let half_turn_about = |x: f64| t(DVec3::X * x) * isometry::rotation(DVec3::Y, PI) * t(DVec3::X * -x);
    let pillow = Generators::new(
        "x",
        vec![half_turn_about(0.5), half_turn_about(-0.5), t(DVec3::Y), t(DVec3::Z)],
    )
    .unwrap();
    assert!(matches!(
        pillow.dirichlet_domain(),
        Err(GeneratorError::SelfPairedHalfTurn { .. })
    ));
}

fn orbifolds_move_the_basepoint_and_manifold_files_refuse_them() {
    let e = Geometry::Euclidean;
    let t = |v: DVec3| isometry::translation(e, v);
    // The cubic lattice and a half-turn about the z-axis through the
    // origin: the origin is fixed, so the domain is tried at generic
    // points; there the bisector of p and its turned image contains the
    // axis, a face paired with itself by the half-turn, which is refused
    // by name (only mirrors may pair a face with itself).
    let mut gens = Generators::new(
        "x",
        vec![t(DVec3::X), t(DVec3::Y), t(DVec3::Z), isometry::rotation(DVec3::Z, PI)],
    )
    .unwrap();
    let err = gens.dirichlet_domain().unwrap_err();
    assert!(matches!(err, GeneratorError::SelfPairedHalfTurn { .. }), "{err}");
    // Declared a manifold: refused at the origin, naming the element
    // that fixes it.
    gens.manifold = true;
    let err = gens.dirichlet_domain().unwrap_err();
    match &err {
        GeneratorError::NotFree { word, .. } => assert!(word.contains("g3"), "{err}"),
        _ => panic!("{err}"),
    }
    // Mirrors: reflections in the faces of the unit cube give the mirrored
    // cube, every face its own partner.
    let refl = |n: DVec3| isometry::reflection(e, n.extend(-0.5));
    let mirrors: Vec<DMat4> = [DVec3::X, -DVec3::X, DVec3::Y, -DVec3::Y, DVec3::Z, -DVec3::Z]
        .map(refl)
        .to_vec();
    let s = Generators::new("mirrors", mirrors).unwrap().dirichlet_domain().unwrap();
    assert_eq!(s.faces().len(), 6);
    assert!(s.faces().iter().all(|f| f.kind == FaceKind::Mirror));
    assert!((s.volume() - 1.0).abs() < 1e-12);
    same_shape(&s, &catalog::mirrored_cube(1.0));
}

fn a_basepoint_centres_the_domain_there() {
    // The 3-torus at any basepoint is the unit cube around it; the space
    // comes out with the basepoint at the chart origin.
    let e = Geometry::Euclidean;
    let mut gens = Generators::new(
        "t",
        [DVec3::X, DVec3::Y, DVec3::Z]
            .map(|v| isometry::translation(e, v))
            .to_vec(),
    )
    .unwrap();
    gens.basepoint = Some(DVec4::new(0.3, -0.2, 0.1, 1.0));
    let s = gens.dirichlet_domain().unwrap();
    assert!((s.inradius() - 0.5).abs() < 1e-12);
    // The Poincare space at a point off the origin: the group acts by left
    // multiplication, whose isometries commute with right multiplications,
    // which move any point to any other: the same dodecahedron.
    let mut p = library::by_name("poincare-generators").unwrap();
    p.basepoint = Some(isometry::translation(Geometry::Spherical, DVec3::new(0.1, 0.2, 0.05)).w_axis);
    same_shape(&p.dirichlet_domain().unwrap(), &catalog::poincare());
    // A third-turn about the z-axis through the origin (with the
    // hexagonal lattice, an orbifold): the origin is fixed, so the domain
    // is built about a generic point, and says which; asked for that
    // basepoint, it is built there and says nothing moved. The volume is
    // a third of the lattice's cell, sqrt 3 / 2.
    let mut third = Generators::new(
        "p3",
        vec![
            isometry::translation(e, DVec3::X),
            isometry::translation(e, DVec3::new(0.5, 3f64.sqrt() / 2.0, 0.0)),
            isometry::translation(e, DVec3::Z),
            isometry::rotation(DVec3::Z, TAU / 3.0),
        ],
    )
    .unwrap();
    let cell = 3f64.sqrt() / 2.0 / 3.0;
    let (s, moved) = third.dirichlet_domain_and_basepoint().unwrap();
    let p = moved.expect("the origin is fixed: moved");
    assert!(e.distance::<f64>(p, DVec4::W) > 1e-3, "{p:?}");
    assert!((s.volume() - cell).abs() < 1e-9, "a third of the cell: {}", s.volume());
    third.basepoint = Some(p);
    let (again, moved) = third.dirichlet_domain_and_basepoint().unwrap();
    assert!(moved.is_none());
    assert!((again.volume() - cell).abs() < 1e-9);
    // A bad basepoint in a JSON list is named.
    let json = r#"{"name": "x", "generators": [[[1,0,0,1],[0,1,0,0],[0,0,1,0],[0,0,0,1]]], "basepoint": [0, 0, 0, 0]}"#;
    assert!(matches!(
        Generators::parse_json(json),
        Err(GeneratorError::BadBasepoint { .. })
    ));
}

/// The p3 group (the hexagonal lattice with a third-turn about the z-axis
/// through the origin) fixes the origin, so its domain is built about a
/// generic point `p`, and the chart's pairings are conjugates. The space
/// keeps the move as its file frame, through which each pairing is an
/// element of the file's group: by the group's own description, a linear
/// part `R^k` (a turn by a multiple of 120 degrees about z) and a
/// translation with integer coordinates in the lattice basis. The file's
/// origin, on the turn's axis, is on the domain's boundary. The frame
/// survives the space file; a frame that is not an isometry is named.
fn a_moved_domain_keeps_the_files_group_through_its_frame() {
    let e = Geometry::Euclidean;
    let v = DVec3::new(0.5, 3f64.sqrt() / 2.0, 0.0);
    let gens = Generators::new(
        "p3",
        vec![
            isometry::translation(e, DVec3::X),
            isometry::translation(e, v),
            isometry::translation(e, DVec3::Z),
            isometry::rotation(DVec3::Z, TAU / 3.0),
        ],
    )
    .unwrap();
    let (s, moved) = gens.dirichlet_domain_and_basepoint().unwrap();
    let p = moved.expect("the origin is fixed: moved");
    assert!(
        (s.file_frame().w_axis - p).length() < 1e-12,
        "the frame carries the origin to p"
    );
    // Coordinates of a translation in the basis (X, v, Z).
    let lattice = glam::DMat3::from_cols(DVec3::X, v, DVec3::Z).inverse();
    let in_group = |m: DMat4| {
        let linear = glam::DMat3::from_mat4(m);
        let turn = (0..3).any(|k| {
            let r = glam::DMat3::from_mat4(isometry::rotation(DVec3::Z, TAU * f64::from(k) / 3.0));
            (linear - r).to_cols_array().iter().all(|x| x.abs() < 1e-9)
        });
        let t = lattice * m.w_axis.truncate();
        turn && (t - t.round()).abs().max_element() < 1e-9
    };
    let turns = s
        .faces()
        .iter()
        .filter(|f| (f.pairing.x_axis.x - 1.0).abs() > 1e-6)
        .count();
    assert!(turns > 0, "some face is paired by a turn");
    for i in 0..s.faces().len() {
        assert!(in_group(s.file_pairing(i)), "face {i}: {:?}", s.file_pairing(i));
    }
    // The chart's own pairings of the turned faces are conjugates, about
    // p rather than the axis: not in the file's group.
    assert!(s.faces().iter().any(|f| !in_group(f.pairing)));
    // The file's origin in the chart: on a face, outside none.
    let o = s.from_file_frame(DMat4::IDENTITY).w_axis;
    assert!(s.outside_face(o, 1e-9).is_none());
    let nearest = s
        .faces()
        .iter()
        .map(|f| f.plane.dot(o).abs())
        .fold(f64::INFINITY, f64::min);
    assert!(nearest < 1e-9, "the axis is on the boundary: {nearest}");
    assert!(
        s.to_file_frame(s.from_file_frame(DMat4::IDENTITY))
            .abs_diff_eq(DMat4::IDENTITY, 1e-12)
    );
    // Through the space file and back.
    let path = Path::new("p3.json");
    let again = SpaceDesc::parse(&s.to_json(), path).unwrap();
    assert!(again.file_frame().abs_diff_eq(s.file_frame(), 1e-12));
    // A built-in space has none.
    assert!(!catalog::poincare().to_json().contains("file_frame"));
    let mut desc = s.to_desc();
    desc.file_frame = Some([
        [2.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ]);
    let text = serde_json::to_string(&desc).unwrap();
    let err = SpaceDesc::parse(&text, path).unwrap_err().to_string();
    assert!(
        err.contains("p3.json") && err.contains("file frame") && err.contains("not an isometry"),
        "{err}"
    );
    let err = s.clone().with_file_frame(DMat4::NAN).unwrap_err();
    assert!(matches!(err, SpaceError::FileFrame { .. }), "{err}");
}

/// L(5, 2) about the origin, a point of the orbit circle of the zw-plane:
/// every image of the origin lies on that circle, so the domain there is a
/// lens (two faces at 72 degrees, the rim the xy circle), built where the
/// file asks, its pairings powers of the file's own generator (not
/// conjugates of them about some other point). About a point of the
/// Clifford torus the same group gives a polyhedron.
fn a_lens_about_a_point_of_an_orbit_circle_keeps_the_files_group() {
    let (a, b) = (TAU / 5.0, 2.0 * TAU / 5.0);
    let g = DMat4::from_cols(
        DVec4::new(a.cos(), a.sin(), 0.0, 0.0),
        DVec4::new(-a.sin(), a.cos(), 0.0, 0.0),
        DVec4::new(0.0, 0.0, b.cos(), b.sin()),
        DVec4::new(0.0, 0.0, -b.sin(), b.cos()),
    );
    let mut gens = Generators::new("l52", vec![g]).unwrap();
    gens.manifold = true;
    let s = gens.dirichlet_domain().unwrap();
    expect(&s, spherical_volume(5), 2, Some(5), "Z/5");
    assert!((s.lens().expect("a lens").dihedral - TAU / 5.0).abs() < 1e-9);
    let powers: Vec<DMat4> = (1..5)
        .scan(DMat4::IDENTITY, |m, _| {
            *m = g * *m;
            Some(*m)
        })
        .collect();
    for f in s.faces() {
        let k = powers.iter().position(|p| p.abs_diff_eq(f.pairing, 1e-12));
        assert!(k.is_some(), "a pairing outside the file's group: {:?}", f.pairing);
    }
    // The faces' pairings are g^2 and g^3 = g^-2: the images of the
    // origin nearest it are a fifth of a turn away on the circle.
    assert!((s.inradius() - PI / 5.0).abs() < 1e-9);
    let generic = library::lens(5, 2).dirichlet_domain().unwrap();
    assert!(generic.lens().is_none() && generic.faces().len() >= 4);
}

fn generator_files_name_the_file_in_errors() {
    let dir = std::env::temp_dir().join(format!("bevy_manifold_gens_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("broken.gen");
    std::fs::write(&path, "1 0 0 0\n0 1 0 0\n0 0 1 0\n").unwrap();
    let err = Space::load(&path).unwrap_err();
    assert!(matches!(
        err.kind,
        SpaceFileErrorKind::Generators(GeneratorError::Incomplete { .. })
    ));
    assert!(err.to_string().contains("broken.gen"), "{err}");
    // A JSON generator list is told from a space file by its "generators".
    let path = dir.join("list.json");
    let rot = |a: f64| {
        let (c, s) = (a.cos(), a.sin());
        [
            [c, -s, 0.0, 0.0],
            [s, c, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ]
    };
    let text = serde_json::json!({"name": "rotation only", "generators": [rot(TAU / 5.0)]}).to_string();
    std::fs::write(&path, text).unwrap();
    let err = Space::load(&path).unwrap_err();
    assert!(
        err.to_string().contains("list.json") && err.to_string().contains("fixes the origin"),
        "{err}"
    );
}

/// Curved Spaces' own files as a Windows editor saves them: a UTF-8
/// byte-order mark first and CRLF line ends. Each reads as the file
/// itself does: the same matrices, the same basepoint, the same space
/// (or, for L(5,1), the same refusal).
fn a_byte_order_mark_and_crlf_line_ends_read_as_the_plain_file() {
    let dir = curved_spaces().expect("the shared Curved Spaces files");
    for file in [
        "3-torus.gen",
        "half-turn.gen",
        "poincare.gen",
        "seifert-weber.gen",
        "lens-5-1.gen",
    ] {
        let plain = std::fs::read_to_string(dir.join(file)).expect("readable");
        let windows = format!("\u{feff}{}", plain.replace('\n', "\r\n"));
        let (a, b) = (
            Generators::parse_gen(&plain, file).expect(file),
            Generators::parse_gen(&windows, file).unwrap_or_else(|e| panic!("{file} with a BOM: {e}")),
        );
        assert_eq!(a.matrices, b.matrices, "{file}");
        assert_eq!(a.basepoint, b.basepoint, "{file}");
        let path = std::env::temp_dir().join(format!("bom-{}-{file}", std::process::id()));
        std::fs::write(&path, &windows).expect("written");
        match (Space::load(dir.join(file)), Space::load(&path)) {
            (Ok(a), Ok(b)) => {
                assert_eq!(a.faces().len(), b.faces().len(), "{file}");
                assert!((a.volume() - b.volume()).abs() < 1e-12, "{file}");
            }
            (Err(a), Err(b)) => assert_eq!(a.kind.to_string(), b.kind.to_string(), "{file}"),
            (a, b) => panic!("{file}: plain {:?}, with a BOM {:?}", a.err(), b.err()),
        }
        let _ = std::fs::remove_file(&path);
    }
    // A JSON generator list with a BOM.
    let json = "\u{feff}{\"name\": \"cube\", \"geometry\": \"euclidean\", \"generators\": [\r\n[[1,0,0,1],[0,1,0,0],[0,0,1,0],[0,0,0,1]],\r\n[[1,0,0,0],[0,1,0,1],[0,0,1,0],[0,0,0,1]],\r\n[[1,0,0,0],[0,1,0,0],[0,0,1,1],[0,0,0,1]]]}";
    let gens = Generators::parse_json(json).unwrap_or_else(|e| panic!("a JSON list with a BOM: {e}"));
    assert_eq!(gens.matrices.len(), 3);
}

bevy_manifold_test_support::test_main_requiring! {
    cpu: [
        the_spherical_library_has_the_right_volumes_orders_and_homology,
        lens_spaces_that_are_the_same_manifold_give_the_same_domain,
        the_poincare_space_from_two_generators_is_the_catalog_one,
        redundant_generators_give_the_same_domain,
        a_five_fold_cover_has_five_times_the_volume,
        the_weeks_manifold_builds_about_far_basepoints,
        seifert_weber_builds_about_points_near_its_centre,
        the_flat_library_has_the_right_volumes_and_homology,
        the_weeks_manifold_has_the_published_volume_and_homology,
        the_shipped_library_files_are_the_library,
        generator_lists_round_trip_through_json_and_gen,
        transposed_files_are_caught_or_harmless,
        broken_generator_lists_give_their_own_errors,
        orbifolds_move_the_basepoint_and_manifold_files_refuse_them,
        a_basepoint_centres_the_domain_there,
        a_moved_domain_keeps_the_files_group_through_its_frame,
        a_lens_about_a_point_of_an_orbit_circle_keeps_the_files_group,
        generator_files_name_the_file_in_errors,
    ],
    requiring(
        "the shared Curved Spaces files",
        curved_spaces().map(|d| d.display().to_string())
    ): [
        every_curved_spaces_file_loads_and_matches,
        a_byte_order_mark_and_crlf_line_ends_read_as_the_plain_file,
    ],
}
