//! The product spaces (H2xR, S2xR) on the GPU: the `#[repr(C)]` twins of
//! `shaders/product.wgsl`'s structs (held to them by `tests/contract.rs`)
//! and their packing from the core's
//! [`ProductScene`](bevy_manifold_core::trace::product::ProductScene), in
//! f32, as the CPU reference
//! ([`bevy_manifold_core::trace::product`]) reads it in f64.
//!
//! ```
//! use bevy_manifold_core::space::product::ProductSpace;
//! use bevy_manifold_core::trace::product::ProductScene;
//! use bevy_manifold_gpu::product::GpuProductScene;
//!
//! let space = ProductSpace::genus_two_x_s1(2.0);
//! let scene = ProductScene::default_for(&space);
//! let gpu = GpuProductScene::pack(&space, &scene, 64, 36);
//! // The octagon's 8 sides, the bottom and the top.
//! assert_eq!(gpu.faces.len(), 10);
//! // The three balls lie inside the prism: no copy of the prism sees
//! // them through a face.
//! assert_eq!(gpu.balls.len(), 3);
//! ```

use bevy_manifold_core::geometry::product::{ProductPoint, ProductTangent};
use bevy_manifold_core::mesh::MeshData;
use bevy_manifold_core::space::product::ProductSpace;
use bevy_manifold_core::space::product_cells::{ProductCellTable, ProductCells, ProductElement};
use bevy_manifold_core::trace::product::{
    FOG_COLOR, ProductLight, ProductLighting, ProductMesh, ProductMeshImage, ProductScene, ProductTubes, ProductView,
    images, light_images, mesh_images, palette,
};
use bytemuck::{Pod, Zeroable};
use std::sync::Arc;

/// WGSL twin: `ProductParams` in `shaders/product.wgsl`.
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct GpuProductParams {
    /// The eye: its surface point (xyz) and height (w).
    pub eye: [f32; 4],
    /// Where the eye looks: surface part (xyz) and vertical speed (w).
    pub forward: [f32; 4],
    /// The eye's right.
    pub right: [f32; 4],
    /// The eye's up.
    pub up: [f32; 4],
    /// The fog's colour (rgb, 1).
    pub fog_color: [f32; 4],
    /// An off-centre frustum, `[half width, half height, centre x, centre
    /// y]` in slopes (`Frustum::half_extent_and_centre`); all 0 for the
    /// symmetric frustum of `tan_half_fov` and the image's aspect.
    pub frustum: [f32; 4],
    /// The prism's edges drawn as tubes: their colour (rgb) and radius
    /// (w; 0 for no edges).
    pub edges: [f32; 4],
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Most faces a ray crosses.
    pub max_crossings: u32,
    /// The polygon's sides (the faces before the bottom and the top).
    pub side_count: u32,
    /// The balls and their images.
    pub ball_count: u32,
    /// The surface's curvature, -1 (H2) or 1 (S2).
    pub curvature: f32,
    /// Half the prism's height.
    pub half_height: f32,
    /// How far rays go.
    pub max_distance: f32,
    /// `tan(fov_y / 2)`.
    pub tan_half_fov: f32,
    /// Fog density.
    pub fog: f32,
    /// The render pass: the viewport's left pixel column in the target.
    pub origin_x: u32,
    /// The render pass: the viewport's top pixel row in the target.
    pub origin_y: u32,
    /// Per-cell shading: 0 for none, else the mode of
    /// [`CellTint::words`](bevy_manifold_core::space::cells::CellTint::words) plus 1.
    pub tint_mode: u32,
    /// The tint's first word.
    pub tint_a: u32,
    /// The tint's second word.
    pub tint_b: u32,
    /// Cells in the table bound with the scene ([`GpuProductCells`]); 0
    /// for none (every cell's id is then `CellId::BEYOND_TABLE`).
    pub cell_count: u32,
    /// The eye's copy's steps up the line ([`ProductElement::steps`]).
    pub camera_steps: i32,
    /// -1 where the eye's copy turns the line over, else 1.
    pub camera_flip: i32,
    /// The light images ([`GpuProductLight`]); 0: the balls are lit from
    /// the eye.
    pub light_count: u32,
    /// 1 where the balls cast shadows.
    pub shadows: u32,
    /// The meshes and their images ([`GpuProductMesh`]).
    pub mesh_count: u32,
    /// Padding.
    pub pad_a: u32,
    /// Padding.
    pub pad_b: u32,
    /// Padding.
    pub pad_c: u32,
}

