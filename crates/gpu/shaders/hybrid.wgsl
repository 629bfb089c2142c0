// Seed 003 §3.12, the hybrid: primary rays are generated and traced for every pixel
// sample, the samples whose ray hit something are compacted (compact.wgsl), and the
// megakernel loop (megakernel.wgsl's run_stack) runs on the survivors only, so
// background pixels leave no idle lanes behind.

// Slots: hits (primary hit per sample), flags (1 = hit), film (background on a miss).
@compute @workgroup_size(64)
fn hybrid_primary(@builtin(global_invocation_id) gid: vec3<u32>) {
    let k = gid.x + gid.y * 65535u * 64u;
    if k >= work.n {
        return;
    }
    let r = camera_ray(work.b + k, k);
    let h = trace_ray(r);
    hits[k] = h;
    if h.prim == NO_HIT {
        flags[k] = 0u;
        film[k] = vec4<f32>(no_nan(scene.background), 0.0);
    } else {
        flags[k] = 1u;
    }
}

// Slots: list_in (samples whose primary ray hit), hits, film.
@compute @workgroup_size(64)
fn hybrid_survivors(@builtin(global_invocation_id) gid: vec3<u32>) {
    let j = gid.x + gid.y * 65535u * 64u;
    if j >= work.n {
        return;
    }
    let k = list_in[j];
    film[k] = vec4<f32>(run_stack(camera_ray(work.b + k, k), hits[k]), 0.0);
}
