//! Command-line grammar (clap). Raw arguments only; validation happens in `commands/`.

use clap::{Args, Parser, Subcommand};
use dynray_accel::AccelKind;
use std::path::PathBuf;

/// Ray tracing of dynamic scenes with GPU-friendly acceleration structures.
#[derive(Parser, Debug)]
#[command(name = "dynray", version, about, propagate_version = true)]
pub struct Cli {
    /// Worker threads (default: all cores).
    #[arg(long, global = true, value_name = "N")]
    pub threads: Option<usize>,
    #[command(subcommand)]
    pub command: Command,
}

/// Subcommands.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Render a scene (.scn) or a mesh file (.obj, .ply, .ply.gz, .gltf, .glb) to an image.
    Render(RenderArgs),
    /// Trace a batch of rays from a .npy file and write the hits to a .npz file.
    TraceRays(TraceRaysArgs),
    /// Print a file's counts and bounding box and an acceleration structure's figures.
    Info(InfoArgs),
}

/// `dynray render`.
#[derive(Args, Debug)]
pub struct RenderArgs {
    /// Scene or mesh file; without it, the built-in demo scene is rendered.
    pub scene: Option<PathBuf>,
    /// Output image: .png, .bmp or .exr.
    #[arg(short, long, default_value = "dynray.png")]
    pub output: PathBuf,
    /// Image width in pixels (overrides the scene's settings).
    #[arg(long)]
    pub width: Option<u32>,
    /// Image height in pixels (overrides the scene's settings).
    #[arg(long)]
    pub height: Option<u32>,
    /// Maximum ray level, 1 = primary rays only (overrides `max_recursion_level`).
    #[arg(long)]
    pub max_depth: Option<u32>,
    /// Secondary rays at or below this weight are not traced (overrides `min_weight`).
    #[arg(long)]
    pub min_weight: Option<f32>,
    /// Acceleration structure.
    #[arg(long, default_value = "bvh", value_parser = parse_accel)]
    pub accel: AccelKind,
}

/// `dynray trace-rays`.
#[derive(Args, Debug)]
pub struct TraceRaysArgs {
    /// Mesh file (.obj, .ply, .ply.gz, .gltf, .glb) or scene file (.scn).
    pub mesh: PathBuf,
    /// Rays: float32 .npy of shape (N, 8): origin xyz, direction xyz, tmin, tmax.
    #[arg(long, value_name = "RAYS.npy")]
    pub rays: PathBuf,
    /// Output .npz with `t`, `prim`, `u`, `v` (or `occluded` with --occluded).
    #[arg(short, long, value_name = "HITS.npz")]
    pub output: PathBuf,
    /// Acceleration structure.
    #[arg(long, default_value = "bvh", value_parser = parse_accel)]
    pub accel: AccelKind,
    /// Any-hit queries: write one boolean `occluded` per ray instead of closest hits.
    #[arg(long)]
    pub occluded: bool,
}

/// `dynray info`.
#[derive(Args, Debug)]
pub struct InfoArgs {
    /// Scene or mesh file.
    pub file: PathBuf,
    /// Structure to build and describe.
    #[arg(long, default_value = "bvh", value_parser = parse_accel)]
    pub accel: AccelKind,
}

fn parse_accel(s: &str) -> Result<AccelKind, String> {
    s.parse()
}
