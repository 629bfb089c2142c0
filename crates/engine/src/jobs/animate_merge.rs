//! `dynray animate --merge`: the last step of an array job, once its tasks have ended —
//! checks that every frame is there, joins the tasks' `timings_shard_K_of_N.csv` into one
//! `timings.csv` in frame order, and writes `preview.gif` (docs/animate.md, "Slurm").

use super::animate::{frame_path, AnimateJob, Plan, TIMINGS_HEADER};
use super::preview;
use crate::load::Loaded;
use anyhow::{bail, Context, Result};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

impl AnimateJob {
    /// Merges what the tasks of an array job wrote into `out` for the frames the job
    /// covers (the scene's timeline, or `--frames`). Fails, naming the first missing
    /// frame, while any frame is missing. Returns the summary line.
    pub fn merge(&self, mut loaded: Loaded) -> Result<String> {
        let Plan { label, timeline, first, last, .. } = self.plan(&mut loaded)?;
        let out = &self.out;
        let missing: Vec<u32> = (first..=last).filter(|&k| !frame_done(out, k)).collect();
        if let Some(&m) = missing.first() {
            bail!(
                "{}: {} of the {} frames {first}..={last} are missing (the first: {}); \
                 rerun the tasks that render them (with --resume), then merge",
                out.display(),
                missing.len(),
                last - first + 1,
                frame_path(out, m).display()
            );
        }
        let sources = timings_files(out)?;
        let mut rows: BTreeMap<u32, String> = BTreeMap::new();
        for path in &sources {
            read_rows(path, &mut rows)?;
        }
        rows.retain(|&k, _| (first..=last).contains(&k));
        let mut csv = format!("{TIMINGS_HEADER}\n");
        for row in rows.values() {
            csv.push_str(row);
            csv.push('\n');
        }
        let merged = out.join("timings.csv");
        crate::output::write_atomic(&merged, csv.as_bytes())?;
        let all: Vec<PathBuf> = (first..=last).map(|k| frame_path(out, k)).collect();
        let gif = out.join("preview.gif");
        preview::write_gif(&all, timeline.frame_rate, &gif)?;
        let unrowed = (last - first + 1) as usize - rows.len();
        Ok(format!(
            "{label}: {} frames {first}..={last} complete; {} timing rows from {} files -> {}{}, preview {}",
            last - first + 1,
            rows.len(),
            sources.len(),
            merged.display(),
            if unrowed > 0 {
                format!(" ({unrowed} frames have no row: a task stopped between writing a frame and its row)")
            } else {
                String::new()
            },
            gif.display()
        ))
    }
}

/// A frame counts as done when its PNG is there and not empty.
pub(super) fn frame_done(out: &Path, k: u32) -> bool {
    std::fs::metadata(frame_path(out, k)).is_ok_and(|m| m.is_file() && m.len() > 0)
}

/// `timings.csv` (a one-task run's, or an earlier merge) first, then every task's file in
/// name order: where two hold a frame, the later one's row is kept.
fn timings_files(out: &Path) -> Result<Vec<PathBuf>> {
    let mut shards: Vec<PathBuf> = std::fs::read_dir(out)
        .with_context(|| format!("{}: cannot list", out.display()))?
        .filter_map(|e| e.ok())
        .map(|e| e.path())
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.starts_with("timings_shard_") && n.ends_with(".csv"))
        })
        .collect();
    shards.sort();
    let whole = out.join("timings.csv");
    Ok(whole.is_file().then_some(whole).into_iter().chain(shards).collect())
}

/// The rows of one timings file, keyed by frame number.
fn read_rows(path: &Path, rows: &mut BTreeMap<u32, String>) -> Result<()> {
    let text =
        dynray_geom::file::read_back_to_string(path).with_context(|| format!("{}: cannot read", path.display()))?;
    let mut lines = text.lines();
    if lines.next() != Some(TIMINGS_HEADER) {
        bail!(
            "{}: not a timings file of this version of dynray (its first line is not `{TIMINGS_HEADER}`)",
            path.display()
        );
    }
    for (i, line) in lines.enumerate() {
        if line.is_empty() {
            continue;
        }
        let k = line
            .split(',')
            .next()
            .and_then(|f| f.parse::<u32>().ok())
            .with_context(|| format!("{}:{}: a row must start with its frame number", path.display(), i + 2))?;
        rows.insert(k, line.to_string());
    }
    Ok(())
}
