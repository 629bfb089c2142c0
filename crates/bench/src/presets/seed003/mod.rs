//! `--preset seed003`: seed 003's CPU-vs-GPU experiment (Tables 4.2–4.8) on this machine.
//! The seed's baseline is a single-threaded Whitted tracer over a binned-SAH BVH and its
//! accelerated side the same tracer on a GPU; here the baseline is our tracer on one
//! thread and the accelerated side the same tracer on every thread, so the speed-up (SP)
//! and efficiency (EF = SP / threads) mean what the seed's do, with 2 cores instead of
//! 128 stream processors. Single-threaded brute force is timed too where the scene is
//! small enough (it is quadratic: rays × triangles), to show what the structure buys.
//!
//! Level 1 is ray casting (primary + shadow rays: the seed's Table 4.2, and the "0 nível"
//! row of its Table 4.8); levels 2–10 are Whitted ray tracing with that maximum recursion
//! level. Every render of a level must produce the same image.

pub mod results;
mod strategies;
mod sweeps;

use crate::config::BenchConfig;
use crate::format::{num, thousands};
use crate::gpu::{self, GpuSession};
use crate::line_chart::{LineChart, Panel, Series};
use crate::measure::ms;
use crate::presets::experiment::{Experiment, Lab};
use crate::progress::progress_bar;
use crate::results::{median, Mismatch};
use crate::scenes::load_scenes;
use anyhow::{Context, Result};
use dynray_accel::AccelSpec;
use dynray_accel::{Accel, Brute, Bvh};
use dynray_render::{render, Film, RenderOptions};
use dynray_scene::Frame;
use results::{Seed003Level, Seed003Result, Seed003Scene};
use std::fmt::Write;
use std::time::Instant;

/// The seed's image size.
pub const SEED_SIZE: (u32, u32) = (640, 480);

/// Brute force is timed only up to this many triangles: at 640×480 and ten levels it
/// costs about `rays × triangles` tests, minutes beyond a few thousand triangles.
pub const BRUTE_MAX_TRIANGLES: usize = 2_000;

/// Maximum recursion levels measured.
pub const LEVELS: u32 = 10;

