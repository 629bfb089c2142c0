//! Seed 003 §3.11: one invocation per pixel sample runs generate → trace → shade with a
//! private ray stack for reflection and refraction (shaders/megakernel.wgsl).

use super::work::{work_group, Recorder, Slot, Stage, Work};
use super::Batch;
use crate::GpuError;

/// Renders samples `base..base + n` into `film` (16 bytes each).
pub(crate) fn render(
    b: &Batch<'_>,
    rec: &mut Recorder<'_>,
    base: u32,
    n: u32,
    film: &wgpu::Buffer,
) -> Result<u64, GpuError> {
    let g = work_group(
        b.ctx,
        b.kernels,
        b.placeholders,
        &[(Slot::Film, film), (Slot::Counters, b.counters)],
        Work { n, b: base, ..Default::default() },
    );
    rec.dispatch(Stage::Fused, &b.kernels.pipeline(b.ctx, "megakernel")?, b.scene, &g, n)?;
    // Its secondary rays are counted on the device.
    Ok(0)
}
