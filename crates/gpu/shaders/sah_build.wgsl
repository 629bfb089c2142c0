// Seed 003 §3.8's GPU builder: the binned SAH, level-synchronous, one workgroup per node
// of the level and 96 invocations = 3 axes × 32 bins. The level's nodes sit at slots
// base + p of a breadth-first array, their triangles in frontier[p] = [first, end) of
// the permutation ids_in. Per level (the host loops until no node splits):
//   sah_split    per node: its box (written), centroid box, the 3 × 32 bins, each
//                invocation one plane's cost, the cheapest plane or a leaf (the CPU
//                builder's rules) -> decisions[p], split_flags[p]
//   (scan of split_flags: each splitting node's rank r; its children are the next
//    level's nodes 2r and 2r + 1, so the next level is compacted, not a sparse heap)
//   sah_flags    per triangle slot: 1 if it goes to its node's left child
//   (scan of flags over n + 1 slots: left ranks and counts)
//   sah_emit     per node: index/count; the children's ranges into frontier_out
//   sah_scatter  per triangle slot: its new slot and node (a stable partition)
// Needs build_common.wgsl.

const BINS: u32 = 32u;
const PLANES: u32 = 96u;
const NONE: u32 = 0xffffffffu;
const KIND_LEAF: u32 = 0u;
const KIND_PLANE: u32 = 1u;
// Split by index into halves: coincident centroids, or the depth limit reached.
const KIND_HALVE: u32 = 2u;

struct BuildParams {
    count: u32,
    base: u32,
    next_base: u32,
    depth: u32,
    leaf_size: u32,
    max_leaf_size: u32,
    depth_limit: u32,
    n: u32,
    kt: f32,
    ki: f32,
    _pad0: u32,
    _pad1: u32,
}

struct Decision {
    kind: u32,
    axis: u32,
    plane: u32,
    _pad0: u32,
    cmin: f32,
    scale: f32,
    _pad1: f32,
    _pad2: f32,
}

@group(0) @binding(0) var<storage, read> mesh_tris: array<f32>;
@group(0) @binding(1) var<storage, read> ids_in: array<u32>;
@group(0) @binding(2) var<storage, read_write> ids_out: array<u32>;
@group(0) @binding(3) var<storage, read> frontier: array<vec2<u32>>;
@group(0) @binding(4) var<storage, read_write> frontier_out: array<vec2<u32>>;
@group(0) @binding(5) var<storage, read_write> decisions: array<Decision>;
@group(0) @binding(6) var<storage, read_write> nodes: array<Node>;
@group(0) @binding(7) var<storage, read_write> split_flags: array<u32>;
@group(0) @binding(8) var<storage, read_write> flags: array<u32>;
@group(0) @binding(9) var<storage, read> owner_in: array<u32>;
@group(0) @binding(10) var<storage, read_write> owner_out: array<u32>;
@group(0) @binding(11) var<uniform> bp: BuildParams;

var<workgroup> red_lo: array<vec3<f32>, PLANES>;
var<workgroup> red_hi: array<vec3<f32>, PLANES>;
var<workgroup> red_clo: array<vec3<f32>, PLANES>;
var<workgroup> red_chi: array<vec3<f32>, PLANES>;
var<workgroup> bin_count: array<atomic<u32>, PLANES>;
// Per bin (axis · 32 + bin) · 6: lo xyz, hi xyz as ordered bits.
var<workgroup> bin_box: array<atomic<u32>, 576>;
var<workgroup> plane_cost: array<f32, PLANES>;
// Per-axis prefix and suffix counts of the bins (sah_split's plane sweep; their boxes
// reuse the red_* arrays, free by then: workgroup memory is 16 KiB on some devices).
var<workgroup> pre_n: array<u32, PLANES>;
var<workgroup> suf_n: array<u32, PLANES>;
var<workgroup> s_area: f32;
var<workgroup> s_kind: u32;
var<workgroup> s_at: u32;
var<workgroup> s_cmin: vec3<f32>;
var<workgroup> s_scale: vec3<f32>;

fn corner(t: u32, v: u32) -> vec3<f32> {
    let b = 9u * t + 3u * v;
    return vec3<f32>(mesh_tris[b], mesh_tris[b + 1u], mesh_tris[b + 2u]);
}

// As Triangle::centroid.
fn centroid(t: u32) -> vec3<f32> {
    return (corner(t, 0u) + corner(t, 1u) + corner(t, 2u)) * (1.0 / 3.0);
}

// The bin of centroid coordinate c; sah_split and sah_flags compute it from the same
// stored cmin and scale, so they agree on every triangle.
fn bin_of(c: f32, cmin: f32, scale: f32) -> u32 {
    return min(u32(max((c - cmin) * scale, 0.0)), BINS - 1u);
}

