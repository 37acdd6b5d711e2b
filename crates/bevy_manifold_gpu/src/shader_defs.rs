//! Which parts of the tracer a scene needs (pay only for what the scene
//! uses): each optional
//! part of the WGSL tracer (`shaders/`) sits behind a shader def, and the pipeline
//! is specialised on the scene's actual content.

use bevy_manifold_core::geometry::Geometry;
use bevy_manifold_core::space::Space;
use bevy_manifold_core::space::cells::CellScheme as Cells;
use bevy_manifold_core::trace::Scene;

/// How the GPU makes cell ids (one of `CELLS_*`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CellScheme {
    /// `CELLS_LATTICE`: integer box lattice.
    Lattice,
    /// `CELLS_FINITE`: Cayley-table index.
    Finite,
    /// `CELLS_HASHED`: hash of the copy's rounded centre.
    Hashed,
    /// `CELLS_TABLE`: exact ids from a table of the cells around the
    /// camera ([`bevy_manifold_core::space::cell_table`]).
    Table,
}

/// The specialisation key of the tracer pipeline.
///
/// ```
/// use bevy_manifold_core::prelude::*;
/// use bevy_manifold_gpu::TraceDefs;
/// let torus = catalog::torus(1.0);
/// let defs = TraceDefs::for_scene(&torus, &Scene::default_for(&torus), false);
/// let names = defs.names();
/// assert!(names.contains(&"GEOMETRY_EUCLIDEAN") && names.contains(&"TRANSLATIONS_ONLY"));
/// assert!(!names.contains(&"FOG") && !names.contains(&"GEOMETRY_HYPERBOLIC"));
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TraceDefs {
    /// The geometry (`GEOMETRY_*`).
    pub geometry: Geometry,
    /// `TRANSLATIONS_ONLY`: every pairing is a Euclidean translation.
    pub translations_only: bool,
    /// The cell scheme.
    pub cells: CellScheme,
    /// `CELL_COLORS`.
    pub cell_colors: bool,
    /// `CELL_RULES`: hidden cells and walls ([`TraceDefs::for_rule`]).
    pub cell_rules: bool,
    /// `FOG`.
    pub fog: bool,
    /// `BALLS`.
    pub balls: bool,
    /// `TUBES`.
    pub tubes: bool,
    /// `LIGHTS`.
    pub lights: bool,
    /// `LIGHT_IMAGES`: the lights are images in the cover, each with its
    /// range and the fog on its way, and in S3 both arcs
    /// (`Lighting::images` above 0); without it each light's copy in the
    /// domain along the chart's straight line, as before light images.
    pub light_images: bool,
    /// `SHADOWS`: shadow rays through the faces (`Lighting::shadows`,
    /// with light images and something to cast them).
    pub shadows: bool,
    /// `SOFT_SHADOWS`: shadows with a light of finite size
    /// (`Light::radius`), each trace's shadow rays aimed at one point of
    /// its disc (`TraceSettings::light_sample`; an accumulating view adds
    /// them up to the penumbra).
    pub soft_shadows: bool,
    /// `MESHES`: triangle meshes through their BVH.
    pub meshes: bool,
    /// `MATERIALS`: some ball or mesh has metallic and roughness (the
    /// GGX lobe), emission or a normal map
    /// ([`bevy_manifold_core::material`]); without it every surface has
    /// the classic look and none of their reads is compiled.
    pub materials: bool,
    /// `REFLECTIONS`: rays reflect off surfaces with a material
    /// (`TraceSettings::reflections` above 0, [`TraceDefs::for_reflections`]);
    /// without it no reflection is compiled and `params.reflections` is not read.
    pub reflections: bool,
    /// `PATH_TRACE`: each pixel is one sample of the rendering equation
    /// (`TraceSettings::path_depth` above 0, [`TraceDefs::for_path`]),
    /// `shaders/path.wgsl`'s `path_sample` in place of `trace_ray`.
    pub path_trace: bool,
    /// `ALPHA_MASK`: some mesh has an alpha mask, tested at every
    /// triangle a ray meets.
    pub alpha_mask: bool,
    /// `BALL_TREE`: the scene has enough balls for a ball tree
    /// ([`bevy_manifold_core::trace::MIN_BALL_TREE`]), so the test of the
    /// tree's leaves is compiled in; without it every interior ball is
    /// tested. A def, not a run-time branch: lavapipe runs both sides of
    /// every branch, under masks, so when the tree was walked, the walk
    /// compiled into every scene cost every segment a fifth to two fifths
    /// of its frame (docs/benchmarks/history.md, "Branches on lavapipe").
    pub ball_tree: bool,
    /// `BALL_LEAVES` (a value def, under `BALL_TREE`): the leaves of the
    /// ball tree the pipeline tests, as a constant, so their loop is
    /// unrolled and each box read at a constant index (`ball_tree.wgsl`).
    /// The tree's leaves are a power of two
    /// ([`bevy_manifold_core::trace::leaf_count`]), so a scene whose balls
    /// come and go (the shooter's shots) compiles a pipeline per doubling:
    /// 2 to 64 leaves, six. [`TraceDefs::for_scene`] counts them from the
    /// scene's balls, at least as many as the tree has, and
    /// [`TraceDefs::for_objects`] sets the tree's own count. A pipeline
    /// sent more leaves than this tests every ball, and one sent fewer
    /// tests only those (the image is the same). 0 without the tree (at
    /// least 1 in the value def).
    pub ball_leaves: u32,
    /// `INSTANCE_TREE`: some face group of mesh instances may have a
    /// tree (`FlatScene::instance_trees`; `shaders/instance_tree.wgsl`),
    /// which a segment walks in place of testing each instance. On in
    /// [`TraceDefs::for_scene`] for a scene of
    /// [`bevy_manifold_core::trace::MIN_INSTANCE_TREE`] meshes or more,
    /// and in [`TraceDefs::for_objects`] where a tree is packed. A def, as
    /// `BALL_TREE`: the walk compiled into every scene would cost the few
    /// meshes of most scenes a branch lavapipe runs either way. A pipeline
    /// with it draws a scene without trees by testing each instance, and
    /// one without it a scene with them.
    pub instance_tree: bool,
    /// `MANY_UNKEYED_TUBES`: more than 32 edge tubes have no edge bits
    /// (`FlatTube::edge` 0, only in a domain of more than 32 faces), so a
    /// loop tests those past the first 32, which the walk takes by their
    /// masks. Known once the scene is packed: [`TraceDefs::for_objects`]
    /// sets it, and the headless runner and the render pass call it. A
    /// def: the loop, compiled in but taking no pass, cost Seifert-Weber's
    /// 12- and 52-face frames 10 ms each on lavapipe.
    pub many_unkeyed_tubes: bool,
    /// `FOOTPRINT`: cone tracing (`TraceSettings::footprint`, the
    /// shader's `footprint.wgsl`), only where there are balls or tubes
    /// to fade ([`TraceDefs::for_footprint`]).
    pub footprint: bool,
    /// `FACE_COUNT` (a value def, [`TraceDefs::for_scene`]): the domain's
    /// faces as a constant, so every loop over the faces has a constant
    /// trip count and is unrolled, and each face is read at a constant
    /// index. lavapipe reads a uniform at a run-time index with a gather,
    /// one lane at a time, and at a constant one with a single load: with
    /// the faces counted at run time the default scene traced 13-17%
    /// slower (docs/benchmarks/history.md, "Branches on lavapipe"). The planes are
    /// also copied once per invocation into a private array of this size
    /// (`planes` in `bindings.wgsl`): on lavapipe even a constant-index
    /// read of the uniform cost several times a private one. It also keeps long
    /// walks whole on lavapipe, which ends all loops of an invocation once
    /// they have taken 65,535 iterations between them (Mesa's
    /// `LP_MAX_TGSI_LOOP_ITERATIONS`): with the faces looped at run time a
    /// 12-face walk was cut after 1638 transports. The price: a pipeline
    /// per face count (the explorer's soak compiles more of them). `None`
    /// (the faces counted at run time, `params.face_count`) only in the
    /// generic pipeline and where a caller clears it.
    pub face_count: Option<u32>,
}

