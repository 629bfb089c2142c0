//! The tracer seam: where a job's rays are traced, behind one interface over the
//! backends. The CPU keeps its structures current in any scene layout
//! ([`LiveScene`]: flat, split, instanced) and traces the scene's distance fields beside
//! the triangles; the GPU ([`GpuTracer`]) keeps a BVH on the device and renders with a
//! seed 003 strategy. Both follow the one update policy ([`dynray_accel::PolicyState`]).

mod gpu;

pub use gpu::{gpu_integrator, GpuChoice, GpuTracer};

use crate::fields::Fields;
use anyhow::{Context, Result};
use dynray_accel::{Accel, AccelSpec, LiveScene, SceneLayout, UpdateAction, UpdatePolicy, UpdateReport};
use dynray_render::{Aov, Film, RenderOptions, RenderStats};
use dynray_scene::{Frame, Scene};

/// Where a job's frames are traced.
pub enum Tracer {
    /// The CPU: the structures (built on the first update) and the render loop.
    Cpu(Box<CpuTracer>),
    /// The GPU.
    Gpu(Box<GpuTracer>),
}

/// The CPU side of [`Tracer`].
pub struct CpuTracer {
    spec: AccelSpec,
    policy: UpdatePolicy,
    layout: SceneLayout,
    live: Option<LiveScene>,
    fields: Fields,
}

impl Tracer {
    /// The CPU tracer of `spec` under `policy` in `layout`, tracing `fields` beside the
    /// triangles.
    pub fn cpu(spec: &AccelSpec, policy: UpdatePolicy, layout: SceneLayout, fields: Fields) -> Self {
        Tracer::Cpu(Box::new(CpuTracer { spec: spec.clone(), policy, layout, live: None, fields }))
    }

    /// The GPU tracer (a BVH; `options` must ask for an integrator the GPU has:
    /// [`gpu_integrator`]).
    pub fn gpu(spec: &AccelSpec, policy: UpdatePolicy, options: &RenderOptions, choice: GpuChoice<'_>) -> Result<Self> {
        Ok(Tracer::Gpu(Box::new(GpuTracer::new(spec, policy, options, choice)?)))
    }

    /// Brings the structure up to `frame`, which `scene` filled (built on the first call).
    pub fn update(&mut self, scene: &Scene, frame: &Frame) -> Result<UpdateReport> {
        match self {
            Tracer::Cpu(c) => c.update(scene, frame),
            Tracer::Gpu(g) => g.update(frame),
        }
    }

    /// Renders `frame` through the structure [`Self::update`] prepared.
    pub fn render(&mut self, frame: &Frame, options: &RenderOptions) -> Result<(Film, RenderStats)> {
        match self {
            Tracer::Cpu(c) => Ok(crate::fields::render(frame, c.accel(), &c.fields, options)),
            Tracer::Gpu(g) => g.render(frame, options),
        }
    }

    /// One AOV of `frame` (the CPU's render loop; the GPU renders no AOVs).
    pub fn render_aov(&mut self, frame: &Frame, aov: Aov, options: &RenderOptions) -> Result<Film> {
        match self {
            Tracer::Cpu(c) => Ok(crate::fields::render_aov(frame, c.accel(), &c.fields, aov, options)),
            Tracer::Gpu(_) => anyhow::bail!("--aov is rendered on the CPU only; drop --backend gpu"),
        }
    }

    /// The CPU's structure over the frame's triangles, once updated (`None` on the GPU).
    pub fn accel(&self) -> Option<&dyn Accel> {
        match self {
            Tracer::Cpu(c) => c.live.as_ref().map(LiveScene::accel),
            Tracer::Gpu(_) => None,
        }
    }

    /// The CPU's structures, once updated.
    pub fn live_scene(&self) -> Option<&LiveScene> {
        match self {
            Tracer::Cpu(c) => c.live.as_ref(),
            Tracer::Gpu(_) => None,
        }
    }

    /// The structure and where it runs, for the summary line.
    pub fn describe(&self) -> String {
        match self {
            Tracer::Cpu(c) => match &c.live {
                Some(l) => format!("{} {}, {}", c.spec, c.policy, l.describe()),
                None => format!("{} {}", c.spec, c.policy),
            },
            Tracer::Gpu(g) => g.describe(),
        }
    }
}

impl CpuTracer {
    fn accel(&self) -> &dyn Accel {
        self.live.as_ref().expect("the tracer is updated before it renders").accel()
    }

    /// Built on the first frame in the layout, then the policy.
    fn update(&mut self, scene: &Scene, frame: &Frame) -> Result<UpdateReport> {
        let spec = &self.spec;
        match &mut self.live {
            None => {
                let (built, time) = dynray_render::build_live_scene(spec, self.policy, self.layout, scene, frame)
                    .with_context(|| format!("cannot build {spec}"))?;
                self.live = Some(built);
                Ok(UpdateReport { action: UpdateAction::Rebuilt, time, cost_ratio: Some(1.0) })
            }
            Some(l) => {
                let actors = dynray_render::actor_geometry(scene, frame);
                l.update(&actors, &frame.mesh, Some(frame.camera.position))
                    .with_context(|| format!("cannot update {spec}"))
            }
        }
    }
}