impl GpuProductParams {
    /// The eye and its frame set from `view`, as [`GpuProductScene::pack`]
    /// writes them, the rest kept: a view moved late, in the same copy of
    /// the prism (a headset's eye from its late-located pose).
    pub fn set_eye(&mut self, view: &ProductView) {
        let [forward, right, up] = view.frame;
        self.eye = point(view.eye);
        self.forward = tangent(forward);
        self.right = tangent(right);
        self.up = tangent(up);
    }
}

/// What `shaders/product.wgsl` is specialised on: the code a scene
/// needs, nothing more. Its shader defs: `PRODUCT_CELLS` where a table of
/// cells is bound (the copies' ids, for per-cell shading), `PRODUCT_LIGHTS`
/// where the scene has lights (else the balls are lit from the eye),
/// `PRODUCT_EDGES` where it draws the prism's edges (their tubes are
/// looked for on every segment and shadow ray: without them the shader
/// carries none of that code), `PRODUCT_MESHES` where it has meshes.
///
/// ```
/// use bevy_manifold_core::space::product::ProductSpace;
/// use bevy_manifold_core::trace::product::ProductScene;
/// use bevy_manifold_gpu::product::{GpuProductScene, ProductShaderDefs};
/// let space = ProductSpace::s2_x_s1(2.0);
/// let lit = GpuProductScene::pack(&space, &ProductScene::lit_for(&space), 8, 8);
/// assert_eq!(ProductShaderDefs::of(&lit.params).names(), ["PRODUCT_LIGHTS"]);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct ProductShaderDefs {
    /// A table of cells is bound: each hit is named by its copy's id.
    pub cells: bool,
    /// The scene has lights.
    pub lights: bool,
    /// The scene draws the prism's edges.
    pub edges: bool,
    /// The scene has meshes.
    pub meshes: bool,
}

impl ProductShaderDefs {
    /// What the packed scene `params` needs.
    #[must_use]
    pub fn of(params: &GpuProductParams) -> Self {
        Self {
            cells: params.cell_count > 0,
            lights: params.light_count > 0,
            edges: params.edges[3] > 0.0,
            meshes: params.mesh_count > 0,
        }
    }

    /// The shader defs.
    #[must_use]
    pub fn names(self) -> Vec<&'static str> {
        [
            (self.cells, "PRODUCT_CELLS"),
            (self.lights, "PRODUCT_LIGHTS"),
            (self.edges, "PRODUCT_EDGES"),
            (self.meshes, "PRODUCT_MESHES"),
        ]
        .into_iter()
        .filter_map(|(on, name)| on.then_some(name))
        .collect()
    }

    /// Every specialisation.
    #[must_use]
    pub fn all() -> [Self; 16] {
        std::array::from_fn(|i| Self {
            cells: i & 8 != 0,
            lights: i & 4 != 0,
            edges: i & 2 != 0,
            meshes: i & 1 != 0,
        })
    }

    /// Its place in [`ProductShaderDefs::all`].
    #[must_use]
    pub fn index(self) -> usize {
        8 * usize::from(self.cells)
            + 4 * usize::from(self.lights)
            + 2 * usize::from(self.edges)
            + usize::from(self.meshes)
    }
}

