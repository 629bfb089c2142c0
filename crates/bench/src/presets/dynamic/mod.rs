//! `--preset dynamic`: geometry moves each frame — a still model's every vertex (a
//! travelling wave plus a twist about the vertical axis), or an animated file's own
//! animation (glTF skins and node animation, BART) — and each structure is brought up to
//! date by `update` (a refit where the structure has one, else a full rebuild);
//! structures that refit are also rebuilt from scratch each frame, so both costs, and the
//! refit tree's drift from a fresh one, are known. Then primary rays are traced and a
//! Whitted image rendered through the updated structure, and a sample of the primary rays
//! is checked against brute force on the moved mesh. A second part
//! (`layouts.rs`) follows animated scenes in each scene layout and update policy.

pub mod layouts;

use crate::config::BenchConfig;
use crate::format::{num, thousands};
use crate::line_chart::{LineChart, Panel, Series};
use crate::measure::{ms, oracle, timed_pass, verify};
use crate::presets::experiment::{Experiment, Lab};
use crate::progress::progress_bar;
use crate::rays::{self, RayKind, RaySets};
use crate::results::{median, Mismatch};
use crate::scenes::load_scenes;
use anyhow::{Context, Result};
use dynray_accel::AccelSpec;
use dynray_accel::{Accel, Brute};
use dynray_geom::{TriangleMesh, Vec3};
use dynray_render::{render, RenderOptions};
use layouts::LayoutRun;
use serde::{Deserialize, Serialize};
use std::fmt::Write;
use std::hint::black_box;
use std::time::Instant;

/// `--preset dynamic`: every vertex moves each frame.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct DynamicResult {
    /// Frames per scene.
    pub frames: usize,
    /// Image width of the primary rays and renders.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// One entry per scene × structure.
    pub runs: Vec<DynamicRun>,
    /// Scene layouts and update policies on the animated scenes
    /// (`presets::dynamic::layouts`); empty in reports written before it.
    #[serde(default)]
    pub layouts: Vec<LayoutRun>,
}

/// One structure animated over one scene.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct DynamicRun {
    /// Scene name.
    pub scene: String,
    /// What moves it: `wave` (the preset's deformation of a still model) or `animation`
    /// (the file's own).
    pub motion: String,
    /// Triangles.
    pub triangles: usize,
    /// Structure.
    pub accel: String,
    /// Per frame: full rebuild, ms (the update's own time when `update` is a rebuild,
    /// i.e. when `refits` is false).
    pub rebuild_ms: Vec<f64>,
    /// Whether `update` refits (BVH, BIH) rather than rebuilds.
    pub refits: bool,
    /// Per frame: `update` (refit where the structure has one), ms.
    pub update_ms: Vec<f64>,
    /// Per frame: primary rays through the updated structure, ms.
    pub trace_ms: Vec<f64>,
    /// Per frame: the same rays through a fresh build, ms (= `trace_ms` where `refits` is
    /// false: the update was the fresh build).
    pub fresh_trace_ms: Vec<f64>,
    /// Per frame, where the structure refits and reports an SAH cost: the refit tree's
    /// normalised SAH cost over the fresh build's (empty otherwise).
    pub sah_ratio: Vec<f64>,
    /// Per frame: update + Whitted render, ms.
    pub time_to_image_ms: Vec<f64>,
    /// Medians of the four series.
    pub median_rebuild_ms: f64,
    /// Median update time.
    pub median_update_ms: f64,
    /// Median trace time.
    pub median_trace_ms: f64,
    /// Median time to image.
    pub median_time_to_image_ms: f64,
    /// Primary-ray Mrays/s in the last frame after updates (refit quality decay shows here).
    pub last_frame_mrays_per_s: f64,
    /// Primary-ray Mrays/s in the first frame.
    pub first_frame_mrays_per_s: f64,
    /// Rays checked against brute force over all frames.
    pub verified: usize,
}

/// Primary rays per frame checked against brute force.
const VERIFY_PER_FRAME: usize = 256;

