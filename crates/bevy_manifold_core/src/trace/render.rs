//! Algorithm 1 per pixel (see [`crate::trace`]), in parallel over pixels.
//!
//! WGSL twin: `shaders/render.wgsl` in `bevy_manifold_gpu` (`camera_ray`,
//! `trace_pixel`, `nearest_object`, `shade`).

/// ln 255: once fog density times the distance travelled passes it, fog
/// has left less than 1/255 of an object's light and the ray may stop.
/// WGSL twin: `FOG_CUT` in `shaders/bindings.wgsl`.
pub const FOG_CUT: f64 = 5.541_263_545_158_426;

use super::cull::{Candidate, each_candidate};
use super::exact_cell::{ExactCell, Table};
use super::flat::{EDGE_ID, FlatInstance, FlatScene, same_cell_point};
use super::footprint::{
    Approach, BALL_GROWTH, Inflation, Layers, SEGMENT_LAYERS, ball_approach, coverage, grown_reach, normal_at_offset,
    pixel_half_angle, radius_of, shading_offset, side_by_side, spread, tube_approach, widest_spread,
};
use super::mesh_hit::{hit_instance, mesh_albedo, mesh_normal};
use super::scene::Scene;
use super::step::{
    ALL_FACES, Ray, Segment, advance_or_raw, foot_on_line, hit_ball, hit_tube, may_hit, near_faces, normal_from,
    on_edge,
};
use super::walk::Walker;
use crate::geometry::{Geometry, Real};
use crate::mesh::MeshHit;
use crate::space::Space;
use crate::space::cells::{CellId, CellTint};
use crate::space::rule::{CellRule, WALL_COLOR, WALL_OBJECT};
#[cfg(feature = "parallel")]
use rayon::prelude::*;

/// How to trace.
#[derive(Clone, Debug, PartialEq)]
pub struct TraceSettings {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Most face crossings (transports) a ray may make: the paper's levels.
    pub levels: u32,
    /// Rays stop after this distance.
    pub max_distance: f64,
    /// Colour objects by the cell they are seen in.
    pub cell_colors: bool,
    /// How, when `cell_colors` is on.
    pub cell_tint: CellTint,
    /// Stop a ray once fog leaves less than 1/255 of its light.
    pub fog_early_stop: bool,
    /// Renormalise the ray after each advance and transport (off only to
    /// measure drift: see [`super::step::advance_raw`]).
    pub renormalize: bool,
    /// Per-cell rules: objects in off cells hidden, walls between cells
    /// ([`crate::space::rule`]); the GPU twin is `CELL_RULES`.
    pub cell_rule: CellRule,
    /// How pixels map to rays: the camera's perspective, or a panorama.
    pub projection: Projection,
    /// Test on each segment only the objects near the faces it comes near
    /// ([`super::step::near_faces`]): the same image, fewer tests. Off
    /// only to measure what it saves (the GPU twin is `FLAG_NO_CULL`).
    pub cull: bool,
    /// Trace each pixel as a cone half a pixel wide
    /// ([`super::footprint`]): balls and edge tubes thinner than its
    /// footprint add the part of the pixel they cover and let the rest
    /// through, so far copies fade to their average instead of
    /// flickering, and silhouettes are smooth. Off: one ray per pixel,
    /// hit or miss. The GPU twin is `params.footprint`.
    pub footprint: bool,
}

/// How the pixels of an image map to view directions.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Projection {
    /// The camera's field of view, square pixels (the scene camera's
    /// `fov_y_degrees`).
    #[default]
    Perspective,
    /// 360 degrees mono, equirectangular: column `i` is the longitude
    /// (the view direction -z in the middle, +x at three quarters), row
    /// `j` the latitude (+y at the top).
    Equirect,
    /// Omni-directional stereo, top-bottom: the left eye's equirectangular
    /// panorama above the right eye's. For each longitude the eyes sit
    /// `eye_separation` apart (the space's distance) on the line through
    /// the camera perpendicular to that direction, reached along the
    /// geodesic, as VR eyes are; the ray's direction is carried there
    /// unchanged (it is perpendicular to the offset).
    Ods {
        /// Distance between the eyes.
        eye_separation: f64,
    },
}

impl Projection {
    /// The projection's number on the GPU (`params.projection`) and the
    /// half eye separation.
    #[must_use]
    pub fn words(self) -> (u32, f32) {
        match self {
            Projection::Perspective => (0, 0.0),
            Projection::Equirect => (1, 0.0),
            Projection::Ods { eye_separation } => (2, (eye_separation * 0.5) as f32),
        }
    }
}

/// Crossings per ray the CPU tracer follows exactly (the exact ids of
/// [`crate::space::exact`], the cell rules); past them the walk's `f64`
/// or `f32` matrix names the cells, as in spaces without exact ids.
pub const MAX_EXACT_LEVELS: u32 = 64;

