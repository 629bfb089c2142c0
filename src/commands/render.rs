//! `dynray render`: scene, mesh or distance-field file (or the built-in demo) -> image,
//! through the engine's render job.

use crate::cli::RenderArgs;
use crate::progress::Progress;
use anyhow::Result;
use dynray_engine::RenderJob;
use std::time::Duration;

/// A render shows its bar once it has lasted this long.
const BAR_AFTER: Duration = Duration::from_millis(300);

pub fn run(a: RenderArgs) -> Result<()> {
    let job = RenderJob { output: Some(a.output.clone()), passes: a.passes, aov: a.aov, ..a.image.job() };
    // Option combinations fail at once, before the scene is read.
    super::usage(job.check())?;
    let loaded = super::load(a.scene.as_deref())?;

    // Only renders longer than a moment get a bar; a log gets a line every few seconds.
    let progress = Progress::new(&loaded.label, "{bar:40} {percent:>3}% {elapsed} (eta {eta})", BAR_AFTER);
    let report = |done: usize, total: usize| {
        progress.update(done, total, || format!("{}% of the tiles ({done}/{total})", done * 100 / total.max(1)))
    };
    let rendered = job.run(loaded, Some(&report))?;
    progress.finish();
    rendered.write(&a.output)?;
    eprintln!("{} -> {}", rendered.summary, a.output.display());
    Ok(())
}