/// WGSL twin: `ProductFace` in `shaders/product.wgsl`. One face of the
/// prism and its gluing.
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct GpuProductFace {
    /// A side's unit normal covector (xyz); zero for the bottom and top.
    pub normal: [f32; 4],
    /// A side's corner with the next side (xyz; [`ProductSpace::vertices`]),
    /// the vertical edge over it and the end of the side's edges; zero for
    /// the bottom and top.
    pub corner: [f32; 4],
    /// The gluing's surface part, by columns (each padded to 4, as a WGSL
    /// `mat3x3<f32>`).
    pub surface: [[f32; 4]; 3],
    /// The gluing's flip of the line (1 or -1).
    pub flip: f32,
    /// The gluing's shift of the line.
    pub shift: f32,
    /// The face a ray comes in through after this one.
    pub partner: u32,
    /// The steps up the line a crossing of this face adds (its partner's
    /// gluing's shift over the prism's height; the exact cells'
    /// [`ProductCells::cross`]).
    pub cross_steps: i32,
}

/// WGSL twin: `ProductBall` in `shaders/product.wgsl`. A ball or one of
/// its images through a face.
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct GpuProductBall {
    /// Its centre: surface point (xyz) and height (w).
    pub center: [f32; 4],
    /// Its colour (linear rgb, 1).
    pub color: [f32; 4],
    /// Its radius.
    pub radius: f32,
    /// Its object id.
    pub id: u32,
    /// `cosh` (H2) or `cos` (S2) of the radius with the shader's reach
    /// slack: the surface distance's bound in `reach`, made once.
    pub reach_trig: f32,
    /// Padding.
    pub pad: u32,
}

/// WGSL twin: `ProductMesh` in `shaders/product.wgsl`. A mesh or one of
/// its images through the faces, the twin of the core's
/// [`ProductMeshImage`].
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct GpuProductMesh {
    /// The surface part of the isometry taking the prism to the mesh's
    /// chart, by columns (each padded to 4).
    pub to_chart: [[f32; 4]; 3],
    /// The surface part of its inverse (the placement), for the normals.
    pub placement: [[f32; 4]; 3],
    /// The chart's origin in the prism: surface point (xyz), height (w).
    pub center: [f32; 4],
    /// Its colour (linear rgb, 1).
    pub color: [f32; 4],
    /// The isometry's flip of the line (1 or -1).
    pub to_flip: f32,
    /// The isometry's shift of the line.
    pub to_shift: f32,
    /// How far across the surface the mesh reaches from its centre
    /// ([`ProductMesh::extent`](bevy_manifold_core::trace::product::ProductMesh::extent)),
    /// with the shader's slack.
    pub across: f32,
    /// `cosh` (H2) or `cos` (S2) of `across`.
    pub across_trig: f32,
    /// How far up and down it reaches, with the shader's slack.
    pub tall: f32,
    /// Its object id.
    pub id: u32,
    /// Its first node in the mesh data (in `vec4`s).
    pub nodes: u32,
    /// Its first triangle in the mesh data (in `vec4`s; its nodes end
    /// there).
    pub triangles: u32,
}

/// WGSL twin: `ProductLight` in `shaders/product.wgsl`. One image of a
/// light, the twin of the core's
/// [`ProductLightImage`](bevy_manifold_core::trace::product::ProductLightImage).
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct GpuProductLight {
    /// Where it is: surface point (xyz) and height (w).
    pub position: [f32; 4],
    /// Its colour (linear rgb) and power (w).
    pub color: [f32; 4],
    /// `1 / range^2`; 0: no cut-off.
    pub inv_range_sq: f32,
    /// The least area its power spreads over.
    pub min_area: f32,
    /// A spot's `cos` of its inner angle.
    pub spot_inner: f32,
    /// A spot's `cos` of its outer angle.
    pub spot_outer: f32,
    /// A spot's unit axis at the image (surface xyz, height w); all 0
    /// for a point light.
    pub spot_axis: [f32; 4],
}

/// WGSL twin: `ProductPixel` in `shaders/product.wgsl`. What one pixel
/// sees, the twin of the core's
/// [`ProductPixel`](bevy_manifold_core::trace::product::ProductPixel).
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct GpuProductPixel {
    /// Linear rgb, and the distance to the hit (w; -1 for none).
    pub color: [f32; 4],
    /// The ball's id, 0 for none.
    pub object: u32,
    /// The faces crossed on the way.
    pub crossings: u32,
    /// The copy the ball was seen in: its `CellId`'s low and high words.
    pub cell: [u32; 2],
}

