//! Algorithm 1 for one ray (see [`crate::trace`]): on each segment of its
//! walk through the faces ([`Walker`]), the objects the segment may meet
//! ([`each_candidate`]), the nearest of them for a ray or a cone's layers
//! ([`super::nearest`], [`super::cone`]), shaded ([`super::shade`]) and
//! added front to back; else on through the exit face.
//!
//! WGSL twin: `shaders/trace.wgsl` in `bevy_manifold_gpu` (`trace_ray`,
//! `nearest_object`, `segment_layers`).

use super::camera::pixel_half_angle_of;
use super::cone::{ConeLayer, Cover, SegmentReach, cone_layer, cover};
use super::cull::{Candidate, each_candidate};
use super::exact_cell::{ExactCell, TableRef};
use super::flat::FlatScene;
use super::footprint::{Approach, BALL_GROWTH, Inflation, Layers, ball_approach, tube_approach};
use super::mesh_hit::hit_instance;
use super::nearest::{Hit, Nearest, instance_shown};
use super::settings::MAX_REFLECTIONS;
use super::settings::TraceSettings;
use super::shade::{Mirror, shade, shade_wall};
use super::step::{Ray, Segment, advance_or_raw, hit_ball, hit_tube, may_hit, on_edge};
use super::walk::Walker;
use crate::geometry::{Geometry, Real};
use crate::space::Space;
use crate::space::cells::CellId;
use crate::space::rule::WALL_OBJECT;

/// ln 255: once fog density times the distance travelled passes it, fog
/// has left less than 1/255 of an object's light and the ray may stop.
/// WGSL twin: `FOG_CUT` in `shaders/trace.wgsl`.
pub const FOG_CUT: f64 = 5.541_263_545_158_426;

/// Crossings per ray the CPU tracer follows exactly (the exact ids of
/// [`crate::space::exact`], the cell rules); past them the walk's `f64`
/// or `f32` matrix names the cells, as in spaces without exact ids.
pub const MAX_EXACT_LEVELS: u32 = 64;

/// What one pixel saw.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TracePixel {
    /// Linear RGB.
    pub color: [f32; 3],
    /// 0 nothing, `k` the k-th ball of the scene, [`super::EDGE_ID`] a domain edge.
    pub object: u32,
    /// Face crossings before the hit (or before the ray stopped).
    pub levels: u32,
    /// The copy of the domain the ray ended in.
    pub cell: CellId,
    /// Distance travelled to the hit (or to where the ray stopped).
    pub distance: f32,
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

/// Traces one ray through the manifold (Algorithm 1): nearest object in the
/// domain, else the exit face; transport through its pairing; repeat. Calls
/// `on_step` for every segment. With [`TraceSettings::reflections`] the ray
/// goes on off each surface with a material ([`trace_path`]). Returns the
/// pixel and why the ray stopped.
///
/// WGSL twin: `trace_ray` in `shaders/trace.wgsl`.
pub fn trace_ray<R: Real>(
    space: &Space,
    flat: &FlatScene<R>,
    ray: Ray<R>,
    settings: &TraceSettings,
    on_step: &mut dyn FnMut(&PathStep<R>),
) -> (TracePixel, Stop) {
    trace_path(space, flat, ray, settings, on_step, &mut |_, _| {})
}

