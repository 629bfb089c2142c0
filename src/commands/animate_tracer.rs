//! Where `dynray animate` traces its frames: the CPU's structure kept current by its
//! update policy ([`LiveAccel`]) and rendered by `dynray_render::render`, or the GPU
//! (`--backend gpu`): a BVH kept on the device and rendered by a seed 003 strategy. The
//! frame loop in `animate.rs` is the same for both: pose, [`Tracer::update`],
//! [`Tracer::render`], write.
//!
//! On the GPU, `--gpu-build cpu` keeps the CPU's BVH current exactly as the CPU backend
//! does and uploads it; `--gpu-build sah|lbvh` builds on the device and follows the
//! policy there: `refit` refits on the device ([`GpuBvh::refit`]), `rebuild` builds
//! afresh, `auto` refits and reads the refit tree back to weigh its SAH cost against the
//! last fresh build's, rebuilding past the bound (the read-back is part of the update's
//! time).

use super::fields::{render, Fields};
use anyhow::{bail, Context, Result};
use dynray_accel::{
    Accel, AccelSpec, Bvh, BvhParams, LiveAccel, LiveScene, SceneLayout, UpdateAction, UpdatePolicy, UpdateReport,
};
use dynray_gpu::{GpuBuild, GpuBvh, GpuContext, GpuIntegrator, GpuOptions, GpuRenderOptions, GpuRenderer, GpuStrategy};
use dynray_render::{Film, IntegratorKind, RenderOptions, RenderStats};
use dynray_scene::{Frame, Scene};
use std::any::Any;
use std::sync::Arc;
use std::time::Instant;

/// The tracer of an animation.
pub enum Tracer {
    /// The CPU: the structures (built on the first frame) and the render loop.
    Cpu { spec: AccelSpec, policy: UpdatePolicy, layout: SceneLayout, live: Option<LiveScene> },
    /// The GPU.
    Gpu(Box<GpuTracer>),
}

/// The GPU side of [`Tracer`].
pub struct GpuTracer {
    ctx: Arc<GpuContext>,
    renderer: GpuRenderer,
    strategy: GpuStrategy,
    build: GpuBuild,
    params: BvhParams,
    spec: AccelSpec,
    policy: UpdatePolicy,
    /// `--gpu-build cpu`: the CPU's BVH, kept current there and uploaded.
    live: Option<LiveAccel>,
    /// A device tree built this frame, handed to the renderer at the next render.
    fresh: Option<GpuBvh>,
    /// The triangles the device tree was last built or refitted on (a frame with the
    /// same ones keeps it).
    positions: Vec<[f32; 3]>,
    indices: Vec<[u32; 3]>,
    /// SAH cost of the last fresh device build (`auto`).
    built_cost: Option<f64>,
    /// The cost ratio the last update reported (a kept frame reports it again).
    last_ratio: Option<f64>,
    /// Whether the renderer holds a device tree.
    has_tree: bool,
}

/// What [`Tracer::gpu`] needs from the command line.
pub struct GpuChoice<'a> {
    /// Adapter options.
    pub options: &'a GpuOptions,
    /// Where the tree is built.
    pub build: GpuBuild,
    /// Seed 003's strategy.
    pub strategy: GpuStrategy,
}

impl Tracer {
    /// The CPU tracer.
    pub fn cpu(spec: &AccelSpec, policy: UpdatePolicy, layout: SceneLayout) -> Self {
        Tracer::Cpu { spec: spec.clone(), policy, layout, live: None }
    }

    /// The GPU tracer (a BVH; `options` must ask for an integrator the GPU has:
    /// [`gpu_integrator`]).
    pub fn gpu(spec: &AccelSpec, policy: UpdatePolicy, options: &RenderOptions, gpu: GpuChoice<'_>) -> Result<Self> {
        gpu_integrator(options, gpu.strategy)?;
        // The GPU traverses the binary tree: plain `bvh` stands for `bvh2` there.
        let spec = &spec.binary_bvh().with_context(|| format!("cannot build {spec}"))?;
        let params = spec.read().with_context(|| format!("cannot build {spec}"))?;
        let ctx = Arc::new(GpuContext::new(gpu.options)?);
        let renderer = GpuRenderer::new(ctx.clone())?;
        Ok(Tracer::Gpu(Box::new(GpuTracer {
            ctx,
            renderer,
            strategy: gpu.strategy,
            build: gpu.build,
            params,
            spec: spec.clone(),
            policy,
            live: None,
            fresh: None,
            positions: Vec::new(),
            indices: Vec::new(),
            built_cost: None,
            last_ratio: None,
            has_tree: false,
        })))
    }

