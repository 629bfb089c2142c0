//! The render kernels' plumbing: their two bind-group layouts (group 0 the frame, which
//! changes per frame; group 1 the queues, which change per dispatch), the compiled entry
//! points, the per-dispatch slot bindings and a recorder that times each stage.

use crate::{buffer, shader, GpuContext, GpuError};
use bytemuck::{Pod, Zeroable};
use std::collections::HashMap;
use std::sync::Mutex;
use std::time::Instant;

/// Invocations per workgroup of the 1-D render kernels (`@workgroup_size(64)`).
const WORKGROUP: u32 = 64;
/// Invocations per workgroup of the compaction kernels (`SCAN_BLOCK` in compact.wgsl).
pub(crate) const SCAN_BLOCK: u32 = 256;
/// Most workgroups in one dispatch dimension; larger dispatches use y too, and the
/// kernels index `x + y · 65535 · size`.
const MAX_GROUPS_X: u32 = 65_535;

/// A ray in a queue (`RayRec` in shaders/render_work.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct RayRec {
    /// Origin (bytes 0–11).
    pub org: [f32; 3],
    /// Pixel sample in this batch (12).
    pub sample: u32,
    /// Direction (16–27).
    pub dir: [f32; 3],
    /// Ray level, primary = 1 (28).
    pub level: u32,
    /// Colour throughput (32–43).
    pub thr: [f32; 3],
    /// Scalar weight (44).
    pub weight: f32,
    /// The cumulative integrator's path number (48) and its sample's key (52).
    pub path: u32,
    pub key: u32,
    /// The path tracer's previous BSDF density (56) and smooth flag (60).
    pub prev_pdf: f32,
    pub prev_smooth: u32,
}
const _: () = assert!(std::mem::size_of::<RayRec>() == 64, "RayRec mirrors the WGSL struct");

/// A hit as the kernels write it (`Hit` in shaders/bvh_traverse.wgsl): 16 bytes.
pub(crate) const HIT_BYTES: u64 = 16;

/// The per-dispatch uniform (`Work` in shaders/render_work.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub(crate) struct Work {
    /// Items of the dispatch.
    pub n: u32,
    /// Kernel-specific (compact_blocks: the number of blocks).
    pub a: u32,
    /// Kernel-specific (ray generation: the first sample of the batch).
    pub b: u32,
    /// Unused.
    pub c: u32,
}

/// Group 1's storage slots (binding numbers of shaders/render_work.wgsl).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u32)]
pub(crate) enum Slot {
    RaysIn = 0,
    RaysOut = 1,
    Hits = 2,
    ListIn = 3,
    ListOut = 4,
    Flags = 5,
    Contrib = 6,
    Aux = 7,
    Film = 9,
    Counters = 10,
}

const STORAGE_SLOTS: [u32; 10] = [0, 1, 2, 3, 4, 5, 6, 7, 9, 10];

/// A measured stage of a render.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Stage {
    Generate,
    Trace,
    Compact,
    Shade,
    /// The megakernel (and the hybrid's survivor kernel): trace and shade in one.
    Fused,
}

/// Seconds per stage (mod.rs's `StageTimings` reports them).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Seconds {
    pub generate: f64,
    pub trace: f64,
    pub compact: f64,
    pub shade: f64,
    pub fused: f64,
}

impl Seconds {
    fn add(&mut self, stage: Stage, s: f64) {
        match stage {
            Stage::Generate => self.generate += s,
            Stage::Trace => self.trace += s,
            Stage::Compact => self.compact += s,
            Stage::Shade => self.shade += s,
            Stage::Fused => self.fused += s,
        }
    }
}

/// The pipelines of one (precision, traversal stack, ray stack) configuration.
pub(crate) struct Kernels {
    module: wgpu::ShaderModule,
    render_layout: wgpu::PipelineLayout,
    compact_layout: wgpu::PipelineLayout,
    pub scene_layout: wgpu::BindGroupLayout,
    work_layout: wgpu::BindGroupLayout,
    empty_group: wgpu::BindGroup,
    pipelines: Mutex<HashMap<&'static str, wgpu::ComputePipeline>>,
}

fn storage_entry(binding: u32, read_only: bool) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

fn uniform_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

