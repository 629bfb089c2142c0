// Seed 003 §3.10, the multi-kernel wavefront, extended to refraction: a wave is a dense
// array of rays sorted by pixel sample; per bounce the host runs
//   trace (closest hit, misses add the background) -> compact the hits ->
//   shade (Phong + shadow rays, up to two children each in slots 2j, 2j+1) ->
//   accumulate (each sample's contributions of this wave into its radiance) ->
//   compact the children -> gather them into the next dense wave.
// The seed's one-ray-per-pixel rule, which forbade refraction (two children would write
// one pixel), is replaced by per-wave contributions summed per sample run: compaction is
// stable, so the rays of one sample stay contiguous and in the CPU's order, and one
// invocation (the run's first) adds them up — no float atomics, no write conflicts.

fn wave_index(gid: vec3<u32>) -> u32 {
    return gid.x + gid.y * 65535u * 64u;
}

// Slots: rays_out (the first wave: every sample's camera ray), film (zeroed).
@compute @workgroup_size(64)
fn wf_generate(@builtin(global_invocation_id) gid: vec3<u32>) {
    let k = wave_index(gid);
    if k >= work.n {
        return;
    }
    rays_out[k] = camera_ray(work.b + k, k);
    film[k] = vec4<f32>(0.0);
}

// Slots: rays_in (the wave), hits, flags (1 = hit), contrib (background × throughput on
// a miss).
@compute @workgroup_size(64)
fn wf_trace(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = wave_index(gid);
    if i >= work.n {
        return;
    }
    let r = rays_in[i];
    let h = trace_ray(r);
    hits[i] = h;
    if h.prim == NO_HIT {
        flags[i] = 0u;
        contrib[i] = vec4<f32>(no_nan(r.thr * scene.background), 0.0);
    } else {
        flags[i] = 1u;
        contrib[i] = vec4<f32>(0.0);
    }
}

// Slots: rays_in (the wave), hits, list_in (wave indices of the hits), rays_out and
// flags (two child slots per shaded ray), contrib.
@compute @workgroup_size(64)
fn wf_shade(@builtin(global_invocation_id) gid: vec3<u32>) {
    let j = wave_index(gid);
    if j >= work.n {
        return;
    }
    let i = list_in[j];
    let r = rays_in[i];
    let sh = shade(r, hits[i]);
    contrib[i] = vec4<f32>(no_nan(r.thr * sh.color), 0.0);
    flags[2u * j] = select(0u, 1u, sh.children >= 1u);
    flags[2u * j + 1u] = select(0u, 1u, sh.children == 2u);
    if sh.children >= 1u {
        rays_out[2u * j] = sh.child0;
    }
    if sh.children == 2u {
        rays_out[2u * j + 1u] = sh.child1;
    }
    count_rays(sh.shadow_rays, 0u);
}

// Slots: rays_in (the wave, for the sample ids), contrib, film.
@compute @workgroup_size(64)
fn wf_accumulate(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = wave_index(gid);
    if i >= work.n {
        return;
    }
    let k = rays_in[i].sample;
    if i > 0u && rays_in[i - 1u].sample == k {
        return;
    }
    var sum = film[k].xyz;
    var j = i;
    loop {
        sum = sum + contrib[j].xyz;
        j = j + 1u;
        if j >= work.n || rays_in[j].sample != k {
            break;
        }
    }
    film[k] = vec4<f32>(sum, 0.0);
}

// Slots: rays_in (the children slots), list_in (compacted slot indices), rays_out (the
// next wave).
@compute @workgroup_size(64)
fn wf_gather(@builtin(global_invocation_id) gid: vec3<u32>) {
    let m = wave_index(gid);
    if m >= work.n {
        return;
    }
    rays_out[m] = rays_in[list_in[m]];
}
