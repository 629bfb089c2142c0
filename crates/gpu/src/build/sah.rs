//! Seed 003 §3.8's GPU builder (shaders/sah_build.wgsl): the binned SAH, level by level,
//! one workgroup of 96 invocations (3 axes × 32 bins) per node of the level, the next
//! level compacted by a prefix sum rather than stored as the seed's sparse heap (which
//! grows with 2^depth), the triangles partitioned stably by a second prefix sum. Leaf
//! rules and SAH constants are the CPU builder's ([`BvhParams`]); coincident centroids and
//! nodes past depth 64 are halved by index, so every leaf is shallower than 96 levels.

use super::kernels::Module;
use super::passes::{BuildTimings, Passes};
use super::{refit, scan};
use crate::{buffer, GpuBvh, GpuContext, GpuError};
use bytemuck::{Pod, Zeroable};
use dynray_accel::BvhParams;
use std::sync::Arc;

/// Depth from which nodes are halved instead of split by the SAH (the CPU's limit).
const SAH_DEPTH_LIMIT: u32 = 64;
/// Most workgroups `sah_split` is dispatched with; they stride over larger levels
/// (where most nodes are small and left to `sah_split_small`).
const MAX_SPLIT_GROUPS: u32 = 2048;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct BuildParams {
    count: u32,
    base: u32,
    next_base: u32,
    depth: u32,
    leaf_size: u32,
    max_leaf_size: u32,
    depth_limit: u32,
    n: u32,
    kt: f32,
    ki: f32,
    _pad: [u32; 2],
}

/// Per-level state the kernels read and write, swapped between levels.
struct Side {
    ids: wgpu::Buffer,
    owner: wgpu::Buffer,
    frontier: wgpu::Buffer,
}

/// Builds over `n` triangles already on the device (`mesh_tris`, mesh order).
pub(crate) fn build(
    ctx: &Arc<GpuContext>,
    mut p: Passes<'_>,
    mesh_tris: wgpu::Buffer,
    n: u32,
    params: &BvhParams,
) -> Result<(GpuBvh, BuildTimings), GpuError> {
    let words = |what, k: u64| buffer::output(ctx, what, 4 * k);
    let identity: Vec<u32> = (0..n).collect();
    let none = wgpu::BufferUsages::empty();
    let mut cur = Side {
        ids: buffer::storage(ctx, "triangle order", &identity, wgpu::BufferUsages::COPY_SRC)?,
        owner: buffer::storage(ctx, "triangle node", &vec![0u32; n as usize], none)?,
        frontier: words("BVH level", 2 * n as u64)?,
    };
    let mut next = Side {
        ids: words("triangle order", n as u64)?,
        owner: words("triangle node", n as u64)?,
        frontier: words("BVH next level", 2 * n as u64)?,
    };
    ctx.queue.write_buffer(&cur.frontier, 0, bytemuck::cast_slice(&[0u32, n]));
    let decisions = words("split decisions", 8 * n as u64)?;
    let nodes = buffer::output(ctx, "BVH nodes", 32 * (2 * n - 1) as u64)?;
    let split_flags = words("split flags", n as u64)?;
    let flags = words("left flags", n as u64 + 1)?;
    let (split_sums, flag_sums) = (scan::sums_buffer(&p, n)?, scan::sums_buffer(&p, n + 1)?);
    let sah = ctx.builders.get(ctx, Module::Sah)?;
    let scan_k = scan::kernels(&p)?;
    p.end_stage("upload")?;

    let mut levels = Vec::new();
    let (mut base, mut count, mut depth) = (0u32, 1u32, 0u32);
    loop {
        let bp = p.uniform(&BuildParams {
            count,
            base,
            next_base: base + count,
            depth,
            leaf_size: params.leaf_size,
            max_leaf_size: params.max_leaf_size,
            depth_limit: SAH_DEPTH_LIMIT,
            n,
            kt: params.traversal_cost,
            ki: params.intersection_cost,
            _pad: [0; 2],
        });
        let split = [
            (0, &mesh_tris),
            (1, &cur.ids),
            (3, &cur.frontier),
            (5, &decisions),
            (6, &nodes),
            (7, &split_flags),
            (11, &bp),
        ];
        p.dispatch(&sah, "sah_split", &split, count.min(MAX_SPLIT_GROUPS));
        p.dispatch_items(&sah, "sah_split_small", &split, count, 64);
        scan::record(&mut p, &scan_k, &split_flags, &split_sums, count);
        let fl = [
            (0, &mesh_tris),
            (1, &cur.ids),
            (3, &cur.frontier),
            (5, &decisions),
            (8, &flags),
            (9, &cur.owner),
            (11, &bp),
        ];
        p.dispatch_items(&sah, "sah_flags", &fl, n + 1, 64);
        scan::record(&mut p, &scan_k, &flags, &flag_sums, n + 1);
        let emit = [
            (3, &cur.frontier),
            (4, &next.frontier),
            (5, &decisions),
            (6, &nodes),
            (7, &split_flags),
            (8, &flags),
            (11, &bp),
        ];
        p.dispatch_items(&sah, "sah_emit", &emit, count, 64);
        let scatter = [
            (1, &cur.ids),
            (2, &next.ids),
            (3, &cur.frontier),
            (5, &decisions),
            (7, &split_flags),
            (8, &flags),
            (9, &cur.owner),
            (10, &next.owner),
            (11, &bp),
        ];
        p.dispatch_items(&sah, "sah_scatter", &scatter, n, 64);
        levels.push([base, count]);
        std::mem::swap(&mut cur, &mut next);
        let splits = p.read_u32(&split_sums, 0)?;
        if splits == 0 {
            break;
        }
        base += count;
        count = 2 * splits;
        depth += 1;
    }
    let node_count = base + count;
    p.end_stage("levels")?;

    // Boxes were written level by level; the leaves need their triangles in order.
    let tris = buffer::output(ctx, "BVH triangles", 36 * n as u64)?;
    refit::gather(&mut p, &mesh_tris, &cur.ids, &tris, n)?;
    p.end_stage("gather")?;

    let bvh = GpuBvh::from_buffers(ctx.clone(), [nodes, tris, cur.ids], node_count as usize, n as usize, depth)?
        .with_levels(levels);
    Ok((bvh, p.timings))
}
