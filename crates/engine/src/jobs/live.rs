//! The live job: what the viewer (`dynray view`) drives every frame. One [`Live`] holds a
//! scene's frame step and an accumulating image; each [`Live::step`] brings the scene to
//! the chosen time and camera (posing, physics and the structure's update only when they
//! changed) and adds one progressive frame of samples.
//!
//! Progressive sampling on the CPU follows the render job's sample pattern exactly: frame
//! `k` of a still view draws sample `k` of every pixel of the `spp`-sample pattern
//! ([`dynray_render::RenderOptions::pattern`]), so after `spp` frames the image holds the
//! bits `dynray render --spp N` writes for the same job, and later frames add its passes.
//! On the GPU each frame renders all `spp` samples; the first equals the GPU render job's
//! image, and later ones add fresh random streams for integrators that draw them.
//!
//! Any change (time, camera, image size, integrator, structure …) restarts the image.

use crate::backend::BackendChoice;
use crate::fields::Fields;
use crate::frame_step::{FrameStep, Stage};
use crate::jobs::render::{RenderJob, DEFAULT_SPP, MAX_SPP};
use crate::load::Loaded;
use crate::tracer::{gpu_integrator, GpuChoice, Tracer};
use anyhow::{bail, Context, Result};
use dynray_accel::{Accel, UpdatePolicy, UpdateReport};
use dynray_gpu::{DeviceImage, GpuContext};
use dynray_render::{Film, IntegratorKind, IntegratorParams, RenderOptions, RenderStats};
use dynray_scene::{Camera, Frame, Timeline};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// What one [`Live::step`] did and how long each part took.
#[derive(Clone, Copy, Debug, Default)]
pub struct LiveFrame {
    /// The image started afresh (something changed, or the first frame).
    pub restarted: bool,
    /// Posing and simulating (zero when the time did not change).
    pub pose: Duration,
    /// The simulation's part of `pose`.
    pub physics: Duration,
    /// The structure's update, when one ran.
    pub update: Option<UpdateReport>,
    /// Tracing and shading this frame's samples (zero when nothing was rendered).
    pub render: Duration,
    /// Rays this frame traced.
    pub rays: u64,
    /// Samples per pixel the image holds after this frame.
    pub samples: u32,
    /// Nothing was rendered: the image has every sample it will get until a change.
    pub idle: bool,
}

/// A scene traced live: the frame step, the camera and time the front end chose, and the
/// accumulated image.
pub struct Live {
    job: RenderJob,
    policy: UpdatePolicy,
    step: FrameStep,
    fields: Fields,
    /// The camera the user moved to; `None` follows the scene's (possibly animated) one.
    camera: Option<Camera>,
    time: f32,
    /// Fraction of the job's image size rendered (resolution scaling while moving).
    scale: f32,
    pool: Option<rayon::ThreadPool>,
    film: Film,
    samples: u32,
    /// What must happen before the next render.
    dirty: Dirty,
    /// The job's image size, as the last pose set it.
    full_size: (u32, u32),
    /// A device opened by the front end (the viewer's window's), which GPU tracers use.
    gpu_context: Option<Arc<GpuContext>>,
    /// The front end shows the GPU backend's image from the device
    /// ([`Live::present_on_device`]).
    on_device: bool,
    /// The live image on the device, when frames resolve there.
    device_image: Option<Arc<DeviceImage>>,
    /// The last frame was resolved into `device_image` (its film is not read back).
    resolved_on_device: bool,
    /// On the GPU: the job's structure built on the CPU over the current frame, for the
    /// heat map and outlines ([`Live::view_structure`]); dropped at every update.
    view_accel: Option<Box<dyn Accel>>,
    rendered_size: (u32, u32),
}

/// Work the next step owes.
#[derive(Clone, Copy, Debug, Default)]
struct Dirty {
    /// Build the tracer's structure (a new tracer: structure, layout, policy or backend
    /// changed).
    build: bool,
    /// Pose and update (time or frame settings changed).
    pose: bool,
    /// The camera moved (an update for view-dependent structures).
    camera: bool,
    /// Restart the image.
    image: bool,
}

