//! The GPU backend in the standard run: a device tree over the scene (built where
//! `--gpu-build` says), the same ray sets traced through its batch queries, checked
//! against the same brute-force answers, and a Whitted render's time to image — the
//! figures a CPU structure gets, in the same [`StructureResult`] shape.

use super::{bvh_params, GpuSession};
use crate::format::{bytes, num, thousands, with_ratio};
use crate::measure::{measure_kind, ms, warm_then_timed, MeasureInput};
use crate::results::{median, Mismatch, SceneResult, StructureResult};
use anyhow::{Context, Result};
use dynray_accel::{Accel, AccelSpec, BvhParams};
use dynray_gpu::{BuildTimings, GpuBvh, GpuRenderOptions, GpuStrategy};
use dynray_render::RenderOptions;
use std::fmt::Write;
use std::time::Instant;

/// The strategy of the standard run's render (seed 003's multi-kernel wavefront; the
/// seed003 preset times all three).
pub const STRATEGY: GpuStrategy = GpuStrategy::Wavefront;

/// Measures the GPU backend tracing `spec` (a BVH) on one scene; `notes` receive what
/// could not be measured (a frame the GPU strategies cannot shade).
pub fn measure(
    spec: &AccelSpec,
    gpu: &mut GpuSession,
    input: &MeasureInput<'_>,
    mismatches: &mut Vec<Mismatch>,
    notes: &mut Vec<String>,
    step: &dyn Fn(&str),
) -> Result<StructureResult> {
    let label = spec.to_string();
    let params = bvh_params(spec)?;
    let mesh = &input.frame.mesh;
    let cannot = || format!("{}: cannot build {label} on the GPU ({} build)", input.scene, gpu.build);
    step("gpu build");
    let build = || GpuBvh::build(gpu.ctx.clone(), mesh, gpu.build, &params).with_context(cannot);
    let (build_ms_runs, (tree, timings)) = warm_then_timed(input.repeat, build)?;
    // The device's own tree, read back: its shape, and the CPU traversal of the same tree
    // counts the work per ray (the kernels walk it in the same order).
    let host = tree.download(mesh, &params).with_context(cannot)?;
    let stats = host.stats();
    let gpu_label = format!("{label} (gpu)");
    let mut kinds = Vec::new();
    for (kind, rays) in &input.sets.sets {
        step(&format!("gpu {}", kind.name()));
        kinds.push(measure_kind(&tree, &host, &gpu_label, input, *kind, rays, mismatches).0);
    }
    let memory_bytes = tree.memory_bytes() as usize;
    drop(tree);

    let (time_to_image_ms, render_ms, render_rays) = if input.time_to_image {
        step("gpu render");
        match time_to_image(gpu, input, &params) {
            Ok(t) => t,
            Err(e) => {
                notes.push(format!("gpu: {}: no time to image: {e:#}", input.scene));
                (None, None, 0)
            }
        }
    } else {
        (None, None, 0)
    };
    let a = gpu.ctx.adapter();
    let mut extra = vec![
        ("backend".to_string(), "gpu".to_string()),
        ("adapter".to_string(), a.name.clone()),
        ("precision".to_string(), gpu.ctx.precision().name().to_string()),
        ("gpu build".to_string(), gpu.build.name().to_string()),
        ("render strategy".to_string(), STRATEGY.name().to_string()),
    ];
    extra.extend(stage_figures(&timings));
    Ok(StructureResult {
        accel: label,
        build_ms: median(&build_ms_runs),
        build_ms_runs,
        memory_bytes,
        nodes: stats.nodes,
        leaves: stats.leaves,
        max_depth: stats.max_depth,
        primitive_refs: stats.primitive_refs,
        sah_cost: stats.sah_cost,
        extra,
        kinds,
        // The GPU backend traces one ray per invocation: no packet path.
        primary_packets: None,
        time_to_image_ms,
        render_ms,
        render_rays,
        heatmap: None,
    })
}

/// The last build's stages as `extra` entries (`"stage morton ms"`, …).
fn stage_figures(t: &BuildTimings) -> Vec<(String, String)> {
    t.stages.iter().map(|(name, s)| (format!("stage {name} ms"), format!("{:.3}", s * 1e3))).collect()
}

