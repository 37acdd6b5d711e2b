//! What a view of a product space sees: each pixel's ray followed to its
//! first ball ([`super::hits`]), lit by the scene's lights
//! ([`super::light`]; from the eye where it has none) and fogged by its
//! distance. The WGSL twin is `product.wgsl`'s `pixel` (in the
//! `bevy_manifold_gpu` crate), which reads the same [`ProductScene`].

use super::edges::{EDGE_ID, ProductEdges};
use super::light::{ProductLight, ProductLightImage, ProductLighting, direct, light_images};
use super::mesh::{ProductMesh, z_up};
use super::{ProductBall, ProductObjects, ProductRay, hits_in, walk_segments};
use crate::geometry::product::{ProductGeometry, ProductIsometry, ProductPoint, ProductTangent};
use crate::mesh::{MeshData, shapes, vehicle};
use crate::space::cell_id::CellId;
use crate::space::cells::CellTint;
use crate::space::product::ProductSpace;
use crate::space::product_cells::{ProductCells, ProductElement};
use crate::trace::Frustum;
use glam::{DQuat, DVec3};
#[cfg(feature = "parallel")]
use rayon::prelude::*;

/// What a product space shows: balls, meshes and lights in the prism,
/// and a view.
#[derive(Clone, Debug, PartialEq)]
pub struct ProductScene {
    /// The balls, in the prism.
    pub balls: Vec<ProductBall>,
    /// The meshes, placed in the prism ([`super::mesh`]).
    pub meshes: Vec<ProductMesh>,
    /// The lights, in the prism; none: the balls are lit from the eye.
    pub lights: Vec<ProductLight>,
    /// How the lights light the scene (their images, shadows).
    pub lighting: ProductLighting,
    /// The prism's edges drawn as tubes; `None` for none.
    pub edges: Option<ProductEdges>,
    /// The eye and how far it sees.
    pub view: ProductView,
}

impl ProductScene {
    /// `balls` seen by `view`, with no lights (lit from the eye).
    #[must_use]
    pub fn new(balls: Vec<ProductBall>, view: ProductView) -> Self {
        Self {
            balls,
            meshes: Vec::new(),
            lights: Vec::new(),
            lighting: ProductLighting::default(),
            edges: None,
            view,
        }
    }

    /// [`ProductScene::default_for`] lit by two lights, a warm one high
    /// beyond the ball on the axis (which shades the smallest ball from
    /// it) and a cool one low between the eye and that ball, with their
    /// images and shadows (`bevy_manifold product --lights`).
    #[must_use]
    pub fn lit_for(space: &ProductSpace) -> Self {
        let g = space.geometry;
        let l = space.height;
        let at = |angle: f64, d: f64, h: f64| polar(g, angle, d, h);
        let mut scene = Self::default_for(space);
        scene.lights = vec![
            ProductLight {
                color: [1.0, 0.85, 0.65],
                ..ProductLight::point(at(1.14, 0.55, 0.42 * l), 6.0)
            },
            ProductLight {
                color: [0.6, 0.75, 1.0],
                ..ProductLight::point(at(2.75, 0.4, -0.3 * l), 4.0)
            },
        ];
        scene
    }

    /// [`ProductScene::default_for`] with two meshes ([`super::mesh`]):
    /// the airplane ([`crate::mesh::vehicle`], 0.45 long) flying across
    /// the prism above the eye, and a box standing ahead to the right
    /// (`bevy_manifold product --meshes`).
    #[must_use]
    pub fn furnished_for(space: &ProductSpace) -> Self {
        let g = space.geometry;
        let l = space.height;
        let mut scene = Self::default_for(space);
        let place = |angle: f64, d: f64, turn: f64, h: f64| {
            ProductIsometry::new(g.translation(angle, d) * g.rotation(turn), 1.0, h)
        };
        let airplane = MeshData::shared(z_up(&vehicle::airplane().mesh, 0.45));
        let block = MeshData::shared(shapes::cuboid([0.12, 0.12, 0.18]));
        scene.meshes = vec![
            ProductMesh {
                mesh: airplane,
                placement: place(1.6, 0.4, 2.4, 0.32 * l),
                id: 5,
            },
            ProductMesh {
                mesh: block,
                placement: place(-1.3, 0.6, 0.4, 0.05 * l),
                id: 4,
            },
        ];
        scene
    }