impl Live {
    /// Prepares `loaded` for live tracing under `job` (its output, AOV and passes are not
    /// used: the viewer saves what it shows) with the structures under `policy`. Nothing
    /// is built until the first [`Live::step`].
    pub fn new(mut loaded: Loaded, job: RenderJob, policy: UpdatePolicy) -> Result<Self> {
        let job = RenderJob { output: None, passes: None, ..job };
        check(&job)?;
        if loaded.field.is_some() {
            bail!(
                "{}: a distance-field file alone is shown by `dynray render`; place it in a scene's `adf` block to view it live",
                loaded.label
            );
        }
        loaded.shade(job.flat_shading)?;
        let label = loaded.label.clone();
        let time = job.when.apply(&mut loaded.scene, &label)?;
        let mut stage = Stage::new(loaded.scene, &label, job.frame_settings())?;
        stage.pose(time)?;
        let fields = Fields::load(&stage.frame().distance_fields, &label)?;
        let tracer = make_tracer(&job, policy, &fields, None)?;
        let s = &stage.frame().settings;
        let full_size = (s.width, s.height);
        let camera = job.camera;
        Ok(Live {
            job,
            policy,
            step: FrameStep::new(stage, tracer),
            fields,
            camera,
            time,
            scale: 1.0,
            pool: None,
            film: Film::new(0, 0),
            samples: 0,
            dirty: Dirty { build: true, pose: false, camera: false, image: true },
            full_size,
            gpu_context: None,
            on_device: false,
            device_image: None,
            resolved_on_device: false,
            view_accel: None,
            rendered_size: (0, 0),
        })
    }

    /// Traces on `ctx` (a device the front end opened, the viewer's window's) whenever the
    /// backend is the GPU, so its image can reach the window without leaving the device.
    pub fn share_gpu(&mut self, ctx: Arc<GpuContext>) -> Result<()> {
        self.gpu_context = Some(ctx);
        self.device_image = None;
        if self.job.backend.is_gpu() {
            self.step.tracer = make_tracer(&self.job, self.policy, &self.fields, self.gpu_context.clone())?;
            self.dirty.build = true;
            self.dirty.image = true;
        }
        Ok(())
    }

    /// With `on` and the GPU backend on a shared device ([`Live::share_gpu`]), frames
    /// resolve into an image on the device ([`Live::device_image`]) instead of being read
    /// back into the film; the film stays empty then. Switching restarts the image.
    pub fn present_on_device(&mut self, on: bool) {
        if on != self.on_device {
            self.on_device = on;
            self.dirty.image = true;
        }
    }

    /// The image on the device, when the last frame was resolved there.
    pub fn device_image(&self) -> Option<&DeviceImage> {
        self.device_image.as_deref().filter(|_| self.resolved_on_device)
    }

    /// The accumulated image as a film wherever it lives (read back from the device when
    /// frames resolve there): what saving it needs.
    pub fn image_film(&self) -> Result<Film> {
        match self.device_image() {
            Some(image) => Ok(image.read_film()?),
            None => Ok(self.film.clone()),
        }
    }

    /// The job the image follows.
    pub fn job(&self) -> &RenderJob {
        &self.job
    }

    /// The structures' update policy.
    pub fn policy(&self) -> UpdatePolicy {
        self.policy
    }

    /// Switches to `job` and `policy` (the viewer's live switches): a new structure,
    /// layout, policy or backend makes a new tracer now (a GPU one compiles its kernels)
    /// and builds it at the next step; new frame settings re-pose; anything else restarts
    /// the image. On an error nothing changes.
    pub fn reconfigure(&mut self, job: RenderJob, policy: UpdatePolicy) -> Result<()> {
        let job = RenderJob { output: None, passes: None, ..job };
        check(&job)?;
        if job.flat_shading != self.job.flat_shading {
            bail!("flat shading is chosen when the scene is opened (--flat-shading)");
        }
        if job.when.clip != self.job.when.clip || job.when.fps != self.job.when.fps {
            bail!("the clip and frame rate are chosen when the scene is opened (--clip, --fps)");
        }
        let new_tracer = job.accel != self.job.accel
            || job.scene_accel != self.job.scene_accel
            || policy != self.policy
            || job.backend.gpu != self.job.backend.gpu
            || job.backend.gpu_build != self.job.backend.gpu_build
            || job.gpu_strategy != self.job.gpu_strategy
            // The GPU tracer compiles its integrator's kernels when it is made.
            || (job.backend.is_gpu() && job.integrator != self.job.integrator);
        if new_tracer {
            self.step.tracer = make_tracer(&job, policy, &self.fields, self.gpu_context.clone())?;
            self.dirty.build = true;
        }
        if job.frame_settings() != self.job.frame_settings() {
            *self.step.stage.settings_mut() = job.frame_settings();
            self.dirty.pose = true;
        }
        self.dirty.image = true;
        self.job = job;
        self.policy = policy;
        Ok(())
    }

