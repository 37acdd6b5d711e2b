//! The CPU reference tracer of the product spaces (H2xR, S2xR): a ray
//! follows its exact geodesic ([`ProductGeometry::exp`]) through the
//! prism, leaves it through the nearest face ([`exit_face`], in closed
//! form) and goes on from the gluing's image of its exit point, as
//! Algorithm 1 does in E3, H3 and S3 ([`super::step::exit_face`]).
//!
//! Balls are true geodesic balls of the product metric, found along the
//! ray by sphere tracing: the distance from a point of the ray to a
//! ball's centre changes by at most the distance travelled, so stepping
//! by the distance to the ball's surface never steps over it.
//!
//! ```
//! use bevy_manifold_core::geometry::product::{ProductPoint, ProductTangent};
//! use bevy_manifold_core::space::product::ProductSpace;
//! use bevy_manifold_core::trace::product::{ProductBall, ProductRay, hits};
//! use glam::DVec3;
//! // In S2 x S1 of circle 2, looking straight up from under a ball: the
//! // ball and its copies every 2 up the circle.
//! let space = ProductSpace::s2_x_s1(2.0);
//! let ball = ProductBall { center: ProductPoint::new(DVec3::Z, 0.5), radius: 0.1, id: 1 };
//! let up = ProductRay { origin: ProductPoint::ORIGIN, dir: ProductTangent::new(DVec3::ZERO, 1.0) };
//! let seen = hits(&space, &[ball], up, 5.0, 16);
//! let at: Vec<f64> = seen.iter().map(|h| h.distance).collect();
//! assert!((at[0] - 0.4).abs() < 1e-9 && (at[1] - 2.4).abs() < 1e-9 && (at[2] - 4.4).abs() < 1e-9);
//! ```

use crate::geometry::product::{ProductGeometry, ProductIsometry, ProductPoint, ProductTangent};
use crate::space::product::ProductSpace;
use glam::DVec3;

pub mod contact;
mod edges;
mod light;
pub mod mesh;
mod view;

pub use edges::{EDGE_ID, ProductEdge, ProductEdges, ProductTubes};
pub use mesh::{ProductMesh, ProductMeshError, ProductMeshImage, mesh_images};

pub use light::{
    DIM_LIGHT, LightArc, MAX_PRODUCT_LIGHT_IMAGES, ProductLight, ProductLightImage, ProductLighting, ProductSpot,
    SHADOW_OFFSET, arc_irradiance, direct, light_arcs, light_images, shadowed, spot_share,
};
pub use view::{AMBIENT, FOG_COLOR, ProductPixel, ProductScene, ProductView, palette, render};

/// A ray: a point and a unit tangent there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProductRay {
    /// Where it starts.
    pub origin: ProductPoint,
    /// Its unit direction.
    pub dir: ProductTangent,
}

/// A geodesic ball of the product metric, in the prism.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProductBall {
    /// Its centre.
    pub center: ProductPoint,
    /// Its radius.
    pub radius: f64,
    /// The object id a hit reports.
    pub id: u32,
}

/// Where a ray entered a ball.
#[derive(Clone, Debug, PartialEq)]
pub struct ProductHit {
    /// The ball's id.
    pub object: u32,
    /// The distance along the ray.
    pub distance: f64,
    /// The point, in the prism.
    pub point: ProductPoint,
    /// The ray's unit tangent there.
    pub dir: ProductTangent,
    /// The surface's unit normal there, facing the ray.
    pub normal: ProductTangent,
    /// The centre of the ball's image it entered, in the prism's frame
    /// (the ball's own, or its image through a face's gluing); for an
    /// edge's tube ([`EDGE_ID`]), the edge's point nearest the hit; for a
    /// mesh, its chart's origin.
    pub center: ProductPoint,
    /// The faces crossed before it, in order (the word of the copy of
    /// the prism it is in).
    pub faces: Vec<usize>,
}

/// A ray followed through the faces: where it is, and how it got there.
#[derive(Clone, Debug, PartialEq)]
pub struct ProductWalk {
    /// The ray at its end, in the prism.
    pub ray: ProductRay,
    /// The faces crossed, in order.
    pub faces: Vec<usize>,
    /// The gluings applied, composed: it maps the universal cover's point
    /// the walk reached onto `ray.origin`. (In H2xR its entries grow as
    /// e to the distance along the surface, past f64 after about 700.)
    pub cell: ProductIsometry,
}

