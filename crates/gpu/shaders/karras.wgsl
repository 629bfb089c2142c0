// The LBVH hierarchy of Karras 2012 ("Maximizing parallelism in the construction of
// BVHs, octrees and k-d trees", §3–4): over n sorted Morton codes, internal node i
// (0 ≤ i < n − 1) finds its key range and split from longest common prefixes alone, so
// all nodes are built at once. Equal codes are told apart by their index, as the paper
// does. Output per internal node: (left, right, first, last), a child being internal
// node j or leaf k | LEAF. Needs build_common.wgsl.

const LEAF: u32 = 0x80000000u;

struct KarrasParams {
    n: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

@group(0) @binding(0) var<storage, read> sorted_keys: array<u32>;
@group(0) @binding(1) var<storage, read_write> inner: array<vec4<u32>>;
@group(0) @binding(2) var<uniform> kp: KarrasParams;

// Length of the common prefix of keys i and j (with the index as tie-breaker), -1
// when j is outside the array.
fn delta(i: i32, j: i32) -> i32 {
    if j < 0 || j >= i32(kp.n) {
        return -1;
    }
    let a = sorted_keys[u32(i)];
    let b = sorted_keys[u32(j)];
    if a == b {
        return 32 + i32(countLeadingZeros(u32(i) ^ u32(j)));
    }
    return i32(countLeadingZeros(a ^ b));
}

@compute @workgroup_size(64)
fn hierarchy(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let idx = items_index(wid, lid, 64u);
    if idx + 1u >= kp.n {
        return;
    }
    let i = i32(idx);
    // The range extends towards the neighbour sharing the longer prefix.
    let d = select(-1, 1, delta(i, i + 1) > delta(i, i - 1));
    let dmin = delta(i, i - d);
    var lmax = 2;
    while delta(i, i + lmax * d) > dmin {
        lmax = lmax * 2;
    }
    var l = 0;
    for (var t = lmax / 2; t >= 1; t = t / 2) {
        if delta(i, i + (l + t) * d) > dmin {
            l = l + t;
        }
    }
    let j = i + l * d;
    let dnode = delta(i, j);
    // The split: the last key sharing more than dnode bits with key i.
    var s = 0;
    var t = l;
    loop {
        t = (t + 1) / 2;
        if delta(i, i + (s + t) * d) > dnode {
            s = s + t;
        }
        if t <= 1 {
            break;
        }
    }
    let gamma = i + s * d + min(d, 0);
    let first = min(i, j);
    let last = max(i, j);
    let left = select(u32(gamma), LEAF | u32(gamma), first == gamma);
    let right = select(u32(gamma + 1), LEAF | u32(gamma + 1), last == gamma + 1);
    inner[idx] = vec4<u32>(left, right, u32(first), u32(last));
}