// A node's triangle box and centroid box.
struct Boxes {
    lo: vec3<f32>,
    hi: vec3<f32>,
    clo: vec3<f32>,
    chi: vec3<f32>,
}

// The boxes of the triangles at slots first, first + stride, … below end.
fn node_boxes(first: u32, end: u32, stride: u32) -> Boxes {
    var b = Boxes(vec3<f32>(inf()), vec3<f32>(-inf()), vec3<f32>(inf()), vec3<f32>(-inf()));
    for (var j = first; j < end; j = j + stride) {
        let t = ids_in[j];
        for (var v = 0u; v < 3u; v = v + 1u) {
            let q = corner(t, v);
            b.lo = min(b.lo, q);
            b.hi = max(b.hi, q);
        }
        let c = centroid(t);
        b.clo = min(b.clo, c);
        b.chi = max(b.chi, c);
    }
    return b;
}

fn half_area(lo: vec3<f32>, hi: vec3<f32>) -> f32 {
    let d = hi - lo;
    return d.x * d.y + d.y * d.z + d.z * d.x;
}

fn area(lo: vec3<f32>, hi: vec3<f32>) -> f32 {
    return 2.0 * half_area(lo, hi);
}

// Nodes of at most this many triangles are split by one invocation (sah_split_small):
// a workgroup's barriers cost more than their whole binning.
const SMALL: u32 = 16u;

// Bins per axis over the centroid box's extent, 0 where the extent cannot separate.
fn bin_scale(ext: vec3<f32>) -> vec3<f32> {
    var scale = vec3<f32>(0.0);
    for (var a = 0u; a < 3u; a = a + 1u) {
        let s = f32(BINS) / ext[a];
        scale[a] = select(0.0, s, ext[a] > 0.0 && s < 3.0e38);
    }
    return scale;
}

// The CPU builder's tests before binning: small enough, nothing to separate, too deep.
fn kind_before_binning(n: u32, scale: vec3<f32>) -> u32 {
    if n == 1u || n < bp.leaf_size {
        return KIND_LEAF;
    } else if all(scale == vec3<f32>(0.0)) {
        return select(KIND_HALVE, KIND_LEAF, n <= bp.max_leaf_size);
    } else if bp.depth >= bp.depth_limit {
        return KIND_HALVE;
    }
    return KIND_PLANE;
}

// After the sweep: the cheapest plane `at` (axis · 32 + plane, NONE if no plane has
// triangles on both sides) of cost `best`, against Eq. 2.1's leaf cost K_I·n.
fn kind_after_sweep(n: u32, best: f32, at: u32, node_area: f32) -> u32 {
    if at == NONE {
        return KIND_HALVE;
    }
    let nf = f32(n);
    var split_cost = bp.kt + bp.ki * nf;
    if node_area > 0.0 {
        split_cost = bp.kt + bp.ki * best / node_area;
    }
    if split_cost > bp.ki * nf && n <= bp.max_leaf_size {
        return KIND_LEAF;
    }
    return KIND_PLANE;
}

fn plane_cost_of(llo: vec3<f32>, lhi: vec3<f32>, nl: u32, rlo: vec3<f32>, rhi: vec3<f32>, nr: u32) -> f32 {
    if nl > 0u && nr > 0u {
        return area(llo, lhi) * f32(nl) + area(rlo, rhi) * f32(nr);
    }
    return inf();
}

fn write_decision(e: u32, kind: u32, at: u32, cmin: vec3<f32>, scale: vec3<f32>) {
    var axis = 0u;
    var plane = 0u;
    if kind == KIND_PLANE {
        axis = at / BINS;
        plane = at % BINS;
    }
    decisions[e] = Decision(kind, axis, plane, 0u, cmin[axis], scale[axis], 0.0, 0.0);
    split_flags[e] = select(1u, 0u, kind == KIND_LEAF);
}

