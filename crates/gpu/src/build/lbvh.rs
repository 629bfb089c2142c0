//! The linear BVH (Lauterbach et al. 2009, with Karras 2012's parallel hierarchy): Morton
//! codes of the centroids, a device radix sort, every internal node at once from the
//! sorted codes, a breadth-first relabelling into the engine's node layout, then the
//! boxes bottom-up. Leaves hold one triangle. Fast to build and to refit, of lower SAH
//! quality than the binned builders (docs/gpu.md gives the figures).

use super::kernels::Module;
use super::passes::{BuildTimings, Passes};
use super::refit;
use super::{radix_sort, scan};
use crate::{buffer, GpuBvh, GpuContext, GpuError};
use bytemuck::{Pod, Zeroable};
use std::sync::Arc;

/// Marks a leaf in a child reference (shaders/karras.wgsl, lbvh_layout.wgsl).
const LEAF: u32 = 0x8000_0000;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct CountParams {
    n: u32,
    _pad: [u32; 3],
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct LayoutParams {
    count: u32,
    base: u32,
    next_base: u32,
    _pad: u32,
}

/// The u32 whose unsigned order is `f`'s float order (build_common.wgsl's `ordered`).
pub(crate) fn ordered(f: f32) -> u32 {
    let b = f.to_bits();
    if b & 0x8000_0000 != 0 {
        !b
    } else {
        b | 0x8000_0000
    }
}

/// Builds the LBVH over `n` triangles already on the device (`mesh_tris`, mesh order).
pub(crate) fn build(
    ctx: &Arc<GpuContext>,
    mut p: Passes<'_>,
    mesh_tris: wgpu::Buffer,
    n: u32,
) -> Result<(GpuBvh, BuildTimings), GpuError> {
    let words = |what, k: u32| buffer::output(ctx, what, 4 * k as u64);

    let morton = ctx.builders.get(ctx, Module::Morton)?;
    let empty_box = [f32::INFINITY; 3].map(ordered).into_iter().chain([f32::NEG_INFINITY; 3].map(ordered));
    let cbox = buffer::storage(ctx, "centroid box", &empty_box.collect::<Vec<u32>>(), wgpu::BufferUsages::empty())?;
    let (keys, vals) = (words("Morton codes", n)?, words("triangle order", n)?);
    let count = p.uniform(&CountParams { n, _pad: [0; 3] });
    p.dispatch_items(&morton, "centroid_bounds", &[(0, &mesh_tris), (1, &cbox), (4, &count)], n, 64);
    let b = [(0, &mesh_tris), (1, &cbox), (2, &keys), (3, &vals), (4, &count)];
    p.dispatch_items(&morton, "morton_codes", &b, n, 64);
    p.end_stage("morton")?;

    let (keys_tmp, vals_tmp) = (words("Morton scratch", n)?, words("order scratch", n)?);
    radix_sort::sort_pairs(&mut p, &keys, &vals, &keys_tmp, &vals_tmp, n)?;
    drop((keys_tmp, vals_tmp));
    p.end_stage("sort")?;

    let karras = ctx.builders.get(ctx, Module::Karras)?;
    let inner = buffer::output(ctx, "LBVH internal nodes", 16 * (n.max(2) - 1) as u64)?;
    p.dispatch_items(&karras, "hierarchy", &[(0, &keys), (1, &inner), (2, &count)], n - 1, 64);
    p.end_stage("hierarchy")?;

    // Breadth-first relabelling: level d's nodes at slots base .. base + count.
    let layout = ctx.builders.get(ctx, Module::LbvhLayout)?;
    let scan_k = scan::kernels(&p)?;
    let node_slots = 2 * n - 1;
    let nodes = buffer::output(ctx, "BVH nodes", 32 * node_slots as u64)?;
    let mut frontier = (words("BVH level", n)?, words("BVH next level", n)?);
    let flags = words("level flags", n)?;
    let sums = scan::sums_buffer(&p, n)?;
    let root = if n == 1 { LEAF } else { 0 };
    ctx.queue.write_buffer(&frontier.0, 0, bytemuck::bytes_of(&root));
    let mut levels = Vec::new();
    let (mut base, mut count_now) = (0u32, 1u32);
    loop {
        let params = p.uniform(&LayoutParams { count: count_now, base, next_base: base + count_now, _pad: 0 });
        p.dispatch_items(&layout, "layout_flags", &[(1, &frontier.0), (3, &flags), (5, &params)], count_now, 64);
        scan::record(&mut p, &scan_k, &flags, &sums, count_now);
        let b = [(0, &inner), (1, &frontier.0), (2, &frontier.1), (3, &flags), (4, &nodes), (5, &params)];
        p.dispatch_items(&layout, "layout_emit", &b, count_now, 64);
        levels.push([base, count_now]);
        let internal = p.read_u32(&sums, 0)?;
        if internal == 0 {
            break;
        }
        base += count_now;
        count_now = 2 * internal;
        std::mem::swap(&mut frontier.0, &mut frontier.1);
    }
    let node_count = base + count_now;
    debug_assert_eq!(node_count, node_slots, "a binary tree over n single-triangle leaves");
    p.end_stage("layout")?;

    let tris = buffer::output(ctx, "BVH triangles", 36 * n as u64)?;
    refit::record(&mut p, &nodes, &tris, &mesh_tris, &vals, &levels, n)?;
    p.end_stage("bounds")?;

    let depth = levels.len() as u32 - 1;
    let bvh = GpuBvh::from_buffers(ctx.clone(), [nodes, tris, vals], node_count as usize, n as usize, depth)?
        .with_levels(levels);
    Ok((bvh, p.timings))
}

#[cfg(test)]
mod tests {
    use super::ordered;

    #[test]
    fn ordered_bits_keep_float_order() {
        let xs = [f32::NEG_INFINITY, -3.5, -1e-30, -0.0, 0.0, 1e-40, 2.0, f32::MAX, f32::INFINITY];
        for w in xs.windows(2) {
            assert!(ordered(w[0]) <= ordered(w[1]), "{} {}", w[0], w[1]);
        }
    }
}
