//! `--preset seed000`, second part: the seed's dynamic scenario. An elastic bunny
//! (point-based animation, `dynray-sim`, Müller et al. 2004) is dropped on a floor and
//! deforms as it lands and settles; every frame each structure is brought up to date —
//! the BIH rebuilt from scratch as the seed does (MaxPrims 1, 5, 10, 20, 30, the seed's
//! build with shrink; and dynray's default BIH, which adds empty-space cuts),
//! the kd-trees (Standard, Ropes++) rebuilt, the BVH rebuilt and, separately, refitted —
//! then primary rays are traced and a Whitted image rendered. Per frame: physics ms,
//! build/update ms, trace ms, render ms and time to image (physics + update + render):
//! the seed's Table 1 metric on the seed's scenario. A sample of every frame's primary
//! rays is checked against brute force on the deformed mesh.
//!
//! Frames go through the engine's frame path, as `dynray animate` does: the scene is posed
//! (`Scene::frame_into`), the world stepped to the frame's time and its bodies written
//! into the frame (`World::write_into`). The simulation runs once; every structure sees
//! the same frames.

use super::experiment::{Experiment, Lab};
use crate::config::BenchConfig;
use crate::format::thousands;
use crate::line_chart::{LineChart, Panel, Series};
use crate::measure::{ms, oracle, timed_pass, verify};
use crate::progress::progress_bar;
use crate::rays::{self, RayKind, RaySets};
use crate::results::{median, Mismatch};
use crate::scenes::{resolve, scenes_dir};
use anyhow::{Context, Result};
use dynray_accel::{Accel, AccelSpec, Brute};
use dynray_engine::{FrameSettings, Stage};
use dynray_render::{render, RenderOptions};
use dynray_scene::Frame;
use serde::{Deserialize, Serialize};
use std::fmt::Write;
use std::hint::black_box;
use std::time::Instant;

/// `--preset seed000`'s dynamic scenario (`presets::seed000_physics`).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Seed000Physics {
    /// Triangles of the frame (the bunny and the floor).
    pub triangles: usize,
    /// Phyxels of the elastic body.
    pub phyxels: usize,
    /// The world in words (bodies, pairs, steps per frame).
    pub world: String,
    /// Frames simulated and rendered.
    pub frames: usize,
    /// Frames per second of simulated time.
    pub frame_rate: u32,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Simulation time per frame, ms (once; shared by every structure).
    pub physics_ms: Vec<f64>,
    /// One entry per structure.
    pub runs: Vec<PhysicsRun>,
}

/// One structure following the deforming mesh.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct PhysicsRun {
    /// `--accels` spelling.
    pub accel: String,
    /// True: refitted each frame (`update`); false: rebuilt from scratch.
    pub refit: bool,
    /// Rebuild or refit per frame, ms.
    pub update_ms: Vec<f64>,
    /// Primary trace per frame, ms.
    pub trace_ms: Vec<f64>,
    /// Whitted render per frame, ms.
    pub render_ms: Vec<f64>,
    /// Physics + update + render per frame, ms.
    pub time_to_image_ms: Vec<f64>,
    /// Sum of `time_to_image_ms`.
    pub total_time_to_image_ms: f64,
    /// Median of `time_to_image_ms`.
    pub median_time_to_image_ms: f64,
    /// Primary rays checked against brute force over all frames.
    pub verified: usize,
}

/// Primary rays per frame checked against brute force.
const VERIFY_PER_FRAME: usize = 256;

/// Frames per second of the scenario (its time step).
const FRAME_RATE: u32 = 24;

/// The structures and how each follows the mesh: `true` refits (`update`), `false`
/// rebuilds from scratch.
fn structures() -> Vec<(String, bool)> {
    let mut v: Vec<(String, bool)> =
        super::seed000::MAX_PRIMS.iter().map(|m| (format!("bih:preset=seed_000,max_prims={m}"), false)).collect();
    // dynray's default BIH (the seed's build plus empty-space cuts), beside the seed's own.
    for s in ["bih", "kdtree", "kdtree-ropes", "bvh"] {
        v.push((s.to_string(), false));
    }
    v.push(("bvh".to_string(), true));
    v
}