/// Smallest step of the sphere tracing (and how near a surface counts as
/// on it).
const SURFACE: f64 = 1e-12;
/// Most sphere-tracing steps per ball and segment (a ray grazing a ball
/// steps slowly; past this the graze counts as a miss).
const MAX_STEPS: usize = 20_000;

/// The face a ray leaves the prism through, and the distance to it:
/// the nearest face the ray moves out of, skipping `skip` (the face it
/// just entered). A vertical face `<n, p> = 0` is met where the surface
/// geodesic `p cosh(a s) + u sinh(a s)` (or cos, sin) crosses the line:
/// `tanh(a s) = -<n, p> / <n, u>` (`tan` on the sphere); a horizontal face
/// where the height reaches it. Crossings behind the origin (rounding)
/// count as 0.
#[must_use]
pub fn exit_face(space: &ProductSpace, ray: &ProductRay, skip: Option<usize>) -> Option<(usize, f64)> {
    let g = space.geometry;
    let speed = g.form(ray.dir.surface, ray.dir.surface).max(0.0).sqrt();
    let mut best: Option<(usize, f64)> = None;
    let mut consider = |face: usize, s: f64| {
        if Some(face) != skip && s.is_finite() && best.is_none_or(|(_, b)| s < b) {
            best = Some((face, s.max(0.0)));
        }
    };
    if speed > 0.0 {
        for (face, n) in space.sides.iter().enumerate() {
            let a = g.form(*n, ray.origin.surface);
            let b = g.form(*n, ray.dir.surface) / speed;
            let sigma = match g {
                ProductGeometry::H2xR if b > 0.0 && -a < b => (-a / b).atanh(),
                ProductGeometry::S2xR if b > 0.0 || a < 0.0 => (-a).atan2(b),
                _ => continue,
            };
            consider(face, sigma / speed);
        }
    }
    let h = ray.origin.height;
    let half = space.height / 2.0;
    if ray.dir.height > 0.0 {
        consider(space.top(), (half - h) / ray.dir.height);
    } else if ray.dir.height < 0.0 {
        consider(space.bottom(), (-half - h) / ray.dir.height);
    }
    best
}

/// The ray moved `s` along its geodesic (inside the prism).
#[must_use]
pub fn advance(g: ProductGeometry, ray: &ProductRay, s: f64) -> ProductRay {
    let (origin, dir) = g.exp(ray.origin, ray.dir, s);
    ProductRay { origin, dir }
}

/// The ray carried through face `face`: the gluing's image of it, put
/// back on the model (so rounding does not grow over many crossings).
#[must_use]
pub fn transport(space: &ProductSpace, face: usize, ray: &ProductRay) -> ProductRay {
    let g = space.geometry;
    let m = space.gluings[face].isometry();
    let origin = g.normalize_point(m.apply(ray.origin));
    ProductRay {
        origin,
        dir: g.normalize_tangent(origin, m.apply_tangent(ray.dir)),
    }
}

/// Walks the ray through the prism for `distance` (through at most
/// `max_crossings` faces), calling `segment(walk, length)` with the walk
/// at the start of each segment and the segment's length (to the face it
/// leaves through, or to the end). The segment returning false stops the
/// walk there. Returns the walk at its end.
pub(crate) fn walk_segments(
    space: &ProductSpace,
    ray: ProductRay,
    distance: f64,
    max_crossings: usize,
    mut segment: impl FnMut(&ProductWalk, f64, f64) -> bool,
) -> ProductWalk {
    let g = space.geometry;
    let mut walk = ProductWalk {
        ray,
        faces: Vec::new(),
        cell: ProductIsometry::IDENTITY,
    };
    let mut travelled = 0.0;
    let mut skip = None;
    loop {
        let exit = exit_face(space, &walk.ray, skip).filter(|(_, s)| travelled + s < distance);
        let length = exit.map_or(distance - travelled, |(_, s)| s);
        if !segment(&walk, travelled, length) {
            return walk;
        }
        match exit {
            Some((face, s)) if walk.faces.len() < max_crossings => {
                walk.ray = transport(space, face, &advance(g, &walk.ray, s));
                walk.cell = space.gluings[face].isometry().compose(&walk.cell);
                walk.faces.push(face);
                travelled += s;
                skip = Some(space.partner(face));
            }
            _ => {
                walk.ray = advance(g, &walk.ray, length);
                return walk;
            }
        }
    }
}

