//! `--preset dynamic`, second part: scene layouts and update policies on animated scenes
//! (BART, CesiumMan, the carousel). Each structure follows the animation as `dynray
//! animate` would ([`LiveScene`]): one flat structure, or the two-level layout in which
//! static actors are built once, deforming ones refit or rebuilt and rigid ones moved as
//! instances; under each update policy (`rebuild`, and `refit` and `auto` for the
//! structures that refit). Per frame: update, primary trace, time to image (update +
//! Whitted render), the action taken and, under `auto`, the parts' SAH drift; a sample
//! of primary rays is checked against the layout's oracle (brute force over the frame
//! for the flat layout, brute force per part in the same two-level layout for instances).

use super::frame_time;
use crate::config::BenchConfig;
use crate::format::thousands;
use crate::line_chart::{LineChart, Panel, Series};
use crate::measure::{ms, oracle, timed_pass, verify};
use crate::progress::progress_bar;
use crate::rays::{self, RayKind, RaySets};
use crate::results::{median, Mismatch};
use crate::scenes::BenchScene;
use anyhow::{Context, Result};
use dynray_accel::{AccelKind, AccelSpec, Brute, LiveScene, SceneLayout, UpdatePolicy};
use dynray_engine::{Fields, FrameSettings, FrameStep, Stage, Tracer};
use dynray_render::{actor_geometry, render, RenderOptions};
use serde::{Deserialize, Serialize};
use std::hint::black_box;
use std::time::Instant;

/// One structure in one scene layout under one update policy, over an animated scene.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct LayoutRun {
    /// Scene name.
    pub scene: String,
    /// Triangles per frame.
    pub triangles: usize,
    /// Structure (of every part).
    pub accel: String,
    /// `flat` or `instanced` (`flat` also where the scene had nothing moving).
    pub layout: String,
    /// `rebuild`, `refit` or `auto`.
    pub policy: String,
    /// Bottom-level structures (1 when flat).
    pub parts: usize,
    /// Instances under the top level (1 when flat).
    pub instances: usize,
    /// Per frame: the update, ms.
    pub update_ms: Vec<f64>,
    /// Per frame: what the update did (`kept`, `refit`, `rebuilt`, `moved`).
    pub actions: Vec<String>,
    /// Per frame: the worst part's SAH cost over its last fresh build (`auto` only).
    pub cost_ratio: Vec<Option<f64>>,
    /// Per frame: primary rays, ms.
    pub trace_ms: Vec<f64>,
    /// Per frame: update + Whitted render, ms.
    pub time_to_image_ms: Vec<f64>,
    /// Median update.
    pub median_update_ms: f64,
    /// Median primary trace.
    pub median_trace_ms: f64,
    /// Median time to image.
    pub median_time_to_image_ms: f64,
    /// Frames in which something was rebuilt.
    pub rebuilds: usize,
    /// Rays checked against the layout's oracle.
    pub verified: usize,
}

/// Primary rays per frame checked against the oracle.
const VERIFY_PER_FRAME: usize = 256;

/// Layouts compared (split holds what flat holds, exactly; its cost sits between).
pub const LAYOUTS: [SceneLayout; 2] = [SceneLayout::Flat, SceneLayout::Instanced];

/// The default scenes of this part: quick, the small carousel and BART's robots.
pub fn default_scenes(quick: bool) -> Vec<String> {
    let names: &[&str] = if quick {
        &["carousel-small", "bart-robots"]
    } else {
        &["cesium-man", "bart-robots", "bart-kitchen", "bart-museum", "carousel"]
    };
    names.iter().map(|s| s.to_string()).collect()
}

/// Runs every animated scene of `scenes` × structure × layout × policy.
pub fn run(
    config: &BenchConfig,
    accels: &[AccelSpec],
    scenes: &[BenchScene],
    (frames, width, height): (usize, u32, u32),
    mismatches: &mut Vec<Mismatch>,
) -> Result<Vec<LayoutRun>> {
    let animated: Vec<&BenchScene> = scenes.iter().filter(|s| s.animated.is_some()).collect();
    let combos = |kind: AccelKind| -> Vec<(SceneLayout, UpdatePolicy)> {
        let policies: &[UpdatePolicy] = if refits(kind) {
            &[UpdatePolicy::Rebuild, UpdatePolicy::Refit, UpdatePolicy::Auto { max_cost_ratio: 1.3 }]
        } else {
            &[UpdatePolicy::Rebuild]
        };
        LAYOUTS.iter().flat_map(|&l| policies.iter().map(move |&p| (l, p))).collect()
    };
    let total: usize = accels.iter().map(|v| combos(v.kind).len()).sum::<usize>() * animated.len() * frames;
    let bar = progress_bar(config.progress, total as u64);
    let mut runs = Vec::new();
    for sc in animated {
        let scene = sc.animated.as_ref().expect("filtered");
        for v in accels {
            for (layout, policy) in combos(v.kind) {
                bar.set_message(format!("dynamic layouts {} / {v} {layout} {policy}", sc.name));
                runs.push(one_run(sc, scene, v, (layout, policy), (frames, width, height), mismatches, &|| {
                    bar.inc(1)
                })?);
            }
        }
    }
    bar.finish_and_clear();
    Ok(runs)
}

/// Whether the structure's update is a refit (else `refit` and `auto` are `rebuild`).
fn refits(kind: AccelKind) -> bool {
    kind.descriptor().refits
}