/// Most levels (face transports per ray) any tracer takes; more are
/// clamped or refused. Enough for the drift probe's 10^4-transport walks;
/// the GPU walk's loop bound (levels plus at most 10^4 distance steps)
/// stays far from `u32` overflow.
pub const MAX_LEVELS: u32 = 16_384;

/// Most pixels in one traced image (8192 x 8192).
pub const MAX_PIXELS: u64 = 1 << 26;

impl TraceSettings {
    /// Checks the settings a tracer can honour: a size of at least one
    /// pixel and at most [`MAX_PIXELS`] (multiplied in 64 bits), levels at
    /// most [`MAX_LEVELS`], a positive `max_distance` (not NaN; the GPU
    /// walk bounds its loop by at most 10^4 steps of it whatever it is).
    ///
    /// # Errors
    /// The first setting out of range, named with its value.
    ///
    /// ```
    /// use bevy_manifold_core::trace::TraceSettings;
    /// let huge = TraceSettings { width: 70_000, height: 70_000, ..TraceSettings::default() };
    /// assert!(huge.check().unwrap_err().contains("70000x70000"));
    /// assert!(TraceSettings::default().check().is_ok());
    /// ```
    pub fn check(&self) -> Result<(), String> {
        let pixels = u64::from(self.width) * u64::from(self.height);
        if pixels == 0 || pixels > MAX_PIXELS {
            return Err(format!(
                "an image of {}x{} pixels: it must have between 1 and {MAX_PIXELS} pixels",
                self.width, self.height
            ));
        }
        if self.levels > MAX_LEVELS {
            return Err(format!("{} levels: at most {MAX_LEVELS}", self.levels));
        }
        if self.max_distance.is_nan() || self.max_distance <= 0.0 {
            return Err(format!("max distance {}: it must be positive", self.max_distance));
        }
        Ok(())
    }
}

impl Default for TraceSettings {
    fn default() -> Self {
        TraceSettings {
            width: 640,
            height: 360,
            levels: 8,
            max_distance: 100.0,
            cell_colors: false,
            cell_tint: CellTint::ByCell,
            fog_early_stop: true,
            renormalize: true,
            cell_rule: CellRule::default(),
            projection: Projection::Perspective,
            cull: true,
            footprint: false,
        }
    }
}

/// What one pixel saw.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TracePixel {
    /// Linear RGB.
    pub color: [f32; 3],
    /// 0 nothing, `k` the k-th ball of the scene, [`EDGE_ID`] a domain edge.
    pub object: u32,
    /// Face crossings before the hit (or before the ray stopped).
    pub levels: u32,
    /// The copy of the domain the ray ended in.
    pub cell: CellId,
    /// Distance travelled to the hit (or to where the ray stopped).
    pub distance: f32,
}

/// A traced image with its id buffer.
#[derive(Clone, Debug)]
pub struct TraceImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Row-major pixels, top row first.
    pub pixels: Vec<TracePixel>,
}

impl TraceImage {
    /// The pixel at column `i`, row `j`.
    #[must_use]
    pub fn at(&self, i: u32, j: u32) -> &TracePixel {
        &self.pixels[(j * self.width + i) as usize]
    }
}

/// One segment of a ray's path inside the domain, for tests and tools.
#[derive(Clone, Copy, Debug)]
pub struct PathStep<R: Real> {
    /// Where the segment starts.
    pub start: Ray<R>,
    /// Where it ends (on a face, or where it stopped).
    pub end: Ray<R>,
    /// The face it leaves through, if it reached one.
    pub face: Option<usize>,
    /// Its length.
    pub length: R,
}

/// Why a ray stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stop {
    /// It hit an object (id as in [`TracePixel::object`]).
    Hit(u32),
    /// It used up its levels.
    MaxLevel,
    /// It went past the maximum distance.
    MaxDistance,
    /// Fog had hidden everything further.
    Fog,
}

/// Renders `scene` in `space`: one ray per pixel, in parallel.
#[must_use]
pub fn render<R: Real>(space: &Space, scene: &Scene, settings: &TraceSettings) -> TraceImage {
    let prep = FlatScene::<R>::new(space, scene);
    let (w, h) = (settings.width, settings.height);
    #[cfg(feature = "parallel")]
    let indices = (0..w * h).into_par_iter();
    #[cfg(not(feature = "parallel"))]
    let indices = 0..w * h;
    let pixels = indices
        .map(|k| {
            let ray = view_ray(&prep, settings.projection, k % w, k / w, w, h);
            trace_ray(space, &prep, ray, settings, &mut |_| {}).0
        })
        .collect();
    TraceImage {
        width: w,
        height: h,
        pixels,
    }
}