/// The ray followed for `distance` through the faces (at most
/// `max_crossings` of them; it stops at the last).
#[must_use]
pub fn flow(space: &ProductSpace, ray: ProductRay, distance: f64, max_crossings: usize) -> ProductWalk {
    walk_segments(space, ray, distance, max_crossings, |_, _, _| true)
}

/// The balls the ray enters within `max_distance` (through at most
/// `max_crossings` faces), nearest first, up to 64 of them. Each ball is
/// looked for in the prism as itself and as its [`images`] that reach
/// into the prism.
#[must_use]
pub fn hits(
    space: &ProductSpace,
    balls: &[ProductBall],
    ray: ProductRay,
    max_distance: f64,
    max_crossings: usize,
) -> Vec<ProductHit> {
    let objects = ProductObjects {
        balls: images(space, balls),
        ..ProductObjects::default()
    };
    hits_in(space, &objects, ray, max_distance, max_crossings)
}

/// What rays meet in a product space, made once for a scene: the balls
/// and their [`images`], the prism's edges' tubes, and the meshes and
/// their [`mesh_images`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ProductObjects {
    /// The balls and their images.
    pub balls: Vec<ProductBall>,
    /// The edges' tubes (none for none).
    pub tubes: ProductTubes,
    /// The meshes and their images.
    pub meshes: Vec<ProductMeshImage>,
}

impl ProductObjects {
    /// `balls`, the `edges`' tubes and `meshes` in `space`, with their
    /// images.
    #[must_use]
    pub fn new(
        space: &ProductSpace,
        balls: &[ProductBall],
        edges: Option<ProductEdges>,
        meshes: &[ProductMesh],
    ) -> Self {
        Self {
            balls: images(space, balls),
            tubes: ProductTubes::of(space, edges),
            meshes: mesh_images(space, meshes),
        }
    }

    /// What `scene` shows in `space`.
    #[must_use]
    pub fn of(space: &ProductSpace, scene: &ProductScene) -> Self {
        Self::new(space, &scene.balls, scene.edges, &scene.meshes)
    }
}

/// Most images of one ball [`images`] keeps.
pub const MAX_IMAGES_PER_BALL: usize = 64;

/// The balls [`hits`] looks for in the prism: each ball, then every image
/// of it that may reach into the prism, that is the ball as each copy of
/// the prism it reaches into sees it. They are found by a breadth-first
/// walk over the gluings from the ball (a ball meets a connected set of
/// copies, so an image that reaches in is the gluing's image of one that
/// does), keeping the images for which [`ProductSpace::may_meet`] holds,
/// at most [`MAX_IMAGES_PER_BALL`] per ball. A ball across an edge or a
/// corner of the prism is seen through two or three gluings.
#[must_use]
pub fn images(space: &ProductSpace, balls: &[ProductBall]) -> Vec<ProductBall> {
    let g = space.geometry;
    balls
        .iter()
        .flat_map(|ball| {
            image_isometries(space, ball.center, ball.radius)
                .into_iter()
                .map(|m| ProductBall {
                    center: g.normalize_point(m.apply(ball.center)),
                    ..*ball
                })
        })
        .collect()
}

/// The isometries taking a ball about `center` of `radius` onto its
/// images that may reach into the prism, the identity first: [`images`]'
/// walk over the gluings, for anything bounded by such a ball (a mesh,
/// [`mesh::ProductMeshImage`]).
pub(crate) fn image_isometries(space: &ProductSpace, center: ProductPoint, radius: f64) -> Vec<ProductIsometry> {
    let g = space.geometry;
    let mut out = vec![(ProductIsometry::IDENTITY, center)];
    let mut next = 0;
    while next < out.len() && out.len() < MAX_IMAGES_PER_BALL {
        let (from, _) = out[next];
        next += 1;
        for gluing in &space.gluings {
            let m = gluing.isometry().compose(&from);
            let image = g.normalize_point(m.apply(center));
            let known = out.iter().any(|(_, c)| g.distance(*c, image) < 1e-9);
            if !known && space.may_meet(image, radius) && out.len() < MAX_IMAGES_PER_BALL {
                out.push((m, image));
            }
        }
    }
    out.into_iter().map(|(m, _)| m).collect()
}

