// Resolving a render's samples into a live image on the device (src/render/device_image.rs):
// `accumulate` adds each pixel's samples of one batch, in sample order, into its running
// sum and weight (the CPU film's rule); `encode` writes every pixel's sum / weight as
// sRGB 8-bit RGBA into rows the window copies into its texture.

struct Resolve {
    width: u32,
    pixels: u32,
    spp: u32,
    base: u32,
    n: u32,
    row_words: u32,
    first_pixel: u32,
    pad: u32,
};

@group(0) @binding(0) var<uniform> r: Resolve;
@group(0) @binding(1) var<storage, read> samples: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read_write> acc: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read_write> rgba: array<u32>;

// Dispatches are 2-D past 65,535 workgroups of 64.
fn item(id: vec3<u32>, groups: vec3<u32>) -> u32 {
    return id.x + id.y * groups.x * 64u;
}

@compute @workgroup_size(64)
fn accumulate(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let p = r.first_pixel + item(id, groups);
    let s0 = max(p * r.spp, r.base);
    let s1 = min((p + 1u) * r.spp, r.base + r.n);
    if (p >= r.pixels || s0 >= s1) {
        return;
    }
    var sum = vec3<f32>(0.0);
    for (var s = s0; s < s1; s++) {
        sum += samples[s - r.base].xyz;
    }
    let a = acc[p];
    acc[p] = vec4<f32>(a.xyz + sum, a.w + f32(s1 - s0));
}

// dynray_render::linear_to_srgb8: the sRGB curve, rounded to the nearest level.
fn srgb8(c: f32) -> u32 {
    var x = clamp(c, 0.0, 1.0);
    if (!(c >= 0.0)) {
        x = 0.0; // NaN and negatives
    }
    var s: f32;
    if (x <= 0.0031308) {
        s = 12.92 * x;
    } else {
        s = 1.055 * pow(x, 1.0 / 2.4) - 0.055;
    }
    return u32(clamp(s * 255.0 + 0.5, 0.0, 255.0));
}

@compute @workgroup_size(64)
fn encode(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let p = item(id, groups);
    if (p >= r.pixels) {
        return;
    }
    let a = acc[p];
    var c = vec3<f32>(0.0);
    if (a.w > 0.0) {
        c = a.xyz / a.w;
    }
    let word = srgb8(c.x) | (srgb8(c.y) << 8u) | (srgb8(c.z) << 16u) | (255u << 24u);
    rgba[(p / r.width) * r.row_words + p % r.width] = word;
}
