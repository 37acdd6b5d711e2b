//! Turning a space and a scene into flat arrays in the tracer's precision,
//! the CPU side of what the GPU pass uploads: face planes, pairings,
//! balls with their ghost copies, edge tubes, lights.

use super::ball_tree::{BallTree, ball_box};
use super::face_groups::{
    FaceGroups, cull_distance, edge_keys, edge_masks, face_mask, joint_carriers, near_reach, near_scale,
};
use super::instance_tree::{InstanceTree, trees_over};
use super::scene::Scene;
use super::step::{Segment, radius_param};
use crate::geometry::{Geometry, Real, isometry};
use crate::material::Pbr;
use crate::mesh::{MeshData, Texture};
use crate::space::Space;
use crate::space::cell_table::CentredTable;
use crate::space::cells::CellScheme;
use crate::space::element::CellElement;
use glam::{DMat4, DVec4};
use std::sync::{Arc, OnceLock};

/// Object id of the domain's edges (tubes and their vertex joints):
/// above every ball's and mesh's (numbered from 1, as many as a scene
/// has), below [`crate::space::rule::WALL_OBJECT`]. WGSL twin: `EDGE_ID`
/// in `shaders/bindings.wgsl`.
pub const EDGE_ID: u32 = u32::MAX - 2;

/// A ball in the tracer's precision.
#[derive(Clone, Copy, Debug)]
pub struct FlatBall<R: Real> {
    /// Centre (normalised).
    pub center: R::V4,
    /// `cosh r`, `cos r` or `r^2`.
    pub k: R,
    /// Albedo.
    pub color: [f32; 3],
    /// [`super::Ball::glow`] (0 for a vertex joint).
    pub glow: f32,
    /// [`super::Ball::pbr`] (`None` for a vertex joint).
    pub pbr: Option<Pbr>,
    /// Object id (1-based scene index, or [`EDGE_ID`]).
    pub id: u32,
    /// The faces (bits 0 to 31) whose planes every point of the ball
    /// inside the domain is within [`FlatScene::near_reach`] of: a
    /// segment can hit it only if it comes near all of them
    /// ([`super::step::near_faces`], [`super::step::may_hit`]).
    pub face_mask: u32,
}

/// A tube along one edge of the domain.
#[derive(Clone, Copy, Debug)]
pub struct FlatTube<R: Real> {
    /// The edge's geodesic segment.
    pub segment: Segment<R>,
    /// Albedo (one colour per edge cycle).
    pub color: [f32; 3],
    /// The faces it lies near, as [`FlatBall::face_mask`]: the two whose
    /// planes hold its edge.
    pub face_mask: u32,
    /// Its edge's two faces as bits (`f % 32`, one bit where two faces
    /// fold onto it): what the tubes are grouped and looked up by
    /// ([`FaceGroups::edges`]), each bits once. Where an earlier tube has
    /// the same bits (a domain of more than 32 faces folds two edges onto
    /// them), one of its two bits alone, if free; 0 where none is free or
    /// the bits are not all in `face_mask` (only in a domain of more than
    /// 32 faces): the tube is then walked on every segment that comes near
    /// all the faces of its mask.
    pub edge: u32,
    /// The vertex joint tested right after this tube (an index into
    /// [`FlatScene::balls`], after every face group): one at an end of
    /// its edge whose face mask holds the tube's, so that a segment near
    /// all of the joint's faces walks this tube
    /// ([`super::each_candidate`]). Each joint rides on at most one
    /// tube, and a tube carries at most one (a matching of joints to
    /// tubes); the joints no tube carries stay in the balls' face groups.
    pub joint: Option<usize>,
}

/// A light in the tracer's precision.
#[derive(Clone, Copy, Debug)]
pub struct FlatLight<R: Real> {
    /// Position (normalised).
    pub position: R::V4,
    /// Power.
    pub intensity: R,
    /// Colour.
    pub color: [f32; 3],
    /// `1 / range^2` of its smooth cut-off; 0: none.
    pub inv_range_sq: R,
    /// The least area its irradiance is divided by: the area of its
    /// sphere, at least [`super::light_images::MIN_AREA`].
    pub min_area: R,
    /// Its radius: a light of finite size, whose shadows are soft
    /// ([`super::shadow::aim_at_light`]); 0: a point.
    pub radius: R,
    /// A spot light's axis at this image (a unit tangent), else zero.
    pub spot_dir: R::V4,
    /// The spot's fall-off `clamp(cos a * scale + offset, 0, 1)^2` at the
    /// angle `a` from its axis: `1 / (cos inner - cos outer)`, and
    /// `-cos outer` times that; 0 and 1 for a light in every direction.
    pub spot_scale: R,
    /// See `spot_scale`.
    pub spot_offset: R,
}