    /// The scene `bevy_manifold product` draws: a ball on the prism's
    /// axis, two off it at other heights, the eye off the axis looking
    /// across it and a little up, through at most 24 faces and 12 units,
    /// with a light fog.
    #[must_use]
    pub fn default_for(space: &ProductSpace) -> Self {
        let g = space.geometry;
        let l = space.height;
        let at = |angle: f64, d: f64, h: f64| polar(g, angle, d, h);
        let r = 0.22 * l.min(1.0);
        let balls = vec![
            ProductBall {
                center: at(0.0, 0.0, 0.25 * l),
                radius: r,
                id: 1,
            },
            ProductBall {
                center: at(2.2, 0.5, -0.2 * l),
                radius: r * 0.8,
                id: 2,
            },
            ProductBall {
                center: at(-2.0, 0.6, 0.05 * l),
                radius: r * 0.7,
                id: 3,
            },
        ];
        let eye = at(std::f64::consts::PI, 0.7, 0.15 * l);
        let tilt = 0.25f64;
        // Towards the axis (+x at the eye's side), tilted up.
        let toward = g.normalize_tangent(eye, ProductTangent::new(DVec3::X, 0.0));
        let forward = ProductTangent::new(toward.surface * tilt.cos(), tilt.sin());
        let up = ProductTangent::new(-toward.surface * tilt.sin(), tilt.cos());
        let right = g.normalize_tangent(eye, ProductTangent::new(DVec3::NEG_Y, 0.0));
        Self::new(
            balls,
            ProductView {
                eye,
                frame: [forward, right, up],
                fov_y_degrees: 70.0,
                frustum: None,
                max_distance: 12.0,
                max_crossings: 24,
                fog: 0.08,
                cell: Some(ProductElement::IDENTITY),
                tint: None,
            },
        )
    }
}

/// The point at surface distance `d` from the origin in direction
/// `angle`, at height `h`.
fn polar(g: ProductGeometry, angle: f64, d: f64, h: f64) -> ProductPoint {
    let (c, s) = g.trig(d);
    ProductPoint::new(DVec3::new(s * angle.cos(), s * angle.sin(), c), h)
}

/// A view from inside a product space: where the eye is and its frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProductView {
    /// The eye, in the prism.
    pub eye: ProductPoint,
    /// Unit tangents at the eye, orthonormal: where it looks, its right
    /// and its up.
    pub frame: [ProductTangent; 3],
    /// The vertical field of view, in degrees (of a symmetric frustum,
    /// its width from the image's aspect).
    pub fov_y_degrees: f64,
    /// An off-centre frustum in place of `fov_y_degrees` (an OpenXR
    /// eye's: [`ProductView::posed`]); `None` for the symmetric one.
    pub frustum: Option<Frustum>,
    /// How far the rays go.
    pub max_distance: f64,
    /// How many faces a ray may cross.
    pub max_crossings: usize,
    /// Fog density (per unit of distance); 0 for none.
    pub fog: f64,
    /// The copy of the prism the eye is in, exactly
    /// ([`ProductCells`]): the origin copy to begin with, kept by
    /// [`ProductView::moved`]; `None` once it is too far to name (its
    /// cells are then shaded [`CellTint::UNKNOWN`]).
    pub cell: Option<ProductElement>,
    /// Per-cell shading: each ball's colour times the tint of the copy
    /// it is seen in; `None` for the balls' own colours.
    pub tint: Option<CellTint>,
}

