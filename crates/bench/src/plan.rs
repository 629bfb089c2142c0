//! Measuring a plan, scenes × structure variants, for the standard run and the seed
//! presets alike: one set of rays and brute-force answers per scene, every structure
//! measured on them (and, with the `compare` feature, the other libraries).

use crate::config::BenchConfig;
use crate::framing::{frame_tightly, Framing};
use crate::gpu::{self, GpuSession};
use crate::heatmap;
use crate::measure::{measure, oracle, MeasureInput};
use crate::progress::progress_bar;
use crate::rays::{self, RayKind};
use crate::results::{KindCount, Mismatch, SceneResult};
use crate::scenes::load_scenes;
use anyhow::{Context, Result};
use dynray_accel::AccelSpec;
use dynray_accel::{AccelKind, Brute};

/// How [`measure_scenes`] measures: the standard run's settings, or a preset's.
pub struct SceneMeasure {
    /// Ray kinds.
    pub rays: Vec<RayKind>,
    /// Image width of the ray sets and renders.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Timed repetitions.
    pub repeat: usize,
    /// Render a Whitted image per structure (time to image).
    pub time_to_image: bool,
    /// Write a traversal-cost heat map per structure (needs primary rays).
    pub heatmaps: bool,
    /// Prefix of the progress messages (`seed000 `, …).
    pub label: &'static str,
    /// Run the competitor libraries too (feature `compare`; the standard run only).
    pub competitors: bool,
    /// The camera: the scene's, or moved to fill the image with the model.
    pub framing: Framing,
}

/// Measures every structure of `plan` on its scene: the same ray sets and brute-force
/// answers for all structures of a scene; disagreements go to `mismatches`. With `gpu`
/// (`--backend gpu`), the GPU backend is measured on the same rays for every BVH of the
/// plan.
pub fn measure_scenes(
    config: &BenchConfig,
    plan: &[(String, Vec<AccelSpec>)],
    how: &SceneMeasure,
    mut gpu: Option<&mut GpuSession>,
    mismatches: &mut Vec<Mismatch>,
    notes: &mut Vec<String>,
) -> Result<Vec<SceneResult>> {
    let names: Vec<String> = plan.iter().map(|(n, _)| n.clone()).collect();
    let mut loaded = load_scenes(&names, config.scenes_dir.as_deref())?;
    if how.framing == Framing::Tight {
        for sc in loaded.iter_mut().filter(|sc| !sc.own_camera) {
            frame_tightly(&mut sc.frame, how.width, how.height);
        }
    }
    let on_gpu = |a: &[AccelSpec]| if gpu.is_some() { gpu::gpu_specs(a).len() } else { 0 };
    let steps: usize = plan.iter().map(|(_, a)| a.len() + 1 + on_gpu(a)).sum();
    let bar = progress_bar(config.progress, steps as u64);
    let mut out = Vec::new();
    let mut heat_maps = Vec::new();
    for (sc, (_, accels)) in loaded.iter().zip(plan) {
        bar.set_message(format!("{}{}: rays and brute-force answers", how.label, sc.name));
        let first = accels.first().context("no structure to measure")?;
        let reference = first
            .build(&sc.frame.mesh, Some(sc.frame.camera.position))
            .with_context(|| format!("{}: cannot build {}", sc.name, first))?;
        let sets = rays::generate(&sc.frame, how.width, how.height, &how.rays, reference.as_ref());
        drop(reference);
        let brute = Brute::build(&sc.frame.mesh).with_context(|| format!("{}: cannot build brute", sc.name))?;
        let expected = oracle(&brute, &sets, config.verify_sample);
        drop(brute);
        bar.inc(1);
        let mut result = SceneResult {
            name: sc.name.clone(),
            path: sc.path.display().to_string(),
            triangles: sc.frame.mesh.triangle_count(),
            vertices: sc.frame.mesh.vertex_count(),
            ray_counts: sets.sets.iter().map(|(k, r)| KindCount { kind: k.name().into(), rays: r.len() }).collect(),
            structures: Vec::new(),
            competitors: Vec::new(),
            gpu: Vec::new(),
        };
        for v in accels {
            // Brute force is the oracle: checking it against itself would prove nothing.
            let is_oracle = v.kind == AccelKind::Brute && v.params.is_empty();
            let input = MeasureInput {
                scene: &sc.name,
                frame: &sc.frame,
                sets: &sets,
                expected: if is_oracle { &[] } else { &expected },
                repeat: how.repeat,
                width: how.width,
                height: how.height,
                time_to_image: how.time_to_image,
            };
            let step = |s: &str| bar.set_message(format!("{}{} / {}: {s}", how.label, sc.name, v));
            let (mut res, heat) = measure(v, &input, mismatches, &step)?;
            if let (Some(work), true) = (heat, how.heatmaps) {
                let file = format!("heatmap-{}-{}.png", file_safe(&sc.name), file_safe(&res.accel));
                let title = format!(
                    "{} on {} ({} triangles), {}x{}",
                    res.accel, sc.name, result.triangles, how.width, how.height
                );
                heat_maps.push(heatmap::Pending {
                    path: config.out.join(&file),
                    work,
                    width: how.width,
                    height: how.height,
                    title,
                });
                res.heatmap = Some(file);
            }
            result.structures.push(res);
            bar.inc(1);
        }
        if let Some(g) = gpu.as_deref_mut() {
            let bvhs = gpu::gpu_specs(accels);
            if bvhs.is_empty() {
                let n = "gpu: the GPU backend traces a BVH only: add bvh or bvh2 to --accels to measure it".to_string();
                if !notes.contains(&n) {
                    notes.push(n);
                }
            }
            for v in bvhs {
                let input = MeasureInput {
                    scene: &sc.name,
                    frame: &sc.frame,
                    sets: &sets,
                    expected: &expected,
                    repeat: how.repeat,
                    width: how.width,
                    height: how.height,
                    time_to_image: how.time_to_image,
                };
                let step = |s: &str| bar.set_message(format!("{}{} / {} on the GPU: {s}", how.label, sc.name, v));
                result.gpu.push(gpu::standard::measure(v, g, &input, mismatches, notes, &step)?);
                bar.inc(1);
            }
        }
        #[cfg(not(feature = "compare"))]
        let _ = &notes; // the competitors' remarks are the only notes of this function
        #[cfg(feature = "compare")]
        if how.competitors {
            let step = |s: &str| bar.set_message(format!("{}: {s}", sc.name));
            result.competitors = crate::compare::measure_scene(
                &sc.name,
                &sc.frame.mesh,
                &sets,
                &expected,
                how.repeat,
                &result.structures,
                notes,
                &step,
            )?;
        }
        out.push(result);
    }
    bar.finish_and_clear();
    // Drawn last, on one colour scale for the whole plan.
    heatmap::write_all(&heat_maps)?;
    Ok(out)
}

/// A name usable in a file name: letters, digits, `-`, `_`, `.`; anything else becomes `_`.
pub fn file_safe(s: &str) -> String {
    s.chars().map(|c| if c.is_ascii_alphanumeric() || "-_.".contains(c) { c } else { '_' }).collect()
}