/// Runs the preset on the configured scenes (default: the Cornell box, the demo's mirror
/// and glass spheres — the seed's "Bolas" — and the bunny — its "Coelhos0101"; quick:
/// the Cornell box and dragon-res4 at 64×48).
pub fn run(
    config: &BenchConfig,
    accels: &[AccelSpec],
    mut gpu: Option<&mut GpuSession>,
    notes: &mut Vec<String>,
    mismatches: &mut Vec<Mismatch>,
) -> Result<Seed003Result> {
    let names: Vec<String> = if !config.scenes.is_empty() {
        config.scenes.clone()
    } else if config.quick {
        vec!["cornell-box".into(), "dragon-res4".into()]
    } else {
        vec!["cornell-box".into(), "demo".into(), "bunny".into()]
    };
    let (width, height) = if config.size_given {
        (config.width, config.height)
    } else if config.quick {
        (64, 48)
    } else {
        SEED_SIZE
    };
    if (width, height) != SEED_SIZE {
        notes.push(format!("seed003: rendered at {width}×{height} instead of the seed's 640×480."));
    }
    let accel_v = super::accelerated(accels);
    let single = rayon::ThreadPoolBuilder::new().num_threads(1).build().context("cannot start a 1-thread pool")?;
    let threads = rayon::current_num_threads();
    let scenes = load_scenes(&names, config.scenes_dir.as_deref())?;
    // The sweeps run on the seed's "Bolas" stand-in where it is measured, else the first scene.
    let sweep_scene = scenes.iter().position(|s| s.name == "demo").unwrap_or(0);
    // With the GPU, each scene's builds are one more step.
    let per_scene = LEVELS as usize + usize::from(gpu.is_some());
    let bar = progress_bar(config.progress, (scenes.len() * per_scene + sweeps::steps(config.quick)) as u64);
    let mut out = Vec::new();
    let mut sweep_result = None;
    for (si, sc) in scenes.iter().enumerate() {
        let mut frame = sc.frame.clone();
        frame.settings.width = width;
        frame.settings.height = height;
        let mut builds = Vec::new();
        let mut accel = accel_v
            .build(&frame.mesh, Some(frame.camera.position))
            .with_context(|| format!("{}: cannot build {}", sc.name, accel_v))?;
        for _ in 0..config.repeat.max(1) {
            drop(accel);
            let t = Instant::now();
            accel = accel_v.build(&frame.mesh, Some(frame.camera.position))?;
            builds.push(ms(t));
        }
        // The GPU renders through the CPU's BVH, uploaded once (the seed's set-up).
        let gpu_params = gpu::bvh_params(&accel_v)?;
        let gpu_bvh = match gpu {
            Some(_) => {
                Some(Bvh::build(&frame.mesh, &gpu_params).with_context(|| format!("{}: cannot build bvh", sc.name))?)
            }
            None => None,
        };
        let brute = if frame.mesh.triangle_count() <= BRUTE_MAX_TRIANGLES {
            Some(Brute::build(&frame.mesh).with_context(|| format!("{}: cannot build brute", sc.name))?)
        } else {
            None
        };
        let mut levels = Vec::new();
        for level in 1..=LEVELS {
            bar.set_message(format!("seed003 {} level {level}", sc.name));
            frame.settings.max_recursion_level = level;
            let timed = |a: &dyn Accel, pool: Option<&rayon::ThreadPool>| timed_render(&frame, a, pool, config.repeat);
            let (single_ms, film_1, rays) = timed(accel.as_ref(), Some(&single));
            let (parallel_ms, film_n, _) = timed(accel.as_ref(), None);
            let brute_run = brute.as_ref().map(|b| timed(b, Some(&single)));
            let mut identical =
                compare(&film_1, &film_n, &sc.name, &accel_v.to_string(), level, "1 thread", mismatches);
            if let Some((_, film_b, _)) = &brute_run {
                identical &= compare(film_b, &film_n, &sc.name, &accel_v.to_string(), level, "brute force", mismatches);
            }
            let speedup = if parallel_ms > 0.0 { single_ms / parallel_ms } else { 0.0 };
            let brute_ms = brute_run.map(|(t, _, _)| t);
            let gpu_runs = match (gpu.as_deref_mut(), &gpu_bvh) {
                (Some(g), Some(b)) => {
                    let what = format!("level {level}");
                    let shot = strategies::CpuShot { scene: &sc.name, what: &what, film: &film_n, single_ms };
                    strategies::strategies(g, &frame, b, &shot, config.repeat, mismatches)?
                }
                _ => Vec::new(),
            };
            levels.push(Seed003Level {
                level,
                rays,
                accel_single_ms: single_ms,
                accel_parallel_ms: parallel_ms,
                speedup,
                efficiency: speedup / threads as f64,
                brute_single_ms: brute_ms,
                brute_speedup: brute_ms.filter(|_| parallel_ms > 0.0).map(|b| b / parallel_ms),
                images_identical: identical,
                gpu: gpu_runs,
            });
            bar.inc(1);
        }
        if si == sweep_scene {
            bar.set_message(format!("seed003 {}: lights and image size", sc.name));
            let input = sweeps::SweepInput {
                scene: &sc.name,
                frame: &frame,
                accel: accel.as_ref(),
                label: &accel_v.to_string(),
                single: &single,
                threads,
                repeat: config.repeat,
                quick: config.quick,
                gpu_bvh: gpu_bvh.as_ref(),
            };
            sweep_result = Some(sweeps::run(&input, gpu.as_deref_mut(), mismatches, &|| bar.inc(1))?);
        }
        let (cpu_single_build_ms, gpu_builds) = match gpu.as_deref_mut() {
            Some(g) => {
                bar.set_message(format!("seed003 {}: builds on the GPU", sc.name));
                let (single_ms, builds) = strategies::builds(g, &frame, &gpu_params, &single, config.repeat, &sc.name)?;
                bar.inc(1);
                (Some(single_ms), builds)
            }
            None => (None, Vec::new()),
        };
        out.push(Seed003Scene {
            name: sc.name.clone(),
            triangles: frame.mesh.triangle_count(),
            lights: frame.lights.len(),
            build_ms: median(&builds),
            levels,
            cpu_single_build_ms,
            gpu_builds,
        });
    }
    bar.finish_and_clear();
    Ok(Seed003Result {
        width,
        height,
        accel: accel_v.to_string(),
        threads,
        brute_max_triangles: BRUTE_MAX_TRIANGLES,
        scenes: out,
        sweeps: sweep_result,
        gpu_adapter: gpu.map(|g| g.ctx.adapter().name.clone()),
    })
}

