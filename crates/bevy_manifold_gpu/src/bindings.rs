//! The tracer's bind group 0, described once. The raw-wgpu runner's
//! layout, the Bevy render pass's layout and the WGSL declarations
//! (`shaders/bindings.wgsl`) all follow [`BINDINGS`]; the contract test
//! (`tests/contract.rs`) holds the WGSL to it through naga.

/// How a binding is accessed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BindingKind {
    /// `var<uniform>`.
    Uniform,
    /// `var<storage, read>`.
    Storage,
    /// `var<storage, read_write>`.
    StorageReadWrite,
}

impl BindingKind {
    /// wgpu's buffer binding type (both layouts are built from it).
    #[must_use]
    pub fn buffer_binding_type(self) -> wgpu_types::BufferBindingType {
        match self {
            BindingKind::Uniform => wgpu_types::BufferBindingType::Uniform,
            BindingKind::Storage => wgpu_types::BufferBindingType::Storage { read_only: true },
            BindingKind::StorageReadWrite => wgpu_types::BufferBindingType::Storage { read_only: false },
        }
    }
}

/// One binding of group 0.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Binding {
    /// The `@binding` number.
    pub binding: u32,
    /// The WGSL variable's name.
    pub name: &'static str,
    /// How it is accessed.
    pub kind: BindingKind,
    /// Read by the compute entries only (the render pass binds the others).
    pub compute_only: bool,
    /// The size of one element (the params' size, or one array element
    /// of a storage buffer): the Rust twin's `size_of`.
    pub element_size: usize,
}

const fn binding(binding: u32, name: &'static str, kind: BindingKind, element_size: usize) -> Binding {
    Binding {
        binding,
        name,
        kind,
        compute_only: matches!(kind, BindingKind::StorageReadWrite),
        element_size,
    }
}

use crate::layout::{GpuBall, GpuFace, GpuInstance, GpuLight, GpuParams, GpuPixel, GpuTube};
use BindingKind::{Storage, StorageReadWrite};
use std::mem::size_of;

/// Group 0, in binding order: the params, then faces, balls,
/// tubes, lights, the cell table, mesh instances and mesh data (read by
/// every entry), and `pixels`, the compute entries' output.
///
/// The params are a read-only storage buffer, not a uniform: with them in
/// a uniform, lavapipe (Mesa 22.3.6) grew the process by about 0.9 MB a
/// frame at 160x90 with a still camera, and by 0.35 MB a headless
/// dispatch, without end (heaptrack places it in lavapipe's execution
/// thread, mostly outside malloc: JIT code, we believe from its inlining
/// of uniform values into loop bounds; trivial shaders with a uniform do
/// not show it). Read from a storage buffer the same shader stays flat.
/// The compute stage then binds nine storage buffers, one more than
/// WebGPU's default limit (the headless runner asks for them; desktop
/// adapters have more).
pub const BINDINGS: [Binding; 9] = [
    binding(0, "params", Storage, size_of::<GpuParams>()),
    binding(1, "faces", Storage, size_of::<GpuFace>()),
    binding(2, "balls", Storage, size_of::<GpuBall>()),
    binding(3, "tubes", Storage, size_of::<GpuTube>()),
    binding(4, "lights", Storage, size_of::<GpuLight>()),
    binding(5, "cell_table", Storage, size_of::<u32>()),
    binding(6, "instances", Storage, size_of::<GpuInstance>()),
    binding(7, "mesh_data", Storage, size_of::<[u32; 4]>()),
    binding(8, "pixels", StorageReadWrite, size_of::<GpuPixel>()),
];

/// The bindings the render pass binds (every one the fragment entry reads).
pub fn render_bindings() -> impl Iterator<Item = &'static Binding> {
    BINDINGS.iter().filter(|b| !b.compute_only)
}
