//! The bench's driver: validated settings in, measurements and files out.

use crate::config::{BenchConfig, Preset};
use crate::gpu::GpuSession;
use crate::plan::{measure_scenes, SceneMeasure};
use crate::presets::dynamic::Dynamic;
use crate::presets::experiment::{charts_of, run_if_asked, Lab};
use crate::presets::path::PathTracer;
use crate::presets::seed000::Seed000;
use crate::presets::seed000_physics::Seed000PhysicsRun;
use crate::presets::seed001::Seed001;
use crate::presets::seed002::Seed002;
use crate::presets::seed003::Seed003;
use crate::presets::seed004::Seed004;
use crate::presets::seed004_renderers::Seed004RenderersRun;
use crate::report::{ConfigEcho, Report, SCHEMA_VERSION};
use crate::results::Mismatch;
use crate::results::SceneResult;
use crate::{charts, fonts, machine, markdown, output};
use anyhow::{Context, Result};
use dynray_accel::AccelSpec;
use std::path::Path;

/// Runs the bench: measures, then writes every file into `config.out`. Disagreements with
/// brute force are in `Report::mismatches` (the caller decides the exit code); setup
/// problems (unknown scene, unreadable file, unwritable folder, missing font) are errors.
pub fn run(config: &BenchConfig) -> Result<Report> {
    fonts::ensure_font()?;
    // One device for the whole run (`--backend gpu`), opened before anything is written:
    // its kernels compile once, and a missing adapter leaves no output folder behind.
    let mut gpu = config.gpu.as_ref().map(GpuSession::open).transpose()?;
    std::fs::create_dir_all(&config.out).with_context(|| format!("cannot create {}", config.out.display()))?;
    let accels = config.accels_or_default();
    let started = machine::now_utc();
    let mut mismatches = Vec::new();
    let mut notes = gpu.as_ref().map(GpuSession::notes).unwrap_or_default();
    let gpu_info = gpu.as_ref().map(GpuSession::info);
    let scenes = if config.presets.contains(&Preset::Standard) {
        standard(config, &accels, gpu.as_mut(), &mut mismatches, &mut notes)?
    } else {
        Vec::new()
    };
    let mut lab = Lab { config, accels: &accels, gpu: gpu.as_mut(), mismatches: &mut mismatches, notes: &mut notes };
    // In the order `--preset all` has always run them (report.json's figures do not
    // depend on it, but the time of each preset in a long run does).
    let seed000 = run_if_asked::<Seed000>(&mut lab)?;
    let seed000_physics = run_if_asked::<Seed000PhysicsRun>(&mut lab)?;
    let seed001 = run_if_asked::<Seed001>(&mut lab)?;
    let seed002 = run_if_asked::<Seed002>(&mut lab)?;
    let seed004 = run_if_asked::<Seed004>(&mut lab)?;
    let seed004_renderers = run_if_asked::<Seed004RenderersRun>(&mut lab)?;
    let seed003 = run_if_asked::<Seed003>(&mut lab)?;
    let dynamic = run_if_asked::<Dynamic>(&mut lab)?;
    let path = run_if_asked::<PathTracer>(&mut lab)?;
    let mut report = Report {
        schema: SCHEMA_VERSION,
        dynray_version: env!("CARGO_PKG_VERSION").to_string(),
        commit: machine::commit(),
        machine: machine::machine(),
        threads: rayon::current_num_threads(),
        started_utc: started,
        finished_utc: String::new(),
        config: ConfigEcho {
            width: config.width,
            height: config.height,
            repeat: config.repeat,
            rays: config.rays.iter().map(|k| k.name().to_string()).collect(),
            accels: accels.iter().map(|a| a.to_string()).collect(),
            verify_sample: config.verify_sample,
            quick: config.quick,
            presets: config.presets.iter().map(|p| p.name().to_string()).collect(),
            framing: config.framing.name().to_string(),
        },
        scenes,
        seed000,
        seed000_physics,
        seed001,
        seed002,
        seed003,
        seed004,
        seed004_renderers,
        dynamic,
        path,
        gpu: gpu_info,
        mismatches,
        notes,
    };
    report.finished_utc = machine::now_utc();
    write_outputs(config, &report)?;
    Ok(report)
}

