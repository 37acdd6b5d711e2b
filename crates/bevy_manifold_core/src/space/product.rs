//! Compact spaces of the product geometries (H2xR, S2xR): a fundamental
//! prism, a polygon of the surface (or the whole sphere) times an interval
//! of heights, with its faces glued in pairs.
//!
//! - The vertical faces stand over the polygon's sides (geodesics of the
//!   surface); each side is glued to its partner by an isometry of the
//!   surface (a translation for a surface, a reflection for a mirror).
//! - The two horizontal faces, at heights `-L/2` and `L/2`, are glued to
//!   each other by a vertical translation by `L`, turned by an isometry
//!   of the surface that maps the polygon onto itself (the twist of a
//!   mapping torus), or are mirrors.
//!
//! The catalog: [`ProductSpace::s2_x_s1`], [`ProductSpace::genus_two_x_s1`],
//! their twisted forms, and [`ProductSpace::mirrored_prism`].
//!
//! ```
//! use bevy_manifold_core::space::product::ProductSpace;
//! let space = ProductSpace::genus_two_x_s1(1.0);
//! space.validate().unwrap();
//! // Gauss-Bonnet: the genus-2 surface has area 4 pi.
//! assert!((space.volume() - 4.0 * std::f64::consts::PI).abs() < 1e-9);
//! ```

use crate::geometry::product::{ProductGeometry, ProductIsometry, ProductPoint};
use glam::{DMat3, DVec3};
use std::f64::consts::PI;

/// How a face is glued.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ProductGluing {
    /// To face `partner` by `pairing`, which maps this face onto it (a ray
    /// leaving through this face goes on from the pairing's image of its
    /// exit point, inside the prism).
    Paired {
        /// The face it is glued to.
        partner: usize,
        /// Maps this face onto the partner.
        pairing: ProductIsometry,
    },
    /// A mirror: the reflection in the face, which keeps it.
    Mirror(ProductIsometry),
}

impl ProductGluing {
    /// The isometry that takes a ray leaving through the face back inside.
    #[must_use]
    pub fn isometry(&self) -> ProductIsometry {
        match self {
            ProductGluing::Paired { pairing, .. } => *pairing,
            ProductGluing::Mirror(m) => *m,
        }
    }
}

/// A compact space of H2xR or S2xR as a glued prism.
#[derive(Clone, Debug, PartialEq)]
pub struct ProductSpace {
    /// Its name.
    pub name: String,
    /// H2xR or S2xR.
    pub geometry: ProductGeometry,
    /// The polygon's sides as unit normal covectors `n` of the surface
    /// (`<n, n> = 1`), `<n, p> <= 0` inside; in order round the polygon.
    /// None for the whole sphere.
    pub sides: Vec<DVec3>,
    /// The height of the prism, `L`: heights from `-L/2` to `L/2`.
    pub height: f64,
    /// How each face is glued: the sides in order, then the bottom
    /// (height `-L/2`), then the top.
    pub gluings: Vec<ProductGluing>,
    /// The polygon's interior angles (at the vertex between side `i` and
    /// side `i + 1`), for its area; empty for the whole sphere.
    pub angles: Vec<f64>,
}

/// What is wrong with a product space.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ProductSpaceError {
    /// A number that is not finite, or a height that is not positive.
    #[error("{space}: {field} is {value} (a finite positive number was expected)")]
    BadNumber {
        /// The space.
        space: String,
        /// The field.
        field: &'static str,
        /// Its value.
        value: f64,
    },
    /// Not one gluing per face.
    #[error("{space}: {gluings} gluings for {faces} faces")]
    GluingCount {
        /// The space.
        space: String,
        /// Gluings given.
        gluings: usize,
        /// Faces.
        faces: usize,
    },
    /// A gluing that is not an isometry, or that does not map its face onto
    /// its partner (or, for a mirror, onto itself).
    #[error("{space}: face {face}: {what}")]
    Gluing {
        /// The space.
        space: String,
        /// The face.
        face: usize,
        /// What is wrong.
        what: String,
    },
    /// The polygon's sides are not unit normals meeting at its angles.
    #[error("{space}: {field}: {what}")]
    Polygon {
        /// The space.
        space: String,
        /// `sides` or `angles`.
        field: &'static str,
        /// What is wrong.
        what: String,
    },
    /// The angles round a vertex of the polygon do not close up.
    #[error("{space}: the corners glued at side {side}'s end add up to {sum} (2 pi / k was expected)")]
    VertexCycle {
        /// The space.
        space: String,
        /// A side that starts the cycle.
        side: usize,
        /// The sum of its angles.
        sum: f64,
    },
}

