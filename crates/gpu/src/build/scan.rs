//! Exclusive prefix sums on the device (shaders/scan.wgsl): reduce-then-scan in three
//! dispatches, with the total left in `sums[0]`.

use super::kernels::{Module, Pipelines};
use super::passes::Passes;
use crate::{buffer, GpuError};
use bytemuck::{Pod, Zeroable};

/// Values per workgroup (`SCAN_BLOCK`).
const BLOCK: u32 = 256;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct ScanParams {
    n: u32,
    blocks: u32,
    _pad: [u32; 2],
}

/// Bytes of the `sums` buffer a scan of up to `n` values needs.
pub(crate) fn sums_bytes(n: u32) -> u64 {
    4 * (1 + n.div_ceil(BLOCK) as u64)
}

/// A `sums` buffer for scans of up to `n` values.
pub(crate) fn sums_buffer(p: &Passes<'_>, n: u32) -> Result<wgpu::Buffer, GpuError> {
    buffer::output(p.ctx, "scan block sums", sums_bytes(n))
}

/// The scan kernels.
pub(crate) fn kernels(p: &Passes<'_>) -> Result<std::sync::Arc<Pipelines>, GpuError> {
    p.ctx.builders.get(p.ctx, Module::Scan)
}

/// Records the exclusive scan of `data[0..n]` in place; `sums[0]` receives the total.
pub(crate) fn record(p: &mut Passes<'_>, k: &Pipelines, data: &wgpu::Buffer, sums: &wgpu::Buffer, n: u32) {
    let blocks = n.div_ceil(BLOCK);
    let params = p.uniform(&ScanParams { n, blocks, _pad: [0; 2] });
    let b = [(0, data), (1, sums), (2, &params)];
    p.dispatch(k, "scan_reduce", &b, blocks);
    p.dispatch(k, "scan_blocks", &b[1..], 1);
    p.dispatch(k, "scan_apply", &b, blocks);
}
