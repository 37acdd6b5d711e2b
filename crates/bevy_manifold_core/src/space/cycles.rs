//! Edge cycles (the classes of edges the pairings identify) and the first
//! homology they give.
//!
//! A cycle is walked as a ray would turn around an edge: standing on edge
//! `e` about to leave through face `a`, the pairing `T_a` carries `e` to an
//! edge `e'` of the partner face; the walk goes on through the other face
//! of `e'`, until it is back on `e` leaving through `a`. Around a mirror the
//! walk bounces, visiting the edge twice. The dihedral angles met on the
//! walk add up to the cycle's angle sum, which must be `2 pi / k`: `k = 1`
//! for a manifold edge, `k > 1` for an orbifold's cone or corner edge.

use super::{FaceKind, Space, SpaceError, max_abs_diff};
use glam::DMat4;

/// One class of identified edges.
#[derive(Clone, Debug, PartialEq)]
pub struct EdgeCycle {
    /// Edges in walk order (a mirror edge appears once per visit).
    pub edges: Vec<usize>,
    /// The face left through at each step.
    pub faces: Vec<usize>,
    /// Sum of the dihedral angles along the walk, in radians.
    pub angle_sum: f64,
    /// `k` with `angle_sum * k = 2 pi` (1 for a manifold edge).
    pub order: u32,
    /// The cycle transformation `T_{a_m} ... T_{a_1}`: a rotation about the
    /// first edge by the angle sum.
    pub holonomy: DMat4,
}

impl EdgeCycle {
    /// How many distinct edges the cycle identifies.
    #[must_use]
    pub fn distinct_edges(&self) -> usize {
        let mut e = self.edges.clone();
        e.sort_unstable();
        e.dedup();
        e.len()
    }
}

/// Walks every edge cycle of the space.
pub(super) fn edge_cycles(space: &Space) -> Result<Vec<EdgeCycle>, SpaceError> {
    let poly = &space.poly;
    let mut seen = vec![false; poly.edges.len()];
    let mut cycles = Vec::new();
    for start in 0..poly.edges.len() {
        if seen[start] {
            continue;
        }
        let start_face = poly.edges[start].faces[0];
        let (mut e, mut a) = (start, start_face);
        let mut cycle = EdgeCycle {
            edges: Vec::new(),
            faces: Vec::new(),
            angle_sum: 0.0,
            order: 0,
            holonomy: DMat4::IDENTITY,
        };
        loop {
            seen[e] = true;
            cycle.edges.push(e);
            cycle.faces.push(a);
            cycle.angle_sum += poly.edges[e].dihedral;
            let t = space.faces[a].pairing;
            cycle.holonomy = t * cycle.holonomy;
            let [v0, v1] = poly.edges[e].vertices;
            let image = |v: usize| poly.vertex_at(t * poly.vertices[v].point);
            let next = match (image(v0), image(v1)) {
                (Some(w0), Some(w1)) => poly.edge_between(w0, w1),
                _ => None,
            };
            let partner = space.faces[a].partner;
            let Some(next) = next.filter(|&n| poly.edges[n].faces.contains(&partner)) else {
                return Err(SpaceError::EdgeCycle {
                    edges: cycle.edges,
                    faces: cycle.faces,
                    detail: format!("the pairing of face {a} does not carry edge {e} onto an edge of face {partner}"),
                });
            };
            let [f0, f1] = poly.edges[next].faces;
            let other = if f0 == partner { f1 } else { f0 };
            (e, a) = (next, other);
            if (e, a) == (start, start_face) {
                break;
            }
            if cycle.edges.len() > 2 * poly.edges.len() {
                return Err(SpaceError::EdgeCycle {
                    edges: cycle.edges,
                    faces: cycle.faces,
                    detail: "the walk around the edge never closes".into(),
                });
            }
        }
        let k = core::f64::consts::TAU / cycle.angle_sum;
        let whole = (1.0..=f64::from(super::MAX_CYCLE_ORDER)).contains(&k.round());
        cycle.order = if (k - k.round()).abs() < 1e-6 && whole {
            k.round() as u32
        } else {
            0
        };
        cycles.push(cycle);
    }
    Ok(cycles)
}

/// Every cycle must close after a whole number of turns: angle sum `2 pi/k`
/// and holonomy of order `k`.
pub(super) fn check_cycles(cycles: &[EdgeCycle]) -> Result<(), SpaceError> {
    for c in cycles {
        let fail = |detail: String| SpaceError::EdgeCycle {
            edges: c.edges.clone(),
            faces: c.faces.clone(),
            detail,
        };
        if c.order == 0 {
            return Err(fail(format!(
                "the dihedral angles add up to {:.6} deg, which is not 360/k deg for a whole k up to {}",
                c.angle_sum.to_degrees(),
                super::MAX_CYCLE_ORDER
            )));
        }
        let mut power = DMat4::IDENTITY;
        for _ in 0..c.order {
            power = c.holonomy * power;
        }
        let err = max_abs_diff(power, DMat4::IDENTITY);
        if err > 1e-7 {
            return Err(fail(format!(
                "the cycle transformation to the power {} is not the identity (error {err:.3e}): the gluing twists the edge",
                c.order
            )));
        }
    }
    Ok(())
}

