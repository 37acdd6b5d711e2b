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

/// What fills a binding's buffer, and so when it is written again.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BindingSource {
    /// The view: the params, per camera and frame.
    View,
    /// The space ([`crate::GpuSpace`]): its faces and cell table, when the
    /// space or the table's centre changes.
    Space,
    /// The scene's objects ([`crate::GpuObjects`]), when an object changes.
    Objects,
    /// Written by the shader: the compute entries' pixels.
    Output,
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
    /// What fills it ([`crate::binding_bytes`] gives a space's and a
    /// scene's bytes).
    pub source: BindingSource,
    /// Read by the compute entries only (the render pass binds the others).
    pub compute_only: bool,
    /// The size of one element (the params' size, or one array element):
    /// the Rust twin's `size_of`.
    pub element_size: usize,
    /// A uniform array's length, fixed in the WGSL: its buffer is always
    /// this many elements, whatever the space or scene holds. 0 for the
    /// others, which are as long as their data.
    pub capacity: usize,
}

impl Binding {
    /// The bytes a buffer for `data` bound here must hold: a uniform
    /// array's whole declared size, else `data` itself.
    ///
    /// ```
    /// use bevy_manifold_gpu::bindings::BINDINGS;
    /// let faces = &BINDINGS[1];
    /// assert_eq!(faces.name, "faces");
    /// assert_eq!(faces.bytes_for(320), 128 * 160);
    /// assert_eq!(BINDINGS[5].bytes_for(320), 320);
    /// ```
    #[must_use]
    pub fn bytes_for(&self, data: usize) -> usize {
        data.max(self.capacity * self.element_size)
    }

    /// wgpu's usage for this binding's buffer (a buffer written in place
    /// adds `COPY_DST`).
    #[must_use]
    pub fn usage(&self) -> wgpu_types::BufferUsages {
        match self.kind {
            BindingKind::Uniform => wgpu_types::BufferUsages::UNIFORM,
            BindingKind::Storage | BindingKind::StorageReadWrite => wgpu_types::BufferUsages::STORAGE,
        }
    }
}

const fn binding(
    binding: u32,
    name: &'static str,
    (kind, source): (BindingKind, BindingSource),
    element_size: usize,
) -> Binding {
    Binding {
        binding,
        name,
        kind,
        source,
        compute_only: matches!(kind, BindingKind::StorageReadWrite),
        element_size,
        capacity: 0,
    }
}

/// A uniform array of `capacity` elements.
const fn uniform_array(
    binding: u32,
    name: &'static str,
    source: BindingSource,
    element_size: usize,
    capacity: usize,
) -> Binding {
    Binding {
        binding,
        name,
        kind: BindingKind::Uniform,
        source,
        compute_only: false,
        element_size,
        capacity,
    }
}

use crate::layout::{GpuBall, GpuFace, GpuInstance, GpuLight, GpuParams, GpuPixel, GpuTube};
use BindingKind::{Storage, StorageReadWrite};
use BindingSource::{Objects, Output, View};
use bevy_manifold_core::space::MAX_FACES;
use bevy_manifold_core::trace::MAX_LIGHT_IMAGES;
use std::mem::size_of;

/// The most edge tubes a domain has: a convex polyhedron with `F` faces
/// has at most `3F - 6` edges (Euler), so [`MAX_FACES`] faces give at most
/// this many. The tubes' uniform array holds this many.
pub const MAX_TUBES: usize = 3 * MAX_FACES - 6;

/// The most balls (ghost copies and vertex joints included) the balls'
/// uniform array holds: 48 KiB of [`GpuBall`]. A scene of up to 254
/// balls stays well within it unless its balls are large against the
/// domain (each of those has a ghost across every face it reaches); past
/// it the headless runner refuses the scene and the render pass draws the
/// first this many.
pub const MAX_BALLS: usize = 1024;

/// The most leaves of the ball tree (`FlatScene::ball_tree`) the
/// `ball_nodes` uniform array holds (one word of four `u32` each, after
/// the two of the boxes' frame): the core's
/// [`bevy_manifold_core::trace::MAX_BALL_LEAVES`], which no tree exceeds.
pub const MAX_BALL_LEAVES: usize = bevy_manifold_core::trace::MAX_BALL_LEAVES;

// The shader keeps the met leaves as the 64 bits of a vec2<u32> and tests
// them in four chunks of 16 (ball_tree_leaves in cull.wgsl, cache_leaves
// in ball_tree.wgsl): more leaves would need both widened.
const _: () = assert!(MAX_BALL_LEAVES <= 64);

/// The entries of the face groups' uniform array: one per face up to 32,
/// and one for the counts.
pub const GROUPS: usize = 33;

