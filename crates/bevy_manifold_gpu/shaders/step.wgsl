// The steps of Algorithm 1 on one ray: where it crosses a face, how it
// advances to there and is carried through the pairing, and where it meets
// a ball or a tube. A ray is a normalised point and a unit tangent there;
// its points are o + t d in the chart.
//
// Rust twin: crates/bevy_manifold_core/src/trace/step.rs (same names, same
// order of functions, same arithmetic in the same order).
//
// Shader defs read: TRANSLATIONS_ONLY (transport), BALL_HITS (hit_ball),
// TUBES (hit_tube, foot_on_line), GEOMETRY_HYPERBOLIC / GEOMETRY_SPHERICAL
// / GEOMETRY_EUCLIDEAN (the quadrics); MESHES through bindings.
#define_import_path bevy_manifold::step

#import bevy_manifold::bindings::{params, cached, faces, Tube, NO_FACE, FLAG_NO_RENORMALIZE, FLAG_NO_CULL, face_count, face_plane}
#import bevy_manifold::geometry::{form, normalize_point, normalize_tangent}

// Rust twin: Ray in crates/bevy_manifold_core/src/trace/step.rs.
struct Ray {
    origin: vec4<f32>,
    dir: vec4<f32>,
}

// Where a ray crosses a face: the nearest face it leaves through
// (n . d > 0), skipping the face it just entered; t = -(n . o) / (n . d),
// clamped at 0 so a point a hair outside leaves at once. Rust twin: what
// exit_face returns, Option<(usize, R)> (NO_FACE for None).
struct Exit {
    face: u32,
    t: f32,
}

// Where a ray crosses a face (see Exit); NO_FACE when it leaves by none.
fn exit_face(ray: Ray, skip: u32) -> Exit {
    var best = Exit(NO_FACE, 0.0);
#ifdef FACE_COUNT
    // In chunks of FACE_CHUNK with constant bounds (see FACE_CHUNK).
    let n = face_count();
    best = exit_faces_in(ray, skip, best, 0u, min(n, FACE_CHUNK));
    best = exit_faces_in(ray, skip, best, FACE_CHUNK, min(n, 2u * FACE_CHUNK));
    best = exit_faces_in(ray, skip, best, 2u * FACE_CHUNK, min(n, 3u * FACE_CHUNK));
    best = exit_faces_in(ray, skip, best, 3u * FACE_CHUNK, min(n, 4u * FACE_CHUNK));
    best = exit_faces_in(ray, skip, best, 4u * FACE_CHUNK, min(n, 5u * FACE_CHUNK));
    best = exit_faces_in(ray, skip, best, 5u * FACE_CHUNK, min(n, 6u * FACE_CHUNK));
    best = exit_faces_in(ray, skip, best, 6u * FACE_CHUNK, min(n, 7u * FACE_CHUNK));
    best = exit_faces_in(ray, skip, best, 7u * FACE_CHUNK, min(n, 8u * FACE_CHUNK));
#else
    best = exit_faces_in(ray, skip, best, 0u, face_count());
#endif
    return best;
}

// The faces lo to hi - 1 of exit_face's loop, after `best`. The entered
// face is left out by the condition, not by a `continue` as in Rust: a
// continue some lanes take makes lavapipe step `i` under a mask, so the
// unrolled loop's index is no longer a constant and each plane is read
// lane by lane (the 52-face frame with nothing to hit: 11% slower).
fn exit_faces_in(ray: Ray, skip: u32, best_in: Exit, lo: u32, hi: u32) -> Exit {
    var best = best_in;
    for (var i = lo; i < hi; i++) {
        let n = face_plane(i);
        let no = dot(n, ray.origin);
        let nd = dot(n, ray.dir);
        if i != skip && nd > 0.0 {
            let t = max(-no / nd, 0.0);
            if best.face == NO_FACE || t < best.t {
                best = Exit(i, t);
            }
        }
    }
    return best;
}

// The most faces one of exit_face's and near_faces' loops takes under
// FACE_COUNT: the faces come in up to 8 chunks (MAX_FACES / 16), each a
// loop with constant bounds, which LLVM unrolls (it left a 52-face loop
// rolled, and lavapipe then gathers each plane lane by lane). WGSL only:
// Rust loops over the faces once.
const FACE_CHUNK: u32 = 16u;

// Every face bit. Rust twin: ALL_FACES.
const ALL_FACES: u32 = 0xffffffffu;

