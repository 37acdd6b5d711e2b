//! Files as Windows editors save them: a UTF-8 byte-order mark first and
//! CRLF line ends. Space, scene and tour files read exactly as without
//! them (generator files: `generators.rs`, with Curved Spaces' own).

use bevy_manifold_core::prelude::*;
use bevy_manifold_core::space::catalog;
use bevy_manifold_core::tour::TourDesc;
use std::path::Path;

/// `text` with a BOM and CRLF line ends.
fn windows(text: &str) -> String {
    format!("\u{feff}{}", text.replace('\n', "\r\n"))
}

#[test]
fn space_scene_and_tour_files_with_a_bom_and_crlf_read_as_without() {
    let space = catalog::seifert_weber();
    let json = space.to_json();
    assert!(json.contains('\n'), "pretty JSON, so CRLF is tried");
    let a = Space::parse_file(&json, Path::new("sw.json")).expect("plain");
    let b = Space::parse_file(&windows(&json), Path::new("sw.json")).expect("with a BOM");
    assert_eq!(a.faces().len(), b.faces().len());
    assert!((a.volume() - b.volume()).abs() < 1e-12);

    let scene = Scene::default_for(&space).to_json();
    let a = Scene::parse(&scene, "scene.json", &space).expect("plain");
    let b = Scene::parse(&windows(&scene), "scene.json", &space).expect("with a BOM");
    assert_eq!(a, b);

    let tours = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/tours/poincare.tour.json");
    let tour = std::fs::read_to_string(&tours).expect("the shipped tour");
    let a = TourDesc::parse(&tour, "poincare.tour.json").expect("plain");
    let b = TourDesc::parse(&windows(&tour), "poincare.tour.json").expect("with a BOM");
    assert_eq!(a.to_json(), b.to_json());

    // A BOM anywhere but first is not whitespace: still refused, by name.
    let e = Scene::parse("{\u{feff}}", "inner.json", &space).unwrap_err();
    assert!(e.to_string().contains("inner.json"), "{e}");
}