impl TraceDefs {
    /// The defs a scene in a space needs, and nothing more.
    #[must_use]
    pub fn for_scene(space: &Space, scene: &Scene, cell_colors: bool) -> Self {
        let geometry = space.geometry();
        let translations_only = geometry == Geometry::Euclidean
            && space
                .faces()
                .iter()
                .all(|f| glam::DMat3::from_mat4(f.pairing).abs_diff_eq(glam::DMat3::IDENTITY, 1e-12));
        let ball_tree = scene.balls.len() >= bevy_manifold_core::trace::MIN_BALL_TREE;
        TraceDefs {
            geometry,
            translations_only,
            cells: match space.cells() {
                Cells::Lattice { .. } => CellScheme::Lattice,
                Cells::Finite { .. } => CellScheme::Finite,
                Cells::Exact(_) => CellScheme::Table,
                Cells::Hashed { .. } => CellScheme::Hashed,
            },
            cell_colors,
            cell_rules: false,
            fog: scene.fog.as_ref().is_some_and(|f| f.density > 0.0),
            // Vertex joints of the edge tubes are balls too.
            balls: !scene.balls.is_empty() || scene.edge_radius.is_some(),
            tubes: scene.edge_radius.is_some(),
            lights: !scene.lights.is_empty(),
            light_images: !scene.lights.is_empty() && scene.lighting.images > 0,
            shadows: !scene.lights.is_empty()
                && scene.lighting.images > 0
                && scene.lighting.shadows
                && (!scene.balls.is_empty() || scene.edge_radius.is_some() || !scene.meshes.is_empty()),
            // Only a light image of finite size has a disc to sample.
            soft_shadows: scene.lights.iter().any(|l| l.radius > 0.0),
            meshes: !scene.meshes.is_empty(),
            materials: scene.balls.iter().any(|b| b.pbr.is_some())
                || scene.meshes.iter().any(|m| {
                    let t = &m.material;
                    t.pbr.is_some() || t.emissive != [0.0; 3] || t.normal_map.is_some()
                }),
            reflections: false,
            path_trace: false,
            alpha_mask: scene.meshes.iter().any(|m| m.material.alpha_cutoff.is_some()),
            // The interior balls, those a tree holds, are scene balls (a
            // ghost copy or a vertex joint lies near a face).
            ball_tree,
            ball_leaves: if ball_tree {
                bevy_manifold_core::trace::leaf_count(scene.balls.len()) as u32
            } else {
                0
            },
            instance_tree: scene.meshes.len() >= bevy_manifold_core::trace::MIN_INSTANCE_TREE,
            many_unkeyed_tubes: false,
            footprint: false,
            face_count: Some(face_count(space)),
        }
    }