    /// The scene's timeline (its frames and frame rate).
    pub fn timeline(&self) -> Timeline {
        self.step.stage.scene().animation.timeline
    }

    /// True when the scene moves: keyframes, clips or physics.
    pub fn is_animated(&self) -> bool {
        self.step.stage.scene().is_animated() || self.step.stage.world().is_some()
    }

    /// The time shown.
    pub fn time(&self) -> f32 {
        self.time
    }

    /// Shows time `t` (seconds on the scene's axis).
    pub fn set_time(&mut self, t: f32) {
        if t.is_finite() && t.to_bits() != self.time.to_bits() {
            self.time = t;
            self.dirty.pose = true;
        }
    }

    /// The camera the image is seen through (the user's, else the scene's at this time).
    pub fn camera(&self) -> Camera {
        self.camera.unwrap_or(self.step.stage.frame().camera)
    }

    /// Looks through `camera` from now on.
    pub fn set_camera(&mut self, camera: Camera) {
        if self.camera() != camera {
            self.camera = Some(camera);
            self.dirty.camera = true;
        }
    }

    /// Back to the job's camera (`--camera`), else the scene's.
    pub fn reset_camera(&mut self) {
        if self.camera != self.job.camera {
            self.camera = self.job.camera;
            self.dirty.pose = true;
        }
    }

    /// Renders at `scale` (in (0, 1]) of the job's image size, the viewer's resolution
    /// scaling while the camera moves.
    pub fn set_scale(&mut self, scale: f32) {
        let scale = if scale.is_finite() { scale.clamp(1.0 / 64.0, 1.0) } else { 1.0 };
        if scale != self.scale {
            self.scale = scale;
            self.dirty.image = true;
        }
    }

    /// The resolution scale.
    pub fn scale(&self) -> f32 {
        self.scale
    }

    /// Traces on `threads` threads (`None`: rayon's global pool, every core).
    pub fn set_threads(&mut self, threads: Option<usize>) -> Result<()> {
        self.pool = match threads {
            None => None,
            Some(n) => Some(
                rayon::ThreadPoolBuilder::new()
                    .num_threads(n.max(1))
                    .build()
                    .context("cannot start the render threads")?,
            ),
        };
        Ok(())
    }

    /// Threads the render uses.
    pub fn threads(&self) -> usize {
        self.pool.as_ref().map_or_else(rayon::current_num_threads, |p| p.current_num_threads())
    }

    /// Samples per pixel of the pattern frames follow ([`Live`]'s docs).
    pub fn spp(&self) -> u32 {
        self.job.spp.or(self.step.stage.frame().settings.spp).unwrap_or(DEFAULT_SPP).clamp(1, MAX_SPP)
    }

    /// The accumulated image (black and empty before the first step).
    pub fn film(&self) -> &Film {
        &self.film
    }

    /// Samples per pixel the image holds.
    pub fn samples(&self) -> u32 {
        self.samples
    }

    /// True when more frames would add nothing: a deterministic integrator's pattern is
    /// complete, or the image holds the most samples a job may ask for.
    pub fn converged(&self) -> bool {
        let cap = match self.job.integrator {
            IntegratorKind::Whitted => self.spp(),
            _ => MAX_SPP,
        };
        self.samples >= cap && !self.needs_work()
    }

    /// The posed frame (its camera the one shown, its size the rendered one).
    pub fn frame(&self) -> &Frame {
        self.step.stage.frame()
    }

    /// The tracer (its CPU structure for heat maps and outlines).
    pub fn tracer(&self) -> &Tracer {
        &self.step.tracer
    }

