//! Where the BVH a GPU traces comes from (`--gpu-build`): built on the CPU and uploaded,
//! or built on the device by seed 003 §3.8's level-synchronous binned SAH or by an LBVH
//! (Morton codes, radix sort, Karras 2012 hierarchy). Every way yields the node,
//! triangle and id arrays of [`dynray_accel::Bvh`]'s layout, so one traversal reads them.

use crate::{GpuBvh, GpuContext, GpuError};
use dynray_accel::{Bvh, BvhParams};
use dynray_geom::TriangleMesh;
use std::sync::Arc;
use std::time::Instant;

/// A way to build the device's BVH.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum GpuBuild {
    /// The CPU's binned-SAH builder, then an upload.
    #[default]
    Cpu,
    /// Binned SAH on the device, one level of the tree per pass.
    Sah,
    /// Linear BVH on the device: Morton codes, radix sort, Karras hierarchy, refit.
    Lbvh,
}

impl GpuBuild {
    /// All ways, in the order listings show them.
    pub const ALL: &'static [GpuBuild] = &[GpuBuild::Cpu, GpuBuild::Sah, GpuBuild::Lbvh];

    /// The names of [`Self::ALL`], for command-line value lists.
    pub const NAMES: &'static [&'static str] = &["cpu", "sah", "lbvh"];

    /// The `--gpu-build` spelling.
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

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .iter()
            .copied()
            .find(|b| b.name() == s)
            .ok_or_else(|| format!("unknown GPU build `{s}` (expected one of {})", Self::NAMES.join(", ")))
    }
}

/// Seconds per stage of one build.
#[derive(Clone, Debug, Default)]
pub struct BuildTimings {
    /// Named stages in the order they ran (device time from timestamp queries where the
    /// adapter has them, else wall clock), e.g. `("cpu build", …)`, `("upload", …)`.
    pub stages: Vec<(&'static str, f64)>,
    /// The whole build, wall clock, until the tree is ready to trace.
    pub total: f64,
    /// True when the device stages come from timestamp queries.
    pub from_timestamps: bool,
}

impl GpuBvh {
    /// Builds a BVH over `mesh` the way `how` says, ready to trace on `ctx`'s device.
    /// `params` are the CPU builder's; the device builders read the ones that apply to
    /// them (leaf size, SAH costs).
    pub fn build(
        ctx: Arc<GpuContext>,
        mesh: &TriangleMesh,
        how: GpuBuild,
        params: &BvhParams,
    ) -> Result<(Self, BuildTimings), GpuError> {
        let start = Instant::now();
        match how {
            GpuBuild::Cpu => {
                let bvh = Bvh::build(mesh, params).map_err(|e| GpuError::Build { message: e.to_string() })?;
                let built = start.elapsed().as_secs_f64();
                let gpu = Self::upload(ctx, &bvh)?;
                crate::buffer::wait(gpu.context())?;
                let total = start.elapsed().as_secs_f64();
                let stages = vec![("cpu build", built), ("upload", total - built)];
                Ok((gpu, BuildTimings { stages, total, from_timestamps: false }))
            }
            GpuBuild::Sah | GpuBuild::Lbvh => Err(GpuError::Unsupported { what: format!("--gpu-build {how} yet") }),
        }
    }
}