/// Build + render on the device at the bench size, `repeat` times after a warm-up:
/// medians of the whole (the tree's build and upload included) and of the render alone,
/// and the rays the render traced.
fn time_to_image(
    gpu: &mut GpuSession,
    input: &MeasureInput<'_>,
    params: &BvhParams,
) -> Result<(Option<f64>, Option<f64>, u64)> {
    let mut frame = input.frame.clone();
    frame.settings.width = input.width;
    frame.settings.height = input.height;
    let defaults = RenderOptions::default();
    let options = GpuRenderOptions::whitted(STRATEGY, defaults.spp, defaults.seed);
    let (mut tti, mut rend) = (Vec::new(), Vec::new());
    let mut rays = 0;
    for run in 0..=input.repeat.max(1) {
        let t = Instant::now();
        // Every builder hands the renderer a tree already on the device, so each run pays
        // for its tree's upload (`cpu`: built there, then uploaded) as a new frame would.
        let (tree, _) = GpuBvh::build(gpu.ctx.clone(), &frame.mesh, gpu.build, params)?;
        let out = gpu.renderer.render_device_tree(&frame, tree, &options)?;
        // The first run compiles the kernels and uploads the frame: a warm-up.
        if run > 0 {
            tti.push(ms(t));
            rend.push(out.timings.total * 1e3);
        }
        rays = out.stats.total_rays();
    }
    Ok((Some(median(&tti)), Some(median(&rend)), rays))
}

/// The GPU rows of a standard scene's section in report.md: the GPU backend's figures
/// and, in brackets, GPU over CPU for the same structure (> 1: the GPU is faster or
/// smaller — the CPU's ms over the GPU's, the GPU's Mrays/s over the CPU's).
pub fn markdown(sc: &SceneResult, rays: &[String], s: &mut String) {
    if sc.gpu.is_empty() {
        return;
    }
    let extra = |st: &StructureResult, key: &str| {
        st.extra.iter().find(|(k, _)| k == key).map(|(_, v)| v.clone()).unwrap_or_else(|| "?".into())
    };
    let _ = writeln!(
        s,
        "\nOn the GPU ({}, {} test; in brackets GPU/CPU against the same structure's CPU row: > 1 means \
         the GPU is faster):\n",
        extra(&sc.gpu[0], "adapter"),
        extra(&sc.gpu[0], "precision")
    );
    let mut head = "| structure | built on | build ms | memory | nodes | depth | SAH |".to_string();
    let mut rule = "|---|---|--:|--:|--:|--:|--:|".to_string();
    for k in rays {
        let _ = write!(head, " {k} Mrays/s |");
        rule.push_str("--:|");
    }
    head.push_str(" time to image ms | rays checked |");
    rule.push_str("--:|--:|");
    let _ = writeln!(s, "{head}\n{rule}");
    let ratio = |v: String, r: Option<f64>| with_ratio(v, r.filter(|r| r.is_finite()));
    for st in &sc.gpu {
        let cpu = sc.structures.iter().find(|c| c.accel == st.accel);
        let over = |gpu: f64, cpu: Option<f64>| cpu.filter(|_| gpu > 0.0).map(|c| c / gpu);
        let _ = write!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} |",
            st.accel,
            extra(st, "gpu build"),
            ratio(num(st.build_ms), over(st.build_ms, cpu.map(|c| c.build_ms))),
            bytes(st.memory_bytes),
            thousands(st.nodes as u64),
            st.max_depth,
            st.sah_cost.map(num).unwrap_or_else(|| "—".into())
        );
        for k in rays {
            let v = match st.kinds.iter().find(|x| &x.kind == k) {
                Some(x) => {
                    let c = cpu.and_then(|c| c.kinds.iter().find(|y| &y.kind == k)).map(|y| y.mrays_per_s);
                    ratio(num(x.mrays_per_s), c.filter(|c| *c > 0.0).map(|c| x.mrays_per_s / c))
                }
                None => "—".into(),
            };
            let _ = write!(s, " {v} |");
        }
        let tti = st.time_to_image_ms.map(|t| ratio(num(t), over(t, cpu.and_then(|c| c.time_to_image_ms))));
        let checked: usize = st.kinds.iter().map(|k| k.verified).sum();
        let _ = writeln!(s, " {} | {} |", tti.unwrap_or_else(|| "—".into()), thousands(checked as u64));
    }
}