/// Renders `frame` `repeat` times on `pool` (`None`: the current pool, every thread):
/// the median time in ms, the last image and the rays it traced.
pub(super) fn timed_render(
    frame: &Frame,
    accel: &dyn Accel,
    pool: Option<&rayon::ThreadPool>,
    repeat: usize,
) -> (f64, Film, u64) {
    let mut runs = Vec::new();
    let mut last = None;
    for _ in 0..repeat.max(1) {
        let t = Instant::now();
        let out = match pool {
            Some(p) => p.install(|| render(frame, accel, &RenderOptions::default())),
            None => render(frame, accel, &RenderOptions::default()),
        };
        runs.push(ms(t));
        last = Some(out);
    }
    let (film, stats) = last.expect("at least one run");
    (median(&runs), film, stats.total_rays())
}

/// Records a [`Mismatch`] when `other` differs from the parallel image `reference`;
/// returns whether they are identical.
pub(super) fn compare(
    other: &Film,
    reference: &Film,
    scene: &str,
    accel: &str,
    level: u32,
    what: &str,
    mismatches: &mut Vec<Mismatch>,
) -> bool {
    let Some(i) = other.pixels().iter().zip(&reference.pixels()).position(|(a, b)| a != b) else {
        return true;
    };
    mismatches.push(Mismatch {
        scene: scene.to_string(),
        accel: accel.to_string(),
        kind: format!("seed003 render level {level}: {what} vs parallel"),
        ray_index: i,
        ray: [0.0; 8],
        expected: format!("pixel {:?}", other.pixels()[i].to_array()),
        got: format!("pixel {:?}", reference.pixels()[i].to_array()),
    });
    false
}

/// The preset's section of report.md.
pub fn markdown(p: &Seed003Result, png: bool, s: &mut String) {
    let _ = writeln!(
        s,
        "## seed003: one thread against {} threads, {} (seed 003, Tables 4.2–4.8)\n\n\
         {}×{}. Level 1 is ray casting (primary + shadow rays: Table 4.2, and Table 4.8's \"0 nível\"); \
         levels 2–10 are Whitted ray tracing with that maximum recursion level. Renders with the structure \
         prebuilt, medians. SP = 1-thread time / {}-thread time (the seed's CPU/GPU ratio), EF = SP / {}. \
         Brute force (1 thread) only up to {} triangles.\n",
        p.threads,
        p.accel,
        p.width,
        p.height,
        p.threads,
        p.threads,
        thousands(p.brute_max_triangles as u64)
    );
    let ext = if png { "png" } else { "svg" };
    let _ = writeln!(s, "![seed003](seed003-speedup.{ext})\n");
    for sc in &p.scenes {
        let _ = writeln!(
            s,
            "### {} — {} triangles, {} light(s), {} build {} ms\n\n\
             | level | rays | 1 thread ms | {} threads ms | SP | EF | brute 1 thread ms | brute / parallel | same image |\n\
             |--:|--:|--:|--:|--:|--:|--:|--:|:-:|",
            sc.name,
            thousands(sc.triangles as u64),
            sc.lights,
            p.accel,
            num(sc.build_ms),
            p.threads
        );
        for l in &sc.levels {
            let dash = || "—".to_string();
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {:.2} | {:.2} | {} | {} | {} |",
                l.level,
                thousands(l.rays),
                num(l.accel_single_ms),
                num(l.accel_parallel_ms),
                l.speedup,
                l.efficiency,
                l.brute_single_ms.map(num).unwrap_or_else(dash),
                l.brute_speedup.map(num).unwrap_or_else(dash),
                if l.images_identical { "yes" } else { "**no**" }
            );
        }
        let _ = writeln!(s);
        strategies::markdown(sc, p.gpu_adapter.as_deref().unwrap_or("the GPU"), s);
    }
    if let Some(w) = &p.sweeps {
        sweeps::markdown(w, p.threads, s);
    }
}