/// The view-space slopes `(x, y)` of the direction through normalised
/// device coordinates `(x, y)` (the direction is `(x, y, -1)`): the
/// symmetric frustum of `tan_half_fov` and the image's aspect, or the
/// scene's off-centre [`crate::trace::Frustum`].
///
/// WGSL twin: `view_slopes` in `shaders/render.wgsl`.
#[must_use]
pub fn view_slopes<R: Real>(prep: &FlatScene<R>, x: R, y: R, w: u32, h: u32) -> (R, R) {
    match prep.frustum {
        None => {
            let aspect = R::of(f64::from(w) / f64::from(h));
            (x * prep.tan_half_fov * aspect, y * prep.tan_half_fov)
        }
        Some([hw, hh, cx, cy]) => (x * hw + cx, y * hh + cy),
    }
}

/// The ray through the centre of pixel `(i, j)` of a `w` x `h` image.
#[must_use]
pub fn camera_ray<R: Real>(prep: &FlatScene<R>, i: u32, j: u32, w: u32, h: u32) -> Ray<R> {
    let one = R::of(1.0);
    let x = R::of(2.0 * (f64::from(i) + 0.5) / f64::from(w)) - one;
    let y = one - R::of(2.0 * (f64::from(j) + 0.5) / f64::from(h));
    let (sx, sy) = view_slopes(prep, x, y, w, h);
    let d = R::v4(sx, sy, -one, R::of(0.0));
    let d = d * (one / R::dot4(d, d).sqrt());
    let g = prep.faces.geometry;
    let o = g.normalize_point::<R>(prep.camera * g.origin::<R>());
    Ray {
        origin: o,
        dir: g.normalize_tangent::<R>(o, prep.camera * d),
    }
}

/// The ray of pixel `(i, j)` of a `w` x `h` image under `projection`
/// ([`camera_ray`] for the perspective).
///
/// WGSL twin: `view_ray` in `shaders/render.wgsl`.
#[must_use]
pub fn view_ray<R: Real>(prep: &FlatScene<R>, projection: Projection, i: u32, j: u32, w: u32, h: u32) -> Ray<R> {
    let (kind, half_separation) = projection.words();
    if kind == 0 {
        return camera_ray(prep, i, j, w, h);
    }
    // ODS: the top half is the left eye, the bottom half the right.
    let (rows, row, side) = if kind == 2 {
        let half = (h / 2).max(1);
        if j < half {
            (half, j, -1.0)
        } else {
            (h - half, j - half, 1.0)
        }
    } else {
        (h, j, 0.0)
    };
    let tau = core::f64::consts::TAU;
    let lon = R::of(tau * ((f64::from(i) + 0.5) / f64::from(w) - 0.5));
    let lat = R::of(core::f64::consts::PI * (0.5 - (f64::from(row) + 0.5) / f64::from(rows)));
    let zero = R::of(0.0);
    let d = R::v4(lon.sin() * lat.cos(), lat.sin(), -(lon.cos() * lat.cos()), zero);
    let g = prep.faces.geometry;
    // The eye, along the geodesic from the camera perpendicular to the
    // longitude's direction (its right: (cos, 0, sin)).
    let right = R::v4(lon.cos(), zero, lon.sin(), zero);
    let (eye, _) = g.exp::<R>(g.origin::<R>(), right, R::of(side) * R::of(f64::from(half_separation)));
    let o = g.normalize_point::<R>(prep.camera * eye);
    Ray {
        origin: o,
        dir: g.normalize_tangent::<R>(o, prep.camera * d),
    }
}

