//! BVH builders on the device (docs/gpu.md, "Building on the GPU"): seed 003 §3.8's
//! level-synchronous binned SAH ([`sah`]) and a linear BVH ([`lbvh`]: Morton codes, radix
//! sort, Karras' hierarchy), both writing the node, triangle and id arrays the CPU
//! builder writes, breadth-first, so [`GpuBvh::refit`] recomputes their boxes one level
//! per dispatch. [`GpuBvh::download`] reads a tree back through the CPU validator.

mod kernels;
mod lbvh;
mod passes;
mod radix_sort;
mod refit;
mod sah;
mod scan;

pub(crate) use kernels::BuildKernels;
pub use passes::BuildTimings;

use crate::{buffer, GpuBvh, GpuContext, GpuError};
use dynray_accel::{Bvh, BvhParams};
use dynray_geom::TriangleMesh;
use passes::Passes;
use std::sync::Arc;

/// Where the device's BVH is built (`--gpu-build`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum GpuBuild {
    /// On the CPU ([`Bvh::build`], parallel binned SAH), then uploaded.
    #[default]
    Cpu,
    /// Seed 003 §3.8's binned SAH on the device, level by level.
    Sah,
    /// A linear BVH on the device (Morton order, Karras 2012), one triangle per leaf.
    Lbvh,
}

impl GpuBuild {
    /// Every builder, in `--gpu-build`'s order.
    pub const ALL: [GpuBuild; 3] = [GpuBuild::Cpu, GpuBuild::Sah, GpuBuild::Lbvh];

    /// The name `--gpu-build` takes.
    pub fn name(self) -> &'static str {
        match self {
            GpuBuild::Cpu => "cpu",
            GpuBuild::Sah => "sah",
            GpuBuild::Lbvh => "lbvh",
        }
    }
}

impl std::fmt::Display for GpuBuild {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for GpuBuild {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        GpuBuild::ALL.into_iter().find(|b| b.name() == s).ok_or_else(|| {
            let names: Vec<_> = GpuBuild::ALL.iter().map(|b| b.name()).collect();
            format!("unknown GPU builder `{s}` (expected one of: {})", names.join(", "))
        })
    }
}

impl GpuBvh {
    /// Builds a BVH over `mesh` for the device with `how`, timing each stage (for `cpu`:
    /// the CPU build and the upload). `params` are the CPU builder's; the device SAH
    /// builder uses their leaf rules and SAH constants with 32 bins (seed 003), the LBVH
    /// only records them. Errors name the mesh problem or the device's.
    pub fn build(
        ctx: Arc<GpuContext>,
        mesh: &TriangleMesh,
        how: GpuBuild,
        params: &BvhParams,
    ) -> Result<(GpuBvh, BuildTimings), GpuError> {
        let invalid = |message: String| GpuError::Device { what: "BVH build", message };
        if how == GpuBuild::Cpu {
            let mut p = Passes::new(&ctx);
            let bvh = Bvh::build(mesh, params).map_err(|e| invalid(e.to_string()))?;
            p.end_stage("cpu build")?;
            let gpu = GpuBvh::upload(ctx.clone(), &bvh)?;
            p.end_stage("upload")?;
            return Ok((gpu, p.timings));
        }
        mesh.validate().map_err(|e| invalid(e.to_string()))?;
        let n = u32::try_from(mesh.triangle_count())
            .ok()
            .filter(|n| (1..1 << 31).contains(n))
            .ok_or_else(|| invalid(format!("{} triangles (1 to 2^31 − 1 build)", mesh.triangle_count())))?;
        let mut p = Passes::new(&ctx);
        let tris = refit::mesh_triangles(mesh);
        let mesh_tris = buffer::storage(&ctx, "mesh triangles", &tris, wgpu::BufferUsages::empty())?;
        match how {
            GpuBuild::Lbvh => {
                p.end_stage("upload")?;
                lbvh::build(&ctx, p, mesh_tris, n)
            }
            GpuBuild::Sah => sah::build(&ctx, p, mesh_tris, n, params),
            GpuBuild::Cpu => unreachable!("handled above"),
        }
    }
}