    /// These defs with cone tracing when `on` and the scene has balls or
    /// tubes (meshes are hit whole either way).
    ///
    /// ```
    /// use bevy_manifold_core::prelude::*;
    /// use bevy_manifold_gpu::TraceDefs;
    /// let sw = catalog::seifert_weber();
    /// assert!(TraceDefs::for_scene(&sw, &Scene::default_for(&sw), false).for_footprint(true).footprint);
    /// assert!(!TraceDefs::for_scene(&sw, &Scene::empty(), false).for_footprint(true).footprint);
    /// ```
    #[must_use]
    pub fn for_footprint(mut self, on: bool) -> Self {
        self.footprint = on && (self.balls || self.tubes);
        self
    }

    /// These defs with reflections when `reflections` is above 0 and some
    /// surface has a material (`MATERIALS`): the others reflect nothing.
    ///
    /// ```
    /// use bevy_manifold_core::prelude::*;
    /// use bevy_manifold_gpu::TraceDefs;
    /// let torus = catalog::torus(1.0);
    /// let defs = TraceDefs::for_scene(&torus, &Scene::default_for(&torus), false);
    /// assert!(!defs.for_reflections(1).reflections, "no surface has a material");
    /// assert!(TraceDefs { materials: true, ..defs }.for_reflections(1).reflections);
    /// ```
    #[must_use]
    pub fn for_reflections(mut self, reflections: u32) -> Self {
        self.reflections = reflections > 0 && self.materials;
        self
    }

    /// These defs for path tracing when `depth` is above 0: `PATH_TRACE`,
    /// without the cell rules, cones and reflections, which the path
    /// tracer does not take (its paths take every lobe whole).
    ///
    /// ```
    /// use bevy_manifold_core::prelude::*;
    /// use bevy_manifold_gpu::TraceDefs;
    /// let torus = catalog::torus(1.0);
    /// let defs = TraceDefs::for_scene(&torus, &Scene::default_for(&torus), false).for_footprint(true);
    /// let path = defs.for_path(8);
    /// assert!(path.path_trace && !path.footprint);
    /// assert_eq!(defs.for_path(0), defs);
    /// ```
    #[must_use]
    pub fn for_path(mut self, depth: u32) -> Self {
        if depth > 0 {
            self.path_trace = true;
            self.cell_rules = false;
            self.footprint = false;
            self.reflections = false;
        }
        self
    }

