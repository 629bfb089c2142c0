// Primary rays: crates/render/src/camera.rs `CameraRays::ray_at`, in the CPU's order.

// The camera ray of pixel sample k (`local`: its index in this batch of samples):
// CameraRays::ray_at at the CPU sampler's sub-pixel position.
fn camera_ray(k: u32, local: u32) -> RayRec {
    let spp = scene.spp;
    let pixel = k / spp;
    let x = pixel % scene.width;
    let y = pixel / scene.width;
    let o = offsets[k];
    let px = f32(x) + o.x;
    let py = f32(y) + o.y;
    let sx = 2.0 * px / scene.cam_width - 1.0;
    let sy = 1.0 - 2.0 * py / scene.cam_height;
    let offset = scene.cam_right * sx + scene.cam_up * sy;
    var r: RayRec;
    r.sample = local;
    r.level = 1u;
    r.thr = vec3<f32>(1.0);
    r.weight = 1.0;
    r.path = 1u;
    r.key = keys[k];
    if scene.cam_parallel != 0u {
        r.org = scene.cam_origin + offset;
        r.dir = scene.cam_forward;
    } else {
        r.org = scene.cam_origin;
        r.dir = normalize_glam(scene.cam_forward + offset);
    }
    return r;
}
