//! Seed 003's three GPU tracing strategies (§3.10–3.12) over the frame's BVH, shading
//! exactly as the CPU Whitted integrator (shaders/whitted_shade.wgsl), returning the CPU
//! renderer's [`Film`]: wavefront, megakernel and hybrid (docs/gpu.md). The wavefront
//! also runs seed 004's cumulative integrator, choosing the CPU's children, and the
//! physically based path tracer (shaders/path_shade.wgsl) ([`GpuIntegrator`]).

mod compact;
mod device_image;
mod frame_upload;
mod hybrid;
mod megakernel;
mod wavefront;
mod work;

pub use device_image::DeviceImage;

use crate::{buffer, GpuBvh, GpuContext, GpuError};
use dynray_accel::Bvh;
use dynray_render::{Film, RenderStats};
use dynray_scene::{Color, Frame};
use std::collections::HashMap;
use std::sync::Arc;
use std::time::Instant;
use work::{Kernels, Placeholders, Recorder};

/// Samples per batch: keeps every queue under lavapipe's 128 MiB binding limit.
const BATCH: u32 = 1 << 18;

/// How the GPU traces a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GpuStrategy {
    /// Multi-kernel wavefront with prefix-sum compaction per bounce.
    Wavefront,
    /// One invocation per pixel sample with a private ray stack.
    Megakernel,
    /// Primary rays compacted once, then the megakernel on the survivors.
    Hybrid,
}

impl GpuStrategy {
    /// The names `--gpu-strategy` accepts.
    pub const NAMES: [&'static str; 3] = ["wavefront", "megakernel", "hybrid"];

    /// Its name.
    pub fn name(self) -> &'static str {
        match self {
            GpuStrategy::Wavefront => "wavefront",
            GpuStrategy::Megakernel => "megakernel",
            GpuStrategy::Hybrid => "hybrid",
        }
    }
}

impl std::str::FromStr for GpuStrategy {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "wavefront" => Ok(GpuStrategy::Wavefront),
            "megakernel" => Ok(GpuStrategy::Megakernel),
            "hybrid" => Ok(GpuStrategy::Hybrid),
            _ => Err(format!("unknown GPU strategy `{s}` (wavefront, megakernel, hybrid)")),
        }
    }
}

impl std::fmt::Display for GpuStrategy {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Which integrator the GPU runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GpuIntegrator {
    /// The CPU Whitted integrator's image (every strategy).
    Whitted,
    /// Seed 004's cumulative integrator with branch depth `K` (the CPU's
    /// `--integrator cumulative`, wavefront strategy only).
    Cumulative {
        /// Hits of rays of level ≤ K expand both children.
        branch_depth: u32,
    },
    /// The physically based path tracer (the CPU's `--integrator path`: NEE, MIS,
    /// Russian roulette; wavefront strategy only), converging to the CPU's image.
    Path,
}

impl GpuIntegrator {
    /// Its name, as `--integrator` spells it.
    pub fn name(self) -> &'static str {
        match self {
            GpuIntegrator::Whitted => "whitted",
            GpuIntegrator::Cumulative { .. } => "cumulative",
            GpuIntegrator::Path => "path",
        }
    }
}

/// What to render.
#[derive(Clone, Copy, Debug)]
pub struct GpuRenderOptions {
    /// The strategy.
    pub strategy: GpuStrategy,
    /// Samples per pixel (the CPU sampler's positions).
    pub spp: u32,
    /// Seed of the sample positions (and of the cumulative and path integrators'
    /// random numbers).
    pub seed: u64,
    /// The integrator.
    pub integrator: GpuIntegrator,
    /// Passes of `spp` samples accumulated into the film, as the CPU render loop's
    /// (pass `p` uses sample indices `p · spp ..`); at least 1.
    pub passes: u32,
}

impl GpuRenderOptions {
    /// Whitted's integrator, one pass.
    pub fn whitted(strategy: GpuStrategy, spp: u32, seed: u64) -> Self {
        Self { strategy, spp, seed, integrator: GpuIntegrator::Whitted, passes: 1 }
    }

    /// The path tracer (wavefront strategy), one pass.
    pub fn path(spp: u32, seed: u64) -> Self {
        Self { strategy: GpuStrategy::Wavefront, spp, seed, integrator: GpuIntegrator::Path, passes: 1 }
    }
}

/// Seconds per stage of one render.
#[derive(Clone, Copy, Debug, Default)]
pub struct StageTimings {
    /// Camera-ray generation.
    pub generate: f64,
    /// Closest-hit tracing.
    pub trace: f64,
    /// Prefix-sum compaction and gathers.
    pub compact: f64,
    /// Shading with shadow rays, accumulation.
    pub shade: f64,
    /// The megakernel (trace and shade fused).
    pub fused: f64,
    /// Frame upload (host side).
    pub upload: f64,
    /// The whole render, wall clock.
    pub total: f64,
    /// True when the stages come from timestamp queries, false for wall clock.
    pub from_timestamps: bool,
}