    /// These defs for the packed `objects`: `MANY_UNKEYED_TUBES` where
    /// more than 32 tubes have no edge bits (the tubes before the first
    /// face group); with `BALL_TREE` on and a ball tree packed,
    /// `BALL_LEAVES` its leaves. `BALL_TREE` itself stays as it was (a
    /// scene whose balls lie near faces packs no tree, and the pipeline
    /// then tests each ball; the generic pipeline keeps every def).
    /// `INSTANCE_TREE` on where an instance tree is packed.
    #[must_use]
    pub fn for_objects(mut self, objects: &crate::pack::GpuObjects) -> Self {
        self.many_unkeyed_tubes = objects.groups[0][1] > 32;
        self.instance_tree |= self.meshes && objects.instance_trees != crate::layout::NO_INSTANCE_TREES;
        let leaves = objects.ball_nodes.len().saturating_sub(2);
        if self.ball_tree && leaves > 0 {
            self.ball_leaves = leaves as u32;
        }
        self
    }

    /// True when these defs and `other` differ at most in the ball tree
    /// (`BALL_TREE`, `BALL_LEAVES`) and the instance trees
    /// (`INSTANCE_TREE`): a pipeline of either draws a scene packed for
    /// the other, testing every ball (no tree, or more leaves than it was
    /// compiled for) or only the leaves the scene has, and every instance
    /// or only those of the leaves met. The render pass draws with the
    /// last pipeline while the one for a new leaf count compiles.
    ///
    /// ```
    /// use bevy_manifold_core::prelude::*;
    /// use bevy_manifold_gpu::TraceDefs;
    /// let sw = catalog::seifert_weber();
    /// let defs = TraceDefs::for_scene(&sw, &Scene::default_for(&sw), false);
    /// let more = TraceDefs { ball_tree: true, ball_leaves: 8, ..defs };
    /// assert!(defs.same_but_ball_tree(&more));
    /// assert!(!defs.same_but_ball_tree(&TraceDefs { fog: true, ..more }));
    /// ```
    #[must_use]
    pub fn same_but_ball_tree(&self, other: &TraceDefs) -> bool {
        TraceDefs {
            ball_tree: other.ball_tree,
            ball_leaves: other.ball_leaves,
            instance_tree: other.instance_tree,
            ..*self
        } == *other
    }

    /// These defs for a space under `rule`: `CELL_RULES` when some rule is
    /// on.
    #[must_use]
    pub fn for_rule(mut self, rule: &bevy_manifold_core::space::rule::CellRule) -> Self {
        self.cell_rules = rule.is_active();
        self
    }

    /// Every def on that can be on with this geometry: the generic pipeline
    /// that specialisation is measured against.
    #[must_use]
    pub fn generic(geometry: Geometry) -> Self {
        TraceDefs {
            geometry,
            translations_only: false,
            cells: CellScheme::Hashed,
            cell_colors: true,
            cell_rules: true,
            fog: true,
            balls: true,
            tubes: true,
            lights: true,
            light_images: true,
            shadows: true,
            soft_shadows: true,
            meshes: true,
            materials: true,
            reflections: true,
            path_trace: false,
            alpha_mask: true,
            ball_tree: true,
            ball_leaves: bevy_manifold_core::trace::MAX_BALL_LEAVES as u32,
            instance_tree: true,
            many_unkeyed_tubes: true,
            footprint: true,
            face_count: None,
        }
    }

