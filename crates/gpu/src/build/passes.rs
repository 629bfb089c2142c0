//! Recording the builders' dispatches and timing their stages: one command encoder per
//! stage, submitted and waited for at the stage's end, so each stage's figure is wall
//! clock from its first dispatch to its completion on the device (recording and
//! submission included, as the build's user waits for them too).

use super::kernels::Pipelines;
use crate::{buffer, GpuContext, GpuError};
use bytemuck::Pod;
use std::time::Instant;

/// Most workgroups in one dispatch dimension; the kernels index `x + y · 65535`.
const MAX_GROUPS_X: u32 = 65_535;

/// Seconds per named stage of one build or refit, in order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BuildTimings {
    /// (stage, seconds): e.g. `upload`, `morton`, `sort`, `hierarchy`, `layout`, `refit`.
    pub stages: Vec<(&'static str, f64)>,
}

impl BuildTimings {
    /// Sum of the stages.
    pub fn total(&self) -> f64 {
        self.stages.iter().map(|(_, s)| s).sum()
    }

    /// Seconds of stage `name` (summed over its occurrences), 0 when absent.
    pub fn stage(&self, name: &str) -> f64 {
        self.stages.iter().filter(|(n, _)| *n == name).map(|(_, s)| s).sum()
    }

    /// `name 1.2 ms, …` for logs and the CLI.
    pub fn summary(&self) -> String {
        self.stages.iter().map(|(n, s)| format!("{n} {:.2} ms", s * 1e3)).collect::<Vec<_>>().join(", ")
    }
}

/// The recorder of one build.
pub(crate) struct Passes<'a> {
    pub ctx: &'a GpuContext,
    encoder: Option<wgpu::CommandEncoder>,
    started: Instant,
    pub timings: BuildTimings,
}

impl<'a> Passes<'a> {
    pub fn new(ctx: &'a GpuContext) -> Self {
        Self { ctx, encoder: None, started: Instant::now(), timings: BuildTimings::default() }
    }

    fn encoder(&mut self) -> &mut wgpu::CommandEncoder {
        self.encoder.get_or_insert_with(|| self.ctx.device.create_command_encoder(&Default::default()))
    }

    /// One dispatch of `entry` of `module` over `groups` workgroups (in two dimensions
    /// past 65,535), with `bindings` as its group 0.
    pub fn dispatch(&mut self, module: &Pipelines, entry: &str, bindings: &[(u32, &wgpu::Buffer)], groups: u32) {
        if groups == 0 {
            return;
        }
        let pipeline = module.get(entry);
        let group = crate::kernel::bind(self.ctx, pipeline, bindings);
        let (x, y) = if groups <= MAX_GROUPS_X { (groups, 1) } else { (MAX_GROUPS_X, groups.div_ceil(MAX_GROUPS_X)) };
        let mut pass = self.encoder().begin_compute_pass(&wgpu::ComputePassDescriptor::default());
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.dispatch_workgroups(x, y, 1);
    }

    /// [`Self::dispatch`] covering `items` invocations of a `width`-wide kernel.
    pub fn dispatch_items(
        &mut self,
        module: &Pipelines,
        entry: &str,
        bindings: &[(u32, &wgpu::Buffer)],
        items: u32,
        width: u32,
    ) {
        self.dispatch(module, entry, bindings, items.div_ceil(width));
    }

    /// A uniform buffer holding `value`.
    pub fn uniform<T: Pod>(&self, value: &T) -> wgpu::Buffer {
        buffer::uniform(self.ctx, "builder params", value)
    }

    /// Submits what was recorded and waits for it.
    pub fn submit(&mut self) -> Result<(), GpuError> {
        if let Some(enc) = self.encoder.take() {
            self.ctx.queue.submit([enc.finish()]);
        }
        buffer::wait(self.ctx)
    }

    /// Submits, waits, and books the time since the previous stage ended as `name`.
    pub fn end_stage(&mut self, name: &'static str) -> Result<(), GpuError> {
        self.submit()?;
        let now = Instant::now();
        self.timings.stages.push((name, (now - self.started).as_secs_f64()));
        self.started = now;
        Ok(())
    }

    /// Submits what was recorded, then reads `src[index]` (a `u32`).
    pub fn read_u32(&mut self, src: &wgpu::Buffer, index: u64) -> Result<u32, GpuError> {
        let staging = buffer::staging(self.ctx, 4);
        self.encoder().copy_buffer_to_buffer(src, 4 * index, &staging, 0, 4);
        self.submit()?;
        let mut v = [0u32];
        buffer::read_into(self.ctx, &staging, &mut v)?;
        Ok(v[0])
    }
}