/// The scenario as a `.scn` (examples/physics/bunny_drop.scn's, self-contained): the
/// bunny scaled to 1.5 m, 0.4 m above the floor, 2,500 phyxels.
fn scenario(bunny: &std::path::Path, frames: usize, (w, h): (u32, u32)) -> String {
    format!(
        r#"settings {{ image_width {w} image_height {h} frames {frames} frame_rate {FRAME_RATE} }}
environment {{ background rgb(0.28, 0.44, 0.68) ambient rgb(0.25, 0.25, 0.25) ior 1 }}
camera {{ perspective position <0.2, 1.4, 4.2> to <-0.2, 0.7, 0> up <0, 1, 0> angle 35 }}
light {{ position <2, 4, 3> color rgb(1, 1, 1) falloff 0 }}
physics {{ gravity <0, -9.81, 0> ground 0 substeps 4 }}
mesh
{{
  file "{}"
  material {{ color rgb(0.7, 0.2, 0.15) finish {{ ambient 0.1 diffuse 0.8 spot 0.5 shine 40 }} }}
  transform {{ scale <0, 0, 0> <1, 1, 1> * 10 translate <0, -0.33 + 0.4, 0> }}
  elastic {{ young 5e5 poisson 0.3 density 1000 damping 0.1 phyxels 2500 velocity <0, 0, 0> }}
}}
box {{ center <0, -0.05, 0> orientation <0, 0, 0> scale <8, 0.1, 8>
      material {{ color rgb(1, 0.96, 0.86) finish {{ ambient 0.15 diffuse 0.85 }} }} }}
"#,
        bunny.display()
    )
}

