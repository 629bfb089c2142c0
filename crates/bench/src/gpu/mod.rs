//! `--backend gpu` (docs/bench.md, "On the GPU"): one device opened for the whole run,
//! the GPU backend measured on the standard run's rays ([`standard`]) and seed 003's
//! strategies and builders timed against the CPU (`presets::seed003::strategies`).

pub mod standard;

use crate::config::GpuBench;
use anyhow::{Context, Result};
use dynray_accel::{AccelKind, AccelSpec, BvhParams};
use dynray_gpu::{GpuBuild, GpuContext, GpuRenderer, Precision};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The adapter of a `--backend gpu` run.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct GpuInfo {
    /// Device name.
    pub adapter: String,
    /// Graphics API (Vulkan).
    pub backend: String,
    /// Discrete, integrated, virtual or CPU (software).
    pub device_type: String,
    /// Driver name and version.
    pub driver: String,
    /// `f64` (hits equal brute force's bit for bit) or `f32` (docs/gpu.md's rule).
    pub precision: String,
    /// True for a software device (lavapipe): a CPU emulating a GPU, whose figures rank
    /// the strategies but are no GPU's speed.
    pub software: bool,
    /// Where the standard run's device tree was built: `cpu` (built there, uploaded),
    /// `sah` or `lbvh`.
    pub build: String,
    /// Per-stage GPU times come from timestamp queries (false: wall clock per stage).
    pub timestamps: bool,
}

/// The device of a `--backend gpu` run, with one renderer (its kernels compiled once).
pub struct GpuSession {
    /// The device.
    pub ctx: Arc<GpuContext>,
    /// Renders frames on it, uploading only what changed since the last one.
    pub renderer: GpuRenderer,
    /// Where the standard run builds its device tree.
    pub build: GpuBuild,
}

impl GpuSession {
    /// Opens the adapter `bench` names (or the most capable one); the error names the
    /// package to install when there is none.
    pub fn open(bench: &GpuBench) -> Result<Self> {
        let ctx = Arc::new(GpuContext::new(&bench.options).context("--backend gpu")?);
        let renderer = GpuRenderer::new(ctx.clone()).context("--backend gpu: cannot create the renderer")?;
        Ok(Self { ctx, renderer, build: bench.build })
    }

    /// What the report says of the adapter.
    pub fn info(&self) -> GpuInfo {
        let a = self.ctx.adapter();
        GpuInfo {
            adapter: a.name.clone(),
            backend: a.backend.clone(),
            device_type: a.device_type.clone(),
            driver: a.driver.clone(),
            precision: self.ctx.precision().name().to_string(),
            software: self.is_software(),
            build: self.build.name().to_string(),
            timestamps: self.ctx.has_timestamps(),
        }
    }

    /// A software device (lavapipe) runs the kernels on the CPU's cores.
    pub fn is_software(&self) -> bool {
        self.ctx.adapter().device_type == "CPU (software)"
    }

    /// The notes a reader needs beside the GPU figures.
    pub fn notes(&self) -> Vec<String> {
        let a = self.ctx.adapter();
        let mut notes = Vec::new();
        if self.is_software() {
            notes.push(format!(
                "gpu: measured on {} ({}), a software Vulkan device: a CPU emulating a GPU on this machine's \
                 cores. Its figures rank the strategies and builders against each other; they are no GPU's speed.",
                a.name, a.driver
            ));
        }
        if self.ctx.precision() == Precision::F32 {
            notes.push(
                "gpu: the adapter has no 64-bit floats: the kernels run the f32 test, whose hits may differ from \
                 brute force's at edges (docs/gpu.md); disagreements are still reported."
                    .into(),
            );
        }
        notes
    }
}

/// The structures of `accels` the GPU measures: the binary trees (`bvh2…`) asked for, or,
/// with none, each plain `bvh` (on the GPU, the binary tree with its defaults: see
/// [`AccelSpec::binary_bvh_params`]), so that the default list measures one GPU tree.
pub fn gpu_specs(accels: &[AccelSpec]) -> Vec<&AccelSpec> {
    let binary: Vec<&AccelSpec> = accels.iter().filter(|v| v.kind == AccelKind::Bvh2).collect();
    if !binary.is_empty() {
        return binary;
    }
    accels.iter().filter(|v| v.binary_bvh_params().is_ok()).collect()
}

/// The BVH the GPU traces for `spec`: its own parameters when `spec` is a BVH, the
/// default BVH otherwise (the GPU kernels traverse the binary tree, `bvh2`).
pub fn bvh_params(spec: &AccelSpec) -> Result<BvhParams> {
    if spec.kind == AccelKind::Bvh2 {
        spec.read().with_context(|| format!("cannot read the parameters of {spec}"))
    } else {
        Ok(BvhParams::default())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn specs(list: &str) -> Vec<AccelSpec> {
        crate::parse_accels(list).unwrap()
    }

    fn names(list: &str) -> Vec<String> {
        gpu_specs(&specs(list)).iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn the_gpu_measures_the_binary_trees_asked_for_else_plain_bvh() {
        assert_eq!(names("bvh,bih"), ["bvh"]);
        assert_eq!(names("bvh,bvh2:bins=8,bih"), ["bvh2:bins=8"]);
        // The wide tree's parameters do not describe a binary tree: nothing to measure.
        assert!(names("bvh:width=4,bih").is_empty());
        assert!(names("bih,kdtree").is_empty());
        assert_eq!(bvh_params(&specs("bvh")[0]).unwrap(), BvhParams::default());
    }
}