/// The textures of a mesh instance's material, as indices into
/// [`FlatScene::textures`] (each texture once there).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct InstanceTextures {
    /// Base colour (sRGB, alpha for the mask).
    pub base: Option<usize>,
    /// Metallic (blue) and roughness (green), linear.
    pub metallic_roughness: Option<usize>,
    /// Emission (sRGB).
    pub emissive: Option<usize>,
    /// Tangent-space normal map, linear.
    pub normal: Option<usize>,
}

/// One placement of a mesh (or a ghost of one, carried through a face),
/// in the tracer's precision.
#[derive(Clone, Copy, Debug)]
pub struct FlatInstance<R: Real> {
    /// From the domain's chart to the mesh's own coordinates (the inverse
    /// of the placement, then of the scale).
    pub to_local: R::M4,
    /// Centre of the bounding ball (normalised).
    pub center: R::V4,
    /// `k` of the bounding ball (as for balls).
    pub k: R,
    /// Index into [`FlatScene::meshes`].
    pub mesh: usize,
    /// Base colour.
    pub color: [f32; 3],
    /// Its material's textures, as indices into [`FlatScene::textures`].
    pub textures: InstanceTextures,
    /// [`crate::material::MeshMaterial::pbr`].
    pub pbr: Option<Pbr>,
    /// Emitted radiance (linear RGB).
    pub emissive: [f32; 3],
    /// The alpha mask: the cutoff and the base alpha factor.
    pub alpha_mask: Option<(f32, f32)>,
    /// Object id.
    pub id: u32,
    /// For a copy of a mesh attached to the camera: the point `g o` of the
    /// walk's cell element `g` from which this copy is the camera's own
    /// body (the copy `h` of the body seen from cell `g` is the home body
    /// when `g h` is the camera's cell). The walk never hits it from there,
    /// at any level. `None` for other meshes.
    pub home: Option<R::V4>,
    /// The faces its bounding ball lies near, as [`FlatBall::face_mask`].
    pub face_mask: u32,
}

/// The per-face arrays a walk through the manifold reads, in precision `R`.
#[derive(Clone, Debug)]
pub struct FaceTables<R: Real> {
    /// The geometry.
    pub geometry: Geometry,
    /// Face planes.
    pub planes: Vec<R::V4>,
    /// `T_i` per face.
    pub pairings: Vec<R::M4>,
    /// Partner per face (the face a transported ray enters through).
    pub partners: Vec<usize>,
    /// What the ray's group element is right-multiplied by on crossing face
    /// `i`: `T_i^-1`.
    pub crossings: Vec<R::M4>,
    /// The factor of [`super::step::near_faces`]'s test: a point `p` of
    /// the domain within distance `r` of a face's plane `n` has
    /// `|n . p| / p_w <= near_scale * s(r)` (`s` is `sinh`, `sin` or the
    /// identity, [`near_reach`]; the planes are normalised, so `n . p` of
    /// a normalised point is `s` of its signed distance). 1 in E3 and H3
    /// (`p_w` is 1, or `cosh` of the distance from the origin); in S3 the
    /// inverse of the least `p_w` of the domain, at a vertex; infinite (no
    /// culling) where the domain reaches `w <= 0`.
    pub near_scale: R,
    /// How much longer a path may be in the chart (`x/w`) than in the
    /// space, inside the domain: 1 in E3 and H3 (the projective chart
    /// only shortens), `near_scale^2` in S3 (the gnomonic chart stretches
    /// by at most `1 / w^2`). Cone tracing pads the ball tree's boxes by
    /// a footprint times this.
    pub chart_stretch: R,
}

