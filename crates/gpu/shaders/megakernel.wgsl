// Seed 003 §3.11, the megakernel: one invocation per pixel sample generates, traces and
// shades every ray of that sample, keeping pending reflection and refraction rays on a
// private stack of RAY_STACK entries (from the prelude: the level limit + 2, enough for
// the depth-first order, which leaves at most one pending sibling per level).
// Slots: film (radiance per sample), counters.

// Runs the stack from `first` (already traced: hit `h`) to empty; the sample's radiance.
fn run_stack(first: RayRec, h: Hit) -> vec3<f32> {
    var stack: array<RayRec, RAY_STACK>;
    var sp = 0u;
    var sum = vec3<f32>(0.0);
    var shadow = 0u;
    var secondary = 0u;
    var r = first;
    var hit = h;
    loop {
        if hit.prim == NO_HIT {
            sum = sum + no_nan(r.thr * scene.background);
        } else {
            let sh = shade(r, hit);
            shadow = shadow + sh.shadow_rays;
            sum = sum + no_nan(r.thr * sh.color);
            // Refraction below reflection, so reflection is traced first, as on the CPU.
            if sh.children == 2u && sp + 2u <= RAY_STACK {
                stack[sp] = sh.child1;
                stack[sp + 1u] = sh.child0;
                sp = sp + 2u;
            } else if sh.children >= 1u && sp < RAY_STACK {
                stack[sp] = sh.child0;
                sp = sp + 1u;
            }
        }
        if sp == 0u {
            break;
        }
        sp = sp - 1u;
        r = stack[sp];
        secondary = secondary + 1u;
        hit = trace_ray(r);
    }
    count_rays(shadow, secondary);
    return sum;
}

@compute @workgroup_size(64)
fn megakernel(@builtin(global_invocation_id) gid: vec3<u32>) {
    let k = gid.x + gid.y * 65535u * 64u;
    if k >= work.n {
        return;
    }
    let r = camera_ray(work.b + k, k);
    film[k] = vec4<f32>(run_stack(r, trace_ray(r)), 0.0);
}