/// One GPU render.
#[derive(Clone, Debug)]
pub struct GpuRender {
    /// The image, as the CPU renderer returns it; empty (0 × 0) when the renderer
    /// resolved it into its target on the device ([`GpuRenderer::set_target`]).
    pub film: Film,
    /// Rays traced.
    pub stats: RenderStats,
    /// Per-stage time.
    pub timings: StageTimings,
    /// Bytes written to the device for this frame (0 when nothing changed).
    pub uploaded_bytes: u64,
}

/// What one batch's kernels share.
pub(crate) struct Batch<'a> {
    ctx: &'a GpuContext,
    kernels: &'a Kernels,
    placeholders: &'a Placeholders,
    scene: &'a wgpu::BindGroup,
    counters: &'a wgpu::Buffer,
}

/// Renders frames on one device, keeping the last frame's arrays to upload only changes.
pub struct GpuRenderer {
    ctx: Arc<GpuContext>,
    upload: frame_upload::FrameUpload,
    kernels: HashMap<(u32, u32), Arc<Kernels>>,
    placeholders: Placeholders,
    /// Where renders resolve on the device instead of being read back
    /// ([`Self::set_target`]).
    target: Option<Arc<DeviceImage>>,
}

impl std::fmt::Debug for GpuRenderer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GpuRenderer").finish_non_exhaustive()
    }
}

impl GpuRenderer {
    /// A renderer on `ctx`.
    pub fn new(ctx: Arc<GpuContext>) -> Result<Self, GpuError> {
        let placeholders = Placeholders::new(&ctx)?;
        Ok(Self {
            upload: frame_upload::FrameUpload::new(ctx.clone()),
            ctx,
            kernels: HashMap::new(),
            placeholders,
            target: None,
        })
    }

    /// Renders of the target's size add their samples into `target` on the device (sums
    /// in sample order, then sRGB RGBA rows a window copies), and return an empty film
    /// instead of reading the samples back; `None` reads back again. The target must be on
    /// this renderer's device.
    pub fn set_target(&mut self, target: Option<Arc<DeviceImage>>) {
        self.target = target;
    }

    fn kernels(&mut self, stack: u32, ray_stack: u32) -> Result<Arc<Kernels>, GpuError> {
        if let Some(k) = self.kernels.get(&(stack, ray_stack)) {
            return Ok(k.clone());
        }
        let k = Arc::new(Kernels::new(&self.ctx, stack, ray_stack)?);
        self.kernels.insert((stack, ray_stack), k.clone());
        Ok(k)
    }

    /// The indices of the set flags, in order, by the device's prefix-sum compaction
    /// (what the wavefront and hybrid strategies run): exposed for tests.
    pub fn compact(&mut self, flags: &[u32]) -> Result<Vec<u32>, GpuError> {
        let k = self.kernels(32, 4)?;
        compact::compact_on_device(&self.ctx, &k, flags)
    }

    /// Renders `frame` (size, camera, limits from its settings) traced through `bvh`,
    /// built on `frame.mesh`, with the integrator `options` name (the CPU Whitted
    /// integrator's shading, the cumulative tracer's or the path tracer's).
    pub fn render(&mut self, frame: &Frame, bvh: &Bvh, options: &GpuRenderOptions) -> Result<GpuRender, GpuError> {
        self.render_tree(frame, frame_upload::Tree::Host(bvh), options)
    }

    /// [`Self::render`] through a tree built on the device over `frame.mesh`
    /// ([`GpuBvh::build`] with `sah` or `lbvh`, or refitted there): nothing of the tree
    /// is uploaded.
    pub fn render_device_tree(
        &mut self,
        frame: &Frame,
        bvh: GpuBvh,
        options: &GpuRenderOptions,
    ) -> Result<GpuRender, GpuError> {
        self.render_tree(frame, frame_upload::Tree::Device(bvh), options)
    }

    /// The tree of the last render, on the device: refit it there
    /// ([`GpuBvh::refit`]) to a new pose, then render that pose with
    /// [`Self::render_kept_tree`]. `None` before the first render.
    pub fn tree_mut(&mut self) -> Option<&mut GpuBvh> {
        self.upload.bvh_mut()
    }

    /// [`Self::render`] through the tree already on the device (the last render's,
    /// perhaps refitted since): the per-frame path of an animation whose tree stays on
    /// the device. An error before any tree was given.
    pub fn render_kept_tree(&mut self, frame: &Frame, options: &GpuRenderOptions) -> Result<GpuRender, GpuError> {
        self.render_tree(frame, frame_upload::Tree::Kept, options)
    }