impl ProductView {
    /// The eye moved `distance` along its geodesic in the direction
    /// `forward * d[0] + right * d[1] + up * d[2]` (made unit), through
    /// the faces it meets (at most 64), its frame carried along by
    /// parallel transport and through each face's gluing: what a camera
    /// flying through the space does. The frame is made orthonormal again
    /// after the move.
    #[must_use]
    pub fn moved(&self, space: &ProductSpace, d: [f64; 3], distance: f64) -> Self {
        let g = space.geometry;
        let [f, r, u] = self.frame;
        let dir = ProductTangent::new(
            f.surface * d[0] + r.surface * d[1] + u.surface * d[2],
            f.height * d[0] + r.height * d[1] + u.height * d[2],
        );
        // Nothing to move along, or no (finite, positive) way to go.
        let moving = dir.length(g) > 0.0 && distance > 0.0 && distance.is_finite();
        if !moving {
            return *self;
        }
        let ray = ProductRay {
            origin: self.eye,
            dir: dir.unit(g),
        };
        // Each segment carries the frame along it, after the gluing of the
        // face crossed before it.
        let mut frame = self.frame;
        let mut glued = 0;
        let mut cells: Option<Option<ProductCells>> = None;
        let mut cell = self.cell;
        let end = walk_segments(space, ray, distance, 64, |walk, _, length| {
            if let Some(&face) = walk.faces.get(glued) {
                let m = space.gluings[face].isometry();
                frame = frame.map(|w| m.apply_tangent(w));
                // The space's exact group, made at the first crossing.
                let exact = cells.get_or_insert_with(|| ProductCells::of(space));
                cell = match (exact, cell) {
                    (Some(exact), Some(c)) => exact.cross(&c, face).ok(),
                    _ => None,
                };
                glued += 1;
            }
            frame = frame.map(|w| carried(g, &walk.ray, w, length));
            true
        });
        Self {
            eye: end.ray.origin,
            frame: orthonormal(g, end.ray.origin, frame),
            cell,
            ..*self
        }
    }

    /// The frame turned by `yaw` (radians, towards the right) about its
    /// up, then by `pitch` (towards its up) about its new right.
    #[must_use]
    pub fn turned(&self, g: ProductGeometry, yaw: f64, pitch: f64) -> Self {
        let [f, r, u] = self.frame;
        let mix = |a: ProductTangent, b: ProductTangent, c: f64, s: f64| {
            ProductTangent::new(a.surface * c + b.surface * s, a.height * c + b.height * s)
        };
        let (cy, sy) = (yaw.cos(), yaw.sin());
        let (f, r) = (mix(f, r, cy, sy), mix(r, f, cy, -sy));
        let (cp, sp) = (pitch.cos(), pitch.sin());
        let (f, u) = (mix(f, u, cp, sp), mix(u, f, cp, -sp));
        Self {
            frame: orthonormal(g, self.eye, [f, r, u]),
            ..*self
        }
    }
}

impl ProductView {
    /// The frame rolled by `angle` (radians, its right towards its up)
    /// about where it looks.
    #[must_use]
    pub fn rolled(&self, g: ProductGeometry, angle: f64) -> Self {
        let [f, r, u] = self.frame;
        let (c, s) = (angle.cos(), angle.sin());
        let r2 = ProductTangent::new(r.surface * c + u.surface * s, r.height * c + u.height * s);
        let u2 = ProductTangent::new(u.surface * c - r.surface * s, u.height * c - r.height * s);
        Self {
            frame: orthonormal(g, self.eye, [f, r2, u2]),
            ..*self
        }
    }
}

impl ProductView {
    /// The view from a pose tracked in a Euclidean space (a headset's
    /// eye, in metres) measured from this one: the eye moved along the
    /// geodesic of `translation / scale` in this view's frame (`x` right,
    /// `y` up, `z` back, as Bevy's; through the faces, as
    /// [`ProductView::moved`]), then its frame turned by `rotation`
    /// (`scale`: metres per unit of the space's distance). The rule of
    /// `bevy_manifold::placement::tracked::pose_isometry`, whose twin
    /// this is for the product spaces.
    ///
    /// ```
    /// use bevy_manifold_core::space::product::ProductSpace;
    /// use bevy_manifold_core::trace::product::ProductScene;
    /// use glam::{DQuat, DVec3};
    ///
    /// let space = ProductSpace::s2_x_s1(3.0);
    /// let view = ProductScene::default_for(&space).view;
    /// // An eye 3.2 cm right of the head, at 4 m per unit.
    /// let eye = view.posed(&space, DVec3::X * 0.032, DQuat::IDENTITY, 4.0);
    /// let d = space.geometry.distance(view.eye, eye.eye);
    /// assert!((d - 0.008).abs() < 1e-12);
    /// ```
    #[must_use]
    pub fn posed(&self, space: &ProductSpace, translation: DVec3, rotation: DQuat, scale: f64) -> Self {
        let t = translation / scale;
        let moved = self.moved(space, [-t.z, t.x, t.y], t.length());
        let g = space.geometry;
        let [f, r, u] = moved.frame;
        // A vector of the pose's frame (x right, y up, z back) as a
        // tangent of the moved view's.
        let tangent = |v: DVec3| {
            ProductTangent::new(
                r.surface * v.x + u.surface * v.y - f.surface * v.z,
                r.height * v.x + u.height * v.y - f.height * v.z,
            )
        };
        let q = rotation.normalize();
        Self {
            frame: orthonormal(
                g,
                moved.eye,
                [tangent(q * DVec3::NEG_Z), tangent(q * DVec3::X), tangent(q * DVec3::Y)],
            ),
            ..moved
        }
    }

