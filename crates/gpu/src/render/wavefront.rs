//! Seed 003 §3.10, extended to refraction: per bounce, trace → compact the hits → shade
//! (up to two children per hit) → accumulate per sample → compact the children →
//! gather them into the next dense wave (shaders/wavefront.wgsl). The host reads each
//! compaction's count to size the next dispatch, as the seed's host loop does.

use super::compact;
use super::work::{work_group, Recorder, Slot, Stage, Work, HIT_BYTES};
use super::Batch;
use crate::{buffer, GpuContext, GpuError};
use std::mem::size_of;

/// Bytes of one queued ray (`RayRec`).
const RAY_BYTES: u64 = size_of::<super::work::RayRec>() as u64;

/// A device array that grows (never shrinks) to the size a wave needs.
struct Grow {
    what: &'static str,
    per_item: u64,
    buffer: wgpu::Buffer,
    items: u64,
}

impl Grow {
    fn new(ctx: &GpuContext, what: &'static str, per_item: u64, items: u64) -> Result<Self, GpuError> {
        Ok(Self { what, per_item, buffer: buffer::output(ctx, what, per_item * items.max(1))?, items: items.max(1) })
    }

    /// At least `items` elements (the content is lost when it grows).
    fn reserve(&mut self, ctx: &GpuContext, items: u64) -> Result<&wgpu::Buffer, GpuError> {
        if items > self.items {
            *self = Self::new(ctx, self.what, self.per_item, items)?;
        }
        Ok(&self.buffer)
    }
}

/// What the shade kernel does with a hit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Mode {
    /// Whitted's shading (wf_shade), expanding both children at the hits of rays of level
    /// `<= branch_depth` and choosing one past it (seed 004's cumulative integrator;
    /// `u32::MAX` is Whitted's).
    Tree { branch_depth: u32 },
    /// The path tracer (pt_trace, pt_shade): emission, a light sample with its shadow
    /// ray, at most one continuation per hit.
    Path,
}

/// Renders samples `base..base + n` into `film` (16 bytes each) in `mode`; returns the
/// secondary rays traced.
pub(crate) fn render(
    b: &Batch<'_>,
    rec: &mut Recorder<'_>,
    base: u32,
    n: u32,
    film: &wgpu::Buffer,
    mode: Mode,
) -> Result<u64, GpuError> {
    let (trace_entry, shade_entry, shade_work) = match mode {
        Mode::Tree { branch_depth } => ("wf_trace", "wf_shade", Work { a: branch_depth, ..Default::default() }),
        Mode::Path => ("pt_trace", "pt_shade", Work { b: base, ..Default::default() }),
    };
    let ctx = b.ctx;
    let n64 = n as u64;
    let mut cur = Grow::new(ctx, "wave rays", RAY_BYTES, n64)?;
    let mut hits = Grow::new(ctx, "wave hits", HIT_BYTES, n64)?;
    let mut flags = Grow::new(ctx, "wave hit flags", 4, n64)?;
    let mut contrib = Grow::new(ctx, "wave contributions", 16, n64)?;
    let mut shade_list = Grow::new(ctx, "rays to shade", 4, n64)?;
    let mut next = Grow::new(ctx, "child rays", RAY_BYTES, 2 * n64)?;
    let mut child_flags = Grow::new(ctx, "child flags", 4, 2 * n64)?;
    let mut child_list = Grow::new(ctx, "rays to trace", 4, 2 * n64)?;
    let mut aux = Grow::new(ctx, "block sums", 1, compact::aux_bytes(n.saturating_mul(2)))?;
    let (k, ph) = (b.kernels, b.placeholders);

    let g = work_group(
        ctx,
        k,
        ph,
        &[(Slot::RaysOut, &cur.buffer), (Slot::Film, film)],
        Work { n, b: base, ..Default::default() },
    );
    rec.dispatch(Stage::Generate, &k.pipeline(ctx, "wf_generate")?, b.scene, &g, n)?;
    let mut m = n;
    let mut secondary = 0u64;
    while m > 0 {
        let w = Work { n: m, ..Default::default() };
        let g = work_group(
            ctx,
            k,
            ph,
            &[
                (Slot::RaysIn, &cur.buffer),
                (Slot::Hits, &hits.buffer),
                (Slot::Flags, &flags.buffer),
                (Slot::Contrib, &contrib.buffer),
            ],
            w,
        );
        rec.dispatch(Stage::Trace, &k.pipeline(ctx, trace_entry)?, b.scene, &g, m)?;
        compact::record(ctx, k, ph, rec, &flags.buffer, &aux.buffer, &shade_list.buffer, m)?;
        let s = compact::count(rec, &aux.buffer)?;
        if s > 0 {
            let s2 = 2 * s as u64;
            next.reserve(ctx, s2)?;
            child_flags.reserve(ctx, s2)?;
            let g = work_group(
                ctx,
                k,
                ph,
                &[
                    (Slot::RaysIn, &cur.buffer),
                    (Slot::Hits, &hits.buffer),
                    (Slot::ListIn, &shade_list.buffer),
                    (Slot::RaysOut, &next.buffer),
                    (Slot::Flags, &child_flags.buffer),
                    (Slot::Contrib, &contrib.buffer),
                    (Slot::Counters, b.counters),
                ],
                Work { n: s, ..shade_work },
            );
            rec.dispatch(Stage::Shade, &k.pipeline(ctx, shade_entry)?, b.scene, &g, s)?;
        }
        let g = work_group(
            ctx,
            k,
            ph,
            &[(Slot::RaysIn, &cur.buffer), (Slot::Contrib, &contrib.buffer), (Slot::Film, film)],
            w,
        );
        rec.dispatch(Stage::Shade, &k.pipeline(ctx, "wf_accumulate")?, b.scene, &g, m)?;
        if s == 0 {
            break;
        }
        let children = s
            .checked_mul(2)
            .filter(|&c| c <= compact::MAX_FLAGS)
            .ok_or_else(|| GpuError::Unsupported { what: format!("a wave of {s} shaded rays (split the image)") })?;
        child_list.reserve(ctx, children as u64)?;
        aux.reserve(ctx, compact::aux_bytes(children))?;
        compact::record(ctx, k, ph, rec, &child_flags.buffer, &aux.buffer, &child_list.buffer, children)?;
        let next_m = compact::count(rec, &aux.buffer)?;
        if next_m == 0 {
            break;
        }
        let nm = next_m as u64;
        cur.reserve(ctx, nm)?;
        hits.reserve(ctx, nm)?;
        flags.reserve(ctx, nm)?;
        contrib.reserve(ctx, nm)?;
        shade_list.reserve(ctx, nm)?;
        aux.reserve(ctx, compact::aux_bytes(next_m))?;
        let g = work_group(
            ctx,
            k,
            ph,
            &[(Slot::RaysIn, &next.buffer), (Slot::ListIn, &child_list.buffer), (Slot::RaysOut, &cur.buffer)],
            Work { n: next_m, ..Default::default() },
        );
        rec.dispatch(Stage::Compact, &k.pipeline(ctx, "wf_gather")?, b.scene, &g, next_m)?;
        secondary += nm;
        m = next_m;
    }
    Ok(secondary)
}
