// Stream compaction by prefix sum, reduce-then-scan (no decoupled look-back, no spin
// waits: lavapipe guarantees no forward progress between workgroups). Three dispatches:
//   compact_reduce   one workgroup per block of SCAN_BLOCK flags: its count -> aux[1 + b]
//   compact_blocks   one workgroup: exclusive scan of the block counts in place, the
//                    total -> aux[0]
//   compact_scatter  one workgroup per block: a workgroup scan of its flags plus the
//                    block's offset; list_out[pos] = i for every set flag, in order.
// Slots: flags (input, work.n of them), aux (block sums; aux[0] = count), list_out.

// SCAN_BLOCK, scratch, block_index and scan_scratch: workgroup_scan.wgsl.

fn flag_at(i: u32) -> u32 {
    if i < work.n {
        return select(0u, 1u, flags[i] != 0u);
    }
    return 0u;
}

@compute @workgroup_size(256)
fn compact_reduce(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let b = block_index(wid);
    scratch[lid] = flag_at(b * SCAN_BLOCK + lid);
    scan_scratch(lid);
    if lid == SCAN_BLOCK - 1u {
        aux[1u + b] = scratch[lid];
    }
}

// work.a = number of blocks.
@compute @workgroup_size(256)
fn compact_blocks(@builtin(local_invocation_index) lid: u32) {
    var carry = 0u;
    for (var base = 0u; base < work.a; base = base + SCAN_BLOCK) {
        let i = base + lid;
        var v = 0u;
        if i < work.a {
            v = aux[1u + i];
        }
        workgroupBarrier();
        scratch[lid] = v;
        scan_scratch(lid);
        if i < work.a {
            aux[1u + i] = carry + scratch[lid] - v;
        }
        carry = carry + scratch[SCAN_BLOCK - 1u];
    }
    if lid == 0u {
        aux[0] = carry;
    }
}

@compute @workgroup_size(256)
fn compact_scatter(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let b = block_index(wid);
    let i = b * SCAN_BLOCK + lid;
    let f = flag_at(i);
    scratch[lid] = f;
    scan_scratch(lid);
    if f != 0u {
        list_out[aux[1u + b] + scratch[lid] - f] = i;
    }
}