// One invocation per node of at most SMALL triangles, without per-invocation bin
// arrays (they cost lavapipe seconds of compilation): each occupied bin's left plane is
// costed by a pass over the node's triangles. Planes between two occupied bins give one
// partition at one cost, so this picks the partition sah_split's sweep picks (it keeps the
// lowest plane of the gap, this the highest; sah_flags splits both the same way).
@compute @workgroup_size(64)
fn sah_split_small(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let e = items_index(wid, lid, 64u);
    if e >= bp.count {
        return;
    }
    let range = frontier[e];
    let n = range.y - range.x;
    if n > SMALL {
        return;
    }
    let boxes = node_boxes(range.x, range.y, 1u);
    let lo = boxes.lo;
    let hi = boxes.hi;
    let clo = boxes.clo;
    let chi = boxes.chi;
    nodes[bp.base + e].lo = lo;
    nodes[bp.base + e].hi = hi;
    let scale = bin_scale(chi - clo);
    var kind = kind_before_binning(n, scale);
    var best = inf();
    var at = NONE;
    if kind == KIND_PLANE {
        for (var a = 0u; a < 3u; a = a + 1u) {
            if scale[a] == 0.0 {
                continue;
            }
            // Planes in increasing order: the lowest cost, first plane on ties.
            var last = 0u;
            loop {
                // The next occupied bin above `last`.
                var plane = BINS;
                for (var j = range.x; j < range.y; j = j + 1u) {
                    let b = bin_of(centroid(ids_in[j])[a], clo[a], scale[a]);
                    if b > last && b < plane {
                        plane = b;
                    }
                }
                if plane == BINS {
                    break;
                }
                var llo = vec3<f32>(inf());
                var lhi = vec3<f32>(-inf());
                var rlo = llo;
                var rhi = lhi;
                var nl = 0u;
                var nr = 0u;
                for (var j = range.x; j < range.y; j = j + 1u) {
                    let t = ids_in[j];
                    let p0 = corner(t, 0u);
                    let p1 = corner(t, 1u);
                    let p2 = corner(t, 2u);
                    let tlo = min(min(p0, p1), p2);
                    let thi = max(max(p0, p1), p2);
                    if bin_of(((p0 + p1 + p2) * (1.0 / 3.0))[a], clo[a], scale[a]) < plane {
                        llo = min(llo, tlo);
                        lhi = max(lhi, thi);
                        nl = nl + 1u;
                    } else {
                        rlo = min(rlo, tlo);
                        rhi = max(rhi, thi);
                        nr = nr + 1u;
                    }
                }
                let cost = plane_cost_of(llo, lhi, nl, rlo, rhi, nr);
                if cost < best {
                    best = cost;
                    at = a * BINS + plane;
                }
                last = plane;
            }
        }
        kind = kind_after_sweep(n, best, at, area(lo, hi));
    }
    write_decision(e, kind, at, clo, scale);
}

@compute @workgroup_size(96)
fn sah_split(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) nwg: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    let groups = nwg.x * nwg.y;
    for (var e = wid.x + wid.y * 65535u; e < bp.count; e = e + groups) {
        let range = frontier[e];
        let n = range.y - range.x;
        if n <= SMALL {
            continue;
        }
        let boxes = node_boxes(range.x + lid, range.y, PLANES);
        var lo = boxes.lo;
        var hi = boxes.hi;
        var clo = boxes.clo;
        var chi = boxes.chi;
        red_lo[lid] = lo;
        red_hi[lid] = hi;
        red_clo[lid] = clo;
        red_chi[lid] = chi;
        // The bins are reset while the boxes are reduced.
        atomicStore(&bin_count[lid], 0u);
        for (var k = 0u; k < 6u; k = k + 1u) {
            atomicStore(&bin_box[6u * lid + k], select(ordered(-inf()), ordered(inf()), k < 3u));
        }
        workgroupBarrier();
        if lid == 0u {
            for (var k = 1u; k < PLANES; k = k + 1u) {
                lo = min(lo, red_lo[k]);
                hi = max(hi, red_hi[k]);
                clo = min(clo, red_clo[k]);
                chi = max(chi, red_chi[k]);
            }
            let slot = bp.base + e;
            nodes[slot].lo = lo;
            nodes[slot].hi = hi;
            let scale = bin_scale(chi - clo);
            let kind = kind_before_binning(n, scale);
            s_kind = kind;
            s_cmin = clo;
            s_scale = scale;
            s_at = NONE;
            s_area = area(lo, hi);
        }
        let kind = workgroupUniformLoad(&s_kind);
        if kind == KIND_PLANE {
            let cmin = s_cmin;
            let scale = s_scale;
            for (var j = range.x + lid; j < range.y; j = j + PLANES) {
                let t = ids_in[j];
                let c = centroid(t);
                let p0 = corner(t, 0u);
                let p1 = corner(t, 1u);
                let p2 = corner(t, 2u);
                let tlo = min(min(p0, p1), p2);
                let thi = max(max(p0, p1), p2);
                for (var a = 0u; a < 3u; a = a + 1u) {
                    if scale[a] > 0.0 {
                        let b = a * BINS + bin_of(c[a], cmin[a], scale[a]);
                        atomicAdd(&bin_count[b], 1u);
                        for (var k = 0u; k < 3u; k = k + 1u) {
                            atomicMin(&bin_box[6u * b + k], ordered(tlo[k]));
                            atomicMax(&bin_box[6u * b + 3u + k], ordered(thi[k]));
                        }
                    }
                }
            }
            workgroupBarrier();
            // Invocation lid owns bin lid % 32 of axis lid / 32: its box and count leave
            // the atomics once, then a prefix (left of the bin, inclusive) and a suffix
            // (from the bin on) scan within the axis, five steps each.
            let axis = lid / BINS;
            let bin = lid % BINS;
            var plo = vec3<f32>(
                unordered(atomicLoad(&bin_box[6u * lid])),
                unordered(atomicLoad(&bin_box[6u * lid + 1u])),
                unordered(atomicLoad(&bin_box[6u * lid + 2u])),
            );
            var phi = vec3<f32>(
                unordered(atomicLoad(&bin_box[6u * lid + 3u])),
                unordered(atomicLoad(&bin_box[6u * lid + 4u])),
                unordered(atomicLoad(&bin_box[6u * lid + 5u])),
            );
            var pn = atomicLoad(&bin_count[lid]);
            var slo = plo;
            var shi = phi;
            var sn = pn;
            red_lo[lid] = plo;
            red_hi[lid] = phi;
            pre_n[lid] = pn;
            red_clo[lid] = slo;
            red_chi[lid] = shi;
            suf_n[lid] = sn;
            for (var off = 1u; off < BINS; off = off * 2u) {
                workgroupBarrier();
                if bin >= off {
                    plo = min(plo, red_lo[lid - off]);
                    phi = max(phi, red_hi[lid - off]);
                    pn = pn + pre_n[lid - off];
                }
                if bin + off < BINS {
                    slo = min(slo, red_clo[lid + off]);
                    shi = max(shi, red_chi[lid + off]);
                    sn = sn + suf_n[lid + off];
                }
                workgroupBarrier();
                red_lo[lid] = plo;
                red_hi[lid] = phi;
                pre_n[lid] = pn;
                red_clo[lid] = slo;
                red_chi[lid] = shi;
                suf_n[lid] = sn;
            }
            workgroupBarrier();
            // Plane `bin` lies between bins bin − 1 and bin (plane 0 is no plane).
            var cost = inf();
            if bin >= 1u && scale[axis] > 0.0 {
                cost = plane_cost_of(red_lo[lid - 1u], red_hi[lid - 1u], pre_n[lid - 1u], slo, shi, sn);
            }
            plane_cost[lid] = cost;
            workgroupBarrier();
            if lid == 0u {
                // Strict `<` over axis-major order: the first axis and plane win ties,
                // as on the CPU.
                var best = inf();
                var at = NONE;
                for (var k = 0u; k < PLANES; k = k + 1u) {
                    if plane_cost[k] < best {
                        best = plane_cost[k];
                        at = k;
                    }
                }
                s_kind = kind_after_sweep(n, best, at, s_area);
                s_at = at;
            }
        }
        workgroupBarrier();
        if lid == 0u {
            write_decision(e, s_kind, s_at, s_cmin, s_scale);
        }
        workgroupBarrier();
    }
}