    /// The CPU structure over the frame's triangles, once built (`None` on the GPU or
    /// without triangles).
    pub fn accel(&self) -> Option<&dyn Accel> {
        self.step.tracer.accel()
    }

    /// Makes [`Live::view_structure`] available: on the GPU, builds the job's structure on
    /// the CPU over the current frame (once per update). Nothing to do on the CPU or
    /// without triangles.
    pub fn build_view_structure(&mut self) -> Result<()> {
        let frame = self.step.stage.frame();
        if self.step.tracer.accel().is_none() && self.view_accel.is_none() && frame.mesh.triangle_count() > 0 {
            let built = self
                .job
                .accel
                .build(&frame.mesh, Some(frame.camera.position))
                .with_context(|| format!("{}: cannot build {} for the views", self.label(), self.job.accel))?;
            self.view_accel = Some(built);
        }
        Ok(())
    }

    /// The structure the views of the structure (heat map, outline) are drawn from: the
    /// CPU tracer's own, or on the GPU the one [`Live::build_view_structure`] built.
    pub fn view_structure(&self) -> Option<&dyn Accel> {
        self.step.tracer.accel().or(self.view_accel.as_deref())
    }

    /// The scene's name in messages.
    pub fn label(&self) -> &str {
        self.step.stage.label()
    }

    fn needs_work(&self) -> bool {
        let d = self.dirty;
        d.build || d.pose || d.camera || d.image
    }

    /// Brings the scene to the chosen time and camera and adds one progressive frame.
    pub fn step(&mut self) -> Result<LiveFrame> {
        let mut report = LiveFrame::default();
        if self.converged() {
            report.samples = self.samples;
            report.idle = true;
            return Ok(report);
        }
        let mut update = self.dirty.build;
        if self.dirty.pose {
            let timing = self.step.stage.pose(self.time)?;
            report.pose = timing.total;
            report.physics = timing.physics;
            let s = &self.step.stage.frame().settings;
            self.full_size = (s.width, s.height);
            update = true;
        }
        if let Some(c) = self.camera {
            let frame = self.step.stage.frame_mut();
            if frame.camera != c {
                frame.camera = c;
            }
            if self.dirty.camera && self.job.accel.kind.is_view_dependent() {
                update = true;
            }
        }
        let has_triangles = self.step.stage.frame().mesh.triangle_count() > 0;
        if update && has_triangles {
            self.view_accel = None;
            let (stage, tracer) = (&self.step.stage, &mut self.step.tracer);
            let label = stage.label().to_string();
            report.update = Some(
                tracer
                    .update(stage.scene(), stage.frame())
                    .with_context(|| format!("{label}: cannot build {}", self.job.accel))?,
            );
        }
        let restart = self.dirty.pose || self.dirty.camera || self.dirty.image || update;
        self.dirty = Dirty::default();

        // The job's size (the pose applied its settings), scaled.
        let frame = self.step.stage.frame_mut();
        let full = self.full_size;
        let max = dynray_render::MAX_IMAGE_EDGE;
        if full.0 == 0 || full.1 == 0 || full.0 > max || full.1 > max {
            bail!("image size {}x{} is outside 1..={max} on a side", full.0, full.1);
        }
        dynray_render::check_image_budget(full.0, full.1).map_err(|m| anyhow::anyhow!(m))?;
        let size = (scaled(full.0, self.scale), scaled(full.1, self.scale));
        frame.settings.width = size.0;
        frame.settings.height = size.1;
        if restart || size != self.rendered_size {
            self.samples = 0;
            report.restarted = true;
        }

        let spp = self.spp();
        let params = IntegratorParams {
            branch_depth: self.job.branch_depth.unwrap_or(IntegratorParams::default().branch_depth),
        };
        let gpu = self.job.backend.is_gpu();
        let options = if gpu {
            // A whole image a frame; frames after the first draw fresh streams.
            let seed = if self.samples == 0 { self.job.seed } else { mix_seed(self.job.seed, self.samples) };
            RenderOptions { spp, seed, integrator: self.job.integrator, params, ..Default::default() }
        } else {
            RenderOptions {
                spp: 1,
                pattern: Some(spp),
                first_sample: self.samples,
                seed: self.job.seed,
                integrator: self.job.integrator,
                params,
                ..Default::default()
            }
        };
        let direct = self.direct_target(size)?;
        let t0 = Instant::now();
        let (film, stats) = self.render(&options, has_triangles)?;
        report.render = t0.elapsed();
        report.rays = stats.total_rays();
        self.resolved_on_device = direct;
        if direct {
            self.film = Film::new(0, 0);
        } else if self.samples == 0 {
            self.film = film;
        } else {
            self.film.add_film(&film);
        }
        self.samples += options.spp;
        self.rendered_size = size;
        report.samples = self.samples;
        Ok(report)
    }

