//! The GPU side of the tracer seam: a BVH kept on the device and rendered by a seed 003
//! strategy.
//!
//! `--gpu-build cpu` keeps the CPU's BVH current exactly as the CPU backend does
//! ([`LiveAccel`]) and uploads it; `--gpu-build sah|lbvh` builds on the device and
//! follows the same policy implementation ([`PolicyState`]) there: `refit` refits on the
//! device ([`GpuBvh::refit`]), `rebuild` builds afresh, `auto` refits and reads the
//! refit tree back to weigh its SAH cost against the last fresh build's, rebuilding past
//! the bound (the read-back is part of the update's time).

use anyhow::{bail, Context, Result};
use dynray_accel::{
    Accel, AccelSpec, Bvh, BvhParams, LiveAccel, PolicyState, PolicyTarget, UpdateAction, UpdatePolicy, UpdateReport,
};
use dynray_geom::{TriangleMesh, Vec3};
use dynray_gpu::{
    DeviceImage, GpuBuild, GpuBvh, GpuContext, GpuIntegrator, GpuOptions, GpuRenderOptions, GpuRenderer, GpuStrategy,
};
use dynray_render::{Film, IntegratorKind, RenderOptions, RenderStats};
use dynray_scene::Frame;
use std::any::Any;
use std::sync::Arc;
use std::time::Instant;

/// What [`GpuTracer::new`] needs from the front end.
pub struct GpuChoice<'a> {
    /// Adapter options.
    pub options: &'a GpuOptions,
    /// Where the tree is built.
    pub build: GpuBuild,
    /// Seed 003's strategy.
    pub strategy: GpuStrategy,
    /// A device already open (the viewer's window's), used instead of opening the one
    /// `options` names.
    pub context: Option<Arc<GpuContext>>,
}

/// A BVH kept current on the device, and the renderer that traces it.
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
    /// The policy's memory of the device tree (`None` before the first build).
    state: Option<PolicyState>,
    /// The device's time for the last render, seconds (timestamp queries where the
    /// adapter has them).
    last_render: f64,
}

/// The device tree as the update policy drives it: the tree is the fresh one of this
/// frame if any, else the one the renderer holds.
struct DeviceTree<'a> {
    ctx: &'a Arc<GpuContext>,
    renderer: &'a mut GpuRenderer,
    fresh: &'a mut Option<GpuBvh>,
    build: GpuBuild,
    params: &'a BvhParams,
    spec: &'a AccelSpec,
}

impl DeviceTree<'_> {
    fn tree(&mut self) -> Result<&mut GpuBvh> {
        match self.fresh.as_mut() {
            Some(tree) => Ok(tree),
            None => self.renderer.tree_mut().context("the device tree is gone"),
        }
    }
}

impl PolicyTarget for DeviceTree<'_> {
    type Error = anyhow::Error;

    fn rebuild(&mut self, mesh: &TriangleMesh, _eye: Option<Vec3>) -> Result<()> {
        let (tree, _) = GpuBvh::build(self.ctx.clone(), mesh, self.build, self.params)
            .with_context(|| format!("cannot build {} on the GPU ({} build)", self.spec, self.build))?;
        *self.fresh = Some(tree);
        Ok(())
    }

    fn refits(&self) -> bool {
        true
    }

    fn refit(&mut self, mesh: &TriangleMesh, _eye: Option<Vec3>) -> Result<()> {
        self.tree()?.refit(mesh).context("cannot refit the BVH on the GPU")?;
        Ok(())
    }

    fn sah_cost(&mut self, mesh: &TriangleMesh) -> Result<Option<f64>> {
        let params = self.params;
        let tree = self.tree()?;
        Ok(tree.download(mesh, params).context("cannot read the tree back")?.stats().sah_cost)
    }
}

