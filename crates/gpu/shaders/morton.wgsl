// The LBVH's first stage: the box of the triangle centroids, then a 30-bit Morton code
// per triangle (10 bits per axis of the centroid in that box). Needs build_common.wgsl.
//   centroid_bounds  per workgroup a reduction, then atomicMin/Max of ordered bits into
//                    cbox (initialised by the host to the empty box)
//   morton_codes     keys[i] = code of triangle i, vals[i] = i

struct MortonParams {
    n: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

@group(0) @binding(0) var<storage, read> mesh_tris: array<f32>;
@group(0) @binding(1) var<storage, read_write> cbox: array<atomic<u32>, 6>;
@group(0) @binding(2) var<storage, read_write> keys: array<u32>;
@group(0) @binding(3) var<storage, read_write> vals: array<u32>;
@group(0) @binding(4) var<uniform> mp: MortonParams;

const GROUP: u32 = 64u;

var<workgroup> group_lo: array<vec3<f32>, GROUP>;
var<workgroup> group_hi: array<vec3<f32>, GROUP>;

// As Triangle::centroid: (p0 + p1 + p2) · (1/3).
fn centroid(j: u32) -> vec3<f32> {
    let b = 9u * j;
    let p0 = vec3<f32>(mesh_tris[b], mesh_tris[b + 1u], mesh_tris[b + 2u]);
    let p1 = vec3<f32>(mesh_tris[b + 3u], mesh_tris[b + 4u], mesh_tris[b + 5u]);
    let p2 = vec3<f32>(mesh_tris[b + 6u], mesh_tris[b + 7u], mesh_tris[b + 8u]);
    return (p0 + p1 + p2) * (1.0 / 3.0);
}

@compute @workgroup_size(64)
fn centroid_bounds(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let i = items_index(wid, lid, GROUP);
    var lo = vec3<f32>(inf());
    var hi = vec3<f32>(-inf());
    if i < mp.n {
        lo = centroid(i);
        hi = lo;
    }
    group_lo[lid] = lo;
    group_hi[lid] = hi;
    for (var half = GROUP / 2u; half > 0u; half = half / 2u) {
        workgroupBarrier();
        if lid < half {
            group_lo[lid] = min(group_lo[lid], group_lo[lid + half]);
            group_hi[lid] = max(group_hi[lid], group_hi[lid + half]);
        }
    }
    if lid == 0u {
        for (var a = 0u; a < 3u; a = a + 1u) {
            atomicMin(&cbox[a], ordered(group_lo[0][a]));
            atomicMax(&cbox[3u + a], ordered(group_hi[0][a]));
        }
    }
}

// Ten bits spread to every third bit.
fn spread(v: u32) -> u32 {
    var x = v & 1023u;
    x = (x | (x << 16u)) & 0x030000ffu;
    x = (x | (x << 8u)) & 0x0300f00fu;
    x = (x | (x << 4u)) & 0x030c30c3u;
    x = (x | (x << 2u)) & 0x09249249u;
    return x;
}

@compute @workgroup_size(64)
fn morton_codes(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let i = items_index(wid, lid, GROUP);
    if i >= mp.n {
        return;
    }
    var lo: vec3<f32>;
    var ext: vec3<f32>;
    for (var a = 0u; a < 3u; a = a + 1u) {
        lo[a] = unordered(atomicLoad(&cbox[a]));
        ext[a] = unordered(atomicLoad(&cbox[3u + a])) - lo[a];
    }
    let c = centroid(i);
    var q: vec3<u32>;
    for (var a = 0u; a < 3u; a = a + 1u) {
        // A flat (or denormal-thin) axis puts every centroid in cell 0.
        let s = 1024.0 / ext[a];
        let scale = select(0.0, s, ext[a] > 0.0 && s < 3.0e38);
        q[a] = min(u32(max((c[a] - lo[a]) * scale, 0.0)), 1023u);
    }
    keys[i] = (spread(q.x) << 2u) | (spread(q.y) << 1u) | spread(q.z);
    vals[i] = i;
}