impl<R: Real> FaceTables<R> {
    /// The tables of `space`.
    #[must_use]
    pub fn new(space: &Space) -> Self {
        let faces = space.faces();
        FaceTables {
            geometry: space.geometry(),
            planes: faces.iter().map(|f| R::v4_of(f.plane)).collect(),
            pairings: faces.iter().map(|f| R::m4_of(f.pairing)).collect(),
            partners: faces.iter().map(|f| f.partner).collect(),
            crossings: (0..faces.len()).map(|i| R::m4_of(space.crossing(i))).collect(),
            near_scale: R::of(near_scale(space)),
            chart_stretch: R::of(match space.geometry() {
                Geometry::Spherical => near_scale(space).powi(2),
                _ => 1.0,
            }),
        }
    }
}

/// Everything the per-pixel loop reads.
#[derive(Clone, Debug)]
pub struct FlatScene<R: Real> {
    /// The faces' planes and pairings (and the geometry).
    pub faces: FaceTables<R>,
    /// Balls, ghosts included, and the vertex joints of the edge tubes,
    /// sorted into [`FaceGroups`] (unmasked first); after the last group,
    /// the joints that ride on a tube ([`FlatTube::joint`]), which only
    /// their tube's walk tests.
    pub balls: Vec<FlatBall<R>>,
    /// Edge tubes, sorted into [`FaceGroups`] by their edge bits
    /// ([`FlatTube::edge`]).
    pub tubes: Vec<FlatTube<R>>,
    /// `k` of the edge tubes.
    pub tube_k: R,
    /// `s(r)` ([`near_reach`]) of the distance `r` within which objects
    /// carry face masks ([`FlatBall::face_mask`]): the edge radius (a hair
    /// more), else twice the smallest ball or mesh radius.
    pub near_reach: R,
    /// The distance `r` itself (infinite when no object is masked): cone
    /// tracing grows it by a segment's footprint
    /// ([`super::footprint::Inflation`]) before taking `s` of it.
    pub near_distance: R,
    /// The mean area of the domain's shadow on a plane, a quarter of its
    /// surface area (Cauchy): a pixel's cone whose cross-section is wider
    /// holds that many copies of the domain side by side, of which its
    /// axis walks one ([`super::footprint::side_by_side`]).
    pub cell_shadow: R,
    /// The widest a pixel's cone grows ([`super::footprint::FOOTPRINT_CAP`]
    /// of the inradius): beyond, far copies are sampled by a cone
    /// narrower than the pixel.
    pub footprint_cap: R,
    /// Where each face's group starts in `balls`, `tubes` and `instances`
    /// (sorted by [`FaceGroups`]): the lists `nearest_object` walks.
    pub groups: FaceGroups,
    /// A hierarchy over the chart boxes ([`super::ball_box`]) of the
    /// balls with no face mask, `balls[..groups.balls[0]]`, which are in
    /// its leaves' order: a segment tests only the balls of the leaves
    /// its chart image meets ([`super::tree_leaves`]). Empty when there
    /// are fewer than [`MIN_BALL_TREE`] such balls: then a segment tests
    /// every one of them.
    pub ball_tree: BallTree,
    /// The lights' images that light the domain
    /// ([`super::light_images()`]): each light once when
    /// `lighting.images` is 0.
    pub lights: Vec<FlatLight<R>>,
    /// How the lights reach what they light.
    pub lighting: super::scene::Lighting,
    /// Mesh instances, ghosts included, sorted into [`FaceGroups`], and
    /// within each group in its tree's leaves' order.
    pub instances: Vec<FlatInstance<R>>,
    /// Per face group of `instances` (0: those with no face mask; `f + 1`:
    /// face `f`'s), the hierarchy over their bounding balls' chart boxes
    /// ([`super::InstanceTree`]): a segment tests only the instances of
    /// the leaves its chart image meets ([`super::tree_instances`]).
    /// Empty for a group of fewer than [`super::MIN_INSTANCE_TREE`].
    pub instance_trees: Vec<InstanceTree>,
    /// The meshes the instances show, each once.
    pub meshes: Vec<Arc<MeshData>>,
    /// The textures the instances use, each once.
    pub textures: Vec<Arc<Texture>>,
    /// Fog density and colour.
    pub fog: Option<(R, [f32; 3])>,
    /// The camera, wrapped into the domain.
    pub camera: R::M4,
    /// The cell the camera is in (group element, f64).
    pub camera_cell: DMat4,
    /// The same cell as exactly as the space names it: where the tracer's
    /// exact ids start ([`FlatScene::in_cell`] to place the camera far).
    pub camera_element: CellElement,
    /// The table of cells around `camera_element`, made on the first ask
    /// ([`FlatScene::centred_table`]).
    centred_table: OnceLock<Arc<CentredTable>>,
    /// `tan(fov_y / 2)`.
    pub tan_half_fov: R,
    /// An off-centre frustum ([`crate::trace::Frustum::half_extent_and_centre`]),
    /// in place of `tan_half_fov` and the image's aspect.
    pub frustum: Option<[R; 4]>,
}