/// [`hits`] among `objects`: the balls' entries, each segment's first
/// entry into an edge's tube (reported as [`EDGE_ID`], its `center` the
/// edge's nearest point) and into each mesh.
#[must_use]
pub fn hits_in(
    space: &ProductSpace,
    objects: &ProductObjects,
    ray: ProductRay,
    max_distance: f64,
    max_crossings: usize,
) -> Vec<ProductHit> {
    let g = space.geometry;
    let mut found = Vec::new();
    walk_segments(space, ray, max_distance, max_crossings, |walk, travelled, length| {
        let mut segment: Vec<(f64, u32, ProductPoint, Option<ProductTangent>)> = Vec::new();
        for ball in &objects.balls {
            if let Some(span) = reach(g, &walk.ray, ball.center, ball.radius + REACH_SLACK, length) {
                entries(g, &walk.ray, ball, span, |s| {
                    segment.push((s, ball.id, ball.center, None))
                });
            }
        }
        if let Some((s, near)) = objects.tubes.entry(g, &walk.ray, length) {
            segment.push((s, EDGE_ID, near, None));
        }
        for mesh in &objects.meshes {
            if let Some(e) = mesh.entry(g, &walk.ray, length) {
                segment.push((e.s, mesh.id, mesh.center, Some(e.normal)));
            }
        }
        segment.sort_by(|a, b| a.0.total_cmp(&b.0));
        for (s, object, center, normal) in segment {
            let at = advance(g, &walk.ray, s);
            let back = ProductTangent::new(-at.dir.surface, -at.dir.height);
            // A ball's or a tube's normal points away from its centre.
            let normal = normal.unwrap_or_else(|| {
                g.log(at.origin, center)
                    .map_or(back, |(v, _)| ProductTangent::new(-v.surface, -v.height))
            });
            found.push(ProductHit {
                object,
                distance: travelled + s,
                point: at.origin,
                dir: at.dir,
                normal,
                center,
                faces: walk.faces.clone(),
            });
            if found.len() >= 64 {
                return false;
            }
        }
        true
    });
    found
}

/// How much farther than its radius a ball is looked for (rounding).
const REACH_SLACK: f64 = 1e-9;

/// The part `[lo, hi]` of the segment `[0, length]` of the ray in which
/// it may come within `radius` of `center`, in closed form: where its
/// height is within `radius` of the centre's and its surface geodesic is
/// within `radius` of the centre's surface point (a box about the ball).
/// On H2 the surface distance is `cosh d = A cosh t + B sinh t` (`t` the
/// surface arc length), within `radius` between the roots of a quadratic
/// in `e^t`; on S2 `cos d = A cos t + B sin t`, within `radius` on windows
/// of the circle. `None` where the segment never comes near.
#[must_use]
pub fn reach(
    g: ProductGeometry,
    ray: &ProductRay,
    center: ProductPoint,
    radius: f64,
    length: f64,
) -> Option<(f64, f64)> {
    let span = height_window(ray, center.height, radius, length)?;
    surface_window(g, ray, center.surface, radius, span)
}

/// The part of `[0, length]` of the ray whose height is within `radius`
/// of `height` (`|dh + v s| <= radius`). WGSL twin: `height_window`.
pub(crate) fn height_window(ray: &ProductRay, height: f64, radius: f64, length: f64) -> Option<(f64, f64)> {
    let dh = ray.origin.height - height;
    let v = ray.dir.height;
    let (mut lo, mut hi) = (0.0f64, length);
    if v == 0.0 {
        if dh.abs() > radius {
            return None;
        }
    } else {
        let (a, b) = ((-radius - dh) / v, (radius - dh) / v);
        lo = lo.max(a.min(b));
        hi = hi.min(a.max(b));
    }
    (lo <= hi).then_some((lo, hi))
}

