//! The envelope of a bench run as written to `report.json` (schema in docs/bench.md):
//! the header, the standard measurements and each preset's result under its key. Each
//! preset's result type lives with the preset that fills it (`presets/`); the measurement
//! types the standard run and the presets share live in `results.rs`.

use crate::gpu::GpuInfo;
use crate::machine::Machine;
use crate::presets::dynamic::DynamicResult;
use crate::presets::path::PathResult;
use crate::presets::seed000_physics::Seed000Physics;
use crate::presets::seed001::Seed001Result;
use crate::presets::seed003::results::Seed003Result;
use crate::presets::seed004_renderers::Seed004Renderers;
use crate::presets::study::StudyResult;
use crate::results::{Mismatch, SceneResult};
use serde::{Deserialize, Serialize};

/// Version of the JSON layout; bumped when a field changes meaning or disappears.
pub const SCHEMA_VERSION: u32 = 1;

/// A whole run.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Report {
    /// [`SCHEMA_VERSION`].
    pub schema: u32,
    /// `dynray` version.
    pub dynray_version: String,
    /// Git commit of the source, if known.
    pub commit: Option<String>,
    /// Where it ran.
    pub machine: Machine,
    /// Worker threads of the parallel passes.
    pub threads: usize,
    /// Start, ISO 8601 UTC.
    pub started_utc: String,
    /// End, ISO 8601 UTC.
    pub finished_utc: String,
    /// The settings of the run.
    pub config: ConfigEcho,
    /// Standard measurements: one entry per scene (empty when only presets ran).
    pub scenes: Vec<SceneResult>,
    /// `--preset seed000` results (BIH leaf-size sweep against the kd-trees).
    pub seed000: Option<StudyResult>,
    /// `--preset seed000`'s dynamic scenario (an elastic bunny dropped; structures rebuilt
    /// or refitted per frame). (Absent from reports written before it existed.)
    #[serde(default)]
    pub seed000_physics: Option<Seed000Physics>,
    /// `--preset seed001` results (distance fields). (Absent from reports written before
    /// it existed.)
    #[serde(default)]
    pub seed001: Option<Seed001Result>,
    /// `--preset seed002` results (octree walks against the BVH).
    pub seed002: Option<StudyResult>,
    /// `--preset seed003` results.
    pub seed003: Option<Seed003Result>,
    /// `--preset seed004` results (A-PIT against the plain A-buffer by resolution).
    pub seed004: Option<StudyResult>,
    /// `--preset seed004`'s renderer comparison (cumulative against recursive Whitted
    /// over the A-PIT, the A-buffer and the BVH). (Absent from reports written before it
    /// existed.)
    #[serde(default)]
    pub seed004_renderers: Option<Seed004Renderers>,
    /// `--preset dynamic` results.
    pub dynamic: Option<DynamicResult>,
    /// `--preset path` results (the path tracer against Mitsuba 3's references). (Absent
    /// from reports written before it existed.)
    #[serde(default)]
    pub path: Option<PathResult>,
    /// `--backend gpu`: the adapter the GPU figures were measured on. (Absent from
    /// reports written before it existed.)
    #[serde(default)]
    pub gpu: Option<GpuInfo>,
    /// Every disagreement with brute force (the run fails when this is not empty).
    pub mismatches: Vec<Mismatch>,
    /// Remarks a reader needs (reduced resolution, skipped parts).
    pub notes: Vec<String>,
}

impl Report {
    /// Scene measurements in the run, over the standard run and every preset.
    pub fn scene_runs(&self) -> usize {
        let studies = [&self.seed000, &self.seed002, &self.seed004];
        self.scenes.len()
            + studies.iter().filter_map(|s| s.as_ref()).map(|s| s.scenes.len()).sum::<usize>()
            + self.seed003.as_ref().map_or(0, |s| s.scenes.len())
            + self.dynamic.as_ref().map_or(0, |d| d.runs.len())
            + self.seed001.as_ref().map_or(0, |s| s.runs.len())
    }
}

/// The run's settings, as used.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ConfigEcho {
    /// Image width of the ray sets and renders.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Timed repetitions (medians are reported), after one warm-up.
    pub repeat: usize,
    /// Ray kinds measured.
    pub rays: Vec<String>,
    /// Structures measured, as `--accels` spells them.
    pub accels: Vec<String>,
    /// Rays per kind checked against brute force (`null`: all).
    pub verify_sample: Option<usize>,
    /// `--quick`.
    pub quick: bool,
    /// The preset(s) run.
    pub presets: Vec<String>,
    /// The standard run's camera: `scene` or `tight` (`--framing`; reports written
    /// before it existed read as `scene`).
    #[serde(default = "scene_framing")]
    pub framing: String,
}

fn scene_framing() -> String {
    crate::framing::Framing::Scene.name().to_string()
}