/// A product scene as the GPU reads it.
#[derive(Clone, Debug, PartialEq)]
pub struct GpuProductScene {
    /// The view and the space's sizes.
    pub params: GpuProductParams,
    /// The faces: the sides, then the bottom and the top.
    pub faces: Vec<GpuProductFace>,
    /// Each ball, then its images that reach into the prism (the CPU
    /// tracer's [`images`]).
    pub balls: Vec<GpuProductBall>,
    /// The light images ([`GpuProductScene::pack_lights`]).
    pub lights: Vec<GpuProductLight>,
    /// Each mesh, then its images that reach into the prism (the CPU
    /// tracer's [`mesh_images`]).
    pub meshes: Vec<GpuProductMesh>,
    /// The meshes' BVHs and triangles, each mesh's once
    /// ([`ProductMeshWords`]), shared while the meshes stay.
    pub mesh_data: Arc<ProductMeshWords>,
}

/// The BVHs and triangles of a scene's meshes as `shaders/product.wgsl`
/// reads them (binding 7), each mesh's once ([`pack_mesh_data`]), with
/// the meshes they were made from: made again only when the meshes
/// change, not as the eye or the meshes' placements move
/// ([`ProductMeshWords::get`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ProductMeshWords {
    /// The meshes, each once, in the order first met.
    pub meshes: Vec<Arc<MeshData>>,
    /// Where each one's nodes and triangles start.
    pub starts: Vec<(u32, u32)>,
    /// The words.
    pub words: Vec<[u32; 4]>,
}

impl ProductMeshWords {
    /// The words of `meshes`' meshes.
    #[must_use]
    pub fn of(meshes: &[ProductMesh]) -> Self {
        let mut out = Self::default();
        for mesh in meshes {
            if !out.meshes.iter().any(|m| Arc::ptr_eq(m, &mesh.mesh)) {
                let start = pack_mesh_data(&mesh.mesh, &mut out.words);
                out.meshes.push(mesh.mesh.clone());
                out.starts.push(start);
            }
        }
        out
    }

    /// Where `mesh`'s nodes and triangles start, if it is here.
    #[must_use]
    pub fn start(&self, mesh: &Arc<MeshData>) -> Option<(u32, u32)> {
        self.meshes
            .iter()
            .position(|m| Arc::ptr_eq(m, mesh))
            .map(|i| self.starts[i])
    }

    /// `kept` where it was made from the same meshes as `meshes` (the same
    /// shared data, in the same order), else the words made again.
    #[must_use]
    pub fn get(kept: Option<&Arc<Self>>, meshes: &[ProductMesh]) -> Arc<Self> {
        let mut unique: Vec<&Arc<MeshData>> = Vec::new();
        for mesh in meshes {
            if !unique.iter().any(|m| Arc::ptr_eq(m, &mesh.mesh)) {
                unique.push(&mesh.mesh);
            }
        }
        match kept {
            Some(k)
                if k.meshes.len() == unique.len() && k.meshes.iter().zip(&unique).all(|(a, b)| Arc::ptr_eq(a, b)) =>
            {
                k.clone()
            }
            _ => Arc::new(Self::of(meshes)),
        }
    }
}

/// How much farther than its radius the shader looks for a ball (f32
/// rounding). WGSL twin: `REACH_SLACK` in `shaders/product.wgsl`.
pub const REACH_SLACK: f64 = 1e-3;

/// A storage array's bytes as they are bound: an empty array still binds
/// a buffer, of one zeroed element (`T`'s size, at least 16 bytes).
/// The headless runner and the Bevy pass bind the faces and balls so.
#[must_use]
pub fn storage_bytes<T: Pod>(items: &[T]) -> std::borrow::Cow<'_, [u8]> {
    if items.is_empty() {
        std::borrow::Cow::Owned(vec![0; std::mem::size_of::<T>().max(16)])
    } else {
        std::borrow::Cow::Borrowed(bytemuck::cast_slice(items))
    }
}