/// Traces one ray through the manifold (Algorithm 1): nearest object in the
/// domain, else the exit face; transport through its pairing; repeat. Calls
/// `on_step` for every segment. Returns the pixel and why the ray stopped.
pub fn trace_ray<R: Real>(
    space: &Space,
    prep: &FlatScene<R>,
    ray: Ray<R>,
    settings: &TraceSettings,
    on_step: &mut dyn FnMut(&PathStep<R>),
) -> (TracePixel, Stop) {
    let g = prep.faces.geometry;
    let fog_cut = R::of(FOG_CUT);
    let max_distance = R::of(settings.max_distance);
    let mut walk = Walker::new(ray, R::m4_of(prep.camera_cell));
    // Where the space's ids are exact, or rules are on, the walk's cell
    // (by the table around the camera, then by exact elements), crossed
    // with the ray; otherwise the id comes from the walk's matrix.
    let rule = &settings.cell_rule;
    let table = Table::of(space, prep);
    let mut exact = ExactCell::start(table, prep, rule.is_active());
    let cell_id = |walk: &Walker<R>, exact: &ExactCell| exact.id(table, space, walk);
    let mut travelled = R::of(0.0);
    let background = prep.fog.map_or([0.0; 3], |(_, c)| c);
    // Cone tracing (settings.footprint): the pixel's half-angle, the
    // layers met so far, and the first layer covering half the pixel or
    // more, which names the pixel's object and depth.
    let beta = settings.footprint.then(|| R::of(pixel_half_angle_of(prep, settings)));
    let mut layers = Layers::default();
    let mut front: Option<TracePixel> = None;
    let pixel = |color, object, walk: &Walker<R>, exact: &ExactCell, distance: R| TracePixel {
        color,
        object,
        levels: walk.levels,
        cell: cell_id(walk, exact),
        distance: distance.f64() as f32,
    };
    let finish = |layers: &Layers, front: Option<TracePixel>, behind: TracePixel| TracePixel {
        color: layers.over(behind.color),
        ..front.unwrap_or(behind)
    };
    // A hard bound on the loop: every pass either transports (at most
    // levels times) or, in S3, advances by a fixed distance of 1 (at most
    // max_distance times), so no input makes it spin.
    let max_passes = settings.levels as usize + settings.max_distance.min(1e4) as usize + 2;
    for _ in 0..max_passes {
        if let Some((density, _)) = prep.fog
            && settings.fog_early_stop
            && density * travelled > fog_cut
        {
            let behind = pixel(background, 0, &walk, &exact, travelled);
            return (finish(&layers, front, behind), Stop::Fog);
        }
        let (face, t_end) = walk.segment_end(&prep.faces);
        let cell_point = walk.cell * R::v4_of(glam::DVec4::W);
        let here = rule.is_active().then(|| cell_id(&walk, &exact));
        let shown = here.is_none_or(|id| rule.visible(id));
        // Objects grow by the segment's widest footprint, at most the cap.
        let w = beta.map_or(R::of(0.0), |b| {
            let end = travelled + g.chart_to_distance::<R>(t_end);
            (b * widest_spread(g, travelled, end)).min(prep.footprint_cap)
        });
        // The faces the segment comes near, for balls (grown BALL_GROWTH
        // footprints) and for tubes and meshes (one).
        let grow = if w > R::of(0.0) {
            Inflation::new(g, w)
        } else {
            Inflation::none()
        };
        let near_within = |growth: R| {
            if !settings.cull {
                return ALL_FACES;
            }
            let reach = if growth > R::of(0.0) {
                grown_reach(g, prep.near_distance, growth)
            } else {
                prep.near_reach
            };
            near_faces(&prep.faces.planes, prep.faces.near_scale, reach, &walk.ray, t_end)
        };
        let near = if w > R::of(0.0) {
            [near_within(w * R::of(BALL_GROWTH)), near_within(w)]
        } else {
            [near_within(w); 2]
        };
        // Each object met on the segment, nearest first: for a ray the
        // first hit, whole; for a cone each object it passes within its
        // footprint of, in the order of the ray's nearest approach, a
        // layer covering part of the pixel.
        let met = match (beta, shown) {
            (_, false) => Nearest::default(),
            (Some(b), true) => segment_layers(
                g,
                prep,
                &walk.ray,
                t_end,
                cell_point,
                (near, settings.cull),
                (&grow, b, travelled),
            ),
            (None, true) => {
                let mut met = Nearest::default();
                if let Some((t, h)) = nearest_object(g, prep, &walk.ray, t_end, cell_point, (near[0], settings.cull)) {
                    met.whole = Some((t, h, None));
                }
                met
            }
        };
        for &(t, hit, cover) in met.iter() {
            let layer = match cover {
                Some(c) => cone_layer(g, prep, &walk.ray, (hit, c), t_end),
                None => ConeLayer::whole(t),
            };
            let dist = travelled + g.chart_to_distance::<R>(layer.t);
            let cell = cell_id(&walk, &exact);
            let color = shade(g, prep, &walk.ray, (layer.t, layer.normal), hit, dist, cell, settings);
            let part = layer.part;
            let this = TracePixel {
                color,
                object: hit.id(prep),
                levels: walk.levels,
                cell,
                distance: dist.f64() as f32,
            };
            if part >= 0.5 && front.is_none() {
                front = Some(this);
            }
            if layers.add(color, part) {
                return (finish(&layers, front, this), Stop::Hit(hit.id(prep)));
            }
            if layers.full() {
                let behind = pixel(background, 0, &walk, &exact, travelled);
                return (finish(&layers, front, behind), Stop::MaxLevel);
            }
        }
        let end = advance_or_raw(g, &walk.ray, t_end, settings.renormalize);
        let length = g.chart_to_distance::<R>(t_end);
        on_step(&PathStep {
            start: walk.ray,
            end,
            face,
            length,
        });
        travelled = travelled + length;
        if travelled > max_distance {
            let behind = pixel(background, 0, &walk, &exact, travelled);
            return (finish(&layers, front, behind), Stop::MaxDistance);
        }
        // The cell across the face, crossed once: for the wall test, then
        // for the walk.
        let next = match face {
            Some(f) if rule.walls.is_some() && !exact.is_off() => Some(exact.crossed(table, space, prep, f)),
            _ => None,
        };
        if let (Some(id), Some(n)) = (here, &next)
            && rule.wall(id, n.id(table, space, &walk))
        {
            let f = face.unwrap_or_default();
            let color = shade_wall(prep, &prep.faces.planes[f], &walk.ray, travelled);
            let wall = pixel(color, WALL_OBJECT, &walk, &exact, travelled);
            layers.add(color, 1.0);
            return (finish(&layers, front, wall), Stop::Hit(WALL_OBJECT));
        }
        if face.is_some() && walk.levels >= settings.levels {
            let behind = pixel(background, 0, &walk, &exact, travelled);
            return (finish(&layers, front, behind), Stop::MaxLevel);
        }
        walk.step(&prep.faces, face, end, settings.renormalize);
        if let Some(f) = face
            && !exact.is_off()
        {
            exact = next.unwrap_or_else(|| exact.crossed(table, space, prep, f));
        }
        // Past MAX_EXACT_LEVELS crossings a ray is far beyond any table or
        // rule of interest and its exact product grows into big integers
        // (the drift probe's 10^4-transport walks): the walk's matrix
        // names its cells from there, far-flagged beyond the horizon.
        if walk.levels > MAX_EXACT_LEVELS {
            exact = ExactCell::Off;
        }
    }
    let behind = pixel(background, 0, &walk, &exact, travelled);
    (finish(&layers, front, behind), Stop::MaxDistance)
}

