//! `dynray render`: scene, mesh or distance-field file (or the built-in demo) -> image.

use super::fields::{render, render_aov, Fields};
use super::thousands;
use crate::cli::RenderArgs;
use anyhow::{bail, Context, Result};
use dynray_accel::{Bvh, UpdatePolicy};
use dynray_adf::AdfGeometry;
use dynray_gpu::{GpuBuild, GpuBvh, GpuContext, GpuOptions, GpuRenderOptions, GpuRenderer};
use dynray_render::{
    build_live_scene, render_with, write_aov, write_image, AovIntegrator, IntegratorKind, IntegratorParams,
    OutputFormat, RenderOptions, SceneIntersector,
};
use dynray_scene::{Camera, Frame, Shading};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::path::Path;
use std::sync::Arc;
use std::time::{Duration, Instant};

pub fn run(a: RenderArgs) -> Result<()> {
    // Check the output name before any work, so a typo fails at once.
    match (OutputFormat::from_path(&a.output), a.aov) {
        (None, _) => bail!("{}: unknown image type (expected .png, .bmp or .exr)", a.output.display()),
        (Some(f), Some(aov)) if f != OutputFormat::Exr => {
            bail!("{}: --aov {aov} writes float data: use an .exr output", a.output.display())
        }
        _ => {}
    }
    // A distance field is rendered in the scene its source mesh would have had.
    let field = match &a.scene {
        Some(p) if super::adf::is_adf(p) => Some(super::adf::load(p)?),
        _ => None,
    };
    let (mut scene, label) = match (&a.scene, &field) {
        (Some(p), Some(adf)) => (super::adf::scene_of(adf), p.display().to_string()),
        (Some(p), None) => (super::load_unshaded(p)?, p.display().to_string()),
        (None, _) => (dynray_scene::demo::demo_scene(), "built-in demo scene".to_string()),
    };
    // Before applying the shading, so that no normals are generated only to be dropped.
    if a.flat_shading {
        for actor in &mut scene.actors {
            actor.shading = Shading::Flat;
        }
    }
    super::apply_shading(&mut scene, Path::new(&label))?;
    let time = super::time::apply(&mut scene, &label, &a.when)?;
    let mut frame = scene.frame(time);
    let mut world = super::physics::world(&scene, &label)?;
    super::physics::simulate(world.as_mut(), time, &mut frame, &label)?;
    let s = &mut frame.settings;
    if let Some(w) = a.width {
        s.width = w;
    }
    if let Some(h) = a.height {
        s.height = h;
    }
    if let Some(d) = a.max_depth {
        // The path tracer counts segments (Mitsuba's max_depth), Whitted ray levels: the
        // same light paths are level D - 1 (dynray_render::PathTracer's docs).
        s.max_recursion_level = if a.integrator == IntegratorKind::Path { d - 1 } else { d };
    }
    let spp = a.spp.or(s.spp).unwrap_or(crate::cli::DEFAULT_SPP).min(crate::cli::MAX_SPP);
    let (params, passes) = cumulative_flags(&a, spp)?;
    if let Some(m) = a.min_weight {
        if !m.is_finite() {
            bail!("--min-weight must be a finite number, got {m}");
        }
        s.min_weight = m;
    }
    // The flags are range-checked by clap; a scene file's settings are checked here.
    let max = dynray_render::MAX_IMAGE_EDGE;
    for (what, v) in [("width", s.width), ("height", s.height)] {
        if v == 0 || v > max {
            bail!("{label}: image {what} {v} is outside 1..={max} (set --{what} to override the scene's settings)");
        }
    }

    a.backend.check()?;
    if let Some(adf) = &field {
        let options =
            RenderOptions { spp, seed: a.seed, integrator: a.integrator, params, passes, ..Default::default() };
        let material = frame.materials.first().cloned().unwrap_or_default();
        if let Some(gpu) = a.backend.gpu_options() {
            return render_field_on_gpu(&a, &frame, &label, adf, material, &gpu);
        }
        let scene = SceneIntersector::new(vec![Box::new(AdfGeometry::new(adf, material))]);
        let what = format!(
            "distance field of max level {} ({} internal cells)",
            adf.max_level(),
            thousands(adf.internal_cells() as usize)
        );
        return render_geometry(&a, &frame, &label, (&scene, what), &options);
    }
    let fields = Fields::load(&frame.distance_fields, &label)?;
    if !fields.is_empty() {
        if a.backend.gpu_options().is_some() {
            bail!("{label}: scenes with `adf` blocks render on the CPU only; drop --backend gpu");
        }
        if scene.camera.is_none() {
            // Only fields, no mesh: the default view frames them.
            frame.camera = Camera::framing(&fields.bounds(&frame).union(&frame.mesh.bounds()));
        }
    }
    if !fields.is_empty() && frame.mesh.triangle_count() == 0 {
        // Nothing for a structure to hold: the fields are the whole scene.
        let options =
            RenderOptions { spp, seed: a.seed, integrator: a.integrator, params, passes, ..Default::default() };
        let what = fields.describe(&frame).trim_start_matches(" and ").to_string();
        return render_geometry(&a, &frame, &label, (&fields.fields_only(&frame), what), &options);
    }
    if let Some(gpu) = a.backend.gpu_options() {
        return render_on_gpu(&a, &frame, &label, (spp, passes, params), &gpu);
    }
    // The same layout `animate` uses, so `render --frame K` draws its frame K (a frame
    // without moving actors is one structure whatever the layout).
    let (live, build) = build_live_scene(&a.accel, UpdatePolicy::default(), a.scene_accel, &scene, &frame)
        .with_context(|| format!("{label}: cannot build {}", a.accel))?;
    let accel = live.accel();
    // The layout follows the build time, so the summary's "N triangles, bvh build" stays.
    let layout = match live.two_level() {
        Some(_) => format!(" ({})", live.describe()),
        None => String::new(),
    };

    let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::hidden());
    bar.set_style(ProgressStyle::with_template("{bar:40} {percent:>3}% {elapsed} (eta {eta})").unwrap());
    let started = Instant::now();
    // Only renders longer than a moment get a bar; indicatif hides it when stderr is no terminal.
    let progress = |done: usize, total: usize| {
        if bar.is_hidden() && started.elapsed() > Duration::from_millis(300) && done < total {
            bar.set_draw_target(ProgressDrawTarget::stderr());
        }
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    };
    let options = RenderOptions {
        progress: Some(&progress),
        spp,
        seed: a.seed,
        integrator: a.integrator,
        params,
        passes,
        ..Default::default()
    };
    let t1 = Instant::now();
    if let Some(aov) = a.aov {
        let film = render_aov(&frame, accel, &fields, aov, &options);
        let trace = t1.elapsed();
        bar.finish_and_clear();
        write_aov(&film, aov, &a.output)?;
        eprintln!(
            "{label}: {} triangles{}, {} build {:.1} ms{layout}, {aov} AOV {:.1} ms ({}x{}) -> {}",
            thousands(frame.mesh.triangle_count()),
            fields.describe(&frame),
            accel.name(),
            build.as_secs_f64() * 1e3,
            trace.as_secs_f64() * 1e3,
            film.width(),
            film.height(),
            a.output.display()
        );
        return Ok(());
    }
    let (film, stats) = render(&frame, accel, &fields, &options);
    let trace = t1.elapsed();
    bar.finish_and_clear();
    write_image(&film, &a.output)?;

    let secs = trace.as_secs_f64().max(1e-9);
    let samples = if passes > 1 { format!("{spp} spp × {passes} passes") } else { format!("{spp} spp") };
    eprintln!(
        "{label}: {} triangles{}, {} build {:.1} ms{layout}, {} render {:.1} ms ({}x{}, {samples}, {} rays, {:.2} Mrays/s) -> {}",
        thousands(frame.mesh.triangle_count()),
        fields.describe(&frame),
        accel.name(),
        build.as_secs_f64() * 1e3,
        a.integrator,
        secs * 1e3,
        film.width(),
        film.height(),
        thousands(stats.total_rays() as usize),
        stats.total_rays() as f64 / secs / 1e6,
        a.output.display()
    );
    Ok(())
}