impl GpuTracer {
    /// Opens the device (a BVH; `options` must ask for an integrator the GPU has).
    pub fn new(spec: &AccelSpec, policy: UpdatePolicy, options: &RenderOptions, gpu: GpuChoice<'_>) -> Result<Self> {
        gpu_integrator(options, gpu.strategy)?;
        // The GPU traverses the binary tree: plain `bvh` stands for `bvh2` there.
        let spec = &spec.binary_bvh().with_context(|| format!("cannot build {spec}"))?;
        let params = spec.read().with_context(|| format!("cannot build {spec}"))?;
        let ctx = match gpu.context {
            Some(ctx) => ctx,
            None => Arc::new(GpuContext::new(gpu.options)?),
        };
        let renderer = GpuRenderer::new(ctx.clone())?;
        Ok(GpuTracer {
            ctx,
            renderer,
            strategy: gpu.strategy,
            build: gpu.build,
            params,
            spec: spec.clone(),
            policy,
            live: None,
            fresh: None,
            state: None,
            last_render: 0.0,
        })
    }

    /// Renders of the target's size resolve into `target` on the device instead of being
    /// read back ([`GpuRenderer::set_target`]); `None` reads back.
    pub fn set_target(&mut self, target: Option<Arc<DeviceImage>>) {
        self.renderer.set_target(target);
    }

    /// The device's context, shared.
    pub fn context_arc(&self) -> &Arc<GpuContext> {
        &self.ctx
    }

    /// The device's context (its adapter's name, for summaries).
    pub fn context(&self) -> &GpuContext {
        &self.ctx
    }

    /// The device's time for the last render, in seconds.
    pub fn last_render_seconds(&self) -> f64 {
        self.last_render
    }

    /// Brings the tree to `frame` (built on the first call).
    pub fn update(&mut self, frame: &Frame) -> Result<UpdateReport> {
        let (mesh, spec) = (&frame.mesh, &self.spec);
        if self.build == GpuBuild::Cpu {
            let eye = Some(frame.camera.position);
            return match &mut self.live {
                None => {
                    let (built, time) = LiveAccel::build(spec, self.policy, mesh, eye)
                        .with_context(|| format!("cannot build {spec}"))?;
                    self.live = Some(built);
                    Ok(UpdateReport { action: UpdateAction::Rebuilt, time, cost_ratio: Some(1.0) })
                }
                Some(l) => l.update(mesh, eye).with_context(|| format!("cannot update {spec}")),
            };
        }
        let mut target = DeviceTree {
            ctx: &self.ctx,
            renderer: &mut self.renderer,
            fresh: &mut self.fresh,
            build: self.build,
            params: &self.params,
            spec: &self.spec,
        };
        match &mut self.state {
            Some(state) => state.update(&mut target, mesh, None),
            None => {
                let t = Instant::now();
                target.rebuild(mesh, None)?;
                let state = PolicyState::after_build(self.policy, &mut target, mesh)?;
                self.state = Some(state);
                let ratio = Some(1.0).filter(|_| matches!(self.policy, UpdatePolicy::Auto { .. }));
                Ok(UpdateReport { action: UpdateAction::Rebuilt, time: t.elapsed(), cost_ratio: ratio })
            }
        }
    }

    /// Renders `frame` through the tree [`Self::update`] prepared.
    pub fn render(&mut self, frame: &Frame, options: &RenderOptions) -> Result<(Film, RenderStats)> {
        let o = GpuRenderOptions {
            strategy: self.strategy,
            spp: options.spp,
            seed: options.seed,
            integrator: gpu_integrator(options, self.strategy)?,
            passes: options.passes,
        };
        let out = if let Some(live) = &self.live {
            let any: &dyn Any = live.accel();
            let bvh = any.downcast_ref::<Bvh>().expect("the GPU tracer keeps a bvh");
            self.renderer.render(frame, bvh, &o)
        } else if let Some(tree) = self.fresh.take() {
            self.renderer.render_device_tree(frame, tree, &o)
        } else {
            self.renderer.render_kept_tree(frame, &o)
        };
        let out = out.context("cannot render on the GPU")?;
        self.last_render = out.timings.total;
        Ok((out.film, out.stats))
    }

    /// The structure and where it runs, for the summary line.
    pub fn describe(&self) -> String {
        format!(
            "{} {} on {} ({} build, {})",
            self.spec,
            self.policy,
            self.ctx.adapter().name,
            self.build,
            self.strategy
        )
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
