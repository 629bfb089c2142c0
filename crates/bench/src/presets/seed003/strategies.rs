//! seed003's GPU columns (`--backend gpu`): the seed's three strategies — Alg. 1 the
//! multi-kernel wavefront, Alg. 2 the megakernel, Alg. 3 the hybrid — rendering every
//! level and sweep point against the single-thread CPU tracer (its Tables 4.2–4.8:
//! SP = T_CPU / T_GPU), and the BVH built on the device against the CPU build (its
//! Table 4.9). The GPU renders through the CPU-built tree uploaded once, as the seed
//! timed rendering alone; their images are compared with the CPU's.

use super::results::{Seed003GpuBuild, Seed003GpuRun, Seed003Scene};
use crate::format::{num, thousands};
use crate::gpu::GpuSession;
use crate::measure::warm_then_timed;
use crate::results::{median, Mismatch};
use anyhow::{Context, Result};
use dynray_accel::{Accel, Bvh, BvhParams};
use dynray_gpu::{GpuBuild, GpuBvh, GpuRenderOptions, GpuStrategy};
use dynray_render::{Film, RenderOptions};
use dynray_scene::Frame;
use std::fmt::Write;

/// The seed's order: Alg. 1, 2, 3.
pub const STRATEGIES: [GpuStrategy; 3] = [GpuStrategy::Wavefront, GpuStrategy::Megakernel, GpuStrategy::Hybrid];

/// A pixel differs when a channel is off by more than this.
pub const PIXEL_TOLERANCE: f32 = 1e-3;

/// The CPU's side of one image: what the GPU's is compared with.
pub struct CpuShot<'a> {
    /// Scene name.
    pub scene: &'a str,
    /// Level or sweep point, in words (for a mismatch's description).
    pub what: &'a str,
    /// The CPU's image.
    pub film: &'a Film,
    /// The CPU's time on one thread, ms.
    pub single_ms: f64,
}

/// Every strategy renders `frame` through `bvh`, `repeat` times after a warm-up; each
/// image is compared with the CPU's and its time with the CPU's on one thread. An image off by more than the rule of [`Seed003GpuRun::images_agree`]
/// becomes a [`Mismatch`]; a device error is an error.
pub fn strategies(
    gpu: &mut GpuSession,
    frame: &Frame,
    bvh: &Bvh,
    shot: &CpuShot<'_>,
    repeat: usize,
    mismatches: &mut Vec<Mismatch>,
) -> Result<Vec<Seed003GpuRun>> {
    let defaults = RenderOptions::default();
    let mut out = Vec::new();
    for strategy in STRATEGIES {
        let options = GpuRenderOptions::whitted(strategy, defaults.spp, defaults.seed);
        let mut runs = Vec::new();
        let mut last = None;
        for run in 0..=repeat.max(1) {
            let r = gpu
                .renderer
                .render(frame, bvh, &options)
                .with_context(|| format!("{}: {}: cannot render with {strategy} on the GPU", shot.scene, shot.what))?;
            // The warm-up compiles the kernels for this depth and uploads the frame.
            if run > 0 {
                runs.push((r.timings.total - r.timings.upload) * 1e3);
            }
            last = Some(r);
        }
        let r = last.expect("at least one run");
        let (max_abs_diff, pixels_over_1e3) = difference(shot.film, &r.film);
        let images_agree = pixels_over_1e3 * 100 <= shot.film.pixels().len();
        if !images_agree {
            mismatches.push(Mismatch {
                scene: shot.scene.to_string(),
                accel: format!("bvh (gpu, {strategy})"),
                kind: format!("seed003 {}: GPU image vs CPU", shot.what),
                ray_index: 0,
                ray: [0.0; 8],
                expected: "at most 1 % of the pixels off by over 1e-3".into(),
                got: format!("{pixels_over_1e3} pixels, largest difference {max_abs_diff:e}"),
            });
        }
        let t = median(&runs);
        out.push(Seed003GpuRun {
            strategy: strategy.name().to_string(),
            ms: t,
            rays: r.stats.total_rays(),
            speedup: if t > 0.0 { shot.single_ms / t } else { 0.0 },
            max_abs_diff: max_abs_diff as f64,
            pixels_over_1e3,
            images_agree,
        });
    }
    Ok(out)
}

/// Largest channel difference and pixels over [`PIXEL_TOLERANCE`].
fn difference(a: &Film, b: &Film) -> (f32, usize) {
    let (pa, pb) = (a.pixels(), b.pixels());
    let mut worst = 0f32;
    let mut over = 0;
    for (x, y) in pa.iter().zip(&pb) {
        let d = (*x - *y).abs().max_element();
        // NaN counts as off.
        if d.is_nan() || d > PIXEL_TOLERANCE {
            over += 1;
        }
        worst = worst.max(d);
    }
    (worst, over + pa.len().abs_diff(pb.len()))
}

