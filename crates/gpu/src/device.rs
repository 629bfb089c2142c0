//! Adapter choice and the device every kernel runs on.

use crate::GpuError;
use std::sync::{Arc, OnceLock};

/// How the kernels compute the triangle test.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Precision {
    /// The engine's f64 watertight test, in the CPU's operation order: hits equal the
    /// CPU's bit for bit where the device rounds as IEEE 754 says ([`Exactness`]).
    F64,
    /// The same test in f32, for adapters without 64-bit floats: the same triangle except
    /// at ties within rounding of an edge, `t` within a few ulps (docs/gpu.md).
    F32,
}

impl Precision {
    /// `f64` or `f32`.
    pub fn name(self) -> &'static str {
        match self {
            Precision::F64 => "f64",
            Precision::F32 => "f32",
        }
    }
}

/// What the start-up self-check found: whether the device's kernels return the CPU's
/// hits on a fixed set of hard rays (edges, vertices, grazing, far away).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Exactness {
    /// Rays checked.
    pub rays: usize,
    /// Rays whose hit differs from the CPU's in triangle or `t` bits.
    pub mismatches: usize,
}

impl Exactness {
    /// True when every checked ray matched.
    pub fn is_exact(&self) -> bool {
        self.mismatches == 0
    }
}

/// Which adapter to open and how.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct GpuOptions {
    /// A case-insensitive substring of the adapter's name (`--gpu-adapter`); `None` reads
    /// `DYNRAY_GPU_ADAPTER`, and without it the most capable adapter is chosen (discrete,
    /// then integrated, then virtual, then software).
    pub adapter: Option<String>,
    /// Use the f32 kernels even where the adapter has 64-bit floats (`DYNRAY_GPU_F32=1`
    /// sets it too): to measure or test the f32 path.
    pub force_f32: bool,
}

/// One adapter, as `dynray info --gpu` lists it.
#[derive(Clone, Debug)]
pub struct AdapterSummary {
    /// Device name.
    pub name: String,
    /// Backend (Vulkan).
    pub backend: String,
    /// Discrete, integrated, virtual or CPU.
    pub device_type: String,
    /// Driver name and version.
    pub driver: String,
    /// 64-bit floats in shaders.
    pub f64: bool,
    /// Subgroup operations.
    pub subgroups: bool,
    /// Timestamp queries (per-stage GPU timings).
    pub timestamps: bool,
    /// Largest storage-buffer binding, bytes.
    pub max_storage_binding: u64,
    /// Largest buffer, bytes.
    pub max_buffer: u64,
    /// Most invocations in one workgroup.
    pub max_workgroup_invocations: u32,
    /// Subgroup sizes the adapter reports (min, max).
    pub subgroup_sizes: (u32, u32),
}

impl AdapterSummary {
    fn of(adapter: &wgpu::Adapter) -> Self {
        let info = adapter.get_info();
        let f = adapter.features();
        let l = adapter.limits();
        let driver = [info.driver.as_str(), info.driver_info.as_str()]
            .iter()
            .filter(|s| !s.is_empty())
            .copied()
            .collect::<Vec<_>>()
            .join(" ");
        Self {
            name: info.name.clone(),
            backend: format!("{:?}", info.backend),
            device_type: match info.device_type {
                wgpu::DeviceType::DiscreteGpu => "discrete GPU",
                wgpu::DeviceType::IntegratedGpu => "integrated GPU",
                wgpu::DeviceType::VirtualGpu => "virtual GPU",
                wgpu::DeviceType::Cpu => "CPU (software)",
                wgpu::DeviceType::Other => "other",
            }
            .to_string(),
            driver,
            f64: f.contains(wgpu::Features::SHADER_F64),
            subgroups: f.contains(wgpu::Features::SUBGROUP),
            timestamps: f.contains(wgpu::Features::TIMESTAMP_QUERY),
            max_storage_binding: l.max_storage_buffer_binding_size,
            max_buffer: l.max_buffer_size,
            max_workgroup_invocations: l.max_compute_invocations_per_workgroup,
            subgroup_sizes: (info.subgroup_min_size, info.subgroup_max_size),
        }
    }

    fn rank(&self) -> u32 {
        match self.device_type.as_str() {
            "discrete GPU" => 0,
            "integrated GPU" => 1,
            "virtual GPU" => 2,
            "CPU (software)" => 3,
            _ => 4,
        }
    }
}

fn instance() -> wgpu::Instance {
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
    desc.backends = wgpu::Backends::VULKAN;
    wgpu::Instance::new(desc)
}

/// Every Vulkan adapter of this machine (empty without a driver or loader).
pub fn list_adapters() -> Vec<AdapterSummary> {
    let inst = instance();
    pollster::block_on(inst.enumerate_adapters(wgpu::Backends::VULKAN)).iter().map(AdapterSummary::of).collect()
}

/// An open device: what every upload and kernel of this crate goes through.
pub struct GpuContext {
    adapter: wgpu::Adapter,
    pub(crate) device: wgpu::Device,
    pub(crate) queue: wgpu::Queue,
    summary: AdapterSummary,
    precision: Precision,
    timestamps: bool,
    pub(crate) kernels: crate::bvh::KernelCache,
    pub(crate) builders: crate::build::BuildKernels,
    exactness: OnceLock<Exactness>,
}

impl std::fmt::Debug for GpuContext {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GpuContext").field("adapter", &self.summary.name).field("precision", &self.precision).finish()
    }
}

impl GpuContext {
    /// Opens the adapter `options` names (or the best one) with the features the kernels
    /// use where it has them.
    pub fn new(options: &GpuOptions) -> Result<Self, GpuError> {
        Self::open(&instance(), options, None)
    }

