//! The one trait every preset of `dynray bench --preset` implements: it runs, and owns
//! its result type (stored under its key in report.json), its section of report.md and
//! its charts. The driver (`run.rs`) and the report's envelope (`report.rs`,
//! `markdown.rs`) only call through it.

use crate::config::{BenchConfig, Preset};
use crate::gpu::GpuSession;
use crate::results::Mismatch;
use anyhow::Result;
use dynray_accel::AccelSpec;
use serde::de::DeserializeOwned;
use serde::Serialize;
use std::path::Path;

/// What a preset's run reads and adds to: the settings, the structures asked for, the
/// run's GPU session, and the report's shared lists.
pub struct Lab<'a> {
    /// The validated settings.
    pub config: &'a BenchConfig,
    /// The structures `--accels` asked for (or the defaults).
    pub accels: &'a [AccelSpec],
    /// The run's device (`--backend gpu`).
    pub gpu: Option<&'a mut GpuSession>,
    /// Disagreements with brute force, over the whole run.
    pub mismatches: &'a mut Vec<Mismatch>,
    /// Remarks for the reader, over the whole run.
    pub notes: &'a mut Vec<String>,
}

/// One experiment of the bench.
pub trait Experiment {
    /// The `--preset` that runs it.
    const PRESET: Preset;
    /// What it measured: the value under its key in report.json.
    type Output: Serialize + DeserializeOwned;
    /// Measures.
    fn run(ctx: &mut Lab<'_>) -> Result<Self::Output>;
    /// Its section of report.md (charts linked as `.png` or `.svg` by `png`).
    fn markdown(out: &Self::Output, png: bool, s: &mut String);
    /// Writes its charts into `dir`.
    fn charts(out: &Self::Output, dir: &Path, png: bool) -> Result<()>;
}

/// Runs `E` when its preset was asked for.
pub fn run_if_asked<E: Experiment>(ctx: &mut Lab<'_>) -> Result<Option<E::Output>> {
    if ctx.config.presets.contains(&E::PRESET) {
        E::run(ctx).map(Some)
    } else {
        Ok(None)
    }
}

/// `E`'s section of report.md, when it ran.
pub fn markdown_of<E: Experiment>(out: &Option<E::Output>, png: bool, s: &mut String) {
    if let Some(o) = out {
        E::markdown(o, png, s);
    }
}

/// `E`'s charts, when it ran.
pub fn charts_of<E: Experiment>(out: &Option<E::Output>, dir: &Path, png: bool) -> Result<()> {
    match out {
        Some(o) => E::charts(o, dir, png),
        None => Ok(()),
    }
}
