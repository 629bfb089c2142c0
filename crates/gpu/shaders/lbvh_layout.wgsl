// The LBVH's node array in the engine's layout (children pairs adjacent and after
// their parent, which Karras' numbering is not): a top-down breadth-first relabelling,
// one level per round. The level's nodes sit at slots base + p in `frontier_in` order;
//   layout_flags  flags[p] = 1 for an internal node (then scan.wgsl: each internal
//                 node's rank among the level's internal nodes, their count)
//   layout_emit   writes each node's index/count; internal node of rank r gets the pair
//                 next_base + 2r, 2r + 1 and puts its children there in the next level
// Bounds come afterwards (refit.wgsl). Needs build_common.wgsl.

const LEAF: u32 = 0x80000000u;

struct LayoutParams {
    count: u32,
    base: u32,
    next_base: u32,
    _pad: u32,
}

@group(0) @binding(0) var<storage, read> inner: array<vec4<u32>>;
@group(0) @binding(1) var<storage, read> frontier_in: array<u32>;
@group(0) @binding(2) var<storage, read_write> frontier_out: array<u32>;
@group(0) @binding(3) var<storage, read_write> flags: array<u32>;
@group(0) @binding(4) var<storage, read_write> nodes: array<Node>;
@group(0) @binding(5) var<uniform> lp: LayoutParams;

@compute @workgroup_size(64)
fn layout_flags(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let p = items_index(wid, lid, 64u);
    if p < lp.count {
        flags[p] = select(0u, 1u, (frontier_in[p] & LEAF) == 0u);
    }
}

@compute @workgroup_size(64)
fn layout_emit(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let p = items_index(wid, lid, 64u);
    if p >= lp.count {
        return;
    }
    let r = frontier_in[p];
    let slot = lp.base + p;
    if (r & LEAF) != 0u {
        // LBVH leaves hold one triangle, at its sorted position.
        nodes[slot].index = r & ~LEAF;
        nodes[slot].count = 1u;
    } else {
        let rank = flags[p];
        nodes[slot].index = lp.next_base + 2u * rank;
        nodes[slot].count = 0u;
        let q = inner[r];
        frontier_out[2u * rank] = q.x;
        frontier_out[2u * rank + 1u] = q.y;
    }
}
