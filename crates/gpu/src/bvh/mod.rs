//! A BVH on the device: the CPU builder's node, triangle and id arrays uploaded unchanged,
//! traced by `shaders/bvh_traverse.wgsl` through the batch-query trait.

mod self_check;

pub(crate) use self_check::self_check;

use crate::{buffer, kernel, shader, GpuContext, GpuError};
use bytemuck::{Pod, Zeroable};
use dynray_accel::{check_batch_lengths, BatchQuery, Bvh, BvhNode, BvhParams};
use dynray_geom::{Hit, Ray, Triangle, TriangleMesh};
use std::collections::HashMap;
use std::sync::{Arc, Mutex};

/// Rays per submission: under the 65,535-workgroup limit of one dispatch dimension
/// (× 64 invocations) and 64 MiB of rays, half of lavapipe's 128 MiB binding limit.
const RAYS_PER_SUBMIT: usize = 1 << 21;

/// A hit as the kernels write it (geom's `Hit` is not Pod).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct GpuHit {
    t: f32,
    u: f32,
    v: f32,
    prim: u32,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Params {
    count: u32,
    _pad: [u32; 3],
}

/// The batch-query pipelines of one stack size.
pub(crate) struct TracePipelines {
    closest: wgpu::ComputePipeline,
    occlusion: wgpu::ComputePipeline,
}

/// Pipelines compiled so far, per stack size (compiling takes ~0.1–1 s on lavapipe).
#[derive(Default)]
pub(crate) struct KernelCache {
    trace: Mutex<HashMap<u32, Arc<TracePipelines>>>,
}

impl KernelCache {
    fn trace(&self, ctx: &GpuContext, stack: u32) -> Result<Arc<TracePipelines>, GpuError> {
        let mut map = self.trace.lock().unwrap_or_else(|p| p.into_inner());
        if let Some(p) = map.get(&stack) {
            return Ok(p.clone());
        }
        let src =
            shader::assemble(ctx.precision(), stack, &[shader::WATERTIGHT, shader::BVH_TRAVERSE, shader::TRACE_RAYS]);
        let mut ps = kernel::compile(ctx, "bvh trace", &src, &["closest", "occlusion"])?;
        let occlusion = ps.pop().expect("two entry points");
        let closest = ps.pop().expect("two entry points");
        let p = Arc::new(TracePipelines { closest, occlusion });
        map.insert(stack, p.clone());
        Ok(p)
    }
}

/// The device's copy of a [`Bvh`]: what the GPU kernels traverse.
pub struct GpuBvh {
    pub(crate) ctx: Arc<GpuContext>,
    pub(crate) nodes: wgpu::Buffer,
    pub(crate) tris: wgpu::Buffer,
    pub(crate) ids: wgpu::Buffer,
    pub(crate) triangles: usize,
    node_count: usize,
    /// Traversal stack entries its kernels are compiled for.
    stack: u32,
    pipelines: Arc<TracePipelines>,
    /// (first slot, nodes) per depth of a breadth-first tree built on the device, which
    /// [`GpuBvh::refit`] walks bottom-up; empty for a tree uploaded from the CPU.
    pub(crate) levels: Vec<[u32; 2]>,
}

impl std::fmt::Debug for GpuBvh {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GpuBvh").field("nodes", &self.node_count).field("triangles", &self.triangles).finish()
    }
}

impl GpuBvh {
    /// Uploads `bvh`'s arrays and compiles (or reuses) the kernels for its depth.
    pub fn upload(ctx: Arc<GpuContext>, bvh: &Bvh) -> Result<Self, GpuError> {
        let depth = bvh.depth();
        // COPY_SRC: a device tree can be read back (`download`) for validation.
        let src = wgpu::BufferUsages::COPY_SRC;
        let nodes = buffer::storage(&ctx, "BVH nodes", bvh.nodes(), src)?;
        let tris = buffer::storage(&ctx, "BVH triangles", bvh.triangles(), src)?;
        let ids = buffer::storage(&ctx, "BVH triangle ids", bvh.triangle_ids(), src)?;
        Self::from_buffers(ctx, [nodes, tris, ids], bvh.nodes().len(), bvh.triangles().len(), depth)
    }