/// The half-angle of the pixels' cones for the scene's camera
/// ([`pixel_half_angle`]): its frustum's half height, or
/// `tan_half_fov`, over the image's rows.
#[must_use]
pub fn pixel_half_angle_of<R: Real>(prep: &FlatScene<R>, settings: &TraceSettings) -> f64 {
    let half_height = prep.frustum.map_or(prep.tan_half_fov, |f| f[1]).f64();
    pixel_half_angle(settings.projection, half_height, settings.height)
}

/// A layer of a pixel's cone: the part of the pixel it covers, where it
/// is shaded, and the normal there when that is not the object's own at
/// the ray's hit.
struct ConeLayer<R: Real> {
    part: f32,
    t: R,
    normal: Option<R::V4>,
}

impl<R: Real> ConeLayer<R> {
    /// All of the pixel, shaded where the ray hit: a ray's hit.
    fn whole(t: R) -> Self {
        ConeLayer {
            part: 1.0,
            t,
            normal: None,
        }
    }
}

/// What a ball or tube met by a pixel's cone covers: where the ray
/// passes nearest it ([`approach`]), the footprint there (`beta` times
/// [`spread`] of the distance from the eye), the object's radius and the
/// part of the pixel it covers ([`coverage`]).
#[derive(Clone, Copy, Debug)]
struct Cover<R: Real> {
    near: Approach<R>,
    gap: R,
    w: R,
    r: R,
    part: f32,
}

/// Where a layer is shaded (`Cover`'s object `hit`, on the segment
/// ending at `t_end`): at the ray's own hit on it when that is where
/// [`shading_offset`] puts the shading, else where the ray passes
/// nearest it, with the normal of that offset ([`normal_at_offset`]).
/// WGSL twin: `cone_layer` in `shaders/render.wgsl`.
fn cone_layer<R: Real>(
    g: Geometry,
    prep: &FlatScene<R>,
    ray: &Ray<R>,
    (hit, cover): (Hit<R>, Cover<R>),
    t_end: R,
) -> ConeLayer<R> {
    let zero = R::of(0.0);
    let (ball, own) = match hit {
        Hit::Mesh(..) => return ConeLayer::whole(cover.near.t),
        Hit::Ball(i) => (true, hit_ball(g, ray, prep.balls[i].center, prep.balls[i].k, zero)),
        Hit::Tube(i) => (false, hit_tube(g, ray, &prep.tubes[i].segment, prep.tube_k, zero)),
    };
    let near = cover.near;
    let s = shading_offset(ball, cover.gap, cover.r, cover.w);
    if let Some(t_own) = own
        && t_own <= t_end
        && cover.gap <= s * cover.r
    {
        return ConeLayer {
            part: cover.part,
            t: t_own,
            normal: None,
        };
    }
    let x = g.normalize_point::<R>(ray.origin + ray.dir * near.t);
    let view = -g.normalize_tangent::<R>(x, ray.dir);
    let n0 = match hit {
        Hit::Tube(i) => normal_from::<R>(g, x, foot_on_line::<R>(g, x, &prep.tubes[i].segment)),
        Hit::Ball(i) => normal_from::<R>(g, x, prep.balls[i].center),
        Hit::Mesh(..) => view,
    };
    ConeLayer {
        part: cover.part,
        t: near.t,
        normal: Some(normal_at_offset(g, n0, view, s)),
    }
}

