// The instance tree: of a face group of many mesh instances, only those
// in the leaves of its hierarchy (over their bounding balls' chart boxes)
// that the segment's chart image meets before the nearest hit so far,
// nearest leaves first (one order of the nodes per octant of the
// segment's direction).
//
// Rust twin: crates/bevy_manifold_core/src/trace/instance_tree.rs
// (octant, chart_fraction, tree_instances), as each_candidate (cull.rs)
// calls it. The table and the nodes are packed into mesh_data by
// GpuObjects::instance_trees (crates/bevy_manifold_gpu/src/pack/objects.rs).
//
// Shader defs read: INSTANCE_TREE (the whole module: a scene with a
// group of MIN_INSTANCE_TREE instances or more), and through
// consider_instance and still_wanted MESHES, FOOTPRINT and SHADOWS.
#define_import_path bevy_manifold::instance_tree

#ifdef INSTANCE_TREE
#import bevy_manifold::bindings::mesh_data
#import bevy_manifold::step::Ray
#import bevy_manifold::ball_tree::ChartSegment
#import bevy_manifold::bvh::{next_met_leaf, safe_inverse}
#import bevy_manifold::nearest::{consider_instance, still_wanted}

// Where along the chart segment (0 at its start, 1 at its end) the point
// of chart parameter t lies, a little further for rounding.
fn chart_fraction(ray: Ray, t_end: f32, t: f32) -> f32 {
    if !(t < t_end) {
        return 1.0;
    }
    let w0 = ray.origin.w;
    let w1 = (ray.origin + ray.dir * t_end).w;
    let l = max(t / t_end, 0.0);
    let s = l * w1 / ((1.0 - l) * w0 + l * w1);
    return min(s * 1.0001 + 1.0e-6, 1.0);
}

// Hands consider_instance the instances of one group of a tree in the
// leaves the segment `seg` (chart_segment, usable) meets before
// still_wanted; `entry` is the group's word of the trees' table. False,
// having handed none, when the group has no tree (the caller then tests
// each instance of the group). Two loops, as hit_mesh's (bvh.wgsl): down
// to the next met leaf (next_met_leaf), then its instances, so lanes that
// found a leaf test them together.
fn tree_instances(ray: Ray, t_end: f32, cell_point: vec4<f32>, near: u32, seg: ChartSegment, entry: u32) -> bool {
    let table = mesh_data[entry];
    let count = table.y;
    if count == 0u {
        return false;
    }
    let d = seg.d;
    // Rust twin: octant.
    let octant = select(0u, 1u, d.x < 0.0) | select(0u, 2u, d.y < 0.0) | select(0u, 4u, d.z < 0.0);
    let nodes = table.x + 2u * count * octant;
    let inv_d = safe_inverse(d);
    var s_max = 1.0;
    var i = 0u;
    loop {
        let leaf = next_met_leaf(nodes, count, seg.a, inv_d, s_max, &i);
        if leaf.y == 0u {
            break;
        }
        for (var k = leaf.x; k < leaf.x + leaf.y; k++) {
            consider_instance(ray, t_end, cell_point, near, k);
        }
        s_max = chart_fraction(ray, t_end, still_wanted(t_end));
    }
    return true;
}
#endif
