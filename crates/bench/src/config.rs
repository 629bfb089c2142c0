//! What a bench run is asked to do: the presets and the validated settings.

use crate::framing::Framing;
use crate::rays::RayKind;
use anyhow::{Context, Result};
use dynray_accel::AccelKind;
use dynray_accel::AccelSpec;
use dynray_gpu::{GpuBuild, GpuOptions};
use std::path::PathBuf;

/// What a bench run does besides (or instead of) the standard measurements.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Preset {
    /// Per scene × structure: build, shape, Mrays/s per ray kind, work per ray, time to
    /// image, heat maps.
    Standard,
    /// Seed 000's experiment: BIH leaf-size sweep (shrink on/off) against the kd-trees.
    Seed000,
    /// Seed 001's measurements: distance fields per model and level (build, hash, memory,
    /// point location by each level search, sphere tracing, error).
    Seed001,
    /// Seed 002's experiment: octree walk and descent, balanced or not, against the BVH.
    Seed002,
    /// Seed 003's experiment: single-threaded brute force vs the parallel accelerated
    /// tracer, ray casting and Whitted levels 1..=10.
    Seed003,
    /// Seed 004's experiment: A-PIT against the plain A-buffer by A-buffer resolution.
    Seed004,
    /// Every vertex moves each frame: rebuild vs update, trace, time to image per frame.
    Dynamic,
    /// The path tracer: samples/s and Mrays/s per structure, and its convergence towards
    /// Mitsuba 3's references against Mitsuba's own time.
    Path,
}

impl Preset {
    /// Every preset, in the order `--preset all` runs them.
    pub const ALL: [Preset; 8] = [
        Preset::Standard,
        Preset::Seed000,
        Preset::Seed001,
        Preset::Seed002,
        Preset::Seed003,
        Preset::Seed004,
        Preset::Dynamic,
        Preset::Path,
    ];

    /// `--preset` spelling.
    pub fn name(self) -> &'static str {
        match self {
            Preset::Standard => "standard",
            Preset::Seed000 => "seed000",
            Preset::Seed001 => "seed001",
            Preset::Seed002 => "seed002",
            Preset::Seed003 => "seed003",
            Preset::Seed004 => "seed004",
            Preset::Dynamic => "dynamic",
            Preset::Path => "path",
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

/// The standard run's default image when the competitors are compiled in (feature
/// `compare`): at 640×480 a shadow or diffuse pass of the bunny is 47k rays and lasts
/// 3 ms, too short to time against another library. Those runs also frame the model
/// tightly by default ([`Framing::Tight`]).
pub const SIDE_BY_SIDE_SIZE: (u32, u32) = (1280, 960);

/// Validated settings of a run.
#[derive(Clone, Debug)]
pub struct BenchConfig {
    /// Scene names or files; empty: the preset's defaults.
    pub scenes: Vec<String>,
    /// Structures; empty: every registered structure but brute (brute alone when it is
    /// the only one).
    pub accels: Vec<AccelSpec>,
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
    /// Folder of the named models (None: the default search, see [`crate::scenes::scenes_dir`]).
    pub scenes_dir: Option<PathBuf>,
    /// Rays per kind checked against brute force (None: all).
    pub verify_sample: Option<usize>,
    /// Frames of the dynamic preset.
    pub frames: usize,
    /// Write PNG charts and heat maps (needs a font, see [`crate::fonts`]); SVG charts always.
    pub png: bool,
    /// Show a progress bar on stderr.
    pub progress: bool,
    /// Explicit --width/--height given (presets keep their own size otherwise).
    pub size_given: bool,
    /// The standard run's camera (`--framing`).
    pub framing: Framing,
    /// `--backend gpu`: measure the GPU backend too (None: the CPU only).
    pub gpu: Option<GpuBench>,
}

/// What `--backend gpu` asks of the bench (docs/bench.md, "On the GPU").
#[derive(Clone, Debug, Default)]
pub struct GpuBench {
    /// Which adapter to open.
    pub options: GpuOptions,
    /// Where the standard run's device tree is built (`--gpu-build`); seed003 times every
    /// builder whatever this says.
    pub build: GpuBuild,
}

impl BenchConfig {
    /// The defaults of a full run (`quick` = false) or a quick one.
    pub fn new(quick: bool) -> Self {
        let side_by_side = cfg!(feature = "compare") && !quick;
        Self {
            scenes: Vec::new(),
            accels: Vec::new(),
            rays: RayKind::ALL.to_vec(),
            width: if quick {
                128
            } else if side_by_side {
                SIDE_BY_SIDE_SIZE.0
            } else {
                640
            },
            height: if quick {
                96
            } else if side_by_side {
                SIDE_BY_SIDE_SIZE.1
            } else {
                480
            },
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
            framing: if side_by_side { Framing::Tight } else { Framing::Scene },
            gpu: None,
        }
    }

    /// The structures to measure: as given, or the default set.
    pub fn accels_or_default(&self) -> Vec<AccelSpec> {
        if !self.accels.is_empty() {
            return self.accels.clone();
        }
        let all: Vec<AccelSpec> =
            AccelKind::ALL.iter().filter(|k| **k != AccelKind::Brute).map(|k| AccelSpec::new(*k)).collect();
        if all.is_empty() {
            vec![AccelSpec::new(AccelKind::Brute)]
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
