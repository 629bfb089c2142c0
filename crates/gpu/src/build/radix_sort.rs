//! A stable LSD radix sort of (u32 key, u32 value) pairs on the device
//! (shaders/radix_sort.wgsl): eight passes of 4-bit digits, each a per-tile histogram, an
//! exclusive scan of the digit-major counts (scan.rs) and a stable scatter.

use super::kernels::Module;
use super::passes::Passes;
use super::scan;
use crate::{buffer, GpuError};
use bytemuck::{Pod, Zeroable};

/// Keys per workgroup (`TILE`).
const TILE: u32 = 256;
/// Digits per pass.
const DIGITS: u32 = 16;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct SortParams {
    n: u32,
    shift: u32,
    tiles: u32,
    _pad: u32,
}

/// Sorts `keys[0..n]` with `vals` alongside (ties keep their input order); `keys_tmp`
/// and `vals_tmp` are scratch of the same size. The result is in `keys` and `vals`.
pub(crate) fn sort_pairs(
    p: &mut Passes<'_>,
    keys: &wgpu::Buffer,
    vals: &wgpu::Buffer,
    keys_tmp: &wgpu::Buffer,
    vals_tmp: &wgpu::Buffer,
    n: u32,
) -> Result<(), GpuError> {
    let sort = p.ctx.builders.get(p.ctx, Module::RadixSort)?;
    let scan_k = scan::kernels(p)?;
    let tiles = n.div_ceil(TILE);
    let offsets = buffer::output(p.ctx, "radix offsets", 4 * (DIGITS * tiles) as u64)?;
    let sums = scan::sums_buffer(p, DIGITS * tiles)?;
    let mut src = (keys, vals);
    let mut dst = (keys_tmp, vals_tmp);
    // An even number of passes leaves the result where it started.
    for pass in 0..8 {
        let params = p.uniform(&SortParams { n, shift: 4 * pass, tiles, _pad: 0 });
        p.dispatch(&sort, "sort_histogram", &[(0, src.0), (4, &offsets), (5, &params)], tiles);
        scan::record(p, &scan_k, &offsets, &sums, DIGITS * tiles);
        p.dispatch(
            &sort,
            "sort_scatter",
            &[(0, src.0), (1, src.1), (2, dst.0), (3, dst.1), (4, &offsets), (5, &params)],
            tiles,
        );
        std::mem::swap(&mut src, &mut dst);
    }
    Ok(())
}
