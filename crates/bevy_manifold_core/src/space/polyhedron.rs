//! The fundamental polyhedron as the intersection of its faces' half-spaces:
//! vertices, edges, face polygons and dihedral angles, all derived from the
//! planes alone (so a space file needs no combinatorics of its own).

use super::SpaceError;
use crate::geometry::{Geometry, plane};
use glam::DVec4;

/// A vertex of the fundamental polyhedron.
#[derive(Clone, Debug, PartialEq)]
pub struct Vertex {
    /// The normalised point.
    pub point: DVec4,
    /// The faces through it, ascending.
    pub faces: Vec<usize>,
}

/// An edge of the fundamental polyhedron: where two faces meet.
#[derive(Clone, Debug, PartialEq)]
pub struct Edge {
    /// Its two end vertices (indices into the vertex list).
    pub vertices: [usize; 2],
    /// The two faces it lies on, ascending.
    pub faces: [usize; 2],
    /// The interior dihedral angle between the two faces, in radians.
    pub dihedral: f64,
}

/// Vertices, edges and face polygons of a convex polyhedron given by planes.
#[derive(Clone, Debug, PartialEq)]
pub struct Polyhedron {
    /// The vertices.
    pub vertices: Vec<Vertex>,
    /// The edges.
    pub edges: Vec<Edge>,
    /// For each face, its vertices in cyclic order.
    pub face_vertices: Vec<Vec<usize>>,
}

/// Tolerance for "this point lies on this plane", in chart units.
pub(crate) const INCIDENCE_EPS: f64 = 1e-9;

/// The chart coordinates of a point (`p / w`): where incidence is tested, so
/// the tolerance means the same in all geometries.
pub(crate) fn chart(p: DVec4) -> DVec4 {
    p / p.w
}

impl Polyhedron {
    /// Builds the polyhedron bounded by the normalised planes `planes`.
    ///
    /// # Errors
    /// [`SpaceError::NotCompact`] when the faces do not close up into a
    /// compact polyhedron, [`SpaceError::RedundantFace`] when a face does not
    /// touch it in a polygon, [`SpaceError::DegenerateVertex`] when more than
    /// two faces meet along an edge.
    pub fn from_planes(g: Geometry, planes: &[DVec4]) -> Result<Self, SpaceError> {
        let nf = planes.len();
        let mut vertices: Vec<Vertex> = Vec::new();
        for i in 0..nf {
            for j in i + 1..nf {
                for k in j + 1..nf {
                    let p = plane::cross4(planes[i], planes[j], planes[k]);
                    if p.length_squared() < 1e-24 || p.w.abs() < 1e-12 * p.length() {
                        continue; // parallel planes, or a point at infinity of the chart
                    }
                    let p = if p.w < 0.0 { -p } else { p };
                    let c = chart(p);
                    if planes.iter().any(|n| n.dot(c) > INCIDENCE_EPS) {
                        continue; // cut off by another face
                    }
                    if g == Geometry::Hyperbolic && g.form::<f64>(c, c) >= -1e-12 {
                        return Err(SpaceError::NotCompact {
                            detail: format!("faces {i}, {j}, {k} meet on or beyond the sphere at infinity"),
                        });
                    }
                    let point = g.normalize_point::<f64>(p);
                    let on: Vec<usize> = (0..nf).filter(|&f| planes[f].dot(c).abs() <= INCIDENCE_EPS).collect();
                    match vertices.iter_mut().find(|v| (chart(v.point) - c).length() < 1e-7) {
                        Some(v) => {
                            for f in on {
                                if !v.faces.contains(&f) {
                                    v.faces.push(f);
                                }
                            }
                            v.faces.sort_unstable();
                        }
                        None => vertices.push(Vertex { point, faces: on }),
                    }
                }
            }
        }
        if vertices.len() < 4 {
            return Err(SpaceError::NotCompact {
                detail: format!("the faces meet in only {} vertices", vertices.len()),
            });
        }
        let mut edges = Vec::new();
        for a in 0..vertices.len() {
            for b in a + 1..vertices.len() {
                let shared: Vec<usize> = vertices[a]
                    .faces
                    .iter()
                    .copied()
                    .filter(|f| vertices[b].faces.contains(f))
                    .collect();
                match shared.len() {
                    0 | 1 => {}
                    2 => {
                        let faces = [shared[0], shared[1]];
                        let dihedral = dihedral_angle(g, planes[faces[0]], planes[faces[1]]);
                        edges.push(Edge {
                            vertices: [a, b],
                            faces,
                            dihedral,
                        });
                    }
                    _ => {
                        return Err(SpaceError::DegenerateVertex {
                            faces: shared,
                            detail: "more than two faces contain the same edge".into(),
                        });
                    }
                }
            }
        }
        let mut face_vertices = Vec::with_capacity(nf);
        for f in 0..nf {
            face_vertices.push(face_cycle(f, &vertices, &edges)?);
        }
        Ok(Polyhedron {
            vertices,
            edges,
            face_vertices,
        })
    }