/// Runs the scenario: `config.frames` frames (60; `--quick`: 4) at 640×480 (`--quick`:
/// the quick size; `--width/--height` override).
pub fn run(config: &BenchConfig, mismatches: &mut Vec<Mismatch>) -> Result<Seed000Physics> {
    let (width, height) = if config.size_given || config.quick { (config.width, config.height) } else { (640, 480) };
    let frames = config.frames.max(1);
    let dir = scenes_dir(config.scenes_dir.as_deref());
    let (_, bunny) = resolve("bunny", dir.as_deref())?;
    // The scenario file lives in a temporary folder: it names the model absolutely.
    let bunny = bunny.canonicalize().with_context(|| format!("seed000 physics: {}", bunny.display()))?;
    let tmp = tempfile::tempdir().context("seed000 physics: no temporary folder")?;
    let file = tmp.path().join("bunny_drop.scn");
    std::fs::write(&file, scenario(&bunny, frames, (width, height))).context("seed000 physics: cannot write")?;
    let scene = dynray_scene::load_file(&file).context("seed000 physics: the scenario")?;
    let timeline = scene.animation.timeline;
    let size = FrameSettings { width: Some(width), height: Some(height), ..Default::default() };
    // The engine's stage: the scene posed and its bodies simulated, as `animate` does.
    let mut stage = Stage::new(scene, "seed000 physics", size)?;
    let world = stage.world().context("seed000 physics: the scenario has no elastic body")?;
    let phyxels = world.bodies().iter().map(|b| b.len()).sum();
    let describe = world.describe();

    // The simulation, once: every frame's mesh and its physics time.
    let bar = progress_bar(config.progress, (frames * (structures().len() + 1)) as u64);
    let mut posed: Vec<Frame> = Vec::with_capacity(frames);
    let mut physics_ms = Vec::with_capacity(frames);
    for f in 0..frames {
        bar.set_message(format!("seed000 physics: simulating frame {}", f + 1));
        let timing = stage.pose(timeline.time_of(f as u32)).with_context(|| format!("seed000 physics: frame {f}"))?;
        physics_ms.push(timing.physics.as_secs_f64() * 1e3);
        posed.push(stage.frame().clone());
        bar.inc(1);
    }
    let rays = rays::primary(&posed[0], width, height);
    let sets = RaySets { sets: vec![(RayKind::Primary, rays)] };
    let rays = &sets.sets[0].1;
    // Brute force's answers per frame, shared by every structure.
    let mut brute = Brute::build(&posed[0].mesh)?;
    let mut expected = Vec::with_capacity(frames);
    for f in &posed {
        brute.update(&f.mesh)?;
        expected.push(oracle(&brute, &sets, Some(VERIFY_PER_FRAME)));
    }

    let mut runs = Vec::new();
    for (label, refit) in structures() {
        let spec: AccelSpec = label.parse().map_err(|e| anyhow::anyhow!("seed000 physics: `{label}`: {e}"))?;
        let eye = posed[0].camera.position;
        let mut accel: Box<dyn Accel> = spec.build(&posed[0].mesh, Some(eye))?;
        let mut run = PhysicsRun {
            accel: label.clone(),
            refit,
            update_ms: Vec::new(),
            trace_ms: Vec::new(),
            render_ms: Vec::new(),
            time_to_image_ms: Vec::new(),
            total_time_to_image_ms: 0.0,
            median_time_to_image_ms: 0.0,
            verified: 0,
        };
        for (f, frame) in posed.iter().enumerate() {
            bar.set_message(format!("seed000 physics: {label}{} frame {}", if refit { " refit" } else { "" }, f + 1));
            let t = Instant::now();
            if refit {
                accel.update_for_eye(&frame.mesh, eye).with_context(|| format!("frame {f}: refit {label}"))?;
            } else {
                accel = spec.build(&frame.mesh, Some(eye)).with_context(|| format!("frame {f}: rebuild {label}"))?;
            }
            let update = ms(t);
            let trace = timed_pass(accel.as_ref(), rays, false).0;
            let t = Instant::now();
            black_box(render(frame, accel.as_ref(), &RenderOptions::default()));
            let render_ms = ms(t);
            let scene_name = format!("seed000 physics (frame {f})");
            for e in &expected[f] {
                run.verified += verify(accel.as_ref(), &label, &scene_name, rays, e, mismatches);
            }
            run.update_ms.push(update);
            run.trace_ms.push(trace);
            run.render_ms.push(render_ms);
            run.time_to_image_ms.push(physics_ms[f] + update + render_ms);
            bar.inc(1);
        }
        run.total_time_to_image_ms = run.time_to_image_ms.iter().sum();
        run.median_time_to_image_ms = median(&run.time_to_image_ms);
        runs.push(run);
    }
    bar.finish_and_clear();
    Ok(Seed000Physics {
        triangles: posed[0].mesh.triangle_count(),
        phyxels,
        world: describe,
        frames,
        frame_rate: FRAME_RATE,
        width,
        height,
        physics_ms,
        runs,
    })
}

/// `BIH MaxPrims = 5` / `BVH refit`: names for the table and the chart.
pub fn display_name(r: &PhysicsRun) -> String {
    let base = super::seed000::display_name(&r.accel);
    match (r.accel.as_str(), r.refit) {
        ("bvh", true) => "BVH refit".into(),
        ("bvh", false) => "BVH rebuilt".into(),
        ("bih", _) => "BIH default (MaxPrims = 8, shrink, empty-space cuts), rebuilt".into(),
        _ => format!("{base}, rebuilt"),
    }
}

