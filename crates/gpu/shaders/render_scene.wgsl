// The frame as every render kernel sees it (group 0, uploaded once per frame by
// src/render/frame_upload.rs, whose Pod mirrors give the byte layouts): the BVH the
// traversal reads, the mesh arrays shading reads, materials, lights, the camera and the
// settings of the CPU Whitted integrator.

struct Material {
    ambient: vec3<f32>,
    shine: f32,
    diffuse: vec3<f32>,
    // sane_ior(ior): positive and finite, else 1.
    ior: f32,
    spot: vec3<f32>,
    // 1 when spot != 0 (the CPU skips the highlight otherwise).
    has_spot: u32,
    specular: vec3<f32>,
    _pad0: u32,
    transparency: vec3<f32>,
    _pad1: u32,
    // The shadow filter of crates/render/src/shadow.rs, computed on the CPU.
    shadow_filter: vec3<f32>,
    _pad2: u32,
}

const LIGHT_POINT: u32 = 0u;
const LIGHT_SPOT: u32 = 1u;
const LIGHT_DIRECTIONAL: u32 = 2u;

struct Light {
    position: vec3<f32>,
    kind: u32,
    // Spot: the cone axis normalised (or zero). Directional: the unit direction towards
    // the light, -normalize_or_zero(direction).
    direction: vec3<f32>,
    falloff: i32,
    color: vec3<f32>,
    cos_inner: f32,
    cos_outer: f32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

struct SceneParams {
    cam_origin: vec3<f32>,
    cam_parallel: u32,
    cam_forward: vec3<f32>,
    cam_width: f32,
    cam_right: vec3<f32>,
    cam_height: f32,
    cam_up: vec3<f32>,
    spp: u32,
    background: vec3<f32>,
    env_ior: f32,
    ambient: vec3<f32>,
    eps_base: f32,
    width: u32,
    height: u32,
    max_level: u32,
    min_weight: f32,
    light_count: u32,
    any_transparent: u32,
    has_normals: u32,
    // Materials uploaded; the last one is the fallback for an index naming none.
    material_count: u32,
}

@group(0) @binding(0) var<storage, read> nodes: array<Node>;
@group(0) @binding(1) var<storage, read> tris: array<f32>;
@group(0) @binding(2) var<storage, read> ids: array<u32>;
@group(0) @binding(3) var<storage, read> positions: array<f32>;
@group(0) @binding(4) var<storage, read> indices: array<u32>;
@group(0) @binding(5) var<storage, read> normals: array<f32>;
@group(0) @binding(6) var<storage, read> material_ids: array<u32>;
@group(0) @binding(7) var<storage, read> materials: array<Material>;
@group(0) @binding(8) var<storage, read> lights: array<Light>;
@group(0) @binding(9) var<uniform> scene: SceneParams;
// Sub-pixel position of every pixel sample (pixel-major: sample k = pixel · spp + s),
// from the CPU's Sampler, so the GPU's camera rays are the CPU's.
@group(0) @binding(10) var<storage, read> offsets: array<vec2<f32>>;
// The cumulative integrator's key of every pixel sample of the pass (the first next_u32
// of the CPU's sampler of that sample), uploaded per pass.
@group(0) @binding(11) var<storage, read> keys: array<u32>;
