//! The render job: a scene, mesh or distance-field file (or the built-in demo) at one
//! instant to an image, on the CPU or the GPU. Every option combination is checked in
//! [`RenderJob::check`] (before loading) and against the loaded scene (before any
//! structure is built); then one of four pipelines runs: a field alone, fields without
//! triangles, triangles (with any fields beside them) on the CPU, triangles on the GPU.

use crate::backend::BackendChoice;
use crate::fields::Fields;
use crate::format::thousands;
use crate::frame_step::{FrameSettings, Stage};
use crate::load::Loaded;
use crate::timeline::TimeChoice;
use crate::tracer::{gpu_integrator, GpuChoice, Tracer};
use anyhow::{bail, Context, Result};
use dynray_accel::{AccelSpec, SceneLayout, UpdatePolicy};
use dynray_adf::{Adf, AdfGeometry};
use dynray_gpu::{DeviceFieldAov, GpuContext, GpuStrategy};
use dynray_render::{
    render_with, write_aov, write_image, Aov, AovIntegrator, Film, IntegratorKind, IntegratorParams, OutputFormat,
    RenderOptions, SceneIntersector,
};
use dynray_scene::{Camera, Frame};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

/// Samples per pixel when neither the job nor the scene says.
pub const DEFAULT_SPP: u32 = 9;
/// Most samples per pixel a job accepts (samples × passes included).
pub const MAX_SPP: u32 = 1 << 16;

/// The policy of a render's structures: one frame, no update follows, so `auto`'s SAH
/// cost of the fresh build (a tree walk, or a read-back on the GPU) would be wasted.
const ONE_FRAME: UpdatePolicy = UpdatePolicy::Rebuild;

/// A render's progress: (tiles done, tiles in all).
pub type Progress<'a> = &'a (dyn Fn(usize, usize) + Sync);

/// Everything a render is asked; `Default` is the CLI's defaults.
#[derive(Clone, Debug)]
pub struct RenderJob {
    /// The image file, when the front end writes one: its type is checked first (and
    /// [`Rendered::write`] writes it). `None` renders in memory.
    pub output: Option<PathBuf>,
    /// Image size; `None` keeps the scene's.
    pub width: Option<u32>,
    /// Image size; `None` keeps the scene's.
    pub height: Option<u32>,
    /// Longest light path in segments (Mitsuba's `max_depth`); `None` keeps the scene's.
    pub max_depth: Option<u32>,
    /// Smallest path weight still traced; `None` keeps the scene's.
    pub min_weight: Option<f32>,
    /// The structure over the triangles.
    pub accel: AccelSpec,
    /// How actors are arranged into structures.
    pub scene_accel: SceneLayout,
    /// Whitted, cumulative or path.
    pub integrator: IntegratorKind,
    /// Samples per pixel; `None`: the scene's, else [`DEFAULT_SPP`].
    pub spp: Option<u32>,
    /// The cumulative tracer's branch depth.
    pub branch_depth: Option<u32>,
    /// The cumulative tracer's passes.
    pub passes: Option<u32>,
    /// Sampler seed.
    pub seed: u64,
    /// Flat shading for every actor.
    pub flat_shading: bool,
    /// Draw one AOV instead of the image (written as EXR).
    pub aov: Option<Aov>,
    /// The instant.
    pub when: TimeChoice,
    /// A camera replacing the scene's (`--camera`, [`crate::parse_camera`]).
    pub camera: Option<Camera>,
    /// CPU or GPU.
    pub backend: BackendChoice,
    /// Seed 003's GPU strategy.
    pub gpu_strategy: GpuStrategy,
}

impl Default for RenderJob {
    fn default() -> Self {
        RenderJob {
            output: None,
            width: None,
            height: None,
            max_depth: None,
            min_weight: None,
            accel: "bvh".parse().expect("the default structure's name parses"),
            scene_accel: SceneLayout::default(),
            integrator: IntegratorKind::default(),
            spp: None,
            branch_depth: None,
            passes: None,
            seed: 0,
            flat_shading: false,
            aov: None,
            when: TimeChoice::default(),
            camera: None,
            backend: BackendChoice::default(),
            gpu_strategy: GpuStrategy::Wavefront,
        }
    }
}

/// A finished render.
pub struct Rendered {
    /// Linear radiance, or the AOV's values.
    pub film: Film,
    /// The AOV the film holds, if any.
    pub aov: Option<Aov>,
    /// The summary line, without the output's name (`… (640x480, 9 spp, …)`).
    pub summary: String,
}