/// How close a glued point must land on its face.
const GLUE_TOLERANCE: f64 = 1e-9;

impl ProductSpace {
    /// The faces: the polygon's sides, then the bottom, then the top.
    #[must_use]
    pub fn face_count(&self) -> usize {
        self.sides.len() + 2
    }

    /// The bottom face's index.
    #[must_use]
    pub fn bottom(&self) -> usize {
        self.sides.len()
    }

    /// The top face's index.
    #[must_use]
    pub fn top(&self) -> usize {
        self.sides.len() + 1
    }

    /// The face a ray entering through a gluing of `face` comes in by:
    /// its partner, or the mirror itself.
    #[must_use]
    pub fn partner(&self, face: usize) -> usize {
        match self.gluings[face] {
            ProductGluing::Paired { partner, .. } => partner,
            ProductGluing::Mirror(_) => face,
        }
    }

    /// True when `p` is in the prism (within `slack`).
    #[must_use]
    pub fn contains(&self, p: ProductPoint, slack: f64) -> bool {
        p.height.abs() <= self.height / 2.0 + slack
            && self.sides.iter().all(|n| self.geometry.form(*n, p.surface) <= slack)
    }

    /// Whether the ball of `radius` about `center` may reach into the
    /// prism: its height within `radius` of the prism's, and its centre
    /// within `radius` beyond no side (a point at distance `d` beyond the
    /// geodesic `<n, p> = 0` has `<n, p> = sinh d` on H2, `sin d` on S2).
    /// True for every ball that does; false only for balls that do not.
    #[must_use]
    pub fn may_meet(&self, center: ProductPoint, radius: f64) -> bool {
        let beyond = match self.geometry {
            ProductGeometry::H2xR => radius.sinh(),
            ProductGeometry::S2xR => radius.min(std::f64::consts::FRAC_PI_2).sin(),
        };
        center.height.abs() <= self.height / 2.0 + radius
            && self
                .sides
                .iter()
                .all(|n| self.geometry.form(*n, center.surface) <= beyond)
    }

    /// The polygon's vertices: vertex `i` joins side `i` and side `i + 1`.
    #[must_use]
    pub fn vertices(&self) -> Vec<DVec3> {
        let g = self.geometry;
        let k = g.curvature();
        (0..self.sides.len())
            .map(|i| {
                let (a, b) = (self.sides[i], self.sides[(i + 1) % self.sides.len()]);
                // The point on both lines: orthogonal (in the form) to both
                // normals, J (a x b) up to scale, on the model.
                let c = a.cross(b);
                let p = DVec3::new(c.x, c.y, k * c.z);
                let p = p / (g.form(p, p) * k).abs().sqrt();
                if p.z < 0.0 { -p } else { p }
            })
            .collect()
    }

    /// The polygon's area: the whole sphere's `4 pi`, or by Gauss-Bonnet
    /// `|(n - 2) pi - sum of angles|` for a geodesic polygon of `n` sides.
    #[must_use]
    pub fn area(&self) -> f64 {
        if self.sides.is_empty() {
            return 4.0 * PI;
        }
        let n = self.sides.len() as f64;
        ((n - 2.0) * PI - self.angles.iter().sum::<f64>()).abs()
    }

    /// The volume: area times height.
    #[must_use]
    pub fn volume(&self) -> f64 {
        self.area() * self.height
    }

