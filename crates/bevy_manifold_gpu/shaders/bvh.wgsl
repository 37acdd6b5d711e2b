// Triangle meshes in their own chart, where a ray is affine: the packed
// mesh data, the slab test, Moller-Trumbore, and the BVH walk.
//
// Rust twin: crates/bevy_manifold_core/src/mesh/bvh.rs (MeshHit,
// hit_triangle, hit_box, safe_inverse, hit_mesh; with ALPHA_MASK,
// hit_mesh_where's test of each hit). The packing of mesh_data
// is GpuObjects::mesh_data in crates/bevy_manifold_gpu/src/layout.rs.
//
// Shader defs read: MESHES (the mesh part: compiled in only with meshes),
// ALPHA_MASK (a masked instance's transparent texels let rays through).
// The slab test and its inverse serve the ball tree too (cull.wgsl's
// interior_balls).
#define_import_path bevy_manifold::bvh

#import bevy_manifold::bindings::mesh_data
#ifdef MESHES
#import bevy_manifold::bindings::Instance
#endif
#ifdef ALPHA_MASK
#import bevy_manifold::texture::{hit_uv, mesh_alpha}
#endif

// mesh_data holds, per mesh: BVH nodes (two words each: min.xyz and,
// for a leaf, its first triangle, for an inner node its skip link, the
// node past its subtree (MeshData::skip); max.xyz and count; an inner
// node's left child is the next node), vertices (two words: position.xyz and u,
// normal.xyz and v), triangles (one word: three vertex indices) and
// textures (a header word [width, height, 0, 0], then four RGBA8 texels
// per word; texture.wgsl reads them). Floats are stored as their bits.
fn data_vec3(i: u32) -> vec3<f32> {
    return bitcast<vec3<f32>>(mesh_data[i].xyz);
}

// Entering s of o + s d into the box within [0, s_max]; -1 for a miss.
fn hit_box(o: vec3<f32>, inv_d: vec3<f32>, lo: vec3<f32>, hi: vec3<f32>, s_max: f32) -> f32 {
    let t0 = (lo - o) * inv_d;
    let t1 = (hi - o) * inv_d;
    let near = min(t0, t1);
    let far = max(t0, t1);
    let enter = max(max(near.x, near.y), max(near.z, 0.0));
    let leave = min(min(far.x, far.y), min(far.z, s_max));
    return select(-1.0, enter, enter <= leave);
}

// 1 / c, with |c| kept above 1e-20 so the slab test meets no infinity.
fn safe_inverse(c: vec3<f32>) -> vec3<f32> {
    let small = abs(c) < vec3<f32>(1.0e-20);
    return 1.0 / select(c, select(vec3<f32>(1.0e-20), vec3<f32>(-1.0e-20), c < vec3<f32>(0.0)), small);
}

// The walk by skip links of a hierarchy of `count` nodes packed at
// `nodes` in mesh_data (two words a node, as push_nodes packs them), from
// node *i: on to the next leaf whose box the ray o + s d meets within
// [0, s_max], returned as its first item and item count, *i left past it;
// (0, 0) once past the last node. A missed inner node's subtree is
// skipped by its skip link. Meshes (hit_mesh) and the instance trees
// (instance_tree.wgsl) walk by it. Rust twins: the loops of hit_mesh in
// crates/bevy_manifold_core/src/mesh/bvh.rs and tree_instances in
// crates/bevy_manifold_core/src/trace/instance_tree.rs.
fn next_met_leaf(nodes: u32, count: u32, o: vec3<f32>, inv_d: vec3<f32>, s_max: f32, i: ptr<function, u32>) -> vec2<u32> {
    loop {
        if *i >= count {
            break;
        }
        let w0 = mesh_data[nodes + 2u * *i];
        let w1 = mesh_data[nodes + 2u * *i + 1u];
        let met = hit_box(o, inv_d, bitcast<vec3<f32>>(w0.xyz), bitcast<vec3<f32>>(w1.xyz), s_max) >= 0.0;
        let leaf = w1.w > 0u;
        *i = select(max(w0.w, *i + 1u), *i + 1u, met || leaf);
        if met && leaf {
            return vec2<u32>(w0.w, w1.w);
        }
    }
    return vec2<u32>(0u, 0u);
}

#ifdef MESHES
// Rust twin: MeshHit in crates/bevy_manifold_core/src/mesh/bvh.rs.
struct MeshHit {
    s: f32,
    triangle: u32,
    u: f32,
    v: f32,
}

// Moller-Trumbore, either side: (s, u, v), s = -1 for a miss.
fn hit_triangle(o: vec3<f32>, d: vec3<f32>, a: vec3<f32>, b: vec3<f32>, c: vec3<f32>) -> vec3<f32> {
    let miss = vec3<f32>(-1.0, 0.0, 0.0);
    let e1 = b - a;
    let e2 = c - a;
    let p = cross(d, e2);
    let det = dot(e1, p);
    if det == 0.0 {
        return miss;
    }
    let inv = 1.0 / det;
    let q = o - a;
    let u = dot(q, p) * inv;
    if u < 0.0 || u > 1.0 {
        return miss;
    }
    let r = cross(q, e1);
    let v = dot(d, r) * inv;
    if v < 0.0 || u + v > 1.0 {
        return miss;
    }
    let s = dot(e2, r) * inv;
    return select(miss, vec3<f32>(s, u, v), s >= 0.0);
}

fn triangle_corner(inst: Instance, tri: vec4<u32>, k: u32) -> vec3<f32> {
    return data_vec3(inst.vertices + 2u * tri[k]);
}

// The nearest hit through the hierarchy by the skip links, without a
// stack (a per-lane array lavapipe reads and writes lane by lane): down
// to the next leaf whose box the ray meets within the nearest hit so far,
// then that leaf's triangles. Two loops, so lanes that found a leaf wait
// for the others and test their leaves together. The paper's scene
// (Suzanne, the hands) at 320x180, 8 levels, traced in 53-56 ms in the
// torus, against 82-84 with the ordered walk and its stack
// (docs/benchmarks/history.md, "Meshes by skip links"). Always forward, so at most
// node_count passes.
fn hit_mesh(inst: Instance, o: vec3<f32>, d: vec3<f32>, s_max: f32) -> MeshHit {
    let inv_d = safe_inverse(d);
    var best = MeshHit(-1.0, 0u, 0.0, 0.0);
    var limit = s_max;
    var i = 0u;
    loop {
        // Down to the next met leaf: its triangles, or none past the end.
        let leaf = next_met_leaf(inst.nodes, inst.node_count, o, inv_d, limit, &i);
        let first = leaf.x;
        let count = leaf.y;
        if count == 0u {
            break;
        }
        // Then its triangles.
        for (var t = first; t < first + count; t++) {
            let tri = mesh_data[inst.triangles + t];
            let h = hit_triangle(o, d, triangle_corner(inst, tri, 0u), triangle_corner(inst, tri, 1u), triangle_corner(inst, tri, 2u));
            if h.x >= 0.0 && h.x <= limit {
#ifdef ALPHA_MASK
                // Rust twin: hit_mesh_where's `keep` (an alpha mask).
                if inst.alpha_cutoff >= 0.0 && mesh_alpha(inst, hit_uv(inst, t, h.y, h.z)) < inst.alpha_cutoff {
                    continue;
                }
#endif
                limit = h.x;
                best = MeshHit(h.x, t, h.y, h.z);
            }
        }
    }
    return best;
}
#endif
