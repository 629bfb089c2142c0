//! Where a job traces: the CPU, or the GPU with an adapter and a place to build its BVH
//! (docs/gpu.md). Plain options, filled by each front end.

use anyhow::{bail, Result};
use dynray_gpu::{GpuBuild, GpuOptions};

/// The backend of a job.
#[derive(Clone, Debug, Default)]
pub struct BackendChoice {
    /// `Some`: trace on the GPU with the adapter these options choose; `None`: the CPU.
    pub gpu: Option<GpuOptions>,
    /// Where the GPU's BVH is built (`cpu`, then uploaded; `sah` or `lbvh` on the device).
    pub gpu_build: GpuBuild,
}

impl BackendChoice {
    /// The CPU.
    pub fn cpu() -> Self {
        Self::default()
    }

    /// Refuses GPU-only options without the GPU.
    pub fn check(&self) -> Result<()> {
        if self.gpu.is_none() && self.gpu_build != GpuBuild::Cpu {
            bail!("--gpu-build {} builds for the GPU: add --backend gpu", self.gpu_build);
        }
        Ok(())
    }

    /// True on the GPU.
    pub fn is_gpu(&self) -> bool {
        self.gpu.is_some()
    }
}