    /// Checks the space: finite numbers, one gluing per face, each gluing
    /// an isometry that maps its face onto its partner's (its vertices
    /// onto the partner's vertices, the bottom onto the top), and the
    /// polygon's corners glued in cycles whose angles add up to `2 pi / k`.
    ///
    /// # Errors
    /// The first thing found wrong, naming the face or side.
    pub fn validate(&self) -> Result<(), ProductSpaceError> {
        let space = self.name.clone();
        if !(self.height.is_finite() && self.height > 0.0) {
            return Err(ProductSpaceError::BadNumber {
                space,
                field: "height",
                value: self.height,
            });
        }
        if self.gluings.len() != self.face_count() {
            return Err(ProductSpaceError::GluingCount {
                space,
                gluings: self.gluings.len(),
                faces: self.face_count(),
            });
        }
        let g = self.geometry;
        let n = self.sides.len();
        if self.angles.len() != n {
            return Err(ProductSpaceError::Polygon {
                space,
                field: "angles",
                what: format!("{} angles for {n} sides", self.angles.len()),
            });
        }
        for (i, side) in self.sides.iter().enumerate() {
            let unit = (g.form(*side, *side) - 1.0).abs();
            if unit.is_nan() || unit > 1e-9 || n < 3 {
                return Err(ProductSpaceError::Polygon {
                    space,
                    field: "sides",
                    what: format!("side {i} is not a unit normal of the surface's form (error {unit:e}) of a polygon"),
                });
            }
        }
        for i in 0..n {
            // The corner to the next side has the angle given:
            // cos(angle) = -<n_i, n_i+1>.
            let corner = (-g.form(self.sides[i], self.sides[(i + 1) % n]))
                .clamp(-1.0, 1.0)
                .acos();
            let off = (corner - self.angles[i]).abs();
            if off.is_nan() || off > 1e-9 {
                return Err(ProductSpaceError::Polygon {
                    space,
                    field: "angles",
                    what: format!(
                        "sides {i} and {} meet at {corner}, not at the angle given, {}",
                        (i + 1) % n,
                        self.angles[i]
                    ),
                });
            }
        }
        let vertices = self.vertices();
        // A convex polygon: every corner inside every side.
        for (i, v) in vertices.iter().enumerate() {
            let outside = |j: usize| {
                let f = g.form(self.sides[j], *v);
                f.is_nan() || f > GLUE_TOLERANCE
            };
            if let Some(j) = (0..n).find(|&j| outside(j)) {
                return Err(ProductSpaceError::Polygon {
                    space,
                    field: "sides",
                    what: format!("corner {i} is outside side {j}: the sides are not a convex polygon in order"),
                });
            }
        }
        for (face, gluing) in self.gluings.iter().enumerate() {
            let bad = |what: String| ProductSpaceError::Gluing {
                space: space.clone(),
                face,
                what,
            };
            let m = gluing.isometry();
            let error = g.isometry_error(m.surface);
            if error.is_nan() || error >= 1e-9 || m.flip.abs() != 1.0 || !m.shift.is_finite() {
                return Err(bad(format!(
                    "not an isometry (form error {error:e}, flip {}, shift {})",
                    m.flip, m.shift
                )));
            }
            let partner = self.partner(face);
            if partner >= self.face_count() {
                return Err(bad(format!("partner {partner} of {} faces", self.face_count())));
            }
            if face < n {
                // The side's two vertices land on the partner side's two.
                let ends = [vertices[(face + n - 1) % n], vertices[face]];
                for p in ends {
                    let image = m.surface * p;
                    let on = (partner < n)
                        && [vertices[(partner + n - 1) % n], vertices[partner]]
                            .iter()
                            .any(|q| g.surface_distance(image, *q) < GLUE_TOLERANCE);
                    if !on {
                        return Err(bad(format!("does not map its side onto side {partner}")));
                    }
                }
                if m.flip != 1.0 || m.shift.abs() > GLUE_TOLERANCE {
                    return Err(bad("a side's gluing moves the heights".into()));
                }
                let fixes = |p: DVec3| g.surface_distance(m.surface * p, p) < GLUE_TOLERANCE;
                if matches!(gluing, ProductGluing::Mirror(_)) && !(fixes(ends[0]) && fixes(ends[1])) {
                    return Err(bad("a mirror that does not fix its side".into()));
                }
            } else {
                // A horizontal face: its height onto the partner's, and the
                // polygon onto itself.
                let h = |f: usize| {
                    if f == self.bottom() {
                        -self.height / 2.0
                    } else {
                        self.height / 2.0
                    }
                };
                if partner < n || (m.flip * h(face) + m.shift - h(partner)).abs() > GLUE_TOLERANCE {
                    return Err(bad(format!("does not map its height onto face {partner}'s")));
                }
                if matches!(gluing, ProductGluing::Mirror(_)) && m.flip != -1.0 {
                    return Err(bad("a mirror end that does not turn the line over".into()));
                }
                let keeps = vertices.iter().all(|p| {
                    vertices
                        .iter()
                        .any(|q| g.surface_distance(m.surface * *p, *q) < GLUE_TOLERANCE)
                });
                if !keeps {
                    return Err(bad("its turn does not map the polygon onto itself".into()));
                }
            }
        }
        self.check_vertex_cycles(&vertices)
    }

