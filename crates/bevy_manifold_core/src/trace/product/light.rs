//! Lights in the product spaces: point lights, each seen as every image
//! of it that lights the prism (the light is a function on the space, so
//! a point is lit by every copy `g p` of a light at `p`, `g` in the
//! group), each along its geodesic (in S2xR also the long way round the
//! sphere), with the exact fall-off of the product metric
//! ([`ProductGeometry::light_area`]), the light's range, the fog on the
//! way, and only where no ball stands in the way ([`shadowed`]).
//!
//! The images are found as for the other spaces
//! ([`crate::trace::light_images()`]): at most [`ProductLighting::images`]
//! of each light, nearest the prism first; when more lie within its range
//! the range is cut to the nearest image left out, so the sum is exact
//! for the light as cut, whichever point of the prism it lights, and
//! continuous across every face.
//!
//! The GPU reads the images as the `bevy_manifold_gpu` crate packs them
//! (`GpuProductScene::pack_lights`); its `product.wgsl` lights a hit
//! with the twins of [`direct`], [`arc_irradiance`] and [`shadowed`].
//!
//! ```
//! use bevy_manifold_core::geometry::product::ProductPoint;
//! use bevy_manifold_core::space::product::ProductSpace;
//! use bevy_manifold_core::trace::product::{ProductLight, ProductLighting, light_images};
//! // S2 x S1 of circle 2: a light's images lie every 2 up and down the
//! // circle; with a range of 5 those nearer than 5 to the prism (whose
//! // heights run from -1 to 1) light it.
//! let space = ProductSpace::s2_x_s1(2.0);
//! let light = ProductLight { range: Some(5.0), ..ProductLight::point(ProductPoint::ORIGIN, 10.0) };
//! let images = light_images(&space, &[light], ProductLighting::default());
//! let mut heights: Vec<f64> = images.iter().map(|i| i.position.height).collect();
//! heights.sort_by(f64::total_cmp);
//! assert_eq!(heights, [-4.0, -2.0, 0.0, 2.0, 4.0]);
//! ```

use super::{ProductObjects, ProductRay, advance, entries, reach, walk_segments};
use crate::geometry::product::{ProductGeometry, ProductIsometry, ProductPoint, ProductTangent};
use crate::space::product::ProductSpace;
use glam::DVec3;

/// A point light in a product space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProductLight {
    /// Where it is, in the prism.
    pub position: ProductPoint,
    /// Its power: the irradiance at distance `d` is `intensity /
    /// light_area(d, ..)` ([`ProductGeometry::light_area`]; `4 pi d^2`
    /// near the light).
    pub intensity: f64,
    /// Linear RGB colour.
    pub color: [f32; 3],
    /// How far its light reaches (a smooth cut-off, as Bevy's
    /// `PointLight::range`); `None`: as far as [`ProductLighting::images`]
    /// images of it allow.
    pub range: Option<f64>,
    /// Its radius: nearer than this the irradiance stays that of its
    /// surface (and where an S2's rays refocus it is capped so). 0: a
    /// point.
    pub radius: f64,
    /// A spot light's cone; `None`: it shines every way.
    pub spot: Option<ProductSpot>,
}

/// A spot light's cone, as Bevy's `SpotLight` has it: full within
/// `inner` of its axis, none past `outer`, a smoothstep between; the
/// angle is that at the light between the axis and the geodesic leaving
/// it towards the lit point (each image's axis turned as its isometry
/// turns the light).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProductSpot {
    /// Where it points: a tangent at the light (made unit).
    pub axis: ProductTangent,
    /// The full cone's half-angle, radians.
    pub inner: f64,
    /// The outer cone's half-angle, radians.
    pub outer: f64,
}

