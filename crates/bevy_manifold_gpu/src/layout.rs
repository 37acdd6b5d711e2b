//! The tracer's GPU data layout: the `#[repr(C)]` twins of the structs
//! in `shaders/bindings.wgsl` (held to them by `tests/contract.rs`), and
//! the flags and markers both sides share. What fills them is
//! [`crate::pack`].

use bevy_manifold_core::trace::TraceSettings;
use bytemuck::{Pod, Zeroable};

/// WGSL twin: `Params` in `shaders/bindings.wgsl`.
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct GpuParams {
    /// Camera isometry (wrapped into the domain).
    pub camera: [f32; 16],
    /// The camera's cell element.
    pub camera_cell: [f32; 16],
    /// Fog colour (rgb, 1).
    pub fog_color: [f32; 4],
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Most transports per ray.
    pub levels: u32,
    /// Number of faces.
    pub face_count: u32,
    /// Number of balls.
    pub ball_count: u32,
    /// Number of tubes.
    pub tube_count: u32,
    /// Number of lights.
    pub light_count: u32,
    /// The camera's index in the Cayley table (finite groups).
    pub camera_cell_index: u32,
    /// `tan(fov_y / 2)`.
    pub tan_half_fov: f32,
    /// Rays stop after this distance.
    pub max_distance: f32,
    /// Fog density (0 without fog).
    pub fog_density: f32,
    /// `k` of the edge tubes.
    pub tube_k: f32,
    /// The render pass: the viewport's left pixel column in the target.
    pub origin_x: u32,
    /// The render pass: the viewport's top pixel row in the target.
    pub origin_y: u32,
    /// The camera's near plane, for reverse-z depth.
    pub near: f32,
    /// [`FLAG_NO_EARLY_STOP`] | [`FLAG_NO_RENORMALIZE`]: measurement
    /// switches, 0 for normal tracing.
    pub flags: u32,
    /// Lattice: 1 / box edges; hashed: 1 / grid step in x, the f32 horizon
    /// in y.
    pub cell_scale: [f32; 4],
    /// Number of mesh instances.
    pub instance_count: u32,
    /// Per-cell shading, the three words of
    /// [`bevy_manifold_core::space::cells::CellTint::words`]: the mode
    /// (0 by cell, 1 highlight, 2 on/off pattern)...
    pub cell_mode: u32,
    /// ... the highlighted cell's low word, or the pattern's threshold...
    pub cell_a: u32,
    /// ... and the highlighted cell's high word.
    pub cell_b: u32,
    /// Per-cell rules, the four words of
    /// [`bevy_manifold_core::space::rule::CellRule::words`]: the on
    /// threshold...
    pub rule_hidden: u32,
    /// ... its seed...
    pub rule_hidden_seed: u32,
    /// ... the wall threshold...
    pub rule_walls: u32,
    /// ... and its seed.
    pub rule_walls_seed: u32,
    /// [`bevy_manifold_core::trace::Projection::words`]: 0 perspective,
    /// 1 equirectangular, 2 omni-directional stereo...
    pub projection: u32,
    /// ... and, for stereo, half the eye separation.
    pub eye_offset: f32,
    /// `FaceTables::near_scale` times `FlatScene::near_reach`: the bound
    /// of `near_faces`' test.
    pub near_reach: f32,
    /// The point of each light's disc shadow rays aim at
    /// (`bevy_manifold_core::trace::light_sample_point` of
    /// `TraceSettings::light_sample`), first coordinate...
    pub light_sample_u: f32,
    /// How many leaves [`GpuObjects::ball_nodes`] holds (0: no tree).
    pub ball_leaves: u32,
    /// Cone tracing: `FaceTables::chart_stretch`...
    pub chart_stretch: f32,
    /// ... and `FlatScene::footprint_cap`.
    pub footprint_cap: f32,
    /// ... and second.
    pub light_sample_v: f32,
    /// An off-centre frustum, `[half width, half height, centre x, centre
    /// y]` in slopes ([`bevy_manifold_core::trace::Frustum`]); all zero
    /// for the symmetric frustum of `tan_half_fov` and the image's aspect.
    pub frustum: [f32; 4],
    /// Cone tracing (`FOOTPRINT`): the pixels' half-angle
    /// ([`GpuView::footprint`]), `FlatScene::near_distance`,
    /// `FaceTables::near_scale`, `FlatScene::cell_shadow`.
    pub cone: [f32; 4],
    /// The faces whose group holds any ball, tube, mesh instance (x, y,
    /// z; bit `f` for face `f` below 32, from [`GpuObjects::groups`]):
    /// the WGSL walks only these of a segment's near faces, so that empty
    /// groups cost no reads (WGSL only; the CPU's empty ranges cost
    /// nothing).
    pub occupied: [u32; 4],
    /// Reflections (`REFLECTIONS`): the most reflections a ray takes
    /// (`bevy_manifold_core::trace::TraceSettings::reflections`).
    pub reflections: u32,
    /// Path tracing (`PATH_TRACE`): the most bounces of a path
    /// (`bevy_manifold_core::trace::TraceSettings::path_depth`)...
    pub path_depth: u32,
    /// ... the paths' seed (`TraceSettings::seed`)...
    pub seed: u32,
    /// ... and the sample's index (`TraceSettings::light_sample`, the
    /// `k` of [`GpuParams::sample`]).
    pub sample: u32,
    /// Where in `mesh_data` the instance trees' table starts
    /// ([`GpuObjects::instance_trees`]), or [`NO_INSTANCE_TREES`].
    pub instance_trees: u32,
    /// Padding to 16 bytes.
    pub pad_a: u32,
    /// Padding.
    pub pad_b: u32,
    /// Padding.
    pub pad_c: u32,
}