    /// The polygon's corners glued in cycles (through the sides'
    /// gluings), each adding up to `2 pi / k` for a whole `k` (a corner
    /// of mirrors counts double).
    fn check_vertex_cycles(&self, vertices: &[DVec3]) -> Result<(), ProductSpaceError> {
        let n = self.sides.len();
        if n == 0 {
            return Ok(());
        }
        let g = self.geometry;
        let mut seen = vec![false; n];
        for start in 0..n {
            if seen[start] {
                continue;
            }
            // Walk the corners glued to corner `start` (between sides
            // `start` and `start + 1`): through side `start + 1`'s gluing,
            // the corner lands on a corner of the partner side, and the
            // walk goes on through that corner's other side.
            let (mut corner, mut side) = (start, (start + 1) % n);
            let mut sum = 0.0;
            let mut mirrors = false;
            for _ in 0..=2 * n {
                seen[corner] = true;
                sum += self.angles[corner];
                let gluing = &self.gluings[side];
                let image = gluing.isometry().surface * vertices[corner];
                let next = (0..n)
                    .find(|&c| g.surface_distance(image, vertices[c]) < GLUE_TOLERANCE)
                    .expect("validated: sides land on sides");
                mirrors |= matches!(gluing, ProductGluing::Mirror(_));
                let partner = self.partner(side);
                // Corner `next` joins sides `next` and `next + 1`; one of
                // them is the partner, the walk goes on through the other.
                side = if partner == next { (next + 1) % n } else { next };
                corner = next;
                if corner == start && (side == (start + 1) % n || mirrors) {
                    break;
                }
            }
            let full = if mirrors { PI } else { 2.0 * PI };
            let k = full / sum;
            if !((k - k.round()).abs() < 1e-9 && k.round() >= 1.0) {
                return Err(ProductSpaceError::VertexCycle {
                    space: self.name.clone(),
                    side: start,
                    sum,
                });
            }
        }
        Ok(())
    }

    /// The regular `n`-gon of the surface centred at the origin with
    /// interior angle `angle`: its sides' normals (side `i` facing
    /// direction `2 pi i / n`) and its inradius.
    #[must_use]
    pub fn regular_polygon(g: ProductGeometry, n: usize, angle: f64) -> (Vec<DVec3>, f64) {
        // Right triangle centre - side midpoint - vertex: angles pi/n at
        // the centre and angle/2 at the vertex; cos(angle/2) =
        // C(inradius) sin(pi/n), C the surface's cosine.
        let c = (angle / 2.0).cos() / (PI / n as f64).sin();
        let r = match g {
            ProductGeometry::H2xR => c.acosh(),
            ProductGeometry::S2xR => c.acos(),
        };
        let (ch, sh) = g.trig(r);
        let k = g.curvature();
        let sides = (0..n)
            .map(|i| {
                let t = 2.0 * PI * i as f64 / n as f64;
                // The line through the origin facing x, (1, 0, 0), moved
                // out by r: its normal is the translation's image of it;
                // turned to face t.
                let m = DVec3::new(ch, 0.0, -k * sh);
                DVec3::new(m.x * t.cos(), m.x * t.sin(), m.z)
            })
            .collect();
        (sides, r)
    }

    /// The names [`ProductSpace::named`] knows, as the command line and
    /// the examples take them.
    pub const NAMES: [&'static str; 5] = [
        "s2xs1",
        "twisted-s2xs1",
        "genus2xs1",
        "twisted-genus2xs1",
        "mirrored-prism",
    ];

    /// The space of that name ([`ProductSpace::NAMES`]) with a circle (or
    /// interval) of length `length`; `twist` is the twisted spaces' turn
    /// (1/`twist` of a turn of the sphere, `twist` eighths of a turn of
    /// the genus-2 surface); the mirrored prism is the pentagon's.
    ///
    /// ```
    /// use bevy_manifold_core::space::product::ProductSpace;
    /// let space = ProductSpace::named("twisted-s2xs1", 2.0, 3).expect("a name it knows");
    /// assert_eq!(space.name, "S2 x S1 turned by 1/3");
    /// assert!(ProductSpace::named("torus", 2.0, 3).is_none());
    /// ```
    #[must_use]
    pub fn named(name: &str, length: f64, twist: u32) -> Option<Self> {
        Some(match name {
            "s2xs1" => Self::s2_x_s1(length),
            "twisted-s2xs1" => Self::twisted_s2_x_s1(length, twist),
            "genus2xs1" => Self::genus_two_x_s1(length),
            "twisted-genus2xs1" => Self::twisted_genus_two_x_s1(length, twist),
            "mirrored-prism" => Self::mirrored_prism(5, length),
            _ => return None,
        })
    }

