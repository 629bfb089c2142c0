//! One module per subcommand; `run` applies the global options and dispatches. Each
//! command parses its arguments into a job of `dynray_engine`, runs it and prints: no
//! engine logic lives here.

mod adf;
mod animate;
mod bench;
mod info;
mod merge_hits;
mod render;
mod trace_rays;
mod view;

use crate::cli::{Cli, Command};
use anyhow::{Context, Result};
use dynray_engine::Loaded;
use std::path::Path;

/// Runs the parsed command line.
pub fn run(cli: Cli) -> Result<()> {
    if let Some(n) = cli.threads {
        anyhow::ensure!(n > 0, "--threads must be at least 1");
        rayon::ThreadPoolBuilder::new().num_threads(n).build_global().context("cannot start the thread pool")?;
    }
    if cli.allow_outside_references {
        dynray_scene::reference::allow_outside(true);
    }
    match cli.command {
        Command::Render(a) => render::run(a),
        Command::TraceRays(a) => trace_rays::run(a),
        Command::MergeHits(a) => merge_hits::run(a),
        Command::Info(a) => info::run(a),
        Command::Animate(a) => animate::run(a),
        Command::Bench(a) => bench::run(a),
        Command::Adf(a) => adf::run(a),
        Command::View(a) => view::run(a),
    }
}

/// An option, or a combination of options, that a job refused before reading any input
/// (its `check`): the binary exits 2 for it, as for clap's own usage errors.
#[derive(Debug)]
pub struct UsageError(anyhow::Error);

impl std::fmt::Display for UsageError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{:#}", self.0)
    }
}

impl std::error::Error for UsageError {}

/// A job's option check, its refusal marked as a usage error.
fn usage(checked: Result<()>) -> Result<()> {
    checked.map_err(|e| UsageError(e).into())
}

/// Loads a file (or the demo when `None`) as the engine does, unshaded. Warnings (a
/// missing `.mtl`, also one referenced from a `.scn`) go to stderr, each once, as
/// `dynray: warning: …`; the engine returns them rather than printing, so this is
/// where a person sees them.
fn load(path: Option<&Path>) -> Result<Loaded> {
    let loaded = Loaded::open(path)?;
    for w in &loaded.warnings {
        eprintln!("dynray: warning: {w}");
    }
    Ok(loaded)
}

/// Formats a count with thousands separators (`871,414`).
fn thousands(n: usize) -> String {
    dynray_engine::format::thousands(n as u64)
}