/// A wall on face `plane`, met at distance `dist`: [`WALL_COLOR`] lit by
/// the angle the ray meets it at (a lamp at the eye), then fog.
/// WGSL twin: `shade_wall` in `bevy_manifold_gpu`'s `shaders/rules.wgsl`.
fn shade_wall<R: Real>(prep: &FlatScene<R>, plane: &R::V4, ray: &Ray<R>, dist: R) -> [f32; 3] {
    let n = R::dot4(*plane, *plane).sqrt();
    let facing = (R::dot4(*plane, ray.dir) / (n * R::dot4(ray.dir, ray.dir).sqrt()))
        .f64()
        .abs()
        .min(1.0) as f32;
    let lit = 0.3 + 0.7 * facing;
    let rgb = WALL_COLOR.map(|c| c * lit);
    match prep.fog {
        Some((density, fog)) => {
            let keep = (-(density * dist).f64()).exp() as f32;
            [0, 1, 2].map(|i| rgb[i] * keep + fog[i] * (1.0 - keep))
        }
        None => rgb,
    }
}

/// Which object a ray hit.
#[derive(Clone, Copy, Debug)]
enum Hit<R: Real> {
    Ball(usize),
    Tube(usize),
    Mesh(usize, MeshHit<R>),
}

impl<R: Real> Hit<R> {
    fn id(self, prep: &FlatScene<R>) -> u32 {
        match self {
            Hit::Ball(i) => prep.balls[i].id,
            Hit::Tube(_) => EDGE_ID,
            Hit::Mesh(i, _) => prep.instances[i].id,
        }
    }
}

/// True when a mesh instance can be hit on a segment near `near` seen
/// from the cell of `cell_point` (not the camera's own body there).
fn instance_shown<R: Real>(inst: &FlatInstance<R>, near: u32, cell_point: R::V4) -> bool {
    may_hit(inst.face_mask, near) && !inst.home.is_some_and(|home| same_cell_point::<R>(home, cell_point))
}

/// The nearest object along the ray with chart parameter in `[0, t_end]`,
/// seen from the cell whose element takes the origin to `cell_point` (the
/// copy of a camera-attached mesh that is the camera's own body from
/// there is skipped), of those [`each_candidate`] hands out. Ties between
/// balls go to the lower index, so the order of the tests changes
/// nothing.
fn nearest_object<R: Real>(
    g: Geometry,
    prep: &FlatScene<R>,
    ray: &Ray<R>,
    t_end: R,
    cell_point: R::V4,
    (near, cull): (u32, bool),
) -> Option<(R, Hit<R>)> {
    let zero = R::of(0.0);
    let mut best: Option<(R, Hit<R>)> = None;
    each_candidate(prep, ray, t_end, ([near; 2], cull), 0.0, |c| match c {
        Candidate::Ball(i) => {
            let b = &prep.balls[i];
            if may_hit(b.face_mask, near)
                && let Some(t) = hit_ball(g, ray, b.center, b.k, zero)
                && t <= t_end
                && best.is_none_or(|(bt, h)| t < bt || (t == bt && matches!(h, Hit::Ball(j) if i < j)))
            {
                best = Some((t, Hit::Ball(i)));
            }
        }
        Candidate::Tube(i) => {
            let tube = &prep.tubes[i];
            if may_hit(tube.face_mask, near)
                && let Some(t) = hit_tube(g, ray, &tube.segment, prep.tube_k, zero)
                && t <= t_end
                && best.is_none_or(|(bt, _)| t < bt)
            {
                best = Some((t, Hit::Tube(i)));
            }
        }
        Candidate::Instance(i) => {
            let inst = &prep.instances[i];
            let limit = best.map_or(t_end, |(bt, _)| bt);
            if instance_shown(inst, near, cell_point)
                && let Some(h) = hit_instance(g, ray, inst, &prep.meshes[inst.mesh], limit)
                && h.t <= limit
            {
                best = Some((h.t, Hit::Mesh(i, h.hit)));
            }
        }
    });
    best
}

/// A thing met on a segment: where, what, and for a cone's layer what
/// it covers.
type Met<R> = (R, Hit<R>, Option<Cover<R>>);

/// Up to [`SEGMENT_LAYERS`] layers met on one segment, nearest first,
/// and the nearest thing hit whole (a mesh for a cone; anything for a
/// ray), which hides what is behind it. WGSL twin: `met_t`, `met_id` and
/// `best` in `shaders/render.wgsl`.
struct Nearest<R: Real> {
    met: [Option<Met<R>>; SEGMENT_LAYERS],
    count: usize,
    whole: Option<Met<R>>,
}