impl Kernels {
    /// Compiles the render module (entry points are made on first use).
    pub fn new(ctx: &GpuContext, stack: u32, ray_stack: u32) -> Result<Self, GpuError> {
        let d = &ctx.device;
        let scope = d.push_error_scope(wgpu::ErrorFilter::Validation);
        let source = shader::render_module(ctx.precision(), stack, ray_stack);
        let module = d.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("render kernels"),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
        let mut scene_entries: Vec<_> = (0..=8).map(|b| storage_entry(b, true)).collect();
        scene_entries.push(uniform_entry(9));
        scene_entries.push(storage_entry(10, true));
        scene_entries.push(storage_entry(11, true));
        // The path tracer's tables (path_shade.wgsl): emitters, emissive triangles, the
        // emitter of each triangle, the BSDF of each material, its parameters.
        scene_entries.extend((12..=15).map(|b| storage_entry(b, true)));
        scene_entries.push(uniform_entry(16));
        let scene_layout = d.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("frame"),
            entries: &scene_entries,
        });
        let mut work_entries: Vec<_> = STORAGE_SLOTS.iter().map(|&b| storage_entry(b, false)).collect();
        work_entries.push(uniform_entry(8));
        let work_layout = d.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("queues"),
            entries: &work_entries,
        });
        let empty_layout =
            d.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some("none"), entries: &[] });
        let empty_group = d.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("none"),
            layout: &empty_layout,
            entries: &[],
        });
        let layout = |label, groups: &[Option<&wgpu::BindGroupLayout>]| {
            d.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(label),
                bind_group_layouts: groups,
                immediate_size: 0,
            })
        };
        let render_layout = layout("render", &[Some(&scene_layout), Some(&work_layout)]);
        let compact_layout = layout("compact", &[Some(&empty_layout), Some(&work_layout)]);
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(GpuError::Device { what: "render kernels", message: e.to_string() });
        }
        Ok(Self {
            module,
            render_layout,
            compact_layout,
            scene_layout,
            work_layout,
            empty_group,
            pipelines: Mutex::new(HashMap::new()),
        })
    }

    /// The pipeline of entry point `entry` (compiled on first use: 0.1–2 s on lavapipe).
    pub fn pipeline(&self, ctx: &GpuContext, entry: &'static str) -> Result<wgpu::ComputePipeline, GpuError> {
        let mut map = self.pipelines.lock().unwrap_or_else(|p| p.into_inner());
        if let Some(p) = map.get(entry) {
            return Ok(p.clone());
        }
        let layout = if entry.starts_with("compact_") { &self.compact_layout } else { &self.render_layout };
        let scope = ctx.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let p = ctx.device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(entry),
            layout: Some(layout),
            module: &self.module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            cache: None,
        });
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(GpuError::Device { what: "render kernel", message: format!("{entry}: {e}") });
        }
        map.insert(entry, p.clone());
        Ok(p)
    }
}

/// Placeholders for the slots a dispatch does not use (one per slot: a buffer may not
/// be bound writable twice in one group) and the shared ray counters.
pub(crate) struct Placeholders {
    by_slot: Vec<(u32, wgpu::Buffer)>,
}

impl Placeholders {
    pub fn new(ctx: &GpuContext) -> Result<Self, GpuError> {
        let by_slot = STORAGE_SLOTS
            .iter()
            .map(|&b| Ok((b, buffer::output(ctx, "unused slot", 64)?)))
            .collect::<Result<_, _>>()?;
        Ok(Self { by_slot })
    }
}

/// One dispatch's group-1 buffers.
pub(crate) fn work_group(
    ctx: &GpuContext,
    kernels: &Kernels,
    placeholders: &Placeholders,
    slots: &[(Slot, &wgpu::Buffer)],
    work: Work,
) -> wgpu::BindGroup {
    let uniform = buffer::uniform(ctx, "work", &work);
    let mut entries: Vec<wgpu::BindGroupEntry> = placeholders
        .by_slot
        .iter()
        .map(|(b, placeholder)| {
            let buf = slots.iter().find(|(s, _)| *s as u32 == *b).map_or(placeholder, |(_, buf)| *buf);
            wgpu::BindGroupEntry { binding: *b, resource: buf.as_entire_binding() }
        })
        .collect();
    entries.push(wgpu::BindGroupEntry { binding: 8, resource: uniform.as_entire_binding() });
    ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("queues"),
        layout: &kernels.work_layout,
        entries: &entries,
    })
}

/// Workgroup counts covering `groups` workgroups in at most two dimensions.
fn grid(groups: u32) -> (u32, u32) {
    if groups <= MAX_GROUPS_X {
        (groups.max(1), 1)
    } else {
        (MAX_GROUPS_X, groups.div_ceil(MAX_GROUPS_X))
    }
}

/// Records dispatches into one command encoder, timing each stage: with timestamp
/// queries (one pair per pass) where the device has them, else by submitting every
/// pass alone and waiting for it (wall clock, which includes the submission overhead).
pub(crate) struct Recorder<'a> {
    ctx: &'a GpuContext,
    encoder: Option<wgpu::CommandEncoder>,
    queries: Option<wgpu::QuerySet>,
    stages: Vec<Stage>,
    pub seconds: Seconds,
}

/// Passes per submission with timestamps (two queries each).
const MAX_TIMED_PASSES: u32 = 64;

