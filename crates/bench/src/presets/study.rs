//! What the seed000, seed002 and seed004 presets share: a plan of scenes and structure
//! variants measured like the standard run, then ratios between chosen pairs.

use crate::config::BenchConfig;
use crate::plan::{measure_scenes, SceneMeasure};
use crate::rays::RayKind;
use crate::results::{Mismatch, SceneResult, StructureResult};
use crate::variant::parse_accels;
use anyhow::Result;
use dynray_accel::AccelSpec;
use serde::{Deserialize, Serialize};

/// A seed preset measured like the standard run (same fields per scene and structure) on
/// the preset's scenes and structure variants, with the ratios the seed reports.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct StudyResult {
    /// Preset name (`seed000`, …).
    pub preset: String,
    /// Image width of the ray sets (and renders, when time to image is measured).
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Timed repetitions (medians reported).
    pub repeat: usize,
    /// Ray kinds measured.
    pub rays: Vec<String>,
    /// Per scene, as in the standard run.
    pub scenes: Vec<SceneResult>,
    /// The seed's comparisons, computed from `scenes`.
    pub ratios: Vec<Ratio>,
}

/// One comparison of two structures on one scene and metric.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Ratio {
    /// Scene.
    pub scene: String,
    /// `build_ms`, `trace_ms:KIND`, `time_to_image_ms` or `memory_bytes`.
    pub metric: String,
    /// The structure compared against (`--accels` spelling).
    pub baseline: String,
    /// The structure compared.
    pub candidate: String,
    /// The baseline's value (ms or bytes).
    pub baseline_value: f64,
    /// The candidate's value.
    pub candidate_value: f64,
    /// `baseline_value / candidate_value`: above 1 the candidate is faster (or smaller).
    pub speedup: f64,
}

/// A preset's experiment.
pub struct Study {
    /// Preset name.
    pub preset: &'static str,
    /// Scenes with the variants measured on each.
    pub plan: Vec<(String, Vec<AccelSpec>)>,
    /// Ray kinds.
    pub rays: Vec<RayKind>,
    /// Image size when the command line gives none.
    pub size: (u32, u32),
    /// Whether to render for the time to image.
    pub time_to_image: bool,
}

/// Parses a variant list written in the preset's source (a typo there is a bug, so the
/// error says which preset).
pub fn variants(preset: &str, list: &str) -> Vec<AccelSpec> {
    parse_accels(list).unwrap_or_else(|e| panic!("preset {preset}: bad built-in structure list `{list}`: {e}"))
}

/// The scenes of a study: the command line's (each with the preset's default variants),
/// or the preset's own plan.
pub fn plan_or_given(
    config: &BenchConfig,
    own: Vec<(String, Vec<AccelSpec>)>,
    quick: &[&str],
) -> Vec<(String, Vec<AccelSpec>)> {
    let default_variants = own.first().map(|(_, v)| v.clone()).unwrap_or_default();
    if !config.scenes.is_empty() {
        return config.scenes.iter().map(|s| (s.clone(), default_variants.clone())).collect();
    }
    if config.quick {
        return quick.iter().map(|s| (s.to_string(), default_variants.clone())).collect();
    }
    own
}

/// Measures the study. `--width/--height` override the preset's size; `--quick` shrinks
/// it to 64×48.
pub fn run(
    config: &BenchConfig,
    study: &Study,
    mismatches: &mut Vec<Mismatch>,
    notes: &mut Vec<String>,
) -> Result<StudyResult> {
    let (width, height) = if config.size_given {
        (config.width, config.height)
    } else if config.quick {
        (64, 48)
    } else {
        study.size
    };
    let how = SceneMeasure {
        rays: study.rays.clone(),
        width,
        height,
        repeat: config.repeat,
        time_to_image: study.time_to_image,
        heatmaps: false,
        label: study.preset,
        competitors: false,
        framing: crate::framing::Framing::Scene,
    };
    let scenes = measure_scenes(config, &study.plan, &how, None, mismatches, notes)?;
    Ok(StudyResult {
        preset: study.preset.to_string(),
        width,
        height,
        repeat: config.repeat,
        rays: study.rays.iter().map(|k| k.name().to_string()).collect(),
        scenes,
        ratios: Vec::new(),
    })
}

/// A metric of one structure: build, trace of a ray kind, time to image, memory.
#[derive(Clone, Copy, Debug)]
pub enum Metric {
    /// Median build, ms.
    Build,
    /// Median pass over one ray kind, ms.
    Trace(RayKind),
    /// Build + render, ms.
    TimeToImage,
    /// Bytes.
    Memory,
}

impl Metric {
    /// The JSON spelling.
    pub fn name(self) -> String {
        match self {
            Metric::Build => "build_ms".into(),
            Metric::Trace(k) => format!("trace_ms:{}", k.name()),
            Metric::TimeToImage => "time_to_image_ms".into(),
            Metric::Memory => "memory_bytes".into(),
        }
    }

    /// The value for `s`, if measured.
    pub fn of(self, s: &StructureResult) -> Option<f64> {
        match self {
            Metric::Build => Some(s.build_ms),
            Metric::Trace(k) => s.kinds.iter().find(|r| r.kind == k.name()).map(|r| r.trace_ms),
            Metric::TimeToImage => s.time_to_image_ms,
            Metric::Memory => Some(s.memory_bytes as f64),
        }
    }
}

/// The ratio `baseline / candidate` of `metric` on `scene`, when both were measured and
/// are positive.
pub fn ratio(scene: &SceneResult, metric: Metric, baseline: &str, candidate: &str) -> Option<Ratio> {
    let find = |label: &str| scene.structures.iter().find(|s| s.accel == label);
    let b = metric.of(find(baseline)?)?;
    let c = metric.of(find(candidate)?)?;
    (b > 0.0 && c > 0.0).then(|| Ratio {
        scene: scene.name.clone(),
        metric: metric.name(),
        baseline: baseline.to_string(),
        candidate: candidate.to_string(),
        baseline_value: b,
        candidate_value: c,
        speedup: b / c,
    })
}

/// The value of parameter `key` in a `--accels` label (`bih:max_prims=5,…`).
pub fn param<'a>(label: &'a str, key: &str) -> Option<&'a str> {
    let (_, params) = label.split_once(':')?;
    params.split(',').find_map(|kv| kv.strip_prefix(key)?.strip_prefix('='))
}

/// A study preset's run through the lab: its study measured, then its ratios.
pub fn run_in_lab(
    lab: &mut super::experiment::Lab<'_>,
    study: fn(&BenchConfig) -> Study,
    ratios: fn(&StudyResult) -> Vec<Ratio>,
) -> Result<StudyResult> {
    let mut r = run(lab.config, &study(lab.config), lab.mismatches, lab.notes)?;
    r.ratios = ratios(&r);
    Ok(r)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn params_are_read_back_from_labels() {
        assert_eq!(param("bih:preset=seed_000,max_prims=5", "max_prims"), Some("5"));
        assert_eq!(param("bih:preset=seed_000,max_prims=5", "preset"), Some("seed_000"));
        assert_eq!(param("bih", "max_prims"), None);
        assert_eq!(param("apit:resolution=64", "res"), None);
    }
}