@compute @workgroup_size(64)
fn sah_flags(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let i = items_index(wid, lid, 64u);
    if i > bp.n {
        return;
    }
    var f = 0u;
    if i < bp.n {
        let o = owner_in[i];
        if o != NONE {
            let d = decisions[o];
            if d.kind == KIND_PLANE {
                let c = centroid(ids_in[i]);
                f = select(0u, 1u, bin_of(c[d.axis], d.cmin, d.scale) < d.plane);
            } else if d.kind == KIND_HALVE {
                let r = frontier[o];
                f = select(0u, 1u, i - r.x < (r.y - r.x) / 2u);
            }
        }
    }
    flags[i] = f;
}

@compute @workgroup_size(64)
fn sah_emit(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let p = items_index(wid, lid, 64u);
    if p >= bp.count {
        return;
    }
    let r = frontier[p];
    let slot = bp.base + p;
    if decisions[p].kind == KIND_LEAF {
        nodes[slot].index = r.x;
        nodes[slot].count = r.y - r.x;
    } else {
        let rank = split_flags[p];
        nodes[slot].index = bp.next_base + 2u * rank;
        nodes[slot].count = 0u;
        let mid = r.x + flags[r.y] - flags[r.x];
        frontier_out[2u * rank] = vec2<u32>(r.x, mid);
        frontier_out[2u * rank + 1u] = vec2<u32>(mid, r.y);
    }
}

@compute @workgroup_size(64)
fn sah_scatter(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let i = items_index(wid, lid, 64u);
    if i >= bp.n {
        return;
    }
    let o = owner_in[i];
    let id = ids_in[i];
    if o == NONE || decisions[o].kind == KIND_LEAF {
        ids_out[i] = id;
        owner_out[i] = NONE;
        return;
    }
    let r = frontier[o];
    let lb = flags[r.x];
    let nl = flags[r.y] - lb;
    let lr = flags[i] - lb;
    let left = flags[i + 1u] != flags[i];
    let dst = select(r.x + nl + (i - r.x - lr), r.x + lr, left);
    ids_out[dst] = id;
    owner_out[dst] = 2u * split_flags[o] + select(1u, 0u, left);
}
