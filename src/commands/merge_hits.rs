//! `dynray merge-hits`: the engine's merge of `trace-rays --rows` slices
//! (docs/trace-rays.md, "Slices"), its summary on stderr.

use crate::cli::MergeHitsArgs;
use anyhow::Result;

pub fn run(a: MergeHitsArgs) -> Result<()> {
    let summary = dynray_engine::merge_hits(&a.parts, &a.output)?;
    eprintln!("{summary}");
    Ok(())
}