fn point(p: ProductPoint) -> [f32; 4] {
    [
        p.surface.x as f32,
        p.surface.y as f32,
        p.surface.z as f32,
        p.height as f32,
    ]
}

fn tangent(v: ProductTangent) -> [f32; 4] {
    [
        v.surface.x as f32,
        v.surface.y as f32,
        v.surface.z as f32,
        v.height as f32,
    ]
}

impl GpuProductScene {
    /// `scene` in `space`, for a `width x height` image.
    #[must_use]
    pub fn pack(space: &ProductSpace, scene: &ProductScene, width: u32, height: u32) -> Self {
        Self::pack_lit(space, scene, Self::pack_lights(space, scene), (width, height))
    }

    /// [`GpuProductScene::pack_lit`] with the meshes' words already made
    /// ([`ProductMeshWords::get`]): a moving eye, or moving meshes,
    /// share them.
    #[must_use]
    pub fn pack_with(
        space: &ProductSpace,
        scene: &ProductScene,
        (lights, words): (Vec<GpuProductLight>, Arc<ProductMeshWords>),
        (width, height): (u32, u32),
    ) -> Self {
        let view = &scene.view;
        let [forward, right, up] = view.frame;
        let balls: Vec<GpuProductBall> = images(space, &scene.balls)
            .iter()
            .map(|b| {
                let [r, g, bl] = palette(b.id);
                GpuProductBall {
                    center: point(b.center),
                    color: [r, g, bl, 1.0],
                    radius: b.radius as f32,
                    id: b.id,
                    reach_trig: space.geometry.trig(b.radius + REACH_SLACK).0 as f32,
                    pad: 0,
                }
            })
            .collect();
        let meshes = pack_meshes(space, &mesh_images(space, &scene.meshes), &words);
        let corners = space.vertices();
        let tube_radius = ProductTubes::radius_of(space, scene.edges);
        let faces = (0..space.face_count())
            .map(|f| {
                let m = space.gluings[f].isometry();
                let col = |c: glam::DVec3| [c.x as f32, c.y as f32, c.z as f32, 0.0];
                let n = space.sides.get(f).copied().unwrap_or(glam::DVec3::ZERO);
                let corner = corners.get(f).copied().unwrap_or(glam::DVec3::ZERO);
                GpuProductFace {
                    normal: col(n),
                    corner: col(corner),
                    surface: [col(m.surface.x_axis), col(m.surface.y_axis), col(m.surface.z_axis)],
                    flip: m.flip as f32,
                    shift: m.shift as f32,
                    partner: space.partner(f) as u32,
                    cross_steps: cross_steps(space, f),
                }
            })
            .collect();
        let [fr, fg, fb] = FOG_COLOR;
        let [tint_mode, tint_a, tint_b] = view.tint.map_or([0; 3], |t| {
            let [mode, a, b] = t.words();
            [mode + 1, a, b]
        });
        let camera = view.cell.unwrap_or(ProductElement::IDENTITY);
        Self {
            params: GpuProductParams {
                eye: point(view.eye),
                forward: tangent(forward),
                right: tangent(right),
                up: tangent(up),
                fog_color: [fr, fg, fb, 1.0],
                frustum: view
                    .frustum
                    .map_or([0.0; 4], |f| f.half_extent_and_centre().map(|v| v as f32)),
                edges: match (scene.edges, tube_radius) {
                    (Some(e), Some(r)) => [e.color[0], e.color[1], e.color[2], r as f32],
                    _ => [0.0; 4],
                },
                width,
                height,
                max_crossings: view.max_crossings.min(u32::MAX as usize) as u32,
                side_count: space.sides.len() as u32,
                ball_count: balls.len() as u32,
                curvature: space.geometry.curvature() as f32,
                half_height: (space.height / 2.0) as f32,
                max_distance: view.max_distance as f32,
                tan_half_fov: (view.fov_y_degrees.to_radians() / 2.0).tan() as f32,
                fog: view.fog as f32,
                origin_x: 0,
                origin_y: 0,
                tint_mode,
                tint_a,
                tint_b,
                cell_count: 0,
                camera_steps: camera.steps() as i32,
                camera_flip: if camera.flips() { -1 } else { 1 },
                light_count: lights.len() as u32,
                shadows: u32::from(scene.lighting.shadows),
                mesh_count: meshes.len() as u32,
                pad_a: 0,
                pad_b: 0,
                pad_c: 0,
            },
            faces,
            balls,
            lights,
            meshes,
            mesh_data: words,
        }
    }