/// The model at frame `f` of `frames`: `base` twisted about the vertical axis through the
/// box centre (up to ±0.6 rad at the top and bottom) and rippled by a wave of 4 % of the
/// box diagonal travelling along y. Deterministic; frame 0 is already moved.
pub fn deform(base: &TriangleMesh, f: usize, frames: usize) -> Vec<[f32; 3]> {
    let b = base.bounds();
    let (c, ext) = (b.center(), b.extent());
    let h = ext.y.max(1e-6);
    let amp = ext.length() * 0.04;
    let phase = std::f32::consts::TAU * (f + 1) as f32 / frames.max(1) as f32;
    base.positions
        .iter()
        .map(|p| {
            let r = Vec3::from_array(*p) - c;
            let s = r.y / h; // about -0.5..0.5
            let a = 0.6 * phase.sin() * 2.0 * s;
            let (sin, cos) = a.sin_cos();
            let mut q = Vec3::new(cos * r.x + sin * r.z, r.y, -sin * r.x + cos * r.z);
            q.x += amp * (std::f32::consts::TAU * 2.0 * s + phase).sin();
            q.z += amp * 0.5 * (std::f32::consts::TAU * 3.0 * s - phase).cos();
            (q + c).to_array()
        })
        .collect()
}

/// Image size of the preset when the command line gives none: every structure renders
/// every frame, and the slowest (A-buffers, kd-tree rebuilds) set the preset's length.
pub const SIZE: (u32, u32) = (320, 240);

