// Batch queries: one invocation per ray of `rays` (two vec4 each: origin xyz, dir x;
// dir yz, tmin, tmax — the CPU's 32-byte Ray), answers in ray order.

struct Params {
    count: u32,
}

@group(0) @binding(0) var<storage, read> nodes: array<Node>;
@group(0) @binding(1) var<storage, read> tris: array<f32>;
@group(0) @binding(2) var<storage, read> ids: array<u32>;
@group(0) @binding(3) var<storage, read> rays: array<vec4<f32>>;
@group(0) @binding(4) var<uniform> params: Params;
@group(0) @binding(5) var<storage, read_write> hits: array<Hit>;
@group(0) @binding(6) var<storage, read_write> occluded: array<u32>;

fn load_ray(i: u32) -> PRay {
    let a = rays[2u * i];
    let b = rays[2u * i + 1u];
    return prepare(a.xyz, vec3<f32>(a.w, b.x, b.y), b.z, b.w);
}

@compute @workgroup_size(64)
fn closest(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= params.count {
        return;
    }
    hits[i] = closest_hit(load_ray(i));
}

@compute @workgroup_size(64)
fn occlusion(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= params.count {
        return;
    }
    occluded[i] = select(0u, 1u, any_hit(load_ray(i)));
}
