// One pass of a stable LSD radix sort of (key, value) pairs on 4-bit digits, in two
// kernels around scan.wgsl's exclusive scan (reduce-then-scan: no look-back):
//   sort_histogram  per tile of TILE keys, its count of each digit -> offsets[d·tiles + t]
//   (scan of offsets: digit-major, so the result is each (digit, tile)'s first slot)
//   sort_scatter    each key's rank among the tile's earlier keys of its digit, by one
//                   workgroup scan of the 16 digit flags packed as 8-bit fields of a vec4
// Eight passes (shift 0, 4, …, 28) sort 32-bit keys; stability makes the order of equal
// keys that of their values' input order.

struct SortParams {
    n: u32,
    shift: u32,
    tiles: u32,
    _pad: u32,
}

const TILE: u32 = 256u;

@group(0) @binding(0) var<storage, read> keys_in: array<u32>;
@group(0) @binding(1) var<storage, read> vals_in: array<u32>;
@group(0) @binding(2) var<storage, read_write> keys_out: array<u32>;
@group(0) @binding(3) var<storage, read_write> vals_out: array<u32>;
@group(0) @binding(4) var<storage, read_write> offsets: array<u32>;
@group(0) @binding(5) var<uniform> sp: SortParams;

var<workgroup> digit_counts: array<atomic<u32>, 16>;
var<workgroup> packed: array<vec4<u32>, TILE>;

fn tile_index(wid: vec3<u32>) -> u32 {
    return wid.x + wid.y * 65535u;
}

@compute @workgroup_size(256)
fn sort_histogram(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let tile = tile_index(wid);
    if tile >= sp.tiles {
        return;
    }
    if lid < 16u {
        atomicStore(&digit_counts[lid], 0u);
    }
    workgroupBarrier();
    let i = tile * TILE + lid;
    if i < sp.n {
        atomicAdd(&digit_counts[(keys_in[i] >> sp.shift) & 15u], 1u);
    }
    workgroupBarrier();
    if lid < 16u {
        offsets[lid * sp.tiles + tile] = atomicLoad(&digit_counts[lid]);
    }
}

@compute @workgroup_size(256)
fn sort_scatter(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let tile = tile_index(wid);
    if tile >= sp.tiles {
        return;
    }
    let i = tile * TILE + lid;
    let live = i < sp.n;
    var key = 0u;
    var d = 0u;
    var one = vec4<u32>(0u);
    if live {
        key = keys_in[i];
        d = (key >> sp.shift) & 15u;
        one[d >> 2u] = 1u << (8u * (d & 3u));
    }
    packed[lid] = one;
    // Inclusive scan of the packed flags. A field can only reach 256 in the last step
    // of the last invocation (all 256 keys of one digit); its carry is undone exactly by
    // the wrapping subtraction below, and every exclusive count is at most 255.
    for (var off = 1u; off < TILE; off = off * 2u) {
        workgroupBarrier();
        var add = vec4<u32>(0u);
        if lid >= off {
            add = packed[lid - off];
        }
        workgroupBarrier();
        packed[lid] = packed[lid] + add;
    }
    workgroupBarrier();
    if live {
        let before = packed[lid] - one;
        let rank = (before[d >> 2u] >> (8u * (d & 3u))) & 255u;
        let dst = offsets[d * sp.tiles + tile] + rank;
        keys_out[dst] = key;
        vals_out[dst] = vals_in[i];
    }
}