/// The part of `[lo, hi]` of the ray in which its surface geodesic comes
/// within `radius` of the surface point `q`, in closed form: [`reach`]'s
/// surface part, and the whole of a vertical edge's tube
/// ([`edges::ProductTubes`]). WGSL twin: `surface_window`.
pub(crate) fn surface_window(
    g: ProductGeometry,
    ray: &ProductRay,
    q: DVec3,
    radius: f64,
    (lo, hi): (f64, f64),
) -> Option<(f64, f64)> {
    let p = ray.origin.surface;
    let speed = g.form(ray.dir.surface, ray.dir.surface).max(0.0).sqrt();
    if speed == 0.0 {
        return (g.surface_distance(p, q) <= radius).then_some((lo, hi));
    }
    let u = ray.dir.surface / speed;
    let (t_lo, t_hi) = match g {
        ProductGeometry::H2xR => {
            let (a, b) = (-g.form(p, q), -g.form(u, q));
            let c = radius.cosh();
            // (a + b) x^2 - 2 c x + (a - b) <= 0, x = e^t; a > |b|.
            let disc = c * c - (a * a - b * b);
            if disc < 0.0 {
                return None;
            }
            let root = disc.sqrt();
            (((c - root) / (a + b)).ln(), ((c + root) / (a + b)).ln())
        }
        ProductGeometry::S2xR => {
            let (a, b) = (g.form(p, q), g.form(u, q));
            let amp = a.hypot(b);
            let c = radius.cos();
            if amp < c {
                return None;
            }
            // cos(t - phi) >= c / amp: windows phi +- w, every turn.
            let w = (c / amp).clamp(-1.0, 1.0).acos();
            let phi = b.atan2(a);
            let turn = std::f64::consts::TAU;
            let k = ((speed * lo - phi - w) / turn).ceil();
            let start = phi - w + turn * k;
            // A later window within the segment: look on to its end.
            let stop = if start + turn <= speed * hi {
                f64::INFINITY
            } else {
                start + 2.0 * w
            };
            (start, stop)
        }
    };
    let (lo, hi) = (lo.max(t_lo / speed), hi.min(t_hi / speed));
    (lo <= hi).then_some((lo, hi))
}

/// Most Newton steps per ball and segment in H2xR (they converge
/// quadratically; only a ray grazing the ball needs more than a few, and
/// past this the graze counts as a miss).
const MAX_NEWTON: usize = 64;

/// The distances in `[start, end]` (the segment's [`reach`] of the ball)
/// at which `ray` enters `ball` (from outside); a ray that starts inside
/// enters only after it has left. In H2xR by Newton's method
/// ([`first_entry_convex`]), in S2xR by sphere tracing, as the shader
/// does in both. WGSL twin: `first_entry` in `product.wgsl`.
fn entries(
    g: ProductGeometry,
    ray: &ProductRay,
    ball: &ProductBall,
    (start, end): (f64, f64),
    mut entered: impl FnMut(f64),
) {
    if g.curvature() < 0.0 {
        if let Some(s) = first_entry_convex(g, ray, ball, (start, end)) {
            entered(s);
        }
        return;
    }
    let gap = |s: f64| g.distance(g.exp(ray.origin, ray.dir, s).0, ball.center) - ball.radius;
    let mut s = start;
    let mut f = gap(s);
    let mut outside = f > SURFACE;
    for _ in 0..MAX_STEPS {
        if outside && f <= SURFACE {
            entered(s);
            outside = false;
        } else if !outside && f > SURFACE {
            outside = true;
        }
        s += f.abs().max(SURFACE);
        if s > end {
            return;
        }
        f = gap(s);
    }
}

