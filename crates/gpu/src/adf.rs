//! Seed 001's distance field on the device: the voxel texture, H, Φ and the per-cell
//! Lipschitz bounds uploaded as storage buffers (the `.adf` layout, unchanged), located
//! and sphere traced by `shaders/adf.wgsl`, a port of `dynray-adf`'s CPU code in its
//! operation order.
//!
//! Agreement: point location is integer work and equals the CPU's exactly (level, block
//! and probes). The march is f32 arithmetic, whose division and square root a Vulkan
//! driver may round differently (and may fuse a multiply-add), so `t` agrees to a few
//! ulps where both find the surface, and a ray grazing a silhouette can, rarely, hit on
//! one side and miss on the other (docs/adf.md, "On the GPU").

use crate::{buffer, kernel, shader, GpuContext, GpuError};
use bytemuck::{Pod, Zeroable};
use dynray_accel::{check_batch_lengths, BatchQuery};
use dynray_adf::{Adf, Located, Search};
use dynray_geom::{Hit, Ray, Vec3};
use std::sync::Arc;

/// Rays (or points) per submission: one dispatch dimension holds 65,535 workgroups of 64.
const ITEMS_PER_SUBMIT: usize = 1 << 21;

/// `AdfParams` of adf.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct Params {
    origin: [f32; 3],
    size: f32,
    max_level: u32,
    m: u32,
    r: u32,
    lipschitz: f32,
    bx: u32,
    by: u32,
    sx: u32,
    sy: u32,
    count: u32,
    search: u32,
    cells: u32,
    run: u32,
    texel_count: u32,
    normals: u32,
    wide: u32,
    _pad: u32,
}

/// `MarchAnswer` of adf.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct Answer {
    grad: [f32; 3],
    t: f32,
    samples: u32,
    probes: u32,
    found: u32,
    _pad: u32,
}

/// One ray's march on the device.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GpuMarch {
    /// `t` of the first crossing, `None` for a miss.
    pub t: Option<f32>,
    /// The field's gradient at the hit (unnormalised; zero unless asked for and hit).
    pub gradient: Vec3,
    /// Field samples taken.
    pub samples: u32,
    /// Hash probes of point location.
    pub probes: u32,
}

/// The level search as the kernel's `search` parameter.
fn search_code(s: Search) -> u32 {
    match s {
        Search::Linear => 0,
        Search::Binary => 1,
        Search::CoherentLinear => 2,
    }
}

/// A distance field on the device.
pub struct GpuAdf {
    ctx: Arc<GpuContext>,
    texels: wgpu::Buffer,
    table: wgpu::Buffer,
    /// H's second identifier words (one zero word for trees of level 10 or less).
    high: wgpu::Buffer,
    phi: wgpu::Buffer,
    bounds: wgpu::Buffer,
    params: Params,
    march: wgpu::ComputePipeline,
    locate: wgpu::ComputePipeline,
}

impl std::fmt::Debug for GpuAdf {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GpuAdf")
            .field("max_level", &self.params.max_level)
            .field("bytes", &self.memory_bytes())
            .finish()
    }
}

impl GpuAdf {
    /// Uploads `adf`'s tables and compiles the kernels. A table larger than the adapter
    /// binds in one buffer is [`GpuError::TooLarge`].
    pub fn upload(ctx: Arc<GpuContext>, adf: &Adf) -> Result<Self, GpuError> {
        let voxels = adf.voxels();
        let hash = adf.hash();
        let none = wgpu::BufferUsages::empty();
        let texels = buffer::storage(&ctx, "ADF voxel texture", voxels.texels(), none)?;
        let table = buffer::storage(&ctx, "ADF cell table H", hash.entries(), none)?;
        let high = buffer::storage(&ctx, "ADF cell table H, second identifier words", hash.high_ids(), none)?;
        let phi = buffer::storage(&ctx, "ADF offset table Φ", hash.offsets(), none)?;
        let bounds = buffer::storage(&ctx, "ADF cell bounds", adf.cell_lipschitz(), none)?;
        let cube = adf.cube();
        let [bx, by, _] = voxels.block_dims();
        let [sx, sy, _] = voxels.size();
        let params = Params {
            origin: cube.origin.to_array(),
            size: cube.size,
            max_level: adf.max_level(),
            m: hash.table_edge(),
            r: hash.offset_edge(),
            lipschitz: adf.lipschitz(),
            bx,
            by,
            sx,
            sy,
            count: 0,
            search: 0,
            cells: adf.cell_lipschitz().len() as u32,
            run: 1,
            texel_count: voxels.texels().len() as u32,
            normals: 0,
            wide: !hash.high_ids().is_empty() as u32,
            _pad: 0,
        };
        let src = shader::assemble(ctx.precision(), 1, &[shader::ADF]);
        let mut ps = kernel::compile(&ctx, "distance field", &src, &["adf_march", "adf_locate"])?;
        let locate = ps.pop().expect("two entry points");
        let march = ps.pop().expect("two entry points");
        Ok(Self { ctx, texels, table, high, phi, bounds, params, march, locate })
    }