impl ProductSpot {
    /// The share of its light a geodesic leaving it at cosine `cos` from
    /// the axis carries: `smoothstep(cos outer, cos inner, cos)`. WGSL
    /// twin: `spot_share` in `product.wgsl`.
    #[must_use]
    pub fn share(cos_inner: f64, cos_outer: f64, cos: f64) -> f64 {
        if cos_inner <= cos_outer {
            return if cos >= cos_outer { 1.0 } else { 0.0 };
        }
        let t = ((cos - cos_outer) / (cos_inner - cos_outer)).clamp(0.0, 1.0);
        t * t * (3.0 - 2.0 * t)
    }
}

impl ProductLight {
    /// A white point light with no range of its own and no size.
    #[must_use]
    pub fn point(position: ProductPoint, intensity: f64) -> Self {
        Self {
            position,
            intensity,
            color: [1.0; 3],
            range: None,
            radius: 0.0,
            spot: None,
        }
    }
}

/// How a product scene's lights light it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ProductLighting {
    /// Most images of each light (at most [`MAX_PRODUCT_LIGHT_IMAGES`]
    /// in all); 0: the light's copy in the prism alone, with no cut-off.
    pub images: u32,
    /// Whether the balls cast shadows.
    pub shadows: bool,
}

impl Default for ProductLighting {
    /// 32 images of each light, with shadows.
    fn default() -> Self {
        Self {
            images: 32,
            shadows: true,
        }
    }
}

/// One image of a light, as the tracers read it.
/// GPU twin: `GpuProductLight` (of the `bevy_manifold_gpu` crate).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProductLightImage {
    /// Where it is, in the frame of the prism.
    pub position: ProductPoint,
    /// Its light's power.
    pub intensity: f64,
    /// Its light's colour.
    pub color: [f32; 3],
    /// `1 / range^2` of the range the images are complete to; 0: no
    /// cut-off.
    pub inv_range_sq: f64,
    /// The least area its power spreads over (its light's size).
    pub min_area: f64,
    /// A spot's unit axis at this image (its light's turned by the
    /// image's isometry), and the cosines of its inner and outer angles;
    /// `None` for a point light.
    pub spot: Option<(ProductTangent, f64, f64)>,
}

/// Most light images a product scene holds.
pub const MAX_PRODUCT_LIGHT_IMAGES: usize = 256;

/// The least area a point light's power spreads over
/// (`intensity / MIN_AREA` is the brightest irradiance).
const MIN_AREA: f64 = 1e-4;

/// How far a shadow ray starts off the surface, along its normal, so that
/// in `f32` it does not meet the ball it leaves. WGSL twin:
/// `SHADOW_OFFSET` in `product.wgsl`.
pub const SHADOW_OFFSET: f64 = 1e-4;

/// The dim light a hit may take without walking its shadows, per colour
/// channel (before the eye's fog): arcs whose light adds less than what
/// is left of this, nearest images first, are taken at half their light,
/// neither walked nor dropped, so the colour is off by at most half of
/// it (1/255) whatever stands in their way. Most of a genus-2 surface's
/// 64 arcs are far dimmer than that, its light falling off as `sinh`.
/// WGSL twin: `DIM_LIGHT` in `product.wgsl`.
pub const DIM_LIGHT: f32 = 2.0 / 255.0;

/// Most copies of the prism [`light_images`] walks through per light.
const MAX_WALK: usize = 50_000;