impl<'a> Recorder<'a> {
    pub fn new(ctx: &'a GpuContext) -> Self {
        let queries = ctx.has_timestamps().then(|| {
            ctx.device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("stage timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: 2 * MAX_TIMED_PASSES,
            })
        });
        Self { ctx, encoder: None, queries, stages: Vec::new(), seconds: Seconds::default() }
    }

    /// The encoder the next commands go to (copies included).
    pub fn encoder(&mut self) -> &mut wgpu::CommandEncoder {
        self.encoder.get_or_insert_with(|| self.ctx.device.create_command_encoder(&Default::default()))
    }

    /// One pass of `pipeline` over `groups` workgroups with the frame group (if any) at 0.
    pub fn dispatch_groups(
        &mut self,
        stage: Stage,
        pipeline: &wgpu::ComputePipeline,
        group0: &wgpu::BindGroup,
        group1: &wgpu::BindGroup,
        groups: u32,
    ) -> Result<(), GpuError> {
        if self.queries.is_some() && self.stages.len() as u32 == MAX_TIMED_PASSES {
            self.submit()?;
        }
        let index = self.stages.len() as u32;
        let writes = self.queries.as_ref().map(|q| wgpu::ComputePassTimestampWrites {
            query_set: q,
            beginning_of_pass_write_index: Some(2 * index),
            end_of_pass_write_index: Some(2 * index + 1),
        });
        let started = Instant::now();
        let (x, y) = grid(groups);
        {
            let enc = self.encoder.get_or_insert_with(|| self.ctx.device.create_command_encoder(&Default::default()));
            let mut pass =
                enc.begin_compute_pass(&wgpu::ComputePassDescriptor { label: None, timestamp_writes: writes });
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, group0, &[]);
            pass.set_bind_group(1, group1, &[]);
            pass.dispatch_workgroups(x, y, 1);
        }
        if self.queries.is_some() {
            self.stages.push(stage);
        } else {
            self.submit()?;
            self.seconds.add(stage, started.elapsed().as_secs_f64());
        }
        Ok(())
    }

    /// [`Self::dispatch_groups`] for a 64-wide kernel over `items` invocations.
    pub fn dispatch(
        &mut self,
        stage: Stage,
        pipeline: &wgpu::ComputePipeline,
        group0: &wgpu::BindGroup,
        group1: &wgpu::BindGroup,
        items: u32,
    ) -> Result<(), GpuError> {
        if items == 0 {
            return Ok(());
        }
        self.dispatch_groups(stage, pipeline, group0, group1, items.div_ceil(WORKGROUP))
    }

    /// The frame-less group 0 of the compaction kernels.
    pub fn empty_group(kernels: &Kernels) -> &wgpu::BindGroup {
        &kernels.empty_group
    }

    /// Submits what was recorded, waits for it, and adds its timestamps to the stages.
    pub fn submit(&mut self) -> Result<(), GpuError> {
        let Some(mut enc) = self.encoder.take() else { return Ok(()) };
        let timed = std::mem::take(&mut self.stages);
        let resolve = match (&self.queries, timed.is_empty()) {
            (Some(q), false) => {
                let n = 2 * timed.len() as u32;
                let bytes = n as u64 * 8;
                let target = self.ctx.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("timestamps"),
                    size: bytes,
                    usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                });
                let staging = buffer::staging(self.ctx, bytes);
                enc.resolve_query_set(q, 0..n, &target, 0);
                enc.copy_buffer_to_buffer(&target, 0, &staging, 0, bytes);
                Some((staging, n as usize))
            }
            _ => None,
        };
        self.ctx.queue.submit([enc.finish()]);
        match resolve {
            Some((staging, n)) => {
                let mut ticks = vec![0u64; n];
                buffer::read_into(self.ctx, &staging, &mut ticks)?;
                let period = self.ctx.queue.get_timestamp_period() as f64 * 1e-9;
                for (i, stage) in timed.into_iter().enumerate() {
                    let dt = ticks[2 * i + 1].saturating_sub(ticks[2 * i]);
                    self.seconds.add(stage, dt as f64 * period);
                }
                Ok(())
            }
            None => buffer::wait(self.ctx),
        }
    }

    /// Submits, then reads `out.len()` elements of `src` back.
    pub fn read<T: Pod>(&mut self, src: &wgpu::Buffer, out: &mut [T]) -> Result<(), GpuError> {
        let bytes = std::mem::size_of_val(out) as u64;
        if bytes == 0 {
            return self.submit();
        }
        let staging = buffer::staging(self.ctx, bytes);
        self.encoder().copy_buffer_to_buffer(src, 0, &staging, 0, bytes);
        self.submit()?;
        buffer::read_into(self.ctx, &staging, out)
    }
}