/// [`GpuParams::instance_trees`]: no instance has a tree (every one is
/// tested).
pub const NO_INSTANCE_TREES: u32 = u32::MAX;

/// WGSL twin: `Face` in `shaders/bindings.wgsl`.
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct GpuFace {
    /// Plane.
    pub plane: [f32; 4],
    /// `T_i`.
    pub pairing: [f32; 16],
    /// `T_i^-1`.
    pub crossing: [f32; 16],
    /// Partner face.
    pub partner: u32,
    /// Padding to 16 bytes, one word a field: the faces are a uniform
    /// array, where an array member would need a 16-byte stride.
    pub pad_a: u32,
    /// Padding.
    pub pad_b: u32,
    /// Padding.
    pub pad_c: u32,
}

/// WGSL twin: `Ball` in `shaders/bindings.wgsl`.
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct GpuBall {
    /// Centre.
    pub center: [f32; 4],
    /// Albedo.
    pub color: [f32; 3],
    /// `cosh r`, `cos r` or `r^2`.
    pub k: f32,
    /// Object id.
    pub id: u32,
    /// `FlatBall::face_mask`.
    pub face_mask: u32,
    /// `FlatBall::glow`.
    pub glow: f32,
    /// `FlatBall::pbr` in one word ([`pack_pbr`]): 0 for the classic
    /// look (and this word pads the struct to 16 bytes, as the balls are
    /// a uniform array).
    pub pbr: u32,
}

/// WGSL twin: `Tube` in `shaders/bindings.wgsl`.
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct GpuTube {
    /// Start point.
    pub a: [f32; 4],
    /// Unit tangent at `a` towards `b`.
    pub e: [f32; 4],
    /// End point.
    pub b: [f32; 4],
    /// Unit tangent at `b`, away from `a`.
    pub e_b: [f32; 4],
    /// Albedo.
    pub color: [f32; 3],
    /// `FlatTube::face_mask`.
    pub face_mask: u32,
    /// `FlatTube::joint`: the index of the vertex joint tested after this
    /// tube, or [`NO_JOINT`].
    pub joint: u32,
    /// Padding to 16 bytes.
    pub pad_a: u32,
    /// Padding.
    pub pad_b: u32,
    /// Padding.
    pub pad_c: u32,
}

/// WGSL twin: `Instance` in `shaders/bindings.wgsl`: one placement of a mesh, with offsets into
/// [`GpuObjects::mesh_data`].
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct GpuInstance {
    /// From the domain's chart to the mesh's coordinates.
    pub to_local: [f32; 16],
    /// Bounding ball centre.
    pub center: [f32; 4],
    /// Base colour.
    pub color: [f32; 3],
    /// Bounding ball `k`.
    pub k: f32,
    /// Offset of the mesh's BVH nodes (two words each).
    pub nodes: u32,
    /// Offset of its vertices (two words each).
    pub vertices: u32,
    /// Offset of its triangles (one word each).
    pub triangles: u32,
    /// Object id.
    pub id: u32,
    /// Its textures in `mesh_data` (base colour, metallic-roughness,
    /// emission, normal map): each the offset of a header word
    /// `[width, height, 0, 0]` followed by the texels, four per word; or
    /// [`NO_TEXTURE`].
    pub textures: [u32; 4],
    /// Number of BVH nodes (bounds the traversal loop).
    pub node_count: u32,
    /// 1 for a copy of a mesh attached to the camera (see `home`).
    pub attached: u32,
    /// `FlatInstance::face_mask`.
    pub face_mask: u32,
    /// The alpha mask's cutoff; negative: opaque.
    pub alpha_cutoff: f32,
    /// Emitted radiance (linear RGB).
    pub emissive: [f32; 3],
    /// Metallic; negative: the classic look (no GGX lobe).
    pub metallic: f32,
    /// Perceptual roughness.
    pub roughness: f32,
    /// The base alpha factor (for the mask).
    pub alpha: f32,
    /// Padding to 16 bytes.
    pub pad: [u32; 2],
    /// With `attached`: the cell point `g o` from which this copy is the
    /// camera's own body (`FlatInstance::home`).
    pub home: [f32; 4],
}