// The faces the segment o + t d, 0 <= t <= t_end, comes near: bit i set
// when some point of it may be within `within` of face i's plane
// (params.near_reach, near_scale times s(r); grown objects reach
// further): |n . p| / p_w is monotone along the segment, so its ends
// decide, or a change of sign. Faces from 32 on fold onto bit i % 32, set
// when any of its faces is near; a segment with no finite end is near
// all. FLAG_NO_CULL: all near. The planes come from bindings' `planes`
// (face_plane), at constant indices once the chunks are unrolled.
// Rust twin: near_faces in crates/bevy_manifold_core/src/trace/step.rs
// (takes the planes and the scale apart).
fn near_faces(ray: Ray, t_end: f32, within: f32) -> u32 {
    if (cached.flags & FLAG_NO_CULL) != 0u || !(t_end < 3.0e38) || !(within < 3.0e38) {
        return ALL_FACES;
    }
    let wa = ray.origin.w;
    let wb = (ray.origin + ray.dir * t_end).w;
    var near = ALL_FACES;
#ifdef FACE_COUNT
    // In chunks of FACE_CHUNK with constant bounds (see FACE_CHUNK).
    let n = face_count();
    near = near_faces_in(ray, t_end, within, wa, wb, near, 0u, min(n, FACE_CHUNK));
    near = near_faces_in(ray, t_end, within, wa, wb, near, FACE_CHUNK, min(n, 2u * FACE_CHUNK));
    near = near_faces_in(ray, t_end, within, wa, wb, near, 2u * FACE_CHUNK, min(n, 3u * FACE_CHUNK));
    near = near_faces_in(ray, t_end, within, wa, wb, near, 3u * FACE_CHUNK, min(n, 4u * FACE_CHUNK));
    near = near_faces_in(ray, t_end, within, wa, wb, near, 4u * FACE_CHUNK, min(n, 5u * FACE_CHUNK));
    near = near_faces_in(ray, t_end, within, wa, wb, near, 5u * FACE_CHUNK, min(n, 6u * FACE_CHUNK));
    near = near_faces_in(ray, t_end, within, wa, wb, near, 6u * FACE_CHUNK, min(n, 7u * FACE_CHUNK));
    near = near_faces_in(ray, t_end, within, wa, wb, near, 7u * FACE_CHUNK, min(n, 8u * FACE_CHUNK));
#else
    near = near_faces_in(ray, t_end, within, wa, wb, near, 0u, face_count());
#endif
    return near;
}

// The faces lo to hi - 1 of near_faces' loop, from `near_in`.
fn near_faces_in(ray: Ray, t_end: f32, within: f32, wa: f32, wb: f32, near_in: u32, lo: u32, hi: u32) -> u32 {
    var near = near_in;
    for (var i = lo; i < hi; i++) {
        // n . o and n . d for this ray; the end's value from them.
        let sa = dot(face_plane(i), ray.origin);
        let sd = dot(face_plane(i), ray.dir);
        let sb = sa + t_end * sd;
        let crosses = (sa < 0.0) != (sb < 0.0);
        let is_near = crosses || abs(sa) <= within * wa || abs(sb) <= within * wb;
        // Faces 0 to 31 clear their bit when far; the folded ones set it
        // again when near.
        if i < 32u && !is_near {
            near &= ~(1u << i);
        } else if i >= 32u && is_near {
            near |= 1u << (i % 32u);
        }
    }
    return near;
}

// True when an object with face mask `mask` can be hit on a segment near
// the faces `near`. Rust twin: may_hit.
fn may_hit(mask: u32, near: u32) -> bool {
    return (mask & ~near) == 0u;
}

fn advance(ray: Ray, t: f32) -> Ray {
    let p = normalize_point(ray.origin + ray.dir * t);
    return Ray(p, normalize_tangent(p, ray.dir));
}

// advance without renormalisation (measuring drift only): the factors
// that are exact for a normalised ray, not measured from the vectors.
fn advance_raw(ray: Ray, t: f32) -> Ray {
    let o = ray.origin;
    let d = ray.dir;
#ifdef GEOMETRY_HYPERBOLIC
    let s = 1.0 / sqrt(1.0 - t * t);
    return Ray((o + d * t) * s, (o * t + d) * s);
#else ifdef GEOMETRY_SPHERICAL
    let s = 1.0 / sqrt(1.0 + t * t);
    return Ray((o + d * t) * s, (d - o * t) * s);
#else
    return Ray(o + d * t, d);
#endif
}

// Rust passes `renormalize` in (TraceSettings::renormalize); here it is
// the FLAG_NO_RENORMALIZE bit of Params::flags.
fn renormalize() -> bool {
    return (cached.flags & FLAG_NO_RENORMALIZE) == 0u;
}

// advance, or advance_raw when FLAG_NO_RENORMALIZE is set.
fn advance_or_raw(ray: Ray, t: f32) -> Ray {
    if renormalize() {
        return advance(ray, t);
    }
    return advance_raw(ray, t);
}

// Carries a ray that reached `face` through its pairing T_face, and
// renormalises it. (Rust takes the pairing matrix; here the face index.)
fn transport(face: u32, ray: Ray) -> Ray {
#ifdef TRANSLATIONS_ONLY
    // A translation moves the point and leaves directions alone.
    return Ray(faces[face].pairing * ray.origin, ray.dir);
#else
    let o = normalize_point(faces[face].pairing * ray.origin);
    return Ray(o, normalize_tangent(o, faces[face].pairing * ray.dir));
#endif
}

