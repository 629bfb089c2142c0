//! Seed 003 §3.12: primary rays traced for every sample and the hits compacted once,
//! then the megakernel's loop on the survivors only (shaders/hybrid.wgsl).

use super::compact;
use super::work::{work_group, Recorder, Slot, Stage, Work, HIT_BYTES};
use super::Batch;
use crate::{buffer, GpuError};

/// Renders samples `base..base + n` into `film` (16 bytes each).
pub(crate) fn render(
    b: &Batch<'_>,
    rec: &mut Recorder<'_>,
    base: u32,
    n: u32,
    film: &wgpu::Buffer,
) -> Result<u64, GpuError> {
    let hits = buffer::output(b.ctx, "primary hits", n as u64 * HIT_BYTES)?;
    let flags = buffer::output(b.ctx, "primary flags", 4 * n as u64)?;
    let aux = buffer::output(b.ctx, "block sums", compact::aux_bytes(n))?;
    let list = buffer::output(b.ctx, "survivors", 4 * n as u64)?;
    let g = work_group(
        b.ctx,
        b.kernels,
        b.placeholders,
        &[(Slot::Hits, &hits), (Slot::Flags, &flags), (Slot::Film, film)],
        Work { n, b: base, ..Default::default() },
    );
    rec.dispatch(Stage::Trace, &b.kernels.pipeline(b.ctx, "hybrid_primary")?, b.scene, &g, n)?;
    compact::record(b.ctx, b.kernels, b.placeholders, rec, &flags, &aux, &list, n)?;
    let survivors = compact::count(rec, &aux)?;
    let g = work_group(
        b.ctx,
        b.kernels,
        b.placeholders,
        &[(Slot::ListIn, &list), (Slot::Hits, &hits), (Slot::Film, film), (Slot::Counters, b.counters)],
        Work { n: survivors, b: base, ..Default::default() },
    );
    rec.dispatch(Stage::Fused, &b.kernels.pipeline(b.ctx, "hybrid_survivors")?, b.scene, &g, survivors)?;
    Ok(0)
}
