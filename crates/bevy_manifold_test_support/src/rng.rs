//! A seeded random source for test inputs, the same in every test.

use bevy_manifold_core::geometry::{Geometry, isometry};
use glam::DMat4;

/// A small deterministic random source (an LCG) for test inputs.
pub struct Rng(pub u64);

impl Rng {
    /// Uniform in [0, 1).
    pub fn next_f64(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A random unit vector.
    pub fn unit(&mut self) -> glam::DVec3 {
        loop {
            let v = glam::DVec3::new(self.next_f64(), self.next_f64(), self.next_f64()) * 2.0 - 1.0;
            let l = v.length();
            if l > 0.05 && l <= 1.0 {
                return v / l;
            }
        }
    }

    /// A point of the cube `[-h, h]^3`.
    pub fn in_box(&mut self, h: f64) -> [f64; 3] {
        [0; 3].map(|_| (self.next_f64() * 2.0 - 1.0) * h)
    }

    /// Uniform in `0..n`.
    pub fn below(&mut self, n: usize) -> usize {
        ((self.next_f64() * n as f64) as usize).min(n.saturating_sub(1))
    }

    /// A random isometry of `g`: a rotation, then a translation of length
    /// at most `reach`.
    pub fn isometry(&mut self, g: Geometry, reach: f64) -> DMat4 {
        let r = isometry::rotation(self.unit(), self.next_f64() * std::f64::consts::TAU);
        isometry::translation(g, self.unit() * self.next_f64() * reach) * r
    }

    /// A random ray starting strictly inside the domain of `space` (within
    /// 0.95 of its inradius of the centre), in a random direction.
    pub fn ray_inside(
        &mut self,
        space: &bevy_manifold_core::space::Space,
    ) -> bevy_manifold_core::trace::step::Ray<f64> {
        let g = space.geometry();
        let place = isometry::translation(g, self.unit() * self.next_f64() * 0.95 * space.inradius())
            * isometry::rotation(self.unit(), self.next_f64() * std::f64::consts::TAU);
        let o = place * glam::DVec4::W;
        bevy_manifold_core::trace::step::Ray {
            origin: o,
            dir: g.normalize_tangent::<f64>(o, place * glam::DVec4::Z),
        }
    }
}