/// Geometry other than the frame's triangles — an `.adf` file alone, or a `.scn` of
/// `adf` blocks and no mesh — through the same render loop, integrators and AOVs;
/// `what` describes it for the summary line.
fn render_geometry(
    a: &RenderArgs,
    frame: &Frame,
    label: &str,
    (scene, what): (&SceneIntersector<'_>, String),
    options: &RenderOptions<'_>,
) -> Result<()> {
    let t0 = Instant::now();
    let done = if let Some(aov) = a.aov {
        let one = RenderOptions { spp: 1, passes: 1, ..*options };
        let film = render_with(frame, &AovIntegrator::new(aov, scene), &one).0;
        write_aov(&film, aov, &a.output)?;
        format!("{aov} AOV")
    } else {
        let integrator = a.integrator.create(frame, scene, &options.params);
        let film = render_with(frame, integrator.as_ref(), options).0;
        write_image(&film, &a.output)?;
        format!("{} render", a.integrator)
    };
    eprintln!(
        "{label}: {what}, {done} {:.1} ms ({}x{}) -> {}",
        t0.elapsed().as_secs_f64() * 1e3,
        frame.settings.width,
        frame.settings.height,
        a.output.display()
    );
    Ok(())
}

/// `render FILE.adf --backend gpu --aov A`: the field uploaded, the camera rays marched
/// on the device (field_on_gpu.rs), through the same render loop as on the CPU.
fn render_field_on_gpu(
    a: &RenderArgs,
    frame: &Frame,
    label: &str,
    adf: &dynray_adf::Adf,
    material: dynray_scene::Material,
    gpu: &GpuOptions,
) -> Result<()> {
    let Some(aov) = a.aov else {
        bail!(
            "{label}: on the GPU a distance field renders its AOVs (--aov depth, normal, prim or albedo); \
             shaded images of fields render on the CPU (drop --backend gpu)"
        );
    };
    let t0 = Instant::now();
    let ctx = Arc::new(GpuContext::new(gpu)?);
    let device = dynray_gpu::GpuAdf::upload(ctx.clone(), adf).with_context(|| format!("{label}: cannot upload"))?;
    let upload = t0.elapsed();
    let integrator =
        super::field_on_gpu::DeviceFieldAov { aov, device: &device, geometry: AdfGeometry::new(adf, material) };
    let t1 = Instant::now();
    let one = RenderOptions { spp: 1, passes: 1, seed: a.seed, ..Default::default() };
    let film = render_with(frame, &integrator, &one).0;
    let trace = t1.elapsed();
    write_aov(&film, aov, &a.output)?;
    eprintln!(
        "{label}: distance field of max level {} on {}, upload {:.1} ms, {aov} AOV {:.1} ms ({}x{}) -> {}",
        adf.max_level(),
        ctx.adapter().name,
        upload.as_secs_f64() * 1e3,
        trace.as_secs_f64() * 1e3,
        film.width(),
        film.height(),
        a.output.display()
    );
    Ok(())
}

/// `--branch-depth` and `--passes`: the cumulative integrator's flags. Given with another
/// integrator they are an error rather than silently ignored (Whitted is deterministic,
/// so passes would only repeat it; the path tracer takes more samples with --spp).
fn cumulative_flags(a: &RenderArgs, spp: u32) -> Result<(IntegratorParams, u32)> {
    if a.integrator != IntegratorKind::Cumulative {
        for (flag, given) in [("--branch-depth", a.branch_depth.is_some()), ("--passes", a.passes.is_some())] {
            if given {
                bail!("{flag} applies to --integrator cumulative only (got `{}`)", a.integrator);
            }
        }
    }
    let passes = a.passes.unwrap_or(1);
    let max = crate::cli::MAX_SPP;
    if spp as u64 * passes as u64 > max as u64 {
        bail!("--passes {passes} × {spp} spp is {} samples per pixel, more than {max}", spp as u64 * passes as u64);
    }
    let params = IntegratorParams { branch_depth: a.branch_depth.unwrap_or(IntegratorParams::default().branch_depth) };
    Ok((params, passes))
}

/// `--backend gpu`: the frame's BVH built where `--gpu-build` says (on the CPU and
/// uploaded, or on the device), traced and shaded there by the chosen strategy (Whitted
/// shading, as the CPU's).
fn render_on_gpu(
    a: &RenderArgs,
    frame: &Frame,
    label: &str,
    (spp, passes, params): (u32, u32, IntegratorParams),
    gpu: &GpuOptions,
) -> Result<()> {
    let cpu_options = RenderOptions { integrator: a.integrator, params, passes, ..Default::default() };
    let integrator = super::animate_tracer::gpu_integrator(&cpu_options, a.gpu_strategy)?;
    if a.aov.is_some() {
        bail!("--aov is rendered on the CPU only; drop --backend gpu");
    }
    let cannot_build = || format!("{label}: cannot build {}", a.accel);
    let params = a.accel.binary_bvh_params().with_context(cannot_build)?;
    let ctx = Arc::new(GpuContext::new(gpu)?);
    let mut renderer = GpuRenderer::new(ctx.clone())?;
    let options = GpuRenderOptions { strategy: a.gpu_strategy, spp, seed: a.seed, integrator, passes };
    let t0 = Instant::now();
    let how = a.backend.gpu_build;
    let (out, build) = if how == GpuBuild::Cpu {
        let bvh = Bvh::build(&frame.mesh, &params).with_context(cannot_build)?;
        let build = t0.elapsed();
        (renderer.render(frame, &bvh, &options), build)
    } else {
        let (tree, _) = GpuBvh::build(ctx.clone(), &frame.mesh, how, &params).with_context(cannot_build)?;
        let build = t0.elapsed();
        (renderer.render_device_tree(frame, tree, &options), build)
    };
    let out = out.with_context(|| format!("{label}: cannot render on the GPU"))?;
    write_image(&out.film, &a.output)?;
    let secs = out.timings.total.max(1e-9);
    let samples = if passes > 1 { format!("{spp} spp × {passes} passes") } else { format!("{spp} spp") };
    eprintln!(
        "{label}: {} triangles, bvh build ({how}) {:.1} ms, {} {} on {} {:.1} ms ({}x{}, {samples}, {} rays, {:.2} Mrays/s) -> {}",
        thousands(frame.mesh.triangle_count()),
        build.as_secs_f64() * 1e3,
        a.integrator,
        a.gpu_strategy,
        ctx.adapter().name,
        secs * 1e3,
        out.film.width(),
        out.film.height(),
        thousands(out.stats.total_rays() as usize),
        out.stats.total_rays() as f64 / secs / 1e6,
        a.output.display()
    );
    Ok(())
}