    /// Every valid combination (each geometry with the cell schemes and
    /// transport kinds it allows, every optional part on and off (light
    /// images and shadows with the lights), the faces
    /// counted at run time and as a constant 12, the cell rules on and off,
    /// cone tracing on and off where there are balls or tubes, the ball
    /// tree on and off where there are balls; the loop over unkeyed tubes
    /// with the tubes where cell colours are on, so that it is checked on
    /// and off without doubling the list).
    #[must_use]
    pub fn all() -> Vec<Self> {
        let mut out = Vec::new();
        let bases = [
            (Geometry::Euclidean, false, CellScheme::Lattice),
            (Geometry::Euclidean, true, CellScheme::Lattice),
            (Geometry::Euclidean, false, CellScheme::Hashed),
            (Geometry::Hyperbolic, false, CellScheme::Hashed),
            (Geometry::Hyperbolic, false, CellScheme::Table),
            (Geometry::Spherical, false, CellScheme::Finite),
            (Geometry::Spherical, false, CellScheme::Hashed),
        ];
        for (geometry, translations_only, cells) in bases {
            for bits in 0..1024u32 {
                let on = |k: u32| bits & (1 << k) != 0;
                if (on(8) && !(on(2) || on(3))) || (on(9) && !on(2)) {
                    continue;
                }
                out.push(TraceDefs {
                    geometry,
                    translations_only,
                    cells,
                    cell_colors: on(0),
                    fog: on(1),
                    balls: on(2),
                    tubes: on(3),
                    lights: on(4),
                    // Light images with the lights and cell colours,
                    // shadows with them and fog: each on and off, with
                    // and without cones, without doubling the list.
                    light_images: on(4) && on(0),
                    shadows: on(4) && on(0) && on(1) && (on(2) || on(3) || on(5)),
                    // Soft with the faces counted as a constant: on and
                    // off with shadows.
                    soft_shadows: on(4) && on(0) && on(1) && (on(2) || on(3) || on(5)) && on(6),
                    meshes: on(5),
                    // Materials with lights and the cell rules, the alpha
                    // mask with meshes and fog: each on and off.
                    materials: on(4) && on(7),
                    // Reflections with materials and fog: on and off.
                    reflections: on(4) && on(7) && on(1),
                    // Path tracing with lights, fog and the faces as a
                    // constant, where rules and cones are off.
                    path_trace: on(4) && on(1) && on(6) && !on(7) && !on(8),
                    alpha_mask: on(5) && on(1),
                    face_count: on(6).then_some(12),
                    cell_rules: on(7),
                    footprint: on(8),
                    ball_tree: on(9),
                    ball_leaves: if on(9) { 16 } else { 0 },
                    // The instance trees with meshes and the ball tree.
                    instance_tree: on(5) && on(9),
                    many_unkeyed_tubes: on(3) && on(0),
                });
            }
        }
        out
    }

    /// The value defs: `FACE_COUNT` when set, `BALL_LEAVES` with the
    /// ball tree.
    #[must_use]
    pub fn values(&self) -> Vec<(&'static str, u32)> {
        let leaves = self.ball_tree.then_some(("BALL_LEAVES", self.ball_leaves.max(1)));
        self.face_count
            .map(|n| ("FACE_COUNT", n))
            .into_iter()
            .chain(leaves)
            .collect()
    }

    /// The names of the defs that are on.
    #[must_use]
    pub fn names(&self) -> Vec<&'static str> {
        let mut n = vec![match self.geometry {
            Geometry::Euclidean => "GEOMETRY_EUCLIDEAN",
            Geometry::Hyperbolic => "GEOMETRY_HYPERBOLIC",
            Geometry::Spherical => "GEOMETRY_SPHERICAL",
        }];
        n.push(match self.cells {
            CellScheme::Lattice => "CELLS_LATTICE",
            CellScheme::Finite => "CELLS_FINITE",
            CellScheme::Hashed => "CELLS_HASHED",
            CellScheme::Table => "CELLS_TABLE",
        });
        for (on, name) in [
            (self.translations_only, "TRANSLATIONS_ONLY"),
            (self.cell_colors, "CELL_COLORS"),
            (self.cell_rules, "CELL_RULES"),
            (self.fog, "FOG"),
            (self.balls, "BALLS"),
            (self.tubes, "TUBES"),
            (self.lights, "LIGHTS"),
            (self.light_images, "LIGHT_IMAGES"),
            (self.shadows, "SHADOWS"),
            (self.shadows && self.soft_shadows, "SOFT_SHADOWS"),
            (self.meshes, "MESHES"),
            (self.materials, "MATERIALS"),
            (self.reflections && self.materials, "REFLECTIONS"),
            (self.path_trace, "PATH_TRACE"),
            (self.alpha_mask && self.meshes, "ALPHA_MASK"),
            (self.ball_tree, "BALL_TREE"),
            (self.instance_tree && self.meshes, "INSTANCE_TREE"),
            (self.many_unkeyed_tubes, "MANY_UNKEYED_TUBES"),
            (self.footprint, "FOOTPRINT"),
        ] {
            if on {
                n.push(name);
            }
        }
        // Derived: the ball test serves balls and meshes' bounding balls
        // (naga_oil's #ifdef takes one name).
        if self.balls || self.meshes {
            n.push("BALL_HITS");
        }
        n
    }
}

/// The faces of `space`'s domain as the shader's `FACE_COUNT` (at most
/// [`bevy_manifold_core::space::MAX_FACES`], which a loaded space never
/// exceeds).
#[must_use]
pub fn face_count(space: &Space) -> u32 {
    u32::try_from(space.faces().len()).unwrap_or(u32::MAX)
}
