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
    /// Seed 003's experiment: single-threaded brute force vs the parallel accelerated
    /// tracer, ray casting and Whitted levels 1..=10.
    Seed003,
    /// Every vertex moves each frame: rebuild vs update, trace, time to image per frame.
    Dynamic,
}

impl Preset {
    /// `--preset` spelling.
    pub fn name(self) -> &'static str {
        match self {
            Preset::Standard => "standard",
            Preset::Seed003 => "seed003",
            Preset::Dynamic => "dynamic",
        }
    }

    /// Parses `--preset`: one of the names above, or `all` for every one.
    pub fn parse(s: &str) -> Result<Vec<Preset>> {
        Ok(match s {
            "standard" => vec![Preset::Standard],
            "seed003" => vec![Preset::Seed003],
            "dynamic" => vec![Preset::Dynamic],
            "all" => vec![Preset::Standard, Preset::Seed003, Preset::Dynamic],
            "seed000" | "seed002" | "seed004" => anyhow::bail!(
                "--preset {s}: not implemented yet (it needs structure parameters the lead wires in; see docs/bench.md)"
            ),
            _ => anyhow::bail!("--preset: unknown preset `{s}` (expected standard, seed003, dynamic or all)"),
        })
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
            repeat: if quick { 1 } else { 5 },
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

/// Loads the scenes named in `names`.
pub fn load_scenes(names: &[String], dir: Option<&Path>) -> Result<Vec<BenchScene>> {
    let dir = scenes::scenes_dir(dir);
    // Resolve every name before loading any, so a typo fails at once.
    let resolved: Vec<(String, PathBuf)> =
        names.iter().map(|n| scenes::resolve(n, dir.as_deref())).collect::<Result<_>>()?;
    resolved.iter().map(|(n, p)| scenes::load(n, p)).collect()
}

/// Runs the bench: measures, then writes every file into `config.out`. Disagreements with
/// brute force are in `Report::mismatches` (the caller decides the exit code); setup
/// problems (unknown scene, unreadable file, unwritable folder, missing font) are errors.
pub fn run(config: &BenchConfig) -> Result<Report> {
    if config.png {
        fonts::ensure_font()?;
    }
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
        seed003: None,
        dynamic: None,
        mismatches: Vec::new(),
        notes: Vec::new(),
    };
    if config.presets.contains(&Preset::Standard) {
        standard(config, &accels, &mut report)?;
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
    let loaded = load_scenes(&config.standard_scenes(), config.scenes_dir.as_deref())?;
    let bar = progress_bar(config.progress, (loaded.len() * (accels.len() + 1)) as u64);
    for sc in &loaded {
        bar.set_message(format!("{}: rays and brute-force answers", sc.name));
        let reference = accels[0]
            .build(&sc.frame.mesh)
            .with_context(|| format!("{}: cannot build {}", sc.name, accels[0].label()))?;
        let sets = rays::generate(&sc.frame, config.width, config.height, &config.rays, reference.as_ref());
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
                repeat: config.repeat,
                width: config.width,
                height: config.height,
            };
            let step = |s: &str| bar.set_message(format!("{} / {}: {s}", sc.name, v.label()));
            let (mut res, heat) = measure(v, &input, &mut report.mismatches, &step)?;
            if let (Some(work), true) = (heat, config.png) {
                let file = format!("heatmap-{}-{}.png", file_safe(&sc.name), file_safe(&res.accel));
                let title = format!(
                    "{} on {} ({} triangles), {}x{}",
                    res.accel, sc.name, result.triangles, config.width, config.height
                );
                heatmap::write(&config.out.join(&file), &work, config.width, config.height, &title)?;
                res.heatmap = Some(file);
            }
            result.structures.push(res);
            bar.inc(1);
        }
        #[cfg(feature = "compare")]
        {
            let step = |s: &str| bar.set_message(format!("{}: {s}", sc.name));
            result.competitors = crate::compare::measure_scene(
                &sc.name,
                &sc.frame.mesh,
                &sets,
                &expected,
                config.repeat,
                &result.structures,
                &mut report.notes,
                &step,
            )?;
        }
        report.scenes.push(result);
    }
    bar.finish_and_clear();
    Ok(())
}

/// A name usable in a file name: letters, digits, `-`, `_`, `.`; anything else becomes `_`.
pub fn file_safe(s: &str) -> String {
    s.chars().map(|c| if c.is_ascii_alphanumeric() || "-_.".contains(c) { c } else { '_' }).collect()
}

fn write_outputs(config: &BenchConfig, report: &Report) -> Result<()> {
    let out = &config.out;
    if !report.scenes.is_empty() {
        charts::save(&charts::BuildVsTriangles(report), out, "build-vs-triangles", config.png)?;
        charts::save(&charts::MraysChart(report), out, "mrays", config.png)?;
    }
    if let Some(d) = &report.dynamic {
        charts::save(&charts::DynamicChart(d), out, "dynamic", config.png)?;
    }
    if let Some(s) = &report.seed003 {
        charts::save(&charts::SpeedupChart(s), out, "seed003-speedup", config.png)?;
    }
    // The reports last: their presence means every other file is complete.
    let json = serde_json::to_vec_pretty(report).context("report.json: serialisation failed")?;
    output::write_atomic(&out.join("report.json"), &json)?;
    output::write_atomic(&out.join("report.md"), markdown::render(report, config.png).as_bytes())?;
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