    fn render_tree(
        &mut self,
        frame: &Frame,
        tree: frame_upload::Tree<'_>,
        options: &GpuRenderOptions,
    ) -> Result<GpuRender, GpuError> {
        let path = options.integrator == GpuIntegrator::Path;
        frame_upload::check_supported(frame, path)?;
        if options.integrator != GpuIntegrator::Whitted && options.strategy != GpuStrategy::Wavefront {
            return Err(GpuError::Unsupported {
                what: format!(
                    "the {} integrator with the {} strategy (its kernel is the wavefront's: \
                     --gpu-strategy wavefront)",
                    options.integrator.name(),
                    options.strategy
                ),
            });
        }
        let passes = options.passes.max(1);
        let spp = options.spp.max(1);
        if spp.checked_mul(passes).is_none() {
            return Err(GpuError::Unsupported {
                what: format!("{passes} passes of {spp} samples (over 2^32 samples)"),
            });
        }
        let t0 = Instant::now();
        let uploaded_bytes = self.upload.sync(frame, tree, options.spp, options.seed, path)?;
        let upload = t0.elapsed().as_secs_f64();
        let params = self.upload.params().expect("synced");
        let stack = self.upload.bvh().expect("synced").stack();
        let kernels = self.kernels(stack, params.max_level + 2)?;
        let scene = self.upload.group(&kernels);
        let ctx = self.ctx.clone();
        let counters = buffer::output(&ctx, "ray counters", 16)?;
        ctx.queue.write_buffer(&counters, 0, &[0u8; 16]);
        let total = self.upload.samples;
        let batch = Batch {
            ctx: &ctx,
            kernels: &kernels,
            placeholders: &self.placeholders,
            scene: &scene,
            counters: &counters,
        };
        let mut rec = Recorder::new(&ctx);
        let (w, h) = (frame.settings.width, frame.settings.height);
        // Resolved on the device when the target has this frame's size.
        let target = self.target.clone().filter(|t| (t.width(), t.height()) == (w, h));
        let mut colors: Vec<[f32; 4]> = vec![[0.0; 4]; if target.is_some() { 0 } else { total as usize }];
        let (mut secondary, mut shadow) = (0u64, 0u64);
        let mut uploaded_bytes = uploaded_bytes;
        let mode = match options.integrator {
            // Whitted's wavefront is the cumulative one expanding every hit.
            GpuIntegrator::Whitted => wavefront::Mode::Tree { branch_depth: u32::MAX },
            GpuIntegrator::Cumulative { branch_depth } => wavefront::Mode::Tree { branch_depth },
            GpuIntegrator::Path => wavefront::Mode::Path,
        };
        let mut film = Film::new(w, h);
        for pass in 0..passes {
            if pass > 0 {
                // Fresh choices per pass, the same sample positions (the CPU's rule).
                uploaded_bytes += self.upload.sync_keys(pass * spp)?;
            }
            let mut base = 0u32;
            while base < total {
                let n = BATCH.min(total - base);
                let film = buffer::output(&ctx, "sample radiance", 16 * n as u64)?;
                secondary += match options.strategy {
                    GpuStrategy::Wavefront => wavefront::render(&batch, &mut rec, base, n, &film, mode)?,
                    GpuStrategy::Megakernel => megakernel::render(&batch, &mut rec, base, n, &film)?,
                    GpuStrategy::Hybrid => hybrid::render(&batch, &mut rec, base, n, &film)?,
                };
                match &target {
                    Some(t) => t.accumulate(rec.encoder(), &film, spp, base, n),
                    None => rec.read(&film, &mut colors[base as usize..(base + n) as usize])?,
                }
                base += n;
            }
            if target.is_some() {
                // Read the counters below; the samples stay on the device.
            } else {
                for (p, samples) in colors.chunks(spp as usize).enumerate() {
                    // Summed in sample order, and passes one after the other, as the CPU
                    // render loop does.
                    let mut sum = Color::ZERO;
                    for s in samples {
                        sum += Color::new(s[0], s[1], s[2]);
                    }
                    film.add_sum(p as u32 % w.max(1), p as u32 / w.max(1), sum, spp as f32);
                }
            }
            // The device counts in u32: read and reset per pass so passes cannot wrap it.
            let mut c = [0u32; 4];
            rec.read(&counters, &mut c)?;
            ctx.queue.write_buffer(&counters, 0, &[0u8; 16]);
            shadow += c[0] as u64;
            secondary += c[1] as u64;
        }
        if let Some(t) = &target {
            t.encode(rec.encoder());
            rec.submit()?;
            film = Film::new(0, 0);
        }
        let s = rec.seconds;
        let stats = RenderStats {
            primary_rays: total as u64 * passes as u64,
            shadow_rays: shadow,
            secondary_rays: secondary,
            tiles: 0,
        };
        let timings = StageTimings {
            generate: s.generate,
            trace: s.trace,
            compact: s.compact,
            shade: s.shade,
            fused: s.fused,
            upload,
            total: t0.elapsed().as_secs_f64(),
            from_timestamps: ctx.has_timestamps(),
        };
        Ok(GpuRender { film, stats, timings, uploaded_bytes })
    }
}
