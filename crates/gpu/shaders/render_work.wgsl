// The queues and outputs of the render kernels (group 1, bound per dispatch by
// src/render/work.rs; a kernel uses the slots it needs, the others hold placeholders).

// A ray waiting to be traced: 64 bytes (RayRec in src/render/work.rs).
struct RayRec {
    org: vec3<f32>,
    // Pixel sample it contributes to (k = pixel · spp + s).
    sample: u32,
    dir: vec3<f32>,
    // Primary = 1.
    level: u32,
    // Colour throughput: the product of the coefficients from the camera to this ray.
    thr: vec3<f32>,
    // Seed 003's scalar weight: parent weight × max component of the coefficient.
    weight: f32,
    // The cumulative integrator's path number (crates/render/src/cumulative/paths.rs
    // `id`) and its sample's key: what its choice hashes (choice_random).
    path: u32,
    key: u32,
    // The path tracer's previous vertex (path_shade.wgsl): its BSDF sample's density, and
    // 1 when that sample came from a smooth lobe (0 after the camera or a delta bounce:
    // emission found next is weighted 1). Unused by the other integrators.
    prev_pdf: f32,
    prev_smooth: u32,
}

struct Work {
    // Items of this dispatch.
    n: u32,
    a: u32,
    b: u32,
    c: u32,
}

@group(1) @binding(0) var<storage, read_write> rays_in: array<RayRec>;
@group(1) @binding(1) var<storage, read_write> rays_out: array<RayRec>;
@group(1) @binding(2) var<storage, read_write> hits: array<Hit>;
@group(1) @binding(3) var<storage, read_write> list_in: array<u32>;
@group(1) @binding(4) var<storage, read_write> list_out: array<u32>;
@group(1) @binding(5) var<storage, read_write> flags: array<u32>;
@group(1) @binding(6) var<storage, read_write> contrib: array<vec4<f32>>;
@group(1) @binding(7) var<storage, read_write> aux: array<u32>;
@group(1) @binding(8) var<uniform> work: Work;
// Radiance of every pixel sample.
@group(1) @binding(9) var<storage, read_write> film: array<vec4<f32>>;
// Rays traced: [0] shadow rays, [1] secondary rays.
@group(1) @binding(10) var<storage, read_write> counters: array<atomic<u32>, 4>;

fn count_rays(shadow: u32, secondary: u32) {
    if shadow != 0u {
        atomicAdd(&counters[0], shadow);
    }
    if secondary != 0u {
        atomicAdd(&counters[1], secondary);
    }
}

