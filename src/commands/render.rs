//! `dynray render`: scene, mesh or distance-field file (or the built-in demo) -> image,
//! through the engine's render job.

use crate::cli::RenderArgs;
use anyhow::Result;
use dynray_engine::RenderJob;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::time::{Duration, Instant};

pub fn run(a: RenderArgs) -> Result<()> {
    let job = RenderJob { output: Some(a.output.clone()), passes: a.passes, aov: a.aov, ..a.image.job() };
    // Option combinations fail at once, before the scene is read.
    job.check()?;
    let loaded = super::load(a.scene.as_deref())?;

    let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::hidden());
    bar.set_style(ProgressStyle::with_template("{bar:40} {percent:>3}% {elapsed} (eta {eta})").unwrap());
    let started = Instant::now();
    // Only renders longer than a moment get a bar; indicatif hides it when stderr is no terminal.
    let progress = |done: usize, total: usize| {
        if bar.is_hidden() && started.elapsed() > Duration::from_millis(300) && done < total {
            bar.set_draw_target(ProgressDrawTarget::stderr());
        }
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    };
    let rendered = job.run(loaded, Some(&progress))?;
    bar.finish_and_clear();
    rendered.write(&a.output)?;
    eprintln!("{} -> {}", rendered.summary, a.output.display());
    Ok(())
}
