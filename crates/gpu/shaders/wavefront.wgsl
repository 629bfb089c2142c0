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
// flags (two child slots per shaded ray), contrib. work.a: the branch depth K of seed
// 004's cumulative integrator (0xffffffff for Whitted): hits of rays of level <= K
// expand both children (numbered 2·path, 2·path + 1); past K a hit with two children
// continues into one, reflection with probability p (reflect_probability) against
// choice_random, its throughput divided by its probability, the path number kept —
// crates/render/src/cumulative/bounce.rs rule for rule.
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
    var children = sh.children;
    var c0 = sh.child0;
    var c1 = sh.child1;
    if r.level <= work.a {
        c0.path = 2u * r.path;
        c1.path = 2u * r.path + 1u;
    } else if children == 2u {
        let pr = reflect_probability(sh.coef0, sh.coef1);
        if choice_random(r.key, r.level, r.path) < pr {
            c0.thr = c0.thr / pr;
        } else {
            c0 = c1;
            c0.thr = c1.thr / (1.0 - pr);
        }
        children = 1u;
    }
    flags[2u * j] = select(0u, 1u, children >= 1u);
    flags[2u * j + 1u] = select(0u, 1u, children == 2u);
    if children >= 1u {
        rays_out[2u * j] = c0;
    }
    if children == 2u {
        rays_out[2u * j + 1u] = c1;
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
