//! Seed 003's two ray-casting sweeps: the speed-up against the number of lights (its
//! Table 4.3 over scenes 1–5, "Bolas1" … "Bolas16": the same spheres lit by 1 to 16
//! lights) and against the image size (its Table 4.4: scene 3, four lights, 300² to
//! 1024²). Both at level 1 (primary + shadow rays), SP = 1 thread / every thread, as in
//! the level table; every pair of images must be identical.
//!
//! The seed does not say where its lights were; ours stand on a ring above the scene,
//! each with 1/N of a white light so the image keeps its brightness (the cost of a
//! shadow ray does not depend on its light's colour).

use super::results::{Seed003Point, Seed003Sweeps};
use super::strategies::{self, CpuShot};
use super::{compare, timed_render};
use crate::format::{num, thousands};
use crate::gpu::GpuSession;
use crate::results::Mismatch;
use anyhow::Result;
use dynray_accel::{Accel, Bvh};
use dynray_geom::Vec3;
use dynray_scene::{Frame, Light, LightKind};
use std::f32::consts::TAU;
use std::fmt::Write;

/// Light counts of the seed's scenes 1–5.
pub const LIGHTS: [usize; 5] = [1, 2, 4, 8, 16];
/// Image sides of the seed's Table 4.4 (square images).
pub const SIDES: [u32; 4] = [300, 400, 800, 1024];
/// Lights of the resolution sweep: the seed's scene 3 ("Bolas4").
pub const RESOLUTION_LIGHTS: usize = 4;

/// `n` point lights on a ring over the scene's box, together as bright as one white light.
pub fn ring_of_lights(frame: &Frame, n: usize) -> Vec<Light> {
    let b = frame.mesh.bounds();
    let (c, size) = (b.center(), b.extent().length().max(1e-3));
    (0..n)
        .map(|i| {
            let a = TAU * i as f32 / n as f32;
            let position = c + Vec3::new(a.cos() * size, size, a.sin() * size);
            Light {
                kind: LightKind::Point { position, falloff: 0 },
                color: Vec3::splat(1.0 / n as f32),
                emitter_stand_in: false,
            }
        })
        .collect()
}

/// What the sweeps need from the preset's run.
pub struct SweepInput<'a> {
    /// Scene name.
    pub scene: &'a str,
    /// The frame at the preset's image size.
    pub frame: &'a Frame,
    /// The structure, built on `frame`'s mesh (the sweeps change lights and size only).
    pub accel: &'a dyn Accel,
    /// Its label, for mismatches.
    pub label: &'a str,
    /// The 1-thread pool.
    pub single: &'a rayon::ThreadPool,
    /// Threads of the parallel side.
    pub threads: usize,
    /// Timed repetitions.
    pub repeat: usize,
    /// `--quick`: fewer, smaller points.
    pub quick: bool,
    /// `--backend gpu`: the BVH the GPU strategies render through (the CPU's, uploaded).
    pub gpu_bvh: Option<&'a Bvh>,
}

/// Measures both sweeps (with `gpu`: the GPU strategies at every point too).
pub fn run(
    input: &SweepInput<'_>,
    mut gpu: Option<&mut GpuSession>,
    mismatches: &mut Vec<Mismatch>,
    step: &dyn Fn(),
) -> Result<Seed003Sweeps> {
    let (lights, sides) = points(input.quick);
    let mut frame = input.frame.clone();
    frame.settings.max_recursion_level = 1;
    let mut by_lights = Vec::new();
    for &n in lights {
        frame.lights = ring_of_lights(&frame, n);
        by_lights.push(point(input, gpu.as_deref_mut(), &frame, &format!("{n} lights"), mismatches)?);
        step();
    }
    frame.lights = ring_of_lights(&frame, RESOLUTION_LIGHTS);
    let mut by_size = Vec::new();
    for &side in sides {
        (frame.settings.width, frame.settings.height) = (side, side);
        by_size.push(point(input, gpu.as_deref_mut(), &frame, &format!("{side}x{side}"), mismatches)?);
        step();
    }
    Ok(Seed003Sweeps { scene: input.scene.to_string(), lights: by_lights, resolution: by_size })
}

