//! Bounds of a device-built (breadth-first) tree, bottom-up one level per dispatch
//! (shaders/refit.wgsl), and the refit of such a tree to a new pose of its mesh: the
//! per-frame update of a deforming mesh, with no array leaving the device but the
//! new triangles going up.

use super::kernels::Module;
use super::passes::{BuildTimings, Passes};
use crate::{buffer, GpuBvh, GpuError};
use bytemuck::{Pod, Zeroable};
use dynray_geom::{Triangle, TriangleMesh};

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct RefitParams {
    first: u32,
    count: u32,
    _pad: [u32; 2],
}

/// Records: `tris[i] = mesh_tris[ids[i]]` for the `n` triangles, then every node's box
/// from the deepest level up. `levels[d]` = (first slot, nodes) of depth `d`.
pub(crate) fn record(
    p: &mut Passes<'_>,
    nodes: &wgpu::Buffer,
    tris: &wgpu::Buffer,
    mesh_tris: &wgpu::Buffer,
    ids: &wgpu::Buffer,
    levels: &[[u32; 2]],
    n: u32,
) -> Result<(), GpuError> {
    gather(p, mesh_tris, ids, tris, n)?;
    let k = p.ctx.builders.get(p.ctx, Module::Refit)?;
    for &[first, count] in levels.iter().rev() {
        let params = p.uniform(&RefitParams { first, count, _pad: [0; 2] });
        p.dispatch_items(&k, "refit_level", &[(0, nodes), (1, tris), (2, &params)], count, 64);
    }
    Ok(())
}

/// Records `tris[i] = mesh_tris[ids[i]]` for the `n` triangles (leaf order).
pub(crate) fn gather(
    p: &mut Passes<'_>,
    mesh_tris: &wgpu::Buffer,
    ids: &wgpu::Buffer,
    tris: &wgpu::Buffer,
    n: u32,
) -> Result<(), GpuError> {
    let k = p.ctx.builders.get(p.ctx, Module::Refit)?;
    let all = p.uniform(&RefitParams { first: 0, count: n, _pad: [0; 2] });
    p.dispatch_items(&k, "gather_triangles", &[(2, &all), (3, mesh_tris), (4, ids), (5, tris)], n, 64);
    Ok(())
}

/// The mesh's triangles in its own order, as the builders read them.
pub(crate) fn mesh_triangles(mesh: &TriangleMesh) -> Vec<Triangle> {
    (0..mesh.triangle_count()).map(|i| mesh.triangle(i)).collect()
}

impl GpuBvh {
    /// Refits a tree built on the device ([`GpuBvh::build`] with `sah` or `lbvh`) to
    /// `mesh`, a new pose of the mesh it was built over (same triangles, moved
    /// vertices): uploads the triangles, re-gathers them into leaf order and recomputes
    /// every box level by level. The topology is kept, so hits stay exact (the boxes
    /// are exact unions) while the tree's quality drifts as the mesh deforms.
    pub fn refit(&mut self, mesh: &TriangleMesh) -> Result<BuildTimings, GpuError> {
        if self.levels.is_empty() {
            return Err(GpuError::Unsupported {
                what: "a device refit of a tree built on the CPU (refit it there and `update`)".into(),
            });
        }
        if mesh.triangle_count() != self.triangles {
            return Err(GpuError::Device {
                what: "refit",
                message: format!("the tree has {} triangles, the mesh {}", self.triangles, mesh.triangle_count()),
            });
        }
        mesh.validate().map_err(|e| GpuError::Device { what: "refit", message: e.to_string() })?;
        let ctx = self.ctx.clone();
        let mut p = Passes::new(&ctx);
        let mesh_tris = buffer::storage(&ctx, "mesh triangles", &mesh_triangles(mesh), wgpu::BufferUsages::empty())?;
        p.end_stage("upload")?;
        record(&mut p, &self.nodes, &self.tris, &mesh_tris, &self.ids, &self.levels, self.triangles as u32)?;
        p.end_stage("refit")?;
        Ok(p.timings)
    }
}