impl<R: Real> Default for Nearest<R> {
    fn default() -> Self {
        Nearest {
            met: [None; SEGMENT_LAYERS],
            count: 0,
            whole: None,
        }
    }
}

impl<R: Real> Nearest<R> {
    /// The farthest still wanted: `t_end`, or once full the farthest
    /// layer kept; never past the whole hit. WGSL twin: `met_limit`.
    fn limit(&self, t_end: R) -> R {
        let layers = match self.count {
            SEGMENT_LAYERS => self.met[SEGMENT_LAYERS - 1].map_or(t_end, |m| m.0),
            _ => t_end,
        };
        self.whole.map_or(layers, |m| m.0.min(layers))
    }

    /// Keeps the layer `m` in order, dropping the farthest when full
    /// (a tie stays ahead). WGSL twin: `keep_met`.
    fn keep(&mut self, m: Met<R>) {
        let mut at = self.count.min(SEGMENT_LAYERS - 1);
        self.met[at] = Some(m);
        while at > 0 && self.met[at - 1].is_some_and(|p| p.0 > m.0) {
            self.met.swap(at - 1, at);
            at -= 1;
        }
        self.count = (self.count + 1).min(SEGMENT_LAYERS);
    }

    /// What was met, nearest first: the layers before the whole hit (or
    /// level with it), then the whole hit.
    fn iter(&self) -> impl Iterator<Item = &Met<R>> {
        let whole = self.whole;
        self.met[..self.count]
            .iter()
            .flatten()
            .take_while(move |m| whole.is_none_or(|h| h.0 >= m.0))
            .chain(self.whole.iter())
    }
}

/// The layers of a pixel's cone on the segment of `ray` ending at
/// `t_end`, nearest first, at most [`SEGMENT_LAYERS`] (the nearest): the
/// balls and tubes that the ray's geodesic passes within their radius
/// grown by `grow` of ([`approach`], [`Approach::within`]), by where it
/// passes nearest, in `[0, t_end]` (a tube's only where the
/// perpendicular's foot lies on its edge), and that cover some of the
/// pixel ([`Cover`]); and the first mesh hit, whole, by its hit. Each
/// object passes nearest the ray at one point of the cover, so it is one
/// layer on one segment whichever copies of the domain its grown shape
/// reaches into. The boxes of the ball tree are padded by the balls'
/// growth times [`super::FaceTables::chart_stretch`]. WGSL twin:
/// `segment_layers` in `shaders/render.wgsl`.
fn segment_layers<R: Real>(
    g: Geometry,
    prep: &FlatScene<R>,
    ray: &Ray<R>,
    t_end: R,
    cell_point: R::V4,
    ([near_balls, near], cull): ([u32; 2], bool),
    (grow, beta, travelled): (&Inflation<R>, R, R),
) -> Nearest<R> {
    let zero = R::of(0.0);
    let mut met = Nearest::<R>::default();
    // An object the grown test lets through covers part of the pixel
    // with the footprint where the ray passes it, which may be none.
    let cover = |a: Approach<R>, end: R, grown: R, k: R, tube: Option<&Segment<R>>| {
        if !(a.t >= zero && a.t <= end && a.within(g, grown)) {
            return None;
        }
        let w = (beta * spread(g, travelled + g.chart_to_distance::<R>(a.t))).min(grow.w);
        let r = radius_of(g, k);
        let length = tube.map_or(zero, |seg| g.distance::<R>(seg.a, seg.b));
        let gap = a.gap(g);
        let part = coverage(tube.is_none(), gap, r, length, w) * side_by_side(w, prep.cell_shadow);
        let part = part.min(R::of(1.0)).f64() as f32;
        (part > 0.0).then_some(Cover {
            near: a,
            gap,
            w,
            r,
            part,
        })
    };
    let pad = (grow.w * R::of(BALL_GROWTH) * prep.faces.chart_stretch).f64() as f32;
    let tube_k = grow.k(g, prep.tube_k);
    each_candidate(prep, ray, t_end, ([near_balls, near], cull), pad, |c| {
        let end = met.limit(t_end);
        match c {
            Candidate::Ball(i) => {
                let b = &prep.balls[i];
                if may_hit(b.face_mask, near_balls)
                    && let Some(c) = cover(ball_approach(g, ray, b.center), end, grow.ball_k(g, b.k), b.k, None)
                {
                    met.keep((c.near.t, Hit::Ball(i), Some(c)));
                }
            }
            Candidate::Tube(i) => {
                let seg = &prep.tubes[i].segment;
                if may_hit(prep.tubes[i].face_mask, near) {
                    let a = tube_approach(g, ray, seg);
                    if on_edge(g, ray.origin + ray.dir * a.t, seg)
                        && let Some(c) = cover(a, end, tube_k, prep.tube_k, Some(seg))
                    {
                        met.keep((a.t, Hit::Tube(i), Some(c)));
                    }
                }
            }
            Candidate::Instance(i) => {
                let inst = &prep.instances[i];
                if instance_shown(inst, near, cell_point)
                    && let Some(h) = hit_instance(g, ray, inst, &prep.meshes[inst.mesh], end)
                    && h.t <= end
                {
                    met.whole = Some((h.t, Hit::Mesh(i, h.hit), None));
                }
            }
        }
    });
    met
}