    /// Brings the structure up to `frame`, which `scene` filled (built on the first call).
    pub fn update(&mut self, scene: &Scene, frame: &Frame) -> Result<UpdateReport> {
        match self {
            Tracer::Cpu { spec, policy, layout, live } => scene_update(live, spec, (*policy, *layout), scene, frame),
            Tracer::Gpu(g) if g.build == GpuBuild::Cpu => cpu_update(&mut g.live, &g.spec, g.policy, frame),
            Tracer::Gpu(g) => g.device_update(frame),
        }
    }

    /// Renders `frame` through the structure [`Self::update`] prepared.
    /// The scene's distance fields (`fields`) are traced beside the triangles on the CPU;
    /// the GPU tracer refuses a scene that has any ([`Tracer::gpu`]'s caller checks).
    pub fn render(&mut self, frame: &Frame, fields: &Fields, options: &RenderOptions) -> Result<(Film, RenderStats)> {
        match self {
            Tracer::Cpu { live, .. } => {
                Ok(render(frame, live.as_ref().expect("updated first").accel(), fields, options))
            }
            Tracer::Gpu(g) => {
                let o = GpuRenderOptions {
                    strategy: g.strategy,
                    spp: options.spp,
                    seed: options.seed,
                    integrator: gpu_integrator(options, g.strategy)?,
                    passes: options.passes,
                };
                let out = if let Some(live) = &g.live {
                    let any: &dyn Any = live.accel();
                    let bvh = any.downcast_ref::<Bvh>().expect("the GPU tracer keeps a bvh");
                    g.renderer.render(frame, bvh, &o)
                } else if let Some(tree) = g.fresh.take() {
                    g.has_tree = true;
                    g.renderer.render_device_tree(frame, tree, &o)
                } else {
                    g.renderer.render_kept_tree(frame, &o)
                };
                let out = out.context("cannot render on the GPU")?;
                Ok((out.film, out.stats))
            }
        }
    }

    /// The structure and where it runs, for the summary line.
    pub fn describe(&self) -> String {
        match self {
            Tracer::Cpu { spec, policy, live, .. } => match live {
                Some(l) => format!("{spec} {policy}, {}", l.describe()),
                None => format!("{spec} {policy}"),
            },
            Tracer::Gpu(g) => {
                format!("{} {} on {} ({} build, {})", g.spec, g.policy, g.ctx.adapter().name, g.build, g.strategy)
            }
        }
    }
}

/// The GPU's integrator for `options`: Whitted's on every strategy; the cumulative
/// tracer and the path tracer on the wavefront strategy only (their kernels are its
/// modes), an error before any device work on the others.
pub fn gpu_integrator(options: &RenderOptions, strategy: GpuStrategy) -> Result<GpuIntegrator> {
    let gpu = match options.integrator {
        IntegratorKind::Whitted => return Ok(GpuIntegrator::Whitted),
        IntegratorKind::Cumulative => GpuIntegrator::Cumulative { branch_depth: options.params.branch_depth },
        IntegratorKind::Path => GpuIntegrator::Path,
    };
    if strategy != GpuStrategy::Wavefront {
        bail!("the {} integrator runs on the GPU with --gpu-strategy wavefront only (got `{strategy}`)", gpu.name());
    }
    Ok(gpu)
}