/// [`GpuInstance::textures`]: no texture in that slot.
pub const NO_TEXTURE: u32 = u32::MAX;

/// A ball's metallic and roughness in one word, as [`GpuBall::pbr`] holds
/// them: bit 0 set, metallic in 15 bits above it, roughness in the high
/// 16; 0 for the classic look. WGSL twin: `ball_pbr` in
/// `shaders/shade.wgsl`.
///
/// ```
/// use bevy_manifold_core::material::Pbr;
/// use bevy_manifold_gpu::layout::pack_pbr;
/// assert_eq!(pack_pbr(None), 0);
/// let w = pack_pbr(Some(Pbr { metallic: 1.0, roughness: 0.5 }));
/// assert_eq!(w & 1, 1);
/// assert_eq!((w >> 1) & 0x7fff, 32767);
/// assert_eq!(w >> 16, 32768);
/// ```
#[must_use]
pub fn pack_pbr(pbr: Option<bevy_manifold_core::material::Pbr>) -> u32 {
    pbr.map_or(0, |p| {
        let m = (p.metallic.clamp(0.0, 1.0) * 32767.0).round() as u32;
        let r = (p.roughness.clamp(0.0, 1.0) * 65535.0).round() as u32;
        1 | (m << 1) | (r << 16)
    })
}

/// WGSL twin: `Light` in `shaders/bindings.wgsl`.
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct GpuLight {
    /// Position (of a light image, `FlatLight::position`).
    pub position: [f32; 4],
    /// Colour.
    pub color: [f32; 3],
    /// Power.
    pub intensity: f32,
    /// `FlatLight::inv_range_sq`.
    pub inv_range_sq: f32,
    /// `FlatLight::min_area`.
    pub min_area: f32,
    /// `FlatLight::spot_scale`.
    pub spot_scale: f32,
    /// `FlatLight::spot_offset`.
    pub spot_offset: f32,
    /// `FlatLight::spot_dir`.
    pub spot_dir: [f32; 4],
    /// `FlatLight::radius`: soft shadows (`SOFT_SHADOWS`).
    pub radius: f32,
    /// Padding to 16 bytes.
    pub pad_a: f32,
    /// Padding.
    pub pad_b: f32,
    /// Padding.
    pub pad_c: f32,
}

/// WGSL twin: `Pixel` in `shaders/bindings.wgsl`.
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct GpuPixel {
    /// Colour, and the distance in `w`.
    pub color: [f32; 4],
    /// Object id.
    pub object: u32,
    /// Levels used.
    pub levels: u32,
    /// Cell id, low word.
    pub cell_lo: u32,
    /// Cell id, high word.
    pub cell_hi: u32,
}

/// [`GpuParams::flags`]: fog does not stop rays early
/// (`TraceSettings::fog_early_stop` off).
pub const FLAG_NO_EARLY_STOP: u32 = 1;

/// [`GpuParams::flags`]: no renormalisation (`TraceSettings::renormalize`
/// off).
pub const FLAG_NO_RENORMALIZE: u32 = 2;

/// [`GpuParams::flags`]: every object tested on every segment
/// (`TraceSettings::cull` off).
pub const FLAG_NO_CULL: u32 = 4;

/// [`GpuTube::joint`] of a tube that carries no vertex joint (or one past
/// the balls packed). WGSL twin: `NO_JOINT` in `shaders/bindings.wgsl`.
pub const NO_JOINT: u32 = u32::MAX;

/// The flags that say how `settings` differs from normal tracing.
#[must_use]
pub fn settings_flags(settings: &TraceSettings) -> u32 {
    let mut flags = 0;
    if !settings.fog_early_stop {
        flags |= FLAG_NO_EARLY_STOP;
    }
    if !settings.renormalize {
        flags |= FLAG_NO_RENORMALIZE;
    }
    if !settings.cull {
        flags |= FLAG_NO_CULL;
    }
    flags
}