impl Rendered {
    /// Writes the film to `path` (PNG/BMP/EXR by its extension; an AOV as EXR), under a
    /// temporary name then renamed.
    pub fn write(&self, path: &Path) -> Result<()> {
        match self.aov {
            Some(aov) => write_aov(&self.film, aov, path)?,
            None => write_image(&self.film, path)?,
        }
        Ok(())
    }
}

impl RenderJob {
    /// Checks what needs no scene: the output's type against the AOV, sample counts, the
    /// cumulative tracer's flags, the backend's flags, the GPU's integrators.
    pub fn check(&self) -> Result<()> {
        if let Some(out) = &self.output {
            match (OutputFormat::from_path(out), self.aov) {
                (None, _) => bail!("{}: unknown image type (expected .png, .bmp or .exr)", out.display()),
                (Some(f), Some(aov)) if f != OutputFormat::Exr => {
                    bail!("{}: --aov {aov} writes float data: use an .exr output", out.display())
                }
                _ => {}
            }
        }
        if let Some(spp) = self.spp {
            if !(1..=MAX_SPP).contains(&spp) {
                bail!("--spp must be in 1..={MAX_SPP}, got {spp}");
            }
        }
        if self.max_depth == Some(0) {
            bail!("--max-depth must be at least 1");
        }
        if self.integrator != IntegratorKind::Cumulative {
            for (flag, given) in [("--branch-depth", self.branch_depth.is_some()), ("--passes", self.passes.is_some())]
            {
                if given {
                    bail!("{flag} applies to --integrator cumulative only (got `{}`)", self.integrator);
                }
            }
        }
        if let Some(m) = self.min_weight {
            // The scene language's range (docs/scene-language.md, `settings`).
            if !(0.0..=1.0).contains(&m) {
                bail!("--min-weight must be a weight in 0..=1, got {m}");
            }
        }
        self.when.check()?;
        self.backend.check()?;
        if self.backend.is_gpu() {
            self.accel.binary_bvh()?;
            if self.aov.is_none() {
                let probe = RenderOptions { integrator: self.integrator, ..Default::default() };
                gpu_integrator(&probe, self.gpu_strategy)?;
            }
        }
        Ok(())
    }

    /// Renders `loaded` (unshaded, as [`Loaded::open`] returns it). `progress` hears of
    /// tiles done on the CPU's triangle pipeline.
    pub fn run(&self, mut loaded: Loaded, progress: Option<Progress<'_>>) -> Result<Rendered> {
        self.check()?;
        loaded.shade(self.flat_shading)?;
        let label = loaded.label.clone();
        let time = self.when.apply(&mut loaded.scene, &label)?;
        if loaded.scene.actors.is_empty() && loaded.scene.distance_fields.is_empty() && loaded.field.is_none() {
            bail!(
                "{label}: nothing to render: the scene has no objects (a file of definitions only, such as \
                 examples/materials.scn, is for `include` in another scene)"
            );
        }
        let camera_given = loaded.scene.camera.is_some() || self.camera.is_some();
        let mut stage = Stage::new(loaded.scene, &label, self.frame_settings())?;
        stage.pose(time)?;
        if let Some(c) = self.camera {
            stage.frame_mut().camera = c;
        }
        let spp = self.spp.or(stage.frame().settings.spp).unwrap_or(DEFAULT_SPP).min(MAX_SPP);
        let passes = self.passes.unwrap_or(1);
        if spp as u64 * passes as u64 > MAX_SPP as u64 {
            bail!(
                "--passes {passes} × {spp} spp is {} samples per pixel, more than {MAX_SPP}",
                spp as u64 * passes as u64
            );
        }
        let s = &stage.frame().settings;
        for (what, v) in [("width", s.width), ("height", s.height)] {
            let max = dynray_render::MAX_IMAGE_EDGE;
            if v == 0 || v > max {
                bail!("{label}: image {what} {v} is outside 1..={max} (set --{what} to override the scene's settings)");
            }
        }
        dynray_render::check_image_budget(s.width, s.height).map_err(|m| anyhow::anyhow!("{label}: {m}"))?;
        let params =
            IntegratorParams { branch_depth: self.branch_depth.unwrap_or(IntegratorParams::default().branch_depth) };
        let options =
            RenderOptions { spp, seed: self.seed, integrator: self.integrator, params, passes, ..Default::default() };

        if let Some(adf) = &loaded.field {
            let material = stage.frame().materials.first().cloned().unwrap_or_default();
            if self.backend.is_gpu() {
                return self.field_on_gpu(stage.frame(), &label, adf, material);
            }
            let scene = SceneIntersector::new(vec![Box::new(AdfGeometry::new(adf, material))]);
            let what = format!(
                "distance field of max level {} ({} internal cells)",
                adf.max_level(),
                thousands(adf.internal_cells())
            );
            return self.geometry(stage.frame(), &label, (&scene, what), &options);
        }
        if self.aov.is_some() && self.backend.is_gpu() {
            bail!("--aov is rendered on the CPU only; drop --backend gpu");
        }
        let fields = Fields::load(&stage.frame().distance_fields, &label)?;
        if !fields.is_empty() {
            if self.backend.is_gpu() {
                bail!("{label}: scenes with `adf` blocks render on the CPU only; drop --backend gpu");
            }
            if !camera_given {
                // Only fields, no mesh: the default view frames them.
                let frame = stage.frame_mut();
                frame.camera = Camera::framing(&fields.bounds(frame).union(&frame.mesh.bounds()));
            }
        }
        let frame = stage.frame();
        if !fields.is_empty() && frame.mesh.triangle_count() == 0 {
            // Nothing for a structure to hold: the fields are the whole scene.
            let what = fields.describe(frame).trim_start_matches(" and ").to_string();
            return self.geometry(frame, &label, (&fields.fields_only(frame), what), &options);
        }
        if let Some(gpu) = &self.backend.gpu {
            return self.triangles_on_gpu(stage, &label, gpu, &options);
        }
        self.triangles_on_cpu(stage, &label, fields, RenderOptions { progress, ..options })
    }