/// Each light of `lights` as the images of it that light the prism under
/// `lighting` (see the module): the light's own copy alone when
/// `lighting.images` is 0. At most [`MAX_PRODUCT_LIGHT_IMAGES`] in all:
/// each light keeps `min(images, MAX_PRODUCT_LIGHT_IMAGES / lights)`.
#[must_use]
pub fn light_images(
    space: &ProductSpace,
    lights: &[ProductLight],
    lighting: ProductLighting,
) -> Vec<ProductLightImage> {
    let g = space.geometry;
    let lights = &lights[..lights.len().min(MAX_PRODUCT_LIGHT_IMAGES)];
    let spot = |l: &ProductLight, m: &ProductIsometry, at: ProductPoint| {
        l.spot
            .filter(|s| s.axis.length(g) > 0.0 && s.inner.is_finite() && s.outer.is_finite())
            .map(|s| {
                let axis = g.normalize_tangent(at, m.apply_tangent(s.axis));
                let outer = s.outer.clamp(0.0, std::f64::consts::PI);
                (axis, s.inner.clamp(0.0, outer).cos(), outer.cos())
            })
    };
    let image = |l: &ProductLight, (position, m): (ProductPoint, ProductIsometry), range: f64| ProductLightImage {
        spot: spot(l, &m, position),
        position,
        intensity: if l.intensity.is_finite() {
            l.intensity.max(0.0)
        } else {
            0.0
        },
        color: l.color,
        inv_range_sq: if range.is_finite() { 1.0 / (range * range) } else { 0.0 },
        min_area: g
            .sphere_area(if l.radius.is_finite() {
                l.radius.clamp(0.0, 1.0)
            } else {
                0.0
            })
            .max(MIN_AREA),
    };
    if lighting.images == 0 {
        return lights
            .iter()
            .map(|l| image(l, (l.position, ProductIsometry::IDENTITY), f64::INFINITY))
            .collect();
    }
    let budget = (lighting.images as usize)
        .min(MAX_PRODUCT_LIGHT_IMAGES / lights.len().max(1))
        .max(1);
    let mut out = Vec::new();
    for l in lights {
        let (images, range) = images_of(space, l, budget);
        out.extend(images.into_iter().map(|pm| image(l, pm, range)));
    }
    out
}

/// The distances of `p`'s parts to the prism's (the distance to the
/// prism is their hypotenuse): the surface point's to the polygon (0
/// inside, else the nearest of its corners and of the feet on the sides
/// it lies beyond that fall within them: the polygon is convex) and the
/// height's to its interval.
fn from_prism(space: &ProductSpace, vertices: &[DVec3], p: ProductPoint) -> (f64, f64) {
    let g = space.geometry;
    let k = g.curvature();
    let dh = (p.height.abs() - space.height / 2.0).max(0.0);
    let n = space.sides.len();
    let q = p.surface;
    let beyond: Vec<f64> = space.sides.iter().map(|s| g.form(*s, q)).collect();
    if beyond.iter().all(|b| *b <= 0.0) {
        return (0.0, dh);
    }
    let mut ds = vertices
        .iter()
        .map(|v| g.surface_distance(q, *v))
        .fold(f64::INFINITY, f64::min);
    for (i, side) in space.sides.iter().enumerate() {
        if beyond[i] <= 0.0 {
            continue;
        }
        // The foot on the side's line, within the side where it is inside
        // both neighbouring sides' half-planes.
        let foot = q - *side * beyond[i];
        let within = [space.sides[(i + n - 1) % n], space.sides[(i + 1) % n]]
            .iter()
            .all(|m| g.form(*m, foot) <= 0.0);
        if within && g.form(foot, foot) * k > 0.0 {
            let d = match g {
                ProductGeometry::H2xR => beyond[i].asinh(),
                ProductGeometry::S2xR => beyond[i].clamp(-1.0, 1.0).asin(),
            };
            ds = ds.min(d);
        }
    }
    (ds, dh)
}