    /// Points the GPU tracer at the device image of `size` (made or cleared as needed)
    /// when frames are to resolve on the device; returns whether they do.
    fn direct_target(&mut self, size: (u32, u32)) -> Result<bool> {
        let Tracer::Gpu(gpu) = &mut self.step.tracer else { return Ok(false) };
        let shared = self.gpu_context.as_ref().filter(|c| Arc::ptr_eq(c, gpu.context_arc()));
        let Some(ctx) = shared.filter(|_| self.on_device).cloned() else {
            gpu.set_target(None);
            return Ok(false);
        };
        let fits = self.device_image.as_ref().is_some_and(|i| (i.width(), i.height()) == size);
        if !fits {
            self.device_image = Some(Arc::new(DeviceImage::new(ctx, size.0, size.1)?));
        } else if self.samples == 0 {
            self.device_image.as_ref().expect("fits").clear();
        }
        gpu.set_target(self.device_image.clone());
        Ok(true)
    }

    fn render(&mut self, options: &RenderOptions, has_triangles: bool) -> Result<(Film, RenderStats)> {
        let (stage, tracer, fields) = (&self.step.stage, &mut self.step.tracer, &self.fields);
        let frame = stage.frame();
        let mut go = move || -> Result<(Film, RenderStats)> {
            if !has_triangles {
                // Fields alone (or nothing): no structure to trace.
                let scene = fields.fields_only(frame);
                let integrator = options.integrator.create(frame, &scene, &options.params);
                return Ok(dynray_render::render_with(frame, integrator.as_ref(), options));
            }
            match tracer.accel() {
                // The CPU: the fields the live job keeps (whatever tracer it makes) beside.
                Some(accel) => Ok(crate::fields::render(frame, accel, fields, options)),
                None => tracer.render(frame, options),
            }
        };
        match &self.pool {
            Some(pool) => pool.install(go),
            None => go(),
        }
    }
}

/// What the live job accepts of a render job.
fn check(job: &RenderJob) -> Result<()> {
    job.check()?;
    if job.aov.is_some() {
        bail!("the live view shows images, not AOVs (the heat map and outlines are its views of the structure)");
    }
    Ok(())
}

/// The tracer `job` asks for; the scene's `fields` are traced beside the triangles by
/// [`Live`] itself on the CPU, and refused on the GPU.
fn make_tracer(
    job: &RenderJob,
    policy: UpdatePolicy,
    fields: &Fields,
    context: Option<Arc<GpuContext>>,
) -> Result<Tracer> {
    match &job.backend {
        BackendChoice { gpu: Some(options), gpu_build } => {
            if !fields.is_empty() {
                bail!("scenes with `adf` blocks render on the CPU only; switch the backend to the CPU");
            }
            let probe = RenderOptions { integrator: job.integrator, ..Default::default() };
            gpu_integrator(&probe, job.gpu_strategy)?;
            let choice = GpuChoice { options, build: *gpu_build, strategy: job.gpu_strategy, context };
            Tracer::gpu(&job.accel, policy, &probe, choice)
        }
        BackendChoice { gpu: None, .. } => Ok(Tracer::cpu(&job.accel, policy, job.scene_accel, Fields::default())),
    }
}

/// `full` scaled by `scale`, at least 1.
fn scaled(full: u32, scale: f32) -> u32 {
    ((full as f32 * scale).round() as u32).clamp(1, full)
}

/// The seed of a GPU frame after the first: a bijective mix of the job's seed and the
/// samples already drawn, so frames draw distinct streams.
fn mix_seed(seed: u64, samples: u32) -> u64 {
    let mut z = seed ^ (samples as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}