/// A light nearer a hit than this (`|tangent towards it|^2`) is on the hit
/// point: `toward_light` lights it along the normal.
/// WGSL twin: `LIGHT_AT_HIT` in `shaders/bindings.wgsl`.
pub const LIGHT_AT_HIT: f64 = 1e-10;

/// The unit tangent at `x` towards the light at `l`; `normal` when the
/// light is on `x` (or, in S3, at its antipode), where the direction is
/// 0 / 0 and `normalize_tangent` would give NaN.
/// WGSL twin: `toward_light` in `shaders/render.wgsl`.
fn toward_light<R: Real>(g: Geometry, x: R::V4, l: R::V4, normal: R::V4) -> R::V4 {
    let t = g.project_tangent::<R>(x, l);
    let len2 = g.form::<R>(t, t).abs();
    if len2.f64() > LIGHT_AT_HIT {
        t * (R::of(1.0) / len2.sqrt())
    } else {
        normal
    }
}

/// Lambert + Blinn shading at the hit (chart parameter `t`, with the
/// object's normal there unless `normal_at` gives another: a cone's
/// layer, see `cone_layer`), lights with geometry-correct fall-off
/// (1 / area of the sphere of radius d), per-cell colour, fog.
#[expect(clippy::too_many_arguments, reason = "the shading inputs are all distinct")]
fn shade<R: Real>(
    g: Geometry,
    prep: &FlatScene<R>,
    ray: &Ray<R>,
    (t, normal_at): (R, Option<R::V4>),
    hit: Hit<R>,
    dist: R,
    cell: CellId,
    settings: &TraceSettings,
) -> [f32; 3] {
    let x = g.normalize_point::<R>(ray.origin + ray.dir * t);
    let view = -g.normalize_tangent::<R>(x, ray.dir);
    let (normal, albedo, glow) = match hit {
        Hit::Ball(i) => (
            normal_from::<R>(g, x, prep.balls[i].center),
            prep.balls[i].color,
            prep.balls[i].glow,
        ),
        Hit::Tube(i) => {
            let seg = &prep.tubes[i].segment;
            (
                normal_from::<R>(g, x, foot_on_line::<R>(g, x, seg)),
                prep.tubes[i].color,
                0.0,
            )
        }
        Hit::Mesh(i, h) => {
            let inst = &prep.instances[i];
            (
                mesh_normal(g, inst, &prep.meshes[inst.mesh], &h, x, view),
                mesh_albedo(prep, inst, &h),
                0.0,
            )
        }
    };
    let normal = normal_at.unwrap_or(normal);
    let mut albedo = albedo;
    if settings.cell_colors {
        let c = settings.cell_tint.tint(cell);
        albedo = [albedo[0] * c[0], albedo[1] * c[1], albedo[2] * c[2]];
    }
    // Ambient light and the object's own glow. WGSL twin: `shade` in
    // render.wgsl.
    let ambient = 0.08f32 + glow;
    let mut rgb = [albedo[0] * ambient, albedo[1] * ambient, albedo[2] * ambient];
    for l in &prep.lights {
        let d = g.distance::<R>(x, l.position);
        let to_light = toward_light::<R>(g, x, l.position, normal);
        let area = g.sphere_area::<R>(d).max(R::of(1e-4));
        let irradiance = (l.intensity / area).f64() as f32;
        let lambert = g.form::<R>(normal, to_light).max(R::of(0.0)).f64() as f32;
        let half = to_light + view;
        let hl = g.form::<R>(half, half).sqrt();
        let spec = if hl.f64() > 1e-12 {
            (g.form::<R>(normal, half) / hl).max(R::of(0.0)).f64().powi(32) as f32 * 0.35
        } else {
            0.0
        };
        for c in 0..3 {
            rgb[c] += (albedo[c] * lambert + spec) * irradiance * l.color[c];
        }
    }
    if let Some((density, fog_color)) = prep.fog {
        let tr = (-(density * dist)).exp().f64() as f32;
        for c in 0..3 {
            rgb[c] = rgb[c] * tr + fog_color[c] * (1.0 - tr);
        }
    }
    rgb
}