/// Group 0, in binding order: the params, then faces, balls,
/// tubes, lights, the cell table, mesh instances and mesh data (read by
/// every entry), `pixels`, the compute entries' output, and the face
/// groups (read by every entry; after `pixels` as it came later).
///
/// The params are a read-only storage buffer, not a uniform: with them in
/// a uniform, lavapipe (Mesa 22.3.6) grew the process by about 0.9 MB a
/// frame at 160x90 with a still camera, and by 0.35 MB a headless
/// dispatch, without end (heaptrack places it in lavapipe's execution
/// thread, mostly outside malloc: JIT code, we believe from its inlining
/// of uniform values into loop bounds; trivial shaders with a uniform do
/// not show it). Read from a storage buffer the same shader stays flat.
///
/// The faces, the edge tubes and the lights are uniform arrays of fixed
/// length ([`MAX_FACES`], [`MAX_TUBES`], [`MAX_LIGHT_IMAGES`]: 20,480, 36,288
/// and 16,384 bytes, within WebGPU's default 64 KiB per binding; the runner
/// and the pass refuse an adapter below [`largest_uniform`]). lavapipe
/// (Mesa 22.3.6) reads a storage buffer one SIMD lane at a time, each lane
/// a loop iteration with its own bounds check, and a uniform with one
/// gather. With these three uniform and the walk's params read once per
/// invocation (`cache_params` in the WGSL), the default scene at 8 levels
/// traced 1.13-1.32x faster on lavapipe (see docs/benchmarks/history.md, "Uniform arrays
/// on lavapipe"). The params stay storage for the leak above; these arrays
/// did not grow the process over 80 headless renders, nor the explorer's
/// soak beyond its pipelines.
///
/// The balls ([`MAX_BALLS`]) and the ball tree's leaves
/// ([`MAX_BALL_LEAVES`], `ball_nodes`, binding 10) are uniform arrays too:
/// with them (and the tree, then walked node by node, without a stack) a
/// swarm of 128 balls in the torus traced in 25.9 ms instead of 46.4
/// (docs/benchmarks/history.md, "Balls in uniforms, the tree by skip links").
///
/// The face groups (`GpuObjects::groups`: where each face's objects start,
/// and the tubes' edge table) are a uniform array of 33 entries, 528
/// bytes. In the params they were read per lane at every group a segment
/// walked; as a uniform the default scene at 8 levels traced 2-8% faster
/// on lavapipe, and 80 headless renders did not grow the process.
///
/// The compute stage binds five storage buffers.
pub const BINDINGS: [Binding; 11] = [
    binding(0, "params", (Storage, View), size_of::<GpuParams>()),
    uniform_array(1, "faces", BindingSource::Space, size_of::<GpuFace>(), MAX_FACES),
    uniform_array(2, "balls", Objects, size_of::<GpuBall>(), MAX_BALLS),
    uniform_array(3, "tubes", Objects, size_of::<GpuTube>(), MAX_TUBES),
    uniform_array(4, "lights", Objects, size_of::<GpuLight>(), MAX_LIGHT_IMAGES),
    binding(5, "cell_table", (Storage, BindingSource::Space), size_of::<u32>()),
    binding(6, "instances", (Storage, Objects), size_of::<GpuInstance>()),
    binding(7, "mesh_data", (Storage, Objects), size_of::<[u32; 4]>()),
    binding(8, "pixels", (StorageReadWrite, Output), size_of::<GpuPixel>()),
    uniform_array(9, "groups", Objects, size_of::<[u32; 4]>(), GROUPS),
    uniform_array(10, "ball_nodes", Objects, size_of::<[u32; 4]>(), MAX_BALL_LEAVES + 2),
];

/// The bytes of the largest uniform binding: what an adapter's
/// `max_uniform_buffer_binding_size` must reach for the tracer to bind
/// (the balls, 49,152 bytes; WebGPU's default limit is 65,536).
///
/// ```
/// assert_eq!(bevy_manifold_gpu::bindings::largest_uniform(), 1024 * 48);
/// ```
#[must_use]
pub const fn largest_uniform() -> u64 {
    let mut largest = 0;
    let mut i = 0;
    while i < BINDINGS.len() {
        let bytes = BINDINGS[i].capacity * BINDINGS[i].element_size;
        if bytes > largest {
            largest = bytes;
        }
        i += 1;
    }
    largest as u64
}

/// Why an adapter whose `max_uniform_buffer_binding_size` is `allowed`
/// cannot bind the tracer's uniform arrays, or `None` when it can: the
/// check the headless runner and the render pass both make.
///
/// ```
/// use bevy_manifold_gpu::bindings::{largest_uniform, uniform_limit_error};
/// assert_eq!(uniform_limit_error(65_536), None);
/// assert!(uniform_limit_error(largest_uniform() - 1).unwrap().contains("49152 bytes"));
/// ```
#[must_use]
pub fn uniform_limit_error(allowed: u64) -> Option<String> {
    let uniform = largest_uniform();
    (allowed < uniform)
        .then(|| format!("the tracer binds a uniform array of {uniform} bytes; this adapter allows {allowed}"))
}

/// The bindings the render pass binds (every one the fragment entry reads).
pub fn render_bindings() -> impl Iterator<Item = &'static Binding> {
    BINDINGS.iter().filter(|b| !b.compute_only)
}