/// Edge-cycle colours: edges identified by the pairings share a colour.
const PALETTE: [[f32; 3]; 10] = [
    [0.90, 0.20, 0.20],
    [0.20, 0.75, 0.25],
    [0.25, 0.40, 0.95],
    [0.95, 0.85, 0.20],
    [0.80, 0.30, 0.85],
    [0.20, 0.85, 0.85],
    [0.95, 0.55, 0.15],
    [0.55, 0.95, 0.35],
    [0.60, 0.45, 0.95],
    [0.95, 0.45, 0.65],
];

/// Fewest balls with no face mask for which [`FlatScene::ball_tree`] is
/// built (into [`super::leaf_count`] leaves, 4 of them at 9 balls).
/// Below it a segment tests each of them. Not remeasured since the leaves
/// are tested flat; when the tree was walked node by node, a tree of 12
/// balls cost less than testing each: on lavapipe
/// (320x180, 8 levels, over the one-ball frame, two runs each;
/// docs/benchmarks/history.md, "MIN_BALL_TREE after the two-loop walk") 12 balls took
/// 1.35-1.48x in the torus with a tree and 1.79-2.18x without,
/// Seifert-Weber 1.45-1.47x and 1.36-1.68x, Poincare 1.38-1.59x and
/// 1.37-1.64x. A tree of one leaf (8 balls), when it was the first scene
/// its pipeline traced, left the frame 2-3x slower (lavapipe specialised
/// on that scene's uniforms; `bench balls`, 8 balls: 31.5-46.8 ms).
/// Scenes with fewer balls do not compile the tree's test at all
/// (`BALL_TREE` in `bevy_manifold_gpu`).
pub const MIN_BALL_TREE: usize = 9;

/// Most copies of one object kept as ghosts (a huge ball in a small
/// domain would otherwise ask for thousands).
pub const MAX_GHOSTS: usize = 256;

/// A ball's centre `c` (normalised) in precision `R`. In H3 its w is made
/// from x, y and z in `R` (`sqrt(1 + (x^2 + y^2 + z^2))`, the point on the
/// hyperboloid), as the GPU's ball test makes it in place of reading w
/// (one word fewer gathered a ball), so both test the same point; in E3
/// and S3 it is `c` as it is. WGSL twin: `ball_center` in
/// `shaders/nearest.wgsl`.
#[must_use]
pub fn ball_center<R: Real>(g: Geometry, c: DVec4) -> R::V4 {
    if g != Geometry::Hyperbolic {
        return R::v4_of(c);
    }
    let (x, y, z) = (R::of(c.x), R::of(c.y), R::of(c.z));
    R::v4(x, y, z, (R::of(1.0) + (x * x + y * y + z * z)).sqrt())
}

