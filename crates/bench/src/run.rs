//! The bench's driver: validated settings in, measurements and files out.

use crate::config::{BenchConfig, Preset};
use crate::gpu::GpuSession;
use crate::plan::{measure_scenes, SceneMeasure};
use crate::report::{ConfigEcho, Mismatch, Report, SCHEMA_VERSION};
use crate::{charts, fonts, machine, markdown, output, presets};
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
        scenes: Vec::new(),
        seed000: None,
        seed000_physics: None,
        seed001: None,
        seed002: None,
        seed003: None,
        seed004: None,
        seed004_renderers: None,
        dynamic: None,
        path: None,
        gpu: None,
        mismatches: Vec::new(),
        notes: Vec::new(),
    };
    if let Some(g) = &gpu {
        report.gpu = Some(g.info());
        report.notes.extend(g.notes());
    }
    if config.presets.contains(&Preset::Standard) {
        standard(config, &accels, gpu.as_mut(), &mut report)?;
    }
    if config.presets.contains(&Preset::Seed000) {
        let mut r =
            presets::study::run(config, &presets::seed000::study(config), &mut report.mismatches, &mut report.notes)?;
        r.ratios = presets::seed000::ratios(&r);
        report.seed000 = Some(r);
        report.seed000_physics = Some(presets::seed000_physics::run(config, &mut report.mismatches)?);
    }
    if config.presets.contains(&Preset::Seed001) {
        report.seed001 = Some(presets::seed001::run(config, gpu.as_ref(), &mut report.notes)?);
    }
    if config.presets.contains(&Preset::Seed002) {
        let mut r =
            presets::study::run(config, &presets::seed002::study(config), &mut report.mismatches, &mut report.notes)?;
        r.ratios = presets::seed002::ratios(&r);
        report.seed002 = Some(r);
    }
    if config.presets.contains(&Preset::Seed004) {
        let mut r =
            presets::study::run(config, &presets::seed004::study(config), &mut report.mismatches, &mut report.notes)?;
        r.ratios = presets::seed004::ratios(&r);
        report.seed004 = Some(r);
        report.seed004_renderers = Some(presets::seed004_renderers::run(config, &mut report.mismatches)?);
    }
    if config.presets.contains(&Preset::Seed003) {
        report.seed003 =
            Some(presets::seed003::run(config, &accels, gpu.as_mut(), &mut report.notes, &mut report.mismatches)?);
    }
    if config.presets.contains(&Preset::Dynamic) {
        report.dynamic = Some(presets::dynamic::run(config, &accels, &mut report.mismatches)?);
    }
    if config.presets.contains(&Preset::Path) {
        report.path = Some(presets::path::run(config, &mut report.mismatches)?);
    }
    report.finished_utc = machine::now_utc();
    write_outputs(config, &report)?;
    Ok(report)
}

fn standard(
    config: &BenchConfig,
    accels: &[AccelSpec],
    gpu: Option<&mut GpuSession>,
    report: &mut Report,
) -> Result<()> {
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
    report.scenes = measure_scenes(config, &plan, &how, gpu, &mut report.mismatches, &mut report.notes)?;
    Ok(())
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
        charts::save(&charts::BuildVsTriangles(report), out, "build-vs-triangles", config.png)?;
        charts::save(&charts::MraysChart(report), out, "mrays", config.png)?;
    }
    if let Some(d) = &report.dynamic {
        charts::save(&presets::dynamic::chart(d), out, "dynamic", config.png)?;
        if !d.layouts.is_empty() {
            let c = presets::dynamic_layouts::chart(&d.layouts, d.width, d.height);
            charts::save(&c, out, "dynamic-layouts", config.png)?;
        }
        if d.runs.iter().any(|r| r.refits) {
            charts::save(&presets::dynamic::drift_chart(d), out, "dynamic-drift", config.png)?;
        }
    }
    if let Some(s) = &report.seed003 {
        charts::save(&presets::seed003::chart(s), out, "seed003-speedup", config.png)?;
    }
    if let Some(p) = &report.seed000_physics {
        charts::save(&presets::seed000_physics::chart(p), out, "seed000-physics", config.png)?;
    }
    if let Some(s) = &report.seed000 {
        charts::save(&presets::seed000::sweep_chart(s), out, "seed000-sweep", config.png)?;
        charts::save(&presets::seed000::memory_chart(s), out, "seed000-memory", config.png)?;
    }
    if let Some(s) = &report.seed004 {
        charts::save(&presets::seed004::chart(s), out, "seed004-speedup", config.png)?;
    }
    if let Some(r) = &report.seed004_renderers {
        charts::save(&presets::seed004_renderers::chart(r), out, "seed004-convergence", config.png)?;
    }
    if let Some(r) = &report.path {
        charts::save(&presets::path::chart(r), out, "path-convergence", config.png)?;
    }
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