#[allow(clippy::too_many_arguments)]
fn one_run(
    sc: &BenchScene,
    scene: &dynray_scene::Scene,
    v: &AccelSpec,
    (layout, policy): (SceneLayout, UpdatePolicy),
    (frames, width, height): (usize, u32, u32),
    mismatches: &mut Vec<Mismatch>,
    tick: &dyn Fn(),
) -> Result<LayoutRun> {
    let label = format!("{v} {layout} {policy}");
    // The engine's frame step, as `animate` drives it: built on frame 0 here, so that
    // the loop's figures are updates only.
    let size = FrameSettings { width: Some(width), height: Some(height), ..Default::default() };
    let stage = Stage::new(scene.clone(), &sc.name, size)?;
    let mut step = FrameStep::new(stage, Tracer::cpu(v, policy, layout, Fields::default()));
    step.advance_to(frame_time(scene, 0, frames)).with_context(|| format!("{}: cannot build {label}", sc.name))?;
    let live = step.tracer.live_scene().expect("built");
    let (parts, instances) = live.two_level().map_or((1, 1), |t| t.counts());
    let brute_spec = AccelSpec::new(AccelKind::Brute);
    let mut run = LayoutRun {
        scene: sc.name.clone(),
        triangles: step.stage.frame().mesh.triangle_count(),
        accel: v.to_string(),
        layout: live.layout().to_string(),
        policy: policy.to_string(),
        parts,
        instances,
        ..LayoutRun::default()
    };
    for f in 0..frames {
        let report = step
            .advance_to(frame_time(scene, f, frames))
            .with_context(|| format!("{} frame {f}: {label}", sc.name))?
            .update;
        // The structure's update alone, as before the pose moved into the frame step.
        let update = report.time.as_secs_f64() * 1e3;
        let (frame, live) = (step.stage.frame(), step.tracer.live_scene().expect("built"));
        let eye = frame.camera.position;
        let actors = actor_geometry(scene, frame);
        let sets = RaySets { sets: vec![(RayKind::Primary, rays::primary(frame, width, height))] };
        let rays = &sets.sets[0].1;
        let trace = timed_pass(live.accel(), rays, false).0;
        let t = Instant::now();
        black_box(render(frame, live.accel(), &RenderOptions::default()));
        run.update_ms.push(update);
        run.trace_ms.push(trace);
        run.time_to_image_ms.push(update + ms(t));
        run.actions.push(report.action.name().to_string());
        run.cost_ratio.push(report.cost_ratio);
        // The layout's oracle: brute force over the frame, or per part as instanced.
        let where_ = format!("{} (layouts, frame {f})", sc.name);
        let expected = if let LiveScene::Flat(_) = live {
            oracle(&Brute::build(&frame.mesh)?, &sets, Some(VERIFY_PER_FRAME))
        } else {
            let (b, _) = LiveScene::build(&brute_spec, UpdatePolicy::Rebuild, layout, &actors, &frame.mesh, Some(eye))?;
            oracle(b.accel(), &sets, Some(VERIFY_PER_FRAME))
        };
        for e in &expected {
            run.verified += verify(live.accel(), &label, &where_, rays, e, mismatches);
        }
        tick();
    }
    run.median_update_ms = median(&run.update_ms);
    run.median_trace_ms = median(&run.trace_ms);
    run.median_time_to_image_ms = median(&run.time_to_image_ms);
    run.rebuilds = run.actions.iter().filter(|a| *a == "rebuilt").count();
    Ok(run)
}

/// Time to image per frame for each layout and policy of the first structure measured
/// (the BVH by default), one panel per scene.
pub fn chart(runs: &[LayoutRun], width: u32, height: u32) -> LineChart {
    let first = runs.first().map(|r| r.accel.clone()).unwrap_or_default();
    let mut scenes: Vec<&str> = runs.iter().map(|r| r.scene.as_str()).collect();
    scenes.dedup();
    let panels = scenes
        .iter()
        .map(|&scene| {
            let mine: Vec<&LayoutRun> = runs.iter().filter(|r| r.scene == scene && r.accel == first).collect();
            let series = mine
                .iter()
                .map(|r| Series {
                    name: format!("{} {}", r.layout, r.policy),
                    points: r.time_to_image_ms.iter().enumerate().map(|(i, &t)| ((i + 1) as f64, t)).collect(),
                    reference: r.layout == "flat",
                })
                .collect();
            let tris = mine.first().map_or(0, |r| r.triangles);
            Panel { title: format!("{scene} ({} triangles)", thousands(tris as u64)), series }
        })
        .collect();
    LineChart {
        caption: format!(
            "dynamic: {first}'s time to image per frame by scene layout and update policy ({width}x{height}; thin: flat)"
        ),
        x_desc: "frame".into(),
        y_desc: "ms".into(),
        log2_x: false,
        log_y: true,
        y_from_zero: false,
        panels,
    }
}

/// Markdown table of the runs.
pub fn markdown(runs: &[LayoutRun], s: &mut String) {
    use std::fmt::Write;
    let _ = writeln!(
        s,
        "### Scene layouts and update policies\n\n\
         Medians over the frames. *flat*: one structure over the frame; *instanced*: static actors in one \
         part built once, deforming actors' parts refit or rebuilt by the policy, rigid actors instances of \
         shared local-space parts under a top-level BVH (docs/animate.md, \"Scene layouts\"). Time to image = \
         update + Whitted render. *rebuilds*: frames in which any part was rebuilt.\n\n\
         | scene | triangles | structure | layout | policy | parts / instances | update ms | primary trace ms | time to image ms | rebuilds | checked |\n\
         |---|--:|---|---|---|--:|--:|--:|--:|--:|--:|"
    );
    for r in runs {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} / {} | {:.3} | {:.2} | {:.2} | {} | {} |",
            r.scene,
            thousands(r.triangles as u64),
            r.accel,
            r.layout,
            r.policy,
            r.parts,
            r.instances,
            r.median_update_ms,
            r.median_trace_ms,
            r.median_time_to_image_ms,
            r.rebuilds,
            thousands(r.verified as u64)
        );
    }
}