/// The images of light `l` that light the prism (each with the isometry
/// taking the light to it), at most `budget`, and the range they are
/// complete to (infinite: no cut-off).
///
/// They are found by walking the copies of the prism from the prism,
/// each across a face of the last (`h` to `h G_f`, the light's image in
/// it `h G_f p`). A copy within `r` of the prism is reached through
/// copies each within `r` of it (those the shortest way crosses), each
/// meeting that way at a point whose surface and height parts are each
/// within `r` of the prism's. Each copy is judged by its anchor, the
/// image of a point `a` of the prism (the model's origin where the
/// polygon holds it, else the light's foot, at height 0), which lies
/// within `far_s` of all of the copy along the surface and `far_h` up
/// the line (the farthest the polygon's corners and the prism's ends are
/// from `a`). So walking on from every copy whose anchor's parts are
/// within `r + far_s` and `r + far_h` finds every image within `r`. (A
/// central anchor halves `far_s` against the light's own image: the
/// genus-2 octagon's corners are 2.45 from its centre, 4.9 apart, and
/// the copies walked grow as `e` to that slack.)
fn images_of(space: &ProductSpace, l: &ProductLight, budget: usize) -> (Vec<(ProductPoint, ProductIsometry)>, f64) {
    let g = space.geometry;
    let vertices = space.vertices();
    let holds = |q: DVec3| space.sides.iter().all(|s| g.form(*s, q) <= 0.0);
    let anchor = ProductPoint::new(
        if holds(ProductPoint::ORIGIN.surface) {
            ProductPoint::ORIGIN.surface
        } else {
            l.position.surface
        },
        0.0,
    );
    // The farthest corner from the anchor (the distance from a point is
    // convex on the convex polygon), and the farthest end.
    let far_h = space.height / 2.0;
    let far_s = if space.sides.is_empty() {
        std::f64::consts::PI
    } else {
        vertices
            .iter()
            .map(|v| g.surface_distance(anchor.surface, *v))
            .fold(0.0f64, f64::max)
    };
    let requested = l.range.filter(|r| r.is_finite() && *r > 0.0).unwrap_or(f64::INFINITY);
    let gluings: Vec<ProductIsometry> = space.gluings.iter().map(|m| m.isometry()).collect();
    // Points keyed on a grid of 1e-3: distinct images lie at least the
    // shortest closed geodesic apart, far more; rounding in the composed
    // gluings moves far images by more than 1e-9.
    let key = |p: ProductPoint| {
        let r = |x: f64| (x * 1e3).round() as i64;
        [r(p.surface.x), r(p.surface.y), r(p.surface.z), r(p.height)]
    };
    // From a short reach, doubled until the budget is met: the copies
    // walked grow exponentially with it in H2xR. Each doubling walks on
    // from where the last stopped: the images found stay found, and the
    // images some of whose neighbours lay past the last reach are looked
    // at again.
    let mut reach = requested.min(1.0);
    let mut last: Option<(Vec<(ProductPoint, ProductIsometry)>, f64)> = None;
    let start = (
        from_prism(space, &vertices, l.position),
        l.position,
        ProductIsometry::IDENTITY,
    );
    // Every image within `reach` of the prism, with its distance; only
    // images to walk on from are kept (every image within `reach` is one).
    let mut found: Vec<((f64, f64), ProductPoint, ProductIsometry)> = vec![start];
    let mut seen = std::collections::HashSet::from([key(l.position)]);
    let mut next = 0;
    let mut again: Vec<usize> = Vec::new();
    for _ in 0..16 {
        let mut capped = false;
        let mut queue = std::mem::take(&mut again);
        loop {
            let i = match queue.pop() {
                Some(i) => i,
                None if next < found.len() => {
                    next += 1;
                    next - 1
                }
                None => break,
            };
            let h = found[i].2;
            let mut beyond = false;
            for m in &gluings {
                let e = h.compose(m);
                let (fs, fh) = from_prism(space, &vertices, g.normalize_point(e.apply(anchor)));
                if fs > reach + far_s || fh > reach + far_h {
                    beyond = true;
                    continue;
                }
                let p = g.normalize_point(e.apply(l.position));
                if !seen.insert(key(p)) {
                    continue;
                }
                let (ds, dh) = from_prism(space, &vertices, p);
                if found.len() >= MAX_WALK {
                    capped = true;
                    break;
                }
                found.push(((ds, dh), p, e));
            }
            if beyond {
                again.push(i);
            }
            if capped {
                break;
            }
        }
        if capped && last.is_none() {
            // Not even the first reach could be walked: a walk of half
            // the reach, from the start.
            reach /= 2.0;
            found.truncate(1);
            seen = std::collections::HashSet::from([key(l.position)]);
            next = 0;
            again.clear();
            continue;
        }
        let mut found: Vec<(f64, ProductPoint, ProductIsometry)> =
            found.iter().map(|f| (f.0.0.hypot(f.0.1), f.1, f.2)).collect();
        found.sort_by(|a, b| a.0.total_cmp(&b.0));
        // One image once (a point on the grid's edge may have two keys).
        let mut images: Vec<(f64, ProductPoint, ProductIsometry)> = Vec::with_capacity(found.len());
        for &(near, p, e) in &found {
            let twice = images
                .iter()
                .rev()
                .take_while(|i| i.0 > near - 1e-3)
                .any(|i| g.distance(i.1, p) < 1e-3);
            if !twice {
                images.push((near, p, e));
            }
        }
        let within = |r: f64| images.partition_point(|f| f.0 < r);
        let keep = |r: f64| (images[..within(r)].iter().map(|f| (f.1, f.2)).collect(), r);
        if capped {
            // The walk could not finish: what the last whole one found.
            return last.unwrap_or((Vec::new(), 0.0));
        }
        if within(reach) > budget {
            return keep(images[budget].0);
        }
        if reach >= requested {
            return keep(requested);
        }
        last = Some(keep(reach));
        reach = (reach * 2.0).min(requested);
    }
    last.unwrap_or((Vec::new(), 0.0))
}