/// Runs the preset (default: the bunny and the dragon at its 48k-triangle resolution,
/// waved, and CesiumMan's skinned walk; 60 frames at 320×240; quick: dragon-res4 and
/// CesiumMan, 4 frames at 128×96).
///
/// A still model gets the wave ([`deform`]), its camera and primary rays fixed; an
/// animated file (`BenchScene::animated`) is posed at `frames` times spread evenly over
/// its timeline, and each frame's camera gives that frame's primary rays. Structures
/// that refit are also built afresh each frame, and the fresh build traces the same rays:
/// the refit tree's trace time and SAH cost over the fresh tree's are the drift that
/// `dynray animate --update auto` watches (docs/animate.md).
pub fn run(config: &BenchConfig, accels: &[AccelSpec], mismatches: &mut Vec<Mismatch>) -> Result<DynamicResult> {
    let names: Vec<String> = if !config.scenes.is_empty() {
        config.scenes.clone()
    } else if config.quick {
        vec!["dragon-res4".into(), "cesium-man".into()]
    } else {
        vec!["bunny".into(), "dragon-res3".into(), "cesium-man".into()]
    };
    let (width, height) = if config.size_given || config.quick { (config.width, config.height) } else { SIZE };
    let frames = config.frames.max(1);
    let scenes = load_scenes(&names, config.scenes_dir.as_deref())?;
    let bar = progress_bar(config.progress, (scenes.len() * accels.len() * frames) as u64);
    let mut runs = Vec::new();
    for sc in &scenes {
        let base = &sc.frame.mesh;
        let motion = if sc.animated.is_some() { "animation" } else { "wave" };
        for v in accels {
            let label = v.to_string();
            let mut frame = sc.frame.clone();
            frame.settings.width = width;
            frame.settings.height = height;
            let mut accel: Box<dyn Accel> = v
                .build(&frame.mesh, Some(frame.camera.position))
                .with_context(|| format!("{}: cannot build {label}", sc.name))?;
            let mut brute = Brute::build(base).with_context(|| format!("{}: cannot build brute", sc.name))?;
            let mut series = FrameSeries::default();
            let mut verified = 0;
            for f in 0..frames {
                bar.set_message(format!("dynamic {} / {label}: frame {}", sc.name, f + 1));
                match &sc.animated {
                    Some(scene) => scene.frame_into(frame_time(scene, f, frames), &mut frame),
                    None => frame.mesh.positions = deform(base, f, frames),
                }
                frame.settings.width = width;
                frame.settings.height = height;
                let eye = frame.camera.position;
                // Camera rays of this frame (an animated camera moves; the wave's stays).
                let sets = RaySets { sets: vec![(RayKind::Primary, rays::primary(&frame, width, height))] };
                let rays = &sets.sets[0].1;
                let t = Instant::now();
                accel
                    .update_for_eye(&frame.mesh, eye)
                    .with_context(|| format!("{} frame {f}: update {label}", sc.name))?;
                let up = ms(t);
                series.update.push(up);
                let trace = timed_pass(accel.as_ref(), rays, false).0;
                series.trace.push(trace);
                // Without a refit, `update` is the rebuild: timing another would double
                // the preset's cost and measure the same thing.
                if accel.update_refits() {
                    let t = Instant::now();
                    let fresh = v
                        .build(&frame.mesh, Some(eye))
                        .with_context(|| format!("{} frame {f}: rebuild {label}", sc.name))?;
                    series.rebuild.push(ms(t));
                    series.fresh_trace.push(timed_pass(fresh.as_ref(), rays, false).0);
                    if let (Some(now), Some(best)) = (accel.sah_cost(), fresh.sah_cost()) {
                        series.sah_ratio.push(now / best);
                    }
                    black_box(fresh);
                } else {
                    series.rebuild.push(up);
                    series.fresh_trace.push(trace);
                }
                let t = Instant::now();
                black_box(render(&frame, accel.as_ref(), &RenderOptions::default()));
                series.tti.push(up + ms(t));
                brute.update(&frame.mesh)?;
                let scene = format!("{} (dynamic frame {f})", sc.name);
                for e in oracle(&brute, &sets, Some(VERIFY_PER_FRAME)) {
                    verified += verify(accel.as_ref(), &label, &scene, rays, &e, mismatches);
                }
                bar.inc(1);
            }
            let rays_per_frame = (width as usize * height as usize) as f64;
            let mrays = |t: f64| if t > 0.0 { rays_per_frame / t / 1e3 } else { 0.0 };
            let FrameSeries { rebuild, update, trace, fresh_trace, sah_ratio, tti } = series;
            runs.push(DynamicRun {
                refits: accel.update_refits(),
                scene: sc.name.clone(),
                motion: motion.to_string(),
                triangles: base.triangle_count(),
                accel: label,
                median_rebuild_ms: median(&rebuild),
                median_update_ms: median(&update),
                median_trace_ms: median(&trace),
                median_time_to_image_ms: median(&tti),
                first_frame_mrays_per_s: mrays(trace[0]),
                last_frame_mrays_per_s: mrays(trace[trace.len() - 1]),
                rebuild_ms: rebuild,
                update_ms: update,
                trace_ms: trace,
                fresh_trace_ms: fresh_trace,
                sah_ratio,
                time_to_image_ms: tti,
                verified,
            });
        }
    }
    bar.finish_and_clear();
    // Second part: layouts and policies on the animated scenes (those given, or the
    // part's own defaults: BART, CesiumMan, the carousel).
    let layout_scenes = if config.scenes.is_empty() {
        load_scenes(&layouts::default_scenes(config.quick), config.scenes_dir.as_deref())?
    } else {
        scenes
    };
    let layouts = layouts::run(config, accels, &layout_scenes, (frames, width, height), mismatches)?;
    Ok(DynamicResult { frames, width, height, runs, layouts })
}

/// Per-frame figures of one structure on one scene.
#[derive(Default)]
struct FrameSeries {
    rebuild: Vec<f64>,
    update: Vec<f64>,
    trace: Vec<f64>,
    fresh_trace: Vec<f64>,
    sah_ratio: Vec<f64>,
    tti: Vec<f64>,
}