    /// The slopes `(x, y)` of pixel `(i, j)` of a `w x h` image (rows
    /// from the top): its ray is the unit tangent `forward + x right +
    /// y up`. From the symmetric frustum of `fov_y_degrees` and the
    /// image's aspect, or from the off-centre `frustum`. WGSL twin:
    /// `camera_ray` in `product.wgsl`.
    #[must_use]
    pub fn slopes(&self, (i, j): (usize, usize), (w, h): (usize, usize)) -> [f64; 2] {
        let ndc_x = (i as f64 + 0.5) / w.max(1) as f64 * 2.0 - 1.0;
        let ndc_y = 1.0 - (j as f64 + 0.5) / h.max(1) as f64 * 2.0;
        match self.frustum {
            Some(f) => {
                let [hw, hh, cx, cy] = f.half_extent_and_centre();
                [ndc_x * hw + cx, ndc_y * hh + cy]
            }
            None => {
                let half = (self.fov_y_degrees.to_radians() / 2.0).tan();
                let aspect = w as f64 / h.max(1) as f64;
                [ndc_x * half * aspect, ndc_y * half]
            }
        }
    }
}

/// `w`, a tangent at the ray's origin, carried `s` along the ray's
/// geodesic by parallel transport: its surface part's component along
/// the geodesic turns with it, the rest (normal to the geodesic's plane)
/// and its height stay.
fn carried(g: ProductGeometry, ray: &ProductRay, w: ProductTangent, s: f64) -> ProductTangent {
    let speed = g.form(ray.dir.surface, ray.dir.surface).max(0.0).sqrt();
    if speed == 0.0 {
        return w;
    }
    let u = ray.dir.surface / speed;
    let along = g.form(w.surface, u);
    let (c, sn) = g.trig(speed * s);
    let turned = u * c - ray.origin.surface * (g.curvature() * sn);
    ProductTangent::new(w.surface - u * along + turned * along, w.height)
}

/// The frame made tangent at `p` and orthonormal (Gram-Schmidt in the
/// product metric, in order).
fn orthonormal(g: ProductGeometry, p: ProductPoint, frame: [ProductTangent; 3]) -> [ProductTangent; 3] {
    let dot = |a: ProductTangent, b: ProductTangent| g.form(a.surface, b.surface) + a.height * b.height;
    let mut out = frame.map(|w| g.normalize_tangent(p, w));
    for i in 1..3 {
        for j in 0..i {
            let k = dot(out[i], out[j]);
            out[i] = ProductTangent::new(out[i].surface - out[j].surface * k, out[i].height - out[j].height * k);
        }
        out[i] = out[i].unit(g);
    }
    out
}

/// What one pixel of a [`render`] sees.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProductPixel {
    /// The ball's id, or 0 for nothing.
    pub object: u32,
    /// The distance to it (infinite for nothing).
    pub distance: f64,
    /// Faces crossed on the way.
    pub crossings: usize,
    /// The copy of the prism the ball was seen in
    /// ([`ProductCells::id`] of the eye's copy times the faces crossed);
    /// [`CellId::BEYOND_TABLE`] where the space has no exact cells or
    /// the copy is too far to name, and for nothing hit.
    pub cell: CellId,
    /// Linear RGB: the ball's colour lit from the eye, fogged by the
    /// distance; the fog's colour where nothing is hit.
    pub color: [f32; 3],
}