/// The first distance in `[start, end]` at which `ray` enters `ball` from
/// outside, in H2xR, by Newton's method on the distance to its centre.
///
/// That distance is convex along every geodesic of H2xR (a product of two
/// spaces of curvature at most 0), so it enters at most once, never after
/// starting inside, and never once it moves away from the centre while
/// outside; and Newton's step from the left of the first root, where the
/// distance falls, ends short of it (the tangent lies below a convex
/// function) and is at least the sphere tracer's step (the distance
/// changes no faster than the ray moves): a grazing ray takes a few steps
/// where sphere tracing took a hundred (130 on average per ball and
/// segment in the bench scenes, to [`SURFACE`]). The shader keeps sphere
/// tracing (`first_entry` in `product.wgsl`): to its f32 tolerance
/// Newton measured no faster there.
fn first_entry_convex(
    g: ProductGeometry,
    ray: &ProductRay,
    ball: &ProductBall,
    (start, end): (f64, f64),
) -> Option<f64> {
    let mut s = start;
    let (mut at, mut dir) = g.exp(ray.origin, ray.dir, s);
    let (mut toward, mut d) = g.log(at, ball.center)?;
    if d - ball.radius <= SURFACE {
        return None;
    }
    for _ in 0..MAX_NEWTON {
        // The distance's derivative along the ray, in [-1, 1].
        let slope = -g.dot(dir, toward);
        if slope >= 0.0 {
            return None;
        }
        s -= (d - ball.radius) / slope;
        if s > end {
            return None;
        }
        (at, dir) = g.exp(ray.origin, ray.dir, s);
        (toward, d) = g.log(at, ball.center)?;
        if d - ball.radius <= SURFACE {
            return Some(s);
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::{ProductBall, ProductRay, first_entry_convex};
    use crate::geometry::product::{ProductGeometry, ProductPoint, ProductTangent};
    use glam::DVec3;

    /// Newton's first entry in H2xR against the distance sampled every
    /// 1e-3 along the ray and the first sign change bisected (no
    /// convexity assumed), over 2,000 random rays and balls, a third of
    /// them grazing.
    #[test]
    fn newtons_entry_is_where_the_sampled_distance_first_falls_to_the_radius() {
        let g = ProductGeometry::H2xR;
        let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
        let mut random = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let point =
            |r: f64, a: f64, h: f64| ProductPoint::new(DVec3::new(r.sinh() * a.cos(), r.sinh() * a.sin(), r.cosh()), h);
        let (mut hits, mut misses, mut skipped) = (0, 0, 0);
        for k in 0..2000 {
            let origin = point(2.0 * random(), 6.3 * random(), 2.0 * random() - 1.0);
            let center = point(2.0 * random(), 6.3 * random(), 2.0 * random() - 1.0);
            let radius = 0.05 + 0.5 * random();
            // Aimed at the centre, then turned off it: by up to the ball's
            // angular size for a third of the rays (grazing), farther for
            // the rest.
            let (toward, d) = g.log(origin, center).expect("apart");
            let side = g.normalize_tangent(
                origin,
                ProductTangent::new(DVec3::new(random(), random(), random()), random()),
            );
            let off = if k % 3 == 0 { (radius / d).min(1.0) * 1.2 } else { 1.5 } * random();
            let dir = g.normalize_tangent(
                origin,
                ProductTangent::new(toward.surface + side.surface * off, toward.height + side.height * off),
            );
            let ray = ProductRay { origin, dir };
            let ball = ProductBall { center, radius, id: 1 };
            let end = d + 2.0;
            let gap = |s: f64| g.distance(g.exp(origin, dir, s).0, center) - radius;
            if gap(0.0) <= 0.0 {
                continue;
            }
            let steps = (end / 1e-3) as usize;
            let first = (1..=steps).map(|i| i as f64 * 1e-3).find(|&s| gap(s) <= 0.0);
            let least = (0..=steps).map(|i| gap(i as f64 * 1e-3)).fold(f64::INFINITY, f64::min);
            if least.abs() < 1e-5 {
                // Too near a graze for the sampling to say.
                skipped += 1;
                continue;
            }
            let newton = first_entry_convex(g, &ray, &ball, (0.0, end));
            match first {
                None => {
                    assert_eq!(newton, None, "ray {k}: sampled a miss");
                    misses += 1;
                }
                Some(after) => {
                    let (mut lo, mut hi) = (after - 1e-3, after);
                    for _ in 0..60 {
                        let mid = 0.5 * (lo + hi);
                        if gap(mid) <= 0.0 { hi = mid } else { lo = mid }
                    }
                    let s = newton.unwrap_or_else(|| panic!("ray {k}: sampled an entry at {hi}"));
                    assert!((s - hi).abs() < 1e-9, "ray {k}: Newton {s}, sampled {hi}");
                    hits += 1;
                }
            }
        }
        eprintln!("{hits} hits, {misses} misses, {skipped} skipped");
        assert!(
            hits > 500 && misses > 500 && skipped < 20,
            "{hits} hits, {misses} misses, {skipped} skipped"
        );
    }
}
