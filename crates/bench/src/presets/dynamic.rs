//! `--preset dynamic`: every vertex of the model moves each frame (a travelling wave plus a
//! twist about the vertical axis), and each structure is brought up to date by `update`
//! (a refit where the structure has one, else a full rebuild); structures that refit are
//! also rebuilt from scratch each frame, so both costs are known. Then primary rays are
//! traced and a Whitted image rendered through the updated structure, and a sample of the
//! primary rays is checked against brute force on the moved mesh.

use crate::config::BenchConfig;
use crate::format::thousands;
use crate::line_chart::{LineChart, Panel, Series};
use crate::measure::{ms, oracle, timed_pass, verify};
use crate::progress::progress_bar;
use crate::rays::{self, RayKind, RaySets};
use crate::report::{median, DynamicResult, DynamicRun, Mismatch};
use crate::scenes::load_scenes;
use anyhow::{Context, Result};
use dynray_accel::AccelSpec;
use dynray_accel::{Accel, Brute};
use dynray_geom::{TriangleMesh, Vec3};
use dynray_render::{render, RenderOptions};
use std::hint::black_box;
use std::time::Instant;

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

/// Runs the preset (default: the bunny and the dragon at its 48k-triangle resolution, 60
/// frames at 320×240; quick: dragon-res4, 4 frames at 128×96).
pub fn run(config: &BenchConfig, accels: &[AccelSpec], mismatches: &mut Vec<Mismatch>) -> Result<DynamicResult> {
    let names: Vec<String> = if !config.scenes.is_empty() {
        config.scenes.clone()
    } else if config.quick {
        vec!["dragon-res4".into()]
    } else {
        vec!["bunny".into(), "dragon-res3".into()]
    };
    let (width, height) = if config.size_given || config.quick { (config.width, config.height) } else { SIZE };
    let frames = config.frames.max(1);
    let scenes = load_scenes(&names, config.scenes_dir.as_deref())?;
    let bar = progress_bar(config.progress, (scenes.len() * accels.len() * frames) as u64);
    let mut runs = Vec::new();
    for sc in &scenes {
        let base = &sc.frame.mesh;
        // Camera and rays fixed from the rest pose: the deformation stays near its box.
        let primary = rays::primary(&sc.frame, width, height);
        let sets = RaySets { sets: vec![(RayKind::Primary, primary)] };
        let rays = &sets.sets[0].1;
        for v in accels {
            let label = v.to_string();
            let mut accel: Box<dyn Accel> = v
                .build(&sc.frame.mesh, Some(sc.frame.camera.position))
                .with_context(|| format!("{}: cannot build {label}", sc.name))?;
            let mut frame = sc.frame.clone();
            frame.settings.width = width;
            frame.settings.height = height;
            let mut brute = Brute::build(base).with_context(|| format!("{}: cannot build brute", sc.name))?;
            let (mut rebuild, mut update, mut trace, mut tti) = (vec![], vec![], vec![], vec![]);
            let mut verified = 0;
            for f in 0..frames {
                bar.set_message(format!("dynamic {} / {label}: frame {}", sc.name, f + 1));
                frame.mesh.positions = deform(base, f, frames);
                let t = Instant::now();
                accel.update(&frame.mesh).with_context(|| format!("{} frame {f}: update {label}", sc.name))?;
                let up = ms(t);
                update.push(up);
                // Without a refit, `update` is the rebuild: timing another would double
                // the preset's cost and measure the same thing.
                if accel.update_refits() {
                    let t = Instant::now();
                    black_box(
                        v.build(&frame.mesh, Some(frame.camera.position))
                            .with_context(|| format!("{} frame {f}: rebuild {label}", sc.name))?,
                    );
                    rebuild.push(ms(t));
                } else {
                    rebuild.push(up);
                }
                trace.push(timed_pass(accel.as_ref(), rays, false).0);
                let t = Instant::now();
                black_box(render(&frame, accel.as_ref(), &RenderOptions::default()));
                tti.push(up + ms(t));
                brute.update(&frame.mesh)?;
                let scene = format!("{} (dynamic frame {f})", sc.name);
                for e in oracle(&brute, &sets, Some(VERIFY_PER_FRAME)) {
                    verified += verify(accel.as_ref(), &label, &scene, rays, &e, mismatches);
                }
                bar.inc(1);
            }
            let mrays = |t: f64| if t > 0.0 { rays.len() as f64 / t / 1e3 } else { 0.0 };
            runs.push(DynamicRun {
                refits: accel.update_refits(),
                scene: sc.name.clone(),
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
                time_to_image_ms: tti,
                verified,
            });
        }
    }
    bar.finish_and_clear();
    Ok(DynamicResult { frames, width, height, runs })
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
            Panel { title: format!("{scene} ({} triangles, every vertex moves)", thousands(tris as u64)), series }
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