impl<R: Real> FlatScene<R> {
    /// Prepares `scene` in `space` for tracing in precision `R`.
    #[must_use]
    pub fn new(space: &Space, scene: &Scene) -> Self {
        let g = space.geometry();
        let reach = cull_distance(g, scene);
        let mut balls = Vec::new();
        for (i, b) in scene.balls.iter().enumerate() {
            let k = R::of(radius_param(g, b.radius));
            for center in ghost_centres(space, b.center, b.radius) {
                balls.push(FlatBall {
                    center: ball_center::<R>(g, center),
                    k,
                    color: b.color,
                    glow: b.glow,
                    pbr: b.pbr,
                    id: i as u32 + 1,
                    face_mask: face_mask(space, &[center], b.radius, reach),
                });
            }
        }
        let mut tubes = Vec::new();
        // The vertex joints that ride on a tube (FlatTube::joint).
        let mut carried = Vec::new();
        let mut tube_k = R::of(0.0);
        if let Some(r) = scene.edge_radius {
            tube_k = R::of(radius_param(g, r));
            let mut cycle_of = vec![0usize; space.edges().len()];
            for (c, cycle) in space.edge_cycles().iter().enumerate() {
                for &e in &cycle.edges {
                    cycle_of[e] = c;
                }
            }
            let masks = edge_masks(space, r, reach);
            let keys = edge_keys(space, &masks);
            for (e, edge) in space.edges().iter().enumerate() {
                let a = space.vertices()[edge.vertices[0]].point;
                let b = space.vertices()[edge.vertices[1]].point;
                let ea = g.normalize_tangent::<f64>(a, b);
                // At b, the tangent pointing away from a (direction of travel).
                let eb = g.normalize_tangent::<f64>(b, -a);
                tubes.push(FlatTube {
                    segment: Segment {
                        a: R::v4_of(a),
                        e: R::v4_of(ea),
                        b: R::v4_of(b),
                        e_b: R::v4_of(eb),
                    },
                    color: PALETTE[cycle_of[e] % PALETTE.len()],
                    face_mask: masks[e],
                    edge: keys[e],
                    joint: None,
                });
            }
            let mut joints = Vec::new();
            for (i, v) in space.vertices().iter().enumerate() {
                // A joint takes the colour of the first edge that ends there.
                let color = space
                    .edges()
                    .iter()
                    .position(|e| e.vertices.contains(&i))
                    .map_or([1.0; 3], |e| PALETTE[cycle_of[e] % PALETTE.len()]);
                joints.push(FlatBall {
                    center: ball_center::<R>(g, v.point),
                    k: tube_k,
                    color,
                    glow: 0.0,
                    pbr: None,
                    id: EDGE_ID,
                    face_mask: face_mask(space, &[v.point], r, reach),
                });
            }
            let ends: Vec<[usize; 2]> = space.edges().iter().map(|e| e.vertices).collect();
            let joint_masks: Vec<u32> = joints.iter().map(|j| j.face_mask).collect();
            let carrier = joint_carriers(&ends, &masks, &joint_masks);
            for (v, joint) in joints.into_iter().enumerate() {
                match carrier[v] {
                    // Numbered among the carried joints for now; placed
                    // after the face groups below.
                    Some(t) => {
                        tubes[t].joint = Some(carried.len());
                        carried.push(joint);
                    }
                    None => balls.push(joint),
                }
            }
        }
        let lights = super::light_images::light_images(space, &scene.lights, scene.lighting);
        let (camera, camera_cell) = space.wrap(scene.camera.isometry, 1000);
        let (mut instances, meshes, textures) = flatten_meshes::<R>(space, scene, camera_cell, reach);
        let faces = space.faces().len();
        let groups = FaceGroups {
            balls: FaceGroups::sort(&mut balls, faces, |b| b.face_mask),
            tubes: FaceGroups::sort(&mut tubes, faces, |t| t.edge),
            instances: FaceGroups::sort(&mut instances, faces, |i| i.face_mask),
            edges: FaceGroups::edge_table(tubes.iter().map(|t| t.edge), faces),
        };
        let instance_trees = trees_over(g, &mut instances, &groups.instances);
        // The carried joints after every group, where only their tubes
        // lead.
        for t in &mut tubes {
            t.joint = t.joint.map(|k| balls.len() + k);
        }
        balls.extend(carried);
        let interior = &mut balls[..groups.balls[0] as usize];
        let ball_tree = if interior.len() >= MIN_BALL_TREE {
            tree_over_interior(g, interior)
        } else {
            BallTree::default()
        };
        // With no object masked there is nothing to cull: an infinite reach
        // tells near_faces so before it tests a face.
        let masked = balls.iter().any(|b| b.face_mask != 0)
            || tubes.iter().any(|t| t.face_mask != 0)
            || instances.iter().any(|i| i.face_mask != 0);
        FlatScene {
            faces: FaceTables::new(space),
            balls,
            tubes,
            tube_k,
            groups,
            ball_tree,
            // A hundredth more than the masks were made for, so that no
            // rounding of the endpoints' test (f32 on the GPU) can cull an
            // object at the edge of its reach.
            near_reach: R::of(if masked {
                near_reach(g, reach * 1.01 + 1e-6)
            } else {
                f64::INFINITY
            }),
            cell_shadow: R::of(space.surface_area() / 4.0),
            footprint_cap: R::of(super::footprint::FOOTPRINT_CAP * space.inradius()),
            near_distance: R::of(if masked { reach * 1.01 + 1e-6 } else { f64::INFINITY }),
            lights,
            lighting: scene.lighting,
            instances,
            instance_trees,
            meshes,
            textures,
            fog: scene
                .fog
                .as_ref()
                .filter(|f| f.density > 0.0)
                .map(|f| (R::of(f.density), f.color)),
            camera: R::m4_of(camera),
            camera_element: space.cell_of_matrix(&camera_cell),
            centred_table: OnceLock::new(),
            camera_cell,
            tan_half_fov: R::of((scene.camera.fov_y_degrees.to_radians() / 2.0).tan()),
            frustum: scene.camera.frustum.map(|f| f.half_extent_and_centre().map(R::of)),
        }
        .in_cell(space, &space.cell_of_word(&scene.camera.cell))
    }
}

