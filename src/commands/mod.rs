//! One module per subcommand; `run` applies the global options and dispatches.

mod adf;
mod animate;
mod animate_tracer;
mod bench;
mod field_on_gpu;
mod fields;
mod gpu_info;
mod info;
mod physics;
mod preview;
mod render;
mod time;
mod trace_rays;

use crate::cli::{Cli, Command};
use anyhow::{Context, Result};
use dynray_scene::Scene;
use std::path::Path;

/// Runs the parsed command line.
pub fn run(cli: Cli) -> Result<()> {
    if let Some(n) = cli.threads {
        anyhow::ensure!(n > 0, "--threads must be at least 1");
        rayon::ThreadPoolBuilder::new().num_threads(n).build_global().context("cannot start the thread pool")?;
    }
    match cli.command {
        Command::Render(a) => render::run(a),
        Command::TraceRays(a) => trace_rays::run(a),
        Command::Info(a) => info::run(a),
        Command::Animate(a) => animate::run(a),
        Command::Bench(a) => bench::run(a),
        Command::Adf(a) => adf::run(a),
    }
}

/// Loads any scene or mesh file the engine reads, with its vertices as the files give
/// them (no generated normals, no split vertices): commands that render then apply the
/// shading ([`apply_shading`]), after any override of their own; those that only need
/// triangles skip it. Warnings (a missing `.mtl`, also one referenced from a `.scn`) go
/// to stderr, each once, as `dynray: warning: …`; the library returns them rather than
/// printing, so this is where a person sees them.
fn load_unshaded(path: &Path) -> Result<Scene> {
    let report = dynray_scene::load_file_unshaded(path)?;
    let mut shown = Vec::with_capacity(report.warnings.len());
    for w in &report.warnings {
        if !shown.contains(&w) {
            eprintln!("dynray: warning: {w}");
            shown.push(w);
        }
    }
    Ok(report.scene)
}

/// `Scene::apply_shading`, its (unlikely: loaders validate meshes) error naming the file.
fn apply_shading(scene: &mut Scene, path: &Path) -> Result<()> {
    scene
        .apply_shading()
        .map_err(|source| dynray_scene::LoadError::Mesh { path: path.to_path_buf(), source })
        .map_err(Into::into)
}

/// Formats a count with thousands separators (`871,414`): the bench's formatter.
fn thousands(n: usize) -> String {
    dynray_bench::format::thousands(n as u64)
}