/// Light counts and image sides of the sweeps (`--quick`: two small points each).
fn points(quick: bool) -> (&'static [usize], &'static [u32]) {
    if quick {
        (&[1, 4], &[48, 64])
    } else {
        (&LIGHTS, &SIDES)
    }
}

/// Steps of [`run`], for the progress bar.
pub fn steps(quick: bool) -> usize {
    let (lights, sides) = points(quick);
    lights.len() + sides.len()
}

fn point(
    input: &SweepInput<'_>,
    gpu: Option<&mut GpuSession>,
    frame: &Frame,
    what: &str,
    mismatches: &mut Vec<Mismatch>,
) -> Result<Seed003Point> {
    let (single_ms, film_1, rays) = timed_render(frame, input.accel, Some(input.single), input.repeat);
    let (parallel_ms, film_n, _) = timed_render(frame, input.accel, None, input.repeat);
    let kind = format!("sweep {what}: 1 thread");
    let images_identical = compare(&film_1, &film_n, input.scene, input.label, 1, &kind, mismatches);
    let speedup = if parallel_ms > 0.0 { single_ms / parallel_ms } else { 0.0 };
    let gpu = match (gpu, input.gpu_bvh) {
        (Some(g), Some(b)) => {
            let what = format!("sweep {what}");
            let shot = CpuShot { scene: input.scene, what: &what, film: &film_n, single_ms };
            strategies::strategies(g, frame, b, &shot, input.repeat, mismatches)?
        }
        _ => Vec::new(),
    };
    Ok(Seed003Point {
        lights: frame.lights.len(),
        width: frame.settings.width,
        height: frame.settings.height,
        rays,
        single_ms,
        parallel_ms,
        speedup,
        efficiency: speedup / input.threads as f64,
        images_identical,
        gpu,
    })
}

/// The sweeps' part of the preset's report.md section (with the GPU strategies' columns
/// when they ran).
pub fn markdown(w: &Seed003Sweeps, threads: usize, s: &mut String) {
    let on_gpu = w.lights.iter().chain(&w.resolution).any(|p| !p.gpu.is_empty());
    let (gpu_head, gpu_rule) = if on_gpu { strategies::header() } else { Default::default() };
    let _ = writeln!(
        s,
        "### Ray casting on {} against the number of lights (Table 4.3's scenes 1–5) and the image size \
         (Table 4.4: {RESOLUTION_LIGHTS} lights)\n\n\
         | lights | image | rays | 1 thread ms | {threads} threads ms | SP | EF | same image |{gpu_head}\n\
         |--:|--:|--:|--:|--:|--:|--:|:-:|{gpu_rule}",
        w.scene
    );
    for p in w.lights.iter().chain(&w.resolution) {
        let gpu = if on_gpu { strategies::cells(&p.gpu) } else { String::new() };
        let _ = writeln!(
            s,
            "| {} | {}×{} | {} | {} | {} | {:.2} | {:.2} | {} |{gpu}",
            p.lights,
            p.width,
            p.height,
            thousands(p.rays),
            num(p.single_ms),
            num(p.parallel_ms),
            p.speedup,
            p.efficiency,
            if p.images_identical { "yes" } else { "**no**" }
        );
    }
    let _ = writeln!(s);
}

#[cfg(test)]
mod tests {
    use super::*;
    use dynray_scene::demo::demo_scene;

    #[test]
    fn ring_lights_share_one_white_light_and_stand_above_the_scene() {
        let frame = demo_scene().frame(0.0);
        let top = frame.mesh.bounds().max.y;
        for n in LIGHTS {
            let lights = ring_of_lights(&frame, n);
            assert_eq!(lights.len(), n);
            let total: Vec3 = lights.iter().map(|l| l.color).sum();
            assert!((total - Vec3::ONE).abs().max_element() < 1e-5, "{n}: {total}");
            for l in &lights {
                let LightKind::Point { position, .. } = l.kind else { panic!("{n}: not a point light") };
                assert!(position.y > top, "{n}: light at {position} under the scene's top {top}");
            }
        }
    }
}