/// The hierarchy of [`FlatScene::ball_tree`] over `balls` (those with no
/// face mask), which it puts in its leaves' order; none for no balls.
fn tree_over_interior<R: Real>(g: Geometry, balls: &mut [FlatBall<R>]) -> BallTree {
    if balls.is_empty() {
        return BallTree::default();
    }
    let boxes: Vec<_> = balls
        .iter()
        .map(|b| ball_box(g, R::v4_f64(b.center), b.k.f64()))
        .collect();
    let (tree, order) = BallTree::over(&boxes);
    let sorted: Vec<FlatBall<R>> = order.iter().map(|&i| balls[i as usize]).collect();
    balls.copy_from_slice(&sorted);
    tree
}

impl<R: Real> FlatScene<R> {
    /// The scene seen from the copy `cell` instead of the origin copy: the
    /// camera's isometry is read in `cell`'s frame, so the camera is in
    /// `cell` times the cell its isometry wraps into. Exact wherever the
    /// space's ids are (`CellElement::Exact`), at any distance; the `f64`
    /// element follows, rounded, and so does the home of a camera-attached
    /// mesh. Objects are copies in every cell, so nothing else changes.
    #[must_use]
    pub fn in_cell(mut self, space: &Space, cell: &CellElement) -> Self {
        if *cell == space.origin_cell() {
            return self;
        }
        self.camera_element = space.compose_cells(cell, &self.camera_element);
        self.camera_cell = space.cell_matrix(&self.camera_element);
        self.centred_table = OnceLock::new();
        // A camera-attached mesh's home (the copy that is the camera's own
        // body) moves with the camera.
        let (g, c) = (space.geometry(), space.cell_matrix(cell));
        for inst in &mut self.instances {
            if let Some(home) = inst.home {
                inst.home = Some(R::v4_of(g.normalize_point::<f64>(c * R::v4_f64(home))));
            }
        }
        self
    }

    /// The table of cells around the camera's copy that the CPU tracer's
    /// rays step through by index ([`crate::space::cell_table::CentredTable`]),
    /// where `space`'s ids are exact and its table has been grown
    /// ([`crate::space::cells::ExactCells::grown_table`]: this never grows
    /// it; the GPU's packing does, and so may the caller, with
    /// `ExactCells::table`). Made on the first ask and kept with the scene,
    /// and handed out only while it is still `space`'s table around
    /// [`FlatScene::camera_element`] (a scene traced with another space,
    /// or whose camera was moved by hand, gets `None`). `None` elsewhere,
    /// or when the camera's copy is past `i128` integers (about distance
    /// 80): rays then multiply exact elements at every crossing.
    #[must_use]
    pub fn centred_table(&self, space: &Space) -> Option<&Arc<CentredTable>> {
        let (CellScheme::Exact(exact), CellElement::Exact(centre)) = (space.cells(), &self.camera_element) else {
            return None;
        };
        let table = exact.grown_table()?;
        let around = match self.centred_table.get() {
            Some(around) => around,
            None if centre.is_small() => self
                .centred_table
                .get_or_init(|| Arc::new(CentredTable::new(table.clone(), centre.clone()))),
            None => return None,
        };
        (std::ptr::eq(around.table(), &**table) && around.centre() == centre).then_some(around)
    }
}

/// Instances, meshes and textures, as [`FlatScene`] holds them.
type FlatMeshes<R> = (Vec<FlatInstance<R>>, Vec<Arc<MeshData>>, Vec<Arc<Texture>>);