    pub(crate) fn frame_settings(&self) -> FrameSettings {
        FrameSettings {
            width: self.width,
            height: self.height,
            // The path tracer counts segments (Mitsuba's max_depth), Whitted ray levels:
            // the same light paths are level D - 1 (dynray_render::PathTracer's docs).
            max_recursion_level: self
                .max_depth
                .map(|d| if self.integrator == IntegratorKind::Path { d - 1 } else { d }),
            min_weight: self.min_weight,
        }
    }

    /// The frame's triangles (and any fields beside them) through the layout `animate`
    /// uses, so `render --frame K` draws its frame K.
    fn triangles_on_cpu(
        &self,
        mut stage: Stage,
        label: &str,
        fields: Fields,
        options: RenderOptions,
    ) -> Result<Rendered> {
        let describe_fields = fields.describe(stage.frame());
        let mut tracer = Tracer::cpu(&self.accel, ONE_FRAME, self.scene_accel, fields);
        let build = tracer
            .update(stage.scene(), stage.frame())
            .with_context(|| format!("{label}: cannot build {}", self.accel))?
            .time;
        let live = tracer.live_scene().expect("updated");
        // The layout follows the build time, so the summary's "N triangles, bvh build" stays.
        let layout = match live.two_level() {
            Some(_) => format!(" ({})", live.describe()),
            None => String::new(),
        };
        let accel_name = live.accel().name();
        let frame = stage.frame_mut();
        let head = format!(
            "{label}: {} triangles{describe_fields}, {accel_name} build {:.1} ms{layout}",
            thousands(frame.mesh.triangle_count() as u64),
            build.as_secs_f64() * 1e3
        );
        let t1 = Instant::now();
        if let Some(aov) = self.aov {
            let film = tracer.render_aov(frame, aov, &options)?;
            let summary = format!(
                "{head}, {aov} AOV {:.1} ms ({}x{})",
                t1.elapsed().as_secs_f64() * 1e3,
                film.width(),
                film.height()
            );
            return Ok(Rendered { film, aov: Some(aov), summary });
        }
        let (film, stats) = tracer.render(frame, &options)?;
        let secs = t1.elapsed().as_secs_f64().max(1e-9);
        let summary = format!(
            "{head}, {} render {:.1} ms ({}x{}, {}, {} rays, {:.2} Mrays/s)",
            self.integrator,
            secs * 1e3,
            film.width(),
            film.height(),
            samples(&options),
            thousands(stats.total_rays()),
            stats.total_rays() as f64 / secs / 1e6,
        );
        Ok(Rendered { film, aov: None, summary })
    }