/// Three panels: SP by level, single-thread time by level (the seed's CPU-time curve),
/// and brute force over the parallel tracer where measured.
pub fn chart(p: &Seed003Result) -> LineChart {
    let per_scene = |f: &dyn Fn(&Seed003Level) -> Option<f64>| -> Vec<Series> {
        p.scenes
            .iter()
            .map(|sc| Series {
                name: sc.name.clone(),
                points: sc.levels.iter().filter_map(|l| Some((l.level as f64, f(l)?))).collect(),
                reference: false,
            })
            .collect()
    };
    let mut sp = per_scene(&|l| Some(l.speedup));
    sp.push(Series {
        name: format!("ideal ({} threads)", p.threads),
        points: vec![(1.0, p.threads as f64), (LEVELS as f64, p.threads as f64)],
        reference: true,
    });
    let panels = vec![
        Panel { title: format!("SP: 1 thread / {} threads", p.threads), series: sp },
        Panel { title: "1-thread render time, ms".into(), series: per_scene(&|l| Some(l.accel_single_ms)) },
        Panel { title: "brute force (1 thread) / parallel".into(), series: per_scene(&|l| l.brute_speedup) },
    ];
    LineChart {
        caption: format!(
            "seed003: {} at {}x{}, by maximum recursion level (1 = ray casting)",
            p.accel, p.width, p.height
        ),
        x_desc: "maximum recursion level".into(),
        y_desc: String::new(),
        log2_x: false,
        log_y: true,
        y_from_zero: false,
        panels,
    }
}

/// `--preset seed003`: brute force against the accelerated tracer, levels and sweeps.
pub struct Seed003;

impl Experiment for Seed003 {
    const PRESET: crate::config::Preset = crate::config::Preset::Seed003;
    type Output = Seed003Result;

    fn run(ctx: &mut Lab<'_>) -> anyhow::Result<Seed003Result> {
        run(ctx.config, ctx.accels, ctx.gpu.as_deref_mut(), ctx.notes, ctx.mismatches)
    }

    fn markdown(out: &Seed003Result, png: bool, s: &mut String) {
        markdown(out, png, s)
    }

    fn charts(out: &Seed003Result, dir: &std::path::Path, png: bool) -> anyhow::Result<()> {
        crate::charts::save(&chart(out), dir, "seed003-speedup", png).map(drop)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use dynray_accel::AccelKind;
    use dynray_scene::Frame;

    fn film_of(frame: &Frame, accel: &dyn Accel) -> Film {
        render(frame, accel, &RenderOptions::default()).0
    }

    #[test]
    fn differing_images_are_reported_with_the_first_pixel() {
        let mut scene = dynray_scene::demo::demo_scene_with(3);
        scene.add_default_light();
        let mut frame = scene.frame(0.0);
        frame.settings.width = 16;
        frame.settings.height = 12;
        let bvh = AccelKind::Bvh2.build(&frame.mesh).unwrap();
        let a = film_of(&frame, bvh.as_ref());
        let mut m = Vec::new();
        assert!(compare(&a, &a, "demo", "bvh", 1, "1 thread", &mut m));
        assert!(m.is_empty());
        frame.camera.position += dynray_geom::Vec3::splat(0.5);
        let b = film_of(&frame, bvh.as_ref());
        assert!(!compare(&b, &a, "demo", "bvh", 1, "1 thread", &mut m));
        assert_eq!(m.len(), 1);
        assert!(m[0].kind.contains("level 1"));
    }
}