/// Table 4.9: the BVH over `frame`'s mesh built on 1 thread of the CPU (returned, ms),
/// then by each device builder and by the CPU on every thread with its upload; medians
/// of `repeat` after a warm-up, with each tree's size and SAH cost (read back).
pub fn builds(
    gpu: &GpuSession,
    frame: &Frame,
    params: &BvhParams,
    single: &rayon::ThreadPool,
    repeat: usize,
    scene: &str,
) -> Result<(f64, Vec<Seed003GpuBuild>)> {
    let mesh = &frame.mesh;
    let cannot = |how: GpuBuild| format!("{scene}: cannot build bvh ({how} build)");
    let cpu_build = || single.install(|| Bvh::build(mesh, params)).with_context(|| cannot(GpuBuild::Cpu));
    let cpu_single = median(&warm_then_timed(repeat, cpu_build)?.0);
    let mut out = Vec::new();
    for how in [GpuBuild::Sah, GpuBuild::Lbvh, GpuBuild::Cpu] {
        let gpu_build = || GpuBvh::build(gpu.ctx.clone(), mesh, how, params).with_context(|| cannot(how));
        let (runs, (tree, timings)) = warm_then_timed(repeat, gpu_build)?;
        let stats = tree.download(mesh, params).with_context(|| cannot(how))?.stats();
        let t = median(&runs);
        out.push(Seed003GpuBuild {
            build: how.name().to_string(),
            ms: t,
            cpu_over_this: if t > 0.0 { cpu_single / t } else { 0.0 },
            nodes: stats.nodes,
            sah_cost: stats.sah_cost,
            stages: timings.stages.iter().map(|(n, s)| (n.to_string(), s * 1e3)).collect(),
        });
    }
    Ok((cpu_single, out))
}

/// The header cells of the strategies' columns: `| wavefront ms | SP₁ | …`.
pub fn header() -> (String, String) {
    let mut head = String::new();
    let mut rule = String::new();
    for (i, st) in STRATEGIES.iter().enumerate() {
        let sub = ["₁", "₂", "₃"][i];
        let _ = write!(head, " {st} ms | SP{sub} |");
        rule.push_str("--:|--:|");
    }
    head.push_str(" GPU images agree |");
    rule.push_str(":-:|");
    (head, rule)
}

/// One row's strategy cells (`—` where the GPU did not run).
pub fn cells(runs: &[Seed003GpuRun]) -> String {
    let mut s = String::new();
    for st in STRATEGIES {
        match runs.iter().find(|r| r.strategy == st.name()) {
            Some(r) => {
                let _ = write!(s, " {} | {} |", num(r.ms), num(r.speedup));
            }
            None => s.push_str(" — | — |"),
        }
    }
    let agree = if runs.is_empty() {
        "—"
    } else if runs.iter().all(|r| r.images_agree) {
        "yes"
    } else {
        "**no**"
    };
    let _ = write!(s, " {agree} |");
    s
}

/// A scene's GPU tables in report.md: the strategies by level, then Table 4.9.
pub fn markdown(sc: &Seed003Scene, adapter: &str, s: &mut String) {
    if sc.levels.iter().all(|l| l.gpu.is_empty()) {
        return;
    }
    let (head, rule) = header();
    let _ = writeln!(
        s,
        "GPU on {adapter}: the seed's Alg. 1 (wavefront), Alg. 2 (megakernel) and Alg. 3 (hybrid) through the \
         CPU-built tree, rendering alone (no upload); SP = 1-thread CPU ms / GPU ms (level 1: Tables 4.2–4.3; \
         level 10: Tables 4.5–4.6; by level: Table 4.8). EF is left out: a GPU's processor count is not \
         the seed's 128.\n\n\
         | level | 1 thread ms |{head}\n|--:|--:|{rule}"
    );
    for l in &sc.levels {
        let _ = writeln!(s, "| {} | {} |{}", l.level, num(l.accel_single_ms), cells(&l.gpu));
    }
    let _ = writeln!(s);
    if let Some(cpu) = sc.cpu_single_build_ms {
        let _ = writeln!(
            s,
            "BVH build (Table 4.9): CPU on 1 thread {} ms; aceleração = that / this build's ms.\n\n\
             | build | ms | 1-thread CPU / this | nodes | SAH | stages ms |\n|---|--:|--:|--:|--:|---|",
            num(cpu)
        );
        for b in &sc.gpu_builds {
            let stages: Vec<String> = b.stages.iter().map(|(n, t)| format!("{n} {}", num(*t))).collect();
            let what = match b.build.as_str() {
                "cpu" => "cpu (every thread) + upload".to_string(),
                other => format!("{other} (device)"),
            };
            let _ = writeln!(
                s,
                "| {what} | {} | {} | {} | {} | {} |",
                num(b.ms),
                num(b.cpu_over_this),
                thousands(b.nodes as u64),
                b.sah_cost.map(num).unwrap_or_else(|| "—".into()),
                stages.join(", ")
            );
        }
        let _ = writeln!(s);
    }
}
