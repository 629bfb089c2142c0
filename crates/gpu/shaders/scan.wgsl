// Exclusive prefix sum of `data[0..sp.n]` in place, reduce-then-scan (no inter-workgroup
// waiting, so correct without forward-progress guarantees). Three dispatches:
//   scan_reduce  one workgroup per block of SCAN_BLOCK values: its sum -> sums[1 + b]
//   scan_blocks  one workgroup: exclusive scan of the block sums, the total -> sums[0]
//   scan_apply   one workgroup per block: data[i] = block offset + workgroup scan
// Needs workgroup_scan.wgsl.

struct ScanParams {
    n: u32,
    blocks: u32,
    _pad0: u32,
    _pad1: u32,
}

@group(0) @binding(0) var<storage, read_write> data: array<u32>;
@group(0) @binding(1) var<storage, read_write> sums: array<u32>;
@group(0) @binding(2) var<uniform> sp: ScanParams;

fn value_at(i: u32) -> u32 {
    if i < sp.n {
        return data[i];
    }
    return 0u;
}

@compute @workgroup_size(256)
fn scan_reduce(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let b = block_index(wid);
    if b >= sp.blocks {
        return;
    }
    scratch[lid] = value_at(b * SCAN_BLOCK + lid);
    scan_scratch(lid);
    if lid == SCAN_BLOCK - 1u {
        sums[1u + b] = scratch[lid];
    }
}

@compute @workgroup_size(256)
fn scan_blocks(@builtin(local_invocation_index) lid: u32) {
    var carry = 0u;
    for (var base = 0u; base < sp.blocks; base = base + SCAN_BLOCK) {
        let i = base + lid;
        var v = 0u;
        if i < sp.blocks {
            v = sums[1u + i];
        }
        workgroupBarrier();
        scratch[lid] = v;
        scan_scratch(lid);
        if i < sp.blocks {
            sums[1u + i] = carry + scratch[lid] - v;
        }
        carry = carry + scratch[SCAN_BLOCK - 1u];
    }
    if lid == 0u {
        sums[0] = carry;
    }
}

@compute @workgroup_size(256)
fn scan_apply(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let b = block_index(wid);
    if b >= sp.blocks {
        return;
    }
    let i = b * SCAN_BLOCK + lid;
    let v = value_at(i);
    scratch[lid] = v;
    scan_scratch(lid);
    if i < sp.n {
        data[i] = sums[1u + b] + scratch[lid] - v;
    }
}
