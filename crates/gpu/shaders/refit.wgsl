// Bounds of a breadth-first node array (what the GPU builders write), bottom-up one
// level per dispatch: every node of a level reads its children's boxes (or its leaf
// triangles), which the previous dispatch finished, so no inter-workgroup
// synchronisation is needed and the boxes are the exact unions the CPU would compute.
//   gather_triangles  tris[i] = mesh_tris[ids[i]] (leaf order, for a new pose too)
//   refit_level       nodes[first .. first + count]'s boxes
// Needs build_common.wgsl.

struct RefitParams {
    first: u32,
    count: u32,
    _pad0: u32,
    _pad1: u32,
}

@group(0) @binding(0) var<storage, read_write> nodes: array<Node>;
@group(0) @binding(1) var<storage, read> tris: array<f32>;
@group(0) @binding(2) var<uniform> rp: RefitParams;
@group(0) @binding(3) var<storage, read> mesh_tris: array<f32>;
@group(0) @binding(4) var<storage, read> ids: array<u32>;
@group(0) @binding(5) var<storage, read_write> tris_out: array<f32>;

@compute @workgroup_size(64)
fn gather_triangles(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let i = items_index(wid, lid, 64u);
    if i >= rp.count {
        return;
    }
    let src = 9u * ids[i];
    for (var k = 0u; k < 9u; k = k + 1u) {
        tris_out[9u * i + k] = mesh_tris[src + k];
    }
}

@compute @workgroup_size(64)
fn refit_level(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let p = items_index(wid, lid, 64u);
    if p >= rp.count {
        return;
    }
    let s = rp.first + p;
    let n = nodes[s];
    var lo = vec3<f32>(inf());
    var hi = vec3<f32>(-inf());
    if n.count != 0u {
        for (var j = n.index; j < n.index + n.count; j = j + 1u) {
            for (var v = 0u; v < 3u; v = v + 1u) {
                let b = 9u * j + 3u * v;
                let q = vec3<f32>(tris[b], tris[b + 1u], tris[b + 2u]);
                lo = min(lo, q);
                hi = max(hi, q);
            }
        }
    } else {
        let a = nodes[n.index];
        let b = nodes[n.index + 1u];
        lo = min(a.lo, b.lo);
        hi = max(a.hi, b.hi);
    }
    nodes[s].lo = lo;
    nodes[s].hi = hi;
}
