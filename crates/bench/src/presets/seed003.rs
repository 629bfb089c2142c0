//! `--preset seed003`: seed 003's CPU-vs-accelerated experiment (Tables 4.2–4.8) on this
//! machine: a single-threaded brute-force tracer against the parallel tracer over an
//! acceleration structure, for ray casting (level 1: primary + shadow rays) and Whitted
//! ray tracing at maximum recursion levels 2..=10, reported as speed-ups.
//!
//! The seed's baseline was a single-threaded BVH tracer and its accelerated side a GPU; we
//! keep its question (how much faster is the accelerated, parallel tracer than the plain
//! one) with the brute-force oracle as the plain side, as the bench's task states. Both
//! sides render the same frame and must produce the same image.

use crate::measure::ms;
use crate::report::{Mismatch, Seed003Level, Seed003Result, Seed003Scene};
use crate::run::{load_scenes, progress_bar, BenchConfig};
use crate::variant::AccelVariant;
use anyhow::{Context, Result};
use dynray_accel::Brute;
use dynray_render::{render, RenderOptions};
use std::time::Instant;

/// The seed's image size.
pub const SEED_SIZE: (u32, u32) = (640, 480);

/// Runs the preset on the configured scenes (default: cornell-box and bunny; quick:
/// cornell-box and dragon-res4 at 64×48).
pub fn run(
    config: &BenchConfig,
    accels: &[AccelVariant],
    notes: &mut Vec<String>,
    mismatches: &mut Vec<Mismatch>,
) -> Result<Seed003Result> {
    let names: Vec<String> = if !config.scenes.is_empty() {
        config.scenes.clone()
    } else if config.quick {
        vec!["cornell-box".into(), "dragon-res4".into()]
    } else {
        vec!["cornell-box".into(), "bunny".into()]
    };
    let (width, height) = if config.size_given {
        (config.width, config.height)
    } else if config.quick {
        (64, 48)
    } else {
        SEED_SIZE
    };
    if (width, height) != SEED_SIZE {
        notes.push(format!(
            "seed003: rendered at {width}×{height} instead of the seed's 640×480 (brute force is slow); \
             speed-ups at a lower resolution are not directly comparable with the seed's tables."
        ));
    }
    let accel_v = super::accelerated(accels);
    let single = rayon::ThreadPoolBuilder::new().num_threads(1).build().context("cannot start a 1-thread pool")?;
    let scenes = load_scenes(&names, config.scenes_dir.as_deref())?;
    let bar = progress_bar(config.progress, (scenes.len() * 10) as u64);
    let mut out = Vec::new();
    for sc in &scenes {
        let mut frame = sc.frame.clone();
        frame.settings.width = width;
        frame.settings.height = height;
        let brute = Brute::build(&frame.mesh).with_context(|| format!("{}: cannot build brute", sc.name))?;
        let accel =
            accel_v.build_in(&frame).with_context(|| format!("{}: cannot build {}", sc.name, accel_v.label()))?;
        let mut levels = Vec::new();
        for level in 1..=10u32 {
            bar.set_message(format!("seed003 {} level {level}", sc.name));
            frame.settings.max_recursion_level = level;
            let t = Instant::now();
            let (film_b, stats) = single.install(|| render(&frame, &brute, &RenderOptions::default()));
            let brute_ms = ms(t);
            let t = Instant::now();
            let (film_a, _) = render(&frame, accel.as_ref(), &RenderOptions::default());
            let accel_ms = ms(t);
            let identical = film_a.pixels() == film_b.pixels();
            if !identical {
                let i = film_a.pixels().iter().zip(film_b.pixels()).position(|(a, b)| a != b).unwrap_or(0);
                mismatches.push(Mismatch {
                    scene: sc.name.clone(),
                    accel: accel_v.label(),
                    kind: format!("seed003 render level {level}"),
                    ray_index: i,
                    ray: [0.0; 8],
                    expected: format!("pixel {:?}", film_b.pixels()[i].to_array()),
                    got: format!("pixel {:?}", film_a.pixels()[i].to_array()),
                });
            }
            levels.push(Seed003Level {
                level,
                rays: stats.total_rays(),
                brute_single_ms: brute_ms,
                accel_parallel_ms: accel_ms,
                speedup: if accel_ms > 0.0 { brute_ms / accel_ms } else { 0.0 },
                images_identical: identical,
            });
            bar.inc(1);
        }
        out.push(Seed003Scene {
            name: sc.name.clone(),
            triangles: frame.mesh.triangle_count(),
            lights: frame.lights.len(),
            levels,
        });
    }
    bar.finish_and_clear();
    Ok(Seed003Result { width, height, accel: accel_v.label(), threads: rayon::current_num_threads(), scenes: out })
}