/// One way a light image's light reaches a point: the unit tangent at
/// the point towards the light, the arc length and the length of its
/// surface part.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightArc {
    /// Towards the light, a unit tangent at the lit point.
    pub dir: ProductTangent,
    /// The arc length.
    pub length: f64,
    /// The length of its surface part.
    pub surface: f64,
}

/// The geodesics from `x` to the light image at `light`: the shortest,
/// and in S2xR the other way round the sphere's great circle (arriving
/// from the opposite side). Geodesics that wind round the sphere again
/// are left out (each is at least `2 pi` longer). None where the light
/// is at `x`. The WGSL twin is the loop over the arcs in `direct` (in
/// `product.wgsl`).
#[must_use]
pub fn light_arcs(g: ProductGeometry, x: ProductPoint, light: ProductPoint) -> Vec<LightArc> {
    let Some((dir, length)) = g.log(x, light) else {
        return Vec::new();
    };
    let surface = g.surface_distance(x.surface, light.surface);
    let mut arcs = vec![LightArc { dir, length, surface }];
    let speed = g.form(dir.surface, dir.surface).max(0.0).sqrt();
    if g == ProductGeometry::S2xR && speed > 1e-12 {
        let dh = light.height - x.height;
        let around = std::f64::consts::TAU - surface;
        let length = around.hypot(dh);
        let u = -dir.surface / speed;
        arcs.push(LightArc {
            dir: ProductTangent::new(u * (around / length), dh / length),
            length,
            surface: around,
        });
    }
    arcs
}

/// The share of a spot image's light that reaches `x` along `arc`: the
/// geodesic followed to the light, the tangent it arrives with turned
/// back (the way it leaves the light towards `x`) against the spot's
/// axis ([`ProductSpot::share`]). WGSL twin: `spot_share`.
#[must_use]
pub fn spot_share(
    g: ProductGeometry,
    x: ProductPoint,
    arc: &LightArc,
    (axis, cos_inner, cos_outer): (ProductTangent, f64, f64),
) -> f64 {
    let (_, arriving) = g.exp(x, arc.dir, arc.length);
    let cos = -g.dot(arriving, axis);
    ProductSpot::share(cos_inner, cos_outer, cos)
}

/// The irradiance a light image gives along an arc of `length` whose
/// surface part is `surface` long: `intensity / max(light_area,
/// min_area)`, times the range's smooth window `(1 - (s^2 / range^2)^2)^2`,
/// times `exp(-fog s)` for the fog on the way. WGSL twin:
/// `arc_irradiance` in `product.wgsl`.
#[must_use]
pub fn arc_irradiance(g: ProductGeometry, l: &ProductLightImage, (length, surface): (f64, f64), fog: f64) -> f64 {
    let f = length * length * l.inv_range_sq;
    let window = (1.0 - f * f).clamp(0.0, 1.0);
    let area = g.light_area(length, surface).max(l.min_area);
    l.intensity * window * window / area * (-fog * length).exp()
}