/// The scene's image, `width x height`, rows from the top: each pixel's
/// ray the unit tangent `forward + x right + y up` (`x`, `y` on the image
/// plane of the field of view), followed to its first ball; in parallel
/// with the `parallel` feature.
#[must_use]
pub fn render(space: &ProductSpace, scene: &ProductScene, width: u32, height: u32) -> Vec<ProductPixel> {
    let (w, h) = (width as usize, height as usize);
    let lit = Lit {
        objects: ProductObjects::of(space, scene),
        edge_color: scene.edges.map_or([0.0; 3], |e| e.color),
        lights: light_images(space, &scene.lights, scene.lighting),
        shadows: scene.lighting.shadows,
    };
    let cells = ProductCells::of(space);
    let cells = cells.as_ref();
    #[cfg(feature = "parallel")]
    let indices = (0..w * h).into_par_iter();
    #[cfg(not(feature = "parallel"))]
    let indices = 0..w * h;
    indices
        .map(|k| pixel(space, cells, &lit, &scene.view, (k % w, k / w), (w, h)))
        .collect()
}

/// What a [`render`] lights: the objects, the edges' colour, the light
/// images, and whether the objects shadow.
struct Lit {
    objects: ProductObjects,
    edge_color: [f32; 3],
    lights: Vec<ProductLightImage>,
    shadows: bool,
}

/// One pixel of [`render`].
fn pixel(
    space: &ProductSpace,
    cells: Option<&ProductCells>,
    lit: &Lit,
    view: &ProductView,
    (i, j): (usize, usize),
    (w, h): (usize, usize),
) -> ProductPixel {
    let g = space.geometry;
    let [forward, right, up] = view.frame;
    let [x, y] = view.slopes((i, j), (w, h));
    let dir = ProductTangent::new(
        forward.surface + right.surface * x + up.surface * y,
        forward.height + right.height * x + up.height * y,
    )
    .unit(g);
    let seen = hits_in(
        space,
        &lit.objects,
        ProductRay { origin: view.eye, dir },
        view.max_distance,
        view.max_crossings,
    );
    let Some(hit) = seen.first() else {
        return ProductPixel {
            object: 0,
            distance: f64::INFINITY,
            crossings: 0,
            cell: CellId::BEYOND_TABLE,
            color: FOG_COLOR,
        };
    };
    let cell = match (cells, view.cell) {
        (Some(cells), Some(eye)) => cells
            .element(&hit.faces)
            .and_then(|e| cells.compose(&eye, &e))
            .map_or(CellId::BEYOND_TABLE, |e| cells.id(&e)),
        _ => CellId::BEYOND_TABLE,
    };
    let tint = view.tint.map_or([1.0; 3], |t| t.tint(cell));
    let base = if hit.object == EDGE_ID {
        lit.edge_color
    } else {
        palette(hit.object)
    };
    let base: [f32; 3] = std::array::from_fn(|c| base[c] * tint[c]);
    let rgb: [f32; 3] = if lit.lights.is_empty() {
        // Lit from the eye: the cosine between the normal and the way
        // back along the ray.
        let lamp = -g.dot(hit.normal, hit.dir).clamp(-1.0, 0.0);
        let shade = 0.25 + 0.75 * lamp as f32;
        base.map(|b| b * shade)
    } else {
        let normal = hit.normal;
        let back = ProductTangent::new(-hit.dir.surface, -hit.dir.height);
        let light = direct(
            space,
            &lit.objects,
            &lit.lights,
            (hit.point, normal, back),
            base,
            view.fog,
            lit.shadows,
            view.max_crossings,
        );
        std::array::from_fn(|c| base[c] * AMBIENT + light[c])
    };
    let fog = (-view.fog * hit.distance).exp() as f32;
    ProductPixel {
        object: hit.object,
        distance: hit.distance,
        crossings: hit.faces.len(),
        cell,
        color: std::array::from_fn(|c| rgb[c] * fog + FOG_COLOR[c] * (1.0 - fog)),
    }
}

/// The ambient light of a lit scene (the other spaces' too). WGSL twin:
/// `AMBIENT` in `product.wgsl`.
pub const AMBIENT: f32 = 0.08;

/// The fog's colour, and what a ray that hits nothing sees.
pub const FOG_COLOR: [f32; 3] = [0.7, 0.75, 0.8];

/// A colour per object id (linear RGB), the balls' base colours.
#[must_use]
pub fn palette(id: u32) -> [f32; 3] {
    const COLORS: [[f32; 3]; 6] = [
        [0.9, 0.55, 0.2],
        [0.25, 0.6, 0.9],
        [0.4, 0.8, 0.35],
        [0.85, 0.3, 0.45],
        [0.8, 0.75, 0.3],
        [0.6, 0.45, 0.85],
    ];
    COLORS[id as usize % COLORS.len()]
}