    /// S2 x S1 with a circle of length `height`: the whole sphere times an
    /// interval, its ends glued straight.
    #[must_use]
    pub fn s2_x_s1(height: f64) -> Self {
        Self::twisted_s2_x_s1(height, 1)
    }

    /// The mapping torus of the sphere turned by `1/order` of a turn about
    /// its poles: going once round the circle turns the sphere, so only
    /// the poles' vertical geodesics close after `height`; the others
    /// close after `order` rounds.
    #[must_use]
    pub fn twisted_s2_x_s1(height: f64, order: u32) -> Self {
        let g = ProductGeometry::S2xR;
        let turn = g.rotation(2.0 * PI / f64::from(order.max(1)));
        Self::prism(
            if order <= 1 {
                "S2 x S1".into()
            } else {
                format!("S2 x S1 turned by 1/{order}")
            },
            g,
            (Vec::new(), Vec::new(), Vec::new()),
            height,
            turn,
        )
    }

    /// A closed surface of genus 2 (the regular octagon with angles
    /// `pi/4`, its opposite sides glued by translations) times a circle of
    /// length `height`.
    #[must_use]
    pub fn genus_two_x_s1(height: f64) -> Self {
        Self::twisted_genus_two_x_s1(height, 0)
    }

    /// The mapping torus of the genus-2 surface turned by `eighths` eighths
    /// of a turn (the octagon's symmetry, which the gluing of opposite
    /// sides respects) as one goes round the circle.
    #[must_use]
    pub fn twisted_genus_two_x_s1(height: f64, eighths: u32) -> Self {
        let g = ProductGeometry::H2xR;
        let (sides, r) = Self::regular_polygon(g, 8, PI / 4.0);
        let gluings = (0..8)
            .map(|i| {
                // Side i onto the opposite side, i + 4: the translation
                // back across the octagon along side i's direction.
                let t = 2.0 * PI * f64::from(i) / 8.0;
                ProductGluing::Paired {
                    partner: (i as usize + 4) % 8,
                    pairing: ProductIsometry::new(g.translation(t, -2.0 * r), 1.0, 0.0),
                }
            })
            .collect();
        let name = if eighths.is_multiple_of(8) {
            "genus 2 x S1".into()
        } else {
            format!("genus 2 x S1 turned by {}/8", eighths % 8)
        };
        let turn = g.rotation(2.0 * PI * f64::from(eighths % 8) / 8.0);
        Self::prism(name, g, (sides, gluings, vec![PI / 4.0; 8]), height, turn)
    }

    /// The orbifold with mirrors: the right-angled regular `n`-gon of H2
    /// (`n >= 5`) times an interval of length `height`, every face a
    /// mirror (a reflection group, as the paper's mirrored cube).
    #[must_use]
    pub fn mirrored_prism(n: usize, height: f64) -> Self {
        let g = ProductGeometry::H2xR;
        let (sides, _) = Self::regular_polygon(g, n.max(5), PI / 2.0);
        let mut gluings: Vec<ProductGluing> = sides
            .iter()
            .map(|s| ProductGluing::Mirror(ProductIsometry::new(g.reflection(*s), 1.0, 0.0)))
            .collect();
        gluings.push(ProductGluing::Mirror(ProductIsometry::new(
            DMat3::IDENTITY,
            -1.0,
            -height,
        )));
        gluings.push(ProductGluing::Mirror(ProductIsometry::new(
            DMat3::IDENTITY,
            -1.0,
            height,
        )));
        let angles = vec![PI / 2.0; sides.len()];
        Self {
            name: format!("mirrored right-angled {}-gon x interval", sides.len()),
            geometry: g,
            sides,
            height,
            gluings,
            angles,
        }
    }

    /// A prism whose ends are glued by a vertical translation by `height`
    /// turned by `turn`.
    fn prism(
        name: String,
        geometry: ProductGeometry,
        (sides, mut gluings, angles): (Vec<DVec3>, Vec<ProductGluing>, Vec<f64>),
        height: f64,
        turn: DMat3,
    ) -> Self {
        let n = sides.len();
        // Leaving through the bottom: up by L, turned back; through the
        // top: down by L, turned on.
        let up = ProductIsometry::new(turn.transpose(), 1.0, height);
        let down = ProductIsometry::new(turn, 1.0, -height);
        gluings.push(ProductGluing::Paired {
            partner: n + 1,
            pairing: up,
        });
        gluings.push(ProductGluing::Paired {
            partner: n,
            pairing: down,
        });
        Self {
            name,
            geometry,
            sides,
            height,
            gluings,
            angles,
        }
    }
}