    /// A tree whose arrays are already on the device (written by a GPU builder): `buffers`
    /// are the node, leaf-order triangle and triangle-id arrays in [`Bvh`]'s layout, with
    /// `node_count` nodes over `triangles` triangles, the deepest leaf at `depth`. They
    /// need `STORAGE | COPY_SRC | COPY_DST` usage (as [`buffer::output`] gives).
    pub(crate) fn from_buffers(
        ctx: Arc<GpuContext>,
        buffers: [wgpu::Buffer; 3],
        node_count: usize,
        triangles: usize,
        depth: u32,
    ) -> Result<Self, GpuError> {
        let stack = shader::stack_for(depth).ok_or(GpuError::Device {
            what: "upload",
            message: format!("the BVH is {depth} levels deep; the kernels' stacks hold at most 127"),
        })?;
        let pipelines = ctx.kernels.trace(&ctx, stack)?;
        let [nodes, tris, ids] = buffers;
        Ok(Self { nodes, tris, ids, triangles, node_count, stack, pipelines, ctx, levels: Vec::new() })
    }

    /// The same tree, recorded as breadth-first with these levels (device builders).
    pub(crate) fn with_levels(mut self, levels: Vec<[u32; 2]>) -> Self {
        self.levels = levels;
        self
    }

    /// Reads the device's arrays back into a CPU [`Bvh`], checked against `mesh` by
    /// [`Bvh::from_parts`]: how tests validate the GPU builders, and how a GPU-built tree
    /// reaches CPU code. `params` are recorded as the tree's build parameters.
    pub fn download(&self, mesh: &TriangleMesh, params: &BvhParams) -> Result<Bvh, GpuError> {
        let mut nodes = vec![BvhNode::zeroed(); self.node_count];
        let mut tris = vec![Triangle::zeroed(); self.triangles];
        let mut ids = vec![0u32; self.triangles];
        buffer::read_back(&self.ctx, &self.nodes, &mut nodes)?;
        buffer::read_back(&self.ctx, &self.tris, &mut tris)?;
        buffer::read_back(&self.ctx, &self.ids, &mut ids)?;
        Bvh::from_parts(mesh, nodes, tris, ids, params)
            .map_err(|e| GpuError::Device { what: "BVH read-back", message: e.to_string() })
    }

    /// Nodes in the device's array.
    pub fn node_count(&self) -> usize {
        self.node_count
    }

    /// Traversal depth bound the kernels were compiled for (the deepest leaf's depth fits).
    pub fn depth_capacity(&self) -> u32 {
        self.stack
    }

    /// Replaces the device's arrays with `bvh`'s (a refit or a rebuild of the same mesh):
    /// written in place when the sizes match, re-allocated otherwise.
    pub fn update(&mut self, bvh: &Bvh) -> Result<(), GpuError> {
        self.levels.clear();
        let same_size = bvh.nodes().len() == self.node_count && bvh.triangles().len() == self.triangles;
        if same_size && bvh.depth() < self.stack {
            let q = &self.ctx.queue;
            q.write_buffer(&self.nodes, 0, bytemuck::cast_slice(bvh.nodes()));
            q.write_buffer(&self.tris, 0, bytemuck::cast_slice(bvh.triangles()));
            q.write_buffer(&self.ids, 0, bytemuck::cast_slice(bvh.triangle_ids()));
            return Ok(());
        }
        *self = Self::upload(self.ctx.clone(), bvh)?;
        Ok(())
    }

    /// The node, triangle and triangle-id buffers, for kernels that traverse it (the
    /// render strategies bind them beside the frame's other arrays).
    pub(crate) fn buffers(&self) -> [&wgpu::Buffer; 3] {
        [&self.nodes, &self.tris, &self.ids]
    }

    /// The traversal stack size its kernels need.
    pub(crate) fn stack(&self) -> u32 {
        self.stack
    }

