//! The GPU backend of dynray (docs/gpu.md): a wgpu device on Vulkan, WGSL kernels in
//! `shaders/`, structures uploaded as the same Pod buffers the CPU traverses.
//!
//! - [`GpuContext`] chooses an adapter (`DYNRAY_GPU_ADAPTER`) and opens a device with
//!   the features the kernels use (64-bit floats, timestamps) where the adapter has them.
//! - [`GpuBvh`] is a BVH on the device; it implements [`dynray_accel::BatchQuery`], so
//!   `trace-rays`, the bench and the renderer trace through it as through a CPU structure.
//!   [`GpuBvh::build`] builds it on the device ([`GpuBuild`]: seed 003's binned SAH or an
//!   LBVH) and [`GpuBvh::refit`] refits it there to a new pose of its mesh.
//!
//! - [`GpuAdf`] is seed 001's distance field on the device (`shaders/adf.wgsl`): point
//!   location through the perfect hash and sphere tracing, the CPU's code ported.
//!
//! Exactness: where the adapter has `SHADER_F64`, the kernels run the engine's f64
//! watertight test in the CPU's operation order, and [`GpuContext::exactness`] checks at
//! start-up that the device rounds as the CPU does; hits then equal brute force's bit for
//! bit. Without f64 the kernels run the same test in f32 ([`Precision::F32`]).

mod adf;
mod adf_aov;
mod backend;
mod buffer;
mod build;
mod bvh;
mod device;
mod error;
mod kernel;
mod render;
mod shader;

pub use adf::{GpuAdf, GpuMarch};
pub use adf_aov::DeviceFieldAov;
pub use backend::Backend;
pub use build::{BuildTimings, GpuBuild};
pub use bvh::GpuBvh;
pub use device::{list_adapters, AdapterSummary, Exactness, GpuContext, GpuOptions, Precision};
pub use error::{GpuError, SOFTWARE_DRIVER_HINT};
pub use render::{DeviceImage, GpuIntegrator, GpuRender, GpuRenderOptions, GpuRenderer, GpuStrategy, StageTimings};
