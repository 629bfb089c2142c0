//! The bench's driver: validated settings in, measurements and files out.

use crate::measure::{measure, oracle, MeasureInput};
use crate::rays::{self, RayKind};
use crate::report::{ConfigEcho, KindCount, Mismatch, Report, SceneResult, SCHEMA_VERSION};
use crate::scenes::{self, BenchScene};
use crate::variant::AccelVariant;
use crate::{charts, fonts, heatmap, machine, markdown, output, presets};
use anyhow::{Context, Result};
use dynray_accel::{AccelKind, Brute};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::path::{Path, PathBuf};

/// What a bench run does besides (or instead of) the standard measurements.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Preset {
    /// Per scene × structure: build, shape, Mrays/s per ray kind, work per ray, time to
    /// image, heat maps.
    Standard,
    /// Seed 000's experiment: BIH leaf-size sweep (shrink on/off) against the kd-trees.
    Seed000,
    /// Seed 002's experiment: octree walk and descent, balanced or not, against the BVH.
    Seed002,
    /// Seed 003's experiment: single-threaded brute force vs the parallel accelerated
    /// tracer, ray casting and Whitted levels 1..=10.
    Seed003,
    /// Seed 004's experiment: A-PIT against the plain A-buffer by A-buffer resolution.
    Seed004,
    /// Every vertex moves each frame: rebuild vs update, trace, time to image per frame.
    Dynamic,
}

impl Preset {
    /// Every preset, in the order `--preset all` runs them.
    pub const ALL: [Preset; 6] =
        [Preset::Standard, Preset::Seed000, Preset::Seed002, Preset::Seed003, Preset::Seed004, Preset::Dynamic];

    /// `--preset` spelling.
    pub fn name(self) -> &'static str {
        match self {
            Preset::Standard => "standard",
            Preset::Seed000 => "seed000",
            Preset::Seed002 => "seed002",
            Preset::Seed003 => "seed003",
            Preset::Seed004 => "seed004",
            Preset::Dynamic => "dynamic",
        }
    }

    /// Parses `--preset`: one of the names above, or `all` for every one.
    pub fn parse(s: &str) -> Result<Vec<Preset>> {
        if s == "all" {
            return Ok(Preset::ALL.to_vec());
        }
        let one = Preset::ALL.iter().find(|p| p.name() == s).copied();
        let names: Vec<&str> = Preset::ALL.iter().map(|p| p.name()).collect();
        Ok(vec![one.with_context(|| format!("--preset: unknown preset `{s}` (expected {} or all)", names.join(", ")))?])
    }
}

/// Validated settings of a run.
#[derive(Clone, Debug)]
pub struct BenchConfig {
    /// Scene names or files; empty: the preset's defaults.
    pub scenes: Vec<String>,
    /// Structures; empty: every registered structure but brute (brute alone when it is
    /// the only one).
    pub accels: Vec<AccelVariant>,
    /// Ray kinds of the standard measurements.
    pub rays: Vec<RayKind>,
    /// Image width of the ray sets and renders.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Timed repetitions after one warm-up (medians are reported).
    pub repeat: usize,
    /// What to run.
    pub presets: Vec<Preset>,
    /// Output folder.
    pub out: PathBuf,
    /// Small models, small images, one repetition, every ray verified.
    pub quick: bool,
    /// Folder of the named models (None: the default search, see [`scenes::scenes_dir`]).
    pub scenes_dir: Option<PathBuf>,
    /// Rays per kind checked against brute force (None: all).
    pub verify_sample: Option<usize>,
    /// Frames of the dynamic preset.
    pub frames: usize,
    /// Write PNG charts and heat maps (needs a font, see [`fonts`]); SVG charts always.
    pub png: bool,
    /// Show a progress bar on stderr.
    pub progress: bool,
    /// Explicit --width/--height given (presets keep their own size otherwise).
    pub size_given: bool,
}

impl BenchConfig {
    /// The defaults of a full run (`quick` = false) or a quick one.
    pub fn new(quick: bool) -> Self {
        Self {
            scenes: Vec::new(),
            accels: Vec::new(),
            rays: RayKind::ALL.to_vec(),
            width: if quick { 128 } else { 640 },
            height: if quick { 96 } else { 480 },
            repeat: if quick { 1 } else { 3 },
            presets: vec![Preset::Standard],
            out: PathBuf::from("results"),
            quick,
            scenes_dir: None,
            verify_sample: if quick { None } else { Some(2000) },
            frames: if quick { 4 } else { 60 },
            png: true,
            progress: true,
            size_given: false,
        }
    }

    /// The structures to measure: as given, or the default set.
    pub fn accels_or_default(&self) -> Vec<AccelVariant> {
        if !self.accels.is_empty() {
            return self.accels.clone();
        }
        let all: Vec<AccelVariant> =
            AccelKind::ALL.iter().filter(|k| **k != AccelKind::Brute).map(|k| AccelVariant::new(*k)).collect();
        if all.is_empty() {
            vec![AccelVariant::new(AccelKind::Brute)]
        } else {
            all
        }
    }

    /// The standard scenes: as given, or bunny and the dragon-res4 (quick), or the set of
    /// named models up to the dragon-res2 (full).
    pub fn standard_scenes(&self) -> Vec<String> {
        if !self.scenes.is_empty() {
            return self.scenes.clone();
        }
        let names: &[&str] = if self.quick {
            &["dragon-res4", "bunny"]
        } else {
            &["cornell-box", "duck", "cesium-man", "dragon-res4", "dragon-res3", "bunny", "dragon-res2", "dragon"]
        };
        names.iter().map(|s| s.to_string()).collect()
    }
}