    /// The device it lives on.
    pub fn context(&self) -> &Arc<GpuContext> {
        &self.ctx
    }

    /// Bytes of the device's arrays.
    pub fn memory_bytes(&self) -> u64 {
        self.nodes.size() + self.tris.size() + self.ids.size()
    }

    /// Closest hits of `rays` into `hits`, or the device's error.
    pub fn try_intersect_into(&self, rays: &[Ray], hits: &mut [Hit]) -> Result<(), GpuError> {
        check_batch_lengths(rays.len(), hits.len());
        let mut out = vec![GpuHit::zeroed(); RAYS_PER_SUBMIT.min(rays.len())];
        for (rs, hs) in rays.chunks(RAYS_PER_SUBMIT).zip(hits.chunks_mut(RAYS_PER_SUBMIT)) {
            let out = &mut out[..rs.len()];
            self.run(&self.pipelines.closest, rs, 5, out)?;
            for (h, g) in hs.iter_mut().zip(out.iter()) {
                *h = Hit { t: g.t, u: g.u, v: g.v, prim: g.prim };
            }
        }
        Ok(())
    }

    /// Any-hit answers of `rays` into `out`, or the device's error.
    pub fn try_occluded_into(&self, rays: &[Ray], out: &mut [bool]) -> Result<(), GpuError> {
        check_batch_lengths(rays.len(), out.len());
        let mut flags = vec![0u32; RAYS_PER_SUBMIT.min(rays.len())];
        for (rs, os) in rays.chunks(RAYS_PER_SUBMIT).zip(out.chunks_mut(RAYS_PER_SUBMIT)) {
            let flags = &mut flags[..rs.len()];
            self.run(&self.pipelines.occlusion, rs, 6, flags)?;
            for (o, &f) in os.iter_mut().zip(flags.iter()) {
                *o = f != 0;
            }
        }
        Ok(())
    }

    /// One submission: uploads `rays`, runs `pipeline`, reads `out` back from the output
    /// buffer bound at `binding`.
    fn run<T: Pod>(
        &self,
        pipeline: &wgpu::ComputePipeline,
        rays: &[Ray],
        binding: u32,
        out: &mut [T],
    ) -> Result<(), GpuError> {
        if rays.is_empty() {
            return Ok(());
        }
        let ctx = &self.ctx;
        let ray_buf = buffer::storage(ctx, "rays", rays, wgpu::BufferUsages::empty())?;
        let params = buffer::uniform(ctx, "trace params", &Params { count: rays.len() as u32, _pad: [0; 3] });
        let bytes = std::mem::size_of_val(out) as u64;
        let result = buffer::output(ctx, "trace answers", bytes)?;
        let group = kernel::bind(
            ctx,
            pipeline,
            &[(0, &self.nodes), (1, &self.tris), (2, &self.ids), (3, &ray_buf), (4, &params), (binding, &result)]
                .into_iter()
                // The any-hit kernel never reads the ids, and a derived layout has only
                // the bindings its entry point uses.
                .filter(|&(b, _)| b != 2 || binding == 5)
                .collect::<Vec<_>>(),
        );
        let staging = buffer::staging(ctx, bytes);
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        kernel::dispatch(&mut enc, pipeline, &group, rays.len() as u32);
        enc.copy_buffer_to_buffer(&result, 0, &staging, 0, bytes);
        ctx.queue.submit([enc.finish()]);
        buffer::read_into(ctx, &staging, out)
    }
}

/// A device failure in the middle of a batch has no slice to report into: it stops the
/// program with wgpu's message (bad input never gets here: rays are checked by callers).
impl BatchQuery for GpuBvh {
    fn intersect_into(&self, rays: &[Ray], hits: &mut [Hit]) {
        if let Err(e) = self.try_intersect_into(rays, hits) {
            panic!("{e}");
        }
    }

    fn occluded_into(&self, rays: &[Ray], out: &mut [bool]) {
        if let Err(e) = self.try_occluded_into(rays, out) {
            panic!("{e}");
        }
    }
}