    /// The polyhedron of a domain without vertices (a lens or hemisphere,
    /// [`super::lens`]): `faces` faces, no vertices, no edges.
    #[must_use]
    pub fn without_vertices(faces: usize) -> Self {
        Polyhedron {
            vertices: Vec::new(),
            edges: Vec::new(),
            face_vertices: vec![Vec::new(); faces],
        }
    }

    /// The edge joining two vertices, if any.
    #[must_use]
    pub fn edge_between(&self, a: usize, b: usize) -> Option<usize> {
        self.edges
            .iter()
            .position(|e| e.vertices == [a, b] || e.vertices == [b, a])
    }

    /// The vertex at (chart distance below 1e-7 from) the point `p`.
    #[must_use]
    pub fn vertex_at(&self, p: DVec4) -> Option<usize> {
        let c = chart(p);
        self.vertices.iter().position(|v| (chart(v.point) - c).length() < 1e-7)
    }
}

/// The interior dihedral angle between two faces that meet: `pi` minus the
/// angle between their outward normals, by `atan2` (no `acos` near 1).
#[must_use]
pub fn dihedral_angle(g: Geometry, a: DVec4, b: DVec4) -> f64 {
    let (na, nb) = (plane::pole(g, a), plane::pole(g, b));
    let (aa, bb, ab) = (a.dot(na), b.dot(nb), a.dot(nb));
    let c = ab / (aa * bb).sqrt();
    core::f64::consts::PI - (1.0 - c * c).max(0.0).sqrt().atan2(c)
}

/// Orders the vertices of face `f` around its polygon by walking its edges.
fn face_cycle(f: usize, vertices: &[Vertex], edges: &[Edge]) -> Result<Vec<usize>, SpaceError> {
    let on_face: Vec<&Edge> = edges.iter().filter(|e| e.faces.contains(&f)).collect();
    let count = vertices.iter().filter(|v| v.faces.contains(&f)).count();
    if count < 3 {
        return Err(SpaceError::RedundantFace {
            face: f,
            vertices: count,
        });
    }
    let start = on_face
        .first()
        .ok_or(SpaceError::RedundantFace {
            face: f,
            vertices: count,
        })?
        .vertices[0];
    let mut cycle = vec![start];
    let mut prev = usize::MAX;
    let mut cur = start;
    loop {
        let next = on_face.iter().find_map(|e| {
            let [a, b] = e.vertices;
            let other = if a == cur {
                b
            } else if b == cur {
                a
            } else {
                return None;
            };
            (other != prev).then_some(other)
        });
        match next {
            Some(n) if n == start => break,
            Some(n) if cycle.len() <= count => {
                cycle.push(n);
                prev = cur;
                cur = n;
            }
            _ => {
                return Err(SpaceError::NotCompact {
                    detail: format!("face {f} is not a closed polygon"),
                });
            }
        }
    }
    if cycle.len() != count {
        return Err(SpaceError::NotCompact {
            detail: format!(
                "face {f} has {count} vertices but its edges close after {}",
                cycle.len()
            ),
        });
    }
    Ok(cycle)
}