/// The section of report.md.
pub fn markdown(p: &Seed000Physics, png: bool, s: &mut String) {
    let _ = writeln!(
        s,
        "### seed000: the dynamic scenario (an elastic bunny dropped on the floor)\n\n\
         {} triangles ({} phyxels: {}), {} frames at {} fps, {}×{}. Per frame: physics, then the structure \
         rebuilt (or refitted), primary rays traced, a Whitted image rendered; time to image = physics + update + \
         render. Medians over the frames; total over all of them; \"× Ropes++\" is Ropes++'s total time to image \
         over this one's (above 1: faster). Median physics per frame: {:.1} ms.\n\n\
         | structure | update ms | primary trace ms | render ms | time to image ms | total s | fps | × Ropes++ | checked |\n\
         |---|--:|--:|--:|--:|--:|--:|--:|--:|",
        thousands(p.triangles as u64),
        thousands(p.phyxels as u64),
        p.world,
        p.frames,
        p.frame_rate,
        p.width,
        p.height,
        median(&p.physics_ms)
    );
    let ropes = p.runs.iter().find(|r| r.accel == "kdtree-ropes").map(|r| r.total_time_to_image_ms);
    for r in &p.runs {
        let x = ropes.map_or("—".into(), |q| format!("{:.2}", q / r.total_time_to_image_ms.max(1e-9)));
        let _ = writeln!(
            s,
            "| {} | {:.1} | {:.1} | {:.1} | {:.1} | {:.2} | {:.1} | {x} | {} |",
            display_name(r),
            median(&r.update_ms),
            median(&r.trace_ms),
            median(&r.render_ms),
            r.median_time_to_image_ms,
            r.total_time_to_image_ms / 1e3,
            1e3 / r.median_time_to_image_ms.max(1e-9),
            thousands(r.verified as u64)
        );
    }
    let ext = if png { "png" } else { "svg" };
    let _ = writeln!(s, "\n![seed000 dynamic scenario: time to image per frame](seed000-physics.{ext})\n");
}

/// Time to image per frame, one line per structure; physics alone as the reference line.
pub fn chart(p: &Seed000Physics) -> LineChart {
    let frames = |v: &[f64]| v.iter().enumerate().map(|(i, &t)| ((i + 1) as f64, t)).collect();
    let mut series: Vec<Series> = p
        .runs
        .iter()
        .map(|r| Series { name: display_name(r), points: frames(&r.time_to_image_ms), reference: false })
        .collect();
    series.push(Series { name: "physics alone".into(), points: frames(&p.physics_ms), reference: true });
    LineChart {
        caption: format!("seed000 dynamic: time to image per frame, {}x{} (lower is better)", p.width, p.height),
        x_desc: "frame".into(),
        y_desc: "time to image, ms".into(),
        log2_x: false,
        log_y: true,
        y_from_zero: false,
        panels: vec![Panel {
            title: format!("bunny, {} triangles, {} phyxels", thousands(p.triangles as u64), p.phyxels),
            series,
        }],
    }
}

/// `--preset seed000`'s dynamic scenario: the physics run.
pub struct Seed000PhysicsRun;

impl Experiment for Seed000PhysicsRun {
    const PRESET: crate::config::Preset = crate::config::Preset::Seed000;
    type Output = Seed000Physics;

    fn run(ctx: &mut Lab<'_>) -> anyhow::Result<Seed000Physics> {
        run(ctx.config, ctx.mismatches)
    }

    fn markdown(out: &Seed000Physics, png: bool, s: &mut String) {
        markdown(out, png, s)
    }

    fn charts(out: &Seed000Physics, dir: &std::path::Path, png: bool) -> anyhow::Result<()> {
        crate::charts::save(&chart(out), dir, "seed000-physics", png).map(drop)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_structures_are_the_seeds_and_the_scenario_parses() {
        let s = structures();
        assert_eq!(s.len(), 10);
        assert_eq!(s.iter().filter(|(_, refit)| *refit).count(), 1);
        for (label, _) in &s {
            assert!(label.parse::<AccelSpec>().is_ok(), "{label}");
        }
        let text = scenario(std::path::Path::new("/nonexistent/bunny.ply"), 4, (64, 48));
        assert!(text.contains("elastic {") && text.contains("frames 4"));
    }
}