// transport without renormalisation (measuring drift only).
fn transport_raw(face: u32, ray: Ray) -> Ray {
    return Ray(faces[face].pairing * ray.origin, faces[face].pairing * ray.dir);
}

// transport, or transport_raw when FLAG_NO_RENORMALIZE is set.
fn transport_or_raw(face: u32, ray: Ray) -> Ray {
    if renormalize() {
        return transport(face, ray);
    }
    return transport_raw(face, ray);
}

// Smallest t >= t_min where a t^2 + 2 b t + c goes from positive to
// non-positive; -1 when none.
fn entering_root(a: f32, b: f32, c: f32, t_min: f32) -> f32 {
    let disc = b * b - a * c;
    if disc < 0.0 {
        return -1.0;
    }
    let s = sqrt(disc);
    let q = select(-(b + s), s - b, b < 0.0);
    var best = -1.0;
    if q != 0.0 {
        let t = c / q;
        if t >= t_min && a * t + b < 0.0 {
            best = t;
        }
    }
    if abs(a) > 1.1920929e-7 * (abs(b) + abs(c)) {
        let t = q / a;
        if t >= t_min && a * t + b < 0.0 && (best < 0.0 || t < best) {
            best = t;
        }
    }
    return best;
}

#ifdef BALL_HITS
// Balls, and the bounding balls of mesh instances.
fn hit_ball(ray: Ray, c: vec4<f32>, k: f32, t_min: f32) -> f32 {
    let o = ray.origin;
    let d = ray.dir;
#ifdef GEOMETRY_HYPERBOLIC
    let a0 = form(o, c);
    let b0 = form(d, c);
    let t = entering_root(b0 * b0 + k * k, a0 * b0, a0 * a0 - k * k, t_min);
    return select(-1.0, t, t >= 0.0 && a0 + t * b0 < 0.0);
#else ifdef GEOMETRY_SPHERICAL
    let a0 = form(o, c);
    let b0 = form(d, c);
    let t = entering_root(k * k - b0 * b0, -(a0 * b0), k * k - a0 * a0, t_min);
    return select(-1.0, t, t >= 0.0 && a0 + t * b0 > 0.0);
#else
    let q = o - c;
    let b = form(q, d);
    return entering_root(form(d, d), b, form(q, q) - k, t_min);
#endif
}
#endif

#ifdef TUBES
fn hit_tube(ray: Ray, seg: Tube, k: f32, t_min: f32) -> f32 {
    let o = ray.origin;
    let d = ray.dir;
#ifdef GEOMETRY_HYPERBOLIC
    let a1 = form(o, seg.a);
    let b1 = form(d, seg.a);
    let a2 = form(o, seg.e);
    let b2 = form(d, seg.e);
    let t = entering_root(b1 * b1 - b2 * b2 + k * k, a1 * b1 - a2 * b2, a1 * a1 - a2 * a2 - k * k, t_min);
#else ifdef GEOMETRY_SPHERICAL
    let a1 = form(o, seg.a);
    let b1 = form(d, seg.a);
    let a2 = form(o, seg.e);
    let b2 = form(d, seg.e);
    let t = entering_root(k * k - b1 * b1 - b2 * b2, -(a1 * b1 + a2 * b2), k * k - a1 * a1 - a2 * a2, t_min);
#else
    let q = o - seg.a;
    let qe = form(q, seg.e);
    let de = form(d, seg.e);
    let t = entering_root(1.0 - de * de, form(q, d) - qe * de, form(q, q) - qe * qe - k, t_min);
#endif
    if t < 0.0 {
        return -1.0;
    }
    return select(-1.0, t, on_edge(o + d * t, seg));
}

// True when p lies between the tube's end planes. Rust twin: on_edge.
fn on_edge(p: vec4<f32>, seg: Tube) -> bool {
#ifdef GEOMETRY_EUCLIDEAN
    let along_a = form(p - seg.a, seg.e);
    let along_b = form(p - seg.b, seg.e_b);
#else
    let along_a = form(p, seg.e);
    let along_b = form(p, seg.e_b);
#endif
    return along_a >= 0.0 && along_b <= 0.0;
}

fn foot_on_line(x: vec4<f32>, seg: Tube) -> vec4<f32> {
#ifdef GEOMETRY_HYPERBOLIC
    return seg.e * form(x, seg.e) - seg.a * form(x, seg.a);
#else ifdef GEOMETRY_SPHERICAL
    return seg.a * form(x, seg.a) + seg.e * form(x, seg.e);
#else
    return seg.a + seg.e * form(x - seg.a, seg.e);
#endif
}
#endif

fn normal_from(x: vec4<f32>, c: vec4<f32>) -> vec4<f32> {
    return normalize_tangent(x, -c);
}
