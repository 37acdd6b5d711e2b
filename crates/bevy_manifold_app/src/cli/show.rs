//! `space show`: a human-readable description of a space.

use bevy_manifold::prelude::*;
use std::fmt::Write;

/// Everything worth knowing about a space, as text.
pub fn describe(s: &Space) -> String {
    let mut o = String::new();
    let kind = if s.is_manifold() { "manifold" } else { "orbifold" };
    let _ = writeln!(o, "name:          {}", s.name());
    let _ = writeln!(o, "geometry:      {}", s.geometry());
    let _ = writeln!(o, "type:          {kind}");
    let _ = writeln!(o, "faces:         {}", s.faces().len());
    let _ = writeln!(o, "vertices:      {}", s.vertices().len());
    let _ = writeln!(o, "edges:         {}", s.edges().len());
    match s.lens() {
        Some(_) if s.faces().len() == 1 => {
            let _ = writeln!(
                o,
                "shape:         a hemisphere (its face a quarter turn from the centre)"
            );
        }
        Some(l) => {
            let _ = writeln!(
                o,
                "shape:         a lens (its rim a quarter turn from the centre, at {:.6} deg)",
                l.dihedral.to_degrees()
            );
        }
        None => {}
    }
    if s.file_frame() != glam::DMat4::IDENTITY {
        let o_file = s.file_frame().w_axis;
        let _ = writeln!(
            o,
            "file frame:    the chart origin is ({:.6}, {:.6}, {:.6}, {:.6}) of the generators' coordinates",
            o_file.x, o_file.y, o_file.z, o_file.w
        );
    }
    let mut dihedrals: Vec<f64> = s.edges().iter().map(|e| e.dihedral.to_degrees()).collect();
    dihedrals.sort_by(f64::total_cmp);
    dihedrals.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    let list: Vec<String> = dihedrals.iter().map(|d| format!("{d:.6}")).collect();
    let _ = writeln!(o, "dihedral angles (deg): {}", list.join(", "));
    let _ = writeln!(o, "inradius:      {:.9}", s.inradius());
    let _ = writeln!(o, "circumradius:  {:.9}", s.circumradius());
    let _ = writeln!(o, "volume:        {:.9}", s.volume());
    match s.group_order() {
        Some(n) => {
            let _ = writeln!(o, "group order:   {n}");
        }
        None => {
            let _ = writeln!(o, "group order:   infinite");
        }
    }
    let homology = s
        .first_homology()
        .map_or("too large to compute".into(), |h| h.to_string());
    let _ = writeln!(o, "first homology: {homology}");
    let _ = writeln!(o, "cell ids:      {}", s.cells().kind());
    let _ = writeln!(o, "edge cycles:   {}", s.edge_cycles().len());
    for (i, c) in s.edge_cycles().iter().enumerate() {
        let _ = writeln!(
            o,
            "  cycle {i}: edges {:?}, angle sum {:.6} deg = 360/{} deg",
            c.edges,
            c.angle_sum.to_degrees(),
            c.order
        );
    }
    let _ = writeln!(o, "faces:");
    for (i, f) in s.faces().iter().enumerate() {
        let n = f.plane;
        let _ = writeln!(
            o,
            "  face {i:2}: {:<6} partner {:2}, plane [{:+.6}, {:+.6}, {:+.6}, {:+.6}], {} vertices",
            f.kind.name(),
            f.partner,
            n.x,
            n.y,
            n.z,
            n.w,
            s.polyhedron().face_vertices[i].len()
        );
    }
    let _ = writeln!(o, "vertices:");
    for (i, v) in s.vertices().iter().enumerate() {
        let p = v.point;
        let _ = writeln!(
            o,
            "  vertex {i:2}: [{:+.6}, {:+.6}, {:+.6}, {:+.6}] on faces {:?}",
            p.x, p.y, p.z, p.w, v.faces
        );
    }
    o
}
