// What the BVH builders' kernels share (crates/gpu/src/build/): the 32-byte node of
// crates/accel/src/bvh/node.rs (as bvh_traverse.wgsl reads it), triangles as 9 floats,
// and floats as order-preserving u32s, so that atomicMin/atomicMax compute float bounds.

struct Node {
    lo: vec3<f32>,
    // Interior: left child (the right one follows it). Leaf: first triangle.
    index: u32,
    hi: vec3<f32>,
    // 0 for an interior node, else the leaf's triangle count.
    count: u32,
}

// +infinity (a runtime bitcast: WGSL constants cannot overflow).
fn inf() -> f32 {
    return bitcast<f32>(0x7f800000u);
}

fn items_index(wid: vec3<u32>, lid: u32, size: u32) -> u32 {
    return (wid.x + wid.y * 65535u) * size + lid;
}

// The u32 whose unsigned order is the float order of `f` (not NaN).
fn ordered(f: f32) -> u32 {
    let b = bitcast<u32>(f);
    return select(b | 0x80000000u, ~b, (b & 0x80000000u) != 0u);
}

fn unordered(u: u32) -> f32 {
    return bitcast<f32>(select(~u, u & 0x7fffffffu, (u & 0x80000000u) != 0u));
}
