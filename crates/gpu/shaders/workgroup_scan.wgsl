// The workgroup prefix sum every scan-based kernel shares (compact.wgsl's compaction,
// scan.wgsl's exclusive scan for the builders): SCAN_BLOCK u32s in `scratch`, scanned
// in place by Hillis–Steele, and the 2-D workgroup index of dispatches wider than the
// 65,535 workgroups one dimension allows.

const SCAN_BLOCK: u32 = 256u;

var<workgroup> scratch: array<u32, SCAN_BLOCK>;

fn block_index(wid: vec3<u32>) -> u32 {
    return wid.x + wid.y * 65535u;
}

// Inclusive scan of scratch; every invocation of the group calls it.
fn scan_scratch(lid: u32) {
    for (var off = 1u; off < SCAN_BLOCK; off = off * 2u) {
        workgroupBarrier();
        var add = 0u;
        if lid >= off {
            add = scratch[lid - off];
        }
        workgroupBarrier();
        scratch[lid] = scratch[lid] + add;
    }
    workgroupBarrier();
}