/// A progress bar over `len` steps (hidden when `show` is false or stderr is no terminal).
pub fn progress_bar(show: bool, len: u64) -> ProgressBar {
    let bar = if show {
        ProgressBar::new(len)
    } else {
        ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::hidden())
    };
    bar.set_style(
        ProgressStyle::with_template("{bar:30} {pos}/{len} {elapsed} {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar
}

/// Loads the scenes named in `names` (model names, files, or `demo`).
pub fn load_scenes(names: &[String], dir: Option<&Path>) -> Result<Vec<BenchScene>> {
    let dir = scenes::scenes_dir(dir);
    // Resolve every name before loading any, so a typo fails at once.
    let resolved: Vec<Option<(String, PathBuf)>> = names
        .iter()
        .map(|n| if n == scenes::DEMO { Ok(None) } else { scenes::resolve(n, dir.as_deref()).map(Some) })
        .collect::<Result<_>>()?;
    resolved.iter().map(|r| r.as_ref().map_or_else(|| Ok(scenes::demo()), |(n, p)| scenes::load(n, p))).collect()
}

/// Runs the bench: measures, then writes every file into `config.out`. Disagreements with
/// brute force are in `Report::mismatches` (the caller decides the exit code); setup
/// problems (unknown scene, unreadable file, unwritable folder, missing font) are errors.
pub fn run(config: &BenchConfig) -> Result<Report> {
    fonts::ensure_font()?;
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
            accels: accels.iter().map(|a| a.label()).collect(),
            verify_sample: config.verify_sample,
            quick: config.quick,
            presets: config.presets.iter().map(|p| p.name().to_string()).collect(),
        },
        scenes: Vec::new(),
        seed000: None,
        seed002: None,
        seed003: None,
        seed004: None,
        dynamic: None,
        mismatches: Vec::new(),
        notes: Vec::new(),
    };
    if config.presets.contains(&Preset::Standard) {
        standard(config, &accels, &mut report)?;
    }
    if config.presets.contains(&Preset::Seed000) {
        let mut r =
            presets::study::run(config, &presets::seed000::study(config), &mut report.mismatches, &mut report.notes)?;
        r.ratios = presets::seed000::ratios(&r);
        report.seed000 = Some(r);
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
    }
    if config.presets.contains(&Preset::Seed003) {
        report.seed003 = Some(presets::seed003::run(config, &accels, &mut report.notes, &mut report.mismatches)?);
    }
    if config.presets.contains(&Preset::Dynamic) {
        report.dynamic = Some(presets::dynamic::run(config, &accels, &mut report.mismatches)?);
    }
    report.finished_utc = machine::now_utc();
    write_outputs(config, &report)?;
    Ok(report)
}

fn standard(config: &BenchConfig, accels: &[AccelVariant], report: &mut Report) -> Result<()> {
    let plan: Vec<(String, Vec<AccelVariant>)> =
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
    };
    report.scenes = measure_scenes(config, &plan, &how, &mut report.mismatches, &mut report.notes)?;
    Ok(())
}

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
}

/// Measures every structure of `plan` on its scene: the same ray sets and brute-force
/// answers for all structures of a scene; disagreements go to `mismatches`.
pub fn measure_scenes(
    config: &BenchConfig,
    plan: &[(String, Vec<AccelVariant>)],
    how: &SceneMeasure,
    mismatches: &mut Vec<Mismatch>,
    notes: &mut Vec<String>,
) -> Result<Vec<SceneResult>> {
    let names: Vec<String> = plan.iter().map(|(n, _)| n.clone()).collect();
    let loaded = load_scenes(&names, config.scenes_dir.as_deref())?;
    let steps: usize = plan.iter().map(|(_, a)| a.len() + 1).sum();
    let bar = progress_bar(config.progress, steps as u64);
    let mut out = Vec::new();
    for (sc, (_, accels)) in loaded.iter().zip(plan) {
        bar.set_message(format!("{}{}: rays and brute-force answers", how.label, sc.name));
        let first = accels.first().context("no structure to measure")?;
        let reference =
            first.build_in(&sc.frame).with_context(|| format!("{}: cannot build {}", sc.name, first.label()))?;
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
            let step = |s: &str| bar.set_message(format!("{}{} / {}: {s}", how.label, sc.name, v.label()));
            let (mut res, heat) = measure(v, &input, mismatches, &step)?;
            if let (Some(work), true) = (heat, how.heatmaps) {
                let file = format!("heatmap-{}-{}.png", file_safe(&sc.name), file_safe(&res.accel));
                let title = format!(
                    "{} on {} ({} triangles), {}x{}",
                    res.accel, sc.name, result.triangles, how.width, how.height
                );
                heatmap::write(&config.out.join(&file), &work, how.width, how.height, &title)?;
                res.heatmap = Some(file);
            }
            result.structures.push(res);
            bar.inc(1);
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
    Ok(out)
}

/// A name usable in a file name: letters, digits, `-`, `_`, `.`; anything else becomes `_`.
pub fn file_safe(s: &str) -> String {
    s.chars().map(|c| if c.is_ascii_alphanumeric() || "-_.".contains(c) { c } else { '_' }).collect()
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
    }
    if let Some(s) = &report.seed003 {
        charts::save(&presets::seed003::chart(s), out, "seed003-speedup", config.png)?;
    }
    if let Some(s) = &report.seed000 {
        charts::save(&presets::seed000::sweep_chart(s), out, "seed000-sweep", config.png)?;
        charts::save(&presets::seed000::memory_chart(s), out, "seed000-memory", config.png)?;
    }
    if let Some(s) = &report.seed004 {
        charts::save(&presets::seed004::chart(s), out, "seed004-speedup", config.png)?;
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
