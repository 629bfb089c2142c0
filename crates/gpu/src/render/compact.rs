//! Stream compaction on the device (shaders/compact.wgsl): the indices of the set flags,
//! in order, by a reduce-then-scan prefix sum — three dispatches, no inter-workgroup
//! waiting, so it is correct on devices without forward-progress guarantees (lavapipe).

use super::work::{work_group, Kernels, Placeholders, Recorder, Slot, Stage, Work, SCAN_BLOCK};
use crate::{buffer, GpuContext, GpuError};

/// Most flags one compaction takes: its blocks fit two dispatch dimensions and their
/// counts one `aux` binding.
pub(crate) const MAX_FLAGS: u32 = u32::MAX - SCAN_BLOCK;

/// Bytes of the `aux` buffer a compaction of `n` flags needs (the count, then one offset
/// per block).
pub(crate) fn aux_bytes(n: u32) -> u64 {
    4 * (1 + n.div_ceil(SCAN_BLOCK) as u64)
}

/// Records the compaction of `flags[0..n]` into `list[0..count]`; `aux[0]` receives the
/// count (read it after the recorder's next submission).
#[allow(clippy::too_many_arguments)]
pub(crate) fn record(
    ctx: &GpuContext,
    kernels: &Kernels,
    placeholders: &Placeholders,
    rec: &mut Recorder<'_>,
    flags: &wgpu::Buffer,
    aux: &wgpu::Buffer,
    list: &wgpu::Buffer,
    n: u32,
) -> Result<(), GpuError> {
    assert!(n <= MAX_FLAGS, "{n} flags: more than one compaction takes");
    let blocks = n.div_ceil(SCAN_BLOCK);
    let work = Work { n, a: blocks, b: 0, c: 0 };
    let group =
        work_group(ctx, kernels, placeholders, &[(Slot::Flags, flags), (Slot::Aux, aux), (Slot::ListOut, list)], work);
    let empty = Recorder::empty_group(kernels);
    if blocks > 0 {
        rec.dispatch_groups(Stage::Compact, &kernels.pipeline(ctx, "compact_reduce")?, empty, &group, blocks)?;
    }
    rec.dispatch_groups(Stage::Compact, &kernels.pipeline(ctx, "compact_blocks")?, empty, &group, 1)?;
    if blocks > 0 {
        rec.dispatch_groups(Stage::Compact, &kernels.pipeline(ctx, "compact_scatter")?, empty, &group, blocks)?;
    }
    Ok(())
}

/// Reads the count a recorded compaction wrote.
pub(crate) fn count(rec: &mut Recorder<'_>, aux: &wgpu::Buffer) -> Result<u32, GpuError> {
    let mut c = [0u32];
    rec.read(aux, &mut c)?;
    Ok(c[0])
}

/// The indices `i` with `flags[i] != 0`, in increasing order, computed on the device by
/// the compaction the wavefront and hybrid strategies use: for tests and checks.
pub(crate) fn compact_on_device(ctx: &GpuContext, kernels: &Kernels, flags: &[u32]) -> Result<Vec<u32>, GpuError> {
    let n = u32::try_from(flags.len())
        .ok()
        .filter(|&n| n <= MAX_FLAGS)
        .ok_or_else(|| GpuError::Unsupported { what: format!("a compaction of {} flags", flags.len()) })?;
    let placeholders = Placeholders::new(ctx)?;
    let f = buffer::storage(ctx, "flags", flags, wgpu::BufferUsages::empty())?;
    let aux = buffer::output(ctx, "block sums", aux_bytes(n))?;
    let list = buffer::output(ctx, "compacted", 4 * n as u64)?;
    let mut rec = Recorder::new(ctx);
    record(ctx, kernels, &placeholders, &mut rec, &f, &aux, &list, n)?;
    let c = count(&mut rec, &aux)? as usize;
    let mut out = vec![0u32; c.min(flags.len())];
    rec.read(&list, &mut out)?;
    Ok(out)
}