/// A finitely generated abelian group `Z^rank + Z/t1 + Z/t2 + ...`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Homology {
    /// Free rank.
    pub rank: usize,
    /// Torsion coefficients greater than 1, each dividing the next.
    pub torsion: Vec<u64>,
}

impl core::fmt::Display for Homology {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let mut parts: Vec<String> = Vec::new();
        match self.rank {
            0 => {}
            1 => parts.push("Z".into()),
            r => parts.push(format!("Z^{r}")),
        }
        parts.extend(self.torsion.iter().map(|t| format!("Z/{t}")));
        if parts.is_empty() {
            f.write_str("0")
        } else {
            f.write_str(&parts.join(" + "))
        }
    }
}

/// The abelianised group of a space's pairings
/// ([`super::Space::abelian_relations`]): one generator per face pair (or
/// mirror), one relation per edge cycle (its word to the power `k`, as
/// exponent sums), `2 g = 0` per mirror.
///
/// ```
/// use bevy_manifold_core::space::catalog;
/// let torus = catalog::torus(1.0);
/// let r = torus.abelian_relations();
/// // Three face pairs; every edge cycle of the cube crosses two pairs
/// // each way, so every relation is 0 (H1 = Z^3).
/// assert_eq!(r.generators, 3);
/// assert!(r.rows.iter().flatten().all(|&x| x == 0));
/// // A face and its partner are one generator, with opposite signs.
/// for (f, face) in torus.faces().iter().enumerate() {
///     assert_eq!(r.letters[f].0, r.letters[face.partner].0);
///     assert_eq!(r.letters[f].1, -r.letters[face.partner].1);
/// }
/// ```
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AbelianRelations {
    /// How many generators (columns): one per face pair or mirror.
    pub generators: usize,
    /// Per face, its pairing as a generator: the column (that of the
    /// pair's first face) and the sign (1 for the pair's first face, and
    /// for a mirror; -1 for its partner).
    pub letters: Vec<(usize, i128)>,
    /// One row of `generators` exponent sums per relation: the edge
    /// cycles' (in [`super::Space::edge_cycles`]' order), then the
    /// mirrors'.
    pub rows: Vec<Vec<i128>>,
}

/// [`AbelianRelations`] of `space`.
pub(super) fn abelian_relations(space: &Space) -> AbelianRelations {
    let faces = &space.faces;
    let gens: Vec<usize> = (0..faces.len()).filter(|&i| faces[i].partner >= i).collect();
    let letters: Vec<(usize, i128)> = (0..faces.len())
        .map(|f| {
            let p = faces[f].partner;
            let col = gens.iter().position(|&g| g == f.min(p)).unwrap_or(0);
            (col, if f <= p { 1 } else { -1 })
        })
        .collect();
    let mut rows: Vec<Vec<i128>> = Vec::new();
    for c in &space.cycles {
        let mut row = vec![0i128; gens.len()];
        for &f in &c.faces {
            let (col, s) = letters[f];
            row[col] += s * i128::from(c.order.max(1));
        }
        rows.push(row);
    }
    for (i, f) in faces.iter().enumerate() {
        // A mirror, and the hemisphere's face glued to itself: T^2 = 1.
        if f.kind == FaceKind::Mirror || (f.partner == i && space.lens.is_some()) {
            let mut row = vec![0i128; gens.len()];
            row[letters[i].0] = 2;
            rows.push(row);
        }
    }
    // A lens's rim, the edge it has in place of cycles: its pairing turns
    // the rim by the rim's angle, so T^k = 1 once k angles make a turn.
    if let Some(shape) = space.lens
        && faces.len() == 2
        && faces.iter().all(|f| f.kind == FaceKind::Glue)
    {
        let mut row = vec![0i128; gens.len()];
        row[letters[0].0] = (std::f64::consts::TAU / shape.dihedral).round() as i128;
        rows.push(row);
    }
    AbelianRelations {
        generators: gens.len(),
        letters,
        rows,
    }
}

/// The first homology of `space`: the Smith normal form of its
/// [`AbelianRelations`]. `None` when the elimination's entries would
/// leave `i128` (see [`smith_diagonal`]).
pub(super) fn first_homology(space: &Space) -> Option<Homology> {
    let AbelianRelations { generators, rows, .. } = abelian_relations(space);
    let diag = smith_diagonal(rows, generators)?;
    let rank = generators - diag.iter().filter(|&&d| d != 0).count();
    let torsion = diag
        .into_iter()
        .filter(|&d| d > 1)
        .map(|d| u64::try_from(d).ok())
        .collect::<Option<_>>()?;
    Some(Homology { rank, torsion })
}