    /// The images of `scene`'s lights as the GPU reads them (the core's
    /// [`light_images`]): worked out once while the lights stay, as the
    /// Bevy pass does.
    #[must_use]
    pub fn pack_lights(space: &ProductSpace, scene: &ProductScene) -> Vec<GpuProductLight> {
        light_images(space, &scene.lights, scene.lighting)
            .iter()
            .map(|l| GpuProductLight {
                position: point(l.position),
                color: [l.color[0], l.color[1], l.color[2], l.intensity as f32],
                inv_range_sq: l.inv_range_sq as f32,
                min_area: l.min_area as f32,
                spot_inner: l.spot.map_or(0.0, |s| s.1 as f32),
                spot_outer: l.spot.map_or(0.0, |s| s.2 as f32),
                spot_axis: l.spot.map_or([0.0; 4], |s| tangent(s.0)),
            })
            .collect()
    }

    /// `scene` in `space` lit by `lights` (its lights' images, packed by
    /// [`GpuProductScene::pack_lights`]), for a `width x height` image.
    #[must_use]
    pub fn pack_lit(
        space: &ProductSpace,
        scene: &ProductScene,
        lights: Vec<GpuProductLight>,
        (width, height): (u32, u32),
    ) -> Self {
        Self::pack_with(
            space,
            scene,
            (lights, Arc::new(ProductMeshWords::of(&scene.meshes))),
            (width, height),
        )
    }
}

/// How much farther the shader looks for a mesh than it reaches (f32
/// rounding). WGSL twin: `mesh_window`'s `across` and `tall` are packed
/// with it.
pub const MESH_SLACK: f64 = 1e-4;

/// The mesh images as the GPU reads them, their meshes in `words`
/// (an image whose mesh is not there is left out).
#[must_use]
pub fn pack_meshes(space: &ProductSpace, images: &[ProductMeshImage], words: &ProductMeshWords) -> Vec<GpuProductMesh> {
    let g = space.geometry;
    let col = |c: glam::DVec3| [c.x as f32, c.y as f32, c.z as f32, 0.0];
    images
        .iter()
        .filter_map(|image| {
            let (nodes, triangles) = words.start(&image.mesh)?;
            let [r, gr, b] = palette(image.id);
            let (across, tall) = (image.extent.0 + MESH_SLACK, image.extent.1 + MESH_SLACK);
            Some(GpuProductMesh {
                to_chart: [
                    col(image.to_chart.surface.x_axis),
                    col(image.to_chart.surface.y_axis),
                    col(image.to_chart.surface.z_axis),
                ],
                placement: [
                    col(image.placement.surface.x_axis),
                    col(image.placement.surface.y_axis),
                    col(image.placement.surface.z_axis),
                ],
                center: point(image.center),
                color: [r, gr, b, 1.0],
                to_flip: image.to_chart.flip as f32,
                to_shift: image.to_chart.shift as f32,
                across: across as f32,
                across_trig: g.trig(across).0 as f32,
                tall: tall as f32,
                id: image.id,
                nodes,
                triangles,
            })
        })
        .collect()
}