    /// [`Self::new`] among the adapters of `instance` that can present to `surface`: the
    /// device a window and the GPU backend share, so the backend's image reaches the
    /// window without leaving the device ([`crate::DeviceImage`]).
    pub fn for_surface(
        instance: &wgpu::Instance,
        surface: &wgpu::Surface<'_>,
        options: &GpuOptions,
    ) -> Result<Self, GpuError> {
        Self::open(instance, options, Some(surface))
    }

    fn open(
        inst: &wgpu::Instance,
        options: &GpuOptions,
        surface: Option<&wgpu::Surface<'_>>,
    ) -> Result<Self, GpuError> {
        let mut adapters = pollster::block_on(inst.enumerate_adapters(wgpu::Backends::VULKAN));
        if let Some(surface) = surface {
            adapters.retain(|a| a.is_surface_supported(surface));
        }
        if adapters.is_empty() {
            return Err(GpuError::NoAdapter);
        }
        let (wanted, source_of_name) = match &options.adapter {
            Some(a) => (Some(a.clone()), "--gpu-adapter"),
            None => (std::env::var("DYNRAY_GPU_ADAPTER").ok().filter(|s| !s.is_empty()), "DYNRAY_GPU_ADAPTER"),
        };
        let mut candidates: Vec<(AdapterSummary, wgpu::Adapter)> =
            adapters.into_iter().map(|a| (AdapterSummary::of(&a), a)).collect();
        if let Some(w) = &wanted {
            let available = candidates.iter().map(|(s, _)| s.name.clone()).collect::<Vec<_>>().join(", ");
            candidates.retain(|(s, _)| s.name.to_lowercase().contains(&w.to_lowercase()));
            if candidates.is_empty() {
                return Err(GpuError::NoMatchingAdapter { wanted: w.clone(), source_of_name, available });
            }
        }
        // Stable: among equals, the driver's order.
        candidates.sort_by_key(|(s, _)| s.rank());
        let (summary, adapter) = candidates.swap_remove(0);
        let af = adapter.features();
        let mut features = wgpu::Features::empty();
        for f in [wgpu::Features::SHADER_F64, wgpu::Features::TIMESTAMP_QUERY, wgpu::Features::SUBGROUP] {
            if af.contains(f) {
                features |= f;
            }
        }
        let force_f32 = options.force_f32 || std::env::var("DYNRAY_GPU_F32").is_ok_and(|v| v == "1");
        let precision = if summary.f64 && !force_f32 { Precision::F64 } else { Precision::F32 };
        let desc = wgpu::DeviceDescriptor {
            label: Some("dynray"),
            required_features: features,
            // The adapter's own limits: lavapipe binds 128 MiB per storage buffer where
            // the WebGPU default is 128 MiB too but the buffer limit is 256 MiB; real
            // GPUs allow far more, and a big mesh needs it.
            required_limits: adapter.limits(),
            experimental_features: wgpu::ExperimentalFeatures::disabled(),
            memory_hints: wgpu::MemoryHints::Performance,
            trace: wgpu::Trace::Off,
        };
        let (device, queue) = pollster::block_on(adapter.request_device(&desc))
            .map_err(|e| GpuError::RequestDevice { adapter: summary.name.clone(), message: e.to_string() })?;
        Ok(Self {
            adapter,
            device,
            queue,
            timestamps: features.contains(wgpu::Features::TIMESTAMP_QUERY),
            summary,
            precision,
            kernels: Default::default(),
            builders: Default::default(),
            exactness: OnceLock::new(),
        })
    }

    /// One device per process, opened on first use with [`GpuOptions::default`] (so
    /// `DYNRAY_GPU_ADAPTER` and `DYNRAY_GPU_F32` apply): what tests and the CLI share.
    /// The error is kept too, so a machine without a driver fails fast every time.
    pub fn shared() -> Result<Arc<GpuContext>, GpuError> {
        static SHARED: OnceLock<Result<Arc<GpuContext>, String>> = OnceLock::new();
        SHARED
            .get_or_init(|| GpuContext::new(&GpuOptions::default()).map(Arc::new).map_err(|e| e.to_string()))
            .clone()
            .map_err(|message| GpuError::Device { what: "device", message })
    }

    /// The wgpu adapter (a window asks it what its surface supports).
    pub fn wgpu_adapter(&self) -> &wgpu::Adapter {
        &self.adapter
    }

    /// The device, for a front end that draws with it (the viewer's window).
    pub fn device(&self) -> &wgpu::Device {
        &self.device
    }

    /// The device's queue.
    pub fn queue(&self) -> &wgpu::Queue {
        &self.queue
    }

    /// The adapter opened.
    pub fn adapter(&self) -> &AdapterSummary {
        &self.summary
    }

    /// The precision of the triangle test in every kernel.
    pub fn precision(&self) -> Precision {
        self.precision
    }

    /// True when per-stage timings come from timestamp queries.
    pub fn has_timestamps(&self) -> bool {
        self.timestamps
    }

    /// The start-up self-check (run once, on first call): the BVH kernel against the
    /// CPU's brute force on rays aimed at edges, vertices and far-away triangles.
    pub fn exactness(self: &Arc<Self>) -> &Exactness {
        self.exactness.get_or_init(|| crate::bvh::self_check(self))
    }

    /// The largest storage binding, checked before every upload.
    pub(crate) fn check_binding(&self, what: &'static str, bytes: u64) -> Result<(), GpuError> {
        if bytes > self.summary.max_storage_binding {
            return Err(GpuError::TooLarge {
                what,
                bytes,
                limit: self.summary.max_storage_binding,
                adapter: self.summary.name.clone(),
            });
        }
        Ok(())
    }
}