/// The CPU structures' update: built on the first frame in the layout, then the policy.
fn scene_update(
    live: &mut Option<LiveScene>,
    spec: &AccelSpec,
    (policy, layout): (UpdatePolicy, SceneLayout),
    scene: &Scene,
    frame: &Frame,
) -> Result<UpdateReport> {
    match live {
        None => {
            let (built, time) = dynray_render::build_live_scene(spec, policy, layout, scene, frame)
                .with_context(|| format!("cannot build {spec}"))?;
            *live = Some(built);
            Ok(UpdateReport { action: UpdateAction::Rebuilt, time, cost_ratio: Some(1.0) })
        }
        Some(l) => {
            let actors = dynray_render::actor_geometry(scene, frame);
            l.update(&actors, &frame.mesh, Some(frame.camera.position)).with_context(|| format!("cannot update {spec}"))
        }
    }
}

/// The GPU tracer's CPU-built BVH (`--gpu-build cpu`): built on the first frame, then its
/// policy, over the whole frame (the device traces one tree).
fn cpu_update(
    live: &mut Option<LiveAccel>,
    spec: &AccelSpec,
    policy: UpdatePolicy,
    frame: &Frame,
) -> Result<UpdateReport> {
    let eye = Some(frame.camera.position);
    match live {
        None => {
            let (built, time) =
                LiveAccel::build(spec, policy, &frame.mesh, eye).with_context(|| format!("cannot build {spec}"))?;
            *live = Some(built);
            Ok(UpdateReport { action: UpdateAction::Rebuilt, time, cost_ratio: Some(1.0) })
        }
        Some(l) => l.update(&frame.mesh, eye).with_context(|| format!("cannot update {spec}")),
    }
}

impl GpuTracer {
    /// The device tree's update under the policy (see the module's text).
    fn device_update(&mut self, frame: &Frame) -> Result<UpdateReport> {
        let mesh = &frame.mesh;
        let t = Instant::now();
        let first = !self.has_tree && self.fresh.is_none();
        let same = !first && mesh.positions == self.positions && mesh.indices == self.indices;
        if same {
            return Ok(UpdateReport { action: UpdateAction::Kept, time: t.elapsed(), cost_ratio: self.last_ratio });
        }
        let topology_changed = mesh.indices != self.indices;
        self.positions.clone_from(&mesh.positions);
        self.indices.clone_from(&mesh.indices);
        if first || topology_changed || self.policy == UpdatePolicy::Rebuild {
            return self.rebuild(frame, t);
        }
        let tree = match self.fresh.as_mut() {
            Some(tree) => tree,
            None => self.renderer.tree_mut().context("the device tree is gone")?,
        };
        tree.refit(mesh).context("cannot refit the BVH on the GPU")?;
        let UpdatePolicy::Auto { max_cost_ratio } = self.policy else {
            self.last_ratio = None;
            return Ok(UpdateReport { action: UpdateAction::Refit, time: t.elapsed(), cost_ratio: None });
        };
        let cost = tree.download(mesh, &self.params).context("cannot read the refit tree back")?.stats().sah_cost;
        let ratio = match (cost, self.built_cost) {
            (Some(c), Some(b)) if b > 0.0 => Some(c / b),
            _ => None,
        };
        if ratio.is_some_and(|r| r > max_cost_ratio) {
            return self.rebuild(frame, t);
        }
        self.last_ratio = ratio;
        Ok(UpdateReport { action: UpdateAction::Refit, time: t.elapsed(), cost_ratio: ratio })
    }

    /// A fresh device build, timed from `t`.
    fn rebuild(&mut self, frame: &Frame, t: Instant) -> Result<UpdateReport> {
        let mesh = &frame.mesh;
        let (tree, _) = GpuBvh::build(self.ctx.clone(), mesh, self.build, &self.params)
            .with_context(|| format!("cannot build {} on the GPU ({} build)", self.spec, self.build))?;
        if matches!(self.policy, UpdatePolicy::Auto { .. }) {
            self.built_cost = tree.download(mesh, &self.params).context("cannot read the tree back")?.stats().sah_cost;
        }
        self.fresh = Some(tree);
        self.last_ratio = self.built_cost.map(|_| 1.0);
        Ok(UpdateReport { action: UpdateAction::Rebuilt, time: t.elapsed(), cost_ratio: self.last_ratio })
    }
}