/// `mesh`'s BVH and triangles appended to `data` as
/// `shaders/product.wgsl` reads them, in `vec4<u32>`s (floats by their
/// bits): per node two (its box's min and its leaf's triangle count; its
/// max and its leaf's first triangle or, for an inner node, the node past
/// its subtree), then per triangle six (its corners, then their
/// normals).
/// Returns where its nodes and its triangles start.
pub fn pack_mesh_data(mesh: &MeshData, data: &mut Vec<[u32; 4]>) -> (u32, u32) {
    let nodes = data.len() as u32;
    for (node, skip) in mesh.nodes.iter().zip(&mesh.skip) {
        let link = if node.count > 0 { node.first } else { *skip };
        let [x, y, z] = node.min.map(f32::to_bits);
        data.push([x, y, z, node.count]);
        let [x, y, z] = node.max.map(f32::to_bits);
        data.push([x, y, z, link]);
    }
    let triangles = data.len() as u32;
    let m = &mesh.mesh;
    let smooth = m.normals.len() == m.positions.len();
    for tri in &m.triangles {
        let [a, b, c] = tri.map(|i| m.positions[i as usize]);
        let face = {
            let (e1, e2) = (
                glam::Vec3::from(b) - glam::Vec3::from(a),
                glam::Vec3::from(c) - glam::Vec3::from(a),
            );
            e1.cross(e2).to_array()
        };
        let word = |p: [f32; 3]| {
            let [x, y, z] = p.map(f32::to_bits);
            [x, y, z, 0]
        };
        for p in [a, b, c] {
            data.push(word(p));
        }
        for i in tri {
            data.push(word(if smooth { m.normals[*i as usize] } else { face }));
        }
    }
    (nodes, triangles)
}

/// A scene's light images packed ([`GpuProductScene::pack_lights`]),
/// kept with what they were made from, and made again only when the
/// space, the lights or the lighting change: a moving eye, or a tour's
/// frames, share them. The headless runner keeps one; the Bevy pass one
/// per camera.
#[derive(Clone, Debug, Default)]
pub struct PackedLights(Option<(ProductSpace, Vec<ProductLight>, ProductLighting, Vec<GpuProductLight>)>);

impl PackedLights {
    /// `scene`'s light images in `space`, packed: the kept ones where
    /// they were made from the same space, lights and lighting.
    pub fn get(&mut self, space: &ProductSpace, scene: &ProductScene) -> Vec<GpuProductLight> {
        let same = |(s, l, g, _): &(ProductSpace, Vec<ProductLight>, ProductLighting, Vec<GpuProductLight>)| {
            s == space && *l == scene.lights && *g == scene.lighting
        };
        match &self.0 {
            Some(kept) if same(kept) => kept.3.clone(),
            _ => {
                let packed = GpuProductScene::pack_lights(space, scene);
                self.0 = Some((space.clone(), scene.lights.clone(), scene.lighting, packed.clone()));
                packed
            }
        }
    }
}

/// The steps up the line a crossing of `face` adds: its partner's gluing's
/// shift in prism heights (0 where it is not a whole number of them, a
/// space without exact cells).
fn cross_steps(space: &ProductSpace, face: usize) -> i32 {
    let shift = space.gluings[space.partner(face)].isometry().shift / space.height;
    if (shift - shift.round()).abs() < 1e-9 && shift.abs() < 1e6 {
        shift.round() as i32
    } else {
        0
    }
}

/// The table of cells around the eye's copy as `shaders/product.wgsl`
/// reads it (binding 4): the [`ProductCellTable`]'s neighbours, then each
/// cell's tile seen from the eye ([`ProductCellTable::tiles_around`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GpuProductCells {
    /// The words: `count * faces` neighbours, then `2 * count` tile words.
    pub words: Vec<u32>,
    /// Cells in the table; 0 for none.
    pub count: u32,
}

impl GpuProductCells {
    /// No table: every copy's id is `CellId::BEYOND_TABLE`.
    #[must_use]
    pub fn none() -> Self {
        Self {
            words: Vec::new(),
            count: 0,
        }
    }

    /// `table` seen from the eye's copy `eye` (none where the eye's copy
    /// is unknown).
    #[must_use]
    pub fn pack(cells: &ProductCells, table: &ProductCellTable, eye: Option<&ProductElement>) -> Self {
        let Some(eye) = eye else { return Self::none() };
        let mut words = table.neighbours.clone();
        words.extend(table.tiles_around(cells, eye).into_iter().flatten());
        Self {
            words,
            count: table.len() as u32,
        }
    }
}
