//! Cone tracing in the walk (settings' `footprint`): what a pixel's
//! cone does on each segment, on top of the footprint's geometry
//! ([`super::footprint`]). Each segment grows the objects by its widest
//! footprint and tests them near the faces it comes near
//! ([`SegmentReach`]); each ball or tube the cone passes within its grown
//! radius of covers a part of the pixel ([`Cover`], [`cover`]), a layer
//! shaded where the ray passes it ([`ConeLayer`], [`cone_layer`]); the
//! layers are kept nearest first ([`super::nearest::Nearest`]) and added
//! front to back ([`super::footprint::Layers`]) by `trace_ray`.
//!
//! WGSL twin: `shaders/cone.wgsl` in `bevy_manifold_gpu` (the same
//! names), compiled under the `FOOTPRINT` def.

use super::flat::FlatScene;
use super::footprint::{
    Approach, BALL_GROWTH, Inflation, coverage, grown_reach, normal_at_offset, radius_of, shading_offset, side_by_side,
    spread, widest_spread,
};
use super::nearest::Hit;
use super::settings::TraceSettings;
use super::step::{ALL_FACES, Ray, Segment, foot_on_line, hit_ball, hit_tube, near_faces, normal_from};
use crate::geometry::{Geometry, Real};

/// A layer of a pixel's cone: the part of the pixel it covers, where it
/// is shaded, and the normal there when that is not the object's own at
/// the ray's hit.
pub(super) struct ConeLayer<R: Real> {
    /// The part of the pixel it covers.
    pub(super) part: f32,
    /// The chart parameter where it is shaded.
    pub(super) t: R,
    /// The normal there, when not the object's own.
    pub(super) normal: Option<R::V4>,
}

impl<R: Real> ConeLayer<R> {
    /// All of the pixel, shaded where the ray hit: a ray's hit.
    pub(super) fn whole(t: R) -> Self {
        ConeLayer {
            part: 1.0,
            t,
            normal: None,
        }
    }
}

/// What a ball or tube met by a pixel's cone covers: where the ray
/// passes nearest it ([`super::footprint::approach`]), the footprint there (`beta` times
/// [`spread`] of the distance from the eye), the object's radius and the
/// part of the pixel it covers ([`coverage`]). WGSL twin: `Cover` in
/// `shaders/cone.wgsl`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Cover<R: Real> {
    /// Where the ray passes nearest the object.
    pub(super) near: Approach<R>,
    gap: R,
    w: R,
    r: R,
    part: f32,
}

/// Where a layer is shaded (`Cover`'s object `hit`, on the segment
/// ending at `t_end`): at the ray's own hit on it when that is where
/// [`shading_offset`] puts the shading, else where the ray passes
/// nearest it, with the normal of that offset ([`normal_at_offset`]).
/// WGSL twin: `cone_layer` in `shaders/cone.wgsl`.
pub(super) fn cone_layer<R: Real>(
    g: Geometry,
    flat: &FlatScene<R>,
    ray: &Ray<R>,
    (hit, cover): (Hit<R>, Cover<R>),
    t_end: R,
) -> ConeLayer<R> {
    let zero = R::of(0.0);
    let (ball, own) = match hit {
        Hit::Mesh(..) => return ConeLayer::whole(cover.near.t),
        Hit::Ball(i) => (true, hit_ball(g, ray, flat.balls[i].center, flat.balls[i].k, zero)),
        Hit::Tube(i) => (false, hit_tube(g, ray, &flat.tubes[i].segment, flat.tube_k, zero)),
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
        Hit::Tube(i) => normal_from::<R>(g, x, foot_on_line::<R>(g, x, &flat.tubes[i].segment)),
        Hit::Ball(i) => normal_from::<R>(g, x, flat.balls[i].center),
        Hit::Mesh(..) => view,
    };
    ConeLayer {
        part: cover.part,
        t: near.t,
        normal: Some(normal_at_offset(g, n0, view, s)),
    }
}

/// What an object the grown test may let through covers of the pixel
/// (a ball's when `tube` is `None`): none unless the ray passes nearest
/// it at `a`, in `[0, end]`, within its `k` grown to `grown`; else the
/// footprint there (`beta` times [`spread`] of the distance from the eye,
/// never wider than the segment's growth), its radius and the part of
/// the pixel it covers, which may be none. WGSL twin: `cover`.
#[expect(clippy::too_many_arguments, reason = "the cover's inputs are all distinct")]
pub(super) fn cover<R: Real>(
    g: Geometry,
    flat: &FlatScene<R>,
    a: Approach<R>,
    end: R,
    grown: R,
    k: R,
    tube: Option<&Segment<R>>,
    (grow, beta, travelled): (&Inflation<R>, R, R),
) -> Option<Cover<R>> {
    let zero = R::of(0.0);
    if !(a.t >= zero && a.t <= end && a.within(g, grown)) {
        return None;
    }
    let w = (beta * spread(g, travelled + g.chart_to_distance::<R>(a.t))).min(grow.w);
    let r = radius_of(g, k);
    let length = tube.map_or(zero, |seg| g.distance::<R>(seg.a, seg.b));
    let gap = a.gap(g);
    let part = coverage(tube.is_none(), gap, r, length, w) * side_by_side(w, flat.cell_shadow);
    let part = part.min(R::of(1.0)).f64() as f32;
    (part > 0.0).then_some(Cover {
        near: a,
        gap,
        w,
        r,
        part,
    })
}

/// How one segment of a pixel's walk tests objects: the cone's growth
/// over it and the faces it comes near.
pub(super) struct SegmentReach<R: Real> {
    /// Objects grown by the segment's widest footprint (at most the
    /// cap); nothing grows for a ray.
    pub(super) grow: Inflation<R>,
    /// The faces the segment comes near ([`near_faces`]), for balls
    /// (grown [`BALL_GROWTH`] footprints) and for tubes and meshes (one);
    /// every face without culling.
    pub(super) near: [u32; 2],
}

impl<R: Real> SegmentReach<R> {
    /// The reach of the segment of `ray` ending at `t_end`, `travelled`
    /// from the eye, for a cone of half-angle `beta` (`None`: a ray).
    /// WGSL twin: the start of each segment in `trace_ray`
    /// (`shaders/trace.wgsl`), which sets `cone_grow` and `near_balls`
    /// (`shaders/cone.wgsl`).
    pub(super) fn new(
        flat: &FlatScene<R>,
        settings: &TraceSettings,
        beta: Option<R>,
        travelled: R,
        (ray, t_end): (&Ray<R>, R),
    ) -> Self {
        let g = flat.faces.geometry;
        let w = beta.map_or(R::of(0.0), |b| {
            let end = travelled + g.chart_to_distance::<R>(t_end);
            (b * widest_spread(g, travelled, end)).min(flat.footprint_cap)
        });
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
                grown_reach(g, flat.near_distance, growth)
            } else {
                flat.near_reach
            };
            near_faces(&flat.faces.planes, flat.faces.near_scale, reach, ray, t_end)
        };
        let near = if w > R::of(0.0) {
            [near_within(w * R::of(BALL_GROWTH)), near_within(w)]
        } else {
            [near_within(w); 2]
        };
        SegmentReach { grow, near }
    }
}