    /// Bytes of the device's tables.
    pub fn memory_bytes(&self) -> u64 {
        self.texels.size() + self.table.size() + self.high.size() + self.phi.size() + self.bounds.size()
    }

    /// The device it lives on.
    pub fn context(&self) -> &Arc<GpuContext> {
        &self.ctx
    }

    /// Marches every ray (in the field's space), locating samples with `search`;
    /// `gradients`: also the field's gradient at each hit (for normals).
    pub fn march(&self, rays: &[Ray], search: Search, gradients: bool) -> Result<Vec<GpuMarch>, GpuError> {
        let mut out = Vec::with_capacity(rays.len());
        for chunk in rays.chunks(ITEMS_PER_SUBMIT) {
            let params = Params {
                count: chunk.len() as u32,
                search: search_code(search),
                normals: gradients as u32,
                ..self.params
            };
            let mut answers = vec![Answer::zeroed(); chunk.len()];
            let ray_buf = buffer::storage(&self.ctx, "rays", chunk, wgpu::BufferUsages::empty())?;
            let entries = [
                (0, &self.texels),
                (1, &self.table),
                (2, &self.phi),
                (3, &self.bounds),
                (5, &ray_buf),
                (9, &self.high),
            ];
            self.run(&self.march, &params, &entries, 6, chunk.len() as u32, &mut answers)?;
            out.extend(answers.iter().map(|a| GpuMarch {
                t: (a.found != 0).then_some(a.t),
                gradient: Vec3::from_array(a.grad),
                samples: a.samples,
                probes: a.probes,
            }));
        }
        Ok(out)
    }

    /// The deepest internal cell holding each of `points` (finest-level coordinates, as
    /// [`Adf::fine_coords`] gives), `run` consecutive points per invocation with the
    /// coherent search's hint carried from one to the next (reset at each run's start).
    pub fn locate(&self, points: &[[u32; 3]], search: Search, run: u32) -> Result<Vec<Located>, GpuError> {
        let run = run.max(1);
        let per_submit = ITEMS_PER_SUBMIT / run as usize * run as usize;
        let mut out = Vec::with_capacity(points.len());
        for chunk in points.chunks(per_submit.max(run as usize)) {
            let padded: Vec<[u32; 4]> = chunk.iter().map(|p| [p[0], p[1], p[2], 0]).collect();
            let params = Params { count: chunk.len() as u32, search: search_code(search), run, ..self.params };
            let mut located = vec![[0u32; 4]; chunk.len()];
            let point_buf = buffer::storage(&self.ctx, "points", &padded, wgpu::BufferUsages::empty())?;
            let entries = [(1, &self.table), (2, &self.phi), (7, &point_buf), (9, &self.high)];
            self.run(&self.locate, &params, &entries, 8, chunk.len().div_ceil(run as usize) as u32, &mut located)?;
            out.extend(located.iter().map(|l| Located { level: l[0], block: l[1], probes: l[2] }));
        }
        Ok(out)
    }

    /// One submission: `inputs` and the parameters bound, `invocations` of `pipeline`,
    /// `out` read back from the buffer at `binding`.
    fn run<T: Pod>(
        &self,
        pipeline: &wgpu::ComputePipeline,
        params: &Params,
        inputs: &[(u32, &wgpu::Buffer)],
        binding: u32,
        invocations: u32,
        out: &mut [T],
    ) -> Result<(), GpuError> {
        if out.is_empty() {
            return Ok(());
        }
        let ctx = &self.ctx;
        let uniform = buffer::uniform(ctx, "ADF params", params);
        let bytes = std::mem::size_of_val(out) as u64;
        let result = buffer::output(ctx, "ADF answers", bytes)?;
        let mut entries = inputs.to_vec();
        entries.push((4, &uniform));
        entries.push((binding, &result));
        let group = kernel::bind(ctx, pipeline, &entries);
        let staging = buffer::staging(ctx, bytes);
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        kernel::dispatch(&mut enc, pipeline, &group, invocations);
        enc.copy_buffer_to_buffer(&result, 0, &staging, 0, bytes);
        ctx.queue.submit([enc.finish()]);
        buffer::read_into(ctx, &staging, out)
    }
}

/// The field as a batch query (primitive 0, `u = v = 0`), as the CPU's `AdfGeometry`
/// answers; a device failure stops the program with wgpu's message, as [`crate::GpuBvh`].
impl BatchQuery for GpuAdf {
    fn intersect_into(&self, rays: &[Ray], hits: &mut [Hit]) {
        check_batch_lengths(rays.len(), hits.len());
        let marched = self.march(rays, Search::CoherentLinear, false).unwrap_or_else(|e| panic!("{e}"));
        for (h, m) in hits.iter_mut().zip(marched) {
            *h = m.t.map_or(Hit::MISS, |t| Hit { t, u: 0.0, v: 0.0, prim: 0 });
        }
    }

    fn occluded_into(&self, rays: &[Ray], out: &mut [bool]) {
        check_batch_lengths(rays.len(), out.len());
        let marched = self.march(rays, Search::CoherentLinear, false).unwrap_or_else(|e| panic!("{e}"));
        for (o, m) in out.iter_mut().zip(marched) {
            *o = m.t.is_some();
        }
    }
}