    /// The frame's BVH built where `--gpu-build` says (on the CPU and uploaded, or on
    /// the device), traced and shaded there by the chosen strategy.
    fn triangles_on_gpu(
        &self,
        stage: Stage,
        label: &str,
        gpu: &dynray_gpu::GpuOptions,
        options: &RenderOptions,
    ) -> Result<Rendered> {
        let how = self.backend.gpu_build;
        let choice = GpuChoice { options: gpu, build: how, strategy: self.gpu_strategy, context: None };
        let mut tracer = Tracer::gpu(&self.accel, ONE_FRAME, options, choice)
            .with_context(|| format!("{label}: cannot build {}", self.accel))?;
        let build = tracer
            .update(stage.scene(), stage.frame())
            .with_context(|| format!("{label}: cannot build {}", self.accel))?
            .time;
        let frame = stage.frame();
        let (film, stats) = tracer.render(frame, options).with_context(|| label.to_string())?;
        let Tracer::Gpu(g) = &tracer else { unreachable!("a GPU tracer") };
        // The device's own timings, not the wall clock around the upload.
        let secs = g.last_render_seconds().max(1e-9);
        let summary = format!(
            "{label}: {} triangles, bvh build ({how}) {:.1} ms, {} {} on {} {:.1} ms ({}x{}, {}, {} rays, {:.2} Mrays/s)",
            thousands(frame.mesh.triangle_count() as u64),
            build.as_secs_f64() * 1e3,
            self.integrator,
            self.gpu_strategy,
            g.context().adapter().name,
            secs * 1e3,
            film.width(),
            film.height(),
            samples(options),
            thousands(stats.total_rays()),
            stats.total_rays() as f64 / secs / 1e6,
        );
        Ok(Rendered { film, aov: None, summary })
    }

    /// Geometry other than the frame's triangles — a field file alone, or fields and no
    /// mesh — through the same render loop, integrators and AOVs; `what` describes it.
    fn geometry(
        &self,
        frame: &Frame,
        label: &str,
        (scene, what): (&SceneIntersector<'_>, String),
        options: &RenderOptions<'_>,
    ) -> Result<Rendered> {
        let t0 = Instant::now();
        let (film, done) = if let Some(aov) = self.aov {
            let one = RenderOptions { spp: 1, passes: 1, ..*options };
            (render_with(frame, &AovIntegrator::new(aov, scene), &one).0, format!("{aov} AOV"))
        } else {
            let integrator = self.integrator.create(frame, scene, &options.params);
            (render_with(frame, integrator.as_ref(), options).0, format!("{} render", self.integrator))
        };
        let summary = format!(
            "{label}: {what}, {done} {:.1} ms ({}x{})",
            t0.elapsed().as_secs_f64() * 1e3,
            frame.settings.width,
            frame.settings.height
        );
        Ok(Rendered { film, aov: self.aov, summary })
    }

    /// A field file's AOV with the camera rays marched on the device.
    fn field_on_gpu(
        &self,
        frame: &Frame,
        label: &str,
        adf: &Adf,
        material: dynray_scene::Material,
    ) -> Result<Rendered> {
        let Some(aov) = self.aov else {
            bail!(
                "{label}: on the GPU a distance field renders its AOVs (--aov depth, normal, prim or albedo); \
                 shaded images of fields render on the CPU (drop --backend gpu)"
            );
        };
        let gpu = self.backend.gpu.as_ref().expect("called on the GPU");
        let t0 = Instant::now();
        let ctx = Arc::new(GpuContext::new(gpu)?);
        let device = dynray_gpu::GpuAdf::upload(ctx.clone(), adf).with_context(|| format!("{label}: cannot upload"))?;
        let upload = t0.elapsed();
        let integrator = DeviceFieldAov { aov, device: &device, geometry: AdfGeometry::new(adf, material) };
        let t1 = Instant::now();
        let one = RenderOptions { spp: 1, passes: 1, seed: self.seed, ..Default::default() };
        let film = render_with(frame, &integrator, &one).0;
        let summary = format!(
            "{label}: distance field of max level {} on {}, upload {:.1} ms, {aov} AOV {:.1} ms ({}x{})",
            adf.max_level(),
            ctx.adapter().name,
            upload.as_secs_f64() * 1e3,
            t1.elapsed().as_secs_f64() * 1e3,
            film.width(),
            film.height()
        );
        Ok(Rendered { film, aov: Some(aov), summary })
    }
}

/// `9 spp`, or `9 spp × 4 passes`.
fn samples(options: &RenderOptions) -> String {
    if options.passes > 1 {
        format!("{} spp × {} passes", options.spp, options.passes)
    } else {
        format!("{} spp", options.spp)
    }
}