/// [`trace_ray`], calling `on_leg` with what each leg of the path saw:
/// the camera's ray first, then each reflected ray, up to
/// [`TraceSettings::reflections`] of them. A leg ends at an object: where its
/// surface has a material ([`crate::material::Pbr`]) and reflections are
/// left, the next leg leaves it along the mirror direction
/// ([`super::Mirror`]), from the same copy of the domain, with a fresh
/// budget of levels and the distance so far (for the fog). The pixel
/// names the first leg's object, cell and distance; its colour adds each
/// leg's, weighted by the reflectances before it, in front of the fog:
/// `c_0 + w_1 (c_1 - fog (1 - f_1)) + w_1 w_2 (c_2 - fog (1 - f_2)) + ...`,
/// `f_i` the fog's transmittance to the `i`-th mirror.
///
/// WGSL twin: the `REFLECTIONS` loop of `trace_ray` in `shaders/trace.wgsl`.
pub fn trace_path<R: Real>(
    space: &Space,
    flat: &FlatScene<R>,
    ray: Ray<R>,
    settings: &TraceSettings,
    on_step: &mut dyn FnMut(&PathStep<R>),
    on_leg: &mut dyn FnMut(&TracePixel, Stop),
) -> (TracePixel, Stop) {
    let table = TableRef::of(space, flat);
    let exact = ExactCell::start(table, flat, settings.cell_rule.is_active());
    let walk = Walker::new(ray, R::m4_of(flat.camera_cell));
    let (mut pixel, stop, mut reflection) = trace_leg(space, flat, (walk, exact, R::of(0.0)), settings, on_step);
    on_leg(&pixel, stop);
    let fog = flat.fog.map_or([0.0; 3], |(_, c)| c);
    let mut weight = [1.0f32; 3];
    for _ in 0..settings.reflections.min(MAX_REFLECTIONS) {
        let Some(b) = reflection.take() else { break };
        for (w, m) in weight.iter_mut().zip(b.mirror.weight) {
            *w *= m;
        }
        let walk = Walker::new(b.mirror.ray, b.cell);
        let (leg, stop, next) = trace_leg(space, flat, (walk, b.exact, b.travelled), settings, on_step);
        on_leg(&leg, stop);
        for c in 0..3 {
            pixel.color[c] += weight[c] * (leg.color[c] - fog[c] * (1.0 - b.mirror.fog_kept));
        }
        reflection = next;
    }
    (pixel, stop)
}

/// Where a leg of a path ends on a surface that reflects: its mirror, the
/// cell it is in and the distance travelled to it. WGSL twin: `Reflection`
/// in `shaders/trace.wgsl`.
struct Reflection<R: Real> {
    mirror: Mirror<R>,
    cell: R::M4,
    exact: ExactCell,
    travelled: R,
}

