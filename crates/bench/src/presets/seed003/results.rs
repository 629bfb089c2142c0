//! What `--preset seed003` writes under `seed003` in report.json: per scene, ray casting
//! and Whitted levels, brute force against the accelerated tracer, the sweeps and the GPU
//! strategies.

use serde::{Deserialize, Serialize};

/// `--preset seed003`: the Whitted tracer on one thread against the same tracer on every
/// thread (the seed's CPU-vs-GPU speed-up, SP, and efficiency, EF = SP / threads), and
/// single-threaded brute force on scenes small enough for it.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Seed003Result {
    /// Image width used (the seed used 640).
    pub width: u32,
    /// Image height used (the seed used 480).
    pub height: u32,
    /// The accelerated structure.
    pub accel: String,
    /// Threads of the parallel tracer.
    pub threads: usize,
    /// Brute force runs only on scenes with at most this many triangles.
    pub brute_max_triangles: usize,
    /// One entry per scene.
    pub scenes: Vec<Seed003Scene>,
    /// Ray casting against the number of lights and the image size (the seed's Tables 4.3
    /// and 4.4); absent from reports written before it existed.
    #[serde(default)]
    pub sweeps: Option<Seed003Sweeps>,
    /// `--backend gpu`: the adapter of the GPU columns (`null` without it).
    #[serde(default)]
    pub gpu_adapter: Option<String>,
}

/// One scene of the seed003 preset.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Seed003Scene {
    /// Scene name.
    pub name: String,
    /// Triangles.
    pub triangles: usize,
    /// Lights.
    pub lights: usize,
    /// Build time of the structure, median, ms (the seed's Table 4.9 measures the CPU build).
    pub build_ms: f64,
    /// Rows by recursion level 1..=10 (level 1 = ray casting: primary + shadow rays, the
    /// seed's "0 nível" row of Table 4.8).
    pub levels: Vec<Seed003Level>,
    /// `--backend gpu`: the BVH built on 1 thread, median, ms (Table 4.9's CPU column).
    #[serde(default)]
    pub cpu_single_build_ms: Option<f64>,
    /// `--backend gpu`: the device's builds (Table 4.9; empty without it).
    #[serde(default)]
    pub gpu_builds: Vec<Seed003GpuBuild>,
}

/// One recursion level of the seed003 preset (renders with the structure prebuilt,
/// medians of `repeat`).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Seed003Level {
    /// Maximum ray level (1 = primary + shadow rays only).
    pub level: u32,
    /// Rays traced.
    pub rays: u64,
    /// The accelerated tracer on one thread, ms (the seed's CPU column).
    pub accel_single_ms: f64,
    /// The accelerated tracer on every thread, ms (the seed's GPU columns).
    pub accel_parallel_ms: f64,
    /// `accel_single_ms / accel_parallel_ms` (the seed's SP).
    pub speedup: f64,
    /// `speedup / threads` (the seed's EF).
    pub efficiency: f64,
    /// Brute force on one thread, ms (`null` above `brute_max_triangles`).
    pub brute_single_ms: Option<f64>,
    /// `brute_single_ms / accel_parallel_ms`: structure and threads together.
    pub brute_speedup: Option<f64>,
    /// True when every image of this level is identical pixel for pixel (they must be).
    pub images_identical: bool,
    /// `--backend gpu`: seed 003's three strategies at this level (empty without it).
    #[serde(default)]
    pub gpu: Vec<Seed003GpuRun>,
}

/// The seed003 preset's two ray-casting sweeps, on one scene.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Seed003Sweeps {
    /// Scene name.
    pub scene: String,
    /// One point per light count, at the preset's image size.
    pub lights: Vec<Seed003Point>,
    /// One point per (square) image size.
    pub resolution: Vec<Seed003Point>,
}

/// One ray-casting render of a sweep, on 1 thread and on every thread (medians).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Seed003Point {
    /// Lights in the scene.
    pub lights: usize,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Rays traced (primary + shadow).
    pub rays: u64,
    /// 1 thread, ms.
    pub single_ms: f64,
    /// Every thread, ms.
    pub parallel_ms: f64,
    /// `single_ms / parallel_ms`.
    pub speedup: f64,
    /// `speedup / threads`.
    pub efficiency: f64,
    /// The two images are identical pixel for pixel (they must be).
    pub images_identical: bool,
    /// `--backend gpu`: the three strategies on the same image (empty without it).
    #[serde(default)]
    pub gpu: Vec<Seed003GpuRun>,
}

/// One GPU strategy rendering one seed003 image (medians of `repeat` after a warm-up).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Seed003GpuRun {
    /// `wavefront` (the seed's Alg. 1), `megakernel` (Alg. 2) or `hybrid` (Alg. 3).
    pub strategy: String,
    /// Render time on the device, ms: the kernels and the read-back of the image, without
    /// the frame's upload (the seed times rendering with the tree already there).
    pub ms: f64,
    /// Rays traced (primary + shadow + secondary).
    pub rays: u64,
    /// The 1-thread CPU time over this one (the seed's SP = T_CPU / T_GPU).
    pub speedup: f64,
    /// Largest channel difference from the CPU's image of the same level.
    pub max_abs_diff: f64,
    /// Pixels whose largest channel difference from the CPU's image is over 1e-3.
    pub pixels_over_1e3: usize,
    /// True when at most 1 % of the pixels differ by over 1e-3 (f32 shading on both sides
    /// in another order; grazing rays may take another path): otherwise a mismatch.
    pub images_agree: bool,
}

/// One BVH build of seed003's Table 4.9 (median of `repeat` after a warm-up).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Seed003GpuBuild {
    /// `cpu` (the CPU's binned SAH on every thread, then uploaded), `sah` (seed 003 §3.8
    /// on the device) or `lbvh`.
    pub build: String,
    /// Build time, ms (upload of the triangles included).
    pub ms: f64,
    /// The 1-thread CPU build's time over this one (the seed's "aceleração").
    pub cpu_over_this: f64,
    /// Nodes of the tree.
    pub nodes: usize,
    /// SAH cost of the tree (the CPU builder's cost model).
    pub sah_cost: Option<f64>,
    /// The last build's stages, ms.
    pub stages: Vec<(String, f64)>,
}