/// Whether one of `objects` (a ball, an edge's tube or a mesh, or an
/// image of one) stands on the way from `x` (a surface point with unit normal `normal`) along
/// `arc` to its light: the way
/// walked through the faces (at most `max_crossings`), from
/// [`SHADOW_OFFSET`] off the surface. WGSL twin: `shadowed` in
/// `product.wgsl`.
#[must_use]
pub fn shadowed(
    space: &ProductSpace,
    objects: &ProductObjects,
    (x, normal): (ProductPoint, ProductTangent),
    arc: &LightArc,
    max_crossings: usize,
) -> bool {
    let g = space.geometry;
    let start = advance(g, &ProductRay { origin: x, dir: normal }, SHADOW_OFFSET).origin;
    let ray = ProductRay {
        origin: start,
        dir: g.normalize_tangent(start, arc.dir),
    };
    let mut blocked = false;
    walk_segments(space, ray, arc.length, max_crossings, |walk, _, length| {
        for ball in &objects.balls {
            if let Some(span) = reach(g, &walk.ray, ball.center, ball.radius + super::REACH_SLACK, length) {
                entries(g, &walk.ray, ball, span, |_| blocked = true);
                if blocked {
                    return false;
                }
            }
        }
        blocked = objects.tubes.entry(g, &walk.ray, length).is_some()
            || objects.meshes.iter().any(|m| m.entry(g, &walk.ray, length).is_some());
        !blocked
    });
    blocked
}

/// The light a surface point `x` (unit normal `normal`, seen along the
/// unit tangent `view` towards the eye, of colour `albedo`) receives
/// from every light image along each of its arcs: Lambert plus a Blinn
/// lobe (`0.35 (n.h)^32`), as the other spaces' classic look, each arc's
/// light only where its way is free when `shadows` (but for the
/// [`DIM_LIGHT`]). WGSL twin: `direct` in `product.wgsl`.
#[must_use]
#[expect(clippy::too_many_arguments, reason = "the shading inputs are all distinct")]
pub fn direct(
    space: &ProductSpace,
    objects: &ProductObjects,
    lights: &[ProductLightImage],
    (x, normal, view): (ProductPoint, ProductTangent, ProductTangent),
    albedo: [f32; 3],
    fog: f64,
    shadows: bool,
    max_crossings: usize,
) -> [f32; 3] {
    let g = space.geometry;
    let mut rgb = [0.0f32; 3];
    let mut dim = DIM_LIGHT;
    for l in lights {
        for arc in light_arcs(g, x, l.position) {
            let nl = g.dot(normal, arc.dir);
            if nl <= 0.0 {
                continue;
            }
            let mut e = arc_irradiance(g, l, (arc.length, arc.surface), fog);
            if let Some((axis, cos_inner, cos_outer)) = l.spot {
                e *= spot_share(g, x, &arc, (axis, cos_inner, cos_outer));
            }
            if e <= 0.0 {
                continue;
            }
            let half = ProductTangent::new(arc.dir.surface + view.surface, arc.dir.height + view.height);
            let hl = g.dot(half, half).max(0.0).sqrt();
            let nh = if hl > 1e-12 {
                (g.dot(normal, half) / hl).max(0.0)
            } else {
                0.0
            };
            let spec = nh.powi(32) * 0.35;
            let light: [f32; 3] = std::array::from_fn(|c| ((f64::from(albedo[c]) * nl + spec) * e) as f32 * l.color[c]);
            let mut share = 1.0;
            if shadows {
                let most = light[0].max(light[1]).max(light[2]);
                if most < dim {
                    dim -= most;
                    share = 0.5;
                } else if shadowed(space, objects, (x, normal), &arc, max_crossings) {
                    continue;
                }
            }
            for c in 0..3 {
                rgb[c] += light[c] * share;
            }
        }
    }
    rgb
}