/// The standard measurements: every scene × structure.
fn standard(
    config: &BenchConfig,
    accels: &[AccelSpec],
    gpu: Option<&mut GpuSession>,
    mismatches: &mut Vec<Mismatch>,
    notes: &mut Vec<String>,
) -> Result<Vec<SceneResult>> {
    let plan: Vec<(String, Vec<AccelSpec>)> =
        config.standard_scenes().into_iter().map(|n| (n, accels.to_vec())).collect();
    let how = SceneMeasure {
        rays: config.rays.clone(),
        width: config.width,
        height: config.height,
        repeat: config.repeat,
        time_to_image: true,
        heatmaps: config.png,
        label: "",
        competitors: true,
        framing: config.framing,
    };
    measure_scenes(config, &plan, &how, gpu, mismatches, notes)
}

/// Draws the charts and writes report.md again from `dir/report.json` (measuring
/// nothing): for a chart or table layout changed after a long run. Heat maps are kept as
/// they are (their per-pixel data is not in the JSON).
pub fn replot(dir: &Path, png: bool) -> Result<Report> {
    let path = dir.join("report.json");
    let text = std::fs::read(&path).with_context(|| format!("cannot read {}", path.display()))?;
    let report: Report =
        serde_json::from_slice(&text).with_context(|| format!("{}: not a bench report", path.display()))?;
    if report.schema != SCHEMA_VERSION {
        anyhow::bail!("{}: schema {} (this dynray reads {SCHEMA_VERSION})", path.display(), report.schema);
    }
    fonts::ensure_font()?;
    let config = BenchConfig { out: dir.to_path_buf(), png, ..BenchConfig::new(report.config.quick) };
    write_charts(&config, &report)?;
    output::write_atomic(&dir.join("report.md"), markdown::render(&report, png).as_bytes())?;
    Ok(report)
}

fn write_outputs(config: &BenchConfig, report: &Report) -> Result<()> {
    write_charts(config, report)?;
    let out = &config.out;
    // The reports last: their presence means every other file is complete.
    let json = serde_json::to_vec_pretty(report).context("report.json: serialisation failed")?;
    output::write_atomic(&out.join("report.json"), &json)?;
    output::write_atomic(&out.join("report.md"), markdown::render(report, config.png).as_bytes())?;
    Ok(())
}

fn write_charts(config: &BenchConfig, report: &Report) -> Result<()> {
    let out = &config.out;
    if !report.scenes.is_empty() {
        let c = &report.config;
        let run = charts::StandardRun {
            scenes: &report.scenes,
            accels: &c.accels,
            rays: &c.rays,
            threads: report.threads,
            framing: &c.framing,
        };
        charts::save(&charts::BuildVsTriangles(run), out, "build-vs-triangles", config.png)?;
        charts::save(&charts::MraysChart(run), out, "mrays", config.png)?;
    }
    charts_of::<Seed000>(&report.seed000, out, config.png)?;
    charts_of::<Seed000PhysicsRun>(&report.seed000_physics, out, config.png)?;
    charts_of::<Seed001>(&report.seed001, out, config.png)?;
    charts_of::<Seed002>(&report.seed002, out, config.png)?;
    charts_of::<Seed003>(&report.seed003, out, config.png)?;
    charts_of::<Seed004>(&report.seed004, out, config.png)?;
    charts_of::<Seed004RenderersRun>(&report.seed004_renderers, out, config.png)?;
    charts_of::<Dynamic>(&report.dynamic, out, config.png)?;
    charts_of::<PathTracer>(&report.path, out, config.png)?;
    Ok(())
}

/// One line naming the first disagreement and the count, for the command's error.
pub fn mismatch_summary(m: &[Mismatch]) -> Option<String> {
    let f = m.first()?;
    Some(format!(
        "{} disagreement(s) with brute force; first: {} on {} ({} ray {}: {:?}): expected {}, got {}",
        m.len(),
        f.accel,
        f.scene,
        f.kind,
        f.ray_index,
        f.ray,
        f.expected,
        f.got
    ))
}
