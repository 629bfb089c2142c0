// Closest-hit and any-hit traversal of the binary BVH (crates/accel/src/bvh/traverse.rs):
// the same 32-byte nodes, the same near-first order, the same culling, so the GPU visits
// what the CPU visits and keeps the same hit. Needs `nodes`, `tris` (9 floats each, leaf
// order) and `ids` (mesh index of each leaf-order triangle) bound by the including kernel,
// and STACK_SIZE and the slab factors from the prelude.

struct Node {
    lo: vec3<f32>,
    // Interior: left child (the right one follows it). Leaf: first triangle.
    index: u32,
    hi: vec3<f32>,
    // 0 for an interior node, else the leaf's triangle count.
    count: u32,
}

struct Hit {
    t: f32,
    u: f32,
    v: f32,
    prim: u32,
}

const NO_HIT: u32 = 0xffffffffu;

fn miss() -> Hit {
    return Hit(bitcast<f32>(0x7f800000u), 0.0, 0.0, NO_HIT);
}

fn load_triangle(j: u32) -> array<vec3<f32>, 3> {
    let b = 9u * j;
    return array<vec3<f32>, 3>(
        vec3<f32>(tris[b], tris[b + 1u], tris[b + 2u]),
        vec3<f32>(tris[b + 3u], tris[b + 4u], tris[b + 5u]),
        vec3<f32>(tris[b + 6u], tris[b + 7u], tris[b + 8u]),
    );
}

fn is_nan3(x: vec3<f32>) -> vec3<bool> {
    // On the bits, so no compiler can fold it away.
    return (bitcast<vec3<u32>>(x) & vec3<u32>(0x7fffffffu)) > vec3<u32>(0x7f800000u);
}

// The slab test of Aabb::clip: (entered, widened entry distance). A NaN slab distance
// (origin on the slab's plane, ray parallel to it) leaves that axis unconstrained.
fn clip_box(n: Node, r: PRay, tmin: f32, limit: f32) -> vec2<f32> {
    let t0 = (n.lo - r.org) * r.inv;
    let t1 = (n.hi - r.org) * r.inv;
    let ninf = vec3<f32>(bitcast<f32>(0xff800000u));
    let pinf = vec3<f32>(bitcast<f32>(0x7f800000u));
    let n0 = select(t0, ninf, is_nan3(t0));
    let n1 = select(t1, ninf, is_nan3(t1));
    let f0 = select(t0, pinf, is_nan3(t0));
    let f1 = select(t1, pinf, is_nan3(t1));
    let lo = min(n0, n1);
    let hi = max(f0, f1);
    var near = max(lo.x, max(lo.y, lo.z));
    var far = min(hi.x, min(hi.y, hi.z));
    near = near * select(SLAB_GROW, SLAB_SHRINK, near > 0.0);
    far = far * select(SLAB_SHRINK, SLAB_GROW, far > 0.0);
    near = select(near, tmin, tmin > near);
    far = select(far, limit, limit < far);
    return vec2<f32>(select(0.0, 1.0, near <= far), near);
}

fn closest_hit(r: PRay) -> Hit {
    var best = miss();
    if r.degenerate || clip_box(nodes[0], r, r.tmin, r.tmax).x == 0.0 {
        return best;
    }
    var stack_node: array<u32, STACK_SIZE>;
    var stack_t: array<f32, STACK_SIZE>;
    var sp = 0u;
    var node = 0u;
    loop {
        let n = nodes[node];
        if n.count != 0u {
            for (var j = n.index; j < n.index + n.count; j = j + 1u) {
                let p = load_triangle(j);
                let h = intersect_triangle(p[0], p[1], p[2], r, min(best.t, r.tmax));
                let id = ids[j];
                // Hit::is_closer: smaller t, equal t to the lower triangle index.
                if h.hit && (h.t < best.t || (h.t == best.t && id < best.prim)) {
                    best = Hit(h.t, h.u, h.v, id);
                }
            }
        } else {
            let l = n.index;
            // Cull only boxes entered after the best hit (a lower index may tie at best.t).
            let limit = min(best.t, r.tmax);
            let cl = clip_box(nodes[l], r, r.tmin, limit);
            let cr = clip_box(nodes[l + 1u], r, r.tmin, limit);
            let hl = cl.x != 0.0;
            let hr = cr.x != 0.0;
            if hl && hr {
                if cr.y < cl.y {
                    stack_node[sp] = l;
                    stack_t[sp] = cl.y;
                    node = l + 1u;
                } else {
                    stack_node[sp] = l + 1u;
                    stack_t[sp] = cr.y;
                    node = l;
                }
                sp = sp + 1u;
                continue;
            }
            if hl {
                node = l;
                continue;
            }
            if hr {
                node = l + 1u;
                continue;
            }
        }
        // Pop the next node entered no later than the best hit.
        var found = false;
        loop {
            if sp == 0u {
                break;
            }
            sp = sp - 1u;
            if stack_t[sp] <= best.t {
                node = stack_node[sp];
                found = true;
                break;
            }
        }
        if !found {
            return best;
        }
    }
    return best;
}

fn any_hit(r: PRay) -> bool {
    if r.degenerate || clip_box(nodes[0], r, r.tmin, r.tmax).x == 0.0 {
        return false;
    }
    var stack_node: array<u32, STACK_SIZE>;
    var sp = 0u;
    var node = 0u;
    loop {
        let n = nodes[node];
        if n.count != 0u {
            for (var j = n.index; j < n.index + n.count; j = j + 1u) {
                let p = load_triangle(j);
                if intersect_triangle(p[0], p[1], p[2], r, r.tmax).hit {
                    return true;
                }
            }
        } else {
            let l = n.index;
            let cl = clip_box(nodes[l], r, r.tmin, r.tmax);
            let cr = clip_box(nodes[l + 1u], r, r.tmin, r.tmax);
            let hl = cl.x != 0.0;
            let hr = cr.x != 0.0;
            if hl && hr {
                if cr.y < cl.y {
                    stack_node[sp] = l;
                    node = l + 1u;
                } else {
                    stack_node[sp] = l + 1u;
                    node = l;
                }
                sp = sp + 1u;
                continue;
            }
            if hl {
                node = l;
                continue;
            }
            if hr {
                node = l + 1u;
                continue;
            }
        }
        if sp == 0u {
            return false;
        }
        sp = sp - 1u;
        node = stack_node[sp];
    }
    return false;
}