/// Time of preset frame `f` of `frames`: spread evenly from the timeline's first frame
/// to its last (one frame: the first).
pub fn frame_time(scene: &dynray_scene::Scene, f: usize, frames: usize) -> f32 {
    let tl = scene.animation.timeline;
    let (t0, t1) = (tl.time_of(0), tl.time_of(tl.frames - 1));
    if frames <= 1 {
        return t0;
    }
    t0 + (t1 - t0) * f as f32 / (frames - 1) as f32
}

/// Time to image per frame (update + render), one line per structure, one panel per
/// scene; thin lines: the full rebuild of the structures whose update is a refit.
pub fn chart(d: &DynamicResult) -> LineChart {
    let mut scenes: Vec<&str> = d.runs.iter().map(|r| r.scene.as_str()).collect();
    scenes.dedup();
    let frames = |v: &[f64]| v.iter().enumerate().map(|(i, &t)| ((i + 1) as f64, t)).collect();
    let panels = scenes
        .iter()
        .map(|&scene| {
            let runs: Vec<&DynamicRun> = d.runs.iter().filter(|r| r.scene == scene).collect();
            let mut series: Vec<Series> = runs
                .iter()
                .map(|r| Series { name: r.accel.clone(), points: frames(&r.time_to_image_ms), reference: false })
                .collect();
            series.extend(runs.iter().filter(|r| r.refits).map(|r| Series {
                name: format!("{}: full rebuild alone", r.accel),
                points: frames(&r.rebuild_ms),
                reference: true,
            }));
            let tris = runs.first().map_or(0, |r| r.triangles);
            let motion = match runs.first().map(|r| r.motion.as_str()) {
                Some("animation") => "its own animation",
                _ => "every vertex moves",
            };
            Panel { title: format!("{scene} ({} triangles, {motion})", thousands(tris as u64)), series }
        })
        .collect();
    LineChart {
        caption: format!(
            "dynamic: time to image per frame (update or refit + Whitted render, {}x{}; lower is better)",
            d.width, d.height
        ),
        x_desc: "frame".into(),
        y_desc: "ms".into(),
        log2_x: false,
        log_y: true,
        y_from_zero: false,
        panels,
    }
}

/// Refit drift per frame, one panel per scene: for each structure that refits, its SAH
/// cost and its primary trace time over a fresh build's on the same frame (1 = as good
/// as rebuilding). The data behind the `auto` update policy's bound (docs/animate.md).
pub fn drift_chart(d: &DynamicResult) -> LineChart {
    let mut scenes: Vec<&str> = d.runs.iter().map(|r| r.scene.as_str()).collect();
    scenes.dedup();
    let panels = scenes
        .iter()
        .map(|&scene| {
            let runs: Vec<&DynamicRun> = d.runs.iter().filter(|r| r.scene == scene && r.refits).collect();
            let mut series = Vec::new();
            for r in &runs {
                let ratio: Vec<(f64, f64)> = r
                    .trace_ms
                    .iter()
                    .zip(&r.fresh_trace_ms)
                    .enumerate()
                    .filter(|(_, (_, &f))| f > 0.0)
                    .map(|(i, (&t, &f))| ((i + 1) as f64, t / f))
                    .collect();
                series.push(Series {
                    name: format!("{}: trace time / fresh", r.accel),
                    points: ratio,
                    reference: false,
                });
                if !r.sah_ratio.is_empty() {
                    let points = r.sah_ratio.iter().enumerate().map(|(i, &x)| ((i + 1) as f64, x)).collect();
                    series.push(Series { name: format!("{}: SAH cost / fresh", r.accel), points, reference: true });
                }
            }
            Panel { title: scene.to_string(), series }
        })
        .collect();
    LineChart {
        caption: format!(
            "dynamic: refit tree over a fresh build, per frame ({}x{} primary rays; 1 = as good as a rebuild)",
            d.width, d.height
        ),
        x_desc: "frame".into(),
        y_desc: "refit / fresh".into(),
        log2_x: false,
        log_y: false,
        y_from_zero: false,
        panels,
    }
}