/// The scene's mesh instances with their ghosts, and the distinct meshes
/// and textures they use. Meshes whose bounding ball does not fit the
/// geometry's chart (reaching infinity in H3) are left out.
fn flatten_meshes<R: Real>(space: &Space, scene: &Scene, camera_cell: DMat4, reach: f64) -> FlatMeshes<R> {
    let g = space.geometry();
    let mut instances = Vec::new();
    let mut meshes: Vec<Arc<MeshData>> = Vec::new();
    let mut textures: Vec<Arc<Texture>> = Vec::new();
    for (j, m) in scene.meshes.iter().enumerate() {
        let Some(radius) = m.bounding_radius(g) else { continue };
        let mesh = match meshes.iter().position(|x| Arc::ptr_eq(x, &m.data)) {
            Some(i) => i,
            None => {
                meshes.push(m.data.clone());
                meshes.len() - 1
            }
        };
        let mat = &m.material;
        let mut index = |t: &Option<Arc<Texture>>| {
            t.as_ref()
                .map(|t| match textures.iter().position(|x| Arc::ptr_eq(x, t)) {
                    Some(i) => i,
                    None => {
                        textures.push(t.clone());
                        textures.len() - 1
                    }
                })
        };
        let maps = InstanceTextures {
            base: index(&mat.texture),
            metallic_roughness: index(&mat.metallic_roughness),
            emissive: index(&mat.emissive_texture),
            normal: index(&mat.normal_map),
        };
        let unscale = DMat4::from_diagonal(DVec4::new(1.0 / m.scale, 1.0 / m.scale, 1.0 / m.scale, 1.0));
        let center = m.center(g);
        let k = R::of(radius_param(g, radius));
        for h in ghost_elements(space, center, radius) {
            let placed = h * m.placement;
            let ghost = g.normalize_point::<f64>(h * center);
            let home = m
                .attached
                .then(|| R::v4_of(g.normalize_point::<f64>((camera_cell * isometry::inverse(g, h)).w_axis)));
            instances.push(FlatInstance {
                to_local: R::m4_of(m.local.inverse() * unscale * isometry::inverse(g, placed)),
                center: R::v4_of(ghost),
                k,
                mesh,
                color: mat.base_color,
                textures: maps,
                pbr: mat.pbr,
                emissive: mat.emissive,
                alpha_mask: mat.alpha_cutoff.map(|c| (c, mat.alpha)),
                id: (scene.balls.len() + 1 + j) as u32,
                home,
                face_mask: face_mask(space, &[ghost], radius, reach),
            });
        }
    }
    (instances, meshes, textures)
}

/// The centre of a ball and of each copy of it that reaches into the
/// domain, so a ball straddling a face (or sitting on a vertex, where 20
/// copies of the domain meet in Seifert-Weber) is seen whole from every
/// side.
#[must_use]
pub fn ghost_centres(space: &Space, center: DVec4, radius: f64) -> Vec<DVec4> {
    let g = space.geometry();
    ghost_elements(space, center, radius)
        .into_iter()
        .map(|h| g.normalize_point::<f64>(h * center))
        .collect()
}

/// The group elements (the identity first) whose image of the ball of
/// `radius` around `center` reaches into the domain: what
/// [`ghost_centres`] places ghost balls by and what carries a straddling
/// mesh's ghost instances.
#[must_use]
pub fn ghost_elements(space: &Space, center: DVec4, radius: f64) -> Vec<DMat4> {
    let g = space.geometry();
    // A ball that reaches no face has no copy reaching into the domain.
    let straddles = space
        .faces()
        .iter()
        .any(|f| crate::geometry::plane::signed_distance(g, f.plane, center) > -radius);
    if !straddles {
        return vec![DMat4::IDENTITY];
    }
    // The copies `k D` of the domain that the ball meets, nearest first
    // (the contact walk's best-first search): the ball's copy `k^-1 c`
    // then meets the domain, so `k^-1` is a ghost's element when that
    // copy's centre is nearer than `radius` to every face's inner side.
    let mut out = vec![DMat4::IDENTITY];
    for (k, _) in crate::contact::copies_within(space, center, radius) {
        if out.len() >= MAX_GHOSTS {
            break;
        }
        let h = isometry::inverse(g, k);
        if space.cell_id(&h) == space.cell_id(&DMat4::IDENTITY) {
            continue;
        }
        let c = g.normalize_point::<f64>(h * center);
        let reaches = space
            .faces()
            .iter()
            .all(|face| crate::geometry::plane::signed_distance(g, face.plane, c) < radius);
        if reaches {
            out.push(h);
        }
    }
    out
}