/// The nonzero diagonal of the Smith normal form of an integer matrix.
///
/// Every pass either zeroes entries or moves a strictly smaller nonzero
/// entry to the pivot, so the loops end; the entries themselves can grow
/// during elimination (integer Gaussian elimination has no general bound
/// short of the determinantal divisors), so every operation is checked and
/// `None` says the `i128` range was left instead of a wrapped, wrong
/// answer. The relation matrices of spaces within
/// [`crate::space::MAX_FACES`] start with entries at most the largest edge
/// order times the faces, far inside it.
fn smith_diagonal(mut a: Vec<Vec<i128>>, cols: usize) -> Option<Vec<i128>> {
    let rows = a.len();
    let mut diag = Vec::new();
    let mut t = 0;
    while t < rows.min(cols) {
        // Pivot: the smallest nonzero entry in the remaining block.
        let mut pivot = None;
        for i in t..rows {
            for j in t..cols {
                if a[i][j] != 0
                    && pivot.is_none_or(|(pi, pj): (usize, usize)| a[i][j].unsigned_abs() < a[pi][pj].unsigned_abs())
                {
                    pivot = Some((i, j));
                }
            }
        }
        let Some((pi, pj)) = pivot else { break };
        a.swap(t, pi);
        for row in a.iter_mut() {
            row.swap(t, pj);
        }
        loop {
            let p = a[t][t];
            let mut done = true;
            for i in t + 1..rows {
                let q = a[i][t].checked_div(p)?;
                if q != 0 {
                    add_row(&mut a, i, t, q.checked_neg()?)?;
                }
                if a[i][t] != 0 {
                    done = false;
                }
            }
            for j in t + 1..cols {
                let q = a[t][j].checked_div(p)?;
                if q != 0 {
                    for row in a.iter_mut() {
                        row[j] = row[j].checked_sub(q.checked_mul(row[t])?)?;
                    }
                }
                if a[t][j] != 0 {
                    done = false;
                }
            }
            if done {
                // Divisibility: every remaining entry must be a multiple of p.
                let bad = (t + 1..rows).find(|&i| (t + 1..cols).any(|j| a[i][j] % p != 0));
                match bad {
                    Some(i) => {
                        add_row(&mut a, t, i, 1)?;
                        continue;
                    }
                    None => break,
                }
            }
            // Move the smallest nonzero entry of row/column t to the pivot.
            let mut best = (t, t);
            for i in t..rows {
                if a[i][t] != 0 && a[i][t].unsigned_abs() < a[best.0][best.1].unsigned_abs() {
                    best = (i, t);
                }
            }
            for j in t..cols {
                if a[t][j] != 0 && a[t][j].unsigned_abs() < a[best.0][best.1].unsigned_abs() {
                    best = (t, j);
                }
            }
            a.swap(t, best.0);
            for row in a.iter_mut() {
                row.swap(t, best.1);
            }
        }
        diag.push(a[t][t].checked_abs()?);
        t += 1;
    }
    Some(diag)
}

/// Row operation `a[dst] += factor * a[src]` (columns left of the pivot
/// are zero in both rows, so the whole row can be added); `None` on
/// overflow.
fn add_row(a: &mut [Vec<i128>], dst: usize, src: usize, factor: i128) -> Option<()> {
    let src_row = a[src].clone();
    for (d, s) in a[dst].iter_mut().zip(&src_row) {
        *d = d.checked_add(factor.checked_mul(*s)?)?;
    }
    Some(())
}

#[cfg(test)]
mod tests {
    use super::smith_diagonal;

    #[test]
    fn smith_of_known_matrices() {
        assert_eq!(smith_diagonal(vec![vec![2, 4], vec![6, 8]], 2), Some(vec![2, 4]));
        assert_eq!(smith_diagonal(vec![vec![5, 0, 0], vec![0, 5, 0]], 3), Some(vec![5, 5]));
        assert_eq!(smith_diagonal(vec![vec![2, 0], vec![0, 3]], 2), Some(vec![1, 6]));
        assert_eq!(smith_diagonal(vec![vec![0, 0]], 2), Some(Vec::new()));
    }

    /// Entries whose elimination leaves i128: reported, not wrapped (a
    /// release build would wrap silently to a wrong group) and not a panic.
    #[test]
    fn smith_reports_overflow() {
        let big = i128::MAX / 3;
        // Row 2 - q * row 1 with q = big / 2 overflows at once in column 2.
        assert_eq!(smith_diagonal(vec![vec![2, -big], vec![big, big]], 2), None);
        // i128::MIN has no absolute value.
        assert_eq!(smith_diagonal(vec![vec![i128::MIN]], 1), None);
        // Large but in range: exact (gcd 1, determinant big * 3 - big * 2).
        assert_eq!(smith_diagonal(vec![vec![3, big], vec![2, big]], 2), Some(vec![1, big]));
    }
}