/// The preset's section of report.md: medians per run, its charts, then the layouts.
pub fn markdown(d: &DynamicResult, png: bool, s: &mut String) {
    let _ = writeln!(
        s,
        "## Preset dynamic — geometry moves each frame ({} frames, {}×{})\n\n\
         Medians over the frames. *motion*: `wave` deforms every vertex of a still model, `animation` \
         plays the file's own. *update* is the structure's `update` (a refit where it has one); \
         *rebuild* a full build; time to image = update + Whitted render; *refit/fresh* the refit \
         tree's primary trace time and SAH cost over a fresh build's on the same frame (last frame).\n\n\
         | scene | motion | triangles | structure | rebuild ms | update ms | primary trace ms | time to image ms | Mrays/s frame 1 → last | refit/fresh trace, SAH | checked |\n\
         |---|---|--:|---|--:|--:|--:|--:|--:|--:|--:|",
        d.frames, d.width, d.height
    );
    for run in &d.runs {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} → {} | {} | {} |",
            run.scene,
            run.motion,
            thousands(run.triangles as u64),
            run.accel,
            num(run.median_rebuild_ms),
            num(run.median_update_ms),
            num(run.median_trace_ms),
            num(run.median_time_to_image_ms),
            num(run.first_frame_mrays_per_s),
            num(run.last_frame_mrays_per_s),
            drift(run),
            thousands(run.verified as u64)
        );
    }
    let ext = if png { "png" } else { "svg" };
    let _ = writeln!(s, "\n![dynamic](dynamic.{ext})\n");
    if d.runs.iter().any(|r| r.refits) {
        let _ = writeln!(s, "![refit drift](dynamic-drift.{ext})\n");
    }
    if !d.layouts.is_empty() {
        layouts::markdown(&d.layouts, s);
        let _ = writeln!(s, "\n![scene layouts](dynamic-layouts.{ext})\n");
    }
}

/// The last frame's refit-over-fresh trace time and SAH cost of a refitting run
/// (`—` for structures that rebuild).
fn drift(run: &DynamicRun) -> String {
    if !run.refits {
        return "—".into();
    }
    let trace = match (run.trace_ms.last(), run.fresh_trace_ms.last()) {
        (Some(&t), Some(&f)) if f > 0.0 => format!("{:.2}", t / f),
        _ => "—".into(),
    };
    let sah = run.sah_ratio.last().map_or("—".into(), |r| format!("{r:.2}"));
    format!("{trace}, {sah}")
}

/// `--preset dynamic`: geometry that moves every frame, and the scene layouts.
pub struct Dynamic;

impl Experiment for Dynamic {
    const PRESET: crate::config::Preset = crate::config::Preset::Dynamic;
    type Output = DynamicResult;

    fn run(ctx: &mut Lab<'_>) -> anyhow::Result<DynamicResult> {
        run(ctx.config, ctx.accels, ctx.mismatches)
    }

    fn markdown(out: &DynamicResult, png: bool, s: &mut String) {
        markdown(out, png, s)
    }

    fn charts(out: &DynamicResult, dir: &std::path::Path, png: bool) -> anyhow::Result<()> {
        crate::charts::save(&chart(out), dir, "dynamic", png)?;
        if !out.layouts.is_empty() {
            crate::charts::save(&layouts::chart(&out.layouts, out.width, out.height), dir, "dynamic-layouts", png)?;
        }
        if out.runs.iter().any(|r| r.refits) {
            crate::charts::save(&drift_chart(out), dir, "dynamic-drift", png)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn deformation_moves_every_vertex_and_is_deterministic() {
        let mesh = TriangleMesh::new(
            vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 1.0]],
            vec![[0, 1, 2], [1, 3, 2]],
        );
        let a = deform(&mesh, 3, 10);
        assert_eq!(a, deform(&mesh, 3, 10));
        for (p, q) in mesh.positions.iter().zip(&a) {
            assert_ne!(p, q);
            assert!(q.iter().all(|x| x.is_finite()));
        }
    }
}
