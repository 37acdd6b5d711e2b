//! What bevy_manifold's tests and benchmarks share (unpublished, like
//! `vello_tests`): one image comparison, one seeded RNG, the stress
//! fixtures, an independent solution of the word problem of the
//! right-angled mirror spaces ([`coxeter`]), an animated glTF character
//! made in code ([`stalk`]), and (feature `gpu`) the GPU to test on or an
//! honest skip.

pub mod compare;
pub mod coxeter;
pub mod fuzz;
#[cfg(feature = "gpu")]
pub mod gpu;
pub mod harness;
pub mod materials;
pub mod rng;
pub mod stalk;
pub mod stress;

pub use compare::agreement;
#[cfg(feature = "gpu")]
pub use gpu::tracer;
pub use rng::Rng;