/// One leg of a path (Algorithm 1 from `walk`, the cell's exact element
/// `exact`, having travelled `travelled`): the pixel it sees, why it
/// stopped and, when it ends on a surface that reflects, the reflection.
/// WGSL twin: `trace_leg` in `shaders/trace.wgsl`.
fn trace_leg<R: Real>(
    space: &Space,
    flat: &FlatScene<R>,
    (mut walk, mut exact, mut travelled): (Walker<R>, ExactCell, R),
    settings: &TraceSettings,
    on_step: &mut dyn FnMut(&PathStep<R>),
) -> (TracePixel, Stop, Option<Reflection<R>>) {
    let g = flat.faces.geometry;
    let fog_cut = R::of(FOG_CUT);
    let max_distance = R::of(settings.max_distance);
    // Where the space's ids are exact, or rules are on, the walk's cell
    // (by the table around the camera, then by exact elements), crossed
    // with the ray; otherwise the id comes from the walk's matrix.
    let rule = &settings.cell_rule;
    let table = TableRef::of(space, flat);
    let cell_id = |walk: &Walker<R>, exact: &ExactCell| exact.id(table, space, walk);
    let background = flat.fog.map_or([0.0; 3], |(_, c)| c);
    // Cone tracing (settings.footprint): the pixel's half-angle, the
    // layers met so far, and the first layer covering half the pixel or
    // more, which names the pixel's object and depth.
    let beta = settings.footprint.then(|| R::of(pixel_half_angle_of(flat, settings)));
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
        if let Some((density, _)) = flat.fog
            && settings.fog_early_stop
            && density * travelled > fog_cut
        {
            let behind = pixel(background, 0, &walk, &exact, travelled);
            return (finish(&layers, front, behind), Stop::Fog, None);
        }
        let (face, t_end) = walk.segment_end(&flat.faces);
        let cell_point = walk.cell * R::v4_of(glam::DVec4::W);
        let here = rule.is_active().then(|| cell_id(&walk, &exact));
        let shown = here.is_none_or(|id| rule.visible(id));
        // Objects grow by the segment's widest footprint (cones), and are
        // tested only near the faces the segment comes near.
        let reach = SegmentReach::new(flat, settings, beta, travelled, (&walk.ray, t_end));
        // Each object met on the segment, nearest first: for a ray the
        // first hit, whole; for a cone each object it passes within its
        // footprint of, in the order of the ray's nearest approach, a
        // layer covering part of the pixel.
        let met = match (beta, shown) {
            (_, false) => Nearest::default(),
            (Some(b), true) => segment_layers(
                g,
                flat,
                &walk.ray,
                t_end,
                cell_point,
                (reach.near, settings.cull),
                (&reach.grow, b, travelled),
            ),
            (None, true) => nearest_object(g, flat, &walk.ray, t_end, cell_point, (reach.near[0], settings.cull)),
        };
        for &(t, hit, cover) in met.iter() {
            let layer = match cover {
                Some(c) => cone_layer(g, flat, &walk.ray, (hit, c), t_end),
                None => ConeLayer::whole(t),
            };
            let dist = travelled + g.chart_to_distance::<R>(layer.t);
            let cell = cell_id(&walk, &exact);
            let (color, mirror) = shade(
                g,
                flat,
                &walk.ray,
                (layer.t, layer.normal),
                hit,
                dist,
                (cell, walk.cell),
                settings,
            );
            let part = layer.part;
            let this = TracePixel {
                color,
                object: hit.id(flat),
                levels: walk.levels,
                cell,
                distance: dist.f64() as f32,
            };
            if part >= 0.5 && front.is_none() {
                front = Some(this);
            }
            // The share of the pixel this layer takes, if it is the last.
            let left = layers.left;
            if layers.add(color, part) {
                // What it reflects is seen in its share of the pixel.
                let reflection = mirror.map(|m| Reflection {
                    mirror: Mirror {
                        weight: m.weight.map(|w| w * left),
                        ..m
                    },
                    cell: walk.cell,
                    exact,
                    travelled: dist,
                });
                return (finish(&layers, front, this), Stop::Hit(hit.id(flat)), reflection);
            }
            if layers.full() {
                let behind = pixel(background, 0, &walk, &exact, travelled);
                return (finish(&layers, front, behind), Stop::MaxLevel, None);
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
            return (finish(&layers, front, behind), Stop::MaxDistance, None);
        }
        // The cell across the face, crossed once: for the wall test, then
        // for the walk.
        let next = match face {
            Some(f) if rule.walls.is_some() && !exact.is_off() => Some(exact.crossed(table, space, flat, f)),
            _ => None,
        };
        if let (Some(id), Some(n)) = (here, &next)
            && rule.wall(id, n.id(table, space, &walk))
        {
            let f = face.unwrap_or_default();
            let color = shade_wall(flat, &flat.faces.planes[f], &walk.ray, travelled);
            let wall = pixel(color, WALL_OBJECT, &walk, &exact, travelled);
            layers.add(color, 1.0);
            return (finish(&layers, front, wall), Stop::Hit(WALL_OBJECT), None);
        }
        if face.is_some() && walk.levels >= settings.levels {
            let behind = pixel(background, 0, &walk, &exact, travelled);
            return (finish(&layers, front, behind), Stop::MaxLevel, None);
        }
        walk.step(&flat.faces, face, end, settings.renormalize);
        if let Some(f) = face
            && !exact.is_off()
        {
            exact = next.unwrap_or_else(|| exact.crossed(table, space, flat, f));
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
    (finish(&layers, front, behind), Stop::MaxDistance, None)
}

/// The nearest object along the ray with chart parameter in `[0, t_end]`,
/// seen from the cell whose element takes the origin to `cell_point` (the
/// copy of a camera-attached mesh that is the camera's own body from
/// there is skipped), of those [`each_candidate`] hands out. Ties between
/// balls go to the lower index, so the order of the tests changes
/// nothing. WGSL twin: `nearest_object` in `shaders/trace.wgsl`. Its arms
/// are `consider_ball`, `consider_tube` and `consider_instance` in
/// `shaders/nearest.wgsl`.
pub(super) fn nearest_object<R: Real>(
    g: Geometry,
    flat: &FlatScene<R>,
    ray: &Ray<R>,
    t_end: R,
    cell_point: R::V4,
    (near, cull): (u32, bool),
) -> Nearest<R, Cover<R>> {
    let zero = R::of(0.0);
    let mut best: Option<(R, Hit<R>)> = None;
    each_candidate(flat, ray, t_end, ([near; 2], cull), 0.0, |c| {
        match c {
            Candidate::Ball(i) => {
                let b = &flat.balls[i];
                if may_hit(b.face_mask, near)
                    && let Some(t) = hit_ball(g, ray, b.center, b.k, zero)
                    && t <= t_end
                    && best.is_none_or(|(bt, h)| t < bt || (t == bt && matches!(h, Hit::Ball(j) if i < j)))
                {
                    best = Some((t, Hit::Ball(i)));
                }
            }
            Candidate::Tube(i) => {
                let tube = &flat.tubes[i];
                if may_hit(tube.face_mask, near)
                    && let Some(t) = hit_tube(g, ray, &tube.segment, flat.tube_k, zero)
                    && t <= t_end
                    && best.is_none_or(|(bt, _)| t < bt)
                {
                    best = Some((t, Hit::Tube(i)));
                }
            }
            Candidate::Instance(i) => {
                let inst = &flat.instances[i];
                let limit = best.map_or(t_end, |(bt, _)| bt);
                if instance_shown(inst, near, cell_point)
                    && let Some(h) = hit_instance(g, flat, ray, inst, limit)
                    && h.t <= limit
                {
                    best = Some((h.t, Hit::Mesh(i, h.hit)));
                }
            }
        }
        best.map_or(t_end, |(bt, _)| bt)
    });
    let mut met = Nearest::default();
    met.whole = best.map(|(t, h)| (t, h, None));
    met
}

/// The layers of a pixel's cone on the segment of `ray` ending at
/// `t_end`, nearest first, at most [`SEGMENT_LAYERS`] (the nearest): the
/// balls and tubes that the ray's geodesic passes within their radius
/// grown by `grow` of ([`super::footprint::approach`], [`Approach::within`]), by where it
/// passes nearest, in `[0, t_end]` (a tube's only where the
/// perpendicular's foot lies on its edge), and that cover some of the
/// pixel ([`cover`]); and the first mesh hit, whole, by its hit. Each
/// object passes nearest the ray at one point of the cover, so it is one
/// layer on one segment whichever copies of the domain its grown shape
/// reaches into. The boxes of the ball tree are padded by the balls'
/// growth times [`super::FaceTables::chart_stretch`]. WGSL twin:
/// `segment_layers` in `shaders/trace.wgsl`. The cone's arms are the
/// `FOOTPRINT` branches of `consider_ball` and `consider_tube` in
/// `shaders/nearest.wgsl`.
fn segment_layers<R: Real>(
    g: Geometry,
    flat: &FlatScene<R>,
    ray: &Ray<R>,
    t_end: R,
    cell_point: R::V4,
    ([near_balls, near], cull): ([u32; 2], bool),
    (grow, beta, travelled): (&Inflation<R>, R, R),
) -> Nearest<R, Cover<R>> {
    let mut met = Nearest::default();
    let cover = |a: Approach<R>, end: R, grown: R, k: R, tube: Option<&Segment<R>>| {
        cover(g, flat, a, end, grown, k, tube, (grow, beta, travelled))
    };
    let pad = (grow.w * R::of(BALL_GROWTH) * flat.faces.chart_stretch).f64() as f32;
    let tube_k = grow.k(g, flat.tube_k);
    each_candidate(flat, ray, t_end, ([near_balls, near], cull), pad, |c| {
        let end = met.limit(t_end);
        match c {
            Candidate::Ball(i) => {
                let b = &flat.balls[i];
                if may_hit(b.face_mask, near_balls)
                    && let Some(c) = cover(ball_approach(g, ray, b.center), end, grow.ball_k(g, b.k), b.k, None)
                {
                    met.keep((c.near.t, Hit::Ball(i), Some(c)));
                }
            }
            Candidate::Tube(i) => {
                let seg = &flat.tubes[i].segment;
                if may_hit(flat.tubes[i].face_mask, near) {
                    let a = tube_approach(g, ray, seg);
                    if on_edge(g, ray.origin + ray.dir * a.t, seg)
                        && let Some(c) = cover(a, end, tube_k, flat.tube_k, Some(seg))
                    {
                        met.keep((a.t, Hit::Tube(i), Some(c)));
                    }
                }
            }
            Candidate::Instance(i) => {
                let inst = &flat.instances[i];
                if instance_shown(inst, near, cell_point)
                    && let Some(h) = hit_instance(g, flat, ray, inst, end)
                    && h.t <= end
                {
                    met.whole = Some((h.t, Hit::Mesh(i, h.hit), None));
                }
            }
        }
        met.limit(t_end)
    });
    met
}
